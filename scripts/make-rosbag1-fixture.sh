#!/usr/bin/env bash
# make-rosbag1-fixture.sh OUT_DIR [VARIANT [RECORDS.json]]: writes OUT_DIR/data.bag, a small
# ROS 1 bag for the tests, with the official ROS 1 Python libraries (Debian's python3-rosbag and
# message packages; tests/fixtures/make_rosbag1.py), installed on first use.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=/usr/bin/python3  # Debian's, whose dist-packages hold the ROS 1 libraries
if ! "$PY" -c "import rosbag, sensor_msgs.msg, nav_msgs.msg, tf2_msgs.msg" 2>/dev/null; then
  bash scripts/install-deps.sh python3-rosbag python3-sensor-msgs python3-nav-msgs \
    python3-tf2-msgs python3-geometry-msgs >&2
fi
"$PY" tests/fixtures/make_rosbag1.py "$@"
