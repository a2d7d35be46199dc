"""Obtaining a mescher from a 3D model seen from a view (paper Sec. 3.5).

The one door, :func:`model_to_mescher` (:mod:`.route`), picks the route (:mod:`.choose`):

* a **cut model**, open at a seam whose loops coincide on screen, is glued there
  (:mod:`meschers_igl.cutmesh`);
* anything else is **seen** (:func:`see_model`, :mod:`.see`), a short pipeline:

  1. :mod:`.cleanup` -- weld, drop contact faces, orient each part outward;
  2. :mod:`.view` -- ``view="auto"``: the view from which junctions line up (on Penrose
     stairs, :mod:`.view_stairs`: the view along which the bottom step sits where the step
     after the top would be; on a relief, its carved front, :func:`relief_fronts`);
  3. :mod:`.junctions` -- the whole model opened at paired caps (false edges, hidden gaps) and
     glued crosswise, a closed surface keeping the hidden side, when junctions are found;
  4. else :mod:`.clip` -- exact hidden-surface removal and the visible map;
  5. :mod:`.glue` -- continuous edges and false edges glued, true occlusions cut (with arcs),
     hidden risers joined by narrow riser bands; :mod:`.stairs` -- the top tread of a
     staircase seen over a wall rising to its bottom tread glued as a false edge;
  6. :mod:`.amodal` -- hidden gaps bridged behind their occluders;
  7. :mod:`.perceive` -- ``perceive="manhattan"``: normals snapped to the perceived frame.

What a step hands the next is a typed record (:mod:`.records`): :class:`Junction`,
:class:`ConversionReport`, :class:`VisibleModel`, :class:`Glue`, :class:`EdgeSides`,
:class:`FalseEdges`.
"""

from __future__ import annotations

from .choose import PERIOD_RTOL, ROUTES, Obtained, drop_small_periods, obtain
from .cleanup import drop_contact_faces, drop_repeated_faces, orient_outward, solid_like_parts, weld
from .junctions import BarEnds, bar_end_pairs, close_junctions
from .perceive import model_face_axes, perceive_manhattan, perceived_frame, snap_to_manhattan
from .records import ConversionReport, EdgeSides, FalseEdges, Glue, Junction, VisibleModel
from .route import cut_model_to_mescher, model_to_mescher
from .see import see_model
from .view import find_model_view, find_view, relief_fronts, up_for_view

__all__ = [
    "PERIOD_RTOL",
    "ROUTES",
    "BarEnds",
    "ConversionReport",
    "EdgeSides",
    "FalseEdges",
    "Glue",
    "Junction",
    "Obtained",
    "VisibleModel",
    "bar_end_pairs",
    "close_junctions",
    "cut_model_to_mescher",
    "drop_contact_faces",
    "drop_repeated_faces",
    "drop_small_periods",
    "find_model_view",
    "find_view",
    "model_face_axes",
    "model_to_mescher",
    "obtain",
    "orient_outward",
    "perceive_manhattan",
    "perceived_frame",
    "relief_fronts",
    "see_model",
    "snap_to_manhattan",
    "solid_like_parts",
    "up_for_view",
    "weld",
]
