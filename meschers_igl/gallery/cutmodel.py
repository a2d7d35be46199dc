"""What a gallery builder returns: a cut 3D model, its view, and how to glue it."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class CutModel:
    """A builder's cut model of an impossible figure (world frame, :doc:`/conventions`).

    Attributes
    ----------
    V : (#V, 3) array_like of float
    F : (#F, 3) array_like of int
        Outward-oriented triangles.
    view, up : (3,) tuple of float
        Direction toward the orthographic camera, and screen up.
    period : float
        Depth gained once around the figure's loop, 0 when it is impossible only through its
        depth order.
    build : callable, optional
        Returns ``(mescher, vmap)`` when the mescher is not the glued cut model.
    front_back : ((k,) int, (l,) int), optional
        Faces put in front of other faces after the order from the cut model's depths.
    """

    V: Any
    F: Any
    view: tuple
    up: tuple
    period: float
    build: Callable[[], tuple[Any, np.ndarray]] | None = None
    front_back: tuple[np.ndarray, np.ndarray] | None = None
