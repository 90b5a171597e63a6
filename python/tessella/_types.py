"""The names tessella's options take, as ``Literal`` types for type checkers (mypy, pyright).

The functions also accept these names in any ASCII case and with ``_`` for ``-``; the literals
list the spellings :func:`tessella.schemes` reports.
"""

from __future__ import annotations

import os
from typing import Literal, Optional, TypedDict, Union

#: ``scheme=``: see :func:`tessella.schemes`.
SchemeName = Literal["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"]
#: ``spacing=``: the uniform grid, or the GPU tessellator's spacings.
Spacing = Literal["grid", "equal", "fractional-odd", "fractional-even"]
#: ``normals_mode=``: how output normals are made.
NormalsMode = Literal["linear", "quadratic", "real"]
#: ``backend=``: where the work runs.
BackendName = Literal["auto", "cpu", "gpu", "gl"]
#: ``tangents=`` of a glTF scene: recomputed on the refined mesh (``"mikktspace"`` is the same),
#: or the file's carried.
Tangents = Literal["recomputed", "mikktspace", "carried"]


class SceneOptions(TypedDict, total=False):
    """The options of a glTF scene's refinement, for :func:`tessella.refine_gltf` and
    :func:`tessella.refine_gltf_bytes` alike; its docstring gives each one's meaning and
    default (the compiled module applies the defaults)."""

    scheme: Optional[SchemeName]
    level: Optional[int]
    max_edge: Optional[float]
    alpha: float
    normals_mode: Optional[NormalsMode]
    tangents: Tangents
    joint_sets: Optional[int]


class ViewOptions(TypedDict, total=False):
    """How :func:`tessella.render` draws: the options it passes to the compiled module as they
    are (its docstring gives each one's meaning and default; the compiled module applies the
    defaults)."""

    yaw: float
    pitch: float
    zoom: float
    wireframe: bool
    color_by: Optional[str]
    colormap: str
    colorbar: bool
    label: Optional[str]
    path: Union[str, "os.PathLike[str]", None]
