"""trimesh in, trimesh out."""

import numpy as np
import pytest
import trimesh

import tessella
from conftest import icosphere


def test_refine_accepts_a_trimesh_and_converts_back():
    v, f = icosphere(1)
    mesh = trimesh.Trimesh(vertices=v.astype(np.float64), faces=f, process=False)
    result = tessella.refine(mesh, scheme="pn", level=4)
    assert isinstance(result, tessella.RefinedMesh)
    out = result.to_trimesh()
    assert isinstance(out, trimesh.Trimesh)
    rv, rf, rn = tessella.refine(v, f, scheme="pn", level=4)
    np.testing.assert_array_equal(out.vertices, rv)
    np.testing.assert_array_equal(out.faces, rf)
    np.testing.assert_allclose(out.vertex_normals, rn, atol=1e-6)
    assert out.is_watertight and out.is_winding_consistent
    # Refining toward the sphere increases the enclosed volume toward 4/3 pi.
    assert mesh.volume < out.volume < 4 / 3 * np.pi + 1e-3


def test_trimesh_normals_option():
    v, f = icosphere(1)
    mesh = trimesh.Trimesh(vertices=v, faces=f, process=False)
    a = tessella.refine_trimesh(mesh, normals="trimesh", level=3)
    b = tessella.refine(v, f, mesh.vertex_normals, level=3)
    np.testing.assert_array_equal(a.vertices, b[0])
    exact = tessella.refine_trimesh(mesh, normals=v, level=3)
    assert not np.array_equal(exact.vertices, a.vertices)  # the given normals are used
    with pytest.raises(ValueError, match="normals must be None, 'trimesh'"):
        tessella.refine_trimesh(mesh, normals="file")


def test_to_trimesh_keeps_vertex_order():
    v, f = icosphere(0)
    m = tessella.to_trimesh(v, f.astype(np.uint32))
    np.testing.assert_array_equal(m.vertices, v)
    assert m.faces.dtype == np.int64
