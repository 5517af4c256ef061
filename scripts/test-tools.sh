#!/usr/bin/env bash
# test-tools.sh: installs (once) the independent readers and writers the tests compare asf
# with: Foxglove's ROS 2 CDR (de)serializer and message definitions, and the MCAP library,
# from npm, pinned, into $ASF_TEST_TOOLS (default: ${ASF_BUILD_DIR:-build}/test-tools), with
# Node.js and npm from Debian when missing. Prints the node_modules folder (for NODE_PATH).
set -euo pipefail
cd "$(dirname "$0")/.."
TOOLS=${ASF_TEST_TOOLS:-${ASF_BUILD_DIR:-build}/test-tools}
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  bash scripts/install-deps.sh nodejs npm >&2
fi
mkdir -p "$TOOLS"
(
  flock 9  # tests run in parallel: one installs, the others wait for it
  if [[ ! -f "$TOOLS/node_modules/lz4js/package.json" ]]; then
    npm install --prefix "$TOOLS" --no-audit --no-fund --silent --no-save \
      @foxglove/rosmsg2-serialization@3.1.0 @foxglove/rosmsg-msgs-common@3.2.3 \
      @mcap/core@2.2.2 @foxglove/wasm-zstd@1.0.1 lz4js@0.2.0 >&2
  fi
) 9>"$TOOLS/.lock"
echo "$(cd "$TOOLS" && pwd)/node_modules"
