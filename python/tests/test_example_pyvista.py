"""The FEM example's PyVista variant runs headless and shows the field it carried."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gmsh")
pytest.importorskip("pyvista")
HERE = Path(__file__).resolve().parents[1] / "examples"


def test_pyvista_example_draws_the_refined_field(tmp_path):
    sys.path.insert(0, str(HERE))
    spec = importlib.util.spec_from_file_location("fem_pyvista", HERE / "fem_pyvista.py")
    example = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = example
    spec.loader.exec_module(example)
    out = example.run(str(tmp_path), level=4)
    grid, result = out["grid"], out["result"]
    # PyVista holds the refined surface with its fields and normals.
    assert grid.n_points == len(result.vertices) and grid.n_cells == len(result.faces)
    np.testing.assert_array_equal(grid.point_data["T"], result.point_data["T"])
    np.testing.assert_array_equal(grid.cell_data["face"], result.cell_data["face"])
    np.testing.assert_array_equal(grid.point_data["Normals"], result.normals)
    # The 6-node shape functions carry the smooth field to within a small part of its range.
    assert out["error"] < 0.05 * 80
    # The picture is coloured: viridis spans blue-purple (cold) to yellow (hot), not grey.
    image = out["image"].astype(int)
    saturated = np.abs(image - image.mean(axis=2, keepdims=True)).sum(axis=2) > 60
    assert saturated.mean() > 0.05
    assert Path(out["picture"]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
