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

cargo test --workspace --locked "$@"
