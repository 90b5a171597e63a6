#!/usr/bin/env bash
# Instructions per refined vertex of the per-frame path (Plan::evaluate, positions + normals
# into reused buffers), per scheme, from callgrind: the instructions of a run with 3 frames
# minus those of a run with 1 frame, over the 2 frames' vertices. Deterministic, unlike seconds.
# One thread: idle rayon workers spin, and under valgrind that spinning would be counted.
# Valgrind reports no AVX-512, so this counts the AVX2 copy of the evaluator.
# Usage: scripts/frame_cost.sh [LEVEL]   (needs valgrind; builds the example in release)
#        FRAME_COST_BIN=path scripts/frame_cost.sh [LEVEL]   (counts that build instead, e.g. an
#        older commit's, for a before/after pair)
set -euo pipefail
cd "$(dirname "$0")/.."
level=${1:-32}
bin=${FRAME_COST_BIN:-}
if [ -z "$bin" ]; then
    cargo build --release --quiet --example frame_cost -p tessella-core
    bin=target/release/examples/frame_cost
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
count() { # scheme normals frames -> instructions
    RAYON_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$out/cg" "$bin" "$1" "$2" "$level" "$3" \
        2>"$out/log" >"$out/stdout"
    grep -o 'Collected : [0-9]*' "$out/log" | grep -o '[0-9]*$'
}
echo "| scheme | normals | level | instructions per vertex |"
echo "|---|---|---:|---:|"
for pair in "pn quadratic" "pn real" "png1 quadratic" "phong quadratic"; do
    set -- $pair
    one=$(count "$1" "$2" 1)
    three=$(count "$1" "$2" 3)
    vertices=$(grep -o '^[0-9]*' "$out/stdout")
    awk -v a="$one" -v b="$three" -v n="$vertices" -v s="$1" -v m="$2" -v l="$level" \
        'BEGIN { printf "| %s | %s | %d | %.1f |\n", s, m, l, (b - a) / (2 * n) }'
done
