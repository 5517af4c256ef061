#!/usr/bin/env bash
# Bad peers for the live ROS 2 source (docs/ROS2.md): each case must end asf run within a
# bounded time with a non-zero exit and an error naming the topic or frame, and, once the run
# had started, with its outputs written.
# Usage: bad_peer.sh ASF SOURCE_DIR OUT_DIR DOMAIN_ID CASE
#   no_robot: nobody publishes; vanishes: the robot stops after 30 simulated seconds;
#   no_odometry: the odometry topic asf reads has no publisher.
set -euo pipefail
asf=$1 src=$2 out=$3 domain=$4 case=$5
rm -rf "$out"
mkdir -p "$out"
common=(--set ros2.discovery=loopback --set ros2.domain_id="$domain" --set ros2.message_timeout_s=2
        --out "$out/asf")
robot=""
case $case in
  no_robot)
    args=(--set ros2.startup_timeout_s=2); expect='topic /scan: .*no publisher of it was discovered'
    written="" ;;
  vanishes)
    args=(); expect='topic /scan: no sensor_msgs/LaserScan for 2 s'; written="summary.json map.pgm ros2.rawlog" ;;
  no_odometry)
    args=(--set ros2.odom_topic=/odom_missing)
    expect='topic /odom_missing: no odometry .*no publisher of /odom_missing was discovered'
    written="" ;;
  *) echo "unknown case $case"; exit 2 ;;
esac
if [[ $case != no_robot ]]; then
  # The vanishing robot lives 15 s of wall time (30 simulated at 2x): asf has started by then.
  duration=0 rate=8; [[ $case == vanishes ]] && duration=30 rate=2
  "$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" --rate "$rate" \
    --duration "$duration" >"$out/robot.log" 2>&1 &
  robot=$!
  trap 'kill -TERM $robot 2>/dev/null || true' EXIT
fi
rc=0
start=$(date +%s)
timeout 120 "$asf" run "$src/configs/ros2_nav2.ini" "${common[@]}" "${args[@]}" >"$out/asf.log" 2>&1 || rc=$?
took=$(( $(date +%s) - start ))
[[ -n "$robot" ]] && { kill -TERM "$robot" 2>/dev/null || true; wait "$robot" || true; }
fail() { echo "FAILED ($case): $*"; tail -20 "$out/asf.log"; exit 1; }
[[ $rc -ne 0 && $rc -ne 124 ]] || fail "exit code $rc (expected an error, not success or the test's timeout)"
grep -Eq "$expect" "$out/asf.log" || fail "no error matching '$expect'"
for f in $written; do [[ -s "$out/asf/$f" ]] || fail "$f was not written"; done
echo "ok ($case): exit $rc after ${took} s: $(grep -Eo "$expect" "$out/asf.log" | head -1)"
