"""meschers_igl: the mescher representation and its geometry processing (numpy, scipy, libigl).

A *mescher* (Dodik et al., "Meschers: Geometry Processing of Impossible Objects", ACM TOG 2025)
stores screen positions per vertex and relative depths per edge that integrate to zero around
every triangle but not necessarily around longer loops.
"""

from __future__ import annotations

from .errors import MescherError, MescherWarning
from .hodge import HodgeDecomposition
from .mescher import Mescher

__all__ = [
    "Mescher",
    "MescherError",
    "MescherWarning",
    "HodgeDecomposition",
    "DepthOrder",
    "HeatGeodesicSolver",
    "save",
    "load",
]

__version__ = "0.1.0"


def __getattr__(name: str):
    # Modules written alongside the core load on first use, keeping `import meschers_igl` light.
    if name == "DepthOrder":
        from .order import DepthOrder

        return DepthOrder
    if name == "HeatGeodesicSolver":
        from .geodesic import HeatGeodesicSolver

        return HeatGeodesicSolver
    if name in ("save", "load"):
        from . import io

        return getattr(io, name)
    raise AttributeError(f"module 'meschers_igl' has no attribute {name!r}")
