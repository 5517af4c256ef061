#!/usr/bin/env bash
# The conformance kit on the live ROS 2 source, against asf sim-robot on loopback (the kit's
# source tests need frames: a live source has them only with a robot on the other side).
# Usage: conformance.sh ASF SOURCE_DIR PLUGIN_SO DOMAIN_ID OUT_DIR
set -euo pipefail
asf=$1 src=$2 plugin=$3 domain=$4 out=$5
rm -rf "$out"
mkdir -p "$out"
"$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" --rate 4 >"$out/robot.log" 2>&1 &
robot=$!
trap 'kill -TERM $robot 2>/dev/null || true; wait $robot 2>/dev/null || true' EXIT
cat >"$out/conformance.ini" <<INI
[ros2]
discovery = loopback
domain_id = $domain
drive = nav2
use_sim_time = true
startup_timeout_s = 20
INI
timeout 600 "$asf" conformance --config "$out/conformance.ini" "$plugin"
