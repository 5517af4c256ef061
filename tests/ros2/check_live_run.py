#!/usr/bin/env python3
"""Checks a live run made by live_loop.sh: finished by the policy, coverage, pose error, and
the scans between the first and the last one asf took were received (the robot publishes one
per simulated step of [sim2d] dt, so N scans over T seconds means none was lost): at most 1 %
lost on the wire, none dropped by asf.

A keyframe ATE above 0.15 m passes only when the robot's own recording (robot/sim2d.rawlog,
written by asf sim-robot, before any DDS), replayed in process through the same SLAM, is above
0.15 m too: then the route is one the SLAM fails on (the corridor of docs/ROS2.md), not the
bridge. No ratio between the two is asked: on such a route the live error and the replay's
differ either way (live / replay measured 0.41, 0.94, 1.13 and, in a CI run of 2026-11-29,
0.476 / 0.333 m = 1.43), as two runs of ICP down a corridor with slightly different frames do.
Usage: check_live_run.py OUT_DIR [ASF SOURCE_DIR (for that replay)]"""
import json
import re
import subprocess
import sys

out = sys.argv[1]
s = json.load(open(f"{out}/asf/summary.json"))
problems = []
if not s.get("finished"):
    problems.append(f"not finished: {s.get('stop_reason')}")
cov = s.get("coverage")
# The 99 % coverage goal is measured over seeds by scripts/ros2-live-seeds.sh: a live run is
# not repeatable, and a few end lower (docs/ROS2.md: 9 of 10 cmd_vel runs reached 99 %, the
# lowest 96.6 %; one CI run 98.0 %; TIGRE's stop reason now counts the frontiers it left, and
# this script prints them). One run fails below 95 %, as a bridge that loses or garbles data
# does (a run fed by two robots at once covered 69 %).
if cov is None or cov < 0.95:
    problems.append(f"coverage {cov} < 0.95")
elif cov < 0.99:
    print(f"note: coverage {cov} below the 99 % goal")
ate = s.get("ate_rmse_m")
replay_ate = None
if ate is not None and ate > 0.15 and len(sys.argv) > 3:
    asf, src = sys.argv[2], sys.argv[3]
    subprocess.run([asf, "run", f"{src}/configs/replay_slam.ini",
                    "--set", f"rawlog.file={out}/robot/sim2d.rawlog",
                    "--set", f"rawlog.ground_truth={out}/robot/sim2d.gt.txt",
                    "--out", f"{out}/replay"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    replay_ate = json.load(open(f"{out}/replay/summary.json")).get("ate_rmse_m")
    print(f"keyframe ATE {ate} m live, {replay_ate} m on the robot's own recording in process")
if ate is None or (ate > 0.15 and (replay_ate is None or replay_ate <= 0.15)):
    problems.append(f"keyframe ATE {ate} > 0.15 m (the robot's recording in process: {replay_ate} m)")
log = open(f"{out}/asf/run.log").read()
m = re.search(r"(\d+) scans received, (\d+) passed to the pipeline, (\d+) dropped \(queue full\), "
              r"(\d+) out of order, \d+ before the first odometry; stamps ([0-9.]+) to ([0-9.]+) s", log)
if not m:
    problems.append("run.log has no scan count line")
else:
    received, passed, dropped, disorder = map(int, m.groups()[:4])
    first, last = float(m.group(5)), float(m.group(6))
    expected = round((last - first) / 0.1) + 1
    # The robot publishes /scan best effort (as ROS 2 drivers do): on a loaded machine the
    # kernel may drop a datagram. Losses are reported; more than 1 % fails.
    lost = expected - passed
    print(f"scans lost on the wire: {lost} of {expected}")
    if lost < 0 or lost > 0.01 * expected or dropped or disorder:
        problems.append(f"scans: {passed} passed between {first} and {last} s, expected {expected}; "
                        f"{dropped} dropped, {disorder} out of order")
print(json.dumps({"finished": s.get("finished"), "stop_reason": s.get("stop_reason"), "coverage": cov,
                  "ate_m": ate, "replay_ate_m": replay_ate, "distance_m": s.get("distance_m"), "scans": m.groups() if m else None}))
if cov is not None and cov < 0.99:
    # What the policy left: the frontier edges of the final topological graph and its last
    # decisions, so that a run which ended early says where.
    topo = json.load(open(f"{out}/asf/topology.json"))
    for e in topo["edges"]:
        if e["frontier"]:
            print(f"frontier left: region {e['a']} at ({e['midpoint'][0]:.2f}, {e['midpoint'][1]:.2f}), "
                  f"{e['width_m']:.2f} m wide")
    print("last decisions:\n" + "".join(open(f"{out}/asf/decisions.csv").readlines()[-6:]), end="")
if problems:
    print("FAILED: " + "; ".join(problems))
    sys.exit(1)
