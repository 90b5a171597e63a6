"""The one thing :func:`tessella.refine` returns: a :class:`RefinedMesh`, and its converters;
and what :func:`tessella.refine_gltf` returns: a :class:`SceneReport` of
:class:`PrimitiveReport` rows.

Each converter imports its package only when it is called (trimesh, pyvista, meshio are
optional). Normals travel as the format's own normals where it has them (trimesh's
``vertex_normals``, PyVista's active ``"Normals"`` point array, meshio point data
``"normals"``, as :func:`tessella.write_fem` writes it); texture coordinates likewise
(trimesh's ``visual.uv``, PyVista's active texture coordinates, meshio point data ``"uv"``);
the fields as the format's point and cell data.
"""

from __future__ import annotations

import os
from typing import Any, Dict, Iterator, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from ._errors import need

NORMALS = "Normals"  # PyVista's and VTK's name for point normals
MESHIO_NORMALS = "normals"  # what write_fem stores
MESHIO_UVS = "uv"  # what to_meshio and save store (tessella.refine reads it back)


class RefinedMesh:
    """A refined surface: arrays and the fields carried onto it.

    Attributes
    ----------
    vertices : numpy.ndarray, float32, V  #V by 3
    faces : numpy.ndarray, uint32, F  #F by 3 (counter-clockwise)
    normals : numpy.ndarray, float32, N  #V by 3 (unit)
    uvs : numpy.ndarray, float32, #V by 2, or None
        Texture coordinates when the input had them (``None`` otherwise).
    point_data : dict of str to numpy.ndarray, float32, #V or #V by k
        ``point_data=`` fields at the refined vertices (empty when none were given).
    cell_data : dict of str to numpy.ndarray, float32, #F or #F by k
        ``cell_data=`` fields, each coarse face's value on its refined triangles.
    origin : (face, bary) or None
        With ``origin=True`` or fields: ``face`` int64 ``#V`` (each vertex's coarse triangle,
        -1 for a coarse vertex no face uses) and ``bary`` float32 ``#V by 3`` (its barycentric
        coordinates in that triangle's corner order). Also as ``.face`` and ``.bary``.

    ``v, f, n = result`` unpacks the three arrays (so code written for the old tuple keeps
    working), and ``result[0]`` .. ``result[2]`` index them.
    """

    __slots__ = ("vertices", "faces", "normals", "uvs", "point_data", "cell_data", "origin")

    def __init__(
        self,
        vertices: Any,
        faces: Any,
        normals: Any,
        face: Any = None,
        bary: Any = None,
        point_data: Optional[Dict[str, Any]] = None,
        cell_data: Optional[Dict[str, Any]] = None,
        uvs: Any = None,
    ) -> None:
        self.vertices, self.faces, self.normals = vertices, faces, normals
        self.origin: Optional[Tuple[Any, Any]] = None if face is None else (face, bary)
        self.point_data: Dict[str, Any] = {} if point_data is None else dict(point_data)
        self.cell_data: Dict[str, Any] = {} if cell_data is None else dict(cell_data)
        self.uvs = uvs

    @property
    def face(self) -> Any:
        """Each vertex's coarse triangle (``origin[0]``), or ``None``."""
        return None if self.origin is None else self.origin[0]

    @property
    def bary(self) -> Any:
        """Each vertex's barycentric coordinates (``origin[1]``), or ``None``."""
        return None if self.origin is None else self.origin[1]

    def __iter__(self) -> Iterator[Any]:
        return iter((self.vertices, self.faces, self.normals))

    def __len__(self) -> int:
        return 3

    def __getitem__(self, index: Any) -> Any:
        return (self.vertices, self.faces, self.normals)[index]

    def __repr__(self) -> str:
        extra = []
        if self.point_data:
            extra.append(f"point_data={sorted(self.point_data)}")
        if self.cell_data:
            extra.append(f"cell_data={sorted(self.cell_data)}")
        if self.uvs is not None:
            extra.append("uvs")
        if self.origin is not None:
            extra.append("origin")
        tail = (", " + ", ".join(extra)) if extra else ""
        return f"RefinedMesh({len(self.vertices)} vertices, {len(self.faces)} faces{tail})"

    # -- converters -------------------------------------------------------------------------

    def to_trimesh(self) -> Any:
        """A ``trimesh.Trimesh`` (``process=False``: vertices kept exactly, faces int64) with
        ``vertex_normals``, the uvs as ``visual.uv`` (a ``TextureVisuals``), and the fields as
        ``vertex_attributes`` / ``face_attributes``."""
        trimesh = need("trimesh")
        visual = None if self.uvs is None else trimesh.visual.TextureVisuals(uv=np.asarray(self.uvs))
        return trimesh.Trimesh(
            vertices=np.asarray(self.vertices),
            faces=np.asarray(self.faces, dtype=np.int64),
            vertex_normals=np.asarray(self.normals),
            vertex_attributes=dict(self.point_data),
            face_attributes=dict(self.cell_data),
            visual=visual,
            process=False,
        )

    def to_pyvista(self) -> Any:
        """A ``pyvista.PolyData`` with point array ``"Normals"`` (the active normals), the uvs
        as its active texture coordinates, and the fields as point and cell data (the first
        point field is the active scalars)."""
        pv = need("pyvista")
        faces = np.asarray(self.faces, dtype=np.int64)
        cells = np.hstack([np.full((len(faces), 1), 3, dtype=np.int64), faces]).ravel()
        mesh = pv.PolyData(np.asarray(self.vertices), cells)
        for name, a in self.point_data.items():
            mesh.point_data[name] = np.asarray(a)
        for name, a in self.cell_data.items():
            mesh.cell_data[name] = np.asarray(a)
        mesh.point_data[NORMALS] = np.asarray(self.normals)
        mesh.point_data.active_normals_name = NORMALS
        if self.uvs is not None:
            mesh.active_texture_coordinates = np.asarray(self.uvs)
        if self.point_data:
            mesh.set_active_scalars(next(iter(self.point_data)), preference="point")
        return mesh

    def to_meshio(self) -> Any:
        """A ``meshio.Mesh`` with one ``"triangle"`` block, point data ``"normals"`` (and
        ``"uv"`` when there are uvs) and the fields as point and cell data."""
        meshio = need("meshio")
        point_data = {MESHIO_NORMALS: np.asarray(self.normals)}
        if self.uvs is not None:
            point_data[MESHIO_UVS] = np.asarray(self.uvs)
        point_data.update({k: np.asarray(a) for k, a in self.point_data.items()})
        cell_data = {k: [np.asarray(a)] for k, a in self.cell_data.items()}
        return meshio.Mesh(
            np.asarray(self.vertices),
            [("triangle", np.asarray(self.faces, dtype=np.int64))],
            point_data=point_data,
            cell_data=cell_data,
        )

    def save(self, path: Union[str, "os.PathLike[str]"], **kwargs: Any) -> None:
        """Write the mesh; the format follows the extension.

        ``.obj``, ``.ply``, ``.gltf``, ``.glb``, ``.stl``: tessella's own writers
        (:func:`tessella.save`, with the uvs where the format has texture coordinates; fields
        are not stored). Anything else (``.vtu``, ``.vtk``, ``.xdmf``, ``.msh``, ...): meshio
        (:func:`tessella.write_fem`), with normals, the uvs as point data ``"uv"`` and the
        fields. Both write a temporary file and rename it, so a failure leaves no half file.
        """
        from . import _tessella
        from ._fem import write_fem

        ext = os.path.splitext(os.fspath(path))[1].lower()
        if ext in (".obj", ".ply", ".gltf", ".glb", ".stl"):
            uvs = None if self.uvs is None else np.ascontiguousarray(self.uvs, dtype=np.float32)
            _tessella.save(os.fspath(path), self.vertices, self.faces, self.normals, uvs=uvs, **kwargs)
        else:
            point_data = dict(self.point_data)
            if self.uvs is not None:
                point_data[MESHIO_UVS] = np.asarray(self.uvs)
            write_fem(
                path,
                self.vertices,
                self.faces,
                self.normals,
                point_data=point_data,
                cell_data=self.cell_data,
                **kwargs,
            )


class PrimitiveReport(NamedTuple):
    """What refining one triangle primitive of a glTF scene made (one row of a
    :class:`SceneReport`).

    ``mesh`` and ``primitive`` index the document's ``meshes`` and that mesh's
    ``primitives``; ``level`` is the primitive's level (segments per coarse edge);
    ``coarse_triangles`` its triangles as read, ``degenerate`` the zero-area ones among them
    (refined flat); ``vertices`` and ``triangles`` what was written
    (``triangles = coarse_triangles * level**2``); ``notes`` anything carried by a fallback (a
    morph target whose shape could not be refined)."""

    mesh: int
    primitive: int
    level: int
    coarse_triangles: int
    degenerate: int
    vertices: int
    triangles: int
    notes: Tuple[str, ...] = ()


class SceneReport:
    """What :func:`tessella.refine_gltf` did: one :class:`PrimitiveReport` per triangle
    primitive of the scene (mesh by mesh, in the document's order; points and lines are
    copied, not refined, and have none).

    Attributes
    ----------
    path : str or None
        The file written (``None`` for :func:`tessella.refine_gltf_bytes`'s scene).
    primitives : list of PrimitiveReport
    warnings : list of str
        What the writer could not do but did not fail on (an image named by a relative URI
        that is missing beside the input, so not copied beside the output).
    levels : list of int
        The distinct levels used, ascending.
    coarse_triangles, triangles, vertices : int
        Sums over the primitives.

    ``len(report)``, ``report[i]`` and ``for row in report`` go through ``primitives``.
    """

    __slots__ = ("path", "primitives", "warnings")

    def __init__(
        self, path: Optional[str], primitives: Sequence[PrimitiveReport], warnings: Sequence[str] = ()
    ) -> None:
        self.path = path
        self.primitives: List[PrimitiveReport] = list(primitives)
        self.warnings: List[str] = list(warnings)

    @property
    def levels(self) -> List[int]:
        return sorted({p.level for p in self.primitives})

    @property
    def coarse_triangles(self) -> int:
        return sum(p.coarse_triangles for p in self.primitives)

    @property
    def triangles(self) -> int:
        return sum(p.triangles for p in self.primitives)

    @property
    def vertices(self) -> int:
        return sum(p.vertices for p in self.primitives)

    def __iter__(self) -> Iterator[PrimitiveReport]:
        return iter(self.primitives)

    def __len__(self) -> int:
        return len(self.primitives)

    def __getitem__(self, index: int) -> PrimitiveReport:
        return self.primitives[index]

    def __repr__(self) -> str:
        levels = "/".join(str(level) for level in self.levels) or "-"
        where = "" if self.path is None else f", path={self.path!r}"
        return (
            f"SceneReport({len(self.primitives)} primitives, level {levels}, "
            f"{self.coarse_triangles} -> {self.triangles} triangles{where})"
        )
