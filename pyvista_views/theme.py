"""The paper's look for figures, as a PyVista theme (the ``pyvista.themes`` entry point).

``pv.set_plot_theme("meschers")`` (no import of ours needed once ``meschers`` is installed)
gives an orthographic camera looking down -z with y up (a mescher is only meaningful head-on),
a white background, the matte grey material of :mod:`pyvista_views.scene` (ambient 0.2,
diffuse 0.8, no specular), flat interpolation and no scalar bar.  A theme cannot carry lights,
so the study's light rig lives here as :data:`LIGHT_RIG`: ``plotter.mescher`` lights with its
key light by default, :func:`apply_rig` puts it on any plotter, and the study relights with all
four.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

import pyvista as pv
from pyvista.plotting.themes import DocumentTheme

#: The study's four directional lights (directions *toward* each light, camera frame: x right,
#: y up, z toward the viewer), as in the paper's Figure 5; the first is the key light.
LIGHT_RIG: tuple[tuple[float, float, float], ...] = (
    (1.0, 1.0, 1.0),
    (-1.0, 1.0, 0.6),
    (0.3, -1.0, 0.8),
    (-0.6, -0.4, 1.0),
)
#: The study's environment map (:mod:`pyvista_views.envmap`).
ENV_MAP = "studio"
#: Matte grey: lit faces stay below the white background (silhouettes are measurable).
COLOR = (0.85, 0.85, 0.85)
AMBIENT, DIFFUSE = 0.2, 0.8


class MeschersTheme(DocumentTheme):
    """Orthographic head-on camera, white background, matte grey, flat shading."""

    _default_name: ClassVar[str] = "meschers"

    def __init__(self) -> None:
        super().__init__()
        self.name = "meschers"
        self.background = "white"
        self.color = COLOR
        self.font.color = "black"
        self.camera.position = (0.0, 0.0, 1.0)
        self.camera.viewup = (0.0, 1.0, 0.0)
        self.camera.parallel_projection = True
        self.lighting_params.ambient = AMBIENT
        self.lighting_params.diffuse = DIFFUSE
        self.lighting_params.specular = 0.0
        self.lighting_params.interpolation = "Flat"
        self.smooth_shading = False
        self.show_scalar_bar = False


def apply_rig(plotter: pv.Plotter, lights: Sequence = LIGHT_RIG[:1]) -> None:
    """Replace ``plotter``'s lights (light kit included) by directional ``lights`` of the rig."""
    from .lights import as_lights, set_vtk_lights

    set_vtk_lights(plotter, as_lights(lights))
