#!/usr/bin/env python3
"""Whether two result folders (runs of `asf run`, `asf experiment`, segment-eval JSON, ...) hold
the same results: every file of A has a counterpart in B at the same relative path, and

  - JSON files are equal after removing the keys that measure the computer rather than the
    result (names with "wall", "cpu", "fps", "date", "written", "_ms": wall_time_s,
    decision_ms_mean, ...; simulated times such as time_to_coverage_90_s stay) and the absolute
    folders they name;
  - graph.g2o, keyframes.txt, trajectory.csv, map.pgm, topology.json, *.txt tables of
    ATE/RPE and the like are byte-identical, except timing columns of CSV files
    (timeseries.csv: the *_ms columns; decisions.csv has none);
  - pictures, HTML reports, Markdown tables (summary.json holds their figures) and logs are
    skipped (they carry dates and times).

Prints each difference and a count; exit 0 when the results are the same, 1 otherwise.

    python3 scripts/same-results.py A B [--ignore-key KEY]...
    python3 scripts/same-results.py --self-test
"""
import argparse
import csv
import io
import json
import os
import re
import sys
import tempfile

SKIP_EXT = (".png", ".svg", ".html", ".md", ".log", ".pdf", ".bt", ".ot", ".rawlog", ".gz", ".mcap")
SKIP_NAMES = {"progress.json", "run.log", "config.ini", "array.sh", ".asf-run.lock"}  # the lock holds a pid
TIMING = re.compile(r"(wall|_ms$|_ms_|fps|cpu|date|written|seconds_per|per_second)", re.I)


def timing_key(k):
    return bool(TIMING.search(k))


def strip(obj, ignore):
    if isinstance(obj, dict):
        return {k: strip(v, ignore) for k, v in obj.items()
                if not timing_key(k) and k not in ignore}
    if isinstance(obj, list):
        return [strip(v, ignore) for v in obj]
    if isinstance(obj, str) and obj.startswith("/"):
        return "<path>"
    return obj


def csv_rows(text):
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return rows
    keep = [i for i, h in enumerate(rows[0]) if not timing_key(h.strip())]
    return [[r[i] for i in keep if i < len(r)] for r in rows]


def same_file(a, b, ignore):
    """None when a and b hold the same results, else a one-line reason."""
    name = os.path.basename(a)
    with open(a, "rb") as fa, open(b, "rb") as fb:
        da, db = fa.read(), fb.read()
    if name.endswith(".json"):
        try:
            ja, jb = strip(json.loads(da), ignore), strip(json.loads(db), ignore)
        except ValueError as e:
            return "not JSON: %s" % e
        if ja == jb:
            return None
        keys = sorted(set(ja) ^ set(jb)) if isinstance(ja, dict) and isinstance(jb, dict) else []
        diff = [k for k in (ja if isinstance(ja, dict) else {})
                if isinstance(jb, dict) and k in jb and ja[k] != jb[k]]
        return "JSON differs (keys %s)" % ", ".join((diff + keys)[:8])
    if name.endswith(".csv"):
        ra, rb = csv_rows(da.decode(errors="replace")), csv_rows(db.decode(errors="replace"))
        if ra == rb:
            return None
        for i, (x, y) in enumerate(zip(ra, rb)):
            if x != y:
                return "row %d differs: %s vs %s" % (i + 1, x[:6], y[:6])
        return "%d rows vs %d" % (len(ra), len(rb))
    return None if da == db else "bytes differ"


def compare(a, b, ignore):
    problems, files = [], 0
    for root, _, names in os.walk(a):
        for n in sorted(names):
            if n in SKIP_NAMES or n.endswith(SKIP_EXT):
                continue
            pa = os.path.join(root, n)
            rel = os.path.relpath(pa, a)
            pb = os.path.join(b, rel)
            files += 1
            if not os.path.exists(pb):
                problems.append("%s: only in %s" % (rel, a))
                continue
            why = same_file(pa, pb, ignore)
            if why:
                problems.append("%s: %s" % (rel, why))
    return files, problems


def self_test():
    with tempfile.TemporaryDirectory() as t:
        a, b = os.path.join(t, "a"), os.path.join(t, "b")
        for d in (a, b):
            os.makedirs(os.path.join(d, "run"))
        runs = [({"distance_m": 1.5, "wall_time_s": 3, "decision_ms_mean": 1},
                 {"distance_m": 1.5, "wall_time_s": 9, "decision_ms_mean": 2}, True),
                ({"distance_m": 1.5}, {"distance_m": 1.6}, False)]
        for ja, jb, want in runs:
            for d, j in ((a, ja), (b, jb)):
                with open(os.path.join(d, "run", "summary.json"), "w") as f:
                    json.dump(j, f)
                with open(os.path.join(d, "run", "timeseries.csv"), "w") as f:
                    f.write("step,coverage,icp_ms\n1,0.5,%d\n" % len(j))
            _, problems = compare(a, b, set())
            if (not problems) != want:
                print("self-test failed: %s vs %s gave %s" % (ja, jb, problems))
                return 1
        with open(os.path.join(b, "run", "graph.g2o"), "w") as f:
            f.write("VERTEX_SE2 0 0 0 0\n")
        with open(os.path.join(a, "run", "graph.g2o"), "w") as f:
            f.write("VERTEX_SE2 0 0 0 1\n")
        if not any("graph.g2o" in p for p in compare(a, b, set())[1]):
            print("self-test failed: differing graph.g2o not reported")
            return 1
    print("self-test passed")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("a", nargs="?")
    ap.add_argument("b", nargs="?")
    ap.add_argument("--ignore-key", action="append", default=[])
    ap.add_argument("--self-test", action="store_true")
    o = ap.parse_args()
    if o.self_test:
        return self_test()
    if not (o.a and o.b) or not os.path.isdir(o.a) or not os.path.isdir(o.b):
        ap.error("two result folders are needed")
    files, problems = compare(o.a, o.b, set(o.ignore_key))
    _, missing = compare(o.b, o.a, set(o.ignore_key))
    problems += [p for p in missing if "only in" in p]
    for p in problems:
        print(p)
    print("%d files compared, %d differ" % (files, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
