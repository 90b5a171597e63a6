"""Typed options: :class:`Camera`, :class:`Lod` and :class:`Displace`, and what
:func:`tessella.refine`'s fields path does not take (:func:`check_fields`); which other options
cannot go together the compiled module checks, with the core's rules (the CLI's and npm's).

Each typed option validates its numbers when it is made (an :class:`~tessella.OptionError`
naming the bad one), has a ``repr`` that reads as the call that made it, and turns into the
string or dict form the compiled module reads. The string forms (``lod="tolerance:0.001"``)
remain a shorthand: :func:`lod_spec` and :func:`displace_spec` accept both.
"""

from __future__ import annotations

import math
import operator
from typing import Any, Dict, Optional, Sequence, Tuple

from ._errors import OptionError


def _finite(what: str, value: Any) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise OptionError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise OptionError(f"{what} must be finite, got {x}")
    return x


def _positive(what: str, value: Any) -> float:
    x = _finite(what, value)
    if x <= 0:
        raise OptionError(f"{what} must be greater than 0, got {x}")
    return x


def _point(what: str, value: Any) -> Tuple[float, float, float]:
    try:
        items = [v for v in value]
    except TypeError:
        raise OptionError(f"{what} must be 3 numbers (x, y, z), got {value!r}") from None
    if len(items) != 3:
        raise OptionError(f"{what} must be 3 numbers (x, y, z), got {len(items)}")
    x, y, z = (_finite(f"{what}[{k}]", v) for k, v in enumerate(items))
    return (x, y, z)


class Camera:
    """A pinhole camera for screen-space and distance LOD.

    ``Camera(eye, target, fov=45.0)``: ``eye`` and ``target`` are 3 numbers each, ``fov`` the
    vertical field of view in degrees (strictly between 0 and 180). ``eye`` and ``target`` must
    differ.
    """

    __slots__ = ("eye", "target", "fov")

    def __init__(self, eye: Sequence[float], target: Sequence[float], fov: float = 45.0) -> None:
        self.eye = _point("Camera eye", eye)
        self.target = _point("Camera target", target)
        self.fov = _finite("Camera fov", fov)
        if not 0.0 < self.fov < 180.0:
            raise OptionError(f"Camera fov (the vertical field of view) must lie strictly between 0 and 180 degrees, got {self.fov}")
        if self.eye == self.target:
            raise OptionError("Camera eye and target are the same point; the camera looks nowhere")

    @classmethod
    def coerce(cls, value: Any) -> "Camera":
        """A :class:`Camera`, or 7 numbers ``(eye_x, eye_y, eye_z, target_x, target_y,
        target_z, fov)`` (a sequence or that comma-separated string)."""
        if isinstance(value, Camera):
            return value
        if isinstance(value, str):
            value = value.split(",")
        try:
            items = list(value)
        except TypeError:
            raise OptionError(f"camera must be a tessella.Camera or 7 numbers, got {value!r}") from None
        if len(items) != 7:
            raise OptionError(
                f"camera must be a tessella.Camera or 7 numbers (eye xyz, target xyz, fov), got {len(items)}"
            )
        return cls(items[0:3], items[3:6], items[6])

    def spec(self) -> str:
        """The camera as the compiled module reads it: ``"ex,ey,ez,tx,ty,tz,fov"``."""
        return ",".join(repr(x) for x in (*self.eye, *self.target, self.fov))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Camera) and (self.eye, self.target, self.fov) == (
            other.eye,
            other.target,
            other.fov,
        )

    def __hash__(self) -> int:
        return hash((self.eye, self.target, self.fov))

    def __repr__(self) -> str:
        return f"Camera(eye={self.eye!r}, target={self.target!r}, fov={self.fov!r})"


class Lod:
    """Per-edge adaptive levels (crack-free: each coarse edge's level from that edge alone).

    Make one with a constructor:

    - ``Lod.tolerance(max_deviation)``: the flat triangles lie within ``max_deviation`` of the
      curved surface.
    - ``Lod.screen(pixels, camera, size)``: edges about ``pixels`` long on screen, for a
      :class:`Camera` and an image ``size = (width, height)``.
    - ``Lod.distance(near, far, max, camera)``: level ``max`` up to ``near`` from the eye,
      falling to 1 at ``far``.
    """

    __slots__ = ("kind", "values", "camera", "size")

    def __init__(
        self,
        kind: str,
        values: Tuple[float, ...],
        camera: Optional[Camera] = None,
        size: Optional[Tuple[int, int]] = None,
    ) -> None:
        # Use the constructors: they validate.
        self.kind, self.values, self.camera, self.size = kind, values, camera, size

    @classmethod
    def tolerance(cls, max_deviation: float) -> "Lod":
        return cls("tolerance", (_positive("Lod.tolerance max_deviation", max_deviation),))

    @classmethod
    def screen(cls, pixels: float, camera: Any, size: Sequence[int]) -> "Lod":
        px = _positive("Lod.screen pixels", pixels)
        return cls("screen", (px,), Camera.coerce(camera), _size("Lod.screen size", size))

    @classmethod
    def distance(cls, near: float, far: float, max: float, camera: Any) -> "Lod":
        n = _finite("Lod.distance near", near)
        f = _finite("Lod.distance far", far)
        m = _finite("Lod.distance max", max)
        if not 0 <= n < f:
            raise OptionError(f"Lod.distance needs 0 <= near < far, got near={n}, far={f}")
        if m < 1:
            raise OptionError(f"Lod.distance max is the finest level, 1 or more, got {m}")
        return cls("distance", (n, f, m), Camera.coerce(camera))

    def spec(self) -> str:
        """The string form the compiled module reads (``"tolerance:0.001"``)."""
        return self.kind + ":" + ",".join(repr(v) for v in self.values)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Lod) and (self.kind, self.values, self.camera, self.size) == (
            other.kind,
            other.values,
            other.camera,
            other.size,
        )

    def __hash__(self) -> int:
        return hash((self.kind, self.values, self.camera, self.size))

    def __repr__(self) -> str:
        if self.kind == "tolerance":
            return f"Lod.tolerance({self.values[0]!r})"
        if self.kind == "screen":
            return f"Lod.screen({self.values[0]!r}, {self.camera!r}, {self.size!r})"
        n, f, m = self.values
        return f"Lod.distance({n!r}, {f!r}, {m!r}, {self.camera!r})"


def _size(what: str, size: Any) -> Tuple[int, int]:
    try:
        w, h = size
    except (TypeError, ValueError):
        raise OptionError(f"{what} must be (width, height) in pixels, got {size!r}") from None
    if int(w) != w or int(h) != h or int(w) < 1 or int(h) < 1:
        raise OptionError(f"{what} must be two whole numbers of pixels, 1 or more, got {size!r}")
    return (int(w), int(h))


class Displace:
    """A displacement along the unit normal, after evaluation: ``P + d(P) n``.

    - ``Displace.sine(amplitude, frequency)``: ``d = amplitude sin(frequency |P|)``.
    - ``Displace.perlin(amplitude, frequency, seed=0)``: ``d = amplitude noise(frequency P)``,
      Perlin's improved noise with a permutation shuffled by ``seed`` (0 .. 2**32-1).
    """

    __slots__ = ("kind", "amplitude", "frequency", "seed")

    def __init__(self, kind: str, amplitude: float, frequency: float, seed: int = 0) -> None:
        if kind not in ("sine", "perlin"):
            raise OptionError(f"Displace kind {kind!r}: use Displace.sine or Displace.perlin")
        self.kind = kind
        self.amplitude = _finite(f"Displace.{kind} amplitude", amplitude)
        self.frequency = _finite(f"Displace.{kind} frequency", frequency)
        if isinstance(seed, bool) or int(seed) != seed or not 0 <= int(seed) < 2**32:
            raise OptionError(f"Displace seed must be a whole number in 0..2**32-1, got {seed!r}")
        self.seed = int(seed)

    @classmethod
    def sine(cls, amplitude: float, frequency: float) -> "Displace":
        return cls("sine", amplitude, frequency)

    @classmethod
    def perlin(cls, amplitude: float, frequency: float, seed: int = 0) -> "Displace":
        return cls("perlin", amplitude, frequency, seed)

    def spec(self) -> Dict[str, Any]:
        """The dict form the compiled module reads."""
        d: Dict[str, Any] = {"kind": self.kind, "amplitude": self.amplitude, "frequency": self.frequency}
        if self.kind == "perlin":
            d["seed"] = self.seed
        return d

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Displace) and self.spec() == other.spec()

    def __hash__(self) -> int:
        return hash(tuple(self.spec().items()))

    def __repr__(self) -> str:
        if self.kind == "sine":
            return f"Displace.sine({self.amplitude!r}, {self.frequency!r})"
        return f"Displace.perlin({self.amplitude!r}, {self.frequency!r}, seed={self.seed})"


_LOD_KEYS = {"tolerance": ["max_deviation"], "screen": ["pixels"], "distance": ["near", "far", "max"]}


def lod_spec(lod: Any, camera: Any, size: Any) -> Tuple[Optional[str], Optional[str], Optional[Tuple[int, int]]]:
    """``(lod, camera, size)`` as the compiled module reads them, from any accepted form: a
    :class:`Lod` (which carries its own camera and size), a string, or a dict."""
    if lod is None:
        if camera is not None or size is not None:
            raise OptionError("camera= and size= serve lod= (Lod.screen, Lod.distance); pass lod= too")
        return None, None, None
    if isinstance(lod, Lod):
        if camera is not None or size is not None:
            raise OptionError(f"{lod!r} carries its own camera and size; do not also pass camera= or size=")
        return lod.spec(), None if lod.camera is None else lod.camera.spec(), lod.size
    cam = None if camera is None else Camera.coerce(camera).spec()
    sz = None if size is None else _size("size", size)
    if isinstance(lod, str):
        return lod, cam, sz
    if isinstance(lod, dict):
        kind = lod.get("kind")
        if kind not in _LOD_KEYS:
            raise OptionError(f"lod kind {kind!r}: expected 'tolerance', 'screen' or 'distance'")
        missing = [k for k in _LOD_KEYS[kind] if k not in lod]
        if missing:
            raise OptionError(f"lod {kind!r} needs {', '.join(missing)}")
        return kind + ":" + ",".join(repr(_finite(f"lod {k}", lod[k])) for k in _LOD_KEYS[kind]), cam, sz
    raise TypeError(f"lod must be a tessella.Lod, a string or a dict, not {type(lod).__name__}")


def displace_spec(displace: Any) -> Any:
    """A :class:`Displace` as its dict; the dict and tuple shorthands pass through (the compiled
    module checks them)."""
    return displace.spec() if isinstance(displace, Displace) else displace


def check_fields(
    *,
    spacing: str,
    lod: Any,
    camera: Any,
    size: Any,
    tags: Any,
    crease_angle: Any,
    displace: Any,
    fields_from: Optional[str] = None,
) -> None:
    """Refuses what the fields path (point or cell data, ``warp``, 6-node faces) does not take,
    in the message style of the core's rules: ``"refine(): A cannot be combined with B (why)"``.
    That path refines with one whole level on the grid pattern, untagged and undisplaced; every
    other combination is the core's to refuse (the compiled ``refine``). ``fields_from`` names
    the fields a mesh object brought along (refused like ``point_data=`` rather than dropped)."""

    def refuse(a: str, b: str, why: str) -> None:
        raise OptionError(f"refine(): {a} cannot be combined with {b} ({why})")

    given = lambda pairs: [name for name, v in pairs if v]  # noqa: E731
    fields = "point_data=, cell_data=, warp= or 6-node faces"
    if fields_from is not None:
        fields = fields_from
        hint = "; pass the object's arrays (vertices, faces) to refine without its fields"
    else:
        hint = ""
    spaced = given([("spacing=", spacing != "grid"), ("lod=", lod is not None),
                    ("camera=", camera is not None), ("size=", size is not None)])
    if spaced:
        refuse(fields, spaced[0], "fields take a whole level on the grid pattern" + hint)
    shaped = given([("tags=", tags is not None), ("crease_angle=", crease_angle is not None),
                    ("displace=", displace is not None)])
    if shaped:
        refuse(fields, shaped[0], "fields are carried on the untagged, undisplaced surface" + hint)


#: :func:`tessella.refine`'s options that work on one merged mesh only, as ``tessella refine``
#: refuses them for a glTF scene written back whole: each with the value that means "not
#: used" (``None`` for all others).
SCENE_REFUSED: Dict[str, Any] = {
    "lod": None, "camera": None, "size": None, "spacing": "grid", "displace": None,
    "origin": False, "tags": None, "crease_angle": None, "weld": True, "backend": ("auto", "cpu"),
    "point_data": None, "cell_data": None, "warp": None, "uvs": None,
}


def check_scene_options(
    call: str, level: Any, max_edge: Any, options: Dict[str, Any], accepted: Sequence[str]
) -> Optional[int]:
    """Checks the options of a glTF scene's refinement (:func:`tessella.refine_gltf`) against
    each other, and returns ``level`` as an int (or ``None``); the compiled module checks
    their values.

    ``level`` and ``max_edge`` cannot be combined. ``options`` are the keyword arguments
    besides ``accepted``: :func:`refine`'s options that work on one merged mesh
    (:data:`SCENE_REFUSED`) are refused when used, with the CLI's message; any other name is
    unknown. A fractional ``level`` is refused like the CLI's."""

    def refuse(what: str) -> None:
        raise OptionError(
            f"{call}(): {what} works on one merged mesh; a glTF scene is refined primitive by "
            "primitive with level= or max_edge=. Use tessella.refine_file() (or tessella.load() "
            "and tessella.refine()) to merge the scene into one mesh first (its nodes, materials "
            "and animations are then dropped)"
        )

    if level is not None and max_edge is not None:
        raise OptionError(
            f"{call}(): level= cannot be combined with max_edge= (max_edge= chooses each "
            "primitive's level from its edges; pass one of them)"
        )
    unknown = sorted(set(options) - set(SCENE_REFUSED))
    if unknown:
        raise OptionError(
            f"{call}(): unknown option(s) {', '.join(unknown)}; the options are {', '.join(accepted)}"
        )
    for name, unused in SCENE_REFUSED.items():
        if name not in options:
            continue
        value = options[name]
        if isinstance(unused, tuple):
            used = not (isinstance(value, str) and value.lower() in unused)
        elif isinstance(unused, str):
            used = not (isinstance(value, str) and value.lower() == unused)
        elif isinstance(unused, bool):
            used = bool(value) != unused
        else:
            used = value is not None
        if used:
            refuse(f"{name}={value!r}" if unused is not None else f"{name}=")
    if level is None:
        return None
    if isinstance(level, float):
        if not level.is_integer():
            refuse(f"a fractional level ({level})")
        return int(level)
    try:
        return operator.index(level)
    except TypeError:
        raise TypeError(f"level must be a whole number, got {type(level).__name__}") from None
