#!/usr/bin/env python3
"""How much an exploration run's topological graph changes once the map is complete: per run,
the distance driven, the distance at which coverage reached 99 % of the run's final coverage
(the map is complete), how often the number of regions changes after that, the final graph's edges and their traversals; then means +- std over the runs and
the correlation between the changes and the distance driven after 99 % coverage; and what
the changes come from: how many of the segmentations after that point change the number of
regions, the map cells each had changed (those that change it against those that do not) and
how many changes return to the count before the previous one (flip-flops).

Usage: scripts/topology-churn.py RUN_DIR [RUN_DIR ...]   (folders written by asf run)
"""
import csv
import json
import statistics as st
import sys


def churn(run, complete=0.99):
    with open(f"{run}/timeseries.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["coverage"]]
    total = float(rows[-1]["distance_m"])
    final = float(rows[-1]["coverage"])
    after = [r for r in rows if float(r["coverage"]) >= complete * final]
    at = float(after[0]["distance_m"]) if after else float("nan")
    regions = [int(r["regions"]) for r in after]
    changes = sum(1 for a, b in zip(regions, regions[1:]) if a != b)
    # Per segmentation after the map is complete: the cells it had changed, whether it changed
    # the number of regions.
    cells_changing, cells_same = [], []
    for a, b in zip(after, after[1:]):
        if int(b["segmentations"]) > int(a["segmentations"]):
            (cells_changing if a["regions"] != b["regions"] else cells_same).append(
                int(b["changed_cells"] or 0))
    counts = [regions[0]] if regions else []
    for x in regions[1:]:
        if x != counts[-1]:
            counts.append(x)
    flips = sum(1 for i in range(2, len(counts)) if counts[i] == counts[i - 2])
    with open(f"{run}/topology.json") as f:
        topo = json.load(f)
    edges = [e for e in topo["edges"] if not e.get("frontier")]
    traversals = sum(len(e.get("traversals", [])) for e in edges)
    return {"distance": total, "at_complete": at, "changes": changes, "edges": len(edges),
            "traversals": traversals, "cells_changing": cells_changing, "cells_same": cells_same,
            "flips": flips, "range": (min(regions), max(regions)) if regions else (0, 0)}


def main(runs):
    if not runs:
        sys.exit(__doc__)
    rows = []
    for run in runs:
        r = churn(run)
        rows.append(r)
        print(f"{run}: {r['distance']:.1f} m, complete at {r['at_complete']:.1f} m, "
              f"{r['changes']} region-count changes after it (between {r['range'][0]} and "
              f"{r['range'][1]} regions), {r['edges']} edges, "
              f"{r['traversals']} traversals")
    def ms(k):
        v = [r[k] for r in rows]
        return f"{st.mean(v):.1f} +- {st.pstdev(v):.1f}"
    print(f"{len(rows)} runs: distance {ms('distance')} m, complete at {ms('at_complete')} m, "
          f"changes {ms('changes')}, edges {ms('edges')}, traversals {ms('traversals')}")
    changing = [c for r in rows for c in r["cells_changing"]]
    same = [c for r in rows for c in r["cells_same"]]
    if changing and same:
        q = lambda v: f"median {st.median(v):g}, p90 {sorted(v)[int(0.9 * (len(v) - 1))]:g}"
        print(f"after the map is complete: {len(changing)} of {len(changing) + len(same)} "
              f"segmentations change the number of regions; cells changed in them: "
              f"{q(changing)}; in the others: {q(same)}; "
              f"{sum(r['flips'] for r in rows)} of {sum(r['changes'] for r in rows)} changes "
              f"return to the count before the previous change")
    if len(rows) > 2:
        x = [r["changes"] for r in rows]
        y = [r["distance"] - r["at_complete"] for r in rows]
        mx, my = st.mean(x), st.mean(y)
        den = (sum((a - mx) ** 2 for a in x) * sum((b - my) ** 2 for b in y)) ** 0.5
        if den > 0:
            r = sum((a - mx) * (b - my) for a, b in zip(x, y)) / den
            print(f"Pearson r (changes, distance after the map is complete) = {r:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
