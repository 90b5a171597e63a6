"""The package's shape: one result type, typed options, typed exceptions, mesh objects of
trimesh / PyVista / meshio in and out."""

import numpy as np
import pytest

import tessella
from conftest import icosphere


def flat_square():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    f = np.array([[0, 1, 2], [0, 2, 3]])
    return v, f


# -- one result type ---------------------------------------------------------------------------

def test_every_call_form_returns_a_refined_mesh_that_unpacks_as_before():
    v, f = flat_square()
    plain = tessella.refine(v, f, scheme="flat", level=2)
    fields = tessella.refine(v, f, scheme="flat", level=2, point_data={"x": v[:, 0]})
    adaptive = tessella.refine(v, f, scheme="flat", level=2, origin=True)
    for r in (plain, fields, adaptive):
        assert isinstance(r, tessella.RefinedMesh)
        rv, rf, rn = r
        assert rv is r.vertices and rf is r.faces and rn is r.normals and r[0] is rv
        # level 2 on two flat triangles: 9 welded points of the unit square's 3x3 grid.
        assert sorted(map(tuple, np.round(rv[:, :2] * 2).astype(int))) == [(i, j) for i in range(3) for j in range(3)]
        assert len(rf) == 8
    assert plain.origin is None and plain.point_data == {}
    face, bary = adaptive.origin
    # Each vertex is its face's corners weighted by its barycentrics (the independent check).
    corners = v[f[face]]
    np.testing.assert_allclose(np.einsum("ij,ijk->ik", bary, corners), adaptive.vertices, atol=1e-6)
    # A linear field carried to the refined vertices is that function of their positions.
    np.testing.assert_allclose(fields.point_data["x"], fields.vertices[:, 0], atol=1e-6)
    assert tessella.RefineResult is tessella.RefinedMesh


# -- typed options -----------------------------------------------------------------------------

def test_typed_options_equal_their_string_and_dict_shorthands():
    v, f, n = icosphere(1), None, None
    v, f = v
    a = tessella.refine(v, f, v, lod=tessella.Lod.tolerance(1e-3))
    b = tessella.refine(v, f, v, lod="tolerance:0.001")
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)
    cam = tessella.Camera((0, 0, 4), (0, 0, 0), fov=40)
    a = tessella.refine(v, f, v, lod=tessella.Lod.screen(8, cam, (320, 240)))
    b = tessella.refine(v, f, v, lod="screen:8", camera=(0, 0, 4, 0, 0, 0, 40), size=(320, 240))
    np.testing.assert_array_equal(a.vertices, b.vertices)
    a = tessella.refine(v, f, v, lod=tessella.Lod.distance(1, 10, 6, cam))
    b = tessella.refine(v, f, v, lod={"kind": "distance", "near": 1, "far": 10, "max": 6}, camera=cam)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    d = tessella.Displace.perlin(0.05, 3.0, seed=7)
    a = tessella.refine(v, f, v, level=3, displace=d, backend="cpu")
    b = tessella.refine(v, f, v, level=3, displace=("perlin", 0.05, 3.0, 7), backend="cpu")
    np.testing.assert_array_equal(a.vertices, b.vertices)
    plain = tessella.refine(v, f, v, level=3, backend="cpu")
    assert not np.array_equal(a.vertices, plain.vertices)  # the displacement did something


def test_typed_options_validate_and_read_back_from_their_repr():
    cam = tessella.Camera((0, 0, 4), (0, 0, 0), 40)
    for option in (
        cam,
        tessella.Lod.tolerance(0.5),
        tessella.Lod.screen(8, cam, (10, 20)),
        tessella.Lod.distance(1.0, 5.0, 8.0, cam),
        tessella.Displace.sine(0.1, 2.0),
        tessella.Displace.perlin(0.1, 2.0, seed=3),
    ):
        again = eval(repr(option), {"Camera": tessella.Camera, "Lod": tessella.Lod, "Displace": tessella.Displace})
        assert again == option and repr(again) == repr(option)
    bad = [
        (lambda: tessella.Lod.tolerance(0), "greater than 0"),
        (lambda: tessella.Lod.tolerance(float("nan")), "finite"),
        (lambda: tessella.Lod.screen(8, cam, (0, 10)), "whole numbers of pixels"),
        (lambda: tessella.Lod.distance(5, 1, 8, cam), "near < far"),
        (lambda: tessella.Camera((0, 0, 0), (0, 0, 0)), "same point"),
        (lambda: tessella.Camera((0, 0), (0, 0, 1)), "3 numbers"),
        (lambda: tessella.Camera((0, 0, 1), (0, 0, 0), fov=180), "field of view"),
        (lambda: tessella.Displace.perlin(0.1, 1.0, seed=-1), "0..2\\*\\*32-1"),
        (lambda: tessella.Displace.sine(float("inf"), 1.0), "finite"),
    ]
    for make, match in bad:
        with pytest.raises(tessella.OptionError, match=match):
            make()


@pytest.mark.parametrize(
    "kwargs, a, b",
    [
        (dict(point_data={"t": np.zeros(4)}, lod="tolerance:0.1"), "point_data=", "lod="),
        (dict(point_data={"t": np.zeros(4)}, displace=("sine", 0.1, 1.0)), "point_data=", "displace="),
        (dict(lod="tolerance:0.1", displace=("sine", 0.1, 1.0)), "displace=", "lod="),
        (dict(spacing="equal", level=3, displace=("sine", 0.1, 1.0)), "displace=", "spacing="),
        (dict(level=2.5, displace=("sine", 0.1, 1.0)), "displace=", "a fractional level="),
        (dict(lod=tessella.Lod.tolerance(0.1), camera=(0, 0, 3, 0, 0, 0, 40)), "Lod.tolerance", "camera="),
        (dict(camera=(0, 0, 3, 0, 0, 0, 40)), "camera=", "lod="),
    ],
)
def test_conflicting_options_are_refused_in_one_style(kwargs, a, b):
    v, f = flat_square()
    with pytest.raises(tessella.OptionError) as info:
        tessella.refine(v, f, **kwargs)
    assert a in str(info.value) and b in str(info.value), str(info.value)


# -- exceptions --------------------------------------------------------------------------------

def test_exception_classes_keep_old_except_clauses_working():
    for cls in (tessella.MeshError, tessella.OptionError, tessella.FileFormatError, tessella.GpuError):
        assert issubclass(cls, tessella.TessellaError) and issubclass(cls, ValueError)
    assert issubclass(tessella.GpuError, RuntimeError)
    v, f = flat_square()
    cases = [
        (tessella.MeshError, dict(vertices=np.full((4, 3), np.nan), faces=f), "non-finite"),
        (tessella.MeshError, dict(vertices=v, faces=[[0, 1, 9]]), "9"),
        (tessella.MeshError, dict(vertices=v[:, :2], faces=f), r"shape \(n, 3\)"),
        (tessella.MeshError, dict(vertices=np.zeros((4, 3)), faces=f), "zero area|degenerate"),
        (tessella.OptionError, dict(vertices=v, faces=f, scheme="bezier"), "bezier"),
        (tessella.OptionError, dict(vertices=v, faces=f, level=0), "level"),
        (tessella.OptionError, dict(vertices=v, faces=f, displace={"kind": "wobble"}), "wobble"),
        (tessella.OptionError, dict(vertices=v, faces=f, scheme="st", tags={"vertices": [{"index": 99}]}), "99"),
    ]
    for cls, kwargs, match in cases:
        with pytest.raises(cls, match=match) as info:
            tessella.refine(**kwargs)
        assert info.value.message == str(info.value)
    with pytest.raises(tessella.MeshError, match="vertex count|vertices|topology"):
        tessella.Refiner(f, vertices=v).refine(np.zeros((3, 3)))
