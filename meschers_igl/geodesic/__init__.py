"""Geodesic distance and shortest paths on meschers.

* :mod:`~meschers_igl.geodesic.heat`: the heat method (:class:`HeatGeodesicSolver`) and heat
  diffusion;
* :mod:`~meschers_igl.geodesic.exact`: exact distances by window propagation on the intrinsic
  mesh (:class:`ExactGeodesicSolver`);
* :mod:`~meschers_igl.geodesic.paths`: shortest paths (:func:`shortest_path`), paths through
  waypoints and closed geodesics.
"""

from __future__ import annotations

from .exact import ExactGeodesicSolver, exact_geodesic
from .heat import HeatGeodesicSolver, choose_method, heat_diffuse, saddle_relief
from .paths import (
    SurfacePath,
    exact_geodesic_distance,
    geodesic_distance,
    shortest_loops,
    shortest_path,
    shortest_path_through,
)

__all__ = [
    "ExactGeodesicSolver",
    "HeatGeodesicSolver",
    "SurfacePath",
    "choose_method",
    "exact_geodesic",
    "exact_geodesic_distance",
    "geodesic_distance",
    "heat_diffuse",
    "saddle_relief",
    "shortest_loops",
    "shortest_path",
    "shortest_path_through",
]
