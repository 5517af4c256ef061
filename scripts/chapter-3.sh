#!/usr/bin/env bash
# Thesis chapter 3 on real logs in one command: Table 3.1 (unreliable-zone avoidance, ch.
# 3.5.1) on the Intel Research Lab and ACES CARMEN logs, and Fig. 3.3 (the Monte Carlo of
# place recognition in a corridor and at a corner) on ACES.
# - each log converted (asf carmen2rawlog, odometry synthesized with MRPT's motion model,
#   seed 1) and its graph SLAM run (configs/slam_<log>.ini);
# - asf plan-eval configs/plan_eval_<log>.ini on the run: in each zone every scan ignored, the
#   links wheel odometry x10 / x100, p_recognition by Monte Carlo ICP on each node's scan;
# - Fig. 3.3: asf recognition on the ACES run, 100 samples at node 141 (the middle of the
#   outer west corridor) and node 153 (the corner where it meets the north corridor);
# - Table 3.2 / Fig. 3.6: the ACES run stopped after 292 frames, when the robot first stands
#   in the rotunda (node 201), having driven the outer ring and the central north arm and
#   seen the other three arms from the rotunda (map.widen_beams: far rays leave no gaps).
#   asf plan --voronoi from node 201 to node 128 (the west corridor where the west arm, seen
#   but not driven, ends): the best path along the graph against the best one through the
#   unexplored arm (length, det E[C], product: eq. 3.25). Virtual edges' odometry: MRPT's
#   model in increments of the run's mean frame step (distance / frames); the same with the
#   odometry covariance x 0.1, 0.03, 0.01 shows where the trade-off turns.
# Usage: scripts/chapter-3.sh [OUT_DIR] [SHARED_DIR]
#   OUT_DIR defaults to results/chapter-3; SHARED_DIR to ../shared.
#   QUICK=1: 20 pairs per zone and 10 Monte Carlo samples (a smoke run of a few minutes).
# Needs a built tree (scripts/build.sh). About 50 min on 2 cores (each plan-eval ~25 min:
# 300 pairs x 4 scenarios x ~1 s of the expected-uncertainty planner).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-results/chapter-3}
S=${2:-../shared}
ASF=${ASF_BUILD_DIR:-build}/bin/asf
[[ -x "$ASF" ]] || { echo "chapter-3: $ASF not found: run scripts/build.sh first" >&2; exit 1; }
PAIRS=300 SAMPLES=40 FIG_SAMPLES=100
if [[ "${QUICK:-0}" == 1 ]]; then PAIRS=20 SAMPLES=10 FIG_SAMPLES=20; fi
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)  # --set paths are taken as given: make them absolute
S=$(cd "$S" && pwd)
for log in intel aces; do
  src=$S/datasets/carmen/$log-corrected.log.gz
  [[ -f "$src" ]] || { echo "chapter-3: $src: no such file" >&2; exit 1; }
  if [[ ! -f "$OUT/$log.rawlog.gz" ]]; then
    echo "chapter-3: converting $src" >&2
    "$ASF" carmen2rawlog -q -i "$src" -o "$OUT/$log.rawlog.gz" --gt "$OUT/$log.gt.txt" \
      --synth-odometry --seed 1
  fi
  if [[ ! -f "$OUT/slam_$log/graph.g2o" ]]; then
    echo "chapter-3: graph SLAM on $log" >&2
    "$ASF" run "configs/slam_$log.ini" --out "$OUT/slam_$log" \
      --set "rawlog.file=$OUT/$log.rawlog.gz" --set "rawlog.ground_truth=$OUT/$log.gt.txt" \
      > "$OUT/slam_$log.txt"
  fi
  echo "chapter-3: Table 3.1 on $log" >&2
  "$ASF" plan-eval "configs/plan_eval_$log.ini" --out "$OUT/table_3_1_$log" \
    --set "plan_eval.graph=$OUT/slam_$log/graph.g2o" --set "plan_eval.rawlog=$OUT/$log.rawlog.gz" \
    --set "plan_eval.max_pairs=$PAIRS" --set "plan_eval.recognition_samples=$SAMPLES" \
    > "$OUT/table_3_1_$log.txt"
done
echo "chapter-3: Fig. 3.3 on aces" >&2
"$ASF" recognition "$OUT/slam_aces/graph.g2o" -r "$OUT/aces.rawlog.gz" -n "$FIG_SAMPLES" \
  -s 141 -s 153 -o "$OUT/fig_3_3" > "$OUT/fig_3_3.txt"
echo "chapter-3: Table 3.2 on aces, partially explored" >&2
P=$OUT/aces_partial
"$ASF" run configs/slam_aces.ini --out "$P" --set "rawlog.file=$OUT/aces.rawlog.gz" \
  --set "rawlog.ground_truth=$OUT/aces.gt.txt" --set rawlog.max_frames=292 \
  --set map.widen_beams=true > "$P.txt"
STEP=$(python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(j['distance_m'] / j['steps'])" "$P/summary.json")
plan32() {  # covariance scale, output stem: the plan as JSON, the chosen path drawn
  "$ASF" plan --graph "$P/graph.g2o" --map "$P/map.yaml" --voronoi --start 201 \
    --goal 128 --planner expected_uncertainty --set max_seconds=0 \
    --set "voronoi_odometry_step=$STEP" --set "voronoi_cov_scale=$1" --image "$2.png" \
    --json > "$2.json"
}
plan32 1 "$OUT/table_3_2"
for s in 0.1 0.03 0.01; do plan32 "$s" "$OUT/table_3_2_cov_$s"; done
cat "$OUT/table_3_1_intel/plan_eval.md" "$OUT/table_3_1_aces/plan_eval.md" "$OUT/fig_3_3.txt"
python3 - "$OUT" "$STEP" <<'PY'
import glob, json, sys
out, step = sys.argv[1], float(sys.argv[2])
print(f"\nTable 3.2 (ACES after 292 frames, node 201 -> 128; virtual edges' odometry in {step:.3f} m "
      "increments):\n\n| odometry covariance | path | distance [m] | det E[C] | product | chosen |\n"
      "|---|---|---:|---:|---:|---|")
for f in [f"{out}/table_3_2.json"] + sorted(glob.glob(f"{out}/table_3_2_cov_*.json"), reverse=True):
    j = json.load(open(f))
    scale = f.split("_cov_")[1][:-5] if "_cov_" in f else "1"
    for kind, name in (("graph", "graph SLAM"), ("unexplored", "traversing unexplored")):
        c = j["comparison"][kind]
        if c is None:
            print(f"| x{scale} | {name} | - | - | - | |")
            continue
        chosen = "yes" if c["path"] == j["path"] else ""
        print(f"| x{scale} | {name} | {c['distance']:.1f} | {c['expected_uncertainty']:.3g} | "
              f"{c['cost']:.3g} | {chosen} |")
PY
echo "chapter-3: wrote $OUT" >&2
