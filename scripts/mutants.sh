#!/usr/bin/env bash
# Mutation testing of penumbra's physics code with cargo-mutants: small
# deliberate bugs are put into the code one at a time and the tests must
# fail for each (docs/testing.md has the figures and every justified
# survivor). Installs cargo-mutants when it is missing.
#
#   scripts/mutants.sh            the physics code, crate by crate (hours on 2 cores)
#   scripts/mutants.sh --ci       the subset CI runs (a few minutes); fails on a missed mutant
#   scripts/mutants.sh ARGS...    cargo mutants ARGS (e.g. -p penumbra-shading -f crates/penumbra-shading/src/bsdf/optics.rs)
#
# Results: target/mutants/<name>/mutants.out/{caught,missed,timeout,unviable}.txt
set -euo pipefail
cd "$(dirname "$0")/.."

VERSION=27.1.0
if ! cargo mutants --version 2>/dev/null | grep -q "$VERSION"; then
  cargo install cargo-mutants --locked --version "$VERSION"
fi

# Each mutant rebuilds the crate: incremental compilation (off in
# [profile.test] to save disk) makes those rebuilds much faster.
export CARGO_INCREMENTAL=1

run() { # NAME, then cargo-mutants arguments
  local name=$1; shift
  mkdir -p "target/mutants/$name"
  cargo mutants --no-shuffle -o "target/mutants/$name" "$@"
}

files() { # PACKAGE DIR-OR-FILE... -> -p PACKAGE -f ... for every .rs below
  local pkg=$1; shift
  local args=(-p "$pkg")
  for f in "$@"; do
    while IFS= read -r rs; do args+=(-f "$rs"); done < <(find "$f" -name '*.rs' | sort)
  done
  printf '%s\n' "${args[@]}"
}

case "${1:-}" in
  --ci)
    # The warps, against the crate's unit tests (the chi-square and moment
    # tests beside the code) and the closed-form points of warp_values.rs.
    # `--cargo-arg`, not `--cargo-test-arg`: the build of each mutant then
    # compiles only these two test targets, not all of the crate's
    # (building was 80 % of this run's time).
    run ci-warp -p penumbra-shading -f crates/penumbra-shading/src/sampling/warp.rs \
      --cargo-arg=--lib --cargo-arg=--test=warp_values
    ;;
  "")
    s=crates/penumbra-shading/src t=crates/penumbra-trace/src i=crates/penumbra-image/src
    mapfile -t a < <(files penumbra-shading $s/bsdf $s/bsdf.rs $s/light $s/light.rs $s/sampling $s/sampling.rs $s/radiometry.rs $s/color.rs)
    run shading "${a[@]}" || true
    mapfile -t a < <(files penumbra-trace $t/integrator $t/lights.rs $t/accel $t/geometry.rs $t/ray.rs $t/texture_lod.rs)
    run trace "${a[@]}" || true
    mapfile -t a < <(files penumbra-image $i/metrics.rs $i/film.rs $i/tonemap.rs $i/flip.rs $i/flip_ldr.rs)
    run image "${a[@]}" || true
    for n in shading trace image; do
      echo "$n: $(wc -l < target/mutants/$n/mutants.out/caught.txt) caught, $(wc -l < target/mutants/$n/mutants.out/missed.txt) missed, $(wc -l < target/mutants/$n/mutants.out/timeout.txt) timed out, $(wc -l < target/mutants/$n/mutants.out/unviable.txt) unviable"
    done
    ;;
  *)
    run custom "$@"
    ;;
esac
