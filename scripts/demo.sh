#!/usr/bin/env bash
# The main job on a fresh machine: build tessella, refine the bundled samples with every scheme
# (table of counts, time and distance to the coarse input), and write the refined meshes and
# pictures into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet -p tessella-cli
mkdir -p out
./target/release/tessella demo --level 8 --output out
echo "refined meshes written to out/"
