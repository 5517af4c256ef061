#!/usr/bin/env bash
# A live exploration over DDS between two processes on loopback (docs/ROS2.md): asf sim-robot
# (Fast DDS) simulates the robot of configs/default.ini; asf run configs/ros2_nav2.ini (the
# ros2 source, Cyclone DDS) explores it by sending nav2-style goals, or (LIVE_CONFIG=
# configs/ros2_cmd_vel.ini) by driving its base with velocity commands. Checks that the run
# finished, covered the world, kept its pose error small and lost (almost) no scan, and that
# what the robot decoded on its vendor (/map, markers, map -> odom) is what the run wrote; the
# run's rosbag2 bag read back by asf's bag reader and by Foxglove's libraries (check_bag.sh).
# Usage: live_loop.sh ASF SOURCE_DIR OUT_DIR DOMAIN_ID RATE [asf run --set ...]
# Environment: LIVE_SEED (the [pipeline] seed of both sides; default the configs'), LIVE_BAG
# (false: no bag, and its check skipped), LIVE_CONFIG (asf's side, relative to SOURCE_DIR;
# default configs/ros2_nav2.ini).
set -euo pipefail
source "$(dirname "$0")/stop_robot.sh"
asf=$1 src=$2 out=$3 domain=$4 rate=$5
shift 5
rm -rf "$out"
mkdir -p "$out"
seed=()
[[ -n "${LIVE_SEED:-}" ]] && seed=(--set pipeline.seed="$LIVE_SEED")
"$asf" sim-robot "$src/configs/default.ini" ${seed[@]+"${seed[@]}"} --loopback --domain "$domain" \
  --rate "$rate" --out "$out/robot" >"$out/robot.log" 2>&1 &
robot=$!
trap 'stop_robot $robot' EXIT
rc=0
timeout 900 "$asf" run "$src/${LIVE_CONFIG:-configs/ros2_nav2.ini}" ${seed[@]+"${seed[@]}"} --set ros2.discovery=loopback \
  --set ros2.domain_id="$domain" --set ros2.bag="${LIVE_BAG:-true}" "$@" --out "$out/asf" >"$out/asf.log" 2>&1 || rc=$?
stop_robot $robot
trap - EXIT
if [[ $rc -ne 0 ]]; then
  echo "asf run exited with $rc"; tail -30 "$out/asf.log"; tail -5 "$out/robot.log"; exit 1
fi
python3 "$src/tests/ros2/check_live_run.py" "$out" "$asf" "$src"
python3 "$src/tests/ros2/check_received.py" "$out/asf" "$out/robot"
[[ "${LIVE_BAG:-true}" == false ]] || bash "$src/tests/ros2/check_bag.sh" "$asf" "$src" "$out/asf"
