"""The names tessella's options take, as ``Literal`` types for type checkers (mypy, pyright).

The functions also accept these names in any ASCII case and with ``_`` for ``-``; the literals
list the spellings :func:`tessella.schemes` reports.
"""

from __future__ import annotations

from typing import Literal

#: ``scheme=``: see :func:`tessella.schemes`.
SchemeName = Literal["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"]
#: ``spacing=``: the uniform grid, or the GPU tessellator's spacings.
Spacing = Literal["grid", "equal", "fractional-odd", "fractional-even"]
#: ``normals_mode=``: how output normals are made.
NormalsMode = Literal["linear", "quadratic", "real"]
#: ``backend=``: where the work runs.
BackendName = Literal["auto", "cpu", "gpu", "gl"]
