"""PNG1, PN-AEN and scalar-tagged PN: equal to the CLI's, with the papers' properties measured
here (G1 across edges, crack-free hard edges, zero tags = PN), and every form of ``tags``."""

import json

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh, cli_refine, icosphere, ridge_mesh

# Tags on bumpy_mesh (a 6 x 6 grid, vertex j*6+i): two creased edges through vertex 8 (one
# crease), a tensioned vertex, a creased vertex with a direction across the crease.
BUMPY_TAGS = {
    "edges": [
        {"vertices": [7, 8], "sharpness": 1.0},
        {"vertices": [8, 9], "sharpness": 0.5, "kappa": -0.05},
    ],
    "vertices": [
        {"index": 14, "tension": 0.3, "bias": 0.1},
        {"index": 8, "sharpness": 0.4, "crease": [0.0, 1.0, 0.0]},
    ],
}


def mesh(name):
    if name == "bumpy":
        return bumpy_mesh(11)
    v, f, n, _ = ridge_mesh()
    return v, f, n


CASES = [
    dict(mesh="bumpy", scheme="png1", level=4, args=[]),
    dict(mesh="bumpy", scheme="png1", level=3, args=[], normals=False),
    dict(mesh="bumpy", scheme="png1", level=3, args=["--soup"], kw=dict(weld=False)),
    dict(mesh="bumpy", scheme="png1", level=3, args=["--normals", "real"], kw=dict(normals_mode="real")),
    dict(mesh="ridge", scheme="png1", level=4, args=[]),
    dict(mesh="bumpy", scheme="png1", level=4, tags=BUMPY_TAGS),
    dict(mesh="bumpy", scheme="png1", level=3, args=["--crease-angle", "12"], kw=dict(crease_angle=12.0)),
    dict(mesh="bumpy", scheme="pn-aen", level=4, args=[]),
    dict(mesh="ridge", scheme="pn-aen", level=5, args=[]),
    dict(mesh="bumpy", scheme="st", level=4, args=[]),
    dict(mesh="ridge", scheme="st", level=4, args=[]),
    dict(mesh="bumpy", scheme="st", level=4, tags=BUMPY_TAGS),
    # The given tags override the split-normal crease on one edge (layering, later wins).
    dict(mesh="ridge", scheme="st", level=3,
         tags={"edges": [{"vertices": [14, 20], "sharpness": 0.25}],
               "vertices": [{"index": 21, "tension": -0.2}]}),
    dict(mesh="ridge", scheme="st", level=3, args=["--crease-angle", "179"], kw=dict(crease_angle=179.0)),
]


def case_id(c):
    extra = " ".join(c.get("args", [])) + (" tags" if "tags" in c else "")
    return f"{c['scheme']}-{c['mesh']}-{c['level']}-{extra}-n{int(c.get('normals', True))}"


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_python_equals_cli(tmp_path, cli, case):
    v, f, n = mesh(case["mesh"])
    n = n if case.get("normals", True) else None
    args = ["--scheme", case["scheme"], "--level", str(case["level"]), *case.get("args", [])]
    kw = dict(case.get("kw", {}))
    if "tags" in case:
        tags_file = tmp_path / "tags.json"
        tags_file.write_text(json.dumps(case["tags"]))
        args += ["--tags", str(tags_file)]
        kw["tags"] = case["tags"]
    cv, cf, cn = cli_refine(cli, tmp_path, v, f, n, args)
    # backend="cpu" like the CLI's: "auto" would take a hardware GPU where there is one.
    pv, pf, pn = tessella.refine(v, f, n, scheme=case["scheme"], level=case["level"], backend="cpu", **kw)
    np.testing.assert_array_equal(cv, pv)
    np.testing.assert_array_equal(cf, pf)
    np.testing.assert_array_equal(cn, pn)


def test_tags_change_the_surface():
    """The CLI cases above would pass with tags ignored on both sides; they are not ignored."""
    v, f, n = bumpy_mesh(11)
    for scheme in ("st", "png1"):
        plain, _, _ = tessella.refine(v, f, n, scheme=scheme, level=4)
        tagged, _, _ = tessella.refine(v, f, n, scheme=scheme, level=4, tags=BUMPY_TAGS)
        assert np.abs(plain - tagged).max() > 1e-3, scheme


def edge_points(v, f, n, level, **kw):
    """Refine without welding and pair up the points both faces of a coarse edge produce.

    Returns (a, b): rows of the two sides, positions and normals, for every point strictly
    inside a shared coarse edge. Built from the documented pattern order, independently of the
    refiner's welding."""
    rv, rf, rn = tessella.refine(v, f, n, level=level, weld=False, **kw)
    bary = np.rint(tessella.pattern(level)[0] * level).astype(int)
    per = len(bary)
    # Edge points by position: the point of edge {p, q} at q-weight k/N, seen from either side.
    key_of = {}
    pid = {}
    for i, p in enumerate(map(tuple, v)):
        pid.setdefault(p, i)
    pos = [pid[tuple(p)] for p in v]
    pairs = []
    for face, tri in enumerate(f):
        for row, w in enumerate(bary):
            on = [k for k in range(3) if w[k] > 0]
            if len(on) != 2:
                continue
            key = frozenset((pos[tri[k]], w[k]) for k in on)
            idx = face * per + row
            if key in key_of:
                pairs.append((key_of.pop(key), idx))
            else:
                key_of[key] = idx
    a, b = np.array(pairs).T
    return (rv[a], rn[a]), (rv[b], rn[b])


def angles_deg(n1, n2):
    c = np.einsum("ij,ij->i", n1.astype(np.float64), n2.astype(np.float64))
    c /= np.linalg.norm(n1, axis=1) * np.linalg.norm(n2, axis=1)
    return np.degrees(np.arccos(np.clip(c, -1, 1)))


def test_png1_is_tangent_continuous_where_pn_is_not(sphere):
    """Fünfzig et al. 2008: PNG1 patches meet with one tangent plane across every edge; PN
    triangles do not. Measured here from the patches' own surface normals (normals="real") at
    the edge points both sides produce, and by tessella.quality in f64."""
    v, f, n = sphere
    jump = {}
    for scheme in ("pn", "png1"):
        (pa, na), (pb, nb) = edge_points(v, f, n, 8, scheme=scheme, normals_mode="real")
        assert len(pa) == 120 * 7  # every edge of icosphere(1), 7 inner points each
        np.testing.assert_allclose(pa, pb, atol=1e-6)  # both sides meet
        jump[scheme] = angles_deg(na, nb).max()
    # Measured: PN 2.6 degrees, PNG1 ~0.01 (float32 rounding of the output normals).
    assert jump["pn"] > 1.0
    assert jump["png1"] < 0.05
    q = {s: tessella.quality(v, f, n, scheme=s, level=8) for s in ("pn", "png1")}
    assert q["pn"]["normal_jump_max_deg"] > 1.0
    assert q["png1"]["normal_jump_max_deg"] < 0.01
    assert abs(q["pn"]["normal_jump_max_deg"] - jump["pn"]) < 0.05
    assert q["pn"]["edges_checked"] == q["png1"]["edges_checked"] == 120


def test_pn_aen_closes_the_cracks_pn_opens_at_hard_edges():
    """McDonald & Kilgard 2010: PN cracks where the normals are split; PN-AEN does not.
    Gaps measured here from the unwelded patches and by tessella.quality."""
    v, f, n, _ = ridge_mesh()
    gap = {}
    for scheme in ("pn", "pn-aen", "st"):
        # Level 10: the inner edge points are the nine quality samples (t = 1/10 .. 9/10).
        (pa, _), (pb, _) = edge_points(v, f, n, 10, scheme=scheme)
        gap[scheme] = np.linalg.norm(pa.astype(np.float64) - pb, axis=1).max()
        q = tessella.quality(v, f, n, scheme=scheme, level=10)
        assert abs(q["gap_max"] - gap[scheme]) < 1e-5
    # Measured: PN 1.0e-3 (of a 1.44 diagonal), PN-AEN and ST ~1e-7 (float32 rounding).
    assert gap["pn"] > 5e-4
    assert gap["pn-aen"] < 1e-6
    assert gap["st"] < 1e-6  # the split normals became a crease, which closes too


def test_st_without_tags_is_pn():
    """GMR Appendix B: with every tag zero the scalar-tagged scheme is PN."""
    v, f, n = bumpy_mesh(5)  # one normal per position: nothing is tagged
    pn = tessella.refine(v, f, n, scheme="pn", level=6)
    for tags in (None, {"vertices": [{"index": 3}], "edges": [{"vertices": [7, 8]}]}):
        st = tessella.refine(v, f, n, scheme="st", level=6, tags=tags)
        np.testing.assert_array_equal(st[1], pn[1])
        np.testing.assert_allclose(st[0], pn[0], atol=2e-6, rtol=0)
        np.testing.assert_allclose(st[2], pn[2], atol=2e-5, rtol=0)


def test_tags_as_dict_string_and_path_give_identical_results(tmp_path):
    v, f, n = bumpy_mesh(11)
    text = json.dumps(BUMPY_TAGS)
    path = tmp_path / "tags.json"
    path.write_text(text)
    as_numpy = {
        "edges": [{"vertices": np.array([7, 8]), "sharpness": np.float32(1.0)},
                  {"vertices": (8, 9), "sharpness": 0.5, "kappa": -0.05}],
        "vertices": [{"index": np.int64(14), "tension": 0.3, "bias": 0.1},
                     {"index": 8, "sharpness": 0.4, "crease": np.array([0.0, 1.0, 0.0])}],
    }
    forms = [BUMPY_TAGS, as_numpy, text, "  \n" + text, str(path), path]
    for scheme in ("st", "png1"):
        results = [tessella.refine(v, f, n, scheme=scheme, level=3, tags=t) for t in forms]
        for r in results[1:]:
            for got, want in zip(r, results[0]):
                np.testing.assert_array_equal(got, want)
        q = [tessella.quality(v, f, n, scheme=scheme, level=3, tags=t) for t in forms]
        assert all(x == q[0] for x in q)


def test_crease_angle_makes_png1_edges_sharp():
    """An edge PNG1 treats as sharp is not G1: with a crease angle the normal jump appears."""
    v, f, n = bumpy_mesh(11)
    smooth = tessella.quality(v, f, n, scheme="png1", level=2)
    creased = tessella.quality(v, f, n, scheme="png1", level=2, crease_angle=5.0)
    assert smooth["normal_jump_max_deg"] < 0.01
    assert creased["normal_jump_max_deg"] > 1.0


GRID_EDGE = [7, 8]  # an interior edge of bumpy_mesh; [0, 1] lies on its boundary


@pytest.mark.parametrize(
    "tags, scheme, exc, message",
    [
        ({"edges": [{"vertices": [0, 99]}]}, "st", ValueError,
         r"bad tags in the tags dict: edge tag names vertex 99, but the mesh has only 36 vertices"),
        ({"edges": [{"vertices": GRID_EDGE, "sharpness": 2}]}, "st", ValueError,
         r"edge 7-8 sharpness is 2, outside 0..=1"),
        ({"edges": [{"vertices": [0, 35]}]}, "png1", ValueError, r"no triangle has that edge"),
        ({"edges": [{"vertices": [0, 1], "sharpness": 1}]}, "st", ValueError,
         r"a boundary or non-manifold edge"),
        ({"vertices": [{"index": 3, "sharpness": 3}]}, "st", ValueError,
         r"vertex 3 sharpness is 3, outside -1..=1"),
        ({"vertices": [{"index": 3, "tension": float("nan")}]}, "st", ValueError, r"finite"),
        ({"edge": []}, "st", ValueError, r"tags JSON: unknown field `edge`"),
        ({"vertices": [{"tension": 1}]}, "st", ValueError, r"missing field `index`"),
        ('{"edges": [', "st", ValueError, r"bad tags in the tags string: tags JSON"),
        # Three creased edges through vertex 8: more than one crease for the scalar-tagged scheme.
        ({"edges": [{"vertices": [7, 8], "sharpness": 1}, {"vertices": [8, 9], "sharpness": 1},
                    {"vertices": [8, 14], "sharpness": 1}]}, "st", ValueError,
         r"vertex 8 has 3 creased edges"),
        ([1, 2], "st", TypeError, r"tags must be None, a dict"),
        ({"edges": [{"vertices": [7, 8], "sharpness": object()}]}, "st", TypeError,
         r"tags hold <object object"),
    ],
)
def test_bad_tags_raise_clear_errors(tags, scheme, exc, message):
    v, f, n = bumpy_mesh(11)
    with pytest.raises(exc, match=message):
        tessella.refine(v, f, n, scheme=scheme, level=2, tags=tags)
    with pytest.raises(exc, match=message):
        tessella.quality(v, f, n, scheme=scheme, level=2, tags=tags)


def test_bad_tag_files_and_crease_angles(tmp_path):
    v, f, n = bumpy_mesh(11)
    with pytest.raises(FileNotFoundError, match=r"cannot read tags from .*missing\.json"):
        tessella.refine(v, f, n, scheme="st", level=2, tags=tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"vertices": [{"index": 40}]}')
    with pytest.raises(ValueError, match=r"bad tags in .*bad\.json: vertex tag names vertex 40"):
        tessella.refine(v, f, n, scheme="st", level=2, tags=str(bad))
    for angle in (200.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match=r"crease angle must be a finite number of degrees"):
            tessella.refine(v, f, n, scheme="png1", level=2, crease_angle=angle)


def test_new_schemes_are_listed_and_named_as_on_the_command_line():
    assert tessella.schemes() == ["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"]
    v, f = icosphere(0)
    a = tessella.refine(v, f, v, scheme="PN-AEN", level=2)
    b = tessella.refine(v, f, v, scheme="pn_aen", level=2)
    np.testing.assert_array_equal(a[0], b[0])
    for name in tessella.schemes():
        assert tessella.quality(v, f, v, scheme=name, level=2)["scheme"] == name
