"""Finite-element meshes through meshio (optional dependency: ``pip install meshio``).

A volume mesh's surface is the set of tetrahedron faces that belong to exactly one
tetrahedron. Each is oriented so that its counter-clockwise normal points out of its
tetrahedron (out of the solid), whatever the file's own node order.
"""

from __future__ import annotations

import os
import tempfile
from typing import Any, Tuple

import numpy as np

from ._errors import FileFormatError, MeshError, OptionError, need

# Local faces of a positively oriented tetrahedron (a, b, c, d), each opposite one corner and
# counter-clockwise seen from outside: (b, c, d), (a, d, c), (a, b, d), (a, c, b).
_TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def _meshio() -> Any:
    return need("meshio", "this function needs meshio; install it with `pip install meshio`")


def boundary_faces(points: Any, tets: Any) -> np.ndarray:
    """The boundary triangles of a tetrahedral mesh, oriented outward.

    Parameters
    ----------
    points : array_like, (n, 3) float
    tets : array_like, (t, 4) integers (extra columns, as in 10-node tetrahedra, are ignored)

    Returns
    -------
    numpy.ndarray, int64 (m, 3)
        The faces used by exactly one tetrahedron, in tetrahedron order, counter-clockwise seen
        from outside the solid. Faces shared by two tetrahedra are interior and dropped.
    """
    tets = np.asarray(tets)
    if tets.ndim != 2 or tets.shape[1] < 4:
        raise MeshError(f"tets must have shape (t, 4), got {tets.shape}")
    faces, _ = _boundary(points, tets[:, :4])
    return faces


# 10-node tetrahedra (VTK and meshio order): the node on the edge between corners i and j.
_TET10_EDGE = np.full((4, 4), -1, dtype=np.int64)
for _k, (_i, _j) in enumerate([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]):
    _TET10_EDGE[_i, _j] = _TET10_EDGE[_j, _i] = 4 + _k


def _boundary(points: Any, tets: Any) -> Tuple[np.ndarray, np.ndarray]:
    """Outward boundary faces of ``(t, 4)`` or ``(t, 10)`` tetrahedra, as ``(m, 3)`` or
    ``(m, 6)`` (corners, then the mid-edge nodes of edges 0-1, 1-2, 2-0), and each face's
    tetrahedron."""
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets)
    if tets.ndim != 2 or tets.shape[1] not in (4, 10):
        raise MeshError(f"tets must have shape (t, 4) or (t, 10), got {tets.shape}")
    tets = tets.astype(np.int64)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise MeshError(f"points must have shape (n, 3), got {points.shape}")
    if tets.size and (tets.min() < 0 or tets.max() >= len(points)):
        raise MeshError(
            f"tets use vertex indices {tets.min()}..{tets.max()}, but there are {len(points)} points"
        )
    if points.shape[1] == 2:
        raise MeshError("tetrahedra need 3-D points, got 2-D ones")
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    # Orientation from the signed volume, so files with either node order work.
    volume = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)
    local = np.broadcast_to(_TET_FACES, (len(tets), 4, 3)).copy()  # (t, 4, 3) local corners
    flip = volume < 0
    local[flip] = local[flip][:, :, ::-1]
    rows = np.arange(len(tets))[:, None, None]
    corners = tets[rows, local]
    if tets.shape[1] == 10:
        edge_nodes = _TET10_EDGE[local, np.roll(local, -1, axis=2)]  # edges 0-1, 1-2, 2-0
        faces = np.concatenate([corners, tets[rows, edge_nodes]], axis=2).reshape(-1, 6)
    else:
        faces = corners.reshape(-1, 3)
    owner = np.repeat(np.arange(len(tets)), 4)
    key = np.sort(faces[:, :3], axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    outer = counts[inverse.reshape(-1)] == 1
    return faces[outer], owner[outer]


def _compact(points: np.ndarray, faces: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Keeps only the points the faces use (-1 entries: no node), in their original order;
    returns the kept points, the renumbered faces and the kept points' old indices."""
    used = np.unique(faces[faces >= 0])
    remap = np.full(len(points) + 1, -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return points[used], remap[faces], used


def read_fem(path: Any, *, cells: str = "auto", order: Any = "auto", fields: bool = False) -> Any:
    """Read a finite-element mesh (.msh, .vtu, .vtk, .xdmf, any format meshio reads) as a surface.

    Parameters
    ----------
    path : str or os.PathLike
    cells : {"auto", "tetra", "triangle"}
        ``"tetra"``: the boundary surface of the tetrahedra (see :func:`boundary_faces`);
        ``"triangle"``: the file's triangle cells as they are; ``"auto"``: tetrahedra when the
        file has any, else triangles.
    order : {"auto", 1, 2}
        ``"auto"``: second-order cells (``triangle6``, ``tetra10``, gmsh order 2) keep their
        mid-edge nodes, so ``faces`` has 6 columns (corners, then the nodes of edges 0-1, 1-2,
        2-0; ``-1`` for the linear faces of a mixed file) and ``tessella.refine`` builds the
        element's own curved surface; ``1``: corners only (3 columns), as before; ``2``: like
        ``"auto"`` but an error when the file has no second-order cells.
    fields : bool
        Also return the file's fields: ``(vertices, faces, point_data, cell_data)``, point data
        as ``{name: (n,) or (n, k) array}`` at the returned vertices, cell data per returned face
        (a tetrahedron's value for each of its boundary faces).

    Returns
    -------
    vertices : numpy.ndarray, float64 (n, 3)
        Only the points the surface uses (2-D points get z = 0).
    faces : numpy.ndarray, int64 (m, 3) or (m, 6)
    point_data, cell_data : dict (only with ``fields=True``)

    Raises
    ------
    MeshError, OptionError
        The file has no cells of the requested kind, or ``cells`` / ``order`` is unknown.
    FileFormatError
        The file is not one meshio reads (``OSError`` when the OS refuses to open it).
    """
    meshio = _meshio()
    _check_choices(cells, order)
    if not os.path.exists(os.fspath(path)):
        raise FileNotFoundError(f"cannot read {os.fspath(path)!r}: no such file")
    try:
        mesh = meshio.read(os.fspath(path))
    except OSError:
        raise
    except Exception as e:  # meshio raises its own ReadError for unreadable files
        raise FileFormatError(f"meshio could not read {os.fspath(path)!r}: {e}") from e
    return mesh_surface(mesh, cells=cells, order=order, fields=fields, where=repr(os.fspath(path)))


def _check_choices(cells: Any, order: Any) -> None:
    if cells not in ("auto", "tetra", "triangle"):
        raise OptionError(f"cells must be 'auto', 'tetra' or 'triangle', got {cells!r}")
    if order not in ("auto", 1, 2):
        raise OptionError(f"order must be 'auto', 1 or 2, got {order!r}")


def mesh_surface(mesh: Any, *, cells: str, order: Any, fields: bool, where: str) -> Any:
    """:func:`read_fem` on a ``meshio.Mesh`` already in memory (``where`` names it in errors)."""
    _check_choices(cells, order)
    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim == 2 and points.shape[1] == 2:
        points = np.hstack([points, np.zeros((len(points), 1))])

    def blocks(*types: str) -> list:
        return [(k, np.asarray(b.data)) for k, b in enumerate(mesh.cells) if b.type in types]

    tets = blocks("tetra", "tetra10")
    tris = blocks("triangle", "triangle6")
    use_tets = cells == "tetra" or (cells == "auto" and bool(tets))
    chosen = tets if use_tets else tris
    if not chosen:
        what = "tetrahedra" if cells == "tetra" else "triangles or tetrahedra"
        raise MeshError(f"{where} has no {what} (cell types: {_types(mesh)})")
    second = any(b.shape[1] in (6, 10) for _, b in chosen)
    if order == 2 and not second:
        raise MeshError(f"{where} has no second-order cells (cell types: {_types(mesh)})")
    keep_mids = second and order != 1
    parts, owners = [], []
    for k, b in chosen:
        if use_tets:
            f, own = _boundary(points, b if keep_mids else b[:, :4])
        else:
            f, own = (b if keep_mids else b[:, :3]).astype(np.int64), np.arange(len(b))
        if keep_mids and f.shape[1] == 3:
            f = np.hstack([f, np.full((len(f), 3), -1, dtype=np.int64)])
        parts.append(f)
        owners.append((k, own))
    faces = np.vstack(parts)
    v, faces, used = _compact(points, faces)
    if not fields:
        return v, faces
    point_data = {name: np.asarray(a)[used] for name, a in mesh.point_data.items()}
    cell_data = {}
    for name, per_block in mesh.cell_data.items():
        cell_data[name] = np.concatenate([np.asarray(per_block[k])[own] for k, own in owners])
    return v, faces, point_data, cell_data


def _types(mesh: Any) -> str:
    return ", ".join(sorted({b.type for b in mesh.cells})) or "none"


def write_fem(
    path: Any,
    vertices: Any,
    faces: Any,
    normals: Any = None,
    *,
    point_data: Any = None,
    cell_data: Any = None,
    **kwargs: Any,
) -> None:
    """Write a triangle surface with meshio (format from the extension: .vtu, .vtk, .xdmf, .msh, ...).

    ``faces`` with 6 columns are written as second-order ``triangle6`` cells (corners, then
    the nodes of edges 0-1, 1-2, 2-0). ``normals`` (n, 3), when given, is stored as point data
    ``"normals"``; ``point_data`` ({name: (n,) or (n, k)}) and ``cell_data``
    ({name: (m,) or (m, k)}) as the file's fields (ParaView shows them). XDMF is written with
    its data inline (XML) unless ``data_format`` says otherwise, so it needs no h5py. The file
    is written to a temporary file in the same folder and renamed, so a failed write never
    leaves half a file. Extra keyword arguments go to ``meshio.write`` (e.g. ``file_format``,
    ``binary``).
    """
    meshio = _meshio()
    path = os.fspath(path)
    vertices = np.asarray(vertices)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"vertices must have shape (n, 3), got {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] not in (3, 6):
        raise MeshError(f"faces must have shape (m, 3) or (m, 6), got {faces.shape}")
    out_points = {}
    if normals is not None:
        normals = np.asarray(normals)
        if normals.shape != vertices.shape:
            raise MeshError(f"normals must have shape {vertices.shape}, got {normals.shape}")
        out_points["normals"] = normals
    for name, a in (point_data or {}).items():
        a = np.asarray(a)
        if a.ndim not in (1, 2) or len(a) != len(vertices):
            raise MeshError(f"point_data {name!r} must have {len(vertices)} rows, got shape {a.shape}")
        out_points[name] = a
    out_cells = {}
    for name, a in (cell_data or {}).items():
        a = np.asarray(a)
        if a.ndim not in (1, 2) or len(a) != len(faces):
            raise MeshError(f"cell_data {name!r} must have {len(faces)} rows, got shape {a.shape}")
        out_cells[name] = [a]
    kind = "triangle6" if faces.shape[1] == 6 else "triangle"
    mesh = meshio.Mesh(vertices, [(kind, faces)], point_data=out_points, cell_data=out_cells)
    if path.lower().endswith((".xdmf", ".xmf")):
        # Inline data: one file, so the atomic rename below moves all of it.
        kwargs.setdefault("data_format", "XML")
        try:
            import h5py  # noqa: F401  (meshio's XDMF writer imports it whatever the format)
        except ImportError as e:
            raise ImportError("writing XDMF needs h5py (meshio imports it); pip install h5py") from e
    folder, name = os.path.split(os.path.abspath(path))
    # The temporary name ends with the same extension, so meshio picks the same format.
    ext = os.path.splitext(name)[1]
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=f".tmp{ext}", dir=folder)
    os.close(fd)
    try:
        meshio.write(tmp, mesh, **kwargs)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise

