"""The second-order FEM example runs (gmsh order 1 and 2 -> read_fem -> refine with fields ->
tables, plot, picture) and its claims hold."""

import importlib.util
import sys
from pathlib import Path

import pytest

pytest.importorskip("gmsh")
pytest.importorskip("matplotlib")
HERE = Path(__file__).resolve().parents[1] / "examples"


def load(name):
    sys.path.insert(0, str(HERE))
    spec = importlib.util.spec_from_file_location(name, HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_p2_example_quadratic_beats_linear_schemes_and_fields(tmp_path, capsys):
    example = load("fem_fields")
    assert example.main(["--out", str(tmp_path), "--levels", "1", "4", "8"]) == 0
    results = example.run(str(tmp_path / "again"), [1, 8])
    for part, res in results.items():
        d = res["distance"]
        # The P2 surface of the order-2 mesh is closer than every scheme on the order-1 mesh.
        for scheme in ("flat", "pn", "png1"):
            assert d["quadratic (P2 mesh)"][-1]["max"] < d[scheme][-1]["max"], (part, scheme)
        # At level 1 every surface is the coarse triangles (the nodes lie on the true surface).
        assert res["field"]["quadratic (P2 mesh)"][0] < 1e-6
        assert res["field"]["quadratic (P2 mesh)"][-1] < res["field"]["linear (P1 mesh)"][-1] / 3
    for name in ("fem_p2_distance.png", "fem-temperature.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "| quadratic (P2 mesh) |" in capsys.readouterr().out
