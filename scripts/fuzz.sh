#!/usr/bin/env bash
# Fuzzes every parser a user feeds asf (fuzz/README.md) with libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer: scripts/fuzz.sh [seconds per target, default 60] [target ...]
# Installs clang and its libFuzzer runtime if missing, builds build-fuzz/ (or
# $ASF_FUZZ_BUILD_DIR), runs each target from fuzz/corpus/<target> (the corpus it grows is
# kept in build-fuzz/corpus/<target>), and prints per target: executions, coverage
# (edges, features), corpus size, findings. Findings (crashes, leaks, timeouts over 10 s per
# input, a single allocation over 4.4 GB or 5 GB resident) are written to
# build-fuzz/findings/<target>/; the exit status is 1 when there is any. The allocation limit
# is above 4 GB because MRPT allocates a string of the length a rawlog says (a 32-bit field)
# before it finds the bytes missing: third-party behaviour, docs/RELIABILITY.md.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-60}
shift || true
bash scripts/install-deps.sh clang libclang-rt-14-dev
BUILD_DIR=${ASF_FUZZ_BUILD_DIR:-build-fuzz}
CC=clang CXX=clang++ cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DASF_SANITIZE=address,undefined,fuzzer-no-link -DASF_FUZZ=ON \
  -DASF_BUILD_TESTS=OFF -DASF_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "${ASF_JOBS:-$(nproc)}" --target asf_fuzz

targets=("$@")
if ((${#targets[@]} == 0)); then
  for d in fuzz/corpus/*/; do targets+=("$(basename "$d")"); done
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
summary=()
failed=0
for t in "${targets[@]}"; do
  rm -rf "$BUILD_DIR/findings/$t"  # this run's findings only (keep one: fuzz/regressions/)
  mkdir -p "$BUILD_DIR/corpus/$t" "$BUILD_DIR/findings/$t"
  log="$BUILD_DIR/findings/$t.log"
  echo "fuzz: $t for ${SECONDS_EACH} s (log: $log)"
  status=0
  ASF_FUZZ_TARGET=$t "$BUILD_DIR/bin/asf_fuzz" -max_total_time="$SECONDS_EACH" \
    -print_final_stats=1 -timeout=10 -rss_limit_mb=5120 -malloc_limit_mb=4400 -max_len=65536 \
    -artifact_prefix="$BUILD_DIR/findings/$t/" "$BUILD_DIR/corpus/$t" "fuzz/corpus/$t" \
    >"$log" 2>&1 || status=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  findings=$(find "$BUILD_DIR/findings/$t" -type f | wc -l)
  if ((status != 0 || findings > 0)); then
    failed=1
    grep -m3 -E 'ERROR|runtime error|terminate called|what\(\)' "$log" || true
  fi
  summary+=("$(printf '%-15s %6ss %12s execs  cov %6s  ft %7s  corpus %-12s findings %s' \
    "$t" "$SECONDS_EACH" "$execs" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$findings")")
done
printf '%s\n' "${summary[@]}"
exit $failed
