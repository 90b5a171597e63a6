"""Second-order finite elements and solution fields: the solver's own curved geometry, refined.

gmsh meshes a sphere and a torus with tetrahedra at order 1 and at order 2 (10-node
tetrahedra, mid-edge nodes on the true geometry). tessella reads their boundary surfaces
(`tessella.read_fem`: 3-column faces for order 1, 6-column for order 2), refines the linear
mesh with flat, PN and PNG1 (exact normals at the nodes) and the P2 mesh with `quadratic`
(the element's own map), and prints the distance to the true surface per level. It then
carries a field with a closed form, T = z², through refinement (`point_data=`): linearly on
the order-1 mesh, with the 6-node shape functions on the order-2 mesh, and prints its error
per level. Last, a "heated" torus (a hot spot on the outer equator) is drawn coloured by
temperature by tessella's own renderer (`tessella.render(..., color_by="T")`, on the GPU;
lavapipe serves): the faceted order-1 boundary next to the refined order-2 surface, with a
colour bar. matplotlib only draws the distance chart.

    pip install ./python gmsh matplotlib meshio
    python python/examples/fem_fields.py --out fem-out [--image docs/images/fem-temperature.png]
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any, Callable, Dict, List, Optional

import numpy as np

import tessella
from tessella._types import SchemeName

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem_sphere import mesh_with_gmsh, parts, surface_distance  # noqa: E402

LEVELS = [1, 2, 4, 8, 16]
LINEAR_SCHEMES: List[SchemeName] = ["flat", "pn", "png1"]


def field_error(r: tessella.RefinedMesh, exact: Callable[[np.ndarray], np.ndarray]) -> float:
    """Largest |interpolated T − T(x)| over the refined vertices."""
    return float(np.abs(r.point_data["T"] - exact(r.vertices.astype(np.float64))).max())


def run(out: str, levels: List[int]) -> Dict[str, Dict[str, Any]]:
    os.makedirs(out, exist_ok=True)
    results: Dict[str, Dict[str, Any]] = {}

    def T(p: np.ndarray) -> np.ndarray:  # the field with a closed form
        return np.asarray(p[:, 2] ** 2)

    for part in parts():
        meshes = {}
        for order in (1, 2):
            msh = os.path.join(out, f"{part.name}-order{order}.msh")
            mesh_with_gmsh(part, msh, order)
            meshes[order] = tessella.read_fem(msh)
        v1, f1 = meshes[1]
        v2, f2 = meshes[2]
        print(f"\n{part.name}: order 1: {len(v1)} nodes, {len(f1)} boundary triangles; "
              f"order 2: {len(v2)} nodes, {f2.shape} boundary faces")
        rows: Dict[str, List[Dict[str, float]]] = {}
        n1 = part.normal(v1)
        for scheme in LINEAR_SCHEMES:
            rows[scheme] = [surface_distance(part, *tessella.refine(v1, f1, n1, scheme=scheme, level=l)[:2])
                            for l in levels]
        rows["quadratic (P2 mesh)"] = [
            surface_distance(part, (r := tessella.refine(v2, f2, level=l)).vertices, r.faces) for l in levels]
        errors = {
            "linear (P1 mesh)": [field_error(tessella.refine(v1, f1, n1, scheme="flat", level=l,
                                                             point_data={"T": T(v1)}), T) for l in levels],
            "quadratic (P2 mesh)": [field_error(tessella.refine(v2, f2, level=l, point_data={"T": T(v2)}), T)
                                    for l in levels],
        }
        results[part.name] = {"distance": rows, "field": errors}
        print(f"\n{part.name}: largest distance to the true surface / size (vertices and centroids)\n")
        print("| scheme | " + " | ".join(f"L{l}" for l in levels) + " |")
        print("|---|" + "---|" * len(levels))
        for label, distances in rows.items():
            print(f"| {label} | " + " | ".join(f"{d['max']:.2e}" for d in distances) + " |")
        print(f"\n{part.name}: largest error of T = z² at the refined vertices\n")
        print("| interpolation | " + " | ".join(f"L{l}" for l in levels) + " |")
        print("|---|" + "---|" * len(levels))
        for name, row_errors in errors.items():
            print(f"| {name} | " + " | ".join(f"{e:.2e}" for e in row_errors) + " |")
        r = tessella.refine(v2, f2, level=8, point_data={"T": T(v2)})
        tessella.write_fem(os.path.join(out, f"{part.name}-p2-l8.vtu"), r.vertices, r.faces, r.normals,
                           point_data=r.point_data)
    return results


def plot(results: Dict[str, Dict[str, Any]], levels: List[int], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(results), figsize=(6 * len(results), 4.4), squeeze=False)
    style = {"flat": ("k", "--"), "pn": ("tab:red", "-"), "png1": ("tab:green", "-"),
             "quadratic (P2 mesh)": ("tab:blue", "-")}
    for ax, (name, res) in zip(axes[0], results.items()):
        for scheme, row in res["distance"].items():
            colour, line = style.get(scheme, (None, "-"))
            label = scheme if "P2" in scheme else f"{scheme} (P1 mesh)"
            ax.loglog(levels, [r["max"] for r in row], line, marker="o", color=colour, label=label)
        ax.set(title=f"{name}: order 1 vs order 2 gmsh boundary",
               xlabel="level (segments per coarse edge)", ylabel="max distance to true surface / size",
               xticks=levels, xticklabels=[str(l) for l in levels])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print(f"\nplot: {path}")


def picture(out: str, image: str) -> None:
    """A heated torus coloured by temperature, drawn by tessella's renderer (`tessella.render`,
    the field interpolated in the vertex shader): the faceted order-1 boundary (flat triangles,
    T linear on each) next to the order-2 surface refined with `quadratic` at level 8 (mid-edge
    nodes on the true torus, T through the 6-node shape functions), one colour bar for both."""
    torus = next(p for p in parts() if p.name == "torus")
    hot = np.array([1.4, 0.0, 0.0])  # a heater on the outer equator

    def temp(p: np.ndarray) -> np.ndarray:
        return np.asarray(20 + 80 * np.exp(-np.sum((p - hot) ** 2, axis=1) / 0.3))

    v1, f1 = tessella.read_fem(os.path.join(out, f"{torus.name}-order1.msh"))
    v2, f2 = tessella.read_fem(os.path.join(out, f"{torus.name}-order2.msh"))
    # Faceted: every triangle its own three corners, so each takes its face's normal.
    corners = v1[f1[:, :3]].reshape(-1, 3)
    facets = np.arange(len(corners)).reshape(-1, 3)
    w, h = 460, 400
    view: Dict[str, Any] = dict(yaw=55, pitch=40, color_by="T", colormap="viridis", range=(20, 100))
    left = tessella.render(corners, facets, scheme="flat", level=1, size=(w, h), colorbar=False,
                           point_data={"T": temp(corners)}, label="order 1 faceted", **view)
    # The bar of a picture 400 pixels tall is 84 pixels wide: the surfaces get the same width.
    right = tessella.render(v2, f2, scheme="quadratic", level=8, size=(w + 84, h),
                            point_data={"T": temp(v2)}, label="order 2 quadratic", **view)
    gap = np.empty((h, 2, 4), dtype=np.uint8)
    gap[:] = (40, 40, 48, 255)
    row = np.concatenate([left, gap, right], axis=1)
    _write_png(image, row)
    print(f"picture: {image} ({len(f1)} faceted triangles | {len(f2)} P2 faces at level 8)")


def _write_png(path: str, rgba: np.ndarray) -> None:
    """An 8-bit RGBA PNG (zlib, no filters), so the example needs no imaging package."""
    import struct
    import zlib

    h, w = rgba.shape[:2]
    raw = b"".join(b"\x00" + rgba[y].tobytes() for y in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="fem-out", help="folder for the .msh, .vtu and .png files")
    ap.add_argument("--levels", type=int, nargs="+", default=LEVELS)
    ap.add_argument("--image", help="where to save the temperature picture (default: in --out)")
    args = ap.parse_args(argv)
    results = run(args.out, args.levels)
    plot(results, args.levels, os.path.join(args.out, "fem_p2_distance.png"))
    picture(args.out, args.image or os.path.join(args.out, "fem-temperature.png"))
    # The claims, checked: the P2 surface ends closer than flat, and P2 beats P1 on T = z².
    for name, res in results.items():
        if not res["distance"]["quadratic (P2 mesh)"][-1]["max"] < res["distance"]["flat"][-1]["max"]:
            print(f"{name}: quadratic does not beat flat", file=sys.stderr)
            return 1
        if not res["field"]["quadratic (P2 mesh)"][-1] < res["field"]["linear (P1 mesh)"][-1]:
            print(f"{name}: the P2 field is not closer than the P1 one", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
