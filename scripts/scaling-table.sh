#!/usr/bin/env bash
# Run time against world size (issue 26): the default pipeline on the cave tiled n x n
# (`sim2d.map_tiles`, every other tile mirrored: 20 m per tile), one run per size, and a
# markdown table of the per-stage times summed from each run's timeseries.csv, per step, and
# how each stage grows from one size to the next (exponent of the steps: 1 = linear).
#   scripts/scaling-table.sh [--tiles "1 2 3"] [--config INI] [--set KEY=VALUE]... [--reuse] [OUT_DIR]
# Needs the built host (scripts/build.sh). Runs one at a time; outputs in OUT_DIR (default
# results/scaling); --reuse keeps a size whose run finished there before (summary.json) and
# only tabulates it. Deterministic per seed: only the times depend on the machine.
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF:-build/bin/asf}
TILES="1 2 3" CONFIG=configs/default.ini REUSE=0 SETS=()
while (($#)); do
  case $1 in
    --reuse) REUSE=1; shift ;;
    --tiles) TILES=$2; shift 2 ;;
    --config) CONFIG=$2; shift 2 ;;
    --set) SETS+=(--set "$2"); shift 2 ;;
    -*) echo "scaling-table: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
OUT=${1:-results/scaling}
[[ -x "$ASF" ]] || { echo "scaling-table: $ASF not built (run scripts/build.sh)" >&2; exit 2; }
mkdir -p "$OUT"
for n in $TILES; do
  if ((REUSE)) && [[ -f "$OUT/tiles_$n/summary.json" ]]; then
    echo "scaling-table: $n x $n tiles: reusing $OUT/tiles_$n" >&2
    continue
  fi
  echo "scaling-table: $n x $n tiles" >&2
  "$ASF" run "$CONFIG" -o "$OUT/tiles_$n" --set sim2d.map_tiles="$n" \
    --set pipeline.max_steps=1000000 --set pipeline.progress_interval=0 "${SETS[@]}" > "$OUT/tiles_$n.log" 2>&1 ||
    { echo "scaling-table: the run with $n tiles failed (see $OUT/tiles_$n.log)" >&2; exit 1; }
done
python3 - "$OUT" $TILES <<'PY'
import math, sys
sys.path.insert(0, "scripts")
from stage_times import NAMES as names, STAGES as stages, stage_cells, stage_totals
out, tiles = sys.argv[1], sys.argv[2:]
rows = []
for n in tiles:
    s, tot, wall = stage_totals(f"{out}/tiles_{n}")
    rows.append((int(n), s["steps"], s["nodes"], wall, tot, s["distance_m"], s["ate_rmse_m"]))
keys = stages + ["rest"]
print("| world | steps | keyframes | distance [m] | ATE [m] | wall [s] | " +
      " | ".join(f"{n} [s] (ms/step)" for n in names) + " |")
print("|---" * (6 + len(names)) + "|")
for n, steps, nodes, wall, tot, dist, ate in rows:
    cells = stage_cells(tot, steps)
    print(f"| {20 * n} m | {steps} | {nodes} | {dist:.1f} | {ate:.4f} | {wall / 1000:.2f} | {cells} |")
print()
print("Growth exponent of each stage's total time in the steps, log(t2/t1) / log(s2/s1):")
print()
print("| from | to | wall | " + " | ".join(names) + " |")
print("|---" * (3 + len(names)) + "|")
for a, b in zip(rows, rows[1:]):
    ls = math.log(b[1] / a[1])
    def g(x, y):
        return f"{math.log(y / x) / ls:.2f}" if x > 0 and y > 0 and ls > 0 else "-"
    cells = " | ".join(g(a[4][k], b[4][k]) for k in keys)
    print(f"| {20 * a[0]} m | {20 * b[0]} m | {g(a[3], b[3])} | {cells} |")
PY
