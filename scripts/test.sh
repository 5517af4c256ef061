#!/usr/bin/env bash
# Install what is missing, build, and run the whole test suite (CTest).
# Tests that need ../shared (datasets beside the repository) skip themselves without it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${ASF_BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${ASF_JOBS:-$(nproc)}" "$@"
