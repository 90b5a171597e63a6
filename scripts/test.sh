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
echo "== CPU-only CLI: builds without the gpu feature, and no wgpu in its tree"
cargo check -p tessella-cli --no-default-features
if cargo tree -p tessella-cli --no-default-features -e normal | grep -q wgpu; then
  echo "wgpu is in the dependency tree of the CPU-only CLI" >&2
  exit 1
fi
echo "== example: an application's own device, buffers and pipeline (tessella-gpu/examples/deform.rs)"
frames=$(mktemp -d)
cargo run --quiet -p tessella-gpu --example deform -- "$frames" --frames 3 --size 64
for k in 000 001 002; do
  test -s "$frames/frame_$k.png" || { echo "deform: frame_$k.png missing" >&2; exit 1; }
done
if cmp -s "$frames/frame_000.png" "$frames/frame_001.png"; then
  echo "deform: frames 0 and 1 are identical: the mesh did not move" >&2
  exit 1
fi
rm -rf "$frames"
if [ -f python/ci.sh ]; then
  echo "== python"
  bash python/ci.sh
fi
