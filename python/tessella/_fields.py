"""Finite-element refinement: second-order (6-node) faces, solution fields, warping.

:func:`tessella.refine` comes here when ``faces`` has 6 columns or ``point_data``,
``cell_data`` or ``warp`` is given.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _tessella
from ._errors import MeshError, OptionError


def _field_rows(name: str, arr: Any, count: int, per: str) -> np.ndarray:
    a = np.asarray(arr)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2:
        raise MeshError(f"field {name!r} must have shape ({count},) or ({count}, k), got {a.shape}")
    if a.shape[0] != count:
        raise MeshError(f"field {name!r} has {a.shape[0]} rows, but the mesh has {count} {per}s")
    if not np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.complexfloating):
        raise TypeError(f"field {name!r} must hold real numbers, got dtype {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float32)


def split_faces(faces: Any) -> Tuple[np.ndarray, Optional[np.ndarray]]:
    """``(m, 3)`` or ``(m, 6)`` faces as corners and mid-edge nodes (-1 rows: linear faces)."""
    f = np.asarray(faces)
    if f.ndim != 2 or f.shape[1] not in (3, 6):
        raise MeshError(
            f"faces must have shape (m, 3) or (m, 6) (corners, then the mid-edge nodes of edges "
            f"0-1, 1-2, 2-0), got {f.shape}"
        )
    if not np.issubdtype(f.dtype, np.integer):
        raise TypeError(f"faces must hold integers, got dtype {f.dtype}")
    if f.shape[1] == 3:
        return f, None
    corners = f[:, :3]
    if corners.size and corners.min() < 0:
        raise MeshError("faces' corner columns hold a negative index")
    return corners, np.ascontiguousarray(f[:, 3:], dtype=np.int64)


def refine_fem(
    vertices: Any,
    faces: Any,
    normals: Any = None,
    *,
    scheme: Optional[str],
    level: Any,
    alpha: float,
    normals_mode: Optional[str],
    backend: str,
    weld: bool,
    point_data: Optional[Dict[str, Any]],
    cell_data: Optional[Dict[str, Any]],
    warp: Optional[str],
    scale: float,
    uvs: Optional[np.ndarray] = None,
) -> Any:
    from ._result import RefinedMesh

    v = np.asarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise MeshError(f"vertices must have shape (n, 3), got {v.shape}")
    corners, mids = split_faces(faces)
    if scheme is None:
        scheme = "quadratic" if mids is not None else "pn"
    if isinstance(level, float) and not float(level).is_integer():
        raise OptionError("fields and 6-node faces take a whole level")
    point_data = dict(point_data or {})
    cell_data = dict(cell_data or {})
    pd = {name: _field_rows(name, a, len(v), "vertex") for name, a in point_data.items()}
    cd = {name: _field_rows(name, a, len(corners), "face") for name, a in cell_data.items()}
    for per, fields in (("vertex", pd), ("face", cd)):
        for name, a in fields.items():
            bad = np.argwhere(~np.isfinite(a))
            if len(bad):
                i, c = bad[0]
                raise MeshError(
                    f"field {name!r} has the non-finite value {a[i, c]} at {per} {i} (component {c})"
                )
    if warp is not None:
        if warp not in pd:
            raise OptionError(f"warp={warp!r} names no point_data field (have: {sorted(pd)})")
        if pd[warp].shape[1] != 3:
            raise OptionError(f"warp field {warp!r} must have 3 components per vertex, got {pd[warp].shape[1]}")
        if not np.isfinite(scale):
            raise OptionError(f"scale must be finite, got {scale}")
        v = v + float(scale) * pd[warp].astype(np.float64)
        normals = None  # the deformed shape's normals, not the undeformed ones
    rv, rf, rn, face, bary, rpd, rcd, ruv = _tessella.refine_fem(
        v,
        corners,
        mids,
        normals,
        scheme=scheme,
        level=int(level),
        alpha=alpha,
        normals_mode=normals_mode,
        backend=backend,
        weld=weld,
        point_data=list(pd.items()),
        cell_data=list(cd.items()),
        uvs=uvs,
    )
    out_pd = {name: (a[:, 0] if np.asarray(point_data[name]).ndim == 1 else a) for name, a in rpd}
    out_cd = {name: (a[:, 0] if np.asarray(cell_data[name]).ndim == 1 else a) for name, a in rcd}
    if weld and mids is not None:
        # Mid-edge nodes are corners of no refined triangle: drop them (and any other vertex
        # no coarse face uses) from the result.
        keep = face >= 0
        if not keep.all():
            remap = np.cumsum(keep) - 1
            rv, rn, face, bary = rv[keep], rn[keep], face[keep], bary[keep]
            rf = remap[rf].astype(np.uint32)
            out_pd = {k: a[keep] for k, a in out_pd.items()}
            ruv = None if ruv is None else ruv[keep]
    return RefinedMesh(rv, rf, rn, face, bary, point_data=out_pd, cell_data=out_cd, uvs=ruv)
