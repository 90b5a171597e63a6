#!/usr/bin/env bash
# One animated character, the default draw against the offline-refined asset only, in
# alternating pairs (the engine table's two columns that the acceptance compares, with more
# rounds than the table can afford): the skinned creature playing `wave` with `Tessellate`
# (PN, its own mesh posed on the GPU) and the same file refined by `tessella refine` played by
# Bevy's skinning; the light's shadows on, a ground, 512x512, each frame waited for.
# Prints each pair (wall and CPU ms a frame, and the ratio) and per level the medians' ratios.
# Usage: scripts/animated-pair.sh [ROUNDS] [FRAMES] [LEVELS] [PROFILE]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
frames=${2:-60}
levels=${3:-4 8 16 32}
profile=${4:-release}
# shellcheck source=common.sh
source "scripts/common.sh"
run() { # view's arguments; prints "wall cpu" ms a frame
  "$view" "$@" --clip wave --frame "$samples/creature.obj" --ground --size 512x512 \
    --frames "$frames" --screenshot "$tmp/shot.png" 2>/dev/null | tail -1 |
    sed 's/.*"mean_frame_ms":\([0-9.]*\).*"mean_frame_cpu_ms":\([0-9.]*\).*/\1 \2/'
}
echo "| level | offline ms (median) | mesh, GPU posing ms (median) | ratio | CPU ratio | pairs' ratios |"
echo "|---:|---:|---:|---:|---:|---|"
for level in $levels; do
  "$cli" refine "$samples/animated-creature.glb" --scheme pn --level "$level" -o "$tmp/skinned.glb" >/dev/null 2>&1
  : > "$tmp/pairs"
  for _ in $(seq "$rounds"); do
    offline=$(run "$tmp/skinned.glb" --plain)
    mesh=$(run "$samples/animated-creature.glb" --scheme pn --level "$level" --draw mesh --pose gpu)
    echo "level $level: offline $offline, mesh $mesh" >&2
    echo "$offline $mesh" >> "$tmp/pairs"
  done
  o=$(cut -d' ' -f1 "$tmp/pairs" | median)
  oc=$(cut -d' ' -f2 "$tmp/pairs" | median)
  m=$(cut -d' ' -f3 "$tmp/pairs" | median)
  mc=$(cut -d' ' -f4 "$tmp/pairs" | median)
  ratios=$(awk '{ printf "%s%.2f", (NR > 1 ? " " : ""), $3 / $1 }' "$tmp/pairs")
  awk -v l="$level" -v o="$o" -v m="$m" -v oc="$oc" -v mc="$mc" -v r="$ratios" \
    'BEGIN { printf "| %s | %.1f | %.1f | %.2f | %.2f | %s |\n", l, o, m, m / o, mc / oc, r }'
done
