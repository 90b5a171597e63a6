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

# Local faces of a positively oriented tetrahedron (a, b, c, d), each opposite one corner and
# counter-clockwise seen from outside: (b, c, d), (a, d, c), (a, b, d), (a, c, b).
_TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def _meshio() -> Any:
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - exercised only without meshio
        raise ImportError("this function needs meshio; install it with `pip install meshio`") from e
    return meshio


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
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets)
    if tets.ndim != 2 or tets.shape[1] < 4:
        raise ValueError(f"tets must have shape (t, 4), got {tets.shape}")
    tets = tets[:, :4].astype(np.int64)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (n, 3), got {points.shape}")
    if tets.size and (tets.min() < 0 or tets.max() >= len(points)):
        raise ValueError(
            f"tets use vertex indices {tets.min()}..{tets.max()}, but there are {len(points)} points"
        )
    if points.shape[1] == 2:
        raise ValueError("tetrahedra need 3-D points, got 2-D ones")
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    # Orientation from the signed volume, so files with either node order work.
    volume = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)
    faces = tets[:, _TET_FACES]  # (t, 4, 3)
    flip = volume < 0
    faces[flip] = faces[flip][:, :, ::-1]
    faces = faces.reshape(-1, 3)
    key = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return faces[counts[inverse.reshape(-1)] == 1]


def _compact(points: np.ndarray, faces: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Keeps only the points the faces use, in their original order."""
    used = np.unique(faces)
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return points[used], remap[faces]


def read_fem(path: Any, *, cells: str = "auto") -> Tuple[np.ndarray, np.ndarray]:
    """Read a finite-element mesh (.msh, .vtu, .vtk, any format meshio reads) as a surface.

    Parameters
    ----------
    path : str or os.PathLike
    cells : {"auto", "tetra", "triangle"}
        ``"tetra"``: the boundary surface of the tetrahedra (see :func:`boundary_faces`);
        ``"triangle"``: the file's triangle cells as they are; ``"auto"``: tetrahedra when the
        file has any, else triangles. 10-node tetrahedra and 6-node triangles use their corner
        nodes.

    Returns
    -------
    vertices : numpy.ndarray, float64 (n, 3)
        Only the points the surface uses (2-D points get z = 0).
    faces : numpy.ndarray, int64 (m, 3)

    Raises
    ------
    ValueError
        The file has no cells of the requested kind, or ``cells`` is unknown.
    OSError
        The file cannot be read.
    """
    meshio = _meshio()
    if cells not in ("auto", "tetra", "triangle"):
        raise ValueError(f"cells must be 'auto', 'tetra' or 'triangle', got {cells!r}")
    try:
        mesh = meshio.read(os.fspath(path))
    except OSError:
        raise
    except Exception as e:  # meshio raises its own ReadError for unreadable files
        raise OSError(f"meshio could not read {os.fspath(path)!r}: {e}") from e
    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim == 2 and points.shape[1] == 2:
        points = np.hstack([points, np.zeros((len(points), 1))])

    def blocks(*types: str) -> list:
        return [np.asarray(b.data) for b in mesh.cells if b.type in types]

    tets = blocks("tetra", "tetra10")
    tris = blocks("triangle", "triangle6")
    if cells == "tetra" or (cells == "auto" and tets):
        if not tets:
            raise ValueError(f"{os.fspath(path)!r} has no tetrahedra (cell types: {_types(mesh)})")
        faces = boundary_faces(points, np.vstack([t[:, :4] for t in tets]))
    else:
        if not tris:
            raise ValueError(
                f"{os.fspath(path)!r} has no triangles or tetrahedra (cell types: {_types(mesh)})"
            )
        faces = np.vstack([t[:, :3] for t in tris]).astype(np.int64)
    return _compact(points, faces)


def _types(mesh: Any) -> str:
    return ", ".join(sorted({b.type for b in mesh.cells})) or "none"


def write_fem(
    path: Any, vertices: Any, faces: Any, normals: Any = None, **kwargs: Any
) -> None:
    """Write a triangle surface with meshio (format from the extension: .vtu, .vtk, .msh, ...).

    ``normals`` (n, 3), when given, is stored as point data ``"normals"``. The file is written
    to a temporary file in the same folder and renamed, so a failed write never leaves half a
    file. Extra keyword arguments go to ``meshio.write`` (e.g. ``file_format``, ``binary``).
    """
    meshio = _meshio()
    path = os.fspath(path)
    vertices = np.asarray(vertices)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3), got {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError(f"faces must have shape (m, 3), got {faces.shape}")
    point_data = {}
    if normals is not None:
        normals = np.asarray(normals)
        if normals.shape != vertices.shape:
            raise ValueError(f"normals must have shape {vertices.shape}, got {normals.shape}")
        point_data["normals"] = normals
    mesh = meshio.Mesh(vertices, [("triangle", faces)], point_data=point_data)
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

