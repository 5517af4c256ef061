#!/usr/bin/env python3
"""Per-policy accuracy and stage costs of `asf experiment` output folders.

For each folder and policy: the keyframe ATE (mean, median, max over the runs' summary.json
`ate_rmse_m`), the back-end time per keyframe and the front-end time per step (the
`backend_ms` / `frontend_ms` columns of every run's timeseries.csv, summed, over the summed
keyframes / steps), keyframes per step, and the wall time per step.

    scripts/experiment-stages.py results/experiment_cave [OTHER_OUT ...]
"""
import csv
import json
import os
import statistics
import sys


def policy_rows(folder):
    for policy in sorted(os.listdir(folder)):
        pdir = os.path.join(folder, policy)
        if not os.path.isdir(pdir):
            continue
        runs = [os.path.join(pdir, r) for r in sorted(os.listdir(pdir))
                if os.path.isfile(os.path.join(pdir, r, "summary.json"))]
        if not runs:
            continue
        ate, keyframes, steps, wall, backend, frontend = [], 0, 0, 0.0, 0.0, 0.0
        for run in runs:
            with open(os.path.join(run, "summary.json")) as f:
                s = json.load(f)
            ate.append(s["ate_rmse_m"])
            keyframes += s["nodes"]
            steps += s["steps"]
            wall += s["wall_time_s"]
            with open(os.path.join(run, "timeseries.csv")) as f:
                for r in csv.DictReader(f):
                    backend += float(r["backend_ms"])
                    frontend += float(r["frontend_ms"])
        yield (policy, len(runs), statistics.mean(ate), statistics.median(ate), max(ate),
               backend / max(keyframes, 1), frontend / max(steps, 1), keyframes / max(steps, 1),
               1000 * wall / max(steps, 1))


def main(folders):
    if not folders:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    print("| folder | policy | runs | keyframe ATE mean / median / max [m] | back-end per keyframe "
          "[ms] | front-end per step [ms] | keyframes per step | wall per step [ms] |")
    print("|---|---|---:|---|---:|---:|---:|---:|")
    for folder in folders:
        for p, n, mean, med, mx, be, fe, kps, wps in policy_rows(folder):
            print(f"| {folder} | {p} | {n} | {mean:.4f} / {med:.4f} / {mx:.4f} | {be:.3f} | "
                  f"{fe:.3f} | {kps:.4f} | {wps:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
