"""The FEM example runs (gmsh -> .msh -> boundary -> refine -> table and plot) and its claim holds."""

import importlib.util
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "fem_sphere.py"


def load_example():
    spec = importlib.util.spec_from_file_location("fem_sphere", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_fem_example_curved_schemes_beat_flat(tmp_path, capsys):
    example = load_example()
    assert example.main(["--out", str(tmp_path), "--levels", "1", "2", "4", "8"]) == 0
    results = example.run(str(tmp_path / "again"), False, [1, 4, 8])
    for part, rows in results.items():
        flat = rows["flat"]
        # Level 1 is the coarse mesh itself for every scheme.
        assert all(abs(row[0]["max"] - flat[0]["max"]) < 1e-6 for row in rows.values())
        for scheme in ("phong", "pn", "png1"):
            assert rows[scheme][-1]["max"] < flat[-1]["max"] / 2, (part, scheme)
        # PN's and PNG1's errors shrink as the level grows.
        for scheme in ("pn", "png1"):
            assert rows[scheme][2]["max"] < rows[scheme][1]["max"] < rows[scheme][0]["max"]
        # PNG1 is at least as close as PN (measured: about half PN's distance at level 8).
        assert rows["png1"][-1]["max"] <= rows["pn"][-1]["max"], part
        # Without tags or split normals, PN-AEN and the scalar-tagged scheme are PN.
        assert example.same_curves(rows)["pn"] == ["pn", "pn-aen", "st"]
    png = tmp_path / "fem_distance.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "sphere-pn8.vtu").exists() and (tmp_path / "torus.msh").exists()
    out = capsys.readouterr().out
    assert "| pn |" in out and "| png1 |" in out
