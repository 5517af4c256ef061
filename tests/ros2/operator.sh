#!/usr/bin/env bash
# An operator steers a live run through /asf/command (docs/ROS2.md): asf sim-robot plays the
# operator's script (--command) while asf run explores it with wait_for_start. Checks, from
# the robot's own ground truth and asf's outputs: the robot stays until 'start'; it stops
# within a second of 'pause' and stays until 'resume'; a text that is no command is reported
# and ignored; 'return_home' brings it back to where it started and ends the run with every
# output; the status topic went exploring -> paused -> exploring -> returning_home -> ended.
# Usage: operator.sh ASF SOURCE_DIR OUT_DIR DOMAIN_ID CONFIG (configs/ros2_nav2.ini or
# configs/ros2_cmd_vel.ini, relative to SOURCE_DIR)
set -euo pipefail
source "$(dirname "$0")/stop_robot.sh"
asf=$1 src=$2 out=$3 domain=$4 config=$5
rm -rf "$out"
mkdir -p "$out"
# Simulated seconds (the robot's clock; asf's run time is about 1 s behind, its first scan).
# At 4x, 'start' comes 6 s after the robot does: asf has started and is waiting by then.
start=25 pause=50 resume=70 home=100
"$asf" sim-robot "$src/configs/default.ini" --loopback --domain "$domain" --rate 4 --out "$out/robot" \
  --command "$start:start" --command 35:dance --command "$pause:pause" --command "$resume:resume" \
  --command "$home:return_home" >"$out/robot.log" 2>&1 &
robot=$!
trap 'stop_robot $robot' EXIT
rc=0
timeout 600 "$asf" run "$src/$config" --set ros2.discovery=loopback --set ros2.domain_id="$domain" \
  --set ros2.wait_for_start=true --out "$out/asf" >"$out/asf.log" 2>&1 || rc=$?
stop_robot $robot
trap - EXIT
if [[ $rc -ne 0 ]]; then
  echo "asf run exited with $rc"; tail -30 "$out/asf.log"; exit 1
fi
python3 - "$out" "$start" "$pause" "$resume" <<'PY'
import json, math, sys
out, start, pause, resume = sys.argv[1], *map(float, sys.argv[2:5])
problems = []
s = json.load(open(f"{out}/asf/summary.json"))
why = s.get("stop_reason", "")
if not why.startswith("the operator asked to return home (topic /asf/command: 'return_home'); back at the start"):
    problems.append(f"stop reason: {why}")
if s.get("finished"):
    problems.append("a run the operator ended says finished")
for f in ("map.pgm", "trajectory.csv", "ros2.rawlog", "report.html"):
    try:
        open(f"{out}/asf/{f}").close()
    except OSError:
        problems.append(f"no {f}")
# The robot's truth: time (simulated, from 0) and pose, one row per step.
gt = []
for line in open(f"{out}/robot/sim2d.gt.txt"):
    if line.strip() and not line.startswith("#"):
        v = line.split()
        gt.append((float(v[0]), float(v[1]), float(v[2])))
def moved(t0, t1):
    p = [(x, y) for t, x, y in gt if t0 <= t <= t1]
    return max(math.hypot(x - p[0][0], y - p[0][1]) for x, y in p)
if moved(0, start) > 1e-9:
    problems.append(f"moved {moved(0, start):.3f} m before 'start'")
if moved(start, pause) < 1.0:
    problems.append(f"moved only {moved(start, pause):.3f} m between 'start' and 'pause'")
if moved(pause + 1, resume) > 0.05:
    problems.append(f"moved {moved(pause + 1, resume):.3f} m while paused")
home = math.hypot(gt[-1][1] - gt[0][1], gt[-1][2] - gt[0][2])
if home > 0.5:
    problems.append(f"ended {home:.2f} m from its start")
log = open(f"{out}/asf/run.log").read()
for text in ("paused at step", "resumed at step", "'dance' is not a command"):
    if text not in log:
        problems.append(f"run.log lacks: {text}")
states = json.load(open(f"{out}/robot/sim_robot.json"))["asf_states"]
want = ["paused", "exploring", "paused", "exploring", "returning_home", "ended"]
if states != want:
    problems.append(f"/asf/status states {states}, not {want}")
print(json.dumps({"stop_reason": why, "moved_before_start": moved(0, start),
                  "moved_while_paused": moved(pause + 1, resume), "end_from_start_m": home,
                  "states": states}))
if problems:
    print("FAILED: " + "; ".join(problems))
    # what the run decided and logged, so that a failure seen once can be read afterwards
    print("decisions.csv, last 15 rows:")
    print("".join(open(f"{out}/asf/decisions.csv").readlines()[-15:]), end="")
    print("run.log, last 25 lines:")
    print("".join(open(f"{out}/asf/run.log").readlines()[-25:]), end="")
    sys.exit(1)
PY
