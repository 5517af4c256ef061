#!/usr/bin/env bash
# The main job: install what is missing, build, and run the shipped default pipeline.
# Extra arguments go to `asf run` (e.g. --set pipeline.seed=7).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what the run needs (the host and its plugins); scripts/test.sh builds the tests.
bash scripts/build.sh asf_runtime
BUILD_DIR=${ASF_BUILD_DIR:-build}
"$BUILD_DIR/bin/asf" run configs/default.ini --out results/default "$@"
echo "Report: results/default/report.html (map, regions, coverage and pose error plots); numbers in results/default/summary.json."
