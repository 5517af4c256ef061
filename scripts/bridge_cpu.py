"""The ros2 source's "bridge CPU" and "scan-to-tf in asf" lines of a run.log
(plugins/source_ros2): the bridge's seconds on the run's thread and on Cyclone DDS's threads (by
name), and the whole run's; and the latency from a scan queued by asf's receive thread to the
map -> odom stamped with it published. Used by scripts/ros2-bridge-cpu.sh and
scripts/ros2-live-seeds.sh."""
import re

_LINE = re.compile(r"bridge CPU: ([\d.e-]+) s on the run's thread .*?, ([\d.e-]+) s on Cyclone DDS's "
                   r"threads \((.*?)\), of ([\d.e-]+) s for the whole run")


def bridge_cpu(run_log):
    """{'run', 'dds', 'threads': {name: s}, 'total', 'share'} from run_log, or None."""
    try:
        m = _LINE.search(open(run_log).read())
    except OSError:
        return None
    if not m:
        return None
    run, dds, total = float(m.group(1)), float(m.group(2)), float(m.group(4))
    threads = {k: float(v) for k, v in (t.rsplit(" ", 1) for t in m.group(3).split(", ") if t)}
    return {"run": run, "dds": dds, "threads": threads, "total": total,
            "share": (run + dds) / total if total > 0 else None}


_LATENCY = re.compile(r"scan-to-tf in asf .*?: median ([\d.e+-]+) ms, p95 ([\d.e+-]+) ms, max ([\d.e+-]+) ms over (\d+)")


def asf_latency(run_log):
    """{'median_ms', 'p95_ms', 'max_ms', 'count'} of asf's own scan-to-tf latency, or None."""
    try:
        m = _LATENCY.search(open(run_log).read())
    except OSError:
        return None
    if not m:
        return None
    return {"median_ms": float(m.group(1)), "p95_ms": float(m.group(2)), "max_ms": float(m.group(3)),
            "count": int(m.group(4))}
