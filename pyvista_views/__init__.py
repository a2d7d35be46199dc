"""Pictures of meschers with PyVista/VTK: rendering, relighting, comparison, interactive views.

Meschers are drawn head-on with an orthographic camera (paper Section 4.1): flattened, shaded
with normals derived from zeta, overlaps resolved in a linear extension of the depth order, lit
only by directional lights and environment maps.

Installed, the package also plugs into PyVista's own registries (:mod:`pyvista_views.plugin`):
``pv.Plotter().mescher`` (a :class:`MescherScene`), ``polydata.mescher`` (cut models to meschers
and back), ``pv.read``/``save`` of ``.mescher`` files and the ``"meschers"`` theme.
"""

from __future__ import annotations

from .headless import configure_headless

configure_headless()  # before any render window exists (EGL when there is no display)

# PyVista registries (also declared as entry points, so an installed `meschers` needs no import).
from . import accessor, fileio, plugin, theme  # noqa: E402, F401
from .compare import compare  # noqa: E402
from .envmap import EnvironmentMap  # noqa: E402
from .interactive import MescherViewer, plot  # noqa: E402
from .layers import Layer, add_embedding, add_mescher, relight  # noqa: E402
from .lights import DirectionalLight  # noqa: E402
from .lineart import draw  # noqa: E402
from .polydata import to_polydata  # noqa: E402
from .render import render  # noqa: E402
from .scene import MescherScene  # noqa: E402

__all__ = [
    "DirectionalLight",
    "EnvironmentMap",
    "Layer",
    "MescherScene",
    "MescherViewer",
    "add_embedding",
    "add_mescher",
    "compare",
    "draw",
    "plot",
    "relight",
    "render",
    "to_polydata",
]
