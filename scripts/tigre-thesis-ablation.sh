#!/usr/bin/env bash
# Where TIGRE's distance goes between asf's configuration and the thesis' (issue 48, item 3):
# TIGRE on the author's robot (configs/cave_thesis.ini), SEEDS seeds per row, each row one
# `asf experiment`: the thesis author's DuDe change rule alone (the baseline), then each other
# setting of the thesis' configuration added to it alone, then all of them together
# (configs/experiment_cave_as_thesis.ini's TIGRE). The offline Chinese postman (cpp_offline)
# runs on the same seeds once per distinct [dude] setting among the rows (its graph comes from
# the segmenter; TIGRE's keys do not touch it). Prints a markdown table: TIGRE's distance mean
# and std, its ratio to the Chinese postman's mean under the same [dude] setting, the distance
# after 99 % coverage, mean pose error, keyframe ATE, coverage.
#   scripts/tigre-thesis-ablation.sh OUT_DIR [SEEDS (default 10)] [JOBS (default 2)]
# An experiment whose folder already holds its summary under the same INI is kept (a rerun
# resumes). Deterministic per seed; about 25 s per TIGRE run on this project's 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF:-build/bin/asf}
out=${1:?usage: scripts/tigre-thesis-ablation.sh OUT_DIR [SEEDS] [JOBS]}
seeds=${2:-10} jobs=${3:-2}
mkdir -p "$out"
base="dude.change_rule=reference"
rows=(
  "reference rule|$base"
  "+ variant = thesis|$base; dude.variant=thesis"
  "+ full re-segmentation after loop closures|$base; dude.rebuild_full_fraction=0"
  "+ ties = random|$base; tigre.ties=random"
  "+ relocate = false|$base; tigre.relocate=false"
  "+ next_goal = centre|$base; tigre.next_goal=centre"
  "+ robot_radius = 0.325|$base; tigre.robot_radius=0.325"
  "all: the thesis' configuration|$base; dude.variant=thesis; dude.rebuild_full_fraction=0; tigre.ties=random; tigre.relocate=false; tigre.next_goal=centre; tigre.robot_radius=0.325"
)
# experiment DIR POLICIES OVERRIDES: one asf experiment into DIR/runs, kept when done before.
experiment() {
  local dir=$1 policies=$2 overrides=$3 ini
  ini=$(printf '[experiment]\npipeline = %s\npolicies = %s\nreplications = %s\nfirst_seed = 1\noverrides = %s\n' \
    "$PWD/configs/cave_thesis.ini" "$policies" "$seeds" "$overrides; pipeline.progress_interval=0")
  mkdir -p "$dir"
  if [[ -f "$dir/runs/summary.json" && -f "$dir/experiment.ini" && "$(cat "$dir/experiment.ini")" == "$ini" ]]; then
    return 0
  fi
  rm -rf "$dir/runs"
  echo "$ini" >"$dir/experiment.ini"
  "$ASF" experiment "$dir/experiment.ini" -j "$jobs" -o "$dir/runs" >"$dir/experiment.log" 2>&1 ||
    { echo "tigre-thesis-ablation: $dir failed (see $dir/experiment.log)" >&2; exit 1; }
}
i=0
for row in "${rows[@]}"; do
  i=$((i + 1))
  name=${row%%|*} overrides=${row#*|}
  echo "row $i/${#rows[@]}: $name" >&2
  experiment "$out/row_$i" tigre "$overrides"
  echo "$name" >"$out/row_$i/name"
  # The Chinese postman under this row's [dude] keys.
  dude=$(tr ';' '\n' <<<"$overrides" | sed 's/^ *//; s/ *$//' | grep '^dude\.' | paste -sd';' | sed 's/;/; /g')
  key=$(tr -c 'a-zA-Z0-9\n' '_' <<<"$dude")
  echo "cpp_$key" >"$out/row_$i/cpp"
  experiment "$out/cpp_$key" cpp_offline "$dude"
done
python3 - "$out" "${#rows[@]}" <<'PY'
import json, sys
out, n = sys.argv[1], int(sys.argv[2])
print("| TIGRE on cave_thesis.ini | finished | distance (m) | CPP (m) | / CPP | after 99 % coverage (m) | mean pose error (m) | keyframe ATE (m) | coverage (%) |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for i in range(1, n + 1):
    d = f"{out}/row_{i}"
    name = open(f"{d}/name").read().strip()
    s = json.load(open(f"{d}/runs/summary.json"))
    cpp = json.load(open(f"{out}/{open(f'{d}/cpp').read().strip()}/runs/summary.json"))["policies"]["cpp_offline"]
    t = s["policies"]["tigre"]
    runs = [r for r in s["runs"] if r.get("policy", "tigre") == "tigre"]
    after = [r["distance_m"] - r["distance_to_coverage_99_m"] for r in runs
             if r.get("distance_to_coverage_99_m") is not None]
    after_m = sum(after) / len(after) if after else float("nan")
    print(f"| {name} | {t['finished']}/{t['total']} | {t['distance_m']['mean']:.1f} ± {t['distance_m']['std']:.1f} "
          f"| {cpp['distance_m']['mean']:.1f} | {t['distance_m']['mean'] / cpp['distance_m']['mean']:.2f} "
          f"| {after_m:.1f} ({len(after)} runs) | {t['mean_pose_error_m']['mean']:.3f} "
          f"| {t['ate_rmse_m']['mean']:.4f} | {100 * t['coverage']['mean']:.1f} |")
PY
