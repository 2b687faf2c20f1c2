#!/usr/bin/env bash
# Builds penumbra (release) and renders; with no arguments, the built-in
# Cornell box to penumbra.png. Arguments are passed to `penumbra render`.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release --locked -p penumbra-cli --bin penumbra -- render "$@"
