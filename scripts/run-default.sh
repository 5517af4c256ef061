#!/usr/bin/env bash
# The main job: install what is missing, build, and run the shipped default pipeline.
# Extra arguments go to `asf run` (e.g. --set pipeline.seed=7).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${ASF_BUILD_DIR:-build}
"$BUILD_DIR/bin/asf" run configs/default.ini --out results/default "$@"
echo "Open results/default/map.png and results/default/regions.png; numbers in results/default/summary.json."
