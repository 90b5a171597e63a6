#!/usr/bin/env bash
# Runs every test of the project: formatting, lints, the Rust workspace's tests (GPU tests on
# Mesa's lavapipe when there is no GPU) and the Python package's tests in a fresh venv.
# Installs what it needs: Debian's Vulkan loader and lavapipe (when run as root), Python
# packages into a fresh virtual environment.
set -euo pipefail
cd "$(dirname "$0")/.."

# A clean run writes about 12 GB: target/ about 6 GB, the Bevy plugin's target/ about 3 GB, the
# Python extension's build and venv about 2 GB, besides Rust 1.97.1, Debian packages and the
# crates' sources. Say so early when the disk is short; make_room below frees what it can.
free_gb() { df -Pk "$1" | awk 'NR == 2 { printf "%d", $4 / 1048576 }'; }
if [ "$(free_gb .)" -lt 12 ]; then
  echo "warning: $(free_gb .) GB free on this disk; a clean test run writes about 12 GB" >&2
fi

# make_room GB STAGE [PATH...]: when fewer than GB gigabytes are free before STAGE, deletes what
# the finished stages wrote and no later stage reads: the workspace's test and example
# executables (the libraries stay, so `cargo build -p tessella-cli` stays quick, and so does the
# CLI binary that the web and Bevy tests compare against), the Python extension's build folder
# and venv, the npm package's wasm intermediates (js/dist keeps the built wasm) and the PATHs
# given. A CI machine once ran out of disk in the Bevy build, the last stage; a developer's
# machine with room keeps its caches.
make_room() {
  local need=$1 stage=$2 before
  shift 2
  before=$(free_gb .)
  [ "$before" -lt "$need" ] || return 0
  find target/debug/deps -maxdepth 1 -type f -perm -u+x ! -name '*.so' -delete
  rm -rf target/debug/examples python/target "${TESSELLA_VENV:-/tmp/tessella-venv}" \
    target/wasm-scalar target/wasm-simd target/wasm32-unknown-unknown "$@"
  echo "== ${before} GB free before ${stage}, fewer than ${need}: deleted finished stages' build outputs, now $(free_gb .) GB"
}

bash scripts/setup-vulkan.sh
bash scripts/setup-gl.sh
# `tessella view`'s window tests (crates/tessella-cli/tests/view.rs) run under a virtual X server
# type keys into the window (xdotool) and read what it shows (xwd, in x11-apps).
if { ! command -v xvfb-run >/dev/null || ! command -v xdotool >/dev/null || ! command -v xwd >/dev/null; } && [ "${TESSELLA_NO_DISPLAY_TESTS:-}" != 1 ]; then
  if [ "$(id -u)" = 0 ]; then
    echo "== installing Xvfb (a virtual X server), xdotool and xwd for the window tests"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb xauth xdotool x11-apps >/dev/null
  else
    echo "the window tests need xvfb-run and xdotool: apt-get install -y xvfb xauth xdotool x11-apps (as root), or set TESSELLA_NO_DISPLAY_TESTS=1" >&2
    exit 1
  fi
fi

# A clean checkout gains nothing from incremental caches: they would only take disk space.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"

echo "== cargo fmt"
cargo fmt --all -- --check
echo "== cargo clippy"
cargo clippy --workspace --all-targets --quiet -- -D warnings
echo "== cargo doc (broken or private links are errors)"
RUSTDOCFLAGS=-Dwarnings cargo doc --workspace --no-deps --quiet
echo "== cargo test"
cargo test --workspace
echo "== CPU-only CLI: builds without the gpu feature, no wgpu in its tree, refines and displaces"
if cargo tree -p tessella-cli --no-default-features -e normal | grep -qE 'wgpu|winit'; then
  echo "wgpu or winit is in the dependency tree of the CPU-only CLI" >&2
  exit 1
fi
# The shared target folder: only the CLI crate itself is compiled again (the GPU-enabled
# binary that later steps use is rebuilt by them: `cargo build -p tessella-cli` below and the
# Python tests' `cli` fixture). Its own folder would build every dependency a second time.
cargo build --quiet -p tessella-cli --no-default-features
cpu_only=$(mktemp -d)
target/debug/tessella refine samples/hard-cube.obj -o "$cpu_only/cube.ply" \
  --scheme pn-aen --level 4 --displace sine:0.05,10 --backend auto
test -s "$cpu_only/cube.ply" || { echo "CPU-only refine wrote nothing" >&2; exit 1; }
if target/debug/tessella render samples/icosphere.obj -o "$cpu_only/x.png" 2>"$cpu_only/err"; then
  echo "the CPU-only binary rendered a picture" >&2
  exit 1
fi
grep -q "built without GPU support" "$cpu_only/err" || { cat "$cpu_only/err" >&2; exit 1; }
test ! -e "$cpu_only/x.png" || { echo "the CPU-only render left a file" >&2; exit 1; }
if target/debug/tessella view 2>"$cpu_only/err"; then
  echo "the CPU-only binary opened a viewer" >&2
  exit 1
fi
grep -q "built without them" "$cpu_only/err" || { cat "$cpu_only/err" >&2; exit 1; }
rm -rf "$cpu_only"
echo "== example: an application's own device, buffers and pipeline (tessella-gpu/examples/deform.rs)"
frames=$(mktemp -d)
cargo run --quiet -p tessella-gpu --example deform -- "$frames" --frames 3 --size 64
for k in 000 001 002; do
  test -s "$frames/frame_$k.png" || { echo "deform: frame_$k.png missing" >&2; exit 1; }
done
if cmp -s "$frames/frame_000.png" "$frames/frame_001.png"; then
  echo "deform: frames 0 and 1 are identical: the mesh did not move" >&2
  exit 1
fi
rm -rf "$frames"
# -- tessella-gpu in the browser: wgpu's webgpu backend, without the blocking forms (pollster),
# builds for wasm32 so the async, non-blocking API cannot regress.
echo "== tessella-gpu for wasm32-unknown-unknown (webgpu backend, no blocking feature)"
rustup target add wasm32-unknown-unknown
cargo check --quiet -p tessella-gpu --target wasm32-unknown-unknown --no-default-features
echo "== python extension crate: fmt and clippy (its own cargo workspace)"
(cd python && cargo fmt -- --check && cargo clippy --quiet -- -D warnings)
if [ -f python/ci.sh ]; then
  echo "== python"
  bash python/ci.sh
fi

# --- The browser: wasm32 builds and the npm package `tessella` (js/) ---
# Installs what it needs: the wasm32 target (rustup), wasm-bindgen-cli at the version locked in
# Cargo.lock when `wasm-bindgen --version` differs (js/scripts/build.js), Node packages (npm ci).
# tessella-core and tessella-io build for wasm32 as dependencies of the package's wasm (no
# separate `cargo check` for wasm32: it compiled every dependency once more).
echo "== npm package js/: build the wasm (core, io, bindings) from the Rust sources, test with Node's test runner"
if ! command -v node >/dev/null && [ "$(id -u)" = 0 ]; then
  apt-get update -qq && apt-get install -y -qq nodejs npm >/dev/null
fi
node -e 'if (+process.versions.node.split(".")[0] < 20) { console.error("the npm package needs Node 20 or later, found " + process.version); process.exit(1) }'
(cd js && npm ci --no-audit --no-fund && npm run build && npm test)

# --- The viewer's web page (web/): Chromium headless against the page and `tessella render` ---
# Installs Debian's Chromium when missing (as root), builds the CLI for the reference pictures,
# builds the site (the engine's wasm through crates/tessella-viewer/build-web.sh; the npm
# package's wasm from the js/ section above is reused, not rebuilt) and runs the browser tests.
echo "== web viewer: build the static site, drive it in headless Chromium (WebGPU on SwiftShader, and the WebGL2 fallback)"
if [ ! -x /usr/bin/chromium ] && [ -z "${CHROMIUM:-}" ]; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    echo "the web tests need Chromium: apt-get install -y chromium (as root), or set CHROMIUM" >&2
    exit 1
  fi
fi
make_room 6 "the web viewer"
cargo build --quiet -p tessella-cli
(cd web && npm ci --no-audit --no-fund && npm run build && npm test)


# --- The Bevy plugin (crates/tessella-bevy): a workspace of its own on Rust 1.97.1 ---
# Bevy 0.20.1 declares Rust 1.97.1 (the crate's rust-toolchain.toml); rustup installs it. Its
# tests run the `view` example headless on lavapipe against the CLI built above
# (target/debug/tessella) as the independent reference.
make_room 8 "the Bevy plugin (about 3 GB of build outputs, and its toolchain)" target/wasm-viewer
echo "== Bevy plugin: fmt, clippy, tests (its own workspace, toolchain 1.97.1)"
rustup toolchain install 1.97.1 --profile minimal --component rustfmt --component clippy
(cd crates/tessella-bevy \
  && cargo fmt -- --check \
  && cargo clippy --all-targets --quiet -- -D warnings \
  && TESSELLA_BIN="$PWD/../../target/debug/tessella" cargo test)
