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
- Results are fresh C-ordered arrays: vertices and normals ``float32 (n, 3)``, faces
  ``uint32 (m, 3)`` (use ``faces.astype(numpy.int64)`` where a library wants int64).

Errors
------
- ``ValueError``: bad shapes (not ``(n, 3)``), bad values (NaN positions, indices out of range
  or negative, degenerate triangles, zero normals), bad options (unknown scheme, level < 1,
  non-finite alpha, output over the 8 GiB size limit), ``tags`` given to a build without tagged
  schemes. Invalid files passed to :func:`load` also raise ``ValueError``.
- ``TypeError``: arrays of an unsupported dtype (e.g. complex, strings, float16).
- ``NotImplementedError``: ``backend="gpu"`` while :func:`backends` does not list it.
- ``OSError``: a file that cannot be read or written (:func:`load`, :func:`save`).
- ``ImportError``: an interop helper whose optional package (trimesh, meshio) is missing.

What this build has: :func:`schemes` and :func:`backends`.
"""

from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy as np

from . import _tessella
from ._tessella import __version__, backends, info, load, pattern, save, schemes

__all__ = [
    "__version__",
    "backends",
    "info",
    "load",
    "pattern",
    "refine",
    "refine_trimesh",
    "save",
    "schemes",
    "to_trimesh",
    "read_fem",
    "write_fem",
    "boundary_faces",
]


def refine(
    vertices: Any,
    faces: Any = None,
    normals: Any = None,
    *,
    scheme: str = "pn",
    level: int = 8,
    alpha: float = 0.75,
    normals_mode: Optional[str] = None,
    tags: Any = None,
    backend: str = "auto",
    weld: bool = True,
) -> Any:
    """Refine a triangle mesh into a curved one.

    Parameters
    ----------
    vertices : array_like, (n, 3) float32/float64, or trimesh.Trimesh
        Coarse vertex positions. A ``trimesh.Trimesh`` here (with ``faces`` left ``None``) is
        refined by :func:`refine_trimesh` and a ``Trimesh`` is returned.
    faces : array_like, (m, 3) integers
        Counter-clockwise triangles (vertex indices).
    normals : array_like, (n, 3) float32/float64, optional
        Vertex normals; ``None`` computes angle-weighted normals. Curved schemes bend the
        surface to follow them, so they matter: pass the true normals when you know them.
    scheme : str
        One of :func:`schemes`: ``"flat"`` (the input triangles), ``"phong"`` (Phong
        tessellation, Boubekeur & Alexa 2008), ``"pn"`` (curved PN triangles, Vlachos et al.
        2001). Names are case-insensitive.
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
    tags : None
        Reserved for tagged schemes; must be ``None`` in a build whose :func:`schemes` has
        none (``ValueError`` otherwise).
    backend : str
        ``"auto"`` (the fastest in :func:`backends`) or ``"cpu"``. ``"gpu"`` raises
        ``NotImplementedError`` while :func:`backends` does not list it.
    weld : bool
        ``True``: refined patches share the vertices on shared coarse corners and edges (a
        watertight mesh where the input is). ``False``: each coarse triangle gets its own
        ``(level+1)(level+2)/2`` vertices.

    Returns
    -------
    vertices : numpy.ndarray, float32 (N, 3)
    faces : numpy.ndarray, uint32 (M, 3)
        ``M = m * level**2``. Welded output starts with the ``n`` input vertices, unchanged.
    normals : numpy.ndarray, float32 (N, 3)
        Unit normals.

    Raises
    ------
    ValueError, TypeError, NotImplementedError
        See the module's "Errors" section.

    Examples
    --------
    >>> import numpy as np, tessella
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
    >>> f = np.array([[0, 1, 2]])
    >>> rv, rf, rn = tessella.refine(v, f, scheme="flat", level=2)
    >>> rv.shape, rf.shape, rf.dtype.name
    ((6, 3), (4, 3), 'uint32')
    """
    if faces is None and _is_trimesh(vertices):
        return refine_trimesh(
            vertices,
            normals=normals,
            scheme=scheme,
            level=level,
            alpha=alpha,
            normals_mode=normals_mode,
            tags=tags,
            backend=backend,
            weld=weld,
        )
    if faces is None:
        raise ValueError("refine(vertices, faces, ...) needs faces, an (m, 3) integer array")
    return _tessella.refine(
        vertices,
        faces,
        normals,
        scheme=scheme,
        level=level,
        alpha=alpha,
        normals_mode=normals_mode,
        tags=tags,
        backend=backend,
        weld=weld,
    )


def _is_trimesh(obj: Any) -> bool:
    # Checked by class name so that trimesh is imported only by those who use it.
    return any(
        c.__name__ == "Trimesh" and c.__module__.startswith("trimesh")
        for c in type(obj).__mro__
    )


from ._interop import refine_trimesh, to_trimesh  # noqa: E402
from ._fem import boundary_faces, read_fem, write_fem  # noqa: E402
