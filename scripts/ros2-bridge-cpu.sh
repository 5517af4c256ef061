#!/usr/bin/env bash
# The ROS 2 bridge's share of a live run's CPU (docs/ROS2.md, "The bridge's CPU"): asf sim-robot
# on Fast DDS against asf run on Cyclone DDS over loopback (tests/ros2/live_loop.sh, no bag), one
# run per seed; from each run.log's "bridge CPU" line, the CPU per frame of the run's thread in
# the bridge's own work (conversions, publishing; the rawlog every run records apart), of
# Cyclone DDS's receive thread (recvUC: receiving, delivering to asf's callbacks) and timed
# events thread (tev), of the whole run, and the bridge's share; and the scan-to-tf latency the
# robot measured (sim_robot.json: publishing a scan to receiving the map -> odom asf stamped
# with it), median, 95th percentile and maximum, beside the part of it inside asf (the scan queued
# by asf's receive thread to its map -> odom published: run.log). A run's checks may fail (with
# the truth topics switched off there is no coverage to check): it is a measurement here.
# Usage: scripts/ros2-bridge-cpu.sh OUT_DIR [SEEDS (default 3)] [RATE (default 4: 40 scans/s)]
#        [CONFIG (default configs/ros2_nav2.ini)] [asf run --set ...]
# e.g. a robot without a simulator's topics: ... OUT 3 4 configs/ros2_nav2.ini \
#        --set ros2.ground_truth_topic= --set ros2.world_map_topic= --set ros2.use_sim_time=false
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/ros2-bridge-cpu.sh OUT_DIR [SEEDS] [RATE] [CONFIG] [--set ...]}
seeds=${2:-3} rate=${3:-4} config=${4:-configs/ros2_nav2.ini}
shift $(( $# < 4 ? $# : 4 ))
mkdir -p "$out"
for seed in $(seq 1 "$seeds"); do
  echo "seed $seed" >&2
  LIVE_SEED=$seed LIVE_BAG=false LIVE_CONFIG=$config bash tests/ros2/live_loop.sh build/bin/asf . \
    "$out/run_$seed" 72 "$rate" "$@" >"$out/run_$seed.log" 2>&1 || true
done
python3 - "$out" "$seeds" <<'PY'
import json, statistics, sys
sys.path.insert(0, "scripts")
from bridge_cpu import asf_latency, bridge_cpu
out, seeds = sys.argv[1], int(sys.argv[2])
print("seed  frames  us/frame: run thread  recvUC  tev  whole run  bridge share  "
      "scan-to-tf ms (robot: median p95 max | in asf: median p95 max)")
shares = []
for seed in range(1, seeds + 1):
    d = f"{out}/run_{seed}/asf"
    b = bridge_cpu(f"{d}/run.log")
    try:
        frames = sum(1 for _ in open(f"{d}/trajectory.csv")) - 1
    except OSError:
        frames = 0
    if not b or b["share"] is None or frames <= 0:
        print(f"{seed:4d}  no measurement (see {out}/run_{seed}.log)")
        continue
    run, threads, total, share = b["run"], b["threads"], b["total"], b["share"]
    us = lambda s: 1e6 * s / frames
    shares.append(share)
    try:
        lat = json.load(open(f"{out}/run_{seed}/robot/sim_robot.json"))["scan_to_tf_latency"]
        lat = f"{lat['median_ms']:6.2f} {lat['p95_ms']:5.1f} {lat['max_ms']:7.1f}"
    except (OSError, KeyError, ValueError, TypeError):
        lat = "-"
    a = asf_latency(f"{d}/run.log")
    lat += f" | {a['median_ms']:6.2f} {a['p95_ms']:5.1f} {a['max_ms']:7.1f}" if a else " | -"
    print(f"{seed:4d}  {frames:6d}  {us(run):19.0f}  {us(threads.get('recvUC', 0)):6.0f}  "
          f"{us(threads.get('tev', 0)):3.0f}  {us(total):9.0f}  {100 * share:11.1f} %  {lat}")
if shares:
    print(f"bridge share min {100 * min(shares):.1f} %  median {100 * statistics.median(shares):.1f} %  "
          f"max {100 * max(shares):.1f} %  (n={len(shares)})")
PY
