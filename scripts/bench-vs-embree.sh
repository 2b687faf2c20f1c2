#!/usr/bin/env bash
# Closest-hit throughput of penumbra and Embree on exactly the same rays, in
# one run: penumbra's bench sphere (~1M triangles) is exported as an OBJ,
# ../shared/anchors/bench_embree.py makes the coherent (camera) and random
# incoherent ray sets from it and times Embree 3 through Mitsuba, then
# `penumbra bench --rays` traces the same files, one ray at a time
# (`file`), interleaved (`file-interleaved`) and in packets of 16
# consecutive rays (`file-packets`). Needs the anchors' venv
# (../shared/anchors/setup.sh).
#
#   scripts/bench-vs-embree.sh [PENUMBRA_BINARY...]   (default: a fresh release build)
# Results: $OUT (default /tmp/bench-vs-embree): results.jsonl (Embree) and penumbra.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/bench-vs-embree}
source scripts/anchors-env.sh
"$1" bench --spp 0 --write-mesh "$OUT/mesh.obj" >/dev/null
cat > "$OUT/scene.json" <<JSON
{"name": "benchsphere", "units": "m",
 "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 42.0, "resolution": [1024, 1024]},
 "lights": [{"type": "directional", "direction": [0.0, -0.6, -0.8], "irradiance": [3, 3, 3]}],
 "background": [0, 0, 0],
 "objects": [{"name": "sphere", "mesh": "$OUT/mesh.obj", "albedo": [0.8, 0.8, 0.8], "emission": [0, 0, 0], "smooth": false}]}
JSON
"$PY" "$ANCHORS/bench_embree.py" --scene "$OUT/scene.json" --export-rays "$OUT/rays"
"$PY" "$ANCHORS/bench_embree.py" --backend mitsuba --runs 5 --scene "$OUT/scene.json"
: > "$OUT/penumbra.txt"
for bin in "$@"; do
  for set in coherent incoherent; do
    for run in 1 2 3; do
      line=$("$bin" bench --mesh "$OUT/mesh.obj" --rays "$OUT/rays/$set.rays" --spp 0 2>&1 | grep -E '^(build|file)' | tr -s ' ' | tr '\n' ' ')
      echo "$bin $set run $run: $line" | tee -a "$OUT/penumbra.txt"
    done
  done
done
grep -h '"trace_\|"bvh_build' "$OUT/results.jsonl" | cut -c1-200
