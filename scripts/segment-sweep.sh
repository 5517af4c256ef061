#!/usr/bin/env bash
# A segmenter's benchmark scores over a grid of its keys (every combination), one
# `asf segment-eval` per point, batch only (3-10 s each): to see which trade-offs a segmenter's
# parameters can reach, not to pick per-benchmark values (the maps are the test set).
# Usage: scripts/segment-sweep.sh [--segmenter NAME] [--set KEY=VALUE]... [--out DIR]
#                                 [--maps DIR] KEY=V1,V2,... [KEY=V1,V2,...]...
#   --set    fixed keys (e.g. --set variant=rooms); KEY=V1,V2 the swept ones
#   --out    JSON of every point and sweep.tsv (default results/segment-sweep)
#   --maps   the benchmark (plain/, gt/, furnished/; default ../shared/datasets/roomseg)
# Prints sweep.tsv: the swept values, then mean precision and recall (roomseg protocol) on the
# plain and the furnished maps, and whether the point meets issue 18's goal for the best
# variant (plain >= 0.97 / 0.96, furnished >= 0.96 / 0.90).
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF_BUILD_DIR:-build}/bin/asf
SEG=dude OUT=results/segment-sweep D=../shared/datasets/roomseg
FIXED=() AXES=()
while (($#)); do
  case $1 in
    --segmenter) SEG=$2; shift 2 ;;
    --set) FIXED+=(--set "$2"); shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --maps) D=$2; shift 2 ;;
    *=*) AXES+=("$1"); shift ;;
    *) echo "segment-sweep: unknown argument '$1' (want KEY=V1,V2,... or an option)" >&2; exit 2 ;;
  esac
done
((${#AXES[@]})) || { echo "segment-sweep: no KEY=V1,V2,... to sweep" >&2; exit 2; }
for sub in plain gt furnished; do
  [[ -d "$D/$sub" ]] || { echo "segment-sweep: $D/$sub: no such folder (the benchmark maps)" >&2; exit 1; }
done
[[ -x "$ASF" ]] || { echo "segment-sweep: $ASF not found: run scripts/build.sh first" >&2; exit 1; }
mkdir -p "$OUT"
TSV=$OUT/sweep.tsv
header=""
for axis in "${AXES[@]}"; do header+="${axis%%=*}	"; done
echo "${header}plain_precision	plain_recall	furnished_precision	furnished_recall	meets_goal" > "$TSV"

points=("")  # each point: "K1=v K2=w " (built axis by axis)
for axis in "${AXES[@]}"; do
  key=${axis%%=*}
  IFS=, read -r -a vals <<< "${axis#*=}"
  next=()
  for p in "${points[@]}"; do for v in "${vals[@]}"; do next+=("$p$key=$v "); done; done
  points=("${next[@]}")
done

n=0
for p in "${points[@]}"; do
  n=$((n + 1))
  sets=() row="" name=""
  for kv in $p; do sets+=(--set "$kv"); row+="${kv#*=}	"; name+="${kv//=/_}_"; done
  json="$OUT/${name%_}.json"
  echo "segment-sweep: [$n/${#points[@]}] $p" >&2
  "$ASF" segment-eval --plain "$D/plain" --gt "$D/gt" --furnished "$D/furnished" --resolution 0.05 \
    --segmenter "$SEG" "${FIXED[@]}" "${sets[@]}" --json "$json" > /dev/null 2>&1 ||
    { echo "segment-sweep: asf segment-eval failed at $p (rerun it by hand to see why)" >&2; exit 1; }
  scores=$(python3 - "$json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))["summary"]
p, f = s["plain"], s["furnished"]
v = [p["precision_mean"], p["recall_mean"], f["precision_mean"], f["recall_mean"]]
goal = [0.97, 0.96, 0.96, 0.90]
meets = all(round(x, 3) >= g for x, g in zip(v, goal))
print("\t".join(f"{x:.3f}" for x in v) + "\t" + ("yes" if meets else "no"))
EOF
)
  echo "$row$scores" >> "$TSV"
done
cat "$TSV"
