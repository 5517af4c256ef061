#!/usr/bin/env bash
# Thesis Table 4.1 and Figs. 4.1-4.2 in one command: the room segmentation benchmark scored
# for dude (variant = thesis), dude (variant = rooms) and voronoi, batch and (DuDe) incremental,
# then put side by side with the thesis' values (asf segment-report). Incremental runs follow
# the author's own protocol (--exploration raster_disks: 5 m disks revealed every 2.5 m along
# rows) on the plain and the furnished maps.
# Usage: scripts/table-4-1.sh [OUT_DIR] [BENCHMARK_DIR]
#   OUT_DIR defaults to results/table-4-1; BENCHMARK_DIR to ../shared/datasets/roomseg
#   (plain/, gt/, furnished/ as described in ../shared/docs/roomseg-eval.md).
# Needs a built tree (scripts/build.sh); runs one evaluation at a time so the times compare.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-results/table-4-1}
D=${2:-../shared/datasets/roomseg}
ASF=${ASF_BUILD_DIR:-build}/bin/asf
for sub in plain gt furnished; do
  [[ -d "$D/$sub" ]] || { echo "table-4-1: $D/$sub: no such folder (the benchmark maps)" >&2; exit 1; }
done
[[ -x "$ASF" ]] || { echo "table-4-1: $ASF not found: run scripts/build.sh first" >&2; exit 1; }
mkdir -p "$OUT"
eval_one() {  # label, segmenter, extra args...
  local label=$1 seg=$2
  shift 2
  echo "table-4-1: $label" >&2
  "$ASF" segment-eval --plain "$D/plain" --gt "$D/gt" --furnished "$D/furnished" --resolution 0.05 \
    --segmenter "$seg" --json "$OUT/$label.json" "$@" > "$OUT/$label.txt"
}
INC="--incremental --exploration raster_disks --incremental-on both"
eval_one dude_thesis dude --set variant=thesis $INC
eval_one dude_rooms dude --set variant=rooms $INC
eval_one voronoi voronoi
"$ASF" segment-report "$OUT/dude_thesis.json" "$OUT/dude_rooms.json" "$OUT/voronoi.json" \
  -l "dude thesis" -l "dude rooms" -l "voronoi" -o "$OUT"
echo "table-4-1: $OUT/table_4_1.md"
