"""Type stubs of the compiled module (documentation: the functions' docstrings)."""

import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from typing_extensions import Unpack

from ._types import BackendName, NormalsMode, SceneOptions, SchemeName, Spacing, ViewOptions

__version__: str

_F32 = npt.NDArray[np.float32]
_U32 = npt.NDArray[np.uint32]
_Path = Union[str, "os.PathLike[str]"]
# A dict in the sidecar-JSON structure, that JSON as a string, or the path of a JSON file.
_Tags = Union[Dict[str, Any], str, "os.PathLike[str]", None]
# {"kind": "sine"|"perlin", "amplitude": a, "frequency": f[, "seed": s]} or (kind, a, f[, s]).
_Displace = Union[Dict[str, Any], Tuple[Any, ...], List[Any], None]

def refine(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    normals: Optional[npt.ArrayLike] = None,
    *,
    scheme: SchemeName = "pn",
    level: float = 8.0,
    alpha: float = 0.75,
    normals_mode: Optional[NormalsMode] = None,
    spacing: Spacing = "grid",
    lod: Optional[str] = None,
    camera: Optional[str] = None,
    size: Optional[Tuple[int, int]] = None,
    tags: _Tags = None,
    crease_angle: Optional[float] = None,
    backend: BackendName = "auto",
    weld: bool = True,
    displace: _Displace = None,
    origin: bool = False,
    uvs: Optional[_F32] = None,
) -> Tuple[_F32, _U32, _F32, Optional[npt.NDArray[np.int64]], Optional[_F32], Optional[_F32]]: ...
def refine_fem(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    mids: Optional[npt.NDArray[np.int64]] = None,
    normals: Optional[npt.ArrayLike] = None,
    *,
    scheme: SchemeName = "quadratic",
    level: int = 8,
    alpha: float = 0.75,
    normals_mode: Optional[NormalsMode] = None,
    backend: BackendName = "auto",
    weld: bool = True,
    point_data: List[Tuple[str, npt.NDArray[np.float32]]] = ...,
    cell_data: List[Tuple[str, npt.NDArray[np.float32]]] = ...,
    uvs: Optional[_F32] = None,
) -> Tuple[
    _F32,
    _U32,
    _F32,
    npt.NDArray[np.int64],
    _F32,
    List[Tuple[str, npt.NDArray[np.float32]]],
    List[Tuple[str, npt.NDArray[np.float32]]],
    Optional[_F32],
]: ...
def render(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    mids: Optional[npt.NDArray[np.int64]] = None,
    normals: Optional[npt.ArrayLike] = None,
    *,
    scheme: SchemeName = "pn",
    level: int = 8,
    size: Tuple[int, int] = (512, 512),
    compare: Optional[List[str]] = None,
    point_data: List[Tuple[str, npt.NDArray[np.float32]]] = ...,
    range: Optional[Tuple[float, float]] = None,
    **view: Unpack[ViewOptions],
) -> npt.NDArray[np.uint8]: ...
def quality(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    normals: Optional[npt.ArrayLike] = None,
    *,
    scheme: SchemeName = "pn",
    level: int = 8,
    alpha: float = 0.75,
    tags: _Tags = None,
    crease_angle: Optional[float] = None,
) -> Dict[str, Any]: ...
def pattern(level: int) -> Tuple[npt.NDArray[np.float64], _U32]: ...
def info(
    vertices: npt.ArrayLike, faces: npt.ArrayLike, normals: Optional[npt.ArrayLike] = None
) -> Dict[str, Any]: ...
def load(path: _Path) -> Tuple[_F32, _U32, Optional[_F32]]: ...
def load_animated(path: _Path) -> AnimatedMesh: ...
def save(
    path: _Path,
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    normals: Optional[npt.ArrayLike] = None,
    *,
    ply_ascii: bool = False,
    uvs: Optional[_F32] = None,
) -> None: ...
def schemes() -> List[SchemeName]: ...
def backends() -> List[str]: ...
def gpu_info() -> Optional[Dict[str, Any]]: ...
def _refine_to_file(
    source: Union[
        _Path,
        Tuple[npt.ArrayLike, npt.ArrayLike, Optional[npt.ArrayLike], List[Tuple[str, npt.ArrayLike]]],
    ],
    output: _Path,
    **options: Any,
) -> Dict[str, Any]: ...
def _sync_folder(path: _Path) -> None: ...
def _refine_gltf(
    source: Union[_Path, bytes],
    output: Optional[_Path] = None,
    *,
    name: str = "scene.glb",
    buffers: List[Tuple[str, bytes]] = ...,
    sync: bool = True,
    **options: Unpack[SceneOptions],
) -> Tuple[
    List[Tuple[int, int, int, int, int, int, int, List[str]]],
    List[str],
    Optional[bytes],
]: ...
def _release_memory() -> int: ...
def _set_memory_reuse(max_bytes: int) -> int: ...
def _reusable_bytes() -> int: ...

class Refiner:
    def __init__(
        self,
        faces: npt.ArrayLike,
        *,
        vertices: Optional[npt.ArrayLike] = None,
        normals: Optional[npt.ArrayLike] = None,
        scheme: SchemeName = "pn",
        level: int = 8,
        alpha: float = 0.75,
        normals_mode: Optional[NormalsMode] = None,
        tags: _Tags = None,
        crease_angle: Optional[float] = None,
        backend: BackendName = "auto",
        weld: bool = True,
    ) -> None: ...
    def refine(
        self,
        vertices: npt.ArrayLike,
        normals: Optional[npt.ArrayLike] = None,
        *,
        out: Optional[Tuple[_F32, _F32]] = None,
    ) -> Tuple[_F32, _U32, _F32]: ...
    @property
    def vertex_count(self) -> Optional[int]: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def faces(self) -> Optional[_U32]: ...
    @property
    def level(self) -> int: ...
    @property
    def scheme(self) -> str: ...
    @property
    def weld(self) -> bool: ...
    @property
    def backend(self) -> str: ...
    def _state(
        self,
    ) -> Tuple[_U32, Dict[str, Any], Optional[Tuple[_F32, Optional[_F32]]]]: ...

class AnimatedMesh:
    @property
    def faces(self) -> _U32: ...
    @property
    def clips(self) -> List[str]: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def has_normals(self) -> bool: ...
    @property
    def path(self) -> str: ...
    def duration(self, clip: Union[str, int]) -> float: ...
    def pose(self, clip: Union[str, int, None] = None, time: float = 0.0) -> Tuple[_F32, _F32]: ...
