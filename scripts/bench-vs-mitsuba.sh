#!/usr/bin/env bash
# Path-tracing efficiency of penumbra and Mitsuba 3 (llvm_ad_rgb) in one run,
# on the three scenes of issue 13: the Cornell box of ../shared/reference
# (512², depth 8), the Cornell box with a glass sphere
# (crates/penumbra-trace/tests/data/cornell-glass, 256², depth 16) and
# glass, gold, mirror and rough copper spheres over a floor
# (crates/penumbra-trace/tests/data/metal-spheres, 384×256, depth 16), all
# at 256 spp on all cores. SCENES="glass cornell metals" (the default)
# picks some of them. Each render is compared with the scene's reference
# EXR (../shared/anchors/compare.py) and the efficiency 1/(relMSE · seconds)
# is printed as a ratio to Mitsuba's. Needs the anchors' venv
# (../shared/anchors/setup.sh).
#
#   scripts/bench-vs-mitsuba.sh [PENUMBRA_BINARY...]   (default: the PGO build; PGO=0: the release build)
#
# Several binaries (say the builds before and after a change) are run one
# after another in the same run, so that their ratios share Mitsuba's time.
#
# MITSUBA_SCALAR=1 also renders with Mitsuba's scalar_rgb variant (one
# path at a time, Embree's single-ray queries: penumbra's own paradigm;
# llvm_ad_rgb runs many paths in SIMD lanes) and prints the ratios to it
# too: what separates penumbra from llvm_ad_rgb is then split into the
# per-path work and the SIMD across paths.
# Results: $OUT (default /tmp/bench-vs-mitsuba): the EXRs, results.jsonl and
# summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/bench-vs-mitsuba}
source scripts/anchors-env.sh
REFERENCE=$(cd ../shared/reference && pwd)
GLASS=$PWD/crates/penumbra-trace/tests/data/cornell-glass
METALS=$PWD/crates/penumbra-trace/tests/data/metal-spheres
SCENES=${SCENES:-glass cornell metals}
CORNELL=$REFERENCE/cornell
: > "$OUT/results.jsonl"
: > "$OUT/summary.txt"

# scene name, Mitsuba scene.json, penumbra scene, reference EXR, max depth
scene() {
  local name=$1 json=$2 scene=$3 ref=$4 depth=$5
  shift 5
  "$PY" "$ANCHORS/render_mitsuba.py" "$json" --spp 256 --max-depth "$depth" --runs 2 --warmup 1 \
    --out "$OUT/mitsuba-$name.exr" | tail -1 | tee -a "$OUT/results.jsonl"
  local tests=("$OUT/mitsuba-$name.exr")
  if [ "${MITSUBA_SCALAR:-0}" = 1 ]; then
    # No JIT to warm up; one run, as it takes about three llvm runs' time.
    "$PY" "$ANCHORS/render_mitsuba.py" "$json" --variant scalar_rgb --spp 256 --max-depth "$depth" \
      --runs 1 --warmup 0 --out "$OUT/mitsuba-scalar-$name.exr" | tail -1 | tee -a "$OUT/results.jsonl"
    tests+=("$OUT/mitsuba-scalar-$name.exr")
  fi
  local k=0
  for bin in "$@"; do
    k=$((k + 1))
    local exr="$OUT/penumbra$k-$name.exr"
    local line
    line=$("$bin" render "$scene" --spp 256 --max-depth "$depth" --seed 1 -o "$exr" 2>&1 | grep -E ' in [0-9.]+ s')
    local secs
    secs=$(sed -E 's/.* in ([0-9.]+) s.*/\1/' <<<"$line")
    echo "{\"tool\": \"penumbra\", \"binary\": \"$bin\", \"scene\": \"$name\", \"seconds\": $secs, \"exr\": \"$exr\"}" |
      tee -a "$OUT/results.jsonl"
    tests+=("$exr")
  done
  "$PY" "$ANCHORS/compare.py" --ref "$ref" "${tests[@]}" | grep '^{' | tee -a "$OUT/results.jsonl"
}

for name in $SCENES; do
  case $name in
    glass) scene glass "$GLASS/scene.json" "$GLASS/scene.toml" "$GLASS/reference-path-depth16-4096spp.exr" 16 "$@" ;;
    cornell) scene cornell "$CORNELL/scene.json" "$CORNELL/cornell.gltf" "$CORNELL/reference-path-depth8-4096spp.exr" 8 "$@" ;;
    metals) scene metals "$METALS/scene.json" "$METALS/scene.toml" "$METALS/reference-path-depth16-4096spp.exr" 16 "$@" ;;
    *) echo "bench-vs-mitsuba: unknown scene $name (glass, cornell, metals)" >&2; exit 2 ;;
  esac
done

# Efficiency 1/(relMSE · s) of each render, as a ratio to Mitsuba's.
python3 - "$OUT/results.jsonl" <<'PY' | tee "$OUT/summary.txt"
import json, os, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{")]
seconds, relmse = {}, {}
for r in rows:
    if r.get("tool") == "compare":
        relmse[os.path.basename(r["test"])] = r["relmse"]
    elif "exr" in r and "seconds" in r:
        seconds[os.path.basename(r["exr"])] = (r.get("binary", r["tool"]), r["seconds"])
efficiency = lambda exr: 1.0 / (relmse[exr] * seconds[exr][1])
for scene in ("glass", "cornell", "metals"):
    base = f"mitsuba-{scene}.exr"
    if base not in seconds:
        continue
    scalar = f"mitsuba-scalar-{scene}.exr"
    print(f"{scene}: Mitsuba {seconds[base][1]:.2f} s, relMSE {relmse[base]:.5f}")
    if scalar in seconds:
        print(f"  Mitsuba scalar_rgb: {seconds[scalar][1]:.2f} s, relMSE {relmse[scalar]:.5f}, "
              f"efficiency {efficiency(scalar) / efficiency(base):.2f}x Mitsuba's")
    for exr, (who, s) in sorted(seconds.items()):
        if exr.startswith("penumbra") and exr.endswith(f"-{scene}.exr"):
            line = f"  {who}: {s:.2f} s, relMSE {relmse[exr]:.5f}, efficiency {efficiency(exr) / efficiency(base):.2f}x Mitsuba's"
            if scalar in seconds:
                line += f", {efficiency(exr) / efficiency(scalar):.2f}x scalar_rgb's"
            print(line)
PY
