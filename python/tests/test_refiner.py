"""tessella.Refiner: a deforming mesh refined frame after frame.

The reference for every frame is an independent call, ``tessella.refine`` on that frame's
vertices (a fresh mesh, topology and plan each time): the refiner must give the same arrays bit
for bit. Deformations are made here in numpy.
"""

import tracemalloc

import numpy as np
import pytest

import tessella
from conftest import icosphere

SCHEMES = ["flat", "phong", "pn", "png1", "pn-aen", "st"]


def twist(v, turns, scale=1.0):
    """Rotates each point about z by ``turns * z`` radians and scales it: a unit sphere stays a
    sphere of radius ``scale``, so its exact normals stay ``v / scale``."""
    v = np.asarray(v, dtype=np.float64)
    a = turns * v[:, 2]
    c, s = np.cos(a), np.sin(a)
    out = np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]], axis=1)
    return (scale * out).astype(np.float32)


def frames(v, count=4):
    """A deforming sequence: twisting more and growing, frame by frame."""
    return [twist(v, 0.4 * k, 1.0 + 0.15 * k) for k in range(count)]


def split_box():
    """A box whose corners are split per face (24 vertices, face normals): coincident vertices
    with different normals, what PN-AEN, PNG1 and "st" look across."""
    v, n, f = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            normal = np.zeros(3)
            normal[axis] = sign
            u, w = [(axis + 1) % 3, (axis + 2) % 3]
            base = len(v)
            for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                p = np.zeros(3)
                p[axis] = sign
                p[u], p[w] = a, b * 0.7
                v.append(p)
                n.append(normal)
            quad = [base, base + 1, base + 2, base + 3]
            if sign < 0:
                quad = quad[::-1]
            f += [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]
    return np.array(v, np.float32), np.array(f, np.int64), np.array(n, np.float32)


def assert_same(got, want):
    for g, w, name in zip(got, want, ("vertices", "faces", "normals")):
        assert g.shape == w.shape and g.dtype == w.dtype, name
        assert np.array_equal(g, w), f"{name} differ from tessella.refine's"


@pytest.mark.parametrize("weld", [True, False], ids=["welded", "soup"])
@pytest.mark.parametrize("scheme", SCHEMES)
def test_every_frame_equals_refine_of_that_frame(scheme, weld):
    v, f = icosphere(2)
    r = tessella.Refiner(f, scheme=scheme, level=5, weld=weld)
    for k, vk in enumerate(frames(v)):
        got = r.refine(vk)  # normals computed from each frame
        want = tessella.refine(vk, f, scheme=scheme, level=5, weld=weld, backend="cpu")
        assert_same(got, want)
        # The frames really deform: the refined surface moved from the first frame's.
        if k:
            assert not np.array_equal(got[0], first)
        else:
            first = got[0].copy()


@pytest.mark.parametrize("scheme", ["pn", "png1", "phong", "flat"])
def test_given_normals_and_out_arrays_equal_refine(scheme):
    v, f = icosphere(2)
    r = tessella.Refiner(f, scheme=scheme, level=7, normals_mode="quadratic" if scheme == "pn" else None)
    out = None
    for k, vk in enumerate(frames(v, 5)):
        nk = vk / (1.0 + 0.15 * k)  # the twisted sphere's exact normals
        want = tessella.refine(
            vk, f, nk, scheme=scheme, level=7, backend="cpu",
            normals_mode="quadratic" if scheme == "pn" else None,
        )
        if out is None:
            out = (np.full_like(want[0], np.nan), np.full_like(want[2], np.nan))
        got = r.refine(vk, nk, out=out)
        assert_same(got, want)


@pytest.mark.parametrize("scheme", ["pn-aen", "png1", "st", "pn"])
@pytest.mark.parametrize("weld", [True, False], ids=["welded", "soup"])
def test_split_normals_are_followed_across_frames(scheme, weld):
    # The box's corners are split; twisting moves coincident vertices together, so the plan's
    # shared positions (from the first frame) stay right and every frame matches a fresh refine.
    v, f, n = split_box()
    r = tessella.Refiner(f, scheme=scheme, level=4, weld=weld, crease_angle=60.0)
    # Mild twists: the edges bending over 60 degrees stay the same ones as in the first frame
    # (the creases are decided there; see the next test).
    for k in range(4):
        vk = twist(v, 0.08 * k, 1.0 + 0.1 * k)
        want = tessella.refine(vk, f, scheme=scheme, level=4, weld=weld, crease_angle=60.0,
                               backend="cpu")
        assert_same(r.refine(vk), want)


def test_crease_angle_creases_are_decided_by_the_first_frame():
    # A strong twist bends other edges of the box past 60 degrees: a refiner planned on the
    # untwisted box keeps its creases, one planned on the twisted box takes the new ones.
    v, f, _ = split_box()
    twisted = twist(v, 0.4, 1.2)
    want = tessella.refine(twisted, f, scheme="png1", level=4, crease_angle=60.0)
    planned_untwisted = tessella.Refiner(f, scheme="png1", level=4, crease_angle=60.0)
    planned_untwisted.refine(v)
    assert not np.array_equal(planned_untwisted.refine(twisted)[0], want[0])
    planned_twisted = tessella.Refiner(f, scheme="png1", level=4, crease_angle=60.0)
    assert_same(planned_twisted.refine(twisted), want)
    # Without crease_angle nothing depends on the first frame: both plans agree.
    a = tessella.Refiner(f, scheme="png1", level=4)
    a.refine(v)
    assert_same(a.refine(twisted), tessella.refine(twisted, f, scheme="png1", level=4))


def test_tags_are_applied_like_refine():
    v, f, n = split_box()
    tags = {"vertices": [{"index": 0, "tension": 0.5}, {"index": 6, "bias": 0.3}]}
    r = tessella.Refiner(f, scheme="st", level=6, tags=tags)
    untagged = tessella.Refiner(f, scheme="st", level=6)
    for k in range(3):
        vk = twist(v, 0.3 * k)
        got = r.refine(vk, n if k == 0 else None)
        want = tessella.refine(vk, f, n if k == 0 else None, scheme="st", level=6, tags=tags)
        assert_same(got, want)
        # The tags change the surface (so the comparison above sees them).
        assert not np.array_equal(got[0], untagged.refine(vk, n if k == 0 else None)[0])


def test_out_arrays_are_the_returned_arrays_and_faces_are_shared_read_only():
    v, f = icosphere(1)
    r = tessella.Refiner(f, scheme="pn", level=6)
    assert r.vertex_count is None and r.faces is None
    assert r.triangle_count == len(f) * 36 and r.level == 6 and r.scheme == "pn" and r.weld
    rv, rf, rn = r.refine(v)
    assert r.vertex_count == len(rv) == len(rn) and len(rf) == r.triangle_count
    assert rf is r.faces and rf.dtype == np.uint32 and not rf.flags.writeable
    with pytest.raises(ValueError):
        rf[0, 0] = 1
    out = (np.zeros_like(rv), np.zeros_like(rn))
    for k, vk in enumerate(frames(v, 3)):
        pv, pf, pn = r.refine(vk, out=out)
        assert pv is out[0] and pn is out[1] and pf is rf
        want = tessella.refine(vk, f, scheme="pn", level=6)
        assert np.array_equal(out[0], want[0]) and np.array_equal(out[1], want[2])
    # Without out=, fresh arrays each call (not the out arrays, not each other's).
    a, _, an = r.refine(v)
    b, _, bn = r.refine(v)
    assert not np.shares_memory(a, b) and not np.shares_memory(an, bn)
    assert not np.shares_memory(a, out[0])
    assert tessella.Refiner(f, scheme="PN_AEN").scheme == "pn-aen"


def test_out_frames_allocate_no_arrays():
    v, f = icosphere(3)
    r = tessella.Refiner(f, scheme="pn", level=8)
    rv, _, rn = r.refine(v)
    out = (np.empty_like(rv), np.empty_like(rn))
    seq = frames(v, 20)
    one_array = rv.nbytes  # numpy reports its data allocations to tracemalloc

    def peak_growth(use_out):
        tracemalloc.start()
        try:
            base = tracemalloc.get_traced_memory()[0]
            tracemalloc.reset_peak()
            for vk in seq:
                r.refine(vk, out=out if use_out else None)
            return tracemalloc.get_traced_memory()[1] - base
        finally:
            tracemalloc.stop()

    # The measurement sees new arrays: without out= each frame makes two of them.
    assert peak_growth(False) >= 2 * one_array
    # With out= no frame makes one (a few small Python objects at most).
    assert peak_growth(True) < one_array // 20
    pointers = (out[0].__array_interface__["data"][0], out[1].__array_interface__["data"][0])
    pv, _, pn = r.refine(seq[3], out=out)
    assert (pv.__array_interface__["data"][0], pn.__array_interface__["data"][0]) == pointers


def _bad_frames(v, f):
    nan = v.copy()
    nan[5, 1] = np.nan
    inf = v.copy()
    inf[2, 0] = np.inf
    flat = v.copy()
    flat[f[0, 1]] = flat[f[0, 0]]  # a zero-area triangle
    zero_normals = v.copy()
    zero_normals[7] = 0.0
    return {
        "fewer vertices": (v[:-1], None, "vert"),
        "more vertices": (np.vstack([v, v[:1]]), None, "vert"),
        "NaN position": (nan, None, "finite|NaN|nan"),
        "infinite position": (inf, None, "finite|inf"),
        "zero-area triangle": (flat, None, "area|degenerate"),
        "zero normal": (v, zero_normals, "normal"),
        "fewer normals": (v, v[:-2], "normal"),
        "bad shape": (v[:, :2], None, r"\(n, 3\)"),
    }


@pytest.mark.parametrize("case", list(_bad_frames(*icosphere(1))))
def test_a_bad_frame_raises_and_changes_nothing(case):
    v, f = icosphere(1)
    vertices, normals, message = _bad_frames(v, f)[case]
    r = tessella.Refiner(f, scheme="png1", level=4)
    good = twist(v, 0.5, 1.3)
    rv, rf, rn = r.refine(good)
    out = (np.full_like(rv, 7.0), np.full_like(rn, -3.0))
    r.refine(good, out=out)
    before = (out[0].copy(), out[1].copy())
    with pytest.raises(ValueError, match=message):
        r.refine(vertices, normals, out=out)
    assert np.array_equal(out[0], before[0]) and np.array_equal(out[1], before[1])
    # tessella.refine refuses the same frame with the same exception type.
    if case not in ("fewer vertices", "more vertices"):
        with pytest.raises(ValueError):
            tessella.refine(vertices, f, normals, scheme="png1", level=4)
    # The refiner still refines: the next good frame is right.
    nxt = twist(v, -0.3, 0.8)
    assert_same(r.refine(nxt, out=out), tessella.refine(nxt, f, scheme="png1", level=4))


def test_a_bad_first_frame_builds_nothing():
    v, f = icosphere(1)
    r = tessella.Refiner(f, level=3)
    bad = v.copy()
    bad[0] = np.nan
    with pytest.raises(ValueError):
        r.refine(bad)
    assert r.vertex_count is None and r.faces is None
    with pytest.raises(ValueError, match="vertex|index|range"):
        r.refine(v[:5])  # faces name vertices this frame lacks
    assert r.vertex_count is None
    assert_same(r.refine(v), tessella.refine(v, f, level=3))


def _out_cases(rv):
    n = len(rv)
    big = np.zeros((2 * n, 3), np.float32)
    readonly = np.zeros_like(rv)
    readonly.flags.writeable = False
    shared = np.zeros_like(rv)
    return {
        "float64": ((rv.astype(np.float64), np.zeros_like(rv)), "float32"),
        "wrong rows": ((np.zeros((n - 1, 3), np.float32), np.zeros_like(rv)), "shape"),
        "wrong columns": ((np.zeros_like(rv), np.zeros((n, 4), np.float32)), "shape|float32"),
        "one-dimensional": ((np.zeros(3 * n, np.float32), np.zeros_like(rv)), "float32|shape"),
        "strided": ((big[::2], np.zeros_like(rv)), "contiguous"),
        "fortran order": ((np.asfortranarray(np.zeros_like(rv)), np.zeros_like(rv)), "contiguous"),
        "read-only": ((np.zeros_like(rv), readonly), "read-only"),
        "same array twice": ((shared, shared), "memory|separate"),
        "a list": ([np.zeros_like(rv), np.zeros_like(rv)], "tuple"),
        "three arrays": ((np.zeros_like(rv),) * 3, "tuple"),
        "not an array": ((rv.tolist(), np.zeros_like(rv)), "float32"),
    }


@pytest.mark.parametrize("case", list(_out_cases(np.zeros((10, 3), np.float32))))
def test_bad_out_arrays_raise_and_change_nothing(case):
    v, f = icosphere(1)
    r = tessella.Refiner(f, scheme="pn", level=4)
    rv, _, rn = r.refine(v)
    arrays, message = _out_cases(rv)[case]
    snapshot = [np.array(a, copy=True) for a in arrays]
    moved = twist(v, 0.7, 1.5)
    with pytest.raises(ValueError, match=message):
        r.refine(moved, out=arrays)
    for a, s in zip(arrays, snapshot):
        assert np.array_equal(np.asarray(a), s)
    # The refused call did not move the frame either: a call without out= still refines the
    # frame it is given, and matches refine.
    assert_same(r.refine(moved), tessella.refine(moved, f, scheme="pn", level=4))


def test_constructor_checks_options_like_refine():
    _, f = icosphere(0)
    with pytest.raises(ValueError, match="scheme"):
        tessella.Refiner(f, scheme="bezier")
    with pytest.raises(ValueError, match="level"):
        tessella.Refiner(f, level=0)
    with pytest.raises(ValueError, match="alpha"):
        tessella.Refiner(f, scheme="phong", alpha=float("nan"))
    with pytest.raises(ValueError, match="normals_mode"):
        tessella.Refiner(f, normals_mode="cubic")
    with pytest.raises(ValueError, match="backend"):
        tessella.Refiner(f, backend="tpu")
    with pytest.raises(ValueError, match="gl"):
        tessella.Refiner(f, backend="gl")
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        tessella.Refiner(f[:, :2])
    with pytest.raises(TypeError):
        tessella.Refiner(f.astype(np.float32))
    with pytest.raises(TypeError):
        tessella.Refiner(f, tags=3.5)
    with pytest.raises(TypeError):
        tessella.Refiner(f, displace=("sine", 0.1, 1.0))
    assert tessella.Refiner(f, backend="AUTO").level == 8


def test_bad_tags_are_refused_by_the_first_frame():
    v, f = icosphere(0)
    r = tessella.Refiner(f, scheme="st", tags={"vertices": [{"index": 99, "tension": 0.5}]})
    with pytest.raises(ValueError, match="99"):
        r.refine(v)
    with pytest.raises(ValueError, match="99"):
        tessella.refine(v, f, scheme="st", tags={"vertices": [{"index": 99, "tension": 0.5}]})
    assert r.vertex_count is None
