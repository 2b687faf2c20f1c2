#!/usr/bin/env bash
# Builds penumbra with profile-guided optimisation (PGO): an instrumented
# build renders a training set of scenes with every integrator, material
# family and light kind and traces the ray benchmark's sets; LLVM then
# compiles the release build again with the branch and call counts it
# measured (hot code laid out together, inlining and branch layout from
# real counts). The images are the same to the bit: only code layout and
# inlining change, never the floating-point operations.
#
#   scripts/build-pgo.sh          # prints the binary's path: target/pgo/release/penumbra
#
# The profile is made from the current sources, so it never goes stale:
# when the sources (crates/, Cargo.toml, Cargo.lock and this script) are
# those of the last PGO build, the script only prints that build's path.
# Otherwise: two release builds in their own target folders, target/pgo-gen
# and target/pgo (about ten minutes on 2 cores the first time), and the
# training renders between them (about a minute, one thread each). The
# counts differ a little from run to run (timers, progress reports), so a
# new profile means new RUSTFLAGS and the second build compiles every crate
# again (about three minutes), none of them with an older profile. It needs
# LLVM's llvm-profdata from rustup's llvm-tools component, which it
# installs when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
SHARED=$ROOT/../shared
PGO_BIN=$ROOT/target/pgo/release/penumbra

# The sources' fingerprint: tracked and untracked files, by content.
STAMP=$ROOT/target/pgo/sources.sha256
rustc_version=$(rustc -vV)
fingerprint=$({ git ls-files -co --exclude-standard crates Cargo.toml Cargo.lock scripts/build-pgo.sh |
  LC_ALL=C sort | xargs sha256sum; echo "$rustc_version"; } | sha256sum | cut -d' ' -f1)
if [ -x "$PGO_BIN" ] && [ "$(cat "$STAMP" 2>/dev/null)" = "$fingerprint" ]; then
  echo "$PGO_BIN"
  exit 0
fi

sysroot=$(rustc --print sysroot)
host=$(sed -n 's/^host: //p' <<<"$rustc_version")
PROFDATA=$sysroot/lib/rustlib/$host/bin/llvm-profdata
if [ ! -x "$PROFDATA" ]; then
  if ! command -v rustup > /dev/null; then
    echo "build-pgo: needs LLVM's llvm-profdata from rustup's llvm-tools component, and rustup is missing" >&2
    exit 1
  fi
  rustup component add llvm-tools >&2
fi

RAW=$ROOT/target/pgo-raw
rm -rf "$RAW"
mkdir -p "$RAW"
echo "build-pgo: the instrumented build (target/pgo-gen)" >&2
RUSTFLAGS="-Cprofile-generate=$RAW" CARGO_TARGET_DIR=$ROOT/target/pgo-gen \
  cargo build --release --locked -p penumbra-cli >&2
# The build scripts ran instrumented too: only the training counts.
rm -f "$RAW"/*.profraw
BIN=$ROOT/target/pgo-gen/release/penumbra
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

train() {
  echo "build-pgo: penumbra $*" >&2
  if ! "$BIN" "$@" --threads 1 > "$OUT/log" 2>&1; then
    cat "$OUT/log" >&2
    echo "build-pgo: that training run failed" >&2
    exit 1
  fi
}
render() {
  local scene=$1
  shift
  train render "$scene" --resolution 96x96 --seed 1 -o "$OUT/train.exr" "$@"
}
render scenes/cornell-box.toml --spp 16
render scenes/cornell-box.toml --spp 4 --integrator direct
render scenes/cornell-box.toml --spp 4 --integrator ao
render scenes/cornell-box.toml --spp 4 --integrator local
render scenes/materials.toml --spp 16
render scenes/materials-environment.toml --spp 16
render scenes/whitted.toml --spp 4
render crates/penumbra-trace/tests/data/cornell-glass/scene.toml --spp 16 --max-depth 16
if [ -d "$SHARED/reference/cornell" ]; then
  render "$SHARED/reference/cornell/cornell.gltf" --spp 16 --max-depth 8
fi
if [ -d "$SHARED/gltf-samples/DamagedHelmet" ]; then
  helmet=$(find "$SHARED/gltf-samples/DamagedHelmet" -name '*.gl[tb]*' | head -1)
  render "$helmet" --spp 8
fi
# The bakes (CPU work the study and the raster engine use).
train bake ao -o "$OUT/ao" --samples 16 --max-size 64
train bake lightmap -o "$OUT/lightmap" --samples 8 --max-size 64
train bake radiosity -o "$OUT/radiosity" --patches 500
# The ray benchmark: build, coherent and random rays one at a time,
# interleaved and in packets, and the path measure on a larger tree.
train bench --triangles 200000 --ray-resolution 256 --spp 2

PROFILE_RAW=$OUT/merged.profdata
"$PROFDATA" merge -o "$PROFILE_RAW" "$RAW"
# Named by its contents: cargo does not watch the file, but it does watch
# RUSTFLAGS, so every crate is compiled with this profile.
sum=$(sha256sum "$PROFILE_RAW" | cut -c1-16)
PROFILE=$ROOT/target/pgo-profiles/penumbra-$sum.profdata
rm -rf "$(dirname "$PROFILE")"
mkdir -p "$(dirname "$PROFILE")"
cp "$PROFILE_RAW" "$PROFILE"
echo "build-pgo: the optimised build with $PROFILE (target/pgo)" >&2
RUSTFLAGS="-Cprofile-use=$PROFILE" CARGO_TARGET_DIR=$ROOT/target/pgo \
  cargo build --release --locked -p penumbra-cli >&2
echo "$fingerprint" > "$STAMP"
echo "$PGO_BIN"
