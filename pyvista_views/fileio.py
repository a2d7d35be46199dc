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
import shutil
import tempfile
from pathlib import Path
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
    path = Path(path)
    with _as_ply(path) as ply:
        m, order = mescher_io.load(ply, return_order=True)
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
    path = Path(path)
    # meschers_igl.save picks its format from the suffix: write a .ply beside, then rename.
    tmp = path.with_name(f".{path.name}.{os.getpid()}.ply")
    try:
        mescher_io.save(m, tmp, order=order)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


class _as_ply:
    """A ``.ply`` name for ``path`` (a symbolic link, or a copy where links are not allowed)."""

    def __init__(self, path: Path) -> None:
        if not path.is_file():
            raise MescherError(f"path: expected an existing file, found nothing at {str(path)!r}")
        self.path = path.resolve()

    def __enter__(self) -> Path:
        self._dir = tempfile.TemporaryDirectory()
        ply = Path(self._dir.name) / (self.path.stem + ".ply")
        try:
            ply.symlink_to(self.path)
        except OSError:
            shutil.copyfile(self.path, ply)
        return ply

    def __exit__(self, *exc: object) -> None:
        self._dir.cleanup()


pv.register_reader(EXTENSION, read_mescher)
pv.register_writer(EXTENSION, write_mescher)
