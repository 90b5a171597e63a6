"""Tessellator spacings, fractional and LOD levels, and origins from Python: counts against the
tessellator's own pattern, origins against the coarse corners, bad levels refused."""

import pathlib

import numpy as np
import pytest

import tessella


def icosphere():
    here = pathlib.Path(__file__).resolve().parents[2]
    return tessella.load(str(here / "samples" / "icosphere.obj"))


def test_fractional_level_gives_the_tessellators_triangles_on_every_face():
    v, f, n = icosphere()
    rv, rf, rn = tessella.refine(v, f, n, spacing="fractional-odd", level=5.5, backend="cpu")
    # Every face gets the same pattern: the level-5.5 fractional-odd triangles.
    assert rf.shape[1] == 3 and rf.dtype == np.uint32
    assert len(rf) % len(f) == 0
    per_face = len(rf) // len(f)
    assert per_face > 25  # more than the grid's 5**2, fewer than 7**2 * 3 / 2
    assert per_face < 74
    assert np.allclose(np.linalg.norm(rn, axis=1), 1, atol=1e-5)


def test_fractional_grid_level_geomorphs_between_the_two_integer_levels():
    v, f, n = icosphere()
    five = tessella.refine(v, f, n, level=5, backend="cpu", weld=False)[0]
    six = tessella.refine(v, f, n, level=6, backend="cpu", weld=False)[0]
    rv, rf, _ = tessella.refine(v, f, n, level=5.5, backend="cpu", weld=False)
    # The grid of 6 segments: 36 triangles per face, points off level 6's by a morph.
    assert len(rf) == 36 * len(f) and rv.shape == six.shape
    assert np.abs(rv - six).max() > 1e-4
    # Level 6 - 1e-4 is within 1e-3 of level 6 (no pop).
    near = tessella.refine(v, f, n, level=6 - 1e-4, backend="cpu", weld=False)[0]
    assert np.abs(near - six).max() < 1e-3 * np.abs(six - six.mean(axis=0)).max()
    assert len(five) < len(six)


def test_origin_returns_a_result_object_whose_corners_are_the_coarse_vertices():
    v, f, n = icosphere()
    for weld in (True, False):
        r = tessella.refine(v, f, n, level=4, origin=True, weld=weld)
        assert isinstance(r, tessella.RefineResult)
        assert r.face.shape == (len(r.vertices),) and r.bary.shape == (len(r.vertices), 3)
        rv, rf, rn = tessella.refine(v, f, n, level=4, weld=weld)
        assert np.array_equal(r.faces, rf)
        assert np.array_equal(r.vertices, rv)
        corners = np.isclose(r.bary.max(axis=1), 1.0)
        idx = f[r.face[corners], np.argmax(r.bary[corners], axis=1)]
        assert np.array_equal(r.vertices[corners], v[idx].astype(np.float32))
        # A flat refinement is exactly its barycentric interpolation.
        flat = tessella.refine(v, f, n, scheme="flat", level=3, origin=True, weld=weld)
        expect = np.einsum("ij,ijk->ik", flat.bary, v[f[flat.face]].astype(np.float64))
        assert np.allclose(flat.vertices, expect, atol=1e-6)


def test_lod_strings_and_dicts_agree():
    v, f, n = icosphere()
    a = tessella.refine(v, f, n, lod="tolerance:0.001")
    b = tessella.refine(v, f, n, lod={"kind": "tolerance", "max_deviation": 0.001})
    assert np.array_equal(a[1], b[1])
    cam = (0, 0, 3, 0, 0, 0, 45)
    s = tessella.refine(v, f, n, lod="screen:10", camera=cam, size=(640, 480), spacing="fractional-even")
    d = tessella.refine(v, f, n, lod={"kind": "distance", "near": 2, "far": 4, "max": 12}, camera=cam)
    assert len(s[1]) > 0 and len(d[1]) > 0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(level=-1.0, spacing="equal"), "finite number above 0"),
        (dict(level=float("nan"), spacing="fractional-odd"), "finite number above 0"),
        (dict(lod="tolerance:0"), "above 0"),
        (dict(lod="screen:4", size=(10, 10)), "camera"),
        (dict(lod="screen:4", camera=(0, 0, 3, 0, 0, 0, 0), size=(10, 10)), "field of view"),
        (dict(lod={"kind": "wobbly"}), "lod kind"),
        (dict(spacing="hexagonal", level=3.0), "unknown spacing"),
    ],
)
def test_bad_levels_are_value_errors(kwargs, match):
    v, f, n = icosphere()
    with pytest.raises(ValueError, match=match):
        tessella.refine(v, f, n, **kwargs)


def test_tags_origins_and_displacement_take_the_levels_the_core_takes_them_with():
    """What the core refines, Python asks for: tags with a tessellator spacing (a sharp PNG1
    crease moves the surface, the triangles stay), origins of a displaced grid refinement (the
    same vertices as without origins, each vertex's origin on its coarse face)."""
    v, f, n = icosphere()
    sharp = {"edges": [{"vertices": [int(f[0][0]), int(f[0][1])], "sharpness": 1.0, "kappa": 0.05}]}
    plain = tessella.refine(v, f, n, scheme="png1", spacing="equal", level=3, backend="cpu")
    tagged = tessella.refine(v, f, n, scheme="png1", spacing="equal", level=3, tags=sharp, backend="cpu")
    assert np.array_equal(plain.faces, tagged.faces)
    assert np.abs(tagged.vertices - plain.vertices).max() > 1e-4
    wave = ("sine", 0.05, 3.0)
    displaced = tessella.refine(v, f, n, level=3, displace=wave, backend="cpu")
    with_origin = tessella.refine(v, f, n, level=3, displace=wave, origin=True, backend="cpu")
    assert np.array_equal(displaced.vertices, with_origin.vertices)
    face, bary = with_origin.origin
    assert face.min() >= 0 and np.allclose(bary.sum(axis=1), 1.0)
