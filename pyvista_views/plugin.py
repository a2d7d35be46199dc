"""Meschers inside PyVista through its own extension points (PyVista >= 0.48 registries).

Installing the ``meschers`` distribution declares, in ``pyproject.toml``:

=================================  =========================================================
``pyvista.plotter_components``     ``plotter.mescher``: a :class:`~pyvista_views.MescherScene`
                                   bound to the plotter (``add``, ``add_embedding``,
                                   ``relight``, ``view``, ``screenshot``)
``pyvista.accessors``              ``polydata.mescher``: :class:`~pyvista_views.accessor.MescherAccessor`
                                   (``to_mescher``, ``to_polydata``)
``pyvista.readers`` / ``writers``  ``.mescher`` files (:mod:`pyvista_views.fileio`)
``pyvista.themes``                 ``"meschers"``: :class:`~pyvista_views.theme.MeschersTheme`
=================================  =========================================================

PyVista reads that metadata lazily and imports this module (or the accessor's) the first time a
user touches ``plotter.mescher`` (``polydata.mescher``), so plain ``import pyvista as pv;
pv.Plotter().mescher.add(m)`` works without importing :mod:`pyvista_views` first, and
``import meschers_igl`` never imports PyVista.  Importing :mod:`pyvista_views` registers the same
names directly (for a source checkout that is not installed).

Examples
--------
>>> import pyvista as pv                                              # doctest: +SKIP
>>> pl = pv.Plotter(off_screen=True)
>>> pl.mescher.add(m, order=order, shading="smooth", scalars=distance)
>>> pl.mescher.add_embedding(m, kind="cut")                       # same camera and lights
>>> pl.mescher.relight((-1, 0.3, 0.6))                            # no geometry rebuilt
>>> image = pl.mescher.screenshot()
"""

from __future__ import annotations

import pyvista as pv

from .scene import MescherScene

#: Name of the plotter component and of the dataset accessor.
NAME = "mescher"


def _register() -> None:
    # Registering twice (the entry point importing this module after a direct import of the
    # package, or the reverse) would only re-attach the same class; skip it to stay silent.
    current = getattr(pv.BasePlotter, "__dict__", {}).get(NAME)
    if current is None or getattr(current, "_component_cls", None) is not MescherScene:
        pv.register_plotter_component(NAME)(MescherScene)


_register()

__all__ = ["NAME", "MescherScene"]
