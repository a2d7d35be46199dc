"""Artist models seen from a view, as (mescher, depth order) pairs: the one place that does it.

Two kinds of 3D model reach meschers (paper Sec. 3.5):

* a **cut model**, open along a seam whose two sides coincide on screen
  (:func:`cut_model_to_mescher`: glue the seam with :func:`meschers_igl.cutmesh.glue_cut_mesh`,
  order the faces that overlap on screen by the model's own depths);
* **any model** -- closed solids, separate blocks, reliefs -- seen from a view
  (:func:`model_to_mescher`: by default the whole model opened at its junctions -- caps that
  coincide on screen, bars broken behind an occluder -- and glued crosswise like a cut model,
  a closed surface; else, or with ``hidden=False``, what the viewer sees, false edges glued
  crosswise; see :mod:`meschers_igl.visible`).  A cut file gives the cut-model path's
  mescher either way.

``meshlab_filters``, the PyVista accessor and the command line all call these, so a cut model
becomes the same mescher and the same order whichever door it comes in through.
"""

from __future__ import annotations

from typing import Any

from .cutmesh import camera_coordinates
from .mescher import Mescher
from .order import DepthOrder
from .validate import as_faces, as_points
from .visible import ConversionReport, see_model

__all__ = ["cut_model_to_mescher", "model_to_mescher"]


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
) -> tuple[Mescher, DepthOrder, ConversionReport]:
    """Any 3D model seen from a view: the mescher of what the viewer sees, its depth order and
    a conversion report.

    :func:`meschers_igl.visible.see_model` builds either the whole model opened at its
    junctions and glued crosswise like a cut model (``hidden``: a closed surface that keeps
    the hidden side, its order from the model's own depths) or the visible surface (false
    edges glued crosswise, true occlusions kept apart, hidden gaps bridged); the mescher is
    ``Mescher.from_corner_depths`` of its per-face depths (edge values averaged, then projected
    onto locally integrable forms, paper Eq. 3-4) and the order holds the occlusion and bridge
    arcs.

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
        Keep the hidden side where the gluing is unambiguous (see
        :func:`meschers_igl.visible.see_model`); ``False``: the visible surface only.
    view_start : (3,) array_like, optional
        With ``view="auto"``: a view near the intended one (within 10 degrees).

    Returns
    -------
    m : Mescher
    order : DepthOrder
    report : ConversionReport
        Junctions (screen position, depth gap), arcs, repairs, snapping, warnings, the view.
    """
    vm = see_model(
        V, F, view=view, up=up, perceive=perceive, tol=tol, bridge=bridge, hidden=hidden,
        view_start=view_start,
    )  # fmt: skip
    m = Mescher.from_corner_depths(vm.F, vm.xy, vm.Z)
    return m, DepthOrder(m.n_faces, vm.arcs, m=m), vm.report
