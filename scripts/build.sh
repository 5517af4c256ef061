#!/usr/bin/env bash
# Installs missing Debian packages, configures and builds asf into build/ (or $ASF_BUILD_DIR):
# everything, or only the CMake targets given (scripts/run-default.sh: asf_runtime, the host
# and its plugins).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${ASF_BUILD_DIR:-build}
BUILD_TYPE=${ASF_BUILD_TYPE:-Release}
JOBS=${ASF_JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE="$BUILD_TYPE" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$BUILD_DIR" -j "$JOBS" ${targets[@]+"${targets[@]}"}
