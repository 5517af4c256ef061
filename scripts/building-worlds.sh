#!/usr/bin/env bash
# Exploration of real buildings (issue 26's multi-room worlds): the default pipeline
# (configs/explore_map_server.ini: TIGRE, ICP graph SLAM, DuDe; with default.ini's
# incremental back-end, sparse_lm.incremental=true, set here) on
# the plain maps of the room segmentation benchmark (Bormann et al. 2016; ../shared/datasets/
# roomseg/plain: ROS map_server images at 0.05 m/px, gray 205 = unknown, which the simulator
# treats as wall), one run per map, and a markdown table: whether the policy finished,
# steps, keyframes, distance, coverage, keyframe ATE, wall time and the per-stage times summed
# from each run's timeseries.csv (ms per step in brackets).
#   scripts/building-worlds.sh [--maps DIR] [--only "NAME ..."] [--max-steps N]
#                              [--config INI] [--set KEY=VALUE]... [--reuse] [OUT_DIR]
# --config: another pipeline (default configs/explore_map_server.ini; configs/
# explore_building.ini adds the loop search that refuses aliased offices).
# Needs the built host (scripts/build.sh) and the maps (a user's clone has no ../shared:
# then it says so and exits 77). Runs one at a time; outputs in OUT_DIR (default
# results/buildings): OUT_DIR/worlds/NAME.yaml, OUT_DIR/NAME/ (the run) and NAME.log.
# --reuse keeps a map whose run finished there before. Deterministic per seed.
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF:-build/bin/asf}
MAPS=../shared/datasets/roomseg/plain ONLY="" MAX_STEPS=20000 REUSE=0 SETS=()
CONFIG=configs/explore_map_server.ini
while (($#)); do
  case $1 in
    --maps) MAPS=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    --max-steps) MAX_STEPS=$2; shift 2 ;;
    --config) CONFIG=$2; shift 2 ;;
    --set) SETS+=(--set "$2"); shift 2 ;;
    --reuse) REUSE=1; shift ;;
    -*) echo "building-worlds: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
OUT=${1:-results/buildings}
[[ -x "$ASF" ]] || { echo "building-worlds: $ASF not built (run scripts/build.sh)" >&2; exit 2; }
[[ -d "$MAPS" ]] || { echo "building-worlds: SKIP: no maps in $MAPS (../shared is beside the repository only)" >&2; exit 77; }
MAPS=$(cd "$MAPS" && pwd)
mkdir -p "$OUT/worlds"
names=()
if [[ -n $ONLY ]]; then names=($ONLY); else
  for f in "$MAPS"/*.png; do names+=("$(basename "$f" .png)"); done
fi
for n in "${names[@]}"; do
  [[ -f "$MAPS/$n.png" ]] || { echo "building-worlds: no $MAPS/$n.png" >&2; exit 2; }
  # The benchmark's maps are map_server images: 254 free, 0 occupied, 205 unknown
  # ((255 - 205) / 255 = 0.1961 > free_thresh 0.196).
  cat > "$OUT/worlds/$n.yaml" <<EOF
image: $MAPS/$n.png
resolution: 0.05
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
EOF
  if ((REUSE)) && [[ -f "$OUT/$n/summary.json" ]]; then
    echo "building-worlds: $n: reusing $OUT/$n" >&2
    continue
  fi
  echo "building-worlds: $n" >&2
  "$ASF" run "$CONFIG" -o "$OUT/$n" --set sim2d.map_image="$OUT/worlds/$n.yaml" \
    --set sparse_lm.incremental=true --set pipeline.max_steps="$MAX_STEPS" \
    --set pipeline.progress_interval=0 "${SETS[@]}" \
    > "$OUT/$n.log" 2>&1 ||
    { echo "building-worlds: the run on $n failed (see $OUT/$n.log)" >&2; exit 1; }
done
python3 - "$OUT" "${names[@]}" <<'PY'
import sys
sys.path.insert(0, "scripts")
from stage_times import NAMES, stage_cells, stage_totals
out, names = sys.argv[1], sys.argv[2:]
print("| map | finished | steps | keyframes | distance [m] | coverage [%] | ATE [m] | wall [s] | " +
      " | ".join(f"{h} [s] (ms/step)" for h in NAMES) + " |")
print("|---" * (8 + len(NAMES)) + "|")
for n in names:
    s, tot, wall = stage_totals(f"{out}/{n}")
    print(f"| {n} | {'yes' if s['finished'] else 'no'} | {s['steps']} | {s['nodes']} | "
          f"{s['distance_m']:.1f} | {100 * s['coverage']:.1f} | {s['ate_rmse_m']:.4f} | "
          f"{wall / 1000:.2f} | {stage_cells(tot, s['steps'])} |")
PY
