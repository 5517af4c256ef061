#!/usr/bin/env bash
# Bad peers for the live ROS 2 source (docs/ROS2.md): each case must end asf run within a
# bounded time with an error or stop reason naming the topic or frame, and, once the run had
# started, with its outputs written.
# Usage: bad_peer.sh ASF SOURCE_DIR OUT_DIR DOMAIN_ID CASE
#   no_robot     nobody publishes
#   vanishes     the robot stops after 30 simulated seconds
#   no_odometry  the odometry topic asf reads has no publisher
#   wrong_type   the robot publishes std_msgs/String on /scan (asf sim-robot --fault)
#   no_laser_tf  the robot publishes no /tf_static (the laser's mounting)
#   stuck        the robot accepts goals and never drives: every goal times out
#   interrupted  Ctrl-C (SIGINT) in the middle of a live run: exit 130, every output written
#   mount_on_tf  not a fault: the laser's mounting only on /tf (asf reads /tf then), 60 steps
#   two_robots   a second robot on the same domain, started 4 s after the first: its scans
#                are stamped 32 simulated seconds behind
set -euo pipefail
source "$(dirname "$0")/stop_robot.sh"
asf=$1 src=$2 out=$3 domain=$4 case=$5
rm -rf "$out"
mkdir -p "$out"
common=(--set ros2.discovery=loopback --set ros2.domain_id="$domain" --set ros2.message_timeout_s=2
        --out "$out/asf")
args=() robot_args=() written="" fail_exit=1 duration=0 rate=8
case $case in
  no_robot)
    args=(--set ros2.startup_timeout_s=2)
    expect='topic /scan: .*no publisher of it was discovered' ;;
  vanishes)
    # It lives 15 s of wall time (30 simulated at 2x): asf has started by then.
    duration=30 rate=2
    expect='topic /scan: no sensor_msgs/LaserScan for 2 s'; written="summary.json map.pgm ros2.rawlog" ;;
  no_odometry)
    args=(--set ros2.odom_topic=/odom_missing)
    expect='topic /odom_missing: no odometry .*no publisher of /odom_missing was discovered' ;;
  wrong_type)
    args=(--set ros2.startup_timeout_s=3); robot_args=(--fault scan_as_string)
    expect='topic /scan: .*published with type std_msgs::msg::dds_::String_, not sensor_msgs::msg::dds_::LaserScan_' ;;
  no_laser_tf)
    # No world map to wait for: its 250 kB can take longer than 3 s on a loaded machine.
    args=(--set ros2.startup_timeout_s=3 --set ros2.world_map_topic=); robot_args=(--fault no_tf_static)
    expect='no transform base_link -> laser \(the scan.s frame\) on /tf_static or /tf'
    written="summary.json" ;;
  stuck)
    args=(--set ros2.goal_timeout_s=3 --set pipeline.max_failed_goals=2); robot_args=(--fault stuck)
    expect='goal_timeout_s = 3 s.*|goals failed; giving up'; written="summary.json map.pgm"
    fail_exit=0 ;;
  mount_on_tf)
    args=(--set ros2.world_map_topic= --set pipeline.max_steps=60); robot_args=(--mount-on-tf)
    expect='reading /tf for the laser.s mounting'; written="summary.json map.pgm ros2.rawlog"
    fail_exit=0 ;;
  two_robots)
    expect='topic /scan: 2 publishers of sensor_msgs/LaserScan, and [0-9]+ messages were stamped before'
    written="summary.json map.pgm ros2.rawlog" ;;
  interrupted)
    expect='interrupted after [0-9]+ steps'; written="summary.json map.pgm ros2.rawlog report.html" ;;
  *) echo "unknown case $case"; exit 2 ;;
esac
robot=""
if [[ $case != no_robot ]]; then
  "$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" --rate "$rate" \
    --duration "$duration" ${robot_args[@]+"${robot_args[@]}"} >"$out/robot.log" 2>&1 &
  robot=$!
  trap 'stop_robot $robot' EXIT
fi
if [[ $case == two_robots ]]; then
  (sleep 4 && exec "$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" \
    --rate "$rate" --duration 200 >"$out/robot2.log" 2>&1) &
  robot2=$!
  trap 'stop_robot $robot; stop_robot $robot2' EXIT
fi
rc=0
start=$(date +%s)
limit=(120) && [[ $case == interrupted ]] && limit=(--preserve-status -s INT 12)
timeout "${limit[@]}" "$asf" run "$src/configs/ros2_nav2.ini" "${common[@]}" ${args[@]+"${args[@]}"} \
  >"$out/asf.log" 2>&1 || rc=$?
took=$(( $(date +%s) - start ))
stop_robot "$robot"
[[ $case != two_robots ]] || stop_robot "$robot2"
trap - EXIT
fail() { echo "FAILED ($case): $*"; tail -20 "$out/asf.log"; exit 1; }
if [[ $case == interrupted ]]; then
  [[ $rc -eq 130 ]] || fail "exit code $rc after SIGINT (expected 130)"
  grep -q '"stop_reason": "interrupted"' "$out/asf/summary.json" || fail "summary.json does not say interrupted"
else
  [[ $rc -ne 124 ]] || fail "asf run did not end within 120 s"
fi
if [[ $fail_exit -eq 1 ]]; then
  [[ $rc -ne 0 ]] || fail "exit code 0 (expected an error)"
fi
grep -Eq "$expect" "$out/asf.log" "$out/asf/run.log" 2>/dev/null || fail "no error matching '$expect'"
for f in $written; do [[ -s "$out/asf/$f" ]] || fail "$f was not written"; done
if [[ $case == mount_on_tf ]]; then
  [[ $rc -eq 0 ]] || fail "exit code $rc (expected 0)"
  grep -q '"steps": 60' "$out/asf/summary.json" || fail "summary.json does not have 60 steps"
fi
if [[ $case == stuck ]]; then
  grep -q '"stop_reason": "the policy.s last 2 goals failed; giving up"' "$out/asf/summary.json" ||
    fail "summary.json does not say the goals failed"
  grep -q 'the goal took longer than goal_timeout_s = 3 s' "$out/asf/run.log" ||
    fail "run.log does not name goal_timeout_s"
fi
echo "ok ($case): exit $rc after ${took} s: $(grep -Eho "$expect" "$out/asf.log" "$out/asf/run.log" 2>/dev/null | head -1)"
