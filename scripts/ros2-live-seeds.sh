#!/usr/bin/env bash
# The default cave explored live over DDS (asf sim-robot on Fast DDS, asf run
# configs/ros2_nav2.ini on Cyclone DDS, loopback) against the same seeds in process
# (asf run configs/default.ini), alternated seed by seed on the same machine. Prints one row per
# run and the min / median / max of keyframe ATE, coverage, distance and (live) the bridge's
# share of the run's CPU (run.log's "bridge CPU" line) per mode.
# Usage: scripts/ros2-live-seeds.sh OUT_DIR [SEEDS (default 10)] [RATE (default 8)] [CONFIG]
# CONFIG: asf's side (default configs/ros2_nav2.ini; configs/ros2_cmd_vel.ini drives by velocity).
# INPROC=false skips the in-process runs (deterministic: the same seed gives the same run).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/ros2-live-seeds.sh OUT_DIR [SEEDS] [RATE]}
seeds=${2:-10} rate=${3:-8} config=${4:-configs/ros2_nav2.ini}
asf=build/bin/asf
domain=73
mkdir -p "$out"
rows="$out/runs.csv"
echo "mode,seed,finished,coverage,ate_rmse_m,distance_m,steps,wall_s,scans_lost,bridge_cpu_share" >"$rows"
row() {  # mode seed run_dir [lost]
  python3 - "$1" "$2" "$3" "${4:-}" >>"$rows" <<'PY'
import json, sys
sys.path.insert(0, "scripts")
from bridge_cpu import bridge_cpu
mode, seed, d, lost = sys.argv[1:5]
s = json.load(open(f"{d}/summary.json"))
b = bridge_cpu(f"{d}/run.log")  # the run's thread + Cyclone DDS's threads, of the whole run's CPU
share = b["share"] if b and b["share"] is not None else ""
print(",".join(str(x) for x in [mode, seed, s.get("finished"), s.get("coverage"), s.get("ate_rmse_m"),
                                 s.get("distance_m"), s.get("steps"), s.get("wall_time_s"), lost, share]))
PY
}
for seed in $(seq 1 "$seeds"); do
  if [[ ${INPROC:-true} != false ]]; then
    echo "seed $seed: in process" >&2
    "$asf" run configs/default.ini --set pipeline.seed="$seed" --out "$out/inproc_$seed" >/dev/null 2>&1 || true
    row inproc "$seed" "$out/inproc_$seed"
  fi
  echo "seed $seed: live over DDS" >&2
  live="$out/live_$seed"
  # The live test's own loop, without its bag; its checks may fail (a run is a measurement here).
  LIVE_SEED=$seed LIVE_BAG=false LIVE_CONFIG=$config bash tests/ros2/live_loop.sh "$asf" . "$live" "$domain" "$rate" \
    >"$out/live_$seed.log" 2>&1 || true
  lost=$(sed -n 's/scans lost on the wire: \([0-9-]*\) of.*/\1/p' "$out/live_$seed.log")
  row live "$seed" "$live/asf" "$lost"
done
python3 - "$rows" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(open(sys.argv[1]).read())
for mode in ("inproc", "live"):
    r = [x for x in rows if x["mode"] == mode]
    for k in ("ate_rmse_m", "coverage", "distance_m", "bridge_cpu_share"):
        v = sorted(float(x[k]) for x in r if x[k] not in ("", "None"))
        if v:
            print(f"{mode:7s} {k:11s} min {v[0]:.4f}  median {statistics.median(v):.4f}  max {v[-1]:.4f}  (n={len(v)})")
    print(f"{mode:7s} finished {sum(x['finished'] == 'True' for x in r)} of {len(r)}")
PY
