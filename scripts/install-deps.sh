#!/usr/bin/env bash
# Installs every Debian package asf needs to build, test and run.
# Idempotent: when everything is present it returns after one dpkg query. Arguments are more
# packages to install the same way (scripts/fuzz.sh: clang and its libFuzzer runtime); --ros2
# adds the optional ROS 2 component's (both DDS implementations and their code generators;
# scripts/test.sh installs them, the main job does not need them).
set -euo pipefail

ROS2_PKGS=(cyclonedds-dev cyclonedds-tools libfastrtps-dev fastddsgen)
args=()
for a in "$@"; do
  if [[ "$a" == "--ros2" ]]; then args+=("${ROS2_PKGS[@]}"); else args+=("$a"); fi
done
set -- ${args[@]+"${args[@]}"}

PKGS=(
  build-essential cmake pkg-config ccache
  libmrpt-dev mrpt-common libnanoflann-dev
  libeigen3-dev libopencv-dev liboctomap-dev libsuitesparse-dev libcgal-dev
  libgtest-dev libgmock-dev libbenchmark-dev libtclap-dev nlohmann-json3-dev
  libbz2-dev zlib1g-dev libsqlite3-dev librosbag-storage-dev libzstd-dev liblz4-dev
  python3-cvxopt  # tests: independent solver the optimal-design cross-check compares with
  sqlite3         # tests: writes the ROS 2 bag fixtures (scripts/make-rosbag2-fixture.sh)
  "$@"
)

missing=()
for p in "${PKGS[@]}"; do
  # dpkg-query prints "install ok installed" only for fully installed packages.
  st=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$st" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "asf: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "asf: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
