"""The one door's choice of route, as arrays (no mescher is built here, so that both
:meth:`meschers_igl.Mescher.from_model` and :func:`meschers_igl.obtain.route.model_to_mescher`
use it without an import circle).

* **cut**: an open model whose boundary loops coincide on screen and glue (a cut model, open at
  a seam) -- :func:`meschers_igl.cutmesh.cut_mesh_arrays`, face ``i`` is input face ``i``;
* **seen**: everything else (closed solids, separate blocks, soups, scenes, ordinary models, and
  every model with ``view="auto"``, ``perceive`` or ``hidden=False``) --
  :func:`meschers_igl.obtain.see.see_model`: the whole model opened at its junctions and glued
  crosswise (``report.route == "closed"``) or the visible surface (``"visible"``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..cutmesh import CutMeshArrays, camera_coordinates, cut_mesh_arrays, glue_cut_mesh
from ..errors import MescherError
from ..operators import view_frame
from ..topology import boundary_loops
from ..validate import as_faces, as_points
from .clip import PERIOD_RTOL
from .records import ConversionReport, Junction, VisibleModel
from .see import see_model

__all__ = ["PERIOD_RTOL", "ROUTES", "Obtained", "drop_small_periods", "obtain"]

#: Routes the door takes ("auto": decided from the model).
ROUTES = ("auto", "cut", "seen")

#: A model whose box centre lies more than this many box diagonals from the origin is seen from
#: its centre (:func:`obtain`).
FAR = 4.0


@dataclass(frozen=True)
class Obtained:
    """What the door found: the arrays of one route and the report.

    Attributes
    ----------
    cut : CutMeshArrays or None
        The cut route's arrays (build with ``Mescher(F, xy, edges, zeta, project=True)``).
    seen : VisibleModel or None
        The seen route's arrays (build with ``Mescher.from_corner_depths(F, xy, Z)``).
    depths : (#F, 3) float64 or None
        Cut route: the model's own corner depths, to order overlapping faces by.
    report : ConversionReport
    """

    cut: CutMeshArrays | None
    seen: VisibleModel | None
    depths: np.ndarray | None
    report: ConversionReport


def _cut_route(V, F, view, up, tol):
    """(Obtained, reason) of the cut-model route, or (None, why it does not apply)."""
    loops = boundary_loops(F)
    if not loops:
        return None, "no open seam (a closed model)"
    try:
        g = glue_cut_mesh(V, F, view=view, up=up, tol=tol)
        if not g["pairings"]:
            return None, f"{len(loops)} boundary loop(s), none coincides with another on screen"
        arrays = cut_mesh_arrays(V, F, view=view, up=up, tol=tol)
    except MescherError as err:
        return None, f"the boundary loops do not glue ({err})"
    R = view_frame(view, up)
    report = ConversionReport(view=R[2].copy(), up=R[1].copy(), route="cut")
    report.reason = (
        f"an open seam: {len(g['pairings'])} pair(s) of boundary loops coincide on screen and glue"
    )
    report.junctions = [
        Junction(
            "cut seam",
            g["xy"][g["vmap"][p.loop_a]].mean(axis=0),
            abs(p.depth_gap),
            int(p.loop_a.size),
        )
        for p in g["pairings"]
    ]
    report.source_face = np.arange(F.shape[0])
    depths = camera_coordinates(V, view, up)[:, 2][F]
    return Obtained(arrays, None, depths, report), report.reason


def obtain(
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
) -> Obtained:
    """Pick the route for a model and obtain its arrays (see the module docstring).

    A model whose bounding box's centre ``c`` lies more than :data:`FAR` diagonals from the
    origin (as in the scene it was exported from) is seen from ``c``: so far out, every plane
    and cross product would lose the digits its junctions are told by.  The screen positions
    (arrays and junctions) are moved back after, ``+ (R c)[:2]``; depths are relative and do
    not move.  (Nearer models are left where they are: a translation is exact only up to
    rounding, and their results stay bit for bit those of their own coordinates.)

    Parameters are those of :func:`meschers_igl.obtain.route.model_to_mescher`.
    """
    if route not in ROUTES:
        raise MescherError(f"route: expected one of {ROUTES}, found {route!r}")
    if hidden not in ("auto", True, False):
        raise MescherError(f"hidden: expected 'auto', True or False, found {hidden!r}")
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    centre = 0.5 * (V.min(axis=0) + V.max(axis=0)) if V.shape[0] else np.zeros(3)
    if np.linalg.norm(centre) <= FAR * np.linalg.norm(np.ptp(V, axis=0)):
        centre = np.zeros(3)
    got = _obtain(V - centre, F, view, up, perceive, tol, bridge, hidden, view_start, route)
    report = got.report
    R = view_frame(view, up) if report.view is None else view_frame(report.view, report.up)
    shift = (R @ centre)[:2]
    report.junctions = [replace(j, position=j.position + shift) for j in report.junctions]
    if got.cut is not None:
        return replace(got, cut=replace(got.cut, xy=got.cut.xy + shift))
    return replace(got, seen=replace(got.seen, xy=got.seen.xy + shift))


def _obtain(V, F, view, up, perceive, tol, bridge, hidden, view_start, route) -> Obtained:
    """:func:`obtain` on checked arrays."""
    auto_view = isinstance(view, str)
    if route == "cut" or (route == "auto" and perceive is None and not auto_view and hidden):
        if route == "cut" and (auto_view or perceive is not None):
            raise MescherError(
                f"route: expected 'auto' or 'seen' with view={view!r}, perceive={perceive!r}, "
                "found 'cut'"
            )
        done, why = _cut_route(V, F, view, up, tol)
        if done is not None:
            return done
        if route == "cut":
            raise MescherError(f"route: expected a cut model whose loops glue, found {why}")
    else:
        why = "view='auto'" if auto_view else ("perceive=" + repr(perceive) if perceive else "")
        why = "hidden=False" if hidden is False and not why else why
    vm = see_model(
        V,
        F,
        view=view,
        up=up,
        perceive=perceive,
        tol=tol,
        bridge=bridge,
        hidden=hidden,
        view_start=view_start,
    )
    if why:
        vm.report.reason = f"{why}; {vm.report.reason}" if vm.report.reason else why
    return Obtained(None, vm, None, vm.report)


def drop_small_periods(m: Any, report: ConversionReport, rtol: float = PERIOD_RTOL) -> Any:
    """Set the periods under ``rtol`` times the model's size to zero (noise of the gluing, not a
    junction), keeping the exact part; said in ``report.repairs``.

    Parameters
    ----------
    m : Mescher
    report : ConversionReport

    Returns
    -------
    Mescher
        ``m`` itself when nothing changed, else ``m.with_periods(p')``.
    """
    p = np.asarray(m.periods())
    small = (np.abs(p) <= rtol * m.scale()) & (p != 0)
    if not small.any():
        return m
    report.repairs.append(
        f"{int(small.sum())} period(s) under {rtol:g} of the size (at most "
        f"{float(np.abs(p[small]).max()):.3g}) set to zero: gluing noise, not a junction"
    )
    return m.with_periods(np.where(small, 0.0, p))
