"""The front door of geodesic distance: one registry of solver classes, one call.

Every method is a class built once per mesh, ``Solver(m, **options)``, that answers queries
with ``distance(sources, targets=None)`` (potpourri3d's shape): a ``(#V,)`` array, the distance
to the nearest source, ``inf`` where no source is reachable.  ``targets`` is a hint: the values
at the targets are always right, and a solver may stop once they are final (``inf`` beyond).
:data:`SOLVERS` maps each method name to its class (or to a class with its preset bound);
adding a method is one class and one line there.
"""

from __future__ import annotations

from functools import partial
from typing import Any, Protocol

import numpy as np

from ..covering import CoveringGeodesicSolver
from ..validate import as_choice, as_index_array
from .exact import ExactGeodesicSolver
from .heat import METHODS as HEAT_METHODS
from .heat import HeatGeodesicSolver

__all__ = ["SOLVERS", "GeodesicSolver", "geodesic_distance", "geodesic_solver", "methods"]


class GeodesicSolver(Protocol):
    """What a registered method builds: set up once for ``m``, then queried."""

    m: Any
    n_vertices: int

    def distance(self, sources: Any, targets: Any = None) -> np.ndarray: ...


#: method name -> solver class (a callable ``(m, **options) -> GeodesicSolver``)
SOLVERS: dict[str, Any] = {
    **{name: partial(HeatGeodesicSolver, method=name) for name in HEAT_METHODS},
    "exact": ExactGeodesicSolver,
    "covering": CoveringGeodesicSolver,
}


def methods() -> tuple[str, ...]:
    """The registered method names (``"auto"`` first: the default)."""
    return tuple(SOLVERS)


def geodesic_solver(m: Any, method: str = "auto", **options: Any) -> GeodesicSolver:
    """A solver for ``m`` by ``method``, set up once and queried with ``distance(sources)``.

    Parameters
    ----------
    m : Mescher
    method : str, default: "auto"
        A key of :data:`SOLVERS`: a heat-method preset (``"auto"``, ``"standard"``,
        ``"robust"``, ``"refined"``, ``"accurate"``, ``"geometry_central"``;
        :class:`~meschers_igl.geodesic.heat.HeatGeodesicSolver` says what ``"auto"`` chooses
        when), ``"exact"`` (window propagation on the intrinsic mesh,
        :class:`~meschers_igl.geodesic.exact.ExactGeodesicSolver`) or ``"covering"`` (MMP on
        the covering, :class:`~meschers_igl.covering.CoveringGeodesicSolver`: an independent
        oracle).
    **options
        Passed to the solver class.

    Returns
    -------
    GeodesicSolver
    """
    method = as_choice(method, "method", methods())
    return SOLVERS[method](m, **options)


def geodesic_distance(
    m: Any, sources: Any, method: str = "auto", targets: Any = None, **options: Any
) -> np.ndarray:
    """One-off geodesic distance: ``geodesic_solver(m, method, **options).distance(sources)``.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) array_like of int
    method : str, default: "auto"
        See :func:`geodesic_solver`.
    targets : int or (t,) array_like of int, optional
        The vertices wanted: exact there, possibly ``inf`` farther away (see the module
        docstring).
    **options
        Passed to the solver class.

    Returns
    -------
    d : (#V,) float64
    """
    as_index_array(sources, "sources", int(m.n_vertices))  # fail before setting up
    return geodesic_solver(m, method, **options).distance(sources, targets)
