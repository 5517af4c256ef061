#!/usr/bin/env bash
# What `asf run --gui` costs: the default run with and without the live view, alternated, under
# a virtual X server (Xvfb, installed by scripts/install-deps.sh when missing). Prints each
# run's wall time (summary.json) and the ratio of the medians.
#   scripts/gui-cost.sh [repetitions=3] [config=configs/default.ini]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
reps=${1:-3}
config=${2:-$here/../configs/default.ini}
asf=$here/../build/bin/asf
command -v Xvfb >/dev/null || bash "$here/install-deps.sh" xvfb
out=$(mktemp -d /tmp/asf_gui_cost.XXXXXX)
display=:$((100 + RANDOM % 400))
Xvfb "$display" -screen 0 1280x1024x24 -nolisten tcp >"$out/xvfb.log" 2>&1 &
xvfb_pid=$!
trap 'kill $xvfb_pid 2>/dev/null || true' EXIT
sleep 1
wall() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['wall_time_s'])" "$1/summary.json"; }
plain=() gui=()
for i in $(seq 1 "$reps"); do
  "$asf" run "$config" --set pipeline.progress_interval=0 --out "$out/plain_$i" >/dev/null
  plain+=("$(wall "$out/plain_$i")")
  DISPLAY=$display "$asf" run "$config" --set pipeline.progress_interval=0 --gui --gui-hold 0 \
    --out "$out/gui_$i" >/dev/null 2>"$out/gui_$i.err"
  gui+=("$(wall "$out/gui_$i")")
  echo "run $i: without --gui ${plain[-1]} s, with --gui ${gui[-1]} s"
done
python3 - "${plain[*]}" "${gui[*]}" <<'PY'
import statistics, sys
p = [float(x) for x in sys.argv[1].split()]
g = [float(x) for x in sys.argv[2].split()]
print("without --gui: min %.2f median %.2f s; with --gui: min %.2f median %.2f s; "
      "median ratio %.3f" % (min(p), statistics.median(p), min(g), statistics.median(g),
                             statistics.median(g) / statistics.median(p)))
PY
rm -rf "$out"
