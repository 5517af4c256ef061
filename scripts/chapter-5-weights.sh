#!/usr/bin/env bash
# Thesis section 5.2 and Figs. 5.11-5.13 in one command:
# - Theorem 5.2.1 / eq. 5.54 on real pose graphs (intel and MIT as distributed with SE-Sync,
#   and a TIGRE run of the default cave pipeline): the exact information J^T Omega J against
#   the theorem's edge sum and the bound ||L_alpha||_p ||Sigma^-1||_p (asf optimal --theorem);
# - Figs. 5.11-5.13: optimal E, A and D weights drawn on three of the thesis' own 174 indoor
#   graphs, picked by the structure each caption describes (the thesis does not say which
#   graphs it drew): the first connected tree with >= 20 nodes (small world, "few nodes with
#   many connections"), the first connected graph with exactly one cycle and >= 15 nodes ("one
#   loop"), the first connected graph with >= 3 independent cycles and <= 30 nodes ("several
#   cycles"); and the same weights on the cave run's pose graph.
# Usage: scripts/chapter-5-weights.sh [OUT_DIR] [SHARED_DIR]
#   OUT_DIR defaults to results/chapter-5-weights; SHARED_DIR to ../shared.
# Needs a built tree (scripts/build.sh). About 3 min on 2 cores (most of it the cave run and
# the dense spectra of MIT's 808 poses).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-results/chapter-5-weights}
S=${2:-../shared}
ASF=${ASF_BUILD_DIR:-build}/bin/asf
G=$S/datasets/optexp/graphs.txt
for f in "$G" "$S/datasets/g2o/intel.g2o" "$S/datasets/g2o/MIT.g2o"; do
  [[ -f "$f" ]] || { echo "chapter-5-weights: $f: no such file" >&2; exit 1; }
done
[[ -x "$ASF" ]] || { echo "chapter-5-weights: $ASF not found: run scripts/build.sh first" >&2; exit 1; }
mkdir -p "$OUT"
pick() {  # rule -> line number of the graph list
  python3 - "$G" "$1" <<'PY'
import sys
path, rule = sys.argv[1], sys.argv[2]
for line_no, line in enumerate(open(path), 1):
    t = line.split()
    if not t or t[0].startswith('#'):
        continue
    n, m = int(t[0]), int(t[1])
    edges = [tuple(map(int, e.split('-'))) for e in t[2:]]
    adj = {v: [] for v in range(1, n + 1)}
    for a, b in edges:
        adj[a].append(b); adj[b].append(a)
    seen, stack = {1}, [1]
    while stack:
        for w in adj[stack.pop()]:
            if w not in seen:
                seen.add(w); stack.append(w)
    if len(seen) != n:
        continue
    cycles = m - n + 1
    if (rule == 'tree' and cycles == 0 and n >= 20) or \
       (rule == 'one_loop' and cycles == 1 and n >= 15) or \
       (rule == 'cycles' and cycles >= 3 and n <= 30):
        print(line_no); sys.exit(0)
sys.exit("no graph matches " + rule)
PY
}
n=11
for rule in tree one_loop cycles; do
  line=$(pick $rule)
  echo "chapter-5-weights: fig 5.$n: $G line $line ($rule)" >&2
  "$ASF" optimal "$G" --index "$line" --criteria E,A,D --draw "$OUT/fig_5_$n.svg" \
    > "$OUT/fig_5_$n.txt"
  n=$((n + 1))
done
echo "chapter-5-weights: a TIGRE run of configs/default.ini" >&2
"$ASF" run configs/default.ini --set pipeline.progress_interval=0 --out "$OUT/cave_run" > "$OUT/cave_run.log" 2>&1
for g in "$S/datasets/g2o/intel.g2o" "$S/datasets/g2o/MIT.g2o" "$OUT/cave_run"; do
  name=$(basename "$g" .g2o)
  echo "chapter-5-weights: theorem 5.2.1 on $name" >&2
  crit=T,D,A,E
  [[ $name == intel ]] && crit=D  # 1728 poses: only D (sparse) at this size
  "$ASF" optimal "$g" --criteria $crit --theorem --json > "$OUT/theorem_$name.json"
done
"$ASF" optimal "$OUT/cave_run" --criteria E,A,D --draw "$OUT/cave_weights.svg" > /dev/null
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
rows = ["| graph | Sigma^-1 (median reference) | alpha min / median / max | sharpness median | criterion | exact | edge sum (Thm 5.2.1) | bound (eq. 5.54) | edge sum / bound | exact / edge sum |",
        "|---|---|---|---|---|---|---|---|---|---|"]
for name in ("intel", "MIT", "cave_run"):
    j = json.load(open(f"{out}/theorem_{name}.json"))
    e = j["edge_information"]
    s = e["sigma_inverse"]
    for c in ("T", "D", "A", "E"):
        t = j["theorem"].get(c)
        if t is None:
            continue
        rows.append(f"| {name} ({j['n']} poses, {j['m']} edges) | diag({s[0]:.4g}, {s[1]:.4g}, {s[2]:.4g}) | "
                    f"{e['alpha_min']:.3g} / {e['alpha_median']:.3g} / {e['alpha_max']:.4g} | {e['sharpness_median']:.3f} | {c} | "
                    f"{t['exact']:.5g} | {t['edge_sum']:.5g} | {t['bound']:.5g} | {t['edge_sum']/t['bound']:.4f} | {t['exact']/t['edge_sum']:.4f} |")
open(f"{out}/theorem_5_2_1.md", "w").write("\n".join(rows) + "\n")
print("\n".join(rows))
PY
echo "chapter-5-weights: $OUT/theorem_5_2_1.md, $OUT/fig_5_11.svg .. fig_5_13.svg, $OUT/cave_weights.svg"
