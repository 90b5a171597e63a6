"""``tessella.plot``: a refined mesh in PyVista, coloured by one of its fields."""

from __future__ import annotations

import os
from typing import Any, Optional, Tuple, Union

from ._errors import OptionError, need
from ._result import RefinedMesh


def plot(
    mesh: Any,
    scalars: Optional[str] = None,
    *,
    off_screen: Optional[bool] = None,
    screenshot: Union[str, "os.PathLike[str]", None] = None,
    window_size: Tuple[int, int] = (800, 600),
    show_edges: bool = False,
    cmap: Optional[str] = None,
    **add_mesh: Any,
) -> Any:
    """Show a :class:`RefinedMesh` (or anything PyVista draws) coloured by a field.

    ``scalars`` names a ``point_data`` or ``cell_data`` field (``None``: no colouring, or
    the active scalars); a vector field is coloured by its magnitude. ``off_screen=True``
    renders without a window (on a headless machine VTK falls back to EGL or OSMesa) and
    returns the picture; ``screenshot`` also writes it as a PNG. Other keyword arguments go to
    ``pyvista.Plotter.add_mesh``.

    The same with PyVista directly::

        grid = result.to_pyvista()
        grid.plot(scalars="temperature", off_screen=True, screenshot="t.png")

    Returns
    -------
    numpy.ndarray, uint8 (height, width, 3) when off screen, else ``None``.

    Raises
    ------
    OptionError
        ``scalars`` names no field of the mesh (the message lists the fields it has).
    ImportError
        PyVista is not installed (``pip install pyvista``).
    """
    pv = need("pyvista")
    grid = mesh.to_pyvista() if isinstance(mesh, RefinedMesh) else mesh
    if scalars is not None and scalars not in grid.point_data and scalars not in grid.cell_data:
        have = sorted(set(grid.point_data.keys()) | set(grid.cell_data.keys()))
        raise OptionError(f"plot(): scalars={scalars!r} names no field of the mesh (it has: {have})")
    if off_screen is None:
        off_screen = screenshot is not None or bool(getattr(pv, "OFF_SCREEN", False))
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    plotter.add_mesh(grid, scalars=scalars, show_edges=show_edges, cmap=cmap, **add_mesh)
    if off_screen:
        image = plotter.screenshot(None if screenshot is None else os.fspath(screenshot), return_img=True)
        plotter.close()
        return image
    plotter.show()
    return None
