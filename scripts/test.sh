#!/usr/bin/env bash
# Install what is missing, build, and run the whole test suite (CTest).
# Tests that need ../shared (datasets beside the repository) skip themselves without it.
set -euo pipefail
cd "$(dirname "$0")/.."
# The optional ROS 2 component too (its tests run two DDS implementations on loopback).
bash scripts/install-deps.sh --ros2
bash scripts/build.sh
BUILD_DIR=${ASF_BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${ASF_JOBS:-$(nproc)}" "$@"
