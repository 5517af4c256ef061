#!/usr/bin/env python3
"""Checks a SLAM run's non-sequential edges (loop closures, revisit edges: |to - from| > 1)
against ground truth: the relative pose each edge asserts against the relative pose of the
ground truth at its two keyframes' timestamps (linear interpolation, angles unwrapped).

  scripts/edges-vs-gt.py RUN_DIR GT_FILE [--wrong 0.5] [--wrong-deg 5] [--sequential] [--list]

RUN_DIR holds graph.g2o and keyframes.txt (`asf run`); GT_FILE is "t x y phi" per line (the
ground truth `asf carmen2rawlog --gt` writes). Prints the number of such edges, how many are
wrong by more than --wrong metres (or --wrong-deg degrees), the median / max translation
error and the median / 90th percentile heading error; --list prints every wrong edge.
--sequential checks the edges between consecutive keyframes instead (the scan-matching
chain). A missing or malformed file is an error naming it (and the line), exit 1."""
import argparse
import bisect
import math
import sys


class InputError(Exception):
    pass


def read_rows(path):
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if line and not line.startswith("#"):
                try:
                    row = [float(v) for v in line.split()[:4]]
                except ValueError:
                    row = []
                if len(row) != 4:
                    raise InputError(f"{path}:{n}: expected 't x y phi', got '{line}'")
                rows.append(row)
    if not rows:
        raise InputError(f"{path}: no poses")
    return rows


def interpolate(gt, t):
    ts = [r[0] for r in gt]
    k = bisect.bisect_left(ts, t)
    if k <= 0:
        return gt[0][1:]
    if k >= len(gt):
        return gt[-1][1:]
    a, b = gt[k - 1], gt[k]
    u = 0 if b[0] == a[0] else (t - a[0]) / (b[0] - a[0])
    dphi = math.atan2(math.sin(b[3] - a[3]), math.cos(b[3] - a[3]))
    return [a[1] + u * (b[1] - a[1]), a[2] + u * (b[2] - a[2]), a[3] + u * dphi]


def relative(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    dphi = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
    return [c * dx + s * dy, -s * dx + c * dy, dphi]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("gt")
    ap.add_argument("--wrong", type=float, default=0.5)
    ap.add_argument("--wrong-deg", type=float, default=5.0)
    ap.add_argument("--sequential", action="store_true")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    kf = read_rows(a.run_dir + "/keyframes.txt")
    gt = read_rows(a.gt)
    errors = []
    g2o = a.run_dir + "/graph.g2o"
    with open(g2o) as f:
        for n, line in enumerate(f, 1):
            p = line.split()
            if not p or p[0] != "EDGE_SE2":
                continue
            try:
                i, j = int(p[1]), int(p[2])
                m = [float(p[3]), float(p[4]), float(p[5])]
            except (IndexError, ValueError):
                raise InputError(f"{g2o}:{n}: malformed EDGE_SE2 line")
            if max(i, j) >= len(kf):
                raise InputError(f"{g2o}:{n}: node {max(i, j)} has no keyframe in keyframes.txt")
            if (abs(j - i) == 1) != a.sequential:
                continue
            truth = relative(interpolate(gt, kf[i][0]), interpolate(gt, kf[j][0]))
            et = math.hypot(m[0] - truth[0], m[1] - truth[1])
            er = abs(math.atan2(math.sin(m[2] - truth[2]), math.cos(m[2] - truth[2])))
            errors.append((et, er, i, j))
    wrong = [e for e in errors if e[0] > a.wrong or e[1] > math.radians(a.wrong_deg)]
    ets = sorted(e[0] for e in errors)
    ers = sorted(math.degrees(e[1]) for e in errors)
    nan = float("nan")
    med = ets[len(ets) // 2] if ets else nan
    print(f"{len(errors)} {'sequential' if a.sequential else 'non-sequential'} edges, "
          f"{len(wrong)} wrong by more than {a.wrong:g} m or {a.wrong_deg:g} deg; translation "
          f"error median {med:.3f} m, max {(ets[-1] if ets else nan):.3f} m; heading error "
          f"median {(ers[len(ers) // 2] if ers else nan):.2f} deg, 90% "
          f"{(ers[int(0.9 * len(ers))] if ers else nan):.2f} deg")
    if a.list:
        for et, er, i, j in sorted(wrong, key=lambda e: -e[0]):
            print(f"  {i} -> {j}: {et:.3f} m, {math.degrees(er):.1f} deg")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (OSError, InputError) as e:
        print(f"edges-vs-gt: error: {e}", file=sys.stderr)
        sys.exit(1)
