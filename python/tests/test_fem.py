"""Finite-element meshes through meshio: boundary extraction, reading, writing."""

import meshio
import numpy as np
import pytest

import tessella


def cube_tets(n=2, seed=0):
    """A unit cube of n^3 small cubes, each split into 6 tetrahedra around its main diagonal
    (a conforming split); half of the tetrahedra get their node order reversed."""
    g = np.linspace(0, 1, n + 1)
    pts = np.array([[x, y, z] for z in g for y in g for x in g])
    idx = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i  # noqa: E731
    tets = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                c = [idx(i + a, j + b, k + d) for d in (0, 1) for b in (0, 1) for a in (0, 1)]
                # Corners c[0] = (0,0,0), c[7] = (1,1,1); the six paths from c0 to c7.
                for p, q in [(1, 3), (1, 5), (2, 3), (2, 6), (4, 5), (4, 6)]:
                    tets.append([c[0], c[p], c[q], c[7]])
    tets = np.array(tets)
    flip = np.random.default_rng(seed).random(len(tets)) < 0.5
    tets[flip] = tets[flip][:, [1, 0, 2, 3]]
    return pts, tets


def test_boundary_of_a_tet_cube_is_its_closed_outward_surface():
    pts, tets = cube_tets(2)
    faces = tessella.boundary_faces(pts, tets)
    assert faces.shape == (6 * 4 * 2, 3)  # 6 sides, 4 squares each, 2 triangles per square
    a, b, c = (pts[faces[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    outward = (a + b + c) / 3 - 0.5
    assert (np.einsum("ij,ij->i", normal, outward) > 0).all()
    report = tessella.info(pts, faces)
    assert report["closed_manifold"] and report["euler_characteristic"] == 2
    assert report["unreferenced_vertices"] == 1  # the cube's centre node


@pytest.mark.parametrize("ext", [".vtu", ".vtk", ".msh"])
def test_read_fem_refine_write_back(tmp_path, ext):
    pts, tets = cube_tets(2, seed=1)
    src = tmp_path / f"cube{ext}"
    kw = {"file_format": "gmsh22"} if ext == ".msh" else {}
    meshio.write(str(src), meshio.Mesh(pts, [("tetra", tets)]), **kw)
    v, f = tessella.read_fem(src)
    assert v.dtype == np.float64 and f.dtype == np.int64
    assert len(v) == 26 and len(f) == 48  # surface nodes only: 27 - the centre
    rv, rf, rn = tessella.refine(v, f, scheme="phong", level=3)
    out = tmp_path / f"refined{ext}"
    tessella.write_fem(out, rv, rf, rn, **kw)
    back = meshio.read(str(out))
    np.testing.assert_allclose(back.points, rv)
    np.testing.assert_array_equal(back.cells_dict["triangle"], rf)
    np.testing.assert_allclose(back.point_data["normals"], rn)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([src.name, out.name])


def test_read_fem_takes_triangles_and_second_order_cells(tmp_path):
    pts = np.array([[0, 0], [1, 0], [0, 1], [5, 5]], dtype=float)  # 2-D points, one unused
    path = tmp_path / "tri.vtu"
    meshio.write(str(path), meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2]])), ("vertex", np.array([[3]]))]))
    v, f = tessella.read_fem(path)
    np.testing.assert_array_equal(v, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_array_equal(f, [[0, 1, 2]])
    with pytest.raises(ValueError, match="has no tetrahedra"):
        tessella.read_fem(path, cells="tetra")
    # A 10-node tetrahedron: its four corners make the surface.
    p10 = np.vstack([np.eye(3), np.zeros((1, 3)), np.random.default_rng(0).random((6, 3))])
    path = tmp_path / "t10.vtu"
    meshio.write(str(path), meshio.Mesh(p10, [("tetra10", np.arange(10)[None])]))
    v, f = tessella.read_fem(path, order=1)
    assert len(v) == 4 and f.shape == (4, 3)
    # By default second-order cells keep their mid-edge nodes: 6-column faces.
    v, f = tessella.read_fem(path)
    assert len(v) == 10 and f.shape == (4, 6)


def test_fem_errors(tmp_path):
    with pytest.raises(OSError):
        tessella.read_fem(tmp_path / "missing.vtu")
    with pytest.raises(ValueError, match="cells must be"):
        tessella.read_fem(tmp_path / "x.vtu", cells="hex")
    with pytest.raises(ValueError, match=r"tets must have shape \(t, 4\)"):
        tessella.boundary_faces(np.zeros((4, 3)), np.array([[0, 1, 2]]))
    with pytest.raises(ValueError, match="tets use vertex indices"):
        tessella.boundary_faces(np.zeros((4, 3)), np.array([[0, 1, 2, 4]]))
    with pytest.raises(ValueError, match=r"vertices must have shape \(n, 3\)"):
        tessella.write_fem(tmp_path / "x.vtu", np.zeros((3, 2)), [[0, 1, 2]])
