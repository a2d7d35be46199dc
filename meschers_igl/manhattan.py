"""Perceived right angles (``perceive="manhattan"``): :mod:`meschers_igl.obtain.perceive`."""

from __future__ import annotations

from .obtain.perceive import (
    CREASE,
    FACING,
    MAX_SNAP,
    model_face_axes,
    perceive_manhattan,
    perceived_frame,
    snap_to_manhattan,
)

__all__ = [
    "CREASE",
    "FACING",
    "MAX_SNAP",
    "model_face_axes",
    "perceive_manhattan",
    "perceived_frame",
    "snap_to_manhattan",
]
