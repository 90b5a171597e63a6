#!/usr/bin/env bash
# Frame time of a tessellated entity against the same surface refined offline by
# `tessella refine` and loaded as a plain Bevy mesh, at levels 8, 16 and 32 (the issue's
# comparison). Each frame waits for the GPU (`view --frames`). Prints one JSON line per run.
# Usage: scripts/frame-times.sh [MESH] [SCHEME] [PROFILE: debug|release]
set -euo pipefail
cd "$(dirname "$0")/.."
mesh=${1:-../../samples/creature.obj}
scheme=${2:-pn}
profile=${3:-release}
view=target/$profile/examples/view
cli=${TESSELLA_BIN:-../../target/release/tessella}
tmp=$(mktemp -d)
for level in 8 16 32; do
  "$cli" refine "$mesh" --scheme "$scheme" --level "$level" -o "$tmp/refined.obj" >/dev/null 2>&1
  "$view" "$mesh" --scheme "$scheme" --level "$level" --size 512x512 --frames 30 \
    --screenshot "$tmp/t.png" 2>/dev/null
  "$view" "$tmp/refined.obj" --plain --frame "$mesh" --level "$level" --size 512x512 --frames 30 \
    --screenshot "$tmp/p.png" 2>/dev/null
done
rm -rf "$tmp"
