#!/usr/bin/env bash
# Runs every test of the project: formatting, lints, the Rust workspace's tests (GPU tests on
# Mesa's lavapipe when there is no GPU) and the Python package's tests in a fresh venv.
# Installs what it needs: Debian's Vulkan loader and lavapipe (when run as root), Python
# packages into a fresh virtual environment.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! ldconfig -p 2>/dev/null | grep -q libvulkan.so.1 || ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    echo "== installing Mesa's lavapipe (software Vulkan) for the GPU tests"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
  else
    echo "== warning: no Vulkan driver found and not root; GPU tests need mesa-vulkan-drivers" >&2
  fi
fi

echo "== cargo fmt"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets --quiet -- -D warnings
echo "== cargo test"
cargo test --workspace
if [ -f python/ci.sh ]; then
  echo "== python"
  bash python/ci.sh
fi
