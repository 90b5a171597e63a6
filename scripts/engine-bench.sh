#!/usr/bin/env bash
# The engine tables of issue 40 in one command, here (lavapipe, SwiftShader) or on a machine
# with a GPU (the `device` machine, which has no network and no Rust build of Bevy):
#   bash scripts/engine-bench.sh pack       # here: builds the release CLI and Bevy's `view`
#                                           # example, strips and packs them into
#                                           # target/engine-bench (about 30 MB)
#   bash scripts/engine-bench.sh [FRAMES]   # anywhere: the tables, with the packed binaries
#                                           # when there are some, else the built ones
# On the device: carry target/engine-bench (and, for the three.js table, js/dist,
# js/node_modules/three and web/node_modules, with a Chromium on the machine).
# Bevy's tables (docs/bevy.md): static and animated at levels 4-32, coarse size at one
# refined size, 100 animated creatures. three.js's (js/README.md): `npm run bench:three`.
set -euo pipefail
cd "$(dirname "$0")/.."
pack=target/engine-bench
view=crates/tessella-bevy/target/release/examples/view
if [ "${1:-}" = pack ]; then
  cargo build --release --quiet -p tessella-cli
  (cd crates/tessella-bevy && cargo build --release --quiet --example view)
  mkdir -p "$pack"
  strip -o "$pack/view" "$view"
  strip -o "$pack/tessella" target/release/tessella
  gzip -f "$pack/view" "$pack/tessella"
  ls -l "$pack"
  exit 0
fi
frames=${1:-30}
if [ -f "$pack/view.gz" ]; then
  gunzip -kf "$pack/view.gz" "$pack/tessella.gz"
  chmod +x "$pack/view" "$pack/tessella"
  mkdir -p "$(dirname "$view")"
  cp "$pack/view" "$view"
  export TESSELLA_BIN="$PWD/$pack/tessella"
else
  export TESSELLA_BIN="${TESSELLA_BIN:-$PWD/target/release/tessella}"
fi
[ -x "$view" ] && [ -x "$TESSELLA_BIN" ] || {
  echo "no binaries: run 'bash scripts/engine-bench.sh pack' first" >&2
  exit 1
}
echo "# Engine tables, $(date -u +%F), $(nproc) cores"
if command -v nvidia-smi >/dev/null; then nvidia-smi --query-gpu=name --format=csv,noheader; fi
echo
echo "## Bevy: static and animated, levels 4-32 (ms a frame, 512x512, shadows on)"
bash crates/tessella-bevy/scripts/engine-table.sh release "$frames" 2>/dev/null
echo
echo "## Bevy: coarse size at 327,680 refined triangles"
bash crates/tessella-bevy/scripts/coarse-size.sh release "$frames" 2>/dev/null
echo
echo "## Bevy: 100 animated creatures"
bash crates/tessella-bevy/scripts/crowd.sh "" wave 100 release "$frames" 2>/dev/null
echo
echo "## three.js (WebGL2 in headless Chromium)"
if [ -d js/node_modules/three ] && [ -d web/node_modules/playwright-core ] && [ -f js/dist/simd/tessella.js ] \
  && command -v "${CHROMIUM:-chromium}" >/dev/null; then
  (cd web && node scripts/bench-three.js --frames 9)
else
  echo "skipped: needs js/dist, js/node_modules/three, web/node_modules and Chromium"
fi
