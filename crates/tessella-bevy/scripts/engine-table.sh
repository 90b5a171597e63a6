#!/usr/bin/env bash
# Bevy's table for issue 40: frame times at levels 4, 8, 16 and 32, the light's shadows on and
# a ground, 512x512, each frame waited for on the GPU (`view --frames`):
# - static: the creature (320 triangles) with `Tessellate` (PN) in each draw (`TessellaDraw`):
#   its own mesh written by the compute pass (the default), per frame (a pool's slot read by the
#   tessellated material), welded and in runs, against the plain Bevy mesh of the same refined
#   surface (`tessella refine`, OBJ);
# - animated: the skinned creature (animated-creature.glb) playing its `wave` clip through
#   Bevy's AnimationPlayer, with `Tessellate`: its own mesh posed on the GPU (the default: joint
#   matrices uploaded), per frame posed on the GPU and on the CPU (nets uploaded), and welded,
#   against the same file refined offline (`tessella refine`, skins and clips kept) played by
#   Bevy's own skinning.
# Prints the view example's JSON lines to stderr and two Markdown tables of mean frame times.
# Usage: scripts/engine-table.sh [PROFILE: debug|release] [FRAMES] [LEVELS]
# TESSELLA_METRIC=mean_frame_cpu_ms: the tables in CPU time a frame (all threads, lavapipe's too).
# TESSELLA_ROUNDS=N: each way run N times, in turn with the others of its level; the median.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=${1:-release}
frames=${2:-40}
levels=${3:-4 8 16 32}
# shellcheck source=common.sh
source "scripts/common.sh"
ms() { # view's arguments; prints the mean frame time
  local line
  line=$("$view" "$@" --ground --size 512x512 --frames "$frames" --screenshot "$tmp/shot.png" 2>/dev/null | tail -1)
  echo "$line" >&2
  echo "$line" | sed "s/.*\"${TESSELLA_METRIC:-mean_frame_ms}\":\([0-9.]*\).*/\1/"
}
echo "| level | static: refined mesh ms | mesh (default) ms | ratio | per frame ms | ratio | welded ms | ratio | runs ms | ratio |" > "$tmp/static.md"
echo "|---|---|---|---|---|---|---|---|---|---|" >> "$tmp/static.md"
echo "| level | animated: offline-refined skinned ms | mesh, GPU posing (default) ms | ratio | per frame, GPU posing ms | ratio | per frame, CPU posing ms | ratio | welded, CPU posing ms | ratio |" > "$tmp/animated.md"
echo "|---|---|---|---|---|---|---|---|---|---|" >> "$tmp/animated.md"
rounds=${TESSELLA_ROUNDS:-1}
for level in $levels; do
  "$cli" refine "$samples/creature.obj" --scheme pn --level "$level" -o "$tmp/static.obj" >/dev/null 2>&1
  "$cli" refine "$samples/animated-creature.glb" --scheme pn --level "$level" -o "$tmp/skinned.glb" >/dev/null 2>&1
  playing=(--scheme pn --level "$level" --clip wave --frame "$samples/creature.obj")
  declare -A got=()
  for _ in $(seq "$rounds"); do
    got[plain]+=" $(ms "$tmp/static.obj" --plain --frame "$samples/creature.obj")"
    got[mesh]+=" $(ms "$samples/creature.obj" --scheme pn --level "$level" --draw mesh)"
    got[frame]+=" $(ms "$samples/creature.obj" --scheme pn --level "$level" --draw per-frame)"
    got[tess]+=" $(ms "$samples/creature.obj" --scheme pn --level "$level" --draw welded)"
    got[runs]+=" $(ms "$samples/creature.obj" --scheme pn --level "$level" --draw runs)"
    got[offline]+=" $(ms "$tmp/skinned.glb" --plain --clip wave --frame "$samples/creature.obj")"
    got[meshgpu]+=" $(ms "$samples/animated-creature.glb" "${playing[@]}" --draw mesh --pose gpu)"
    got[gpu]+=" $(ms "$samples/animated-creature.glb" "${playing[@]}" --draw per-frame --pose gpu)"
    got[cpu]+=" $(ms "$samples/animated-creature.glb" "${playing[@]}" --draw per-frame --pose cpu)"
    got[welded]+=" $(ms "$samples/animated-creature.glb" "${playing[@]}" --draw welded)"
  done
  # shellcheck disable=SC2086 # the rounds' values, one word each
  for way in plain mesh frame tess runs offline meshgpu gpu cpu welded; do declare "$way=$(printf "%s\n" ${got[$way]} | median)"; done
  awk -v l="$level" -v a="$plain" -v m="$mesh" -v f="$frame" -v b="$tess" -v r="$runs" \
    'BEGIN { printf "| %s | %.2f | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx |\n", l, a, m, m / a, f, f / a, b, b / a, r, r / a }' >> "$tmp/static.md"
  awk -v l="$level" -v a="$offline" -v m="$meshgpu" -v g="$gpu" -v c="$cpu" -v w="$welded" \
    'BEGIN { printf "| %s | %.2f | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx |\n", l, a, m, m / a, g, g / a, c, c / a, w, w / a }' >> "$tmp/animated.md"
  unset got
done
cat "$tmp/static.md"
echo
cat "$tmp/animated.md"
