"""The FEM example's heated torus in PyVista: a refined second-order surface coloured by a field.

gmsh meshes the torus with 10-node tetrahedra (mid-edge nodes on the true geometry);
`tessella.read_fem` reads the boundary's 6-node faces, `tessella.refine` refines them with
the `quadratic` scheme and carries a temperature field through the 6-node shape functions
(`point_data=`), and `RefinedMesh.to_pyvista()` hands PyVista the surface with its normals,
point data and cell data. `tessella.plot(result, scalars="T")` draws it off screen (headless:
VTK falls back to EGL or OSMesa) and writes a PNG; the same picture straight from PyVista is
`grid.plot(scalars="T", off_screen=True, screenshot=path)`.

    pip install ./python gmsh meshio pyvista
    python python/examples/fem_pyvista.py --out fem-out
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any, Dict, List, Optional

import numpy as np
import numpy.typing as npt

import tessella

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem_sphere import mesh_with_gmsh, parts  # noqa: E402

HOT = np.array([1.4, 0.0, 0.0])  # a heater on the torus's outer equator


def temperature(p: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The field, in closed form: 20 degrees far away, 100 at the heater."""
    t: npt.NDArray[np.float64] = 20 + 80 * np.exp(-np.sum((p - HOT) ** 2, axis=1) / 0.3)
    return t


def run(out: str, level: int = 8) -> Dict[str, Any]:
    """Meshes, refines and draws the torus; returns the refined mesh, its PyVista surface, the
    picture and the largest error of the carried field against its closed form."""
    os.makedirs(out, exist_ok=True)
    torus = next(p for p in parts() if p.name == "torus")
    msh = os.path.join(out, "torus-order2.msh")
    mesh_with_gmsh(torus, msh, 2)
    v, f = tessella.read_fem(msh)
    result = tessella.refine(v, f, level=level, point_data={"T": temperature(v)},
                             cell_data={"face": np.arange(len(f))})
    grid = result.to_pyvista()
    picture = os.path.join(out, "torus-temperature-pyvista.png")
    image = tessella.plot(result, scalars="T", off_screen=True, screenshot=picture,
                          window_size=(640, 480), cmap="viridis")
    error = float(np.abs(result.point_data["T"] - temperature(result.vertices.astype(np.float64))).max())
    print(f"torus: {len(v)} nodes, {len(f)} 6-node boundary faces -> {grid.n_points} points, "
          f"{grid.n_cells} triangles in PyVista (point data {list(grid.point_data.keys())}, "
          f"cell data {list(grid.cell_data.keys())})")
    print(f"largest error of the carried temperature: {error:.2e} (range 20..100)")
    print(f"picture: {picture}")
    return {"result": result, "grid": grid, "image": image, "picture": picture, "error": error}


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="fem-out", help="folder for the .msh and the picture")
    parser.add_argument("--level", type=int, default=8)
    args = parser.parse_args(argv)
    run(args.out, args.level)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
