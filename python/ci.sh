#!/usr/bin/env bash
# Builds the tessella Python package in a fresh virtual environment and runs its tests.
#
#   bash python/ci.sh [VENV]        (VENV defaults to $TESSELLA_VENV, else /tmp/tessella-venv)
#
# Needs: python3 with venv, a Rust toolchain (cargo, for the extension and the CLI the tests
# compare against), PyPI, and a GPU adapter for tests/test_gpu.py: without a GPU, Mesa's
# software Vulkan driver (lavapipe). The FEM example's gmsh wheel needs X11/OpenGL client
# libraries; PyVista's off-screen pictures need EGL (scripts/setup-gl.sh). When the libraries
# or the Vulkan driver are missing and this runs as root with
# apt-get, they are installed (Debian names below).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
VENV="${1:-${TESSELLA_VENV:-/tmp/tessella-venv}}"
PYTHON="${PYTHON:-python3}"
GMSH_DEBS="libglu1-mesa libgl1 libxrender1 libxcursor1 libxfixes3 libxext6 libxft2 libfontconfig1 libxinerama1 libx11-6 libgomp1"
VULKAN_DEBS="mesa-vulkan-drivers libvulkan1"

# Installs Debian packages when this runs as root with apt-get, else says what is missing and
# goes on; the one policy for every system library the tests need (gmsh's, the Vulkan driver).
#   apt_install_or_warn WHAT DEBS PROBLEM
apt_install_or_warn() {
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "== python: installing $1: $2"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $2 >/dev/null
    else
        echo "$3; install: apt-get install $2" >&2
    fi
}

# A Vulkan loader and at least one driver (lavapipe is one); the GPU tests fail without them.
have_vulkan() {
    { ldconfig -p 2>/dev/null || /sbin/ldconfig -p 2>/dev/null; } | grep -q 'libvulkan\.so\.1' &&
        { compgen -G "/usr/share/vulkan/icd.d/*.json" || compgen -G "/etc/vulkan/icd.d/*.json"; } >/dev/null
}

echo "== python: the CPU-only build (no gpu, no gl feature) compiles and links no wgpu, glow or EGL"
(cd "$HERE" && cargo check -q --no-default-features)
if (cd "$HERE" && cargo tree -q --no-default-features -e normal) | grep -qE 'wgpu|glow|khronos-egl'; then
    echo "cargo tree --no-default-features still pulls in wgpu, glow or khronos-egl" >&2
    exit 1
fi

echo "== python: fresh venv in $VENV"
rm -rf "$VENV"
"$PYTHON" -m venv "$VENV"
PIP=("$VENV/bin/python" -m pip --disable-pip-version-check -q)
"${PIP[@]}" install --upgrade pip
"${PIP[@]}" install maturin numpy pytest trimesh meshio h5py gmsh matplotlib pyvista mypy "dask[distributed]"

echo "== python: building and installing the package (maturin, release)"
"${PIP[@]}" install "$HERE"

if ! "$VENV/bin/python" -c "import gmsh" 2>/dev/null; then
    apt_install_or_warn "gmsh's system libraries" "$GMSH_DEBS" "gmsh cannot be imported"
fi

# backend="gl" (tests/test_gl.py) needs EGL with OpenGL 4.3: Mesa's llvmpipe.
bash "$HERE/../scripts/setup-gl.sh"

if ! have_vulkan; then
    apt_install_or_warn "a software Vulkan driver for the GPU tests" "$VULKAN_DEBS" \
        "no Vulkan driver found, the GPU tests will fail"
fi

echo "== python: mypy --strict on the examples (the package's annotations and _tessella.pyi)"
(cd "$HERE" && "$VENV/bin/python" -m mypy --strict examples/fem_sphere.py examples/fem_fields.py examples/fem_pyvista.py)

# PyVista renders off screen without an X server: VTK's wheel falls back to EGL (Mesa's
# llvmpipe, set up above for backend="gl"); naming the EGL window skips the X attempt.
export VTK_DEFAULT_OPENGL_WINDOW="${VTK_DEFAULT_OPENGL_WINDOW:-vtkEGLRenderWindow}"

echo "== python: pytest"
# Run from outside python/ so the source tree's tessella/ does not shadow the installed one.
cd "$VENV"
"$VENV/bin/python" -m pytest "$HERE/tests" -q -p no:cacheprovider
