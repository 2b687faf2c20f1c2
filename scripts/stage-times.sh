#!/usr/bin/env bash
# Where a path sample's time goes, stage by stage: builds penumbra with the
# `stage-timing` feature (in target/stage-timing, so the normal build is
# kept) and runs `penumbra bench SCENE --threads 1 --spp SPP`, which prints
# after its path measure each stage's time-stamp-counter ticks per sample,
# calls per sample, ticks per call and share of the sample (stages nest:
# the traversal is inside the closest hit, the shadow ray inside next-event
# estimation; crates/penumbra-trace/src/stages.rs), then the nodes, leaves
# and triangles the single-ray walk visits per closest-hit query (`bench
# --rays FILE` with this build prints them per ray). These machines have no
# performance counters; this prices latency and mispredictions, which
# instruction counts (scripts/instructions-per-sample.sh) do not. The
# instrumented build runs about 5 % slower than the normal one.
#
#   scripts/stage-times.sh [SCENE]   (default: the Cornell box of ../shared/reference)
#
# SPP (default 8) and THREADS (default 1) override the bench's settings.
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-../shared/reference/cornell/cornell.gltf}
cargo build --release --locked -p penumbra-cli --features stage-timing --target-dir target/stage-timing
target/stage-timing/release/penumbra bench "$SCENE" --threads "${THREADS:-1}" --spp "${SPP:-8}" |
  grep -E '^(path|stage) '
