"""Refined surfaces checked against independent f64 evaluations of the papers' formulas."""

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh, icosphere, phong_points, pn_points, uniform_barycentrics


def soup_patches(v, f, n, level, **kw):
    """Refine without welding: face k's pattern points are rows k*P .. (k+1)*P."""
    rv, rf, rn = tessella.refine(v, f, n, level=level, weld=False, **kw)
    per = (level + 1) * (level + 2) // 2
    assert rv.shape == (len(f) * per, 3)
    assert rf.shape == (len(f) * level * level, 3)
    return rv.reshape(len(f), per, 3), rn.reshape(len(f), per, 3)


@pytest.mark.parametrize("level", [1, 2, 5])
def test_flat_points_are_the_pattern_mapped_onto_each_input_triangle(level):
    v, f, n = bumpy_mesh()
    pts, _ = soup_patches(v, f, n, level, scheme="flat")
    bary = uniform_barycentrics(level)
    for k, tri in enumerate(f):
        expected = bary @ v[tri].astype(np.float64)
        np.testing.assert_allclose(pts[k], expected, atol=2e-6)


@pytest.mark.parametrize("level", [3, 6])
def test_pn_matches_vlachos_formula_in_f64(level):
    v, f, n = bumpy_mesh()
    pts, _ = soup_patches(v, f, n, level, scheme="pn")
    bary = uniform_barycentrics(level)
    for k, tri in enumerate(f):
        np.testing.assert_allclose(pts[k], pn_points(v[tri], n[tri], bary), atol=2e-6)


@pytest.mark.parametrize("alpha", [0.0, 0.75, 1.0])
def test_phong_matches_boubekeur_alexa_formula_in_f64(alpha):
    v, f, n = bumpy_mesh(3)
    pts, _ = soup_patches(v, f, n, 4, scheme="phong", alpha=alpha)
    bary = uniform_barycentrics(4)
    for k, tri in enumerate(f):
        np.testing.assert_allclose(
            pts[k], phong_points(v[tri], n[tri], bary, alpha), atol=2e-6
        )


def test_welded_output_has_the_same_triangles_as_the_soup():
    v, f, n = bumpy_mesh()
    wv, wf, _ = tessella.refine(v, f, n, scheme="pn", level=4)
    sv, sf, _ = tessella.refine(v, f, n, scheme="pn", level=4, weld=False)
    assert len(wv) < len(sv)
    np.testing.assert_array_equal(wv[: len(v)], v)  # welded output starts with the input
    np.testing.assert_allclose(wv[wf], sv[sf], atol=1e-6)


def test_curved_schemes_are_closer_to_the_sphere_than_flat(sphere):
    v, f, n = sphere
    err = {}
    for scheme in ["flat", "phong", "pn"]:
        rv, rf, rn = tessella.refine(v, f, n, scheme=scheme, level=8)
        r = np.linalg.norm(rv.astype(np.float64), axis=1)
        err[scheme] = np.abs(r - 1).max()
        # Unit normals on output.
        np.testing.assert_allclose(np.linalg.norm(rn, axis=1), 1, atol=1e-5)
    assert err["flat"] > 0.05  # the coarse icosphere is far from round
    # Measured: flat 0.065, Phong (alpha 3/4) 0.023, PN 0.0094.
    assert err["phong"] < err["flat"] / 2
    assert err["pn"] < err["flat"] / 5


def test_closed_input_refines_to_a_closed_manifold(sphere):
    v, f, n = sphere
    rv, rf, rn = tessella.refine(v, f, n, scheme="pn", level=5)
    report = tessella.info(rv, rf, rn)
    assert report["closed_manifold"]
    assert report["euler_characteristic"] == 2
    assert report["faces"] == len(f) * 25


def test_pattern_is_the_documented_grid():
    for level in [1, 2, 7]:
        bary, tris = tessella.pattern(level)
        assert bary.dtype == np.float64 and tris.dtype == np.uint32
        np.testing.assert_array_equal(bary, uniform_barycentrics(level))
        assert tris.shape == (level * level, 3)
        # Every small triangle is counter-clockwise in the (l2, l3) plane; together they tile it.
        a, b, c = (bary[tris[:, k]] for k in range(3))
        area = 0.5 * ((b[:, 1] - a[:, 1]) * (c[:, 2] - a[:, 2]) - (b[:, 2] - a[:, 2]) * (c[:, 1] - a[:, 1]))
        assert (area > 0).all()
        assert abs(area.sum() - 0.5) < 1e-12


def test_normals_modes_differ_and_are_unit(sphere):
    v, f, n = sphere
    out = {m: tessella.refine(v, f, n, scheme="pn", level=4, normals_mode=m)[2] for m in ["linear", "quadratic", "real"]}
    for m, rn in out.items():
        np.testing.assert_allclose(np.linalg.norm(rn, axis=1), 1, atol=1e-5)
    assert not np.allclose(out["linear"], out["real"], atol=1e-4)
    # On a sphere the real surface normal is close to the radial direction.
    rv = tessella.refine(v, f, n, scheme="pn", level=4)[0]
    radial = rv / np.linalg.norm(rv, axis=1, keepdims=True)
    assert np.min(np.sum(out["real"] * radial, axis=1)) > 0.99


def test_info_counts_an_open_and_a_closed_mesh():
    v, f = icosphere(0)
    r = tessella.info(v, f)
    assert (r["vertices"], r["faces"], r["edges"]) == (12, 20, 30)
    assert r["closed_manifold"] and r["euler_characteristic"] == 2 and r["normals_computed"]
    r = tessella.info(v, f[:5])
    assert r["boundary_edges"] == 5 and not r["closed_manifold"]
    assert r["unreferenced_vertices"] == 12 - 6
