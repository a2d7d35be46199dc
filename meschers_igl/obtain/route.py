"""Artist models seen from a view, as (mescher, depth order) pairs: the one place that does it.

Two kinds of 3D model reach meschers (paper Sec. 3.5):

* a **cut model**, open along a seam whose two sides coincide on screen
  (:func:`cut_model_to_mescher`: glue the seam with :func:`meschers_igl.cutmesh.glue_cut_mesh`,
  order the faces that overlap on screen by the model's own depths);
* **any model** -- closed solids, separate blocks, reliefs -- seen from a view
  (:func:`model_to_mescher`: by default the whole model opened at its junctions -- caps that
  coincide on screen, bars broken behind an occluder -- and glued crosswise like a cut model,
  a closed surface; else, or with ``hidden=False``, what the viewer sees, false edges glued
  crosswise; see :mod:`meschers_igl.obtain.see`).  A cut file gives the cut-model path's
  mescher either way.

``meshlab_filters``, the PyVista accessor and the command line all call these, so a cut model
becomes the same mescher and the same order whichever door it comes in through.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..cutmesh import camera_coordinates
from ..mescher import Mescher
from ..order import DepthOrder
from ..validate import as_faces, as_points
from .choose import PERIOD_RTOL, ROUTES, drop_small_periods, obtain
from .records import ConversionReport

__all__ = [
    "PERIOD_RTOL",
    "ROUTES",
    "cut_model_to_mescher",
    "drop_small_periods",
    "model_to_mescher",
]


def cut_model_to_mescher(
    V: Any,
    F: Any,
    view: Any = (0.0, 0.0, 1.0),
    up: Any = (0.0, 1.0, 0.0),
    tol: float | None = None,
    merge: Any = None,
) -> tuple[Mescher, DepthOrder]:
    """The mescher of a cut 3D model and the depth order of its overlapping faces.

    ``m = Mescher.from_cut_mesh(V, F, view, up, tol, merge)`` glues the coincident cut loops;
    ``order = DepthOrder.from_embedding(m, Zc)`` orders the faces that overlap on screen by the
    model's own depths ``Zc[f, k] = (V R^T)[F[f, k], 2]`` with ``R = view_frame(view, up)``.

    Parameters
    ----------
    V : (#V, 3) array_like of float
        Cut model, world frame.
    F : (#F, 3) array_like of int
        Oriented triangles.
    view : (3,) array_like, default: (0, 0, 1)
        Direction from the model toward the orthographic camera.
    up : (3,) array_like, default: (0, 1, 0)
        Screen up.
    tol : float, optional
        Gluing tolerance relative to the bounding-box diagonal (default 1e-5).
    merge : (k, 2) array_like of int, optional
        Explicit vertex pairs to glue instead of the automatic loop pairing.

    Returns
    -------
    m : Mescher
        Face ``i`` is face ``i`` of the input.
    order : DepthOrder
        Arc ``i -> j`` when face ``i`` is behind face ``j`` where they overlap on screen.
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    m = Mescher.from_cut_mesh(V, F, view=view, up=up, tol=tol, merge=merge)
    Zc = camera_coordinates(V, view, up)[:, 2][F]
    return m, DepthOrder.from_embedding(m, Zc)


def model_to_mescher(
    V: Any,
    F: Any,
    view: Any = (0.0, 0.0, 1.0),
    up: Any = (0.0, 1.0, 0.0),
    perceive: str | None = None,
    *,
    tol: float | None = None,
    bridge: bool = True,
    hidden: bool | str = "auto",
    view_start: Any = None,
    route: str = "auto",
) -> tuple[Mescher, DepthOrder, ConversionReport]:
    """Any 3D model seen from a view -- the one door: it picks the route, and says which and why.

    * **cut** route: an open model whose boundary loops coincide on screen and glue (a cut
      model, open at a seam): :func:`cut_model_to_mescher`, face ``i`` is input face ``i``;
    * **seen** route, everything else (closed solids, separate blocks, soups, scenes, ordinary
      models, and every model with ``view="auto"``, ``perceive`` or ``hidden=False``):
      :func:`meschers_igl.visible.see_model` builds either the whole model opened at its
      junctions and glued crosswise (``report.route == "closed"``) or the visible surface
      (``"visible"``: false edges glued crosswise, true occlusions kept apart, hidden gaps
      bridged); the mescher is ``Mescher.from_corner_depths`` of its per-face depths (edge
      values averaged, then projected onto locally integrable forms, paper Eq. 3-4) and the
      order holds the occlusion and bridge arcs.

    An ordinary model gives a possible mescher: periods under :data:`PERIOD_RTOL` of the size
    are gluing noise and set to zero (:func:`drop_small_periods`).

    Parameters
    ----------
    V : (#V, 3) array_like of float
    F : (#F, 3) array_like of int
    view : (3,) array_like or "auto", default: (0, 0, 1)
    up : (3,) array_like, default: (0, 1, 0)
    perceive : {None, "manhattan"}
    tol : float, optional
        Relative tolerance (default 1e-5 of the bounding-box diagonal).
    bridge : bool, default: True
        Bridge hidden gaps (amodal completion).
    hidden : {"auto", True, False}, default: "auto"
        Seen route: keep the hidden side where the gluing is unambiguous (see
        :func:`meschers_igl.visible.see_model`); ``False``: the visible surface only.
    view_start : (3,) array_like, optional
        With ``view="auto"``: a view near the intended one (within 10 degrees).
    route : {"auto", "cut", "seen"}, default: "auto"
        Override the choice: ``"cut"`` refuses a model whose loops do not glue.

    Returns
    -------
    m : Mescher
    order : DepthOrder
    report : ConversionReport
        Route and reason, junctions (screen position, depth gap), arcs, repairs, snapping,
        warnings, the view.
    """
    got = obtain(
        V,
        F,
        view,
        up,
        perceive,
        tol=tol,
        bridge=bridge,
        hidden=hidden,
        view_start=view_start,
        route=route,
    )
    report = got.report
    if got.cut is not None:
        a = got.cut
        m = Mescher(a.F, a.xy, a.edges, a.zeta, project=True)
        order = DepthOrder.from_embedding(m, got.depths)
        report.arcs = np.asarray(order.arcs, dtype=np.int64).reshape(-1, 2)
        report.n_arcs = order.n_arcs
    else:
        m = Mescher.from_corner_depths(got.seen.F, got.seen.xy, got.seen.Z)
        order = DepthOrder(m.n_faces, got.seen.arcs, m=m)
    return drop_small_periods(m, report), order, report
