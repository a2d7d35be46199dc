"""Geodesic distance and shortest paths on meschers.

One front door: :func:`geodesic_solver` (a solver per method, set up once, queried with
``distance(sources)``) and :func:`geodesic_distance` (one-off), over the registry
:data:`SOLVERS`:

* :mod:`~meschers_igl.geodesic.heat`: the heat method (:class:`HeatGeodesicSolver`, its
  presets) and heat diffusion;
* :mod:`~meschers_igl.geodesic.exact`: exact distances by window propagation on the intrinsic
  mesh (:class:`ExactGeodesicSolver`);
* :class:`~meschers_igl.covering.CoveringGeodesicSolver`: MMP on a covering, the oracle;
* :mod:`~meschers_igl.geodesic.paths`: shortest paths (:func:`shortest_path`), paths through
  waypoints and closed geodesics.
"""

from __future__ import annotations

from ..covering import CoveringGeodesicSolver
from .exact import ExactGeodesicSolver
from .heat import HeatGeodesicSolver, choose_method, heat_diffuse, saddle_relief
from .methods import SOLVERS, GeodesicSolver, geodesic_distance, geodesic_solver, methods
from .paths import SurfacePath, shortest_loops, shortest_path, shortest_path_through

__all__ = [
    "SOLVERS",
    "CoveringGeodesicSolver",
    "ExactGeodesicSolver",
    "GeodesicSolver",
    "HeatGeodesicSolver",
    "SurfacePath",
    "choose_method",
    "geodesic_distance",
    "geodesic_solver",
    "heat_diffuse",
    "methods",
    "saddle_relief",
    "shortest_loops",
    "shortest_path",
    "shortest_path_through",
]
