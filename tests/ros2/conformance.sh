#!/usr/bin/env bash
# The conformance kit on the live ROS 2 source, against asf sim-robot on loopback (the kit's
# source tests need frames: a live source has them only with a robot on the other side).
# Usage: conformance.sh ASF SOURCE_DIR PLUGIN_SO DOMAIN_ID OUT_DIR
set -euo pipefail
source "$(dirname "$0")/stop_robot.sh"
asf=$1 src=$2 plugin=$3 domain=$4 out=$5
rm -rf "$out"
mkdir -p "$out"
"$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" --rate 4 >"$out/robot.log" 2>&1 &
robot=$!
trap 'stop_robot $robot' EXIT
cat >"$out/conformance.ini" <<INI
[ros2]
discovery = loopback
domain_id = $domain
drive = nav2
use_sim_time = true
startup_timeout_s = 20
INI
# Two of the kit's tests compare the frames of two instances: a live robot moves on between
# them, so they cannot hold for any live source. Two instances at once in one process (one
# shared DDS domain) are checked by test_ros2_cyclone_link.
timeout 600 "$asf" conformance --config "$out/conformance.ini" "$plugin" \
  --gtest_filter='-*same_seed_gives_identical_output:*concurrent_instances_match_sequential_runs'
