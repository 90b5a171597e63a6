"""load/save, and Python results equal the CLI's (`tessella refine`) for the same input."""

import subprocess

import numpy as np
import pytest

import tessella
from conftest import bumpy_mesh, icosphere, read_ply_with_meshio, write_ascii_ply

CASES = [
    dict(scheme="flat", level=1, normals=True, args=[]),
    dict(scheme="phong", level=4, normals=True, args=["--alpha", "0.6"], kw=dict(alpha=0.6)),
    dict(scheme="pn", level=5, normals=True, args=[]),
    dict(scheme="pn", level=3, normals=False, args=[]),
    dict(scheme="pn", level=3, normals=True, args=["--soup"], kw=dict(weld=False)),
    dict(scheme="pn", level=4, normals=True, args=["--normals", "real"], kw=dict(normals_mode="real")),
]


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['scheme']}-{c['level']}-{' '.join(c['args'])}-n{int(c['normals'])}")
def test_python_equals_cli(tmp_path, cli, case):
    v, f, n = bumpy_mesh(11)
    n = n if case["normals"] else None
    src, dst = tmp_path / "in.ply", tmp_path / "out.ply"
    write_ascii_ply(src, v, f, n)
    subprocess.run(
        [cli, "refine", str(src), "-o", str(dst), "--scheme", case["scheme"],
         "--level", str(case["level"]), "--backend", "cpu", *case["args"]],
        check=True,
        capture_output=True,
    )
    cv, cf, cn = read_ply_with_meshio(dst)
    # backend="cpu" like the CLI's: "auto" would take a hardware GPU where there is one.
    pv, pf, pn = tessella.refine(v, f, n, scheme=case["scheme"], level=case["level"], backend="cpu",
                                 **case.get("kw", {}))
    np.testing.assert_array_equal(cv, pv)
    np.testing.assert_array_equal(cf, pf)
    np.testing.assert_array_equal(cn, pn)


@pytest.mark.parametrize("ext", [".ply", ".obj", ".glb", ".gltf"])
def test_save_then_load_round_trips(tmp_path, ext):
    v, f = icosphere(1)
    rv, rf, rn = tessella.refine(v, f, v, scheme="pn", level=3)
    path = tmp_path / f"mesh{ext}"
    tessella.save(path, rv, rf, rn)
    lv, lf, ln = tessella.load(str(path))
    assert lv.dtype == np.float32 and lf.dtype == np.uint32
    if ext == ".obj":
        # OBJ is text and numbers vertices by first use: compare triangle by triangle.
        assert lf.shape == rf.shape
        np.testing.assert_allclose(lv[lf], rv[rf], atol=1e-6, rtol=0)
        np.testing.assert_allclose(ln[lf], rn[rf], atol=1e-6, rtol=0)
    else:
        np.testing.assert_array_equal(lv, rv)
        np.testing.assert_array_equal(lf, rf)
        np.testing.assert_array_equal(ln, rn)


def test_load_reads_a_hand_written_obj_and_refine_takes_it(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    v, f, n = tessella.load(path)
    np.testing.assert_array_equal(v, [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    assert f.shape == (2, 3) and n is None  # the quad is fan-triangulated; no normals in file
    rv, rf, rn = tessella.refine(v, f, n, scheme="pn", level=2)
    assert rf.shape == (8, 3)
    np.testing.assert_allclose(rv[:, 2], 0, atol=1e-7)  # a flat quad stays flat


def test_ascii_ply_option(tmp_path):
    v, f = icosphere(0)
    path = tmp_path / "a.ply"
    tessella.save(path, v, f, ply_ascii=True)
    assert path.read_bytes().startswith(b"ply\nformat ascii")
    lv, lf, _ = tessella.load(path)
    np.testing.assert_array_equal(lv, v)
    np.testing.assert_array_equal(lf, f)


def test_file_errors(tmp_path):
    v, f = icosphere(0)
    with pytest.raises(FileNotFoundError, match="missing.obj"):
        tessella.load(tmp_path / "missing.obj")
    with pytest.raises(ValueError, match="unknown mesh file extension"):
        tessella.load(tmp_path / "mesh.xyz")
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")
    with pytest.raises(ValueError, match="bad.ply"):
        tessella.load(bad)
    with pytest.raises(OSError):
        tessella.save(tmp_path / "no" / "such" / "dir.ply", v, f)
    with pytest.raises(ValueError, match="uses vertex 99"):
        tessella.save(tmp_path / "out.ply", v, np.array([[0, 1, 99]]))
    assert not (tmp_path / "out.ply").exists()
    with pytest.raises(ValueError, match=r"faces must have shape \(n, 3\)"):
        tessella.save(tmp_path / "out.ply", v, f[:, :2])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.ply"]  # no temporary files left
