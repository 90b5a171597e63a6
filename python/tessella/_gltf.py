"""glTF scenes refined whole: :func:`refine_gltf` (file in, file out) and
:func:`refine_gltf_bytes` (bytes in, GLB bytes out), the CLI's ``tessella refine in.glb -o
out.glb``.

The scene is read once, every triangle primitive of every mesh is refined on its own (a mesh
that several nodes show, once) with its material, its attributes (texture coordinates and
colours interpolated, tangents recomputed, skin influences blended) and its morph targets, and
the document is written back with everything else it held: nodes, materials, textures, images,
samplers, cameras, lights, skins, animations, extensions and extras. Points and lines are
copied. The work runs in Rust with the GIL released.
"""

from __future__ import annotations

import os
import sys
import warnings as _warnings
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Tuple, Union, cast

from . import _options, _tessella
from ._result import PrimitiveReport, SceneReport
from ._types import SceneOptions

if sys.version_info >= (3, 11):
    from typing import Unpack
elif TYPE_CHECKING:
    from typing_extensions import Unpack

PathLike = Union[str, "os.PathLike[str]"]
BytesLike = Union[bytes, bytearray, memoryview]

#: The options :func:`refine_gltf` and :func:`refine_gltf_bytes` take (:class:`SceneOptions`).
OPTIONS = tuple(SceneOptions.__annotations__)


def refine_gltf(
    src: PathLike,
    dst: PathLike,
    *,
    sync: bool = True,
    **options: Unpack[SceneOptions],
) -> SceneReport:
    """Refine a whole glTF scene: read ``src`` (``.glb`` or ``.gltf``), refine every triangle
    primitive, write ``dst`` (``.glb``, or ``.gltf`` with ``NAME.bin`` beside it) keeping
    everything else the document held.

    Parameters
    ----------
    src, dst : str or os.PathLike
        The scene read and the scene written; ``dst`` may be ``src``. Images the document names
        by a relative URI are copied beside ``dst`` when it lies in another folder (a missing
        one is a warning, in the report's ``warnings`` and as a ``RuntimeWarning``).
    scheme : str
        One of :func:`tessella.schemes` (``"pn"`` by default), as for :func:`tessella.refine`.
    level : int, optional
        Segments per coarse edge for every primitive (1 or more; default 8): each triangle
        becomes ``level**2``.
    max_edge : float, optional
        Instead of ``level``: a target edge length in world space. Each primitive gets
        ``ceil(mean coarse edge * scale / max_edge)`` (1 to 64), ``scale`` being the largest
        scale of the nodes that show its mesh, so parts of different sizes get different
        levels. ``level`` and ``max_edge`` cannot be combined (:class:`OptionError`).
    alpha : float
        Phong's shape factor, as for :func:`tessella.refine`.
    normals_mode : {"linear", "quadratic", "real"} or None
        As for :func:`tessella.refine`.
    tangents : {"recomputed", "carried"}
        The refined ``TANGENT`` of primitives that have one: MikkTSpace on the refined mesh
        (``"recomputed"``, the default), or the file's tangents interpolated and made
        orthogonal to the refined normals (``"carried"``, about twice as fast).
    joint_sets : int, optional
        How many ``JOINTS_n``/``WEIGHTS_n`` sets skinned primitives get: ``None`` (the default)
        as many as the file has (three.js and Bevy skin with the first set only), or up to
        this many (1 to 8) where a refined vertex blends more influences than the file's sets
        hold.
    sync : bool
        ``True``: the files are flushed to the disk before they get their names (as
        :func:`tessella.refine_to_file`); both are written whole or not at all.
    **options
        :func:`tessella.refine`'s options that work on one merged mesh (``lod``, ``spacing``,
        ``displace``, ``origin``, ``tags``, ``crease_angle``, ``weld=False``,
        ``backend="gpu"`` / ``"gl"``, fields, ``uvs``) are refused with an
        :class:`OptionError` saying so (``refine_gltf(): lod= works on one merged mesh; ...``),
        as ``tessella refine`` refuses them for a scene: :func:`tessella.refine_file` merges a
        glTF scene into one mesh and takes them. Given at their defaults they are accepted, so
        a dict of :func:`tessella.refine`'s options passes when it fits.

    Returns
    -------
    SceneReport
        One :class:`PrimitiveReport` per triangle primitive: ``mesh``, ``primitive``,
        ``level``, ``coarse_triangles``, ``degenerate`` (zero-area triangles, refined flat),
        ``vertices``, ``triangles`` (``coarse_triangles * level**2``), ``notes``; and the
        writer's ``warnings``.

    Raises
    ------
    FileFormatError
        ``src`` is broken (truncated, bad JSON, an index past the end of an array, a missing
        buffer), requires an extension tessella does not read, or ``src`` / ``dst`` is not a
        ``.gltf`` / ``.glb`` path.
    OptionError
        Bad or refused options, ``level`` with ``max_edge``, a primitive whose output would
        exceed the size limit.
    MeshError
        A primitive whose triangles cannot be refined.
    OSError
        ``src`` cannot be read or ``dst`` written. Nothing is left at ``dst`` after an error.

    Example::

        report = tessella.refine_gltf("scene.glb", "smooth.glb", level=4)
        for row in report:
            print(row.mesh, row.primitive, row.level, row.coarse_triangles, row.triangles)
    """
    if isinstance(src, (bytes, bytearray, memoryview)):
        raise TypeError("refine_gltf(src, dst): src is a path; tessella.refine_gltf_bytes(data) refines bytes")
    scene = _scene_options("refine_gltf", options, OPTIONS + ("sync",))
    out = os.fspath(dst)
    rows, warnings, _ = _tessella._refine_gltf(os.fspath(src), out, sync=sync, **scene)
    for warning in warnings:
        _warnings.warn(f"refine_gltf(): {warning}", RuntimeWarning, stacklevel=2)
    return SceneReport(out, _rows(rows), warnings)


def refine_gltf_bytes(
    data: BytesLike,
    *,
    name: str = "scene.glb",
    buffers: Optional[Mapping[str, BytesLike]] = None,
    **options: Unpack[SceneOptions],
) -> bytes:
    """Refine a whole glTF scene held in memory: the bytes of a ``.glb`` (or ``.gltf``) file
    in, the refined scene's GLB bytes out, the file system untouched. The same refinement and
    options as :func:`refine_gltf` (the GLB bytes :func:`refine_gltf` writes to a ``.glb``
    path, byte for byte).

    Parameters
    ----------
    data : bytes, bytearray or memoryview
        The file's bytes.
    name : str
        The file's name, for messages; its extension says whether ``data`` is GLB (``.glb``)
        or glTF JSON (``.gltf``).
    buffers : dict of str to bytes, optional
        A ``.gltf``'s external buffers by their relative URI (``{"scene.bin": b"..."}``);
        a buffer URI missing from it is a :class:`FileFormatError`. GLB files and ``data:``
        URIs need none. Images named by URI stay named by URI in the output.
    scheme, level, max_edge, alpha, normals_mode, tangents, joint_sets, **options
        As for :func:`refine_gltf`.

    Returns
    -------
    bytes
        The refined scene as one GLB file.

    Raises
    ------
    FileFormatError, OptionError, MeshError
        As :func:`refine_gltf`.
    """
    scene = _scene_options("refine_gltf_bytes", options, ("name", "buffers") + OPTIONS)
    given = [(str(uri), bytes(b)) for uri, b in dict(buffers or {}).items()]
    _, _, glb = _tessella._refine_gltf(bytes(data), None, name=name, buffers=given, **scene)
    assert glb is not None
    return glb


def _scene_options(call: str, options: Mapping[str, Any], accepted: Tuple[str, ...]) -> SceneOptions:
    """The :class:`SceneOptions` among a call's keyword ``options``, checked against each other
    and against the others (:func:`tessella._options.check_scene_options`), for the compiled
    module, which checks their values and applies the defaults."""
    scene: Dict[str, Any] = {k: v for k, v in options.items() if k in OPTIONS}
    others = {k: v for k, v in options.items() if k not in OPTIONS}
    scene["level"] = _options.check_scene_options(call, scene.get("level"), scene.get("max_edge"), others, accepted)
    return cast(SceneOptions, scene)


def _rows(rows: List[Tuple[int, int, int, int, int, int, int, List[str]]]) -> List[PrimitiveReport]:
    """The compiled module's report tuples as :class:`PrimitiveReport` rows."""
    return [
        PrimitiveReport(mesh, primitive, level, coarse, degenerate, vertices, triangles, tuple(notes))
        for mesh, primitive, level, coarse, degenerate, vertices, triangles, notes in rows
    ]


__all__ = ["refine_gltf", "refine_gltf_bytes", "PrimitiveReport", "SceneReport"]
