#!/usr/bin/env bash
# Many animated characters (Bevy's many_foxes stress test, on the view example's `--crowd`):
# COUNT copies of a skinned glTF playing CLIP through Bevy's AnimationPlayer, with `Tessellate`
# (PN: each copy's own mesh posed on the GPU, the default; per frame (pooled) posed on the GPU
# and on the CPU, each copy's nets uploaded; welded, posed on the CPU) against the same file
# refined offline by `tessella refine` (skins and clips kept) played by Bevy's own skinning.
# The light's shadows on, a ground, 512x512, each frame waited for on the GPU.
# Usage: scripts/crowd.sh [FILE.glb] [CLIP] [COUNT] [PROFILE] [FRAMES] [LEVELS]
# TESSELLA_METRIC=mean_frame_cpu_ms: CPU time a frame (all threads, lavapipe's too) instead of wall time.
# e.g. scripts/crowd.sh path/to/bevy/assets/models/animated/Fox.glb Run 100
set -euo pipefail
cd "$(dirname "$0")/.."
file=$(realpath "${1:-../../samples/animated-creature.glb}")
clip=${2:-wave}
count=${3:-100}
profile=${4:-release}
frames=${5:-30}
levels=${6:-4 8}
# shellcheck source=common.sh
source "scripts/common.sh"
ms() {
  local line
  line=$("$view" "$@" --crowd "$count" --clip "$clip" --frame "$file" --ground --size 512x512 \
    --frames "$frames" --screenshot "$tmp/shot.png" 2>/dev/null | tail -1)
  echo "$line" >&2
  echo "$line" | sed "s/.*\"${TESSELLA_METRIC:-mean_frame_ms}\":\([0-9.]*\).*/\1/"
}
echo "| $(basename "$file") x $count, level | offline-refined skinned ms | mesh, GPU posing (default) ms | ratio | per frame, GPU posing ms | ratio | per frame, CPU posing ms | ratio | welded ms | ratio |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for level in $levels; do
  "$cli" refine "$file" --scheme pn --level "$level" -o "$tmp/refined.glb" >/dev/null 2>&1
  offline=$(ms "$tmp/refined.glb" --plain)
  mesh=$(ms "$file" --scheme pn --level "$level" --draw mesh --pose gpu)
  gpu=$(ms "$file" --scheme pn --level "$level" --draw per-frame --pose gpu)
  cpu=$(ms "$file" --scheme pn --level "$level" --draw per-frame --pose cpu)
  welded=$(ms "$file" --scheme pn --level "$level" --draw welded)
  awk -v l="$level" -v a="$offline" -v m="$mesh" -v g="$gpu" -v c="$cpu" -v w="$welded" \
    'BEGIN { printf "| %s | %.2f | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx | %.2f | %.2fx |\n", l, a, m, m / a, g, g / a, c, c / a, w, w / a }'
done
