#!/usr/bin/env bash
# Where the ROS 2 bridge's CPU goes (docs/ROS2.md, "The bridge's CPU"): one live run (asf
# sim-robot on Fast DDS, asf run configs/ros2_nav2.ini on Cyclone DDS, loopback, no bag), with
# `perf record` sampling asf run's threads for SECONDS of wall time once it is exploring; then
# each sample of Cyclone DDS's receive thread (recvUC) and each sample of the run's thread inside
# the ros2 source's publishing (Ros2Source::observe) is put in one class by its call stack:
#   kernel: waking another thread   the kernel making a sleeping thread runnable (a futex wake,
#                                   a datagram delivered to a socket someone waits on)
#   kernel: scheduling              switching this thread out and in (waiting for datagrams)
#   kernel: sockets                 the rest of sendmsg / recvmsg
#   kernel: other
#   asf (innermost frame)           asf's callbacks and conversions
#   user space: Cyclone DDS, libc   the rest (Cyclone DDS, and libc: allocations, copies)
# Needs perf (linux-perf) and a perf_event_paranoid that lets root or the user record a process.
# Usage: scripts/ros2-bridge-profile.sh OUT_DIR [SEED (default 1)] [RATE (default 4)] [SECONDS (default 20)]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/ros2-bridge-profile.sh OUT_DIR [SEED] [RATE] [SECONDS]}
seed=${2:-1} rate=${3:-4} secs=${4:-20}
command -v perf >/dev/null || { echo "ros2-bridge-profile: perf is not installed (apt-get install linux-perf)" >&2; exit 1; }
mkdir -p "$out"
LIVE_SEED=$seed LIVE_BAG=false bash tests/ros2/live_loop.sh build/bin/asf . "$out/run" 73 "$rate" \
  >"$out/run.log" 2>&1 &
loop=$!
pid=""
for _ in $(seq 1 100); do  # up to 50 s for asf run to start
  pid=$(pgrep -f "^build/bin/asf run .*--out $out/run/asf" | head -1 || true)
  [[ -n "$pid" ]] && break
  sleep 0.5
done
[[ -n "$pid" ]] || { echo "ros2-bridge-profile: asf run did not start (see $out/run.log)" >&2; kill "$loop" 2>/dev/null; exit 1; }
sleep 10  # past the start-up
perf record -F 4000 --call-graph dwarf,16384 -p "$pid" -o "$out/perf.data" -- sleep "$secs" >"$out/perf.log" 2>&1
wait "$loop" || true
perf script -i "$out/perf.data" 2>/dev/null | python3 scripts/bridge_profile.py
