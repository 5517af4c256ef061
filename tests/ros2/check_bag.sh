#!/usr/bin/env bash
# The bag of a live run (ros2 source, bag = true) read back two ways: by asf's own bag reader
# (asf bag2rawlog: every scan the run received, with odometry and ground truth) and by
# Foxglove's MCAP and CDR libraries (tests/ros2/read_bag.js), whose decoded /map, markers and
# map -> odom must be the run's own (check_received.py).
# Usage: check_bag.sh ASF SOURCE_DIR RUN_DIR   (RUN_DIR: the asf run's output folder)
set -euo pipefail
asf=$1 src=$2 run=$3
bag="$run/ros2_bag"
[[ -f "$bag/metadata.yaml" && -f "$bag/data.mcap" ]] || { echo "no bag in $bag"; exit 1; }
received=$(sed -n 's/.*topic \/scan: \([0-9]*\) scans received.*/\1/p' "$run/run.log")
out=$("$asf" bag2rawlog --in "$bag" --out "$run/bag.rawlog" --gt-topic /ground_truth --gt "$run/bag.gt.txt" -q)
echo "$out"
scans=$(echo "$out" | sed -n 's/^bag2rawlog: \([0-9]*\) scans.*/\1/p')
[[ "$scans" == "$received" ]] || { echo "FAILED: asf's bag reader found $scans scans, the run received $received"; exit 1; }
modules=$(bash "$src/scripts/test-tools.sh")
rm -rf "$run/bag_decoded"
NODE_PATH="$modules" node "$src/tests/ros2/read_bag.js" "$bag" "$run/bag_decoded"
python3 "$src/tests/ros2/check_received.py" "$run" "$run/bag_decoded"
