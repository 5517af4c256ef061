#!/usr/bin/env python3
"""Scores one loop or revisit edge of a SLAM run against the ground truth's relative pose:
is the edge a false match, or does the scene really look alike there (aliasing)?

  scripts/edge-vs-truth-score.py CARMEN_LOG.gz RUN_DIR GT_FILE FROM TO [--half 6]

The reference is keyframe FROM's scan and those of the HALF keyframes on either side, placed
by the ground truth (the corrected poses); keyframe TO's scan is placed in it twice, by the
ground truth's relative pose and by the edge's (graph.g2o), and scored as the correlative
search scores (mean of exp(-d^2 / (2 * 0.1^2)), d the distance to the nearest reference
point) with the share of points within 0.1 m; then along the straight line between the two
poses (t = 0: the truth, t = 1: the edge). RUN_DIR holds graph.g2o and keyframes.txt (`asf
run`); GT_FILE is "t x y phi" per line (`asf carmen2rawlog --gt`); keyframe times are the
scan numbers of the log (its FLASER lines, in order; what carmen2rawlog writes when the log's
own times are unusable). Pure Python; a missing file or edge is an error naming it, exit 1."""
import argparse
import gzip
import math
import sys


def read_scans(path):
    scans = []
    with gzip.open(path, "rt") as f:
        for line in f:
            if line.startswith("FLASER"):
                parts = line.split()
                n = int(parts[1])
                scans.append([float(v) for v in parts[2:2 + n]])
    return scans


def read_gt(path):
    gt = {}
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                t, x, y, p = map(float, line.split()[:4])
                gt[round(t)] = (x, y, p)
    return gt


def points(ranges):
    n = len(ranges)
    out = []
    for k, r in enumerate(ranges):
        if 0.05 < r < 25:
            a = -math.pi / 2 + k * math.pi / (n - 1)
            out.append((r * math.cos(a), r * math.sin(a)))
    return out


def moved(p, pts):
    c, s = math.cos(p[2]), math.sin(p[2])
    return [(c * x - s * y + p[0], s * x + c * y + p[1]) for x, y in pts]


def relative(p, q):
    dx, dy = q[0] - p[0], q[1] - p[1]
    c, s = math.cos(p[2]), math.sin(p[2])
    return (c * dx + s * dy, -s * dx + c * dy, q[2] - p[2])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("log")
    ap.add_argument("run_dir")
    ap.add_argument("gt")
    ap.add_argument("a", type=int)
    ap.add_argument("b", type=int)
    ap.add_argument("--half", type=int, default=6)
    o = ap.parse_args()
    try:
        scans = read_scans(o.log)
        gt = read_gt(o.gt)
        kf = [round(float(l.split()[0])) for l in open(o.run_dir + "/keyframes.txt")
              if l.strip() and not l.startswith("#")]
        edge = None
        for line in open(o.run_dir + "/graph.g2o"):
            f = line.split()
            if f and f[0] == "EDGE_SE2" and int(f[1]) == o.a and int(f[2]) == o.b:
                edge = tuple(map(float, f[3:6]))
    except (OSError, ValueError, IndexError) as e:
        sys.exit(f"edge-vs-truth-score: {e}")
    if edge is None:
        sys.exit(f"edge-vs-truth-score: no edge {o.a} -> {o.b} in {o.run_dir}/graph.g2o")
    for k in (o.a, o.b):
        if k >= len(kf) or kf[k] not in gt or kf[k] - 1 >= len(scans):
            sys.exit(f"edge-vs-truth-score: keyframe {k} has no scan or ground truth")
    ga = gt[kf[o.a]]
    cell = 0.3
    grid = {}
    for k in range(max(0, o.a - o.half), min(len(kf), o.a + o.half + 1)):
        if kf[k] not in gt:
            continue
        for x, y in moved(relative(ga, gt[kf[k]]), points(scans[kf[k] - 1])):
            grid.setdefault((math.floor(x / cell), math.floor(y / cell)), []).append((x, y))
    scan = points(scans[kf[o.b] - 1])

    def nearest(x, y):
        i, j = math.floor(x / cell), math.floor(y / cell)
        best = 9.0
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                for u, v in grid.get((i + di, j + dj), ()):
                    best = min(best, (u - x) ** 2 + (v - y) ** 2)
        return math.sqrt(best)

    def score(p):
        d = [nearest(x, y) for x, y in moved(p, scan)]
        return sum(v < 0.1 for v in d) / len(d), sum(math.exp(-v * v / 0.02) for v in d) / len(d)

    truth = relative(ga, gt[kf[o.b]])
    fmt = lambda p: "(%.3f, %.3f, %.3f)" % p
    print("truth %s: within 0.1 m %.3f, likelihood %.3f" % (fmt(truth), *score(truth)))
    print("edge  %s: within 0.1 m %.3f, likelihood %.3f" % (fmt(edge), *score(edge)))
    for i in range(-5, 16):
        t = i / 10
        p = tuple(truth[k] + t * (edge[k] - truth[k]) for k in range(3))
        print("  t = %4.1f: within 0.1 m %.3f, likelihood %.3f" % (t, *score(p)))


if __name__ == "__main__":
    main()
