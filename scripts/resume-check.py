#!/usr/bin/env python3
"""Issue 23's resume goal, measured: for each seed, the default run whole, the same run
stopped at half its steps (the step budget), and that run continued with `asf run --resume`.
Prints a Markdown table: distance and coverage of the whole and the resumed run, their ratio,
the recorded decisions the policy took again (and how many came out otherwise), and a
control: the whole run again with the laser's range noise one part in 10^5 larger
(sim2d.range_sigma), never interrupted: how far a path moves when anything moves it.

    scripts/resume-check.py [--config configs/default.ini] [--seeds 1-10] [--out /tmp/resume]
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ASF = os.path.join(HERE, "..", "build", "bin", "asf")


def run(args):
    r = subprocess.run([ASF] + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("asf " + " ".join(args) + " failed:\n" + r.stdout[-2000:])


def summary(folder):
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def seeds(text):
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=os.path.join(HERE, "..", "configs", "default.ini"))
    ap.add_argument("--seeds", default="1-10")
    ap.add_argument("--out", default="/tmp/asf_resume_check")
    a = ap.parse_args()
    print("| seed | whole: steps | distance (m) | coverage (%) | stopped at step | resumed: distance (m) "
          "| coverage (%) | distance / whole | decisions retaken (differing) | control: distance / whole |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    ratios, controls = [], []
    for seed in seeds(a.seeds):
        base = os.path.join(a.out, "seed_%d" % seed)
        common = [a.config, "--set", "pipeline.seed=%d" % seed, "--set",
                  "pipeline.progress_interval=0"]
        run(["run"] + common + ["--out", base + "_whole"])
        whole = summary(base + "_whole")
        half = whole["steps"] // 2
        run(["run"] + common + ["--set", "pipeline.max_steps=%d" % half, "--out", base + "_half"])
        run(["run", "--resume", base + "_half", "--set", "pipeline.max_steps=1000000", "--out",
             base + "_resumed"])
        res = summary(base + "_resumed")
        sigma = 0.01 * (1 + 1e-5)
        run(["run"] + common + ["--set", "sim2d.range_sigma=%.9g" % sigma, "--out", base + "_control"])
        control = summary(base + "_control")["distance_m"] / whole["distance_m"]
        controls.append(control)
        ratio = res["distance_m"] / whole["distance_m"]
        ratios.append(ratio)
        print("| %d | %d | %.1f | %.2f | %d | %.1f | %.2f | %.3f | %d (%d) | %.3f |" % (
            seed, whole["steps"], whole["distance_m"], 100 * whole["coverage"], half,
            res["distance_m"], 100 * res["coverage"], ratio, res["resumed"]["replayed_decisions"],
            res["resumed"]["replayed_decisions_differing"], control), flush=True)
    for name, v in (("resumed", ratios), ("control", controls)):
        within = sum(1 for r in v if abs(r - 1) <= 0.1)
        print("%s distance / whole: min %.3f, max %.3f; within 10 %%: %d of %d" % (
            name, min(v), max(v), within, len(v)))


if __name__ == "__main__":
    main()
