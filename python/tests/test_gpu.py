"""The GPU backend: ``backend="gpu"`` gives the CPU's faces and, to float rounding, its vertices
and normals for every scheme; displacement on the GPU equals the CPU's and the formulas (sine,
Perlin's improved noise, evaluated here in float64); ``"auto"`` picks the CPU without a
hardware GPU; bad ``displace`` values raise; no adapter gives clear errors.

These tests need a GPU adapter. Without a hardware GPU, Mesa's software Vulkan driver (lavapipe)
serves: ``apt-get install mesa-vulkan-drivers libvulkan1`` (CI installs it). They fail, not skip,
when no adapter exists.
"""

import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh, icosphere, ridge_mesh
from test_schemes import BUMPY_TAGS

POSITION_TOL = 1e-5  # times the coarse bounding-box diagonal
NORMAL_TOL = 1e-4


def meshes():
    sphere_v, sphere_f = icosphere(1)
    ridge_v, ridge_f, ridge_n, _ = ridge_mesh()
    return {
        "sphere": (sphere_v, sphere_f, sphere_v.copy()),  # closed, exact normals
        "bumpy": bumpy_mesh(3),  # open, irregular, skewed normals
        "ridge": (ridge_v, ridge_f, ridge_n),  # split normals along a hard edge
    }


MESHES = meshes()


def diagonal(v):
    v = np.asarray(v, dtype=np.float64)
    return float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))


def assert_close(cpu, gpu, diag):
    """Same faces exactly; positions within POSITION_TOL * diag; normals within NORMAL_TOL."""
    (cv, cf, cn), (gv, gf, gn) = cpu, gpu
    assert gv.dtype == np.float32 and gf.dtype == np.uint32 and gn.dtype == np.float32
    assert gv.shape == cv.shape and gn.shape == cn.shape
    np.testing.assert_array_equal(gf, cf)
    assert np.abs(gv.astype(np.float64) - cv).max() <= POSITION_TOL * diag
    assert np.abs(gn.astype(np.float64) - cn).max() <= NORMAL_TOL


def test_a_gpu_adapter_is_there():
    # Fails (never skips) on a machine without any adapter: CI installs lavapipe.
    assert tessella.backends()[:2] == ["cpu", "gpu"]
    info = tessella.gpu_info()
    assert info is not None, "no GPU adapter: apt-get install mesa-vulkan-drivers libvulkan1"
    assert set(info) == {"name", "backend", "device_type", "driver", "driver_info", "software"}
    assert info["name"] and info["backend"] in {"Vulkan", "Metal", "Dx12"}
    assert info["software"] == (info["device_type"] == "Cpu")


@pytest.mark.parametrize("level", [1, 4, 9])
@pytest.mark.parametrize("mesh", sorted(MESHES))
@pytest.mark.parametrize("scheme", tessella.schemes())
def test_gpu_equals_cpu(scheme, mesh, level):
    v, f, n = MESHES[mesh]
    kw = dict(scheme=scheme, level=level)
    cpu = tessella.refine(v, f, n, backend="cpu", **kw)
    gpu = tessella.refine(v, f, n, backend="gpu", **kw)
    assert gpu[1].shape == (len(f) * level**2, 3)
    assert_close(cpu, gpu, diagonal(v))


@pytest.mark.parametrize(
    "kw",
    [
        dict(scheme="pn", weld=False),
        dict(scheme="png1", weld=False),
        dict(scheme="phong", alpha=0.4),
        dict(scheme="pn", normals_mode="real"),
        dict(scheme="phong", normals_mode="quadratic"),
        dict(scheme="png1", normals_mode="real"),
        dict(scheme="png1", tags=BUMPY_TAGS),
        dict(scheme="st", tags=BUMPY_TAGS),
        dict(scheme="png1", crease_angle=15.0),
        dict(scheme="flat", weld=False),
    ],
    ids=lambda kw: "-".join(f"{k}={v}" if k != "tags" else "tags" for k, v in kw.items()),
)
def test_gpu_equals_cpu_with_options(kw):
    v, f, n = MESHES["bumpy"]
    cpu = tessella.refine(v, f, n, level=5, backend="cpu", **kw)
    gpu = tessella.refine(v, f, n, level=5, backend="gpu", **kw)
    assert_close(cpu, gpu, diagonal(v))


def test_options_reach_the_gpu():
    # Guards the comparisons above against a GPU path that ignores an option and a CPU path that
    # ignores it too: each option must change the GPU's output.
    v, f, n = MESHES["bumpy"]
    base = tessella.refine(v, f, n, scheme="phong", level=4, backend="gpu")
    for kw in [dict(alpha=0.3), dict(scheme="pn"), dict(normals_mode="quadratic")]:
        other = tessella.refine(v, f, n, **{"scheme": "phong", "level": 4, "backend": "gpu", **kw})
        assert not (np.array_equal(other[0], base[0]) and np.array_equal(other[2], base[2])), kw


# ---- displacement -------------------------------------------------------------------------

SINE = {"kind": "sine", "amplitude": 0.05, "frequency": 9.0}
PERLIN = {"kind": "perlin", "amplitude": 0.08, "frequency": 3.5, "seed": 11}


@pytest.mark.parametrize("weld", [True, False])
@pytest.mark.parametrize("displace", [SINE, PERLIN], ids=["sine", "perlin"])
@pytest.mark.parametrize("scheme", ["flat", "pn", "png1"])
def test_displacement_on_gpu_equals_cpu(scheme, displace, weld):
    v, f, n = MESHES["sphere"]
    kw = dict(scheme=scheme, level=6, weld=weld, displace=displace)
    cpu = tessella.refine(v, f, n, backend="cpu", **kw)
    gpu = tessella.refine(v, f, n, backend="gpu", **kw)
    assert_close(cpu, gpu, diagonal(v))


def permutation(seed):
    """The crate's documented permutation: 0..255 shuffled by Fisher-Yates driven by a 32-bit
    LCG seeded with seed * 2654435761 + 1, doubled to 512 entries."""
    p = list(range(256))
    state = (seed * 2654435761 + 1) & 0xFFFFFFFF
    for i in range(255, 0, -1):
        state = (state * 1664525 + 1013904223) & 0xFFFFFFFF
        j = (state >> 8) % (i + 1)
        p[i], p[j] = p[j], p[i]
    return np.array(p + p, dtype=np.int64)


def improved_noise(perm, p):
    """Perlin's reference ImprovedNoise (2002) in float64, vectorised over points p (k, 3)."""
    p = np.asarray(p, dtype=np.float64)
    fl = np.floor(p)
    xi, yi, zi = (fl.astype(np.int64) & 255).T
    x, y, z = (p - fl).T
    fade = lambda t: t * t * t * (t * (t * 6 - 15) + 10)  # noqa: E731
    lerp = lambda t, a, b: a + t * (b - a)  # noqa: E731

    def grad(h, x, y, z):
        h = h & 15
        u = np.where(h < 8, x, y)
        v = np.where(h < 4, y, np.where((h == 12) | (h == 14), x, z))
        return np.where(h & 1 == 0, u, -u) + np.where(h & 2 == 0, v, -v)

    P = lambda i: perm[i & 511]  # noqa: E731
    u, v, w = fade(x), fade(y), fade(z)
    a = P(xi) + yi
    aa, ab = P(a) + zi, P(a + 1) + zi
    b = P(xi + 1) + yi
    ba, bb = P(b) + zi, P(b + 1) + zi
    return lerp(
        w,
        lerp(v, lerp(u, grad(P(aa), x, y, z), grad(P(ba), x - 1, y, z)),
             lerp(u, grad(P(ab), x, y - 1, z), grad(P(bb), x - 1, y - 1, z))),
        lerp(v, lerp(u, grad(P(aa + 1), x, y, z - 1), grad(P(ba + 1), x - 1, y, z - 1)),
             lerp(u, grad(P(ab + 1), x, y - 1, z - 1), grad(P(bb + 1), x - 1, y - 1, z - 1))),
    )


def offsets(displace, points):
    """The documented offset d(P) along the normal, in float64."""
    a, freq = displace["amplitude"], displace["frequency"]
    if displace["kind"] == "sine":
        return a * np.sin(freq * np.linalg.norm(points, axis=1))
    return a * improved_noise(permutation(displace.get("seed", 0)), freq * points)


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
@pytest.mark.parametrize("displace", [SINE, PERLIN], ids=["sine", "perlin"])
def test_displacement_follows_the_formula_and_stays_within_the_amplitude(backend, displace):
    v, f, n = MESHES["bumpy"]
    kw = dict(scheme="pn", level=7, backend=backend)
    bv, bf, bn = tessella.refine(v, f, n, **kw)
    dv, df, dn = tessella.refine(v, f, n, displace=displace, **kw)
    np.testing.assert_array_equal(df, bf)
    # Normals are the undisplaced surface's, as documented.
    assert np.abs(dn.astype(np.float64) - bn).max() <= NORMAL_TOL
    base = bv.astype(np.float64)
    moved = dv.astype(np.float64) - base
    d = offsets(displace, base)
    # P + d(P) n, with d from this file's float64 formulas.
    expected = d[:, None] * bn.astype(np.float64)
    assert np.abs(moved - expected).max() <= POSITION_TOL * diagonal(v)
    # Within the amplitude (bn is unit length to float rounding), and really displaced.
    a = displace["amplitude"]
    assert np.linalg.norm(moved, axis=1).max() <= a * (1 + 1e-5) + 1e-6
    assert np.linalg.norm(moved, axis=1).max() > 0.3 * a


def test_displacement_forms_and_seeds():
    v, f, n = MESHES["sphere"]
    go = lambda d: tessella.refine(v, f, n, level=3, backend="cpu", displace=d)[0]  # noqa: E731
    plain = go(None)
    np.testing.assert_array_equal(go(("perlin", 0.08, 3.5, 11)), go(PERLIN))
    np.testing.assert_array_equal(go(["sine", 0.05, 9.0]), go(SINE))
    np.testing.assert_array_equal(go({"kind": "SINE", "amplitude": np.float32(0.05), "frequency": 9}), go(SINE))
    np.testing.assert_array_equal(go(("perlin", 0.08, 3.5)), go(("perlin", 0.08, 3.5, 0)))
    np.testing.assert_array_equal(go(("sine", 0.0, 9.0)), plain)
    assert not np.array_equal(go(("perlin", 0.08, 3.5, 1)), go(("perlin", 0.08, 3.5, 2)))


@pytest.mark.parametrize(
    "displace, exc, message",
    [
        ({"kind": "wave", "amplitude": 1, "frequency": 1}, ValueError, r"unknown displace kind \"wave\"; use \"sine\" or \"perlin\""),
        ({"amplitude": 1, "frequency": 1}, ValueError, r"needs a \"kind\""),
        ({"kind": "sine", "frequency": 1}, ValueError, r"needs a value for amplitude"),
        ({"kind": "sine", "amplitude": 1}, ValueError, r"needs a value for frequency"),
        ({"kind": "sine", "amplitude": 1, "frequency": 1, "phase": 2}, ValueError, r"unknown key 'phase'"),
        ({"kind": "sine", "amplitude": 1, "frequency": 1, "seed": 2}, ValueError, r"takes no seed"),
        ({"kind": "sine", "amplitude": float("nan"), "frequency": 1}, ValueError, r"amplitude must be finite"),
        ({"kind": "sine", "amplitude": 1, "frequency": float("inf")}, ValueError, r"frequency must be finite"),
        ({"kind": "sine", "amplitude": 1e300, "frequency": 1}, ValueError, r"float32 range"),
        ({"kind": "sine", "amplitude": "big", "frequency": 1}, ValueError, r"amplitude must be a number, got 'big'"),
        ({"kind": 3, "amplitude": 1, "frequency": 1}, ValueError, r"kind must be a string"),
        (("perlin", 1, 1, -1), ValueError, r"seed must be a whole number from 0 to 4294967295, got -1"),
        (("perlin", 1, 1, 2**32), ValueError, r"seed must be a whole number"),
        (("perlin", 1, 1, 7.5), ValueError, r"seed must be a whole number"),
        (("sine", 1), ValueError, r"got 2 items"),
        (("sine", 1, 2, 3, 4), ValueError, r"got 5 items"),
        (("heightmap", 1, 1), ValueError, r"needs texture coordinates"),
        (3, TypeError, r"displace must be None, a dict"),
        ("sine:0.1,10", TypeError, r"displace must be None, a dict"),
    ],
)
@pytest.mark.parametrize("backend", ["cpu", "gpu", "auto"])
def test_bad_displacement_raises_clear_errors(displace, exc, message, backend):
    v, f, n = MESHES["sphere"]
    with pytest.raises(exc, match=message):
        tessella.refine(v, f, n, level=2, backend=backend, displace=displace)


# ---- backend choice -----------------------------------------------------------------------


@pytest.mark.parametrize("displace", [None, PERLIN])
def test_auto_uses_the_cpu_without_a_hardware_gpu(displace):
    v, f, n = MESHES["bumpy"]
    kw = dict(scheme="png1", level=6, displace=displace)
    auto = tessella.refine(v, f, n, backend="auto", **kw)
    info = tessella.gpu_info()
    # A software adapter is slower than the CPU path, so "auto" leaves it alone.
    expected_backend = "gpu" if info is not None and not info["software"] else "cpu"
    expected = tessella.refine(v, f, n, backend=expected_backend, **kw)
    for a, b in zip(auto, expected):
        np.testing.assert_array_equal(a, b)


def test_threads_share_the_device():
    # The cached device is used by several threads at once (the GIL is released meanwhile).
    v, f, n = MESHES["sphere"]
    jobs = [dict(scheme=s, level=l) for s in ("pn", "png1", "phong") for l in (3, 6)]
    alone = [tessella.refine(v, f, n, backend="gpu", **kw) for kw in jobs]
    together = [None] * len(jobs)
    errors = []

    def work(i):
        try:
            together[i] = tessella.refine(v, f, n, backend="gpu", **jobs[i])
        except Exception as e:  # reported below, with the job
            errors.append((jobs[i], e))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(jobs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for a, b in zip(alone, together):
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)


NO_ADAPTER = """
import numpy as np, tessella
v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
f = [[0, 1, 2]]
assert "gpu" not in tessella.backends(), tessella.backends()
assert tessella.gpu_info() is None
for attempt in range(2):  # the failure is remembered as a failure, never as a device
    try:
        tessella.refine(v, f, level=3, backend="gpu")
    except RuntimeError as e:
        print("ERROR:", e)
    else:
        raise SystemExit("backend='gpu' worked without an adapter")
cpu = tessella.refine(v, f, level=3, backend="cpu", displace=("sine", 0.1, 2.0))
auto = tessella.refine(v, f, level=3, backend="auto", displace=("sine", 0.1, 2.0))
assert all(np.array_equal(a, b) for a, b in zip(cpu, auto))
print("OK")
"""


def test_without_an_adapter_gpu_raises_and_auto_uses_the_cpu(tmp_path):
    # Point the Vulkan loader at no driver at all (both the old and the new variable).
    missing = str(tmp_path / "no-driver.json")
    env = dict(os.environ, VK_ICD_FILENAMES=missing, VK_DRIVER_FILES=missing)
    run = subprocess.run([sys.executable, "-c", NO_ADAPTER], env=env, capture_output=True,
                         text=True, cwd=tmp_path, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    errors = [line for line in run.stdout.splitlines() if line.startswith("ERROR:")]
    assert len(errors) == 2 and errors[0] == errors[1]
    assert 'backend="gpu" needs a GPU adapter: no usable GPU adapter found' in errors[0]
    assert "apt-get install mesa-vulkan-drivers libvulkan1" in errors[0]
    assert run.stdout.splitlines()[-1] == "OK"


def test_unknown_backends_are_refused():
    v, f, n = MESHES["sphere"]
    with pytest.raises(ValueError, match=r'unknown backend "tpu"; use one of \["auto", "cpu", "gpu", "gl"\]'):
        tessella.refine(v, f, n, backend="tpu")
    a = tessella.refine(v, f, n, level=2, backend="GPU")
    b = tessella.refine(v, f, n, level=2, backend="gpu")
    np.testing.assert_array_equal(a[0], b[0])


def test_adaptive_levels_refine_on_the_gpu_as_on_the_cpu():
    """Tessellator spacings and LOD levels take every backend, as the CLI's do: the GPU's
    vertices are the CPU's to float rounding, its triangles the same."""
    v, f = icosphere(2)
    n = None
    for options in (dict(spacing="fractional-odd", level=4.5), dict(lod="tolerance:0.01")):
        cv, cf, cn = tessella.refine(v, f, n, backend="cpu", **options)
        gv, gf, gn = tessella.refine(v, f, n, backend="gpu", **options)
        assert np.array_equal(cf, gf), options
        assert np.abs(gv - cv).max() < 1e-5 * diagonal(cv), options
        assert np.abs(gn - cn).max() < 1e-4, options
