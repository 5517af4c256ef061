#!/usr/bin/env bash
# make-rosbag2-fixture.sh OUT_DIR [VARIANT[@STORAGE]]: writes a small ROS 2 bag for the tests
# with a writer independent of asf (tests/fixtures/make_rosbag2.js: Foxglove's ROS 2 CDR
# serializer from npm, the sqlite3 shell from Debian, or Foxglove's MCAP writer from npm). Installs what it needs on first use: the Debian
# packages (sqlite3; nodejs and npm when there is no node), the npm packages, pinned, into
# $ASF_TEST_TOOLS (default: ${ASF_BUILD_DIR:-build}/test-tools).
set -euo pipefail
cd "$(dirname "$0")/.."
TOOLS=${ASF_TEST_TOOLS:-${ASF_BUILD_DIR:-build}/test-tools}
command -v sqlite3 >/dev/null || bash scripts/install-deps.sh sqlite3 >&2
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
NODE_PATH="$TOOLS/node_modules" node tests/fixtures/make_rosbag2.js "$@"
