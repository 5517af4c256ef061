#!/usr/bin/env bash
# How long the README's main command takes on a fresh Debian machine (issue 22's first-run
# goal): a Debian bookworm base system made by debootstrap (no compiler, no CMake, no git),
# a clone of this repository in it, then `scripts/run-default.sh` timed in the chroot: the
# packages it installs with apt-get, the build of the host and plugins (no compiler cache:
# the chroot's ccache starts empty), the default run.
#   sudo scripts/first-run-time.sh [CHROOT_DIR]        (default /var/tmp/asf-first-run)
# Needs root, debootstrap (installed here with apt-get if missing) and the Debian mirror of
# /etc/apt (the same one every install uses). Prints the apt, build+run and total seconds and
# the run's last line; CHROOT_DIR/root/asf keeps the build and CHROOT_DIR/tmp the logs. The
# download's share depends on the mirror's speed: the apt line says how many MB it fetched.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-/var/tmp/asf-first-run}
(($(id -u) == 0)) || { echo "first-run-time: needs root (debootstrap, chroot)" >&2; exit 2; }
[[ ! -e $dir ]] || { echo "first-run-time: $dir exists; give a new folder" >&2; exit 2; }
command -v debootstrap >/dev/null ||
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
mirror=$(grep -hoE 'https?://deb\.debian\.org/debian/?' /etc/apt/sources.list.d/*.sources \
  /etc/apt/sources.list 2>/dev/null | head -1 || true)
echo "first-run-time: debootstrap bookworm $dir ${mirror:-http://deb.debian.org/debian}" >&2
debootstrap bookworm "$dir" "${mirror:-http://deb.debian.org/debian}" > "$dir.debootstrap.log" 2>&1
cp /etc/resolv.conf "$dir/etc/"
for m in proc sys dev; do mount --rbind "/$m" "$dir/$m"; done
trap 'for m in dev sys proc; do umount -R "$dir/$m" 2>/dev/null || true; done' EXIT
git clone -q . "$dir/root/asf"
chroot "$dir" /bin/bash -c '
  cd /root/asf && export HOME=/root
  ms() { echo $(($(date +%s%N) / 1000000)); }
  secs() { printf "%d.%03d" $(($1 / 1000)) $(($1 % 1000)); }
  t0=$(ms)
  bash scripts/install-deps.sh > /tmp/apt.log 2>&1
  t1=$(ms)
  bash scripts/run-default.sh > /tmp/run.log 2>&1
  t2=$(ms)
  fetched=$(grep -E "^Fetched" /tmp/apt.log || echo "Fetched: ?")
  echo "apt: $(secs $((t1 - t0))) s ($fetched)"
  echo "build + run: $(secs $((t2 - t1))) s"
  echo "total: $(secs $((t2 - t0))) s"
  grep "asf run: policy" /tmp/run.log || { tail -20 /tmp/run.log; exit 1; }
'
