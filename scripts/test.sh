#!/usr/bin/env bash
# Runs every test of the project: formatting, lints, the Rust workspace's tests (GPU tests on
# Mesa's lavapipe when there is no GPU) and the Python package's tests in a fresh venv.
# Installs what it needs: Debian's Vulkan loader and lavapipe (when run as root), Python
# packages into a fresh virtual environment.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup-vulkan.sh

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
