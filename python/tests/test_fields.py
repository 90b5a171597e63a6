"""Second-order faces and solution fields through tessella.refine, read_fem and write_fem.

Independent references: the 6-node shape functions written out here in float64, analytic
fields, and meshio reading back what write_fem wrote."""

import numpy as np
import pytest

import tessella

meshio = pytest.importorskip("meshio")


def icosphere_p2(curved=True):
    """A P2 octahedron-sphere: corners on the unit sphere, one mid node per edge (shared)."""
    v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    f = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    )
    pts, mid, rows = list(v), {}, []
    for t in f:
        row = list(t)
        for k in range(3):
            a, b = sorted((t[k], t[(k + 1) % 3]))
            if (a, b) not in mid:
                m = (v[a] + v[b]) / 2
                pts.append(m / np.linalg.norm(m) if curved else m)
                mid[(a, b)] = len(pts) - 1
            row.append(mid[(a, b)])
        rows.append(row)
    return np.array(pts), np.array(rows)


def shape6(l):
    a, b, c = l.T
    return np.stack([a * (2 * a - 1), b * (2 * b - 1), c * (2 * c - 1), 4 * a * b, 4 * b * c, 4 * c * a], 1)


def test_p2_surface_matches_the_six_node_map_and_hits_the_sphere_nodes():
    v, f6 = icosphere_p2()
    r = tessella.refine(v, f6, level=6, backend="cpu")
    assert isinstance(r, tessella.RefineResult)
    assert r.face.min() >= 0  # the mid-edge nodes are dropped
    nodes = v[f6[r.face]]  # (N, 6, 3)
    want = np.einsum("nk,nkd->nd", shape6(r.bary.astype(np.float64)), nodes)
    assert np.abs(r.vertices - want).max() <= 1e-6 * np.ptp(v, axis=0).max() * np.sqrt(3)
    # Nodes are hit: every refined vertex at an element node lies on the unit sphere.
    at_node = np.isin(np.round(r.bary * 2, 6), [0, 1, 2]).all(axis=1)
    assert at_node.sum() > 0
    np.testing.assert_allclose(np.linalg.norm(r.vertices[at_node], axis=1), 1, atol=1e-6)
    # Far closer to the sphere than the flat octahedron.
    flat = tessella.refine(v[:6], f6[:, :3], scheme="flat", level=6, backend="cpu")[0]
    assert np.abs(np.linalg.norm(r.vertices, axis=1) - 1).max() < 0.3 * np.abs(np.linalg.norm(flat, axis=1) - 1).max()


def test_fields_linear_on_p1_and_quadratic_on_p2_are_exact():
    v, f6 = icosphere_p2(curved=False)
    T = lambda p: p[:, 0] ** 2 - 2 * p[:, 1] * p[:, 2] + 0.5 * p[:, 2] + 1  # noqa: E731
    L = lambda p: np.stack([2 * p[:, 0] - p[:, 1] + 3, p[:, 2]], 1)  # noqa: E731
    r = tessella.refine(v, f6, level=5, backend="cpu", point_data={"T": T(v), "L": L(v)})
    np.testing.assert_allclose(r.point_data["T"], T(r.vertices.astype(np.float64)), atol=3e-6)
    assert r.point_data["T"].shape == (len(r.vertices),)
    np.testing.assert_allclose(r.point_data["L"], L(r.vertices.astype(np.float64)), atol=3e-6)
    # Linear elements: a linear field is exact, the quadratic one is not.
    r1 = tessella.refine(v[:6], f6[:, :3], scheme="flat", level=5, point_data={"T": T(v[:6]), "L": L(v[:6])})
    np.testing.assert_allclose(r1.point_data["L"], L(r1.vertices.astype(np.float64)), atol=3e-6)
    assert np.abs(r1.point_data["T"] - T(r1.vertices.astype(np.float64))).max() > 1e-2


def test_cell_data_and_warp():
    v, f6 = icosphere_p2()
    ids = np.arange(len(f6), dtype=float)
    r = tessella.refine(v, f6, level=3, weld=False, cell_data={"id": ids})
    np.testing.assert_array_equal(r.cell_data["id"], r.face[r.faces[:, 0]])
    # Warp by a displacement U = 0.5 * p (the sphere grows to radius 1 + 0.5 * 2 = 2 at scale 2).
    U = 0.5 * v
    w = tessella.refine(v, f6, level=4, point_data={"U": U}, warp="U", scale=2.0)
    np.testing.assert_allclose(np.linalg.norm(w.vertices[np.isin(np.round(w.bary * 2, 6), [0, 1, 2]).all(1)], axis=1), 2, atol=2e-6)
    with pytest.raises(ValueError, match="warp='T'"):
        tessella.refine(v, f6, point_data={"U": U}, warp="T")


def test_bad_second_order_input_and_fields_name_the_problem():
    v, f6 = icosphere_p2()
    with pytest.raises(ValueError, match="field 'T' has 5 rows"):
        tessella.refine(v, f6, point_data={"T": np.zeros(5)})
    bad = np.zeros(len(v))
    bad[7] = np.nan
    with pytest.raises(ValueError, match="field 'T' has the non-finite value nan at vertex 7"):
        tessella.refine(v, f6, point_data={"T": bad})
    with pytest.raises(ValueError, match="field 'id' has 3 rows, but the mesh has 8 faces"):
        tessella.refine(v, f6, cell_data={"id": np.zeros(3)})
    # Neighbours naming different mid nodes at different places.
    v2 = np.vstack([v, [[3.0, 3.0, 3.0]]])
    f2 = f6.copy()
    f2[0, 3] = len(v)
    with pytest.raises(ValueError, match=r"faces \d+ and \d+ share the edge"):
        tessella.refine(v2, f2)
    # An inverted element: a mid node pulled across its triangle.
    v3 = v.copy()
    a, b, c = v[f6[2, :3]]
    v3[f6[2, 3]] = (a + b) / 2 + 3 * (c - (a + b) / 2)
    with pytest.raises(ValueError, match="second-order face 2 is inverted"):
        tessella.refine(v3, f6)


def test_write_fem_read_fem_round_trip_with_fields(tmp_path):
    v, f6 = icosphere_p2()
    T = v[:, 2] ** 2
    r = tessella.refine(v, f6, level=4, point_data={"T": T, "U": v}, cell_data={"id": np.arange(8.0)})
    for ext in ("vtu", "xdmf"):
        if ext == "xdmf":
            pytest.importorskip("h5py")  # meshio's XDMF writer imports it
        path = tmp_path / f"out.{ext}"
        tessella.write_fem(path, r.vertices, r.faces, r.normals, point_data=r.point_data, cell_data=r.cell_data)
        m = meshio.read(str(path))
        np.testing.assert_allclose(m.points, r.vertices, rtol=0, atol=1e-6)
        np.testing.assert_array_equal(m.cells_dict["triangle"], r.faces)
        np.testing.assert_allclose(np.ravel(m.point_data["T"]), r.point_data["T"], atol=1e-6)
        np.testing.assert_allclose(m.point_data["U"], r.point_data["U"], atol=1e-6)
        np.testing.assert_allclose(np.ravel(m.cell_data["id"][0]), r.cell_data["id"])
    # The coarse P2 mesh itself, written as triangle6 and read back with its fields.
    path = tmp_path / "p2.vtu"
    tessella.write_fem(path, v, f6, point_data={"T": T}, cell_data={"id": np.arange(8.0)})
    rv, rf, pd, cd = tessella.read_fem(path, fields=True)
    assert rf.shape == (8, 6)
    np.testing.assert_allclose(rv[rf], v[f6])
    np.testing.assert_allclose(pd["T"], T)
    np.testing.assert_allclose(cd["id"], np.arange(8.0))
    rv1, rf1 = tessella.read_fem(path, order=1)
    assert rf1.shape == (8, 3) and len(rv1) == 6


def test_read_fem_tetra10_boundary_is_second_order_and_outward(tmp_path):
    # One 10-node tetrahedron (VTK order: edges 01, 12, 02, 03, 13, 23), mid nodes bulged.
    c = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    mids = np.array([(c[i] + c[j]) / 2 for i, j in edges])
    centre = c.mean(0)
    mids += 0.1 * (mids - centre)
    pts = np.vstack([c, mids])
    temp = pts[:, 0] + 2 * pts[:, 1] ** 2
    path = tmp_path / "t10.vtu"
    meshio.write(str(path), meshio.Mesh(pts, [("tetra10", np.arange(10)[None])], point_data={"temp": temp}, cell_data={"k": [np.array([7.0])]}))
    v, f, pd, cd = tessella.read_fem(path, fields=True)
    assert f.shape == (4, 6)
    np.testing.assert_allclose(cd["k"], 7.0)
    # Each face's mid nodes are the mids of its own edges.
    for row in f:
        for k in range(3):
            a, b = v[row[k]], v[row[(k + 1) % 3]]
            np.testing.assert_allclose(v[row[3 + k]], (a + b) / 2 + 0.1 * ((a + b) / 2 - centre), atol=1e-12)
    r = tessella.refine(v, f, level=4, point_data=pd)
    # Outward: normals point away from the centre.
    assert (np.einsum("ij,ij->i", r.normals, r.vertices - centre) > 0).all()
    # The field is the P2 interpolant of temp, which is exact: temp is quadratic in l here?
    # (not in general: the geometry is curved), so compare with the shape functions directly.
    nodes_t = pd["temp"][f[r.face]]
    np.testing.assert_allclose(r.point_data["temp"], np.einsum("nk,nk->n", shape6(r.bary.astype(float)), nodes_t), atol=1e-5)
