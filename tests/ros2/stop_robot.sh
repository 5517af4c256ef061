# Sourced by the ROS 2 test scripts: stop_robot PID ends an asf sim-robot, bounded: SIGTERM
# (it writes its summary and what it received, then leaves), and SIGKILL after 10 s should
# leaving hang (its outputs are written before it starts to leave).
stop_robot() {
  local pid=$1 i
  [[ -n "$pid" ]] || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for i in $(seq 50); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.2
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "asf sim-robot $pid did not leave within 10 s of SIGTERM: killed" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}
