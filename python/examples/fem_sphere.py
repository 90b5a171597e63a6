"""The finite-element use case: a coarse volume mesh of a curved part, its boundary made smooth.

gmsh meshes a sphere and a torus coarsely with tetrahedra (as a solver would), the mesh goes
through a .msh file, tessella reads its boundary surface (`tessella.read_fem`), refines it with
every scheme this build has (`tessella.schemes()`: flat, Phong, PN, PNG1, PN-AEN, scalar-tagged
PN), and the script measures how far the refined surface lies from the true geometry at each
level. It prints a table, saves a plot (schemes that give the same surface share a curve: PN-AEN
and the scalar-tagged scheme are PN on a smooth untagged mesh) and writes the refined PN
boundaries as .vtu files next to it.

Distance is measured at the refined vertices *and* at the centroids of the refined triangles,
so it covers the flat facets between samples, relative to the part's size (sphere radius, torus
tube radius). The coarse nodes lie on the true surface and carry its exact normals, as a
CAD-driven mesher provides them (`--computed-normals` uses tessella's own instead).

    pip install ./python gmsh matplotlib meshio
    python python/examples/fem_sphere.py --out fem-out

On a bare Debian machine gmsh's wheel needs: apt-get install libglu1-mesa libgl1 libxrender1
libxcursor1 libxfixes3 libxext6 libxft2 libfontconfig1 libxinerama1 libx11-6 libgomp1.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional

import numpy as np

import tessella

LEVELS = [1, 2, 3, 4, 6, 8, 12, 16]


@dataclass
class Part:
    name: str
    scale: float  # the length distances are divided by
    mesh_size: float
    build: Callable[[], None]  # adds the solid to the current gmsh model
    distance: Callable[[np.ndarray], np.ndarray]  # signed distance to the true surface
    normal: Callable[[np.ndarray], np.ndarray]  # unit outward normal at points on the surface


R_SPHERE = 1.0
R_TORUS, r_TORUS = 1.0, 0.4


def _sphere_distance(p: np.ndarray) -> np.ndarray:
    return np.asarray(np.linalg.norm(p, axis=1) - R_SPHERE)


def _sphere_normal(p: np.ndarray) -> np.ndarray:
    return np.asarray(p / np.linalg.norm(p, axis=1, keepdims=True))


def _torus_tube_vector(p: np.ndarray) -> np.ndarray:
    """From the nearest point of the torus' core circle to p."""
    ring = p.copy()
    ring[:, 2] = 0
    ring *= R_TORUS / np.linalg.norm(ring, axis=1, keepdims=True)
    return np.asarray(p - ring)


def _torus_distance(p: np.ndarray) -> np.ndarray:
    return np.asarray(np.linalg.norm(_torus_tube_vector(p), axis=1) - r_TORUS)


def _torus_normal(p: np.ndarray) -> np.ndarray:
    q = _torus_tube_vector(p)
    return np.asarray(q / np.linalg.norm(q, axis=1, keepdims=True))


def parts() -> List[Part]:
    import gmsh

    return [
        Part("sphere", R_SPHERE, 0.55, lambda: gmsh.model.occ.addSphere(0, 0, 0, R_SPHERE),
             _sphere_distance, _sphere_normal),
        Part("torus", r_TORUS, 0.3, lambda: gmsh.model.occ.addTorus(0, 0, 0, R_TORUS, r_TORUS),
             _torus_distance, _torus_normal),
    ]


def mesh_with_gmsh(part: Part, path: str, order: int = 1) -> None:
    """A coarse tetrahedral mesh of the part at `order` (1 or 2), written as a .msh file.

    The examples' one gmsh recipe: fem_fields.py and fem_pyvista.py mesh with it too, so the
    order 1 meshes they compare are the ones measured here.
    """
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)  # its log would drown the table
        gmsh.model.add(part.name)
        part.build()
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", part.mesh_size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", part.mesh_size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.model.mesh.generate(3)
        if order == 2:
            gmsh.model.mesh.setOrder(2)  # mid-edge nodes placed on the CAD geometry
        gmsh.write(path)
    finally:
        gmsh.finalize()


def surface_distance(part: Part, v: np.ndarray, f: np.ndarray) -> Dict[str, float]:
    """Largest and root-mean-square distance, at vertices and triangle centroids, relative."""
    v = v.astype(np.float64)
    samples = np.vstack([v, v[f].mean(axis=1)])
    d = np.abs(part.distance(samples)) / part.scale
    return {"max": float(d.max()), "rms": float(np.sqrt(np.mean(d**2)))}


def run(out: str, computed_normals: bool, levels: List[int]) -> Dict[str, Dict[str, List[Dict[str, float]]]]:
    os.makedirs(out, exist_ok=True)
    results: Dict[str, Dict[str, List[Dict[str, float]]]] = {}
    # flat, phong, pn, and whatever later builds add (png1, ...); "quadratic" needs second-order
    # elements (on this first-order mesh it is flat): examples/fem_fields.py compares it.
    schemes = [s for s in tessella.schemes() if s != "quadratic"]
    for part in parts():
        msh = os.path.join(out, f"{part.name}.msh")
        mesh_with_gmsh(part, msh)
        v, f = tessella.read_fem(msh)  # the tetrahedra's outward boundary
        n = None if computed_normals else part.normal(v)
        coarse = surface_distance(part, v, f)
        print(f"\n{part.name}: {len(v)} boundary nodes, {len(f)} boundary triangles "
              f"(from {msh}); coarse mesh max distance {coarse['max']:.2e}")
        results[part.name] = {}
        for scheme in schemes:
            row = []
            for level in levels:
                try:
                    rv, rf, rn = tessella.refine(v, f, n, scheme=scheme, level=level)
                except ValueError as e:  # a scheme this input cannot use: say so, go on
                    print(f"  {scheme}: skipped ({e})")
                    break
                row.append(surface_distance(part, rv, rf))
            if row:
                results[part.name][scheme] = row
        if "pn" in schemes:
            rv, rf, rn = tessella.refine(v, f, n, scheme="pn", level=8)
            tessella.write_fem(os.path.join(out, f"{part.name}-pn8.vtu"), rv, rf, rn)
        print_table(part.name, results[part.name], levels)
    return results


def print_table(name: str, rows: Dict[str, List[Dict[str, float]]], levels: List[int]) -> None:
    print(f"\n{name}: largest distance to the true surface / size (vertices and centroids)\n")
    print("| scheme | " + " | ".join(f"L{l}" for l in levels) + " |")
    print("|---|" + "---|" * len(levels))
    for scheme, row in rows.items():
        print(f"| {scheme} | " + " | ".join(f"{r['max']:.2e}" for r in row) + " |")


def same_curves(rows: Dict[str, List[Dict[str, float]]]) -> Dict[str, List[str]]:
    """Schemes grouped by equal results (PN-AEN and ST equal PN, up to float32 rounding, on a
    smooth mesh without tags), keyed by the first of each group: one curve per distinct surface."""

    def same(a: List[Dict[str, float]], b: List[Dict[str, float]]) -> bool:
        return len(a) == len(b) and all(
            abs(x[k] - y[k]) <= 1e-4 * max(abs(x[k]), abs(y[k])) for x, y in zip(a, b)
            for k in ("max", "rms"))

    groups: Dict[str, List[str]] = {}
    for scheme, row in rows.items():
        first = next((g for g in groups if same(rows[g], row)), None)
        groups.setdefault(first or scheme, []).append(scheme)
    return groups


def plot(results: Dict[str, Dict[str, List[Dict[str, float]]]], levels: List[int], path: str, normals: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(results), figsize=(6 * len(results), 4.6), squeeze=False)
    style = {"flat": ("k", "--"), "phong": ("tab:blue", "-"), "pn": ("tab:red", "-"),
             "png1": ("tab:green", "-"), "pn-aen": ("tab:purple", "-"), "st": ("tab:brown", "-")}
    for ax, (name, rows) in zip(axes[0], results.items()):
        for scheme, names in same_curves(rows).items():
            row = rows[scheme]
            colour, line = style.get(scheme, (None, "-"))
            lv = levels[: len(row)]
            label = " = ".join(names)  # schemes that give this very surface here share a curve
            ax.loglog(lv, [r["max"] for r in row], line, marker="o", color=colour,
                      label=f"{label} (max)")
            ax.loglog(lv, [r["rms"] for r in row], line, marker=".", color=colour, alpha=0.45,
                      label=f"{label} (rms)")
        ax.set(title=f"{name}: coarse gmsh boundary refined ({normals} normals)",
               xlabel="level (segments per coarse edge)", ylabel="distance to true surface / size",
               xticks=levels, xticklabels=[str(l) for l in levels])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"\nplot: {path}")


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="fem-out", help="folder for the .msh, .vtu and .png files")
    ap.add_argument("--computed-normals", action="store_true",
                    help="let tessella compute angle-weighted normals instead of exact ones")
    ap.add_argument("--levels", type=int, nargs="+", default=LEVELS)
    args = ap.parse_args(argv)
    normals = "computed" if args.computed_normals else "exact"
    results = run(args.out, args.computed_normals, args.levels)
    plot(results, args.levels, os.path.join(args.out, "fem_distance.png"), normals)
    # The claim the plot makes, checked: every curved scheme ends below flat.
    for name, rows in results.items():
        flat = rows["flat"][-1]["max"]
        for scheme, row in rows.items():
            if scheme != "flat" and not row[-1]["max"] < flat:
                print(f"{name}: {scheme} does not beat flat", file=sys.stderr)
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
