"""Shared test inputs and independent f64 references (the papers' formulas, in numpy)."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import meshio
import numpy as np
import pytest


def icosphere(subdivisions: int):
    """Unit icosphere built here (not by tessella): positions on the sphere, CCW outward faces."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = [
        [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
        [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
        [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
    ]
    f = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ]
    v = [list(np.array(p) / np.linalg.norm(p)) for p in v]
    for _ in range(subdivisions):
        mids = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                p = np.array(v[a]) + np.array(v[b])
                v.append(list(p / np.linalg.norm(p)))
                mids[key] = len(v) - 1
            return mids[key]

        nf = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    v = np.array(v, dtype=np.float32)
    return v, np.array(f, dtype=np.int64)


@pytest.fixture
def sphere():
    """Icosphere(1) in float32 with its exact normals (= positions)."""
    v, f = icosphere(1)
    return v, f, v.copy()


def bumpy_mesh(seed: int = 7):
    """An open, curved, irregular patch with skewed normals: a harder input than a sphere."""
    rng = np.random.default_rng(seed)
    n = 6
    xs, ys = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="xy")
    xs = xs + rng.uniform(-0.04, 0.04, xs.shape)
    ys = ys + rng.uniform(-0.04, 0.04, ys.shape)
    zs = 0.3 * np.sin(2.5 * xs) * np.cos(1.7 * ys)
    v = np.stack([xs.ravel(), ys.ravel(), zs.ravel()], axis=1).astype(np.float32)
    f = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i, (j + 1) * n + i + 1
            f += [[a, b, d], [a, d, c]]
    nrm = rng.normal(size=v.shape) * 0.3 + np.array([0, 0, 1.0])
    nrm = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(np.float32)
    return v, np.array(f, dtype=np.int64), nrm


def grid(n: int, z=None):
    """An n x n vertex grid over the unit square, two CCW triangles per cell; heights z(x, y)."""
    xs, ys = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="xy")
    zs = np.zeros_like(xs) if z is None else z(xs, ys)
    v = np.stack([xs.ravel(), ys.ravel(), zs.ravel()], axis=1).astype(np.float32)
    f = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i, (j + 1) * n + i + 1
            f += [[a, b, d], [a, d, c]]
    return v, np.array(f, dtype=np.int64)


def ridge_mesh(n: int = 6, column: int = 2):
    """A curved open grid with a hard edge: the vertices of one interior grid column are
    doubled, the cells left of it use the originals, the cells right of it the copies, and the
    two copies get normals tilted apart by about 30 degrees (split normals, as a file stores a
    crease). Returns (v, f, n, crease_edges) with crease_edges the column's edges (originals)."""
    v, f = grid(n, lambda x, y: 0.25 * np.sin(2.0 * x) * np.cos(1.5 * y))
    col = [j * n + column for j in range(n)]
    copy = {c: n * n + k for k, c in enumerate(col)}
    v = np.vstack([v, v[col]])
    x = v[:, 0].astype(np.float64)
    f = f.copy()
    for t in f:
        if min(x[t]) >= x[col[0]] - 1e-6:  # a cell right of the column (inclusive)
            t[:] = [copy.get(int(i), int(i)) for i in t]
    y = v[:, 1].astype(np.float64)
    # The height field's normal (-dz/dx, -dz/dy, 1), then the crease's tilt on top.
    nrm = np.stack([-0.5 * np.cos(2.0 * x) * np.cos(1.5 * y),
                    0.375 * np.sin(2.0 * x) * np.sin(1.5 * y), np.ones_like(x)], axis=1)
    nrm[col, 0] -= 0.3  # left side of the crease leans left ...
    nrm[list(copy.values()), 0] += 0.3  # ... right side leans right
    nrm = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(np.float32)
    edges = [[col[j], col[j + 1]] for j in range(n - 1)]
    return v, f, nrm, edges


def uniform_barycentrics(level: int) -> np.ndarray:
    """Points of the uniform pattern, in its documented order (j outer, i inner):
    (l1, l2, l3) = ((N-i-j)/N, i/N, j/N)."""
    n = level
    return np.array(
        [[(n - i - j) / n, i / n, j / n] for j in range(n + 1) for i in range(n + 1 - j)]
    )


def pn_points(p: np.ndarray, nrm: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """PN triangle (Vlachos et al. 2001, docs/formulas.md) of corners p (3,3), normals nrm (3,3),
    evaluated in f64 at barycentrics bary (k, 3)."""
    p = p.astype(np.float64)
    nrm = nrm.astype(np.float64)
    nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)

    def edge(i, j):
        w = np.dot(p[j] - p[i], nrm[i])
        return (2 * p[i] + p[j] - w * nrm[i]) / 3

    b210, b120 = edge(0, 1), edge(1, 0)
    b021, b012 = edge(1, 2), edge(2, 1)
    b102, b201 = edge(2, 0), edge(0, 2)
    e = (b210 + b120 + b021 + b012 + b102 + b201) / 6
    b111 = e + (e - p.mean(axis=0)) / 2
    l1, l2, l3 = (bary[:, k : k + 1] for k in range(3))
    return (
        p[0] * l1**3 + p[1] * l2**3 + p[2] * l3**3
        + 3 * (b210 * l1**2 * l2 + b120 * l1 * l2**2 + b201 * l1**2 * l3)
        + 3 * (b021 * l2**2 * l3 + b012 * l2 * l3**2 + b102 * l1 * l3**2)
        + 6 * b111 * l1 * l2 * l3
    )


def phong_points(p: np.ndarray, nrm: np.ndarray, bary: np.ndarray, alpha: float) -> np.ndarray:
    """Phong tessellation (Boubekeur & Alexa 2008, docs/formulas.md) in f64."""
    p = p.astype(np.float64)
    nrm = nrm.astype(np.float64)
    nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    flat = bary @ p
    proj = np.zeros_like(flat)
    for i in range(3):
        # pi_i(q) = q - ((q - P_i) . N_i) N_i, weighted by l_i.
        d = (flat - p[i]) @ nrm[i]
        proj += bary[:, i : i + 1] * (flat - d[:, None] * nrm[i])
    return (1 - alpha) * flat + alpha * proj


# --- the `tessella` CLI, which the Python results are compared with --------------------------

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """The `tessella` binary: $TESSELLA_CLI, else built with cargo from the repository root
    (a no-op when it is up to date)."""
    if os.environ.get("TESSELLA_CLI"):
        return os.environ["TESSELLA_CLI"]
    out = subprocess.run(
        ["cargo", "build", "-p", "tessella-cli", "--message-format=json-render-diagnostics"],
        cwd=REPO,
        check=True,
        stdout=subprocess.PIPE,
        text=True,
    ).stdout
    for line in out.splitlines():
        msg = json.loads(line)
        if msg.get("reason") == "compiler-artifact" and msg.get("executable"):
            if msg["target"]["name"] == "tessella":
                return msg["executable"]
    raise AssertionError("cargo built tessella-cli but reported no `tessella` executable")


def write_ascii_ply(path, v, f, n=None):
    """An ascii PLY written here, independently of tessella-io; %.9g round-trips float32."""
    lines = ["ply", "format ascii 1.0", f"element vertex {len(v)}"]
    lines += [f"property float {c}" for c in "xyz"]
    if n is not None:
        lines += [f"property float n{c}" for c in "xyz"]
    lines += [f"element face {len(f)}", "property list uchar int vertex_indices", "end_header"]
    for i, p in enumerate(v):
        row = list(p) + (list(n[i]) if n is not None else [])
        lines.append(" ".join(f"{float(x):.9g}" for x in row))
    lines += [f"3 {a} {b} {c}" for a, b, c in f]
    Path(path).write_text("\n".join(lines) + "\n")


def read_ply_with_meshio(path):
    m = meshio.read(path)
    n = np.stack([m.point_data[k] for k in ("nx", "ny", "nz")], axis=1)
    return m.points, m.cells_dict["triangle"], n


def cli_refine(cli, tmp_path, v, f, n, args):
    """`tessella refine` on (v, f, n) written as ascii PLY here; its result read with meshio."""
    src, dst = tmp_path / "in.ply", tmp_path / "out.ply"
    write_ascii_ply(src, v, f, n)
    subprocess.run(
        [cli, "refine", str(src), "-o", str(dst), "--backend", "cpu", *args],
        check=True,
        capture_output=True,
    )
    return read_ply_with_meshio(dst)
