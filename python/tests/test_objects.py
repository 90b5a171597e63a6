"""Round trips through trimesh, PyVista and meshio keep vertices, faces, normals and fields,
and their mesh objects are accepted as input with their point and cell data."""

import numpy as np
import pytest

import tessella
from conftest import icosphere


@pytest.fixture
def refined():
    v, f = icosphere(1)
    temperature = v[:, 2].astype(np.float64)  # linear: exactly carried by the linear basis
    velocity = np.column_stack([v[:, 1], -v[:, 0], np.zeros(len(v))])
    region = np.arange(len(f)) % 3
    return tessella.refine(
        v, f, v, scheme="pn", level=3,
        point_data={"temperature": temperature, "velocity": velocity},
        cell_data={"region": region},
    )


def back_through(r, obj):
    """The object refined with flat level 1 (the identity: welded output starts with the input
    vertices unchanged, the input triangles, the given normals normalised)."""
    return tessella.refine(obj, scheme="flat", level=1)


def assert_same(a, r):
    np.testing.assert_array_equal(a.vertices, r.vertices)
    np.testing.assert_array_equal(a.faces, r.faces)
    np.testing.assert_allclose(a.normals, r.normals, atol=1e-6)
    assert set(a.point_data) == set(r.point_data) and set(a.cell_data) == set(r.cell_data)
    for k in r.point_data:
        np.testing.assert_allclose(a.point_data[k], r.point_data[k], atol=1e-6)
    for k in r.cell_data:
        np.testing.assert_array_equal(a.cell_data[k], r.cell_data[k])


def test_refined_fields_are_the_fields_at_the_refined_points(refined):
    # Independent check of what the round trips carry: the linear fields of the coarse
    # vertices, evaluated by barycentrics of each refined vertex on its coarse (flat) face.
    v, f = icosphere(1)
    face, bary = refined.origin
    flat = np.einsum("ij,ijk->ik", bary, v[f[face]].astype(np.float64))
    np.testing.assert_allclose(refined.point_data["temperature"], flat[:, 2], atol=1e-6)
    assert refined.cell_data["region"].shape == (len(refined.faces),)


def test_trimesh_round_trip(refined):
    mesh = refined.to_trimesh()
    assert len(mesh.vertices) == len(refined.vertices)
    assert_same(back_through(refined, mesh), refined)


def test_pyvista_round_trip(refined):
    grid = refined.to_pyvista()
    assert grid.n_points == len(refined.vertices) and grid.n_cells == len(refined.faces)
    np.testing.assert_array_equal(grid.point_data["velocity"], refined.point_data["velocity"])
    assert_same(back_through(refined, grid), refined)


def test_pyvista_unstructured_grid_gives_its_surface():
    pv = pytest.importorskip("pyvista")
    v, f = icosphere(0)
    r = tessella.RefinedMesh(v, f.astype(np.uint32), v, point_data={"s": v[:, 0]})
    grid = r.to_pyvista().cast_to_unstructured_grid()
    assert isinstance(grid, pv.UnstructuredGrid)
    a = tessella.refine(grid, scheme="flat", level=1)
    # Surface extraction may renumber points: compare as sets of triangles by position.
    key = lambda vv, ff: sorted(tuple(sorted(map(tuple, np.round(vv[t], 6)))) for t in ff)  # noqa: E731
    assert key(a.vertices, a.faces) == key(v, f)
    np.testing.assert_allclose(a.point_data["s"], a.vertices[:, 0], atol=1e-6)


def test_meshio_round_trip(refined, tmp_path):
    mesh = refined.to_meshio()
    assert_same(back_through(refined, mesh), refined)
    # And through a file: save() picks meshio for .vtu.
    path = tmp_path / "r.vtu"
    refined.save(path)
    import meshio

    assert_same(back_through(refined, meshio.read(path)), refined)


def test_save_uses_tessellas_writers_for_mesh_formats(refined, tmp_path):
    path = tmp_path / "r.ply"
    refined.save(path)
    v, f, n = tessella.load(path)
    np.testing.assert_array_equal(v, refined.vertices)
    np.testing.assert_array_equal(f, refined.faces)


def test_plot_colours_a_fem_field_off_screen(refined, tmp_path):
    pytest.importorskip("pyvista")
    png = tmp_path / "t.png"
    image = tessella.plot(refined, scalars="temperature", off_screen=True, screenshot=png, window_size=(240, 180))
    assert image.shape == (180, 240, 3) and png.stat().st_size > 0
    plain = tessella.plot(refined, off_screen=True, window_size=(240, 180), color="white")
    # Coloured by a field varying over the sphere: many distinct colours, unlike plain white.
    def colours(img):
        return len(np.unique(img.reshape(-1, 3) // 16, axis=0))
    assert colours(image) > colours(plain) + 10
    # The field named is the one drawn: the 3-valued cell field gives another picture.
    region = tessella.plot(refined, scalars="region", off_screen=True, window_size=(240, 180))
    assert not np.array_equal(region, image)
    with pytest.raises(tessella.OptionError, match="pressure.*temperature"):
        tessella.plot(refined, scalars="pressure", off_screen=True)
