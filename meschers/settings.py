"""Settings of the comparison study: resolutions, lights, colour maps and the citation.

One place for every constant a study step or figure reads, so that a step is a function of
(its inputs, :class:`StudySettings`) and two runs with the same settings compute the same thing
wherever they run (in this process or on a Dask worker).
"""

from __future__ import annotations

from dataclasses import dataclass

from pyvista_views.theme import ENV_MAP, LIGHT_RIG

__all__ = [
    "CITATION",
    "DOI_URL",
    "ENV_MAP",
    "GEODESIC_CMAP",
    "HEAT_CMAP",
    "LIGHTS",
    "StudySettings",
    "study_settings",
]

CITATION = (
    "Ana Dodik, Isabella Yu, Kartik Chandra, Jonathan Ragan-Kelley, Joshua Tenenbaum, "
    "Vincent Sitzmann, Justin Solomon. Meschers: Geometry Processing of Impossible Objects. "
    "ACM Transactions on Graphics 44(4), 2025. DOI 10.1145/3731422."
)
DOI_URL = "https://doi.org/10.1145/3731422"

#: The four directional lights of the paper's Fig. 5 and the environment map of the render
#: figures: the rig is pyvista_views' (:data:`pyvista_views.theme.LIGHT_RIG`), named here for the
#: study's steps.
LIGHTS: tuple[tuple[float, float, float], ...] = LIGHT_RIG
GEODESIC_CMAP = "viridis"
HEAT_CMAP = "plasma"  # no black end: faces far from the source stay readable


@dataclass(frozen=True)
class StudySettings:
    """Resolutions of one study run.

    Attributes
    ----------
    quick : bool
    cell : int
        Width and height in pixels of one rendered panel.
    levels : int
        Midpoint subdivision levels applied to each model before processing, at most: a level
        is skipped when it would take the model past ``max_faces``.
    max_faces : int
        Face budget of a subdivided model (a model already finer gets fewer levels; each level
        multiplies the faces, and the accurate heat method's cost, by 4).
    heat_times : tuple of float
        Heat diffusion times in units of ``s^2``, ``s`` the diagonal of the model's xy box (so
        the heat spreads as far whatever the subdivision level: a point source's heat reaches
        about ``14 sqrt(t)`` before it falls below 1e-6 of its peak).
    smooth_times : tuple of float
        Smoothing times in units of ``s^2``, ``s`` the diagonal of the model's xy box.
    compare_time : float
        Smoothing time of the mescher / cut / bent comparison, in units of ``s^2``; one of
        ``smooth_times`` so that the smoothing is computed once.
    isolines : int
        Isolines drawn on distance fields.
    """

    quick: bool
    cell: int
    levels: int
    max_faces: int = 24_000
    heat_times: tuple[float, ...] = (1e-3, 1e-2, 1e-1)
    smooth_times: tuple[float, ...] = (0.0, 2e-4, 1e-3, 5e-3)
    compare_time: float = 1e-3
    isolines: int = 10


def study_settings(quick: bool = False) -> StudySettings:
    """``--quick``: 192-pixel panels and one subdivision level; default: 320 pixels, two levels."""
    if quick:
        return StudySettings(quick=True, cell=192, levels=1)
    return StudySettings(quick=False, cell=320, levels=2)


def subdivision_levels(n_faces: int, levels: int, max_faces: int) -> int:
    """The most levels, up to ``levels``, whose result has at most ``max_faces`` faces
    (each level multiplies the faces by 4)."""
    while levels > 0 and n_faces * 4**levels > max_faces:
        levels -= 1
    return levels
