#!/usr/bin/env bash
# The main job on a fresh machine: build tessella, refine the bundled samples with every scheme
# on the CPU (table of counts, time and distance to the coarse input), and write the refined
# meshes and side-by-side pictures (rendered by wgpu: the GPU, or Mesa's software Vulkan driver
# when there is none) into out/, then a few frames of the animated sample's `wave` clip,
# posed and refined every frame (out/creature-wave/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-vulkan.sh
cargo build --release --quiet -p tessella-cli
mkdir -p out
./target/release/tessella demo --level 8 --output out
./target/release/tessella animate samples/animated-creature.glb --clip wave --level 8 \
    -o out/creature-wave --fps 8 --frames 8
echo "refined meshes and pictures written to out/, the animated sample's frames to out/creature-wave/"
