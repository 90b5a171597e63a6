"""Mesh objects of other libraries as tessella's arrays: ``trimesh.Trimesh``,
``pyvista.PolyData`` / ``UnstructuredGrid`` (its surface) and ``meshio.Mesh``.

Objects are recognised by their class names, so none of those packages is imported here.
Each gives ``(vertices, faces, normals or None, point_data, cell_data, uvs or None)``.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np

from ._errors import MeshError

Arrays = Tuple[Any, Any, Optional[Any], Dict[str, Any], Dict[str, Any], Optional[Any]]

#: meshio point data taken as texture coordinates (the first present with 2 columns).
MESHIO_UV_NAMES = ("uv", "uvs", "UV", "texcoords", "TCoords", "obj:vt")

# Arrays VTK adds on its own (surface extraction's bookkeeping, normals): not user fields.
_VTK_BOOKKEEPING = ("vtkOriginalPointIds", "vtkOriginalCellIds", "Normals", "TCoords")


def _kind(obj: Any) -> Optional[str]:
    for c in type(obj).__mro__:
        module = c.__module__ or ""
        if c.__name__ == "Trimesh" and module.startswith("trimesh"):
            return "trimesh"
        if module.startswith("pyvista") and c.__name__ in ("PolyData", "UnstructuredGrid", "DataSet"):
            return "pyvista"
        if c.__name__ == "Mesh" and module.startswith("meshio"):
            return "meshio"
    return None


def is_mesh_object(obj: Any) -> bool:
    """Whether ``obj`` is a mesh of a library :func:`arrays` reads."""
    return _kind(obj) is not None


def arrays(obj: Any) -> Arrays:
    """The arrays and fields of a mesh object (see the module docs)."""
    kind = _kind(obj)
    if kind == "trimesh":
        return _from_trimesh(obj)
    if kind == "pyvista":
        return _from_pyvista(obj)
    if kind == "meshio":
        return _from_meshio(obj)
    raise TypeError(f"not a mesh object tessella reads: {type(obj).__name__}")


def _from_trimesh(mesh: Any) -> Arrays:
    # Normals only when the mesh holds them (given, or loaded from a file); trimesh would
    # otherwise compute its own average, and tessella computes angle-weighted ones.
    cache = getattr(mesh, "_cache", None)
    normals = None
    if cache is not None and "vertex_normals" in cache:
        normals = np.asarray(mesh.vertex_normals)
    point_data = {k: np.asarray(a) for k, a in dict(getattr(mesh, "vertex_attributes", {})).items()}
    cell_data = {k: np.asarray(a) for k, a in dict(getattr(mesh, "face_attributes", {})).items()}
    uv = getattr(getattr(mesh, "visual", None), "uv", None)  # TextureVisuals only
    uvs = None if uv is None else np.asarray(uv)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces), normals, point_data, cell_data, uvs


def _from_pyvista(mesh: Any) -> Arrays:
    if type(mesh).__name__ != "PolyData":
        try:
            mesh = mesh.extract_surface(algorithm="dataset_surface")
        except TypeError:  # PyVista before the `algorithm` keyword
            mesh = mesh.extract_surface()
    if mesh.n_cells == 0:
        raise MeshError(f"the {type(mesh).__name__} has no surface cells to refine")
    if not mesh.is_all_triangles:
        mesh = mesh.triangulate()
    faces = np.asarray(mesh.faces).reshape(-1, 4)[:, 1:]
    normals = None
    name = mesh.point_data.active_normals_name
    if name is not None:
        normals = np.asarray(mesh.point_data[name])
    point_data = {
        k: np.asarray(mesh.point_data[k]) for k in mesh.point_data.keys()
        if k not in _VTK_BOOKKEEPING and k != name
    }
    cell_data = {
        k: np.asarray(mesh.cell_data[k]) for k in mesh.cell_data.keys() if k not in _VTK_BOOKKEEPING
    }
    uv = getattr(mesh, "active_texture_coordinates", None)
    uvs = None if uv is None else np.asarray(uv)
    return np.asarray(mesh.points), faces, normals, point_data, cell_data, uvs


def _from_meshio(mesh: Any) -> Arrays:
    from ._fem import mesh_surface

    v, f, point_data, cell_data = mesh_surface(mesh, cells="auto", order="auto", fields=True, where="the meshio.Mesh")
    normals = None
    for name in ("normals", "Normals"):
        if name in point_data:
            normals = point_data.pop(name)
            break
    uvs = None
    for name in MESHIO_UV_NAMES:
        if name in point_data and np.ndim(point_data[name]) == 2 and np.shape(point_data[name])[1] == 2:
            uvs = point_data.pop(name)
            break
    return v, f, normals, point_data, cell_data, uvs
