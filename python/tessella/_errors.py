"""The exceptions tessella raises, one class per kind of mistake.

All derive from :class:`TessellaError`, itself a ``ValueError``, so code written before these
classes existed (``except ValueError``) still catches them. The compiled extension raises them
too (``python/src/errors.rs`` maps the core's error types to them in one place); the message is
the core's, unchanged, and also kept as ``.message``.

- :class:`MeshError`: the mesh itself is bad: NaN or infinite positions, indices out of range or
  negative, degenerate triangles, zero normals, arrays of the wrong shape, fields that do not
  fit the mesh.
- :class:`OptionError`: an option is bad or two options conflict: an unknown scheme, level 0,
  a non-finite alpha, an output over the size limit, a bad ``lod``/``displace``/``camera``,
  tags that do not fit the mesh.
- :class:`FileFormatError`: a file that is broken (truncated, garbage, bad numbers) or of a
  format or feature tessella does not read. A file the OS refuses to open stays an ``OSError``.
- :class:`GpuError`: no GPU adapter for ``backend="gpu"``, a device that fails or is lost, GPU
  limits. Also a ``RuntimeError``, as these were before.
"""

from __future__ import annotations

import importlib
from typing import Any, Optional

__all__ = ["TessellaError", "MeshError", "OptionError", "FileFormatError", "GpuError"]


def need(module: str, message: Optional[str] = None) -> Any:
    """Imports the optional dependency ``module``, or raises ``ImportError`` with ``message``
    (by default: this needs it, and how to install it)."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(message or f"this needs {module}; install it with `pip install {module}`") from e


class TessellaError(ValueError):
    """Base class of tessella's errors (a ``ValueError``); ``.message`` is the core's text."""

    @property
    def message(self) -> str:
        return str(self.args[0]) if self.args else ""


class MeshError(TessellaError):
    """A bad mesh: NaN positions, indices out of range, degenerate triangles, zero normals,
    arrays or fields of the wrong shape."""


class OptionError(TessellaError):
    """A bad option (unknown scheme, level 0, bad ``lod``, ``displace`` or tags), or options
    that cannot be combined (the message names both)."""


class FileFormatError(TessellaError):
    """A broken mesh file (truncated, garbage, bad numbers) or one of a format or feature
    tessella does not read."""


class GpuError(TessellaError, RuntimeError):
    """The GPU is missing or failed (adapter, device, limits); also a ``RuntimeError``."""
