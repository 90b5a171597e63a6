#!/usr/bin/env bash
# Frame time against coarse size at one refined size: the creature (320 triangles) at level
# 32, its PN refinements at levels 8 (20,480 triangles) and 16 (81,920) tessellated at levels 4
# and 2: 327,680 refined triangles each time, with the light's shadows on and a ground, drawn
# in its own mesh (the default), per frame, welded and in runs (`TessellaDraw`). Beside them, the plain Bevy mesh of the
# same 327,680 triangles (`tessella refine` offline), the baseline of the same run. Each frame waits for the GPU (`view --frames`). Prints one JSON
# line per run, then a table of mean frame times and ratios to the plain mesh.
# Usage: scripts/coarse-size.sh [PROFILE: debug|release] [FRAMES]
# TESSELLA_METRIC=mean_frame_cpu_ms: CPU time a frame (all threads, lavapipe's too) instead of wall time.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=${1:-release}
frames=${2:-60}
# shellcheck source=common.sh
source "scripts/common.sh"
creature=$samples/creature.obj
"$cli" refine "$creature" --scheme pn --level 8 -o "$tmp/c20k.obj" >/dev/null
"$cli" refine "$creature" --scheme pn --level 16 -o "$tmp/c82k.obj" >/dev/null
"$cli" refine "$creature" --scheme pn --level 32 -o "$tmp/plain.obj" >/dev/null
run() { # label, then view's arguments
  local label=$1
  shift
  local line
  line=$("$view" "$@" --ground --size 512x512 --frames "$frames" --screenshot "$tmp/$label.png" 2>/dev/null | tail -1)
  echo "$line" >&2
  echo "$label $(echo "$line" | sed "s/.*\"${TESSELLA_METRIC:-mean_frame_ms}\":\([0-9.]*\).*/\1/")"
}
{
  run plain "$tmp/plain.obj" --plain --frame "$creature"
  for draw in mesh per-frame welded runs; do
    run "$draw-320" "$creature" --scheme pn --level 32 --draw $draw
    run "$draw-20480" "$tmp/c20k.obj" --scheme pn --level 4 --draw $draw
    run "$draw-81920" "$tmp/c82k.obj" --scheme pn --level 2 --draw $draw
  done
} | awk '
  NR == 1 { base = $2 }
  { rows[NR] = $1; ms[NR] = $2 }
  END {
    print "| draw, coarse triangles (327,680 refined) | mean frame ms | vs plain | vs 320 coarse, same draw |"
    print "|---|---|---|---|"
    for (i = 1; i <= NR; i++) {
      first = 2 + 3 * int((i - 2) / 3)
      printf "| %s | %.2f | %.2fx | %s |\n", rows[i], ms[i], ms[i] / base, (i >= 2 ? sprintf("%.2fx", ms[i] / ms[first]) : "")
    }
  }'
