#!/usr/bin/env bash
# Cold build time of commits of this repository: for each commit, a fresh clone, a Release
# configure and a build without ccache of the main job's target (asf_runtime: the host and its
# plugins), then of the rest of the tree (tests, benchmarks, fuzzers). Prints one line per commit:
#   <commit> asf_runtime <s> whole_tree <s> cores <n> load_before <1-min load average>
# Usage: scripts/build-time.sh [-j N] COMMIT...   (default -j: nproc)
# Builds run one after the other, never two at once; say what else ran on the machine.
# (scripts/first-run-time.sh times the README's first run on a fresh system instead: apt,
# build and run of one commit.)
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
jobs=$(nproc)
if [[ ${1:-} == -j ]]; then jobs=$2; shift 2; fi
if [[ $# -eq 0 ]]; then
  echo "usage: scripts/build-time.sh [-j N] COMMIT..." >&2
  exit 2
fi
work=$(mktemp -d /tmp/asf-build-time.XXXXXX)
trap 'rm -rf "$work"' EXIT
for commit in "$@"; do
  sha=$(git -C "$repo" rev-parse --short "$commit")
  src="$work/$sha"
  git clone -q "$repo" "$src"
  git -C "$src" checkout -q "$sha"
  load=$(cut -d' ' -f1 /proc/loadavg)
  cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  t0=$(date +%s.%N)
  CCACHE_DISABLE=1 cmake --build "$src/build" -j "$jobs" --target asf_runtime >"$work/$sha.log"
  t1=$(date +%s.%N)
  CCACHE_DISABLE=1 cmake --build "$src/build" -j "$jobs" >>"$work/$sha.log"
  t2=$(date +%s.%N)
  awk -v s="$sha" -v a="$t0" -v b="$t1" -v c="$t2" -v j="$jobs" -v l="$load" 'BEGIN {
    printf "%s asf_runtime %.0f whole_tree %.0f cores %s load_before %s\n", s, b - a, c - a, j, l }'
  rm -rf "$src"
done
