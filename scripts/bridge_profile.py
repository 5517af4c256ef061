"""Classifies `perf script` samples (with call stacks) of an asf run on the ros2 source: Cyclone
DDS's receive thread (recvUC) and the run's thread inside Ros2Source::observe (publishing).
Reads perf script's text on stdin; prints one table per thread. See
scripts/ros2-bridge-profile.sh for the classes."""
import collections
import sys

CLASSES = ["kernel: waking another thread", "kernel: scheduling", "kernel: sockets", "kernel: other",
           "asf (innermost frame)", "user space: Cyclone DDS, libc"]
WAKE = ("try_to_wake_up", "sock_def_readable", "futex_wake", "__wake_up")
SCHED = ("schedule", "finish_task_switch")
SOCK = ("sendmsg", "recvmsg", "udp_", "ip_", "skb")


def classify(frames):
    """frames: innermost first, each 'address symbol (object)'."""
    kernel = "kernel.kallsyms" in frames[0]
    if kernel:
        kstack = [f for f in frames if "kernel.kallsyms" in f]
        if any(w in f for f in kstack for w in WAKE):
            return CLASSES[0]
        if any(s in f for f in kstack for s in SCHED):
            return CLASSES[1]
        if any(s in f for f in kstack for s in SOCK):
            return CLASSES[2]
        return CLASSES[3]
    return CLASSES[4] if "asf::" in frames[0] or "source_ros2" in frames[0] else CLASSES[5]


def main():
    counts = {"recvUC": collections.Counter(), "run thread, publishing": collections.Counter()}
    for block in sys.stdin.read().split("\n\n"):
        lines = [l.strip() for l in block.strip().split("\n") if l.strip()]
        if len(lines) < 2:
            continue
        comm, frames = lines[0].split()[0], lines[1:]
        if comm == "recvUC":
            counts["recvUC"][classify(frames)] += 1
        elif comm == "asf" and any("Ros2Source::observe" in f for f in frames):
            counts["run thread, publishing"][classify(frames)] += 1
    for thread, c in counts.items():
        n = sum(c.values())
        print(f"{thread}: {n} samples")
        for k in CLASSES:
            if n:
                print(f"  {k:32s} {c[k]:6d}  {100 * c[k] / n:5.1f} %")


if __name__ == "__main__":
    main()
