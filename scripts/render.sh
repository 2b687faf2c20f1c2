#!/usr/bin/env bash
# Builds penumbra (release) and renders; with no arguments, the built-in
# Cornell box to penumbra.png. Arguments are passed to `penumbra render`.
# PGO=1 renders with the profile-guided build instead (scripts/build-pgo.sh:
# faster path tracing, the same image; two builds the first time).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${PGO:-0}" = 1 ]; then
  bin=$(scripts/build-pgo.sh)
  exec "$bin" render "$@"
fi
cargo run --release --locked -p penumbra-cli --bin penumbra -- render "$@"
