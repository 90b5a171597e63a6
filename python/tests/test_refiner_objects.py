"""tessella.Refiner as a per-frame object: planned at construction, on the GPU when asked,
picklable, and the same in a `spawn` subprocess as in the parent."""

import multiprocessing
import pickle

import numpy as np
import pytest

import tessella
from conftest import icosphere


def frames(v, count=3):
    return [v * (1 + 0.1 * t) + 0.05 * t for t in range(count)]


def test_plans_at_construction_and_checks_up_front():
    v, f = icosphere(1)
    r = tessella.Refiner(f, vertices=v, normals=v, scheme="png1", level=4, backend="cpu")
    # Planned: the counts are known before any frame (icosphere(1): 42 + 120*3 + 80*3 = 642).
    assert r.vertex_count == 42 + 120 * 3 + 80 * 3 and r.faces is not None and r.backend == "cpu"
    with pytest.raises(tessella.MeshError, match="non-finite"):
        tessella.Refiner(f, vertices=np.full_like(v, np.nan))
    with pytest.raises(tessella.OptionError, match="99"):
        tessella.Refiner(f, vertices=v, scheme="st", tags={"vertices": [{"index": 99, "tension": 0.5}]})
    with pytest.raises(tessella.MeshError, match=r"\(n, 3\)"):
        tessella.Refiner(f[:, :2])


def test_gpu_frames_equal_the_cpu():
    if "gpu" not in tessella.backends():
        pytest.fail("no GPU adapter (a software one such as lavapipe is enough); see python/ci.sh")
    v, f = icosphere(1)
    gpu = tessella.Refiner(f, vertices=v, normals=v, scheme="pn", level=5, backend="gpu")
    assert gpu.backend == "gpu"
    out = (np.empty((gpu.vertex_count, 3), np.float32), np.empty((gpu.vertex_count, 3), np.float32))
    for frame in frames(v):
        want = tessella.refine(frame, f, v, scheme="pn", level=5, backend="cpu")
        gv, gf, gn = gpu.refine(frame, v, out=out)
        assert gv is out[0] and gn is out[1]
        np.testing.assert_array_equal(gf, want.faces)
        np.testing.assert_allclose(gv, want.vertices, atol=2e-6)
        np.testing.assert_allclose(gn, want.normals, atol=2e-6)


def test_pickle_rebuilds_the_plan():
    v, f = icosphere(1)
    r = tessella.Refiner(f, vertices=v, scheme="st", level=4, crease_angle=30.0, backend="cpu")
    again = pickle.loads(pickle.dumps(r))
    assert type(again) is tessella.Refiner and again.vertex_count == r.vertex_count
    for frame in frames(v):
        a, b = r.refine(frame), again.refine(frame)
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)
    # A refiner not yet planned pickles as its arguments.
    lazy = pickle.loads(pickle.dumps(tessella.Refiner(f, scheme="pn", level=3)))
    assert lazy.vertex_count is None
    np.testing.assert_array_equal(lazy.refine(v)[0], tessella.refine(v, f, scheme="pn", level=3).vertices)


def _refine_in_child(refiner, frame, normals):
    v, f, n = refiner.refine(frame, normals)
    return v, np.array(f), n


def test_spawn_subprocess_gives_the_parents_arrays():
    v, f = icosphere(1)
    r = tessella.Refiner(f, vertices=v, normals=v, scheme="png1", level=4, backend="cpu")
    frame = frames(v)[2]
    want = r.refine(frame, v)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        got = pool.apply(_refine_in_child, (r, frame, v))
    for x, y in zip(got, want):
        np.testing.assert_array_equal(x, y)


def _gpu_frame_in_child(refiner, frame, normals):
    return refiner.backend, refiner.refine(frame, normals)[0]


def test_a_gpu_refiner_reopens_the_gpu_in_a_spawn_subprocess():
    if "gpu" not in tessella.backends():
        pytest.fail("no GPU adapter (a software one such as lavapipe is enough); see python/ci.sh")
    v, f = icosphere(1)
    r = tessella.Refiner(f, vertices=v, normals=v, scheme="pn", level=5, backend="gpu")
    frame = frames(v)[1]
    want = r.refine(frame, v)[0]
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        backend, got = pool.apply(_gpu_frame_in_child, (r, frame, v))
    assert backend == "gpu"
    # The plan rebuilt and the GPU reopened there: the parent's vertices (to float rounding,
    # should the child open another adapter).
    np.testing.assert_allclose(got, want, atol=2e-6)
