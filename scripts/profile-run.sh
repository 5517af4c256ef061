#!/usr/bin/env bash
# Where the time of one `asf run` goes (issue 26: profile first).
#
#   scripts/profile-run.sh [CONFIG.ini] [OUT_DIR]     (default: configs/default.ini,
#                                                      results/profile)
#
# Writes into OUT_DIR:
#   run/               the run's own outputs (its timeseries.csv has the per-stage times)
#   stages.txt         wall time per pipeline stage, summed over the run's timeseries rows
#   by_library.txt     perf: share of the CPU samples per shared library (self time)
#   by_function.txt    perf: share per function (self time), functions of >= 0.5 %
#   perf.data          the samples (perf report -i OUT_DIR/perf.data)
# Needs linux-perf (Debian: apt-get install linux-perf) and a user allowed to profile its
# own processes (kernel.perf_event_paranoid <= 2). The profile is flat (self time): a Release
# build has no frame pointers for call graphs. Sampling costs a few percent of the run.
set -euo pipefail
cd "$(dirname "$0")/.."
config=${1:-configs/default.ini}
out=${2:-results/profile}
build=${ASF_BUILD_DIR:-build}
command -v perf >/dev/null || { echo "profile-run.sh: needs perf (apt-get install linux-perf)" >&2; exit 2; }
[[ -x "$build/bin/asf" ]] || { echo "profile-run.sh: no $build/bin/asf (run scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out"
rm -rf "$out/run"

echo "profile-run.sh: $config under perf (999 samples/s) -> $out"
start=$(date +%s.%N)
perf record -q -F 999 -o "$out/perf.data" -- \
  "$build/bin/asf" run "$config" --out "$out/run" --set pipeline.progress_interval=0 \
  >"$out/run.log" 2>&1
end=$(date +%s.%N)

perf report -i "$out/perf.data" --stdio --no-children --sort dso --percent-limit 1 \
  2>/dev/null | grep -v '^#' | sed '/^$/d' >"$out/by_library.txt"
perf report -i "$out/perf.data" --stdio --no-children --sort dso,symbol --percent-limit 0.5 \
  2>/dev/null | grep -v '^#' | sed '/^$/d' >"$out/by_function.txt"

python3 - "$out/run/timeseries.csv" "$out/run/summary.json" "$start" "$end" >"$out/stages.txt" <<'PY'
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
summary = json.load(open(sys.argv[2]))
wall = float(sys.argv[4]) - float(sys.argv[3])
stages = ["frontend", "backend", "map", "segment", "policy"]
total = {s: sum(float(r[s + "_ms"] or 0) for r in rows) / 1000 for s in stages}
steps = summary["steps"]
print(f"steps {steps}, run wall time {summary['wall_time_s']:.2f} s "
      f"(under perf, process {wall:.2f} s)")
print(f"{'stage':10s} {'seconds':>8s} {'share':>6s} {'ms/step':>8s}")
for s in stages:
    print(f"{s:10s} {total[s]:8.2f} {100 * total[s] / summary['wall_time_s']:5.1f}% "
          f"{1000 * total[s] / max(steps, 1):8.3f}")
rest = summary["wall_time_s"] - sum(total.values())
print(f"{'rest':10s} {rest:8.2f} {100 * rest / summary['wall_time_s']:5.1f}%  "
      "(simulator, recorders, outputs)")
PY
cat "$out/stages.txt"
echo
head -n 12 "$out/by_library.txt"
echo "profile-run.sh: per function in $out/by_function.txt"
