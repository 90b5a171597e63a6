"""tessella.quality: its numbers checked against cases with known answers and against
measurements made here from refine's output."""

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh, grid, icosphere, uniform_barycentrics

KEYS = {
    "scheme", "level", "edges_checked", "samples_per_edge", "normal_jump_max_deg",
    "normal_jump_mean_deg", "gap_max", "gap_max_relative", "distance_max",
    "distance_max_relative", "diagonal",
}


@pytest.mark.parametrize("scheme", ["flat", "phong", "pn", "png1", "pn-aen", "st"])
def test_every_scheme_keeps_a_flat_grid_flat(scheme):
    n = 5
    v, f = grid(n)
    q = tessella.quality(v, f, scheme=scheme, level=8)
    assert set(q) == KEYS
    assert q["scheme"] == scheme and q["level"] == 8 and q["samples_per_edge"] > 0
    # Interior edges of an n x n grid: 3(n-1)^2 + 2(n-1) edges, 4(n-1) of them on the boundary.
    assert q["edges_checked"] == 3 * (n - 1) ** 2 + 2 * (n - 1) - 4 * (n - 1)
    assert q["diagonal"] == pytest.approx(2**0.5)
    # A plane with its own normals has nothing to bend: no distance, jump or gap (float32 nets).
    assert q["distance_max"] < 1e-7 and q["distance_max_relative"] < 1e-7
    assert q["normal_jump_max_deg"] < 1e-4 and q["normal_jump_mean_deg"] < 1e-4
    assert q["gap_max"] < 1e-7


@pytest.mark.parametrize("scheme", ["phong", "pn", "png1"])
def test_distance_from_the_coarse_mesh_matches_the_refined_points(sphere, scheme):
    """distance_max is the largest |refined point - flat point| over the pattern: measured here
    from refine's unwelded output and the pattern's barycentrics."""
    v, f, n = sphere
    level = 6
    rv, _, _ = tessella.refine(v, f, n, scheme=scheme, level=level, weld=False)
    bary = uniform_barycentrics(level)
    flat = np.einsum("pk,fkc->fpc", bary, v[f].astype(np.float64))
    ours = np.linalg.norm(rv.reshape(flat.shape) - flat, axis=2).max()
    q = tessella.quality(v, f, n, scheme=scheme, level=level)
    assert ours > 0.02  # the sphere bulges out of its coarse facets
    assert q["distance_max"] == pytest.approx(ours, abs=2e-6)
    assert q["distance_max_relative"] == pytest.approx(q["distance_max"] / q["diagonal"])
    lo, hi = v.min(axis=0).astype(np.float64), v.max(axis=0).astype(np.float64)
    assert q["diagonal"] == pytest.approx(np.linalg.norm(hi - lo), rel=1e-6)


def test_closed_mesh_checks_every_edge_and_open_mesh_only_inner_ones():
    v, f = icosphere(2)
    assert tessella.quality(v, f, v, level=1)["edges_checked"] == len(f) * 3 // 2
    v, f, n = bumpy_mesh()
    # 6 x 6 grid: 85 edges, 20 on the boundary.
    assert tessella.quality(v, f, n, level=1)["edges_checked"] == 65


def test_phong_alpha_is_used():
    v, f = icosphere(1)
    d = [tessella.quality(v, f, v, scheme="phong", alpha=a, level=4)["distance_max"] for a in (0.0, 0.5, 1.0)]
    assert d[0] < 1e-6 < d[1] < d[2]


@pytest.mark.parametrize(
    "kwargs, exc, message",
    [
        (dict(level=0), ValueError, r"level must be 1 or more"),
        (dict(level=257), ValueError, r"use a level of 256 or less"),
        (dict(scheme="loop"), ValueError, r"unknown scheme"),
        (dict(scheme="phong", alpha=float("inf")), ValueError, r"alpha: must be finite"),
        (dict(crease_angle=181), ValueError, r"crease angle must be"),
    ],
)
def test_bad_options_raise_clear_errors(kwargs, exc, message):
    v, f = icosphere(0)
    with pytest.raises(exc, match=message):
        tessella.quality(v, f, **kwargs)


def test_bad_arrays_raise_like_refine():
    v, f = icosphere(0)
    with pytest.raises(ValueError, match=r"vertices must have shape \(n, 3\)"):
        tessella.quality(v[:, :2], f)
    with pytest.raises(ValueError, match=r"uses vertex 12"):
        tessella.quality(v, f + 1)
    with pytest.raises(TypeError, match=r"faces must hold integers"):
        tessella.quality(v, f.astype(np.float32))
