#!/usr/bin/env bash
# Fuzzes every reader and `refine` with cargo-fuzz (libFuzzer), one target after another on one
# core, so other builds can still run.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     default: 60 seconds each, every target
#   RUNS=10000000 scripts/fuzz.sh 0 obj       a number of executions instead of a time
#
# Runs without a sanitizer (`-s none`: the code under test is safe Rust, and it runs ~3x faster)
# with debug assertions, so overflows panic. Needs the nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`). Each target starts
# from fuzz/seeds/<target> and fuzz/regressions/<target> (both committed) and keeps what it
# learns in fuzz/corpus/<target> (ignored by git). A crash is saved under fuzz/artifacts/; copy
# it to fuzz/regressions/<target>/ once fixed: the io tests (tests/fuzz_regressions.rs) replay
# every file there, and the seeds, through the same harness (tessella_io::fuzzing, behind the
# io crate's `fuzzing` feature, which fuzz/Cargo.toml and the io tests turn on).
# -timeout=60: on a loaded machine libFuzzer reported 10 s "timeouts" for inputs that replay in
# milliseconds. The final stats line of each run (stat::number_of_executed_units) goes to fuzz/stats.txt.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds=${1:-60}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(obj ply_ascii ply_binary gltf stl tags_json refine)
fi
limit=(-max_total_time="$seconds")
if [ -n "${RUNS:-}" ]; then
  limit=(-runs="$RUNS")
fi
cargo +nightly fuzz build -O -s none
for target in "${targets[@]}"; do
  mkdir -p "corpus/$target" "regressions/$target" "artifacts/$target"
  log="artifacts/$target/last-run.log"
  echo "== fuzz $target (${limit[*]})"
  status=0
  cargo +nightly fuzz run -O -s none "$target" "corpus/$target" "seeds/$target" "regressions/$target" -- \
    "${limit[@]}" -max_len=4096 -rss_limit_mb=2048 -timeout=60 -print_final_stats=1 \
    >"$log" 2>&1 || status=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  echo "$(date -u +%FT%TZ) $target executions=${runs:-?} exit=$status" | tee -a stats.txt
  if [ "$status" -ne 0 ]; then
    tail -40 "$log" >&2
    echo "fuzz $target found a problem; the input is under fuzz/artifacts/$target/" >&2
    exit "$status"
  fi
done
