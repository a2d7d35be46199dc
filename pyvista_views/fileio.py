"""``.mescher`` files through PyVista: ``pv.read("x.mescher")`` and ``mesh.save("y.mescher")``.

A ``.mescher`` file is the lossless PLY of :func:`meschers_igl.save` (binary little-endian: the
flattened vertices ``(x, y, 0)``, the faces, an ``edge`` element with ``zeta`` and, when there is
one, a ``depth_arc`` element with the order), under its own extension so PyVista can route it to
these functions (the ``pyvista.readers`` / ``pyvista.writers`` entry points) without taking
``.ply`` over from VTK.  Renamed to ``.ply`` it still opens in MeshLab, or with ``pv.read``, as
the flat mesh; ``meschers_igl.save(m, "x.ply")`` writes exactly the same bytes.

Reading gives the flattened, shaded PolyData of :meth:`~pyvista_views.accessor.MescherAccessor.to_polydata`
(cells back to front, zeta's normals) with the mescher in its arrays (``field_data`` ``edges``,
``zeta``, ``depth_arcs``, ``has_order``); saving such a PolyData writes the mescher back, bit
for bit.
"""

from __future__ import annotations

import os
from typing import Any

import pyvista as pv

from meschers_igl import io as mescher_io
from meschers_igl.errors import MescherError

from .polydata import to_polydata

EXTENSION = ".mescher"


def read_mescher(
    path: str | os.PathLike, shading: str = "flat", layout: str = "indexed", **_: Any
) -> pv.PolyData:
    """Read a ``.mescher`` file as a flattened, shaded PolyData carrying the mescher.

    Parameters
    ----------
    path : str or PathLike
    shading : {"flat", "smooth"}
        Normals set on the result (:func:`~pyvista_views.polydata.to_polydata`).
    layout : {"indexed", "soup"}

    Returns
    -------
    pyvista.PolyData
        ``poly.mescher.to_mescher()`` returns the stored ``(mescher, order or None)``.
    """
    m, order = mescher_io.load(path, format="ply", return_order=True)
    return to_polydata(m, order, shading=shading, layout=layout, embed=True)


def write_mescher(dataset: Any, path: str | os.PathLike, **_: Any) -> None:
    """Write the mescher a PolyData carries (``pv.read("x.mescher")``, ``poly.mescher.to_polydata``).

    Raises
    ------
    MescherError
        When ``dataset`` carries no mescher: a plain (cut) model must first be converted with
        ``poly.mescher.to_polydata(view=..., up=...)``, which needs the view it is seen from.
    """
    accessor = getattr(dataset, "mescher", None)
    if not isinstance(dataset, pv.PolyData) or not accessor.is_flattened:
        raise MescherError(
            "dataset: expected a PolyData carrying a mescher (field data 'edges' and 'zeta', as "
            f"pv.read('x{EXTENSION}') or poly.mescher.to_polydata(view=...) give), found "
            f"{type(dataset).__name__} without them; convert a cut model with "
            "poly.mescher.to_polydata(view=..., up=...) first"
        )
    m, order = accessor.to_mescher()
    mescher_io.save(m, path, order=order, format="ply")


pv.register_reader(EXTENSION, read_mescher)
pv.register_writer(EXTENSION, write_mescher)
