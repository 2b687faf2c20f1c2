#!/usr/bin/env bash
# Path-tracing throughput of several builds on a noisy machine: runs
# `penumbra bench SCENE --threads THREADS --spp SPP` RUNS times for each
# binary, alternating the binaries (A B A B …, so that a slow spell of the
# host falls on both), and prints each one's minimum, median (the lower
# middle run for an even count) and maximum Msamples/s. Compare medians;
# a difference inside the ranges' overlap is noise. On a shared host one
# binary took 42.8 s and 52.6 s for the same render minutes apart
# (README, stop 39).
#
#   scripts/ab-bench.sh SCENE RUNS BINARY...
#
# SPP (default 8) and THREADS (default 1) override the bench's settings.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 SCENE RUNS BINARY..." >&2
  exit 2
fi
scene=$1 runs=$2
shift 2
declare -A rates
for _ in $(seq "$runs"); do
  for bin in "$@"; do
    rate=$("$bin" bench "$scene" --threads "${THREADS:-1}" --spp "${SPP:-8}" | awk '/^path / {print $4}')
    rates[$bin]="${rates[$bin]:-} $rate"
  done
done
for bin in "$@"; do
  printf '%s: ' "$bin"
  tr ' ' '\n' <<<"${rates[$bin]}" | grep . | sort -n |
    awk '{v[NR] = $1} END {printf "min %s median %s max %s Msamples/s (%d runs)\n", v[1], v[int((NR + 1) / 2)], v[NR], NR}'
done
