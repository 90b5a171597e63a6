"""trimesh interop (optional dependency: ``pip install trimesh``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._errors import OptionError, need


def _trimesh() -> Any:
    return need("trimesh", "this function needs trimesh; install it with `pip install trimesh`")


def to_trimesh(vertices: Any, faces: Any, normals: Any = None) -> Any:
    """Wrap arrays (e.g. :func:`tessella.refine`'s result) in a ``trimesh.Trimesh``.

    The mesh is built with ``process=False``, so trimesh keeps the vertices exactly as given
    (no merging, no reordering); faces become int64 as trimesh expects.
    """
    trimesh = _trimesh()
    return trimesh.Trimesh(
        vertices=np.asarray(vertices),
        faces=np.asarray(faces, dtype=np.int64),
        vertex_normals=None if normals is None else np.asarray(normals),
        process=False,
    )


def refine_trimesh(mesh: Any, *, normals: Any = None, **options: Any) -> Any:
    """Refine a ``trimesh.Trimesh`` and return a new ``Trimesh`` with refined normals.

    ``normals`` chooses the input normals: ``None`` lets tessella compute angle-weighted
    normals, ``"trimesh"`` takes ``mesh.vertex_normals`` (the file's normals when trimesh loaded
    some, else trimesh's own average), and an ``(n, 3)`` array is used as given. The other
    arguments are :func:`tessella.refine`'s keyword arguments (``scheme``, ``level``,
    ``alpha``, ``normals_mode``, ``tags``, ``crease_angle``, ``backend``, ``weld``,
    ``displace``, ...), passed on to it.
    """
    from . import refine

    if isinstance(normals, str):
        if normals != "trimesh":
            raise OptionError(
                f"normals must be None, 'trimesh' or an (n, 3) array, got {normals!r}"
            )
        normals = mesh.vertex_normals
    v, f, n = refine(mesh.vertices, mesh.faces, normals, **options)
    return to_trimesh(v, f, n)
