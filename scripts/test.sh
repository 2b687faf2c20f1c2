#!/usr/bin/env bash
# Runs penumbra's whole test suite on a fresh Debian/Ubuntu machine with Rust
# installed: installs what the tests need, then runs them with optimisation
# (image tests are heavy; [profile.test] is opt-level 3).
set -euo pipefail
cd "$(dirname "$0")/.."

# The GPU tests (real-time pipeline, a later issue) run on Mesa's software
# Vulkan driver; install it and the Vulkan loader when apt is available.
if command -v apt-get >/dev/null 2>&1 && ! dpkg -s mesa-vulkan-drivers >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq || true
  $SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null || echo "warning: could not install mesa-vulkan-drivers" >&2
fi

# The study report test (crates/penumbra-study/tests/report_browser.rs) opens
# index.html in headless Chromium; install it when apt is available. Without
# it that test fails and says so (PENUMBRA_SKIP_BROWSER=1 skips it).
if command -v apt-get >/dev/null 2>&1 && ! command -v chromium >/dev/null 2>&1 \
  && ! command -v chromium-browser >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq || true
  $SUDO apt-get install -y -qq chromium >/dev/null || echo "warning: could not install chromium; the study report test will fail (set PENUMBRA_SKIP_BROWSER=1 to skip it)" >&2
fi

# The glTF export test checks its files with the Khronos glTF validator (npm
# package gltf-validator, pinned with its lock file in tools/gltf-validator/);
# install it with npm when missing. Without npm the test fails and says so
# (PENUMBRA_SKIP_GLTF_VALIDATOR=1 skips that check).
if [ ! -f tools/gltf-validator/node_modules/gltf-validator/package.json ]; then
  if command -v npm >/dev/null 2>&1; then
    npm ci --prefix tools/gltf-validator --no-audit --no-fund --loglevel=error >/dev/null \
      || echo "warning: could not install the glTF validator (npm ci in tools/gltf-validator); the glTF export test will fail" >&2
  else
    echo "warning: npm not found: the Khronos glTF validator is not installed and the glTF export test will fail (install Node.js and npm, or set PENUMBRA_SKIP_GLTF_VALIDATOR=1)" >&2
  fi
fi

# The farm tests check Kubernetes manifests with the official Python client
# (Debian's python3-kubernetes, run by /usr/bin/python3), and submit job
# arrays to a real single-node Slurm cluster that scripts/slurm-local.sh
# installs (slurm-wlm, munge) and starts here; it is stopped again at the end.
# Without them those tests fail and say so (PENUMBRA_SKIP_SLURM=1 skips Slurm).
if command -v apt-get >/dev/null 2>&1 && ! /usr/bin/python3 -c "import kubernetes" >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq || true
  $SUDO apt-get install -y -qq python3-kubernetes >/dev/null || echo "warning: could not install python3-kubernetes; the Kubernetes manifest test will fail" >&2
fi
if [ "${PENUMBRA_SKIP_SLURM:-0}" != 1 ] && ! bash scripts/slurm-local.sh status >/dev/null 2>&1; then
  if bash scripts/slurm-local.sh start; then
    trap 'bash scripts/slurm-local.sh stop || true' EXIT
  else
    echo "warning: could not start a local Slurm cluster; the Slurm farm test will fail (PENUMBRA_SKIP_SLURM=1 skips it)" >&2
  fi
fi

cargo test --workspace --locked "$@"
# The stage timer (off in normal builds) with its feature on. penumbra-cli
# is selected beside penumbra-trace (its binary is not built: `--lib`) so
# that cargo resolves the dependencies' features for the whole workspace, as
# in the line above, and reuses their builds: with penumbra-trace alone about
# 20 of them were built again with fewer features (3 min 44 s of a CI run,
# against 22 s for penumbra-trace's own test build).
cargo test -p penumbra-trace -p penumbra-cli --locked --features penumbra-trace/stage-timing \
  --lib stages "$@"
