#!/usr/bin/env bash
# make-rosbag2-fixture.sh OUT_DIR [VARIANT[@STORAGE]]: writes a small ROS 2 bag for the tests
# with a writer independent of asf (tests/fixtures/make_rosbag2.js: Foxglove's ROS 2 CDR
# serializer from npm, the sqlite3 shell from Debian, or Foxglove's MCAP writer from npm). Installs what it needs on first use: the Debian
# packages (sqlite3; nodejs and npm when there is no node), the npm packages, pinned, into
# $ASF_TEST_TOOLS (default: ${ASF_BUILD_DIR:-build}/test-tools).
set -euo pipefail
cd "$(dirname "$0")/.."
command -v sqlite3 >/dev/null || bash scripts/install-deps.sh sqlite3 >&2
modules=$(bash scripts/test-tools.sh)
NODE_PATH="$modules" node tests/fixtures/make_rosbag2.js "$@"
