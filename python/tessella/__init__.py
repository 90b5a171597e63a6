"""tessella: turn coarse triangle meshes into smooth curved surfaces.

Each coarse triangle is replaced by a curved patch (Phong tessellation, PN triangles, ...)
sampled with a *refinement pattern* of ``level`` segments per edge (``level**2`` small
triangles per coarse triangle). The work runs in Rust, in parallel, with the GIL released.

Conventions
-----------
- ``vertices``: ``(n, 3)`` float32 or float64 points. float64 is rounded to float32 (integer
  arrays are converted too).
- ``faces``: ``(m, 3)`` integer vertex indices (int8..int64, uint8..uint64), counter-clockwise
  seen from the side the normals face. Indices must lie in ``0 .. n-1``.
- ``normals``: ``(n, 3)`` float32/float64 (or integer) vertex normals (normalised on input), or ``None`` to
  compute angle-weighted normals.
- Any array-like is accepted (lists go through ``numpy.asarray``); C order, Fortran order and
  strided views are all read as they are, without a copy first.
- Results are a :class:`RefinedMesh` of fresh C-ordered arrays: vertices and normals
  ``float32 (n, 3)``, faces ``uint32 (m, 3)``; it unpacks as ``v, f, n`` and converts with
  ``to_trimesh()``, ``to_pyvista()``, ``to_meshio()`` and ``save(path)``.

Errors
------
Errors about your input are :class:`TessellaError` (a ``ValueError``) subclasses carrying the
core's message: :class:`MeshError` (NaN positions, indices out of range, degenerate triangles,
zero normals, wrong shapes, fields that do not fit), :class:`OptionError` (unknown names, level
< 1, output over the 8 GiB limit, bad tags, ``lod``, ``camera`` or ``displace``, options that
cannot be combined), :class:`FileFormatError` (broken or unsupported files) and
:class:`GpuError` (no adapter for ``backend="gpu"``, the GPU failing; also a ``RuntimeError``).
Besides: ``TypeError`` for unsupported dtypes and option types, ``OSError`` when the OS refuses
a file, ``ImportError`` for a converter whose package (trimesh, pyvista, meshio) is missing.

Whole glTF scenes (nodes, materials, animations kept): :func:`refine_gltf` and
:func:`refine_gltf_bytes`.

What this build has: :func:`schemes`; what works on this machine: :func:`backends` and
:func:`gpu_info`.
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _fields, _inputs, _options, _tessella
from ._errors import FileFormatError, GpuError, MeshError, OptionError, TessellaError
from ._options import Camera, Displace, Lod
from ._result import PrimitiveReport, RefinedMesh, SceneReport
from ._tessella import AnimatedMesh, __version__, backends, gpu_info, info, load, load_animated, pattern, save, schemes
from ._types import BackendName, NormalsMode, SchemeName, Spacing, ViewOptions

if sys.version_info >= (3, 11):
    from typing import Unpack
elif TYPE_CHECKING:
    from typing_extensions import Unpack

#: What ``tags=`` accepts: a dict in the sidecar-JSON structure, that JSON as a string, or the
#: path of a JSON file (see :func:`refine`).
TagsLike = Union[Dict[str, Any], str, "os.PathLike[str]", None]

#: What ``displace=`` accepts: ``None``, ``{"kind": "sine", "amplitude": a, "frequency": f}``,
#: ``{"kind": "perlin", "amplitude": a, "frequency": f, "seed": s}`` or a tuple
#: ``(kind, amplitude, frequency[, seed])`` (see :func:`refine`).
DisplaceLike = Union["Displace", Dict[str, Any], Tuple[Any, ...], List[Any], None]

__all__ = [
    "__version__",
    "Camera",
    "Displace",
    "FileFormatError",
    "GpuError",
    "Lod",
    "MeshError",
    "OptionError",
    "RefinedMesh",
    "TessellaError",
    "plot",
    "backends",
    "gpu_info",
    "info",
    "load",
    "load_animated",
    "AnimatedMesh",
    "pattern",
    "quality",
    "refine",
    "RefineResult",
    "render",
    "Refiner",
    "refine_trimesh",
    "save",
    "schemes",
    "to_trimesh",
    "read_fem",
    "write_fem",
    "boundary_faces",
    "batch",
    "refine_file",
    "refine_gltf",
    "refine_gltf_bytes",
    "SceneReport",
    "PrimitiveReport",
    "refine_to_file",
    "sync_folder",
    "release_memory",
    "set_memory_reuse",
    "reusable_bytes",
]


def refine(
    vertices: Any,
    faces: Any = None,
    normals: Any = None,
    *,
    scheme: Optional[SchemeName] = None,
    level: Union[int, float] = 8,
    alpha: float = 0.75,
    normals_mode: Optional[NormalsMode] = None,
    tags: TagsLike = None,
    crease_angle: Optional[float] = None,
    backend: BackendName = "auto",
    weld: bool = True,
    displace: DisplaceLike = None,
    spacing: Spacing = "grid",
    lod: Union[Lod, str, Dict[str, Any], None] = None,
    camera: Union[Camera, str, Tuple[float, ...], List[float], None] = None,
    size: Optional[Tuple[int, int]] = None,
    origin: bool = False,
    point_data: Optional[Dict[str, Any]] = None,
    cell_data: Optional[Dict[str, Any]] = None,
    warp: Optional[str] = None,
    scale: float = 1.0,
    uvs: Any = None,
) -> RefinedMesh:
    """Refine a triangle mesh into a curved one.

    Parameters
    ----------
    vertices : array_like, (n, 3) float32/float64, or a mesh object
        Coarse vertex positions. A ``trimesh.Trimesh``, ``pyvista.PolyData`` /
        ``UnstructuredGrid`` (its surface) or ``meshio.Mesh`` here (with ``faces`` left
        ``None``) gives its vertices, faces, normals, texture coordinates (trimesh's
        ``visual.uv``, PyVista's active texture coordinates, meshio point data ``"uv"``,
        ``"uvs"``, ``"texcoords"``, ``"TCoords"`` or ``"obj:vt"``), and its point and cell
        data as ``point_data`` / ``cell_data``. Options that take no fields (``tags``,
        ``crease_angle``, ``displace``, ``spacing``, ``lod``, ``camera``, ``size``) refuse an
        object that has fields (:class:`OptionError`); pass its arrays to refine without them.
    faces : array_like, (m, 3) or (m, 6) integers
        Counter-clockwise triangles (vertex indices). Six columns: second-order (6-node)
        finite elements, the corners then the mid-edge nodes of edges 0-1, 1-2, 2-0 (gmsh, VTK
        and meshio order; ``-1`` in all three for a linear face of a mixed mesh); the
        ``"quadratic"`` scheme (their default) refines each into its exact isoparametric P2
        surface. Mid-edge nodes are dropped from the result's vertices.
    normals : array_like, (n, 3) float32/float64, optional
        Vertex normals; ``None`` computes angle-weighted normals. Curved schemes bend the
        surface to follow them, so they matter: pass the true normals when you know them.
    scheme : str
        One of :func:`schemes`: ``"flat"`` (the input triangles), ``"phong"`` (Phong
        tessellation, Boubekeur & Alexa 2008), ``"pn"`` (curved PN triangles, Vlachos et al.
        2001), ``"png1"`` (PNG1 triangles, Fünfzig et al. 2008: tangent-plane continuous
        across edges, built from each triangle and its edge neighbours), ``"pn-aen"`` (PN with
        adjacent edge normals, McDonald & Kilgard 2010: no cracks where normals are split) or
        ``"st"`` (scalar-tagged PN, GMR Appendix B: creases and per-vertex shape tags; no tags
        gives PN), ``"quadratic"`` (second-order finite elements: 6-column ``faces``). ``None``:
        ``"quadratic"`` for 6-column faces, else ``"pn"``. Names are case-insensitive.
    level : int
        Segments per coarse edge, 1 or more: each coarse triangle becomes ``level**2``
        triangles.
    alpha : float
        Phong shape factor (0 = flat, 1 = full projection; 0.75 is the paper's default).
        Ignored by other schemes.
    normals_mode : {"linear", "quadratic", "real"} or None
        How output normals are made: interpolated linearly, Vlachos' quadratic normals, or the
        patch's own surface normal. ``None`` is the scheme's default (linear for flat/Phong,
        quadratic for PN).
    tags : dict, str, os.PathLike or None
        Shape tags for ``"st"`` (all of them) and ``"png1"`` (edges with ``sharpness > 0`` are
        sharp, displaced by ``kappa``); other schemes check and ignore them. A dict in the
        sidecar-JSON structure (vertex indices of this mesh; every field but ``vertices`` /
        ``index`` optional, missing numbers are 0)::

            {"edges": [{"vertices": [a, b], "sharpness": 1.0, "kappa": 0.0}],
             "vertices": [{"index": i, "tension": 0.0, "sharpness": 0.5, "bias": 0.0,
                           "crease": [x, y, z]}]}

        or that JSON as a string (first non-blank character ``{``), or the path of such a
        file (any other string, or an ``os.PathLike``). Numpy numbers and arrays in the dict
        are fine. Layering, as the CLI's: for ``"st"`` the edges where the normals are split
        (the same position with different normals) become creases first, then
        ``crease_angle``, then ``tags``; a later source overrides an earlier one on the same
        edge or vertex.
    crease_angle : float or None
        Also crease every edge whose two faces bend by more than this many degrees (0..180).
    backend : {"auto", "cpu", "gpu", "gl"}
        Where the refinement runs. ``"gl"``: the OpenGL 4 hardware tessellator (tessellation
        shaders through EGL; Mesa's llvmpipe without a GPU), with ``spacing="equal"``,
        ``"fractional-odd"`` or ``"fractional-even"`` only (``ValueError`` otherwise, and in a
        package built without the ``gl`` cargo feature; ``RuntimeError`` without an EGL
        driver); its output is an unwelded soup (vertex ``3t + i`` is corner ``i`` of triangle
        ``t``, whatever ``weld``), the CPU's vertices within float rounding. ``"cpu"``: the CPU, on all cores. ``"gpu"``: the GPU
        through wgpu (Vulkan, Metal or DX12), on any adapter, software ones such as Mesa's
        lavapipe included; ``RuntimeError`` when there is none (see :func:`backends` and
        :func:`gpu_info`). ``"auto"``: a hardware GPU when there is one, else the CPU (a
        software adapter is slower than the CPU path); if the GPU fails it refines on the CPU
        and emits a ``RuntimeWarning``. The GPU gives the same faces as the CPU and the same
        vertices and normals to float rounding (about 1e-7 relative), so ``"auto"`` equals
        ``"cpu"`` bit for bit only where it runs on the CPU. The GPU device is opened once
        per process and reused; the GIL is released while it works.
    weld : bool
        ``True``: refined patches share the vertices on shared coarse corners and edges (a
        watertight mesh where the input is). ``False``: each coarse triangle gets its own
        ``(level+1)(level+2)/2`` vertices.
    displace : Displace, dict, tuple or None
        Moves every refined vertex along its unit normal ``n``, after evaluation (GMR section
        4), on the chosen backend: ``P + d(P) n``: :meth:`Displace.sine`,
        :meth:`Displace.perlin`, or the dict forms::

            {"kind": "sine", "amplitude": a, "frequency": f}                 # d = a sin(f |P|)
            {"kind": "perlin", "amplitude": a, "frequency": f, "seed": s}    # d = a noise(f P)

        where ``noise`` is Perlin's improved noise (2002, values in about -1..1) with a
        permutation shuffled by the whole number ``s`` (0..2**32-1, optional, default 0), or
        the tuples (or lists) ``("sine", a, f)`` and ``("perlin", a, f[, s])``. Numbers must be
        finite.
        Normals are returned as evaluated (the undisplaced surface's). In welded output a
        vertex shared by coarse triangles moves once, so the surface stays closed. Height maps
        (the CLI's ``--displace heightmap:``) need texture coordinates and are not offered here.

    spacing : {"grid", "equal", "fractional-odd", "fractional-even"}
        How a level divides each coarse edge: the uniform grid, or the GPU tessellator's
        spacings (``level`` may then be a float such as 5.5, clamped to the spacing's range
        as the hardware does: equal 1..64, fractional-odd 1..63, fractional-even 2..64).
    lod : Lod, str, dict or None
        Per-edge adaptive levels, crack-free (each coarse edge's level from that edge alone):
        :meth:`Lod.tolerance`, :meth:`Lod.screen`, :meth:`Lod.distance`, or the shorthands
        ``"tolerance:D"`` / ``{"kind": "tolerance", "max_deviation": D}`` (flat triangles
        within D of the curved surface), ``"screen:PX"`` / ``{"kind": "screen", "pixels": PX}``
        (needs ``camera`` and ``size``), ``"distance:NEAR,FAR,MAX"`` /
        ``{"kind": "distance", "near": .., "far": .., "max": ..}`` (needs ``camera``).
        Overrides ``level``.
    camera : Camera, str or sequence of 7 numbers
        A :class:`Camera`, or ``(eye_x, eye_y, eye_z, target_x, target_y, target_z, fov_deg)``,
        for string or dict ``lod`` forms (a :class:`Lod` carries its own).
    size : (int, int)
        Image width and height in pixels for ``lod="screen:PX"``.
    origin : bool
        Fill the result's ``origin = (face, bary)``: each
        refined vertex's coarse triangle and barycentric coordinates in its corner order (for
        mapping finite-element fields), with any levels and any backend but ``"gl"``.
        ``displace`` needs a whole level on the grid (no ``spacing``, fractional level or
        ``lod``); ``backend="gl"`` takes no ``origin``, ``uvs`` or ``displace``. Those are the
        core's rules, the CLI's and npm's too.
    point_data : dict of str to array_like (n,) or (n, k), optional
        Per-vertex fields (temperature, displacement, ...) carried to every refined vertex with
        its coarse face's own basis: linear on 3-node faces, the 6 quadratic shape functions on
        6-node faces. The result's ``point_data`` has the same names.
    cell_data : dict of str to array_like (m,) or (m, k), optional
        Per-face fields, copied to each refined triangle of the face (``cell_data`` of the result).
    warp : str, optional
        A 3-component ``point_data`` field to move the coarse vertices by before refining
        (ParaView's "warp by vector"): the curved surface follows the deformed shape.
    scale : float
        The factor of ``warp``.
    uvs : array_like, UV  #V by 2 floats, optional
        Texture coordinates, interpolated linearly over each coarse triangle (in its corner
        order) onto the refined vertices: the result's ``uvs``, ``#RV by 2`` float32. Not with
        ``backend="gl"``.

    Returns
    -------
    RefinedMesh
        ``vertices`` float32 ``(N, 3)``, ``faces`` uint32 ``(M, 3)`` (``M = m * level**2``;
        welded output starts with the ``n`` input vertices, unchanged), unit ``normals``
        float32 ``(N, 3)``; ``uvs``, ``point_data``, ``cell_data`` and ``origin`` (face, bary)
        when asked for. ``v, f, n = result`` unpacks the three arrays.

    Raises
    ------
    MeshError, OptionError, FileFormatError, GpuError, TypeError, OSError
        See the module's "Errors" section. Options that cannot be combined are an
        :class:`OptionError` saying ``refine(): A cannot be combined with B (why)``.

    Examples
    --------
    >>> import numpy as np, tessella
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
    >>> f = np.array([[0, 1, 2]])
    >>> rv, rf, rn = tessella.refine(v, f, scheme="flat", level=2)
    >>> rv.shape, rf.shape, rf.dtype.name
    ((6, 3), (4, 3), 'uint32')
    >>> wave = {"kind": "sine", "amplitude": 0.1, "frequency": np.pi / 2}
    >>> rv, rf, rn = tessella.refine(v, f, scheme="flat", level=1, displace=wave, backend="cpu")
    >>> rv[1]  # (1, 0, 0) moved by 0.1 sin(pi/2 * 1) along its normal (0, 0, 1)
    array([1. , 0. , 0.1], dtype=float32)
    """
    fields_from = None
    if faces is None and _inputs.is_mesh_object(vertices):
        kind = type(vertices).__name__
        vertices, faces, normals, point_data, cell_data, uvs, names = _from_object(
            vertices, normals, point_data, cell_data, uvs,
        )
        if names:
            fields_from = f"the {kind}'s point/cell data {names}"
    if faces is None:
        raise MeshError("refine(vertices, faces, ...) needs faces, an (m, 3) integer array (or a mesh object)")
    fem = point_data is not None or cell_data is not None or warp is not None or _six_columns(faces)
    if fem:
        _options.check_fields(
            spacing=spacing, lod=lod, camera=camera, size=size, tags=tags, crease_angle=crease_angle,
            displace=displace, fields_from=fields_from,
        )
    # What both paths (fields, and the plain surface) take alike.
    shared: Dict[str, Any] = dict(
        alpha=alpha, normals_mode=normals_mode, weld=weld, uvs=None if uvs is None else _uv_rows(uvs)
    )
    if fem:
        return _fields.refine_fem(
            vertices, faces, normals, scheme=scheme, level=level, backend=backend, point_data=point_data,
            cell_data=cell_data, warp=warp, scale=scale, **shared,
        )
    if scheme is None:
        scheme = "pn"
    # Every other option, and which of them cannot go together, the compiled module checks
    # with the core's rules (the CLI's and npm's).
    lod_text, camera_text, size_pair = _options.lod_spec(lod, camera, size)
    v, f, n, face, bary, ruv = _tessella.refine(
        vertices, faces, normals, scheme=scheme, level=level, spacing=spacing, lod=lod_text,
        camera=camera_text, size=size_pair, tags=tags, crease_angle=crease_angle, backend=backend,
        displace=_options.displace_spec(displace), origin=origin, **shared,
    )
    return RefinedMesh(v, f, n, face, bary, uvs=ruv)


#: The old name of :class:`RefinedMesh` (what ``origin=True`` and fields returned).
RefineResult = RefinedMesh


def _from_object(
    obj: Any, normals: Any, point_data: Any, cell_data: Any, uvs: Any
) -> Tuple[Any, Any, Any, Any, Any, Any, List[str]]:
    """A mesh object's arrays and uvs (where the caller gave none of their own), its numeric
    fields (where the caller gave none), and the names of the fields taken from it."""
    v, f, n, pd, cd, uv = _inputs.arrays(obj)
    if normals is None:
        normals = n
    if uvs is None:
        uvs = uv
    numeric = lambda d: {  # noqa: E731
        k: a for k, a in d.items()
        if np.issubdtype(np.asarray(a).dtype, np.number) and np.asarray(a).ndim in (1, 2)
        and not np.issubdtype(np.asarray(a).dtype, np.complexfloating)
    }
    names: List[str] = []
    if point_data is None and numeric(pd):
        point_data = numeric(pd)
        names += sorted(point_data)
    if cell_data is None and numeric(cd):
        cell_data = numeric(cd)
        names += sorted(cell_data)
    return v, f, normals, point_data, cell_data, uvs, names


def _uv_rows(uvs: Any) -> np.ndarray:
    """``uvs`` as a float32 C-ordered ``(n, 2)`` array (its row count is checked by the core)."""
    a = np.asarray(uvs)
    if a.ndim != 2 or a.shape[1] != 2:
        raise MeshError(f"uvs must have shape (n, 2), got {a.shape}")
    if not np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.complexfloating):
        raise TypeError(f"uvs must hold real numbers, got dtype {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float32)


def _six_columns(faces: Any) -> bool:
    shape = getattr(faces, "shape", None)
    if shape is None:
        shape = np.shape(faces)
    return len(shape) == 2 and shape[1] == 6


class Refiner(_tessella.Refiner):
    """Refine one mesh topology frame after frame: a deforming mesh, without re-planning.

    ``Refiner(F, *, vertices=V, normals=N, ...)`` plans at construction: the coarse triangles,
    the options and the first frame's mesh (which vertices share a position, the tags) are
    checked and turned into a plan there, so every mistake is raised by the constructor. Each
    ``refine(V, N=None)`` then refines one frame of vertex positions: it recomputes only the
    coarse control nets (proportional to the coarse mesh) and evaluates the refined vertices,
    optionally into arrays you own (``out=``), with the GIL released. Every frame's result is
    what :func:`refine` gives for that frame's vertices (bit for bit on the CPU).

    Without ``vertices=`` (the older form ``Refiner(F)``) the faces and options are still
    checked at construction, and the plan is built by the first ``refine`` call from its mesh;
    an error there builds nothing, so the next call is a first call again.

    Parameters
    ----------
    faces : array_like, F  #F by 3 integers
        Counter-clockwise triangles (vertex indices), as for :func:`refine`.
    vertices : array_like, V  #V by 3 floats, optional
        The first frame (later frames must have as many vertices; keep coincident vertices
        coincident, since ``"png1"``, ``"pn-aen"`` and ``"st"`` look across them).
    normals : array_like, N  #V by 3 floats, optional
        The first frame's normals (``None``: computed).
    scheme, level, alpha, normals_mode, tags, crease_angle, weld
        As for :func:`refine`.
    backend : {"auto", "cpu", "gpu"}
        Where frames are refined. ``"gpu"``: the GPU through wgpu, any adapter (a
        :class:`GpuError` without one); the kernels are compiled and the plan uploaded once,
        each frame uploads its coarse nets and reads the vertices back; the vertices equal the
        CPU's to float rounding. ``"auto"``: a hardware GPU when there is one, else the CPU.
        The ``backend`` attribute says which one was chosen once the plan is built.

    Attributes
    ----------
    vertex_count : int or None
        Refined vertices per frame; ``None`` until planned.
    triangle_count : int
        Refined triangles per frame, ``#F * level**2``.
    faces : numpy.ndarray, uint32 (triangle_count, 3), read-only, or None
        The refined triangles, computed once: the **same** read-only array object is returned
        by every ``refine`` call (``faces.copy()`` for a writable one); ``None`` until planned.
    level : int
    scheme : str
        The scheme's name as :func:`schemes` spells it.
    weld : bool
    backend : str
        ``"cpu"`` or ``"gpu"`` once planned, the asked-for name before.

    Methods
    -------
    refine(vertices, normals=None, *, out=None) -> (vertices, faces, normals)
        ``vertices``: ``#V by 3`` positions of this frame; ``normals``: ``#V by 3`` or
        ``None`` to compute them from this frame. Without ``out``, returns fresh float32
        ``(vertex_count, 3)`` vertices and normals. With ``out=(v, n)``, writes into ``v`` and
        ``n`` (float32, shape ``(vertex_count, 3)``, C-contiguous, writable, two separate
        arrays; else :class:`OptionError` naming the problem) and returns ``(v, faces, n)``:
        the same objects, no new arrays. A bad frame (another vertex count, NaN or infinite
        positions, zero normals, a degenerate triangle) raises :class:`MeshError` and changes
        nothing: the refiner keeps its previous frame and ``out`` is not written.

    Pickling and processes
    ----------------------
    A ``Refiner`` pickles as its arguments and the mesh its plan was built from; unpickling
    rebuilds the plan (and reopens the GPU in that process), so a refiner sent to a
    ``multiprocessing`` worker (``spawn`` included) refines to the same arrays as in the parent.

    One ``Refiner`` refines one frame at a time: a second thread calling ``refine`` on the same
    object while one runs gets ``RuntimeError`` (already borrowed); use one refiner per thread.

    Examples
    --------
    >>> import numpy as np, tessella
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> r = tessella.Refiner(f, vertices=v, scheme="pn", level=4, backend="cpu")
    >>> r.vertex_count, r.triangle_count, r.backend
    (34, 64, 'cpu')
    >>> rv, rf, rn = r.refine(v)
    >>> rf is r.faces
    True
    >>> out = (np.empty_like(rv), np.empty_like(rn))
    >>> for t in range(3):                            # a deforming mesh, no new arrays
    ...     pv, pf, pn = r.refine(v * (1 + 0.1 * t), out=out)
    >>> pv is out[0], pn is out[1]
    (True, True)
    >>> bool(np.array_equal(pv, tessella.refine(v * (1 + 0.1 * 2), f, scheme="pn", level=4)[0]))
    True
    """

    __slots__ = ()

    def __reduce__(self) -> Tuple[Any, ...]:
        faces, kwargs, planned = self._state()
        return (_rebuild_refiner, (type(self), faces, kwargs, planned))


def _rebuild_refiner(cls: Any, faces: Any, kwargs: Dict[str, Any], planned: Any) -> "Refiner":
    """Unpickles a :class:`Refiner`: the same arguments, the plan rebuilt from the same mesh."""
    if planned is not None:
        kwargs = dict(kwargs, vertices=planned[0], normals=planned[1])
    refiner: Refiner = cls(faces, **kwargs)
    return refiner


def quality(
    vertices: Any,
    faces: Any,
    normals: Any = None,
    *,
    scheme: SchemeName = "pn",
    level: int = 8,
    alpha: float = 0.75,
    tags: TagsLike = None,
    crease_angle: Optional[float] = None,
) -> Dict[str, Any]:
    """Measure a scheme's curved surface on a mesh (float64 evaluation of its patches).

    Parameters are :func:`refine`'s. ``level`` (1..256) only sets the pattern that samples the
    distance from the coarse mesh; the edge measurements do not depend on it.

    Returns
    -------
    dict
        - ``scheme`` (str), ``level`` (int)
        - ``edges_checked``: coarse edges with two faces (by position) that were compared;
          ``samples_per_edge``: points compared along each (ends excluded).
        - ``normal_jump_max_deg``, ``normal_jump_mean_deg``: angle between the two sides'
          surface normals across coarse edges, the G1 defect (PNG1 ~0, PN degrees).
        - ``gap_max``, ``gap_max_relative``: largest distance between the two sides' points
          along a coarse edge (cracks; PN opens them where normals are split, PN-AEN does not).
        - ``distance_max``, ``distance_max_relative``: largest distance of a refined point from
          the flat triangle's point at the same barycentric coordinates.
        - ``diagonal``: the coarse mesh's bounding-box diagonal (the ``*_relative`` values are
          divided by it).

    Raises
    ------
    ValueError, TypeError, OSError
        As :func:`refine`; ``ValueError`` also for ``level > 256``.

    Examples
    --------
    >>> import numpy as np, tessella
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    >>> q = tessella.quality(v, [[0, 1, 2], [0, 2, 3]], scheme="pn", level=4)
    >>> q["edges_checked"], q["normal_jump_max_deg"], q["distance_max"] < 1e-6  # flat stays flat
    (1, 0.0, True)
    """
    return _tessella.quality(
        vertices,
        faces,
        normals,
        scheme=scheme,
        level=level,
        alpha=alpha,
        tags=tags,
        crease_angle=crease_angle,
    )


def render(
    vertices: Any,
    faces: Any,
    normals: Any = None,
    *,
    scheme: Optional[SchemeName] = None,
    level: int = 8,
    size: Tuple[int, int] = (512, 512),
    compare: Optional[List[str]] = None,
    point_data: Optional[Dict[str, Any]] = None,
    range: Optional[Tuple[float, float]] = None,
    **view: Unpack[ViewOptions],
) -> np.ndarray:
    """Draw the refined surface offscreen on the GPU (the CLI's ``tessella render``).

    One refinement pattern per coarse triangle is evaluated in the vertex shader (as the GMR
    paper draws), multisampled, and read back.

    Parameters
    ----------
    vertices, faces, normals
        As :func:`refine`; ``faces`` with 6 columns are second-order (6-node) elements, drawn
        with the ``"quadratic"`` scheme by default.
    path : str or os.PathLike, optional
        Also write the picture there as a PNG (through a temporary file, renamed into place).
    scheme : str, optional
        One of :func:`schemes`; ``None``: ``"quadratic"`` for 6-column faces, else ``"pn"``.
    level : int
        Segments per coarse edge (1 or more).
    size : (int, int)
        Width and height in pixels (1 .. 8192 each), the colour bar and panels included.
    yaw, pitch : float
        Orbit about the vertical axis and elevation of the eye, degrees (yaw 0 looks along -Z).
    zoom : float
        1 frames the mesh's bounding sphere; larger values move closer.
    wireframe : bool
        Overlay the refinement pattern's edges.
    compare : list of str, optional
        Scheme names: one labelled panel per scheme side by side (``size`` is the whole row);
        ``scheme`` is then ignored.
    point_data : dict of str to array_like, optional
        Per-vertex fields, ``(n,)`` or ``(n, 1)`` (mid-edge nodes of 6-column faces included),
        as for :func:`refine`.
    color_by : str, optional
        Colour the surface by this ``point_data`` field (interpolated across each face with its
        shape functions: linear, or the 6-node ones for second-order faces), with a colour bar
        on the right showing the field's name and range.
    colormap : {"viridis", "coolwarm"}
        The colours from low to high.
    range : (float, float), optional
        The values mapped to the colormap's ends (clamped beyond); ``None``: the field's
        smallest and largest value.
    colorbar : bool
        ``False`` leaves the colour bar out (the surface then fills ``size``), to compose
        several pictures sharing one bar.
    label : str, optional
        Text written at the picture's top left.

    Returns
    -------
    numpy.ndarray, uint8 (height, width, 4)
        RGBA, sRGB, top row first; the background is white.

    Raises
    ------
    ValueError
        Bad arrays or options as :func:`refine`, a bad size, zoom or angle, an unknown
        ``color_by`` field (the message names the available ones), colormap or scheme, a bad
        ``range``, or a package built without the ``gpu`` cargo feature.
    RuntimeError
        No GPU adapter opens (a software one such as Mesa's lavapipe is enough) or the GPU fails.
    OSError
        ``path`` cannot be written.
    """
    corners, mids = _fields.split_faces(faces)
    if scheme is None:
        scheme = "quadratic" if mids is not None else "pn"
    n = np.shape(vertices)[0] if np.ndim(vertices) else 0
    fields = [
        (name, _fields._field_rows(name, a, n, "vertex")) for name, a in dict(point_data or {}).items()
    ]
    return _tessella.render(
        vertices,
        corners,
        mids,
        normals,
        scheme=scheme,
        level=level,
        size=(int(size[0]), int(size[1])),
        compare=None if compare is None else [str(s) for s in compare],
        point_data=fields,
        range=None if range is None else (float(range[0]), float(range[1])),
        **view,
    )


from ._interop import refine_trimesh, to_trimesh  # noqa: E402
from ._fem import boundary_faces, read_fem, write_fem  # noqa: E402
from ._batch import batch, refine_file, refine_to_file, sync_folder  # noqa: E402
from ._gltf import refine_gltf, refine_gltf_bytes  # noqa: E402
from ._memory import release_memory, reusable_bytes, set_memory_reuse  # noqa: E402
from ._plot import plot  # noqa: E402
