"""Texture coordinates (``uvs=``): interpolated linearly over each coarse triangle, checked in
f64 against the coarse uvs and each refined vertex's barycentrics (the result's ``origin``, or
the refinement pattern for unwelded output); carried from and to mesh objects and files."""

from __future__ import annotations

import meshio
import numpy as np
import pytest
import pyvista
import trimesh

import tessella
from conftest import icosphere


def _mesh():
    v, f = icosphere(1)
    # Spherical angles as texture coordinates: smooth, distinct per vertex, not linear in xyz.
    uv = np.stack([np.arctan2(v[:, 1], v[:, 0]), np.arccos(np.clip(v[:, 2], -1, 1))], axis=1)
    return v, f, uv.astype(np.float64)


def _expected(uv, faces, face, bary):
    """Each vertex's uv from its coarse triangle's corner uvs, in f64."""
    corners = np.asarray(uv, dtype=np.float64)[np.asarray(faces)[face]]  # (N, 3, 2)
    return np.einsum("nk,nkc->nc", np.asarray(bary, dtype=np.float64), corners)


@pytest.mark.parametrize("scheme", ["pn", "phong", "png1"])
def test_welded_uvs_follow_origin_barycentrics(scheme):
    v, f, uv = _mesh()
    r = tessella.refine(v, f, v, scheme=scheme, level=5, origin=True, uvs=uv)
    assert r.uvs.shape == (len(r.vertices), 2) and r.uvs.dtype == np.float32
    face, bary = r.origin
    assert (face >= 0).all()
    np.testing.assert_allclose(r.uvs, _expected(uv, f, face, bary), atol=2e-6)
    np.testing.assert_array_equal(r.uvs[: len(v)], uv.astype(np.float32))  # coarse vertices kept


def test_unwelded_uvs_follow_the_pattern():
    v, f, uv = _mesh()
    level = 4
    r = tessella.refine(v, f, v, scheme="pn", level=level, weld=False, uvs=uv, backend="cpu")
    bary, _ = tessella.pattern(level)  # every face's vertices follow the pattern's order
    face = np.repeat(np.arange(len(f)), len(bary))
    np.testing.assert_allclose(r.uvs, _expected(uv, f, face, np.tile(bary, (len(f), 1))), atol=2e-6)


def test_uvs_with_displacement_and_fields():
    v, f, uv = _mesh()
    d = tessella.refine(v, f, v, level=3, weld=False, uvs=uv, backend="cpu",
                        displace=tessella.Displace.sine(0.05, 3.0))
    bary, _ = tessella.pattern(3)
    face = np.repeat(np.arange(len(f)), len(bary))
    np.testing.assert_allclose(d.uvs, _expected(uv, f, face, np.tile(bary, (len(f), 1))), atol=2e-6)
    r = tessella.refine(v, f, v, level=3, uvs=uv, point_data={"z": v[:, 2]})
    np.testing.assert_allclose(r.uvs, _expected(uv, f, r.face, r.bary), atol=2e-6)


def test_uvs_on_lod_levels():
    v, f, uv = _mesh()
    r = tessella.refine(v, f, v, lod=tessella.Lod.tolerance(1e-3), origin=True, uvs=uv)
    np.testing.assert_allclose(r.uvs, _expected(uv, f, r.face, r.bary), atol=2e-6)


def test_no_uvs_gives_none():
    v, f, _ = _mesh()
    assert tessella.refine(v, f, level=2).uvs is None
    assert "uvs" not in repr(tessella.refine(v, f, level=2))


def test_bad_uvs_are_mesh_errors():
    v, f, uv = _mesh()
    with pytest.raises(tessella.MeshError, match=r"uvs must have shape \(n, 2\)"):
        tessella.refine(v, f, uvs=np.zeros((len(v), 3)))
    with pytest.raises(tessella.MeshError, match="uvs"):
        tessella.refine(v, f, uvs=uv[:-1])
    bad = uv.copy()
    bad[3, 1] = np.nan
    with pytest.raises(tessella.MeshError):
        tessella.refine(v, f, uvs=bad)
    with pytest.raises(TypeError, match="real numbers"):
        tessella.refine(v, f, uvs=np.full((len(v), 2), "a"))
    with pytest.raises(tessella.OptionError, match=r"uvs= cannot be combined with backend='gl'"):
        tessella.refine(v, f, uvs=uv, spacing="equal", backend="gl")


def _check(r, uv, f):
    np.testing.assert_allclose(r.uvs, _expected(uv, f, r.face, r.bary), atol=2e-6)


def test_uvs_from_trimesh():
    v, f, uv = _mesh()
    m = trimesh.Trimesh(v, f, process=False, visual=trimesh.visual.TextureVisuals(uv=uv))
    _check(tessella.refine(m, level=3, origin=True), uv, f)


def test_uvs_from_pyvista():
    v, f, uv = _mesh()
    m = pyvista.PolyData(v.astype(np.float64), np.hstack([np.full((len(f), 1), 3), f]).ravel())
    m.active_texture_coordinates = uv
    _check(tessella.refine(m, level=3, origin=True), uv, f)


def test_uvs_from_meshio():
    v, f, uv = _mesh()
    m = meshio.Mesh(v, [("triangle", f)], point_data={"uv": uv})
    r = tessella.refine(m, level=3, origin=True)
    _check(r, uv, f)
    assert "uv" not in r.point_data  # taken as uvs, not as a field


def test_uvs_round_trip_through_converters_and_files(tmp_path):
    v, f, uv = _mesh()
    r = tessella.refine(v, f, v, level=3, uvs=uv)
    np.testing.assert_array_equal(np.asarray(r.to_trimesh().visual.uv), r.uvs)
    np.testing.assert_array_equal(np.asarray(r.to_pyvista().active_texture_coordinates), r.uvs)
    np.testing.assert_array_equal(r.to_meshio().point_data["uv"], r.uvs)
    back = tessella.refine(r.to_pyvista(), scheme="flat", level=1)  # flat level 1: vertices kept
    np.testing.assert_array_equal(back.uvs, r.uvs)
    r.save(tmp_path / "m.obj")
    vt = [line.split()[1:3] for line in (tmp_path / "m.obj").read_text().splitlines() if line.startswith("vt ")]
    np.testing.assert_allclose(np.array(vt, dtype=np.float64), r.uvs, atol=1e-6)
    r.save(tmp_path / "m.vtu")
    np.testing.assert_allclose(meshio.read(tmp_path / "m.vtu").point_data["uv"], r.uvs)


def test_uvs_on_six_node_faces_follow_the_corners():
    from test_fields import icosphere_p2

    v, f6 = icosphere_p2()
    uv = np.stack([v[:, 0] * 0.5 + 0.5, v[:, 1] ** 2], axis=1)  # mid nodes' uvs unused
    r = tessella.refine(v, f6, level=4, uvs=uv)
    assert len(r.uvs) == len(r.vertices)  # mid-edge nodes dropped from both
    np.testing.assert_allclose(r.uvs, _expected(uv, f6[:, :3], r.face, r.bary), atol=2e-6)
