#!/usr/bin/env bash
# Bevy's table for issue 40: frame times at levels 4, 8, 16 and 32, the light's shadows on and
# a ground, 512x512, each frame waited for on the GPU (`view --frames`):
# - static: the creature (320 triangles) with `Tessellate` (PN), welded and in runs
#   (`TessellaDraw`), against the plain Bevy mesh of the same refined surface (`tessella
#   refine`, OBJ);
# - animated: the skinned creature (animated-creature.glb) playing its `wave` clip through
#   Bevy's AnimationPlayer, with `Tessellate` (tessella poses the coarse mesh, uploads the
#   nets) against the same file refined offline (`tessella refine`, skins and clips kept)
#   played by Bevy's own skinning.
# Prints the view example's JSON lines to stderr and a Markdown table of mean frame times.
# Usage: scripts/engine-table.sh [PROFILE: debug|release] [FRAMES] [LEVELS]
set -euo pipefail
cd "$(dirname "$0")/.."
profile=${1:-release}
frames=${2:-40}
levels=${3:-4 8 16 32}
view=target/$profile/examples/view
cli=${TESSELLA_BIN:-../../target/release/tessella}
samples=../../samples
[ -x "$view" ] || { echo "build it first: cargo build --$profile --example view" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ms() { # view's arguments; prints the mean frame time
  local line
  line=$("$view" "$@" --ground --size 512x512 --frames "$frames" --screenshot "$tmp/shot.png" 2>/dev/null | tail -1)
  echo "$line" >&2
  echo "$line" | sed 's/.*"mean_frame_ms":\([0-9.]*\).*/\1/'
}
echo "| level | static: refined mesh ms | welded ms | ratio | runs ms | ratio | animated: offline-refined skinned ms | Tessellate (welded) ms | ratio |"
echo "|---|---|---|---|---|---|---|---|---|"
for level in $levels; do
  "$cli" refine "$samples/creature.obj" --scheme pn --level "$level" -o "$tmp/static.obj" >/dev/null 2>&1
  "$cli" refine "$samples/animated-creature.glb" --scheme pn --level "$level" -o "$tmp/skinned.glb" >/dev/null 2>&1
  plain=$(ms "$tmp/static.obj" --plain --frame "$samples/creature.obj")
  tess=$(ms "$samples/creature.obj" --scheme pn --level "$level" --draw welded)
  runs=$(ms "$samples/creature.obj" --scheme pn --level "$level" --draw runs)
  offline=$(ms "$tmp/skinned.glb" --plain --clip wave --frame "$samples/creature.obj")
  animated=$(ms "$samples/animated-creature.glb" --scheme pn --level "$level" --clip wave --frame "$samples/creature.obj")
  awk -v l="$level" -v a="$plain" -v b="$tess" -v r="$runs" -v c="$offline" -v d="$animated" \
    'BEGIN { printf "| %s | %.2f | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2f | %.2fx |\n", l, a, b, b / a, r, r / a, c, d, d / c }'
done
