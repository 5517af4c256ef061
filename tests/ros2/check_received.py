#!/usr/bin/env python3
"""Checks what asf sim-robot decoded on Fast DDS (its --out received/ folder) against what the
asf run (Cyclone DDS) wrote itself: the last /map against map.pgm and map.yaml cell by cell,
the pose graph markers against graph.g2o, the region markers against topology.json, and that
the map -> odom transforms (one per frame and one at the end, reliable) arrived.
Usage: check_received.py RUN_DIR ROBOT_DIR"""
import json
import sys


def read_pgm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval; '#' comments between
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end].decode())
        pos = end
    pos += 1
    w, h = int(fields[1]), int(fields[2])
    return w, h, data[pos:pos + w * h]


run, robot = sys.argv[1], sys.argv[2]
problems = []

# The map: same grid, and every cell of the same class (free, occupied, unknown) by map.yaml's
# thresholds, except cells within 1 % of a threshold (the ROS value is a rounded percent).
yaml = {}
for line in open(f"{run}/map.yaml"):
    if ":" in line and not line.startswith("#"):
        k, v = line.split(":", 1)
        yaml[k.strip()] = v.strip()
occ_t, free_t = float(yaml["occupied_thresh"]), float(yaml["free_thresh"])
w, h, gray = read_pgm(f"{run}/map.pgm")
rw, rh, values = read_pgm(f"{robot}/received/map.pgm")
head = json.load(open(f"{robot}/received/map.json"))
origin = [float(x) for x in yaml["origin"].strip("[]").split(",")[:2]]
if (w, h) != (rw, rh):
    problems.append(f"map size: run {w}x{h}, received {rw}x{rh}")
elif max(abs(a - b) for a, b in zip(origin, head["origin"])) > 0.5 * float(yaml["resolution"]):
    problems.append(f"map origin: run {origin}, received {head['origin']}")
else:
    compared = differ = 0
    for row in range(h):
        for col in range(w):
            g = gray[(h - 1 - row) * w + col]  # the image's first row is the highest y
            p = (255 - g) / 255.0
            run_class = "occ" if p > occ_t else "free" if p < free_t else "unknown"
            v = values[row * w + col]
            if v == 255:
                rec_class = "unknown"
            else:
                if min(abs(v - 100 * occ_t), abs(v - 100 * free_t)) <= 1:
                    continue
                rec_class = "occ" if v / 100 > occ_t else "free" if v / 100 < free_t else "unknown"
            compared += 1
            differ += run_class != rec_class
    if differ:
        problems.append(f"map: {differ} of {compared} cells differ in class")
    print(f"map: {compared} cells compared, {differ} differ")

markers = json.load(open(f"{robot}/received/markers.json"))
by_ns = {}
for m in markers:
    by_ns.setdefault(m["ns"], []).append(m)
vertices = [tuple(map(float, l.split()[2:4])) for l in open(f"{run}/graph.g2o") if l.startswith("VERTEX_SE2")]
nodes = by_ns.get("pose_graph_nodes", [{"points": []}])[0]["points"]
if len(nodes) != len(vertices) or any(abs(a[0] - b[0]) > 1e-6 or abs(a[1] - b[1]) > 1e-6
                                      for a, b in zip(nodes, vertices)):
    problems.append(f"pose graph: {len(nodes)} node markers, graph.g2o has {len(vertices)} (or they differ)")
topo = json.load(open(f"{run}/topology.json"))
regions = sorted(n["region"] for n in topo["nodes"] if n["region"] > 0)
got = sorted(m["id"] for m in by_ns.get("regions", []))
if got != regions:
    problems.append(f"regions: markers {got}, topology.json {regions}")
if not markers or markers[0]["action"] != 3:
    problems.append("the marker array does not start with DELETEALL")
if any(m["frame_id"] != "map" for m in markers[1:]):
    problems.append("a marker is not in frame map")

summary = json.load(open(f"{robot}/sim_robot.json"))
log = open(f"{run}/run.log").read()
import re
frames = int(re.search(r"(\d+) passed to the pipeline", log).group(1))
# Reliable, but a writer keeps the last 100: a reader stalled longer than that (a loaded
# machine) may miss some. More than 1 % missing, or more received than sent, fails.
received_tf = summary["map_to_odom_received"]
if received_tf > frames + 1 or received_tf < 0.99 * (frames + 1):
    problems.append(f"map -> odom: {received_tf} received, {frames + 1} sent")
print(json.dumps({"markers": {k: len(v) for k, v in by_ns.items()}, "pose_graph_nodes": len(nodes),
                  "map_to_odom_received": summary["map_to_odom_received"], "frames": frames,
                  "maps_received": summary["maps_received"]}))
if problems:
    print("FAILED: " + "; ".join(problems))
    sys.exit(1)
