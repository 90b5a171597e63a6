"""dtype/order variants give identical results; bad input raises the documented exceptions."""

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh


@pytest.fixture(scope="module")
def reference():
    v, f, n = bumpy_mesh()
    return (v, f, n), tessella.refine(v, f, n, scheme="pn", level=3)


@pytest.mark.parametrize("vdtype", [np.float32, np.float64])
@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32, np.uint64, np.int16])
@pytest.mark.parametrize("order", ["C", "F"])
def test_dtype_and_order_variants_give_identical_results(reference, vdtype, fdtype, order):
    (v, f, n), expected = reference
    # float32 values upcast to float64 are exact, so the results must be bit-identical.
    args = (
        np.asarray(v, dtype=vdtype, order=order),
        np.asarray(f, dtype=fdtype, order=order),
        np.asarray(n, dtype=vdtype, order=order),
    )
    assert args[0].flags.f_contiguous == (order == "F")
    got = tessella.refine(*args, scheme="pn", level=3)
    for g, e in zip(got, expected):
        assert g.flags.c_contiguous
        np.testing.assert_array_equal(g, e)
    assert got[0].dtype == np.float32 and got[1].dtype == np.uint32 and got[2].dtype == np.float32


def test_strided_views_and_lists_are_accepted(reference):
    (v, f, n), expected = reference
    wide = np.zeros((len(v), 6), dtype=np.float64)
    wide[:, ::2] = v  # every other column: a non-contiguous view
    got = tessella.refine(wide[:, ::2], f.tolist(), n.tolist(), scheme="pn", level=3)
    for g, e in zip(got, expected):
        np.testing.assert_array_equal(g, e)


def test_integer_points_are_converted():
    v = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0]], dtype=np.int64)
    a = tessella.refine(v, [[0, 1, 2]], [[0, 0, 1]] * 3, scheme="pn", level=3)
    b = tessella.refine(v.astype(np.float32), [[0, 1, 2]], scheme="pn", level=3)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


def test_float64_input_is_rounded_to_float32():
    v = np.array([[0, 0, 0], [1 + 1e-12, 0, 0], [0, 1, 0]], dtype=np.float64)
    rv, _, _ = tessella.refine(v, [[0, 1, 2]], scheme="flat", level=1)
    assert rv[1, 0] == np.float32(1.0)


def tri():
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64), np.array([[0, 1, 2]])


@pytest.mark.parametrize(
    "change, exc, message",
    [
        (lambda v, f: (v[:, :2], f), ValueError, r"vertices must have shape \(n, 3\), got \(3, 2\)"),
        (lambda v, f: (v.ravel(), f), ValueError, r"vertices must have shape \(n, 3\), got \(9,\)"),
        (lambda v, f: (v, f.ravel()), ValueError, r"faces must have shape \(n, 3\)"),
        (lambda v, f: (v, f + 1), ValueError, r"triangle 0 uses vertex 3, but the mesh has only 3"),
        (lambda v, f: (v, -f), ValueError, r"faces\[0, 1\] = -1 is not a vertex index"),
        (lambda v, f: (v, f * 2**33), ValueError, r"is not a vertex index"),
        (lambda v, f: (np.where(v == 1, np.nan, v), f), ValueError, r"non-finite coordinate"),
        (lambda v, f: (v * [1, 0, 0], f), ValueError, r"zero area"),
        (lambda v, f: (v, [[0, 1, 1]]), ValueError, r"uses vertex 1 twice"),
        (lambda v, f: (v, f[:0]), ValueError, r"no triangles"),
        (lambda v, f: (v.astype(np.complex128), f), TypeError, r"float32 or float64 \(or integers\), got dtype complex128"),
        (lambda v, f: (v.astype(np.float16), f), TypeError, r"float32 or float64"),
        (lambda v, f: (v.astype(bool), f), TypeError, r"float32 or float64"),
        (lambda v, f: (v, f.astype(np.float64)), TypeError, r"faces must hold integers"),
        (lambda v, f: (["a", "b", "c"], f), ValueError, r"vertices must have shape"),
    ],
)
def test_bad_arrays_raise_clear_errors(change, exc, message):
    v, f = change(*tri())
    with pytest.raises(exc, match=message):
        tessella.refine(v, f)


@pytest.mark.parametrize(
    "kwargs, exc, message",
    [
        (dict(level=0), ValueError, r"level: must be a finite number above 0"),
        (dict(level=-3), ValueError, r"level: must be a finite number above 0"),
        (dict(level=10**7), ValueError, r"over the limit"),
        (dict(scheme="loop"), ValueError, r"unknown scheme \"loop\".*flat"),
        (dict(scheme="phong", alpha=float("nan")), ValueError, r"alpha: must be finite"),
        (dict(normals_mode="smooth"), ValueError, r"normals_mode: unknown normal mode"),
        (dict(backend="tpu"), ValueError, r"unknown backend"),
        (dict(displace={"kind": "wave"}), ValueError, r"unknown displace kind"),
        (dict(tags={"edge_sharpness": [1.0]}), ValueError, r"bad tags in the tags dict: tags JSON: unknown field `edge_sharpness`"),
        (dict(tags=3), TypeError, r"tags must be None, a dict"),
    ],
)
def test_bad_options_raise_clear_errors(kwargs, exc, message):
    v, f = tri()
    with pytest.raises(exc, match=message):
        tessella.refine(v, f, **kwargs)


def test_bad_normals_raise_value_error():
    v, f = tri()
    with pytest.raises(ValueError, match=r"normals has 2 entries but the mesh has 3"):
        tessella.refine(v, f, v[:2] + [0, 0, 1])
    with pytest.raises(ValueError, match=r"vertex 1 has a zero-length normal"):
        tessella.refine(v, f, [[0, 0, 1], [0, 0, 0], [0, 0, 1]])


def test_faces_are_required_for_arrays():
    with pytest.raises(ValueError, match="needs faces"):
        tessella.refine(tri()[0])


def test_pattern_rejects_bad_levels():
    with pytest.raises(ValueError, match="level must be 1 or more"):
        tessella.pattern(0)
    with pytest.raises(ValueError, match="choose a level"):
        tessella.pattern(10**6)


def test_scheme_names_are_case_insensitive_and_listed():
    v, f = tri()
    assert set(tessella.schemes()) >= {"flat", "phong", "pn"}
    assert "cpu" in tessella.backends()
    a = tessella.refine(v, f, scheme="PN", level=2, backend="CPU")
    b = tessella.refine(v, f, scheme="pn", level=2, backend="cpu")
    np.testing.assert_array_equal(a[0], b[0])
