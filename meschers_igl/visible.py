"""Any 3D model seen from a view: the names of :mod:`meschers_igl.obtain` under their first
home (see :mod:`meschers_igl.obtain` for the pipeline)."""

from __future__ import annotations

from .obtain.cleanup import drop_contact_faces, orient_outward, solid_like_parts, weld
from .obtain.clip import FRONT_NZ, REL_GRID, REL_TOL
from .obtain.junctions import BarEnds, bar_end_pairs, close_junctions
from .obtain.records import ConversionReport, Junction, VisibleModel
from .obtain.see import see_model
from .obtain.view import find_model_view

__all__ = [
    "FRONT_NZ",
    "REL_GRID",
    "REL_TOL",
    "BarEnds",
    "ConversionReport",
    "Junction",
    "VisibleModel",
    "bar_end_pairs",
    "close_junctions",
    "drop_contact_faces",
    "find_model_view",
    "orient_outward",
    "see_model",
    "solid_like_parts",
    "weld",
]
