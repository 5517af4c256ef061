#!/usr/bin/env bash
# The whole CTest suite under AddressSanitizer + UndefinedBehaviorSanitizer (issue 20).
# Builds every target (host, plugins, tests) instrumented into build-sanitize/ (or
# $ASF_SANITIZE_BUILD_DIR), then runs ctest there; extra arguments go to ctest (e.g. -R Host).
# A finding aborts the process that made it, so it fails its test; the report is in the
# test's output. Figures: docs/RELIABILITY.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${ASF_SANITIZE_BUILD_DIR:-build-sanitize}
JOBS=${ASF_JOBS:-$(nproc)}
# -O1: instrumented code at -O2 builds much slower on 2 cores and finds the same; asserts on.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DASF_SANITIZE=address,undefined -DASF_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0:suppressions=$PWD/tests/sanitizer/asan.supp}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:suppressions=$PWD/tests/sanitizer/ubsan.supp}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" --timeout 3000 "$@"
