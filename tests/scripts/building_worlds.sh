#!/usr/bin/env bash
# scripts/building-worlds.sh on one benchmark map with a short step budget: it writes the
# map_server YAML the simulator reads (gray 205 unknown), runs the pipeline on it and prints
# the table row. Skipped (77) without ../shared's room segmentation maps.
#   tests/scripts/building_worlds.sh ASF_BINARY SOURCE_DIR OUT_DIR
set -euo pipefail
asf=$1 src=$2 out=$3
rm -rf "$out"
set +e
ASF=$asf bash "$src/scripts/building-worlds.sh" --only office_c --max-steps 300 "$out" > "$out.md" 2> "$out.err"
rc=$?
set -e
if ((rc == 77)); then cat "$out.err"; exit 77; fi
((rc == 0)) || { cat "$out.err"; echo "FAIL: exit $rc"; exit 1; }
grep -q "^free_thresh: 0.196$" "$out/worlds/office_c.yaml" || { echo "FAIL: the YAML"; exit 1; }
row=$(grep "^| office_c | " "$out.md") || { cat "$out.md"; echo "FAIL: no table row"; exit 1; }
# The budget ends the run: not finished, 300 steps.
[[ $row == "| office_c | no | 300 | "* ]] || { echo "FAIL: row: $row"; exit 1; }
python3 - "$out/office_c/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["steps"] == 300 and s["coverage"] > 0.02, (s["steps"], s["coverage"])
PY
echo "OK: $row"
