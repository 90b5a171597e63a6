"""Fields a mesh object brings along are never dropped silently: options that take no fields
refuse them (one OptionError, naming the fields), and ``origin=True`` carries them."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import tessella
from conftest import icosphere


def _object():
    v, f = icosphere(1)
    m = trimesh.Trimesh(v, f, process=False)
    m.vertex_attributes["temperature"] = v[:, 2].astype(np.float64) * 10.0
    return m, v, f


@pytest.mark.parametrize(
    "options, named",
    [
        ({"tags": {"edges": []}, "scheme": "st"}, "tags="),
        ({"crease_angle": 30.0}, "crease_angle="),
        ({"displace": tessella.Displace.sine(0.1, 2.0)}, "displace="),
        ({"lod": tessella.Lod.tolerance(1e-3)}, "lod="),
        ({"spacing": "equal", "level": 4.0}, "spacing="),
    ],
)
def test_object_fields_with_options_that_take_none_are_refused(options, named):
    m, _, _ = _object()
    with pytest.raises(tessella.OptionError) as e:
        tessella.refine(m, **options)
    msg = str(e.value)
    assert msg.startswith("refine(): the Trimesh's point/cell data ['temperature'] cannot be combined with " + named)
    assert "without its fields" in msg


def test_object_fields_come_along_with_origin():
    m, v, f = _object()
    r = tessella.refine(m, level=4, origin=True)
    # Linear on 3-node faces: the coarse values weighted by each vertex's barycentrics (f64).
    expected = np.einsum("nk,nk->n", r.bary.astype(np.float64), (v[:, 2].astype(np.float64) * 10.0)[f[r.face]])
    np.testing.assert_allclose(r.point_data["temperature"], expected, atol=1e-5)


def test_object_arrays_without_fields_take_the_options():
    m, v, f = _object()
    r = tessella.refine(np.asarray(m.vertices), np.asarray(m.faces), crease_angle=30.0, level=2)
    assert r.point_data == {} and len(r.faces) == 4 * len(f)
