#!/usr/bin/env bash
# Instructions per path sample of `penumbra render`, counted by Valgrind's
# callgrind: the same count on every run, so a change of 1 % shows where
# timings on a shared machine wander by ±5 %. It counts work, not time
# (cache misses cost nothing here, and the CPU runs independent work side
# by side: 13 % fewer instructions made Cornell 3 % faster on 2026-12-05):
# confirm a gain with timings, and quote both.
#
#   scripts/instructions-per-sample.sh [BIN...]
#
# Renders SCENE (default the Cornell box of ../shared/reference) at 64×64,
# 16 spp, depth DEPTH (default 8), one thread, with each binary (default a
# fresh release build), counting only inside `penumbra_trace::render::render`
# (no scene loading, no image writing). Prints instructions per sample, the
# conditional branches per sample and how many of them callgrind's simple
# simulated predictor mispredicts (a real CPU's predictor does better; on
# a machine without performance counters, as these are, it is the only
# view of where branches go wrong, each costing some 15 cycles; unlike the
# instructions, that count moves by about 1 % between runs, as the
# simulated predictor's tables are indexed by addresses), and,
# with TOP=n, each binary's n largest functions (exclusive counts, inlined
# code counted in its caller). Installs valgrind when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${SCENE:-$(cd ../shared/reference/cornell && pwd)/cornell.gltf}
DEPTH=${DEPTH:-8}
TOP=${TOP:-0}
OUT=${OUT:-/tmp/instructions-per-sample}
mkdir -p "$OUT"
if ! command -v valgrind > /dev/null; then
  apt-get update > /dev/null && apt-get install -y valgrind > /dev/null
fi
if [ $# -eq 0 ]; then
  cargo build --release --locked -p penumbra-cli
  set -- "$PWD/target/release/penumbra"
fi
samples=$((64 * 64 * 16))
for bin in "$@"; do
  # Named by binary and scene, so that runs on other scenes keep their own.
  name=$(basename "$bin")-$(basename "${SCENE%.*}")
  log=$(valgrind --tool=callgrind --branch-sim=yes --toggle-collect='penumbra_trace::render::render' \
    --callgrind-out-file="$OUT/$name.callgrind" \
    "$bin" render "$SCENE" --spp 16 --max-depth "$DEPTH" --threads 1 --resolution 64x64 \
    -o "$OUT/$name.exr" 2>&1)
  # Collected: instructions, conditional branches and their mispredictions
  # (callgrind's simulated predictor), indirect branches and theirs.
  read -r collected branches mispredicted _ < <(grep -o 'Collected : [0-9 ]*' <<< "$log" | cut -d: -f2)
  awk -v bin="$bin" -v i="$collected" -v b="$branches" -v m="$mispredicted" -v s="$samples" 'BEGIN {
    printf "%s: %d instructions per sample (%d in %d samples), %d conditional branches, %.1f mispredicted (simulated)\n",
      bin, i / s, i, s, b / s, m / s }'
  if [ "$TOP" -gt 0 ]; then
    # callgrind splits a function's count by source file (inlined code);
    # sum them per function.
    callgrind_annotate --auto=no --inclusive=no "$OUT/$name.callgrind" 2> /dev/null |
      awk -v s="$samples" -v top="$TOP" '
        /^ *[0-9,]+ \(/ && !/PROGRAM TOTALS|events annotated|\([0-9,]+x\)/ {
          n = $1; gsub(",", "", n)
          f = $0; sub(/^ *[0-9,]+ \( *[0-9.]+%\) +/, "", f); sub(/ \[[^]]*\]$/, "", f)
          i = index(f, ".rs:"); if (i > 0) f = substr(f, i + 4)
          sum[f] += n
        }
        END { for (f in sum) printf "%9.0f  %s\n", sum[f] / s, f }' |
      sort -rn | head -n "$TOP" || true
  fi
done
