#!/usr/bin/env python3
"""Where an exploration run's distance goes: the distance driven after each decision, summed
by the kind of goal the decision's reason names (tigre's reasons: frontier, region centre,
link to a visited region, entrance edge, edge to an unvisited region, relocation).

Usage: scripts/distance-breakdown.py RUN_DIR [RUN_DIR ...]   (folders written by asf run)
"""
import csv
import sys


def kind(reason):
    if "relocating" in reason:
        return "relocate"
    if "frontier" in reason:
        return "frontier"
    if "into region" in reason:
        return "centre"
    if "entrance" in reason:
        return "entrance"
    if "link to visited" in reason:
        return "link"
    if "unvisited" in reason:
        return "unvisited"
    return "other"


def breakdown(run):
    with open(f"{run}/trajectory.csv") as f:
        dist = {int(r["step"]): float(r["distance_m"]) for r in csv.DictReader(f)}
    with open(f"{run}/decisions.csv") as f:
        rows = list(csv.DictReader(f))
    last = max(dist)
    out = {}
    for i, r in enumerate(rows):
        begin = int(r["step"])
        end = int(rows[i + 1]["step"]) if i + 1 < len(rows) else last
        k = kind(r["reason"])
        out[k] = out.get(k, 0.0) + dist.get(end, 0.0) - dist.get(begin, 0.0)
    return out, dist[last]


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for run in sys.argv[1:]:
        parts, total = breakdown(run)
        cells = ", ".join(f"{k} {v:.0f} m" for k, v in sorted(parts.items()))
        print(f"{run}: {total:.1f} m = {cells}")


if __name__ == "__main__":
    main()
