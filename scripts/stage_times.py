"""Per-stage times of one `asf run` folder (issue 26's tables: scripts/scaling-table.sh,
scripts/building-worlds.sh): the `*_ms` columns of timeseries.csv summed, and "rest", the
wall time of summary.json minus those stages (the simulator, the recorders, the outputs)."""
import csv
import json

STAGES = ["frontend_ms", "backend_ms", "map_ms", "segment_ms", "policy_ms"]
NAMES = ["front-end", "back-end", "maps", "segmentation", "policy", "rest"]


def stage_totals(run_dir):
    """(summary.json as a dict, {stage: ms} for STAGES and "rest", wall ms)."""
    summary = json.load(open(f"{run_dir}/summary.json"))
    total = dict.fromkeys(STAGES, 0.0)
    with open(f"{run_dir}/timeseries.csv") as f:
        for row in csv.DictReader(f):
            for k in STAGES:
                total[k] += float(row[k])
    wall = summary["wall_time_s"] * 1000
    total["rest"] = wall - sum(total[k] for k in STAGES)
    return summary, total, wall


def stage_cells(total, steps):
    """The table cells "seconds (ms per step)" of every stage and the rest."""
    return " | ".join(f"{total[k] / 1000:.2f} ({total[k] / max(steps, 1):.3f})"
                      for k in STAGES + ["rest"])
