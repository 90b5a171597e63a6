"""backend="gl": the OpenGL 4 tessellator (tessella-gl) against backend="cpu" with the same
spacing and levels. The GL output is an unwelded soup; it is compared with the CPU's soup
(weld=False) as sets of triangles: every GL triangle has a CPU triangle whose corners are within
1e-5 of the bounding-box diagonal, normals within 1e-4. Needs an EGL driver with OpenGL 4.3
(CI: Mesa's llvmpipe); in a build without the ``gl`` feature the ValueError is checked instead.
"""

import numpy as np
import pytest

import tessella

NO_FEATURE = '"gl" cargo feature is off'


def _ico():
    t = (1 + 5**0.5) / 2
    v = np.array(
        [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]],
        dtype=np.float32,
    )
    f = np.array(
        [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]],
        dtype=np.uint32,
    )
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def _gl(**kw):
    v, f = _ico()
    try:
        return tessella.refine(v, f, backend="gl", **kw)
    except ValueError as e:
        if NO_FEATURE in str(e):
            pytest.skip("built without the gl feature (checked in test_gl_feature_off_message)")
        raise
    except RuntimeError as e:
        pytest.fail(f"no EGL driver with OpenGL 4.3: {e}")


@pytest.mark.parametrize(
    "kw",
    [
        dict(scheme="pn", spacing="equal", level=4),
        dict(scheme="png1", spacing="fractional-odd", level=3.5),
        dict(scheme="phong", spacing="fractional-even", level=4.2),
        dict(scheme="pn", normals_mode="real", spacing="equal", level=3),
        dict(scheme="pn", spacing="fractional-odd", lod="tolerance:0.003"),
    ],
)
def test_gl_equals_the_cpu_soup(kw):
    gv, gf, gn = _gl(**kw)
    v, f = _ico()
    cv, cf, cn = tessella.refine(v, f, backend="cpu", weld=False, **kw)
    assert gv.dtype == np.float32 and gf.dtype == np.uint32
    # Unwelded as the CLI's: 3 vertices per triangle, triangle t is (3t, 3t+1, 3t+2).
    assert len(gv) == 3 * len(gf)
    assert np.array_equal(gf.ravel(), np.arange(len(gv), dtype=np.uint32))
    assert len(gf) == len(cf)
    diag = float(np.linalg.norm(v.max(0) - v.min(0)))
    worst_p, worst_n = _match(gv, gf, gn, cv, cf, cn, diag)
    assert worst_p < 1e-5, worst_p
    assert worst_n < 1e-4, worst_n


def _match(gv, gf, gn, cv, cf, cn, diag):
    """Largest corner (over the diagonal) and normal differences, each GL triangle matched to
    the CPU triangle with the nearest centroid, as some rotation of it (same winding); each
    CPU triangle is matched once."""
    gc = gv[gf].mean(axis=1)
    cc = cv[cf].mean(axis=1)
    used = np.zeros(len(cf), dtype=bool)
    worst_p = worst_n = 0.0
    for t in range(len(gf)):
        j = int(np.argmin(np.linalg.norm(cc - gc[t], axis=1)))
        assert not used[j], f"two GL triangles on CPU triangle {j}"
        used[j] = True
        best = min(
            (
                np.linalg.norm(gv[gf[t]] - cv[np.roll(cf[j], -r)], axis=1).max() / diag,
                np.linalg.norm(gn[gf[t]] - cn[np.roll(cf[j], -r)], axis=1).max(),
            )
            for r in range(3)
        )
        worst_p, worst_n = max(worst_p, best[0]), max(worst_n, best[1])
    return worst_p, worst_n


def test_the_match_catches_a_moved_vertex():
    v, f = _ico()
    cv, cf, cn = tessella.refine(v, f, backend="cpu", weld=False, spacing="equal", level=2)
    moved = cv.copy()
    moved[7] += 1e-3
    diag = float(np.linalg.norm(v.max(0) - v.min(0)))
    assert _match(cv, cf, cn, cv, cf, cn, diag) == (0.0, 0.0)
    assert _match(moved, cf, cn, cv, cf, cn, diag)[0] > 1e-4


def test_gl_refuses_the_grid_and_origin_with_value_errors():
    v, f = _ico()
    with pytest.raises(ValueError, match="spacing=|cargo feature is off"):
        tessella.refine(v, f, backend="gl", level=4)
    with pytest.raises(ValueError, match="origin=True cannot be combined with backend=.gl.|cargo feature is off"):
        tessella.refine(v, f, backend="gl", spacing="equal", level=4, origin=True)


def test_gl_feature_off_message():
    """Whatever this build has, the CPU-only message names the feature (the Rust source is the
    one the package is built from)."""
    import pathlib

    src = pathlib.Path(__file__).resolve().parents[1] / "src" / "gl.rs"
    if not src.exists():
        pytest.skip("the Rust sources are not beside the tests")
    assert NO_FEATURE.replace('"', '\\"') in src.read_text()


def test_backends_lists_gl_exactly_when_it_runs():
    """``backends()`` names "gl" when a context opens; then backend="gl" refines (CI has
    llvmpipe, so there it must be listed)."""
    v, f = _ico()
    if "gl" in tessella.backends():
        gl = tessella.refine(v, f, backend="gl", spacing="equal", level=2)
        cpu = tessella.refine(v, f, backend="cpu", weld=False, spacing="equal", level=2)
        assert len(gl[1]) == len(cpu[1]) == 20 * 6  # the tessellator's level-2 triangle
    else:
        with pytest.raises((ValueError, RuntimeError)):
            tessella.refine(v, f, backend="gl", spacing="equal", level=2)
        pytest.fail("no OpenGL 4.3 context here; CI installs Mesa's llvmpipe (scripts/setup-gl.sh)")
