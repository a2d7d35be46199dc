from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from ..errors import MescherError, MescherWarning
from ..operators import view_frame
from ..validate import as_faces, as_points
from .amodal import bridge_hidden_gaps
from .bar_joints import coincident_gaps, corner_vertices, join_ends, prepare_joints
from .cleanup import (
    drop_contact_faces,
    drop_repeated_faces,
    manifold_notes,
    open_faces,
    orient_outward,
    pinch_warning,
    solid_like_parts,
    weld,
)
from .clip import FRONT_NZ, PERIOD_RTOL, REL_GRID, REL_TOL, plane_depth, visible_map
from .glue import (
    STEP_BAND,
    add_step_bands,
    classify,
    cut_and_glue,
    depths_have_period,
    false_edge_junctions,
    hidden_step_edges,
    narrow_step_bands,
    reglue,
    split_cut_faces,
    stuck_cuts,
)
from .junctions import closed_surface
from .openings import RING_PARTS, period_around_opening
from .perceive import model_face_axes, perceive_manhattan, perceived_frame
from .records import ConversionReport, VisibleModel
from .stairs import glue_step_junctions, step_junctions
from .view import START_ANGLE, find_model_view, relief_fronts, up_for_view


def _visible_report(report, junctions, arcs, is_bridge, source, perceive) -> None:
    """Fill ``report`` for the visible route: its junctions, reason, arcs and each face's
    source face (-1 for a bridge's)."""
    report.junctions = junctions
    report.route = "visible"
    if not report.reason:
        report.reason = (
            "perceived depths are read on the visible surface"
            if perceive
            else "no junction to open on the whole model: the surface the viewer sees"
        )
    report.n_arcs = int(arcs.shape[0])
    report.source_face = np.where(is_bridge, -1, source)
    report.arcs = arcs


def see_model(
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
    snap: bool = True,
) -> VisibleModel:
    """The visible surface of a 3D model from an orthographic view, false edges glued.

    Parameters
    ----------
    V : (#V, 3) array_like of float
        Model vertices (world frame); closed solids, separate parts, open reliefs, soups.
    F : (#F, 3) array_like of int
        Triangles (any orientation: each part is oriented outward by its signed volume).
    view : (3,) array_like or "auto", default: (0, 0, 1)
        Direction from the model toward the camera; ``"auto"``: the view from which the
        model's junctions line up (:func:`find_model_view`; reported in ``report.view``), or a
        relief's front (:func:`relief_fronts`) from which the perceived reading is impossible:
        with ``perceive``, or when nothing lines up (possible as carved, with a warning).
    up : (3,) array_like, default: (0, 1, 0)
        Screen up (with ``view="auto"``: world +z projected, as modelling tools do).
    perceive : {None, "manhattan"}, default: None
        ``"manhattan"``: snap each face's normal to the perceived orthogonal frame and
        re-project zeta (paper Eq. 3-4), see :mod:`meschers_igl.manhattan`; the angles are in
        ``report.snapped``.
    tol : float, optional
        Relative tolerance (of the bounding-box diagonal) for screen coincidence and depth
        continuity; default :data:`REL_TOL`.
    bridge : bool, default: True
        Bridge hidden gaps (amodal completion).
    view_start : (3,) array_like, optional
        With ``view="auto"``: a view near the intended one (searched within 10 degrees).
    snap : bool, default: True
        A given view is a person's, approximate: when no junction is seen from it, the view
        within :data:`SNAP_ANGLE` from which one lines up is taken (reported in
        ``report.reason`` and ``report.repairs``).
    hidden : {"auto", True, False}, default: "auto"
        Keep the hidden side: the whole model, opened at its junctions and glued crosswise by
        the cut-model path (:func:`close_junctions`, :func:`meschers_igl.cutmesh.glue_cut_mesh`),
        a closed surface like a cut model's, with its own depths and the order of its
        overlapping faces.  ``"auto"``: when junctions are found (paired caps, hidden gaps,
        coinciding cut loops) and the gluing is a manifold, else (and with ``perceive``) the
        visible surface; ``True``: refuse when it cannot be built; ``False``: always the
        visible surface.

    Returns
    -------
    VisibleModel
        ``F``, ``xy``, per-face corner depths ``Z`` (zeta of an edge is the depth difference
        along it, the same on both sides of a glued false edge), depth-order ``arcs`` and the
        ``report``.

    Raises
    ------
    MescherError
        Bad arrays, a model with no face toward the viewer.
    """
    V, F, part, report, rel, tol_abs, grid = _prepare(V, F, perceive, tol)
    _check_options(view, view_start, hidden, perceive)
    found = isinstance(view, str)
    snap = snap and not found  # a found view is exact already
    if isinstance(view, str):
        try:
            view, up = _auto_view(V, F, tol_abs, view_start, perceive)
        except MescherError as err:
            vm = (
                None
                if perceive
                else _relief_read(V, F, tol_abs, rel, view_start, bridge, hidden, err)
            )
            if vm is None:
                raise
            return vm
    R = view_frame(view, up)
    report.view, report.up = R[2].copy(), R[1].copy()
    pinch_warning(F, report)
    manifold_notes(F, report)
    if hidden is not False and perceive is None:
        closed = closed_surface(V, F, R, tol_abs, rel, bridge, report, strict=hidden is True)
        if closed is not None:
            return closed
    C = V @ R.T
    F, N, front = _facing(V, F, C, part, report)
    xy, Fa, src, pl_all = visible_map(C, F, front, tol_abs, grid)
    joints = None  # bar ends hidden exactly behind bar ends (not with perceived depths)
    if perceive is None:
        xy, Fa, src, joints = prepare_joints(xy, Fa, src, pl_all, C, F, front, tol_abs, grid)
    ftol = _part_tolerances(V, F, part, tol_abs, rel)
    glue_args = (xy, Fa, src, pl_all, C, F, N, front, tol_abs, ftol, bridge, perceive, report)
    g = _glue_visible(*glue_args, joints)
    chance = _lined_up_by_chance(g, part, F.shape[0], tol_abs) if perceive is None else None
    if chance is not None:  # blocks lined up by chance: glued again without what joined them
        g = _glue_visible(*glue_args, plain=chance == "plain")
    Fm, corner_vertex, xy, Zb, arcs, fe, bridges, is_bridge, sb = g
    _visible_report(report, false_edge_junctions(xy, fe) + bridges, arcs, is_bridge, sb, perceive)
    first = _corner_of_vertex(Fm, corner_vertex)
    if snap and perceive is None and hidden is not False and not _has_junction(report, tol_abs):
        snapped = _snap_view(V, F, R, tol_abs, rel, bridge, hidden)
        if snapped is not None:
            return snapped
    if found and perceive is None and not _has_junction(report, tol_abs):
        err = MescherError(
            f"view: expected a view from which junctions line up, found "
            f"{np.round(R[2], 4).tolist()} (lining up bar ends) from which none is glued; pass "
            "view= or view_start="
        )
        vm = _relief_read(V, F, tol_abs, rel, view_start, bridge, hidden, err)
        if vm is None:
            raise err
        return vm
    _expectation_warning(report, V, F, C, front)
    return VisibleModel(F=Fm, xy=xy[first], Z=Zb, arcs=arcs, report=report)


def _prepare(V: Any, F: Any, perceive: str | None, tol: float | None):
    """Checked and cleaned arrays, the report, and the tolerances (relative, absolute, grid)."""
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    if perceive not in (None, "manhattan"):
        raise MescherError(f"perceive: expected None or 'manhattan', found {perceive!r}")
    used = np.unique(F)
    diag = float(np.linalg.norm(V[used].max(axis=0) - V[used].min(axis=0)))
    if diag == 0.0:
        raise MescherError("V: expected vertices spanning a non-empty box, found a single point")
    report = ConversionReport()
    rel = REL_TOL if tol is None else float(tol)
    tol_abs = rel * diag
    V, F, part = _clean(V, F, tol_abs, report)
    return V, F, part, report, rel, tol_abs, REL_GRID * diag


def _has_junction(report, tol: float) -> bool:
    return any(j.depth_gap > tol for j in report.junctions if j.kind != "occluded continuation")


#: A given view is a person's: when no junction lines up from it, the view within this angle
#: (radians) from which one does is taken (and reported).
SNAP_ANGLE = np.radians(3.0)


def _snap_view(V, F, R, tol_abs, rel, bridge, hidden):
    """The model seen from the view within :data:`SNAP_ANGLE` of ``R``'s from which a junction
    lines up (:func:`find_model_view` started at it, else the direction of a single pair of
    corners lining up, :func:`_pair_views`), with the snap reported; None if none."""

    def judge(v, u):
        return _false_edge_seen(V, F, v, u, tol_abs)

    def views():  # the vote's view, then single pairs' (nearest first), judged lazily
        try:
            yield find_model_view(V, F, tol_abs, start=R[2], judge=judge, within=SNAP_ANGLE)[0]
        except MescherError:
            pass
        # one pair of corners lining up (the vote above needs two pairs along one direction):
        # taken when they are joined there (a crease joint, their gap); a pair lines up within
        # a few degrees of almost any view, and other coincidences from its direction are
        # accidents the person did not choose
        for w, gap in _pair_views(V, F, R, tol_abs, SNAP_ANGLE):
            up = _up_on(R, w)
            if _shared_gap(V, F, w, up, tol_abs, gap):
                continue  # two or more pairs that far apart: the vote's to judge, above
            if _joint_seen(V, F, w, up, tol_abs, gap):
                yield w

    for v in views():
        angle = float(np.degrees(np.arctan2(np.linalg.norm(np.cross(v, R[2])), v @ R[2])))
        if angle <= 1e-4:
            continue  # the given view itself, to round-off: nothing lines up better
        vm = see_model(V, F, v, _up_on(R, v), tol=rel, bridge=bridge, hidden=hidden, snap=False)
        if _has_junction(vm.report, tol_abs):
            break
    else:
        return None
    vm.report.reason = (
        f"view snapped by {angle:.3g} degrees to the view from which the junctions line up; "
        + vm.report.reason
    )
    vm.report.repairs.append(
        f"view snapped by {angle:.3g} degrees (a person's view is approximate)"
    )
    return vm


def _up_on(R, v):
    """The person's up (``R[1]``), kept on the screen of view ``v``."""
    return R[1] - (R[1] @ v) * v


#: Most single corner pairs whose directions :func:`_pair_views` returns (each is judged by
#: seeing the model from it).
MAX_PAIR_VIEWS = 4
#: Most corners :func:`_pair_views` pairs (a fine mesh, every vertex a corner, has no bar
#: tips to line up; its pairs within a few degrees would be quadratic in number).
MAX_PAIR_CORNERS = 2000


def _pair_views(V, F, R, tol_abs, within) -> list:
    """(unit direction toward the camera side of ``R[2]``, distance) of the pairs of corners
    (:func:`~.bar_joints.corner_vertices`) that line up within ``within`` (radians) of the view
    ``R[2]``, nearest first, at most :data:`MAX_PAIR_VIEWS`: from each, those two corners
    coincide on screen (two mitred tips meeting at a point), that far apart in depth."""
    C = V @ R.T
    vs = np.unique(F)
    vs = vs[corner_vertices(C, F)[vs]]
    if vs.size < 2 or vs.size > MAX_PAIR_CORNERS:
        return []
    P = C[vs]
    # two corners dz apart in depth line up within `within` when dz tan(within) apart on screen
    r = float(np.ptp(P[:, 2])) * np.tan(within) + tol_abs
    pr = cKDTree(P[:, :2]).query_pairs(r, output_type="ndarray")
    if pr.size == 0:
        return []
    D = V[vs[pr[:, 1]]] - V[vs[pr[:, 0]]]
    L = np.linalg.norm(D, axis=1)
    D, L = D[L > 100 * tol_abs], L[L > 100 * tol_abs]
    ang = np.arccos(np.clip(np.abs(D @ R[2]) / L, 0.0, 1.0))
    k = np.flatnonzero((ang <= within) & (ang > np.radians(1e-4)))  # not the view itself
    k = k[np.argsort(ang[k], kind="stable")][:MAX_PAIR_VIEWS]
    return [(D[i] / L[i] * np.sign(D[i] @ R[2]), float(L[i])) for i in k.tolist()]


def _shared_gap(V, F, v, up, tol, gap) -> bool:
    """Do two or more pairs of corners coincide ``gap`` apart in depth (to 10 ``tol``) from
    ``v`` (:func:`~.bar_joints.coincident_gaps`)?  Then the view is no single pair's: blocks on
    a grid line up many pairs along a few directions, which the vote judges by their false
    edges."""
    C = V @ view_frame(v, up).T
    return any(abs(g - gap) <= 10.0 * tol for g, _, _ in coincident_gaps(C, F, tol))


def _joint_seen(V, F, v, up, tol, gap) -> bool:
    """Does the visible surface from ``v`` join bar ends (a ``"bar joint"``) ``gap`` apart in
    depth (to 10 ``tol``), with a loop that gains depth?"""
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        try:
            vm = see_model(V, F, v, up, tol=tol / diag, bridge=False, hidden=False, snap=False)
        except MescherError:
            return False
    if not any(
        j.kind == "bar joint" and abs(j.depth_gap - gap) <= 10.0 * tol for j in vm.report.junctions
    ):
        return False
    return depths_have_period(vm.F, vm.Z, 10.0 * tol)


def _clean(V, F, tol_abs, report):
    """Weld (a soup: corners apart by less than the tolerance), drop contact faces, orient
    each part outward; the repairs go to the report.  Returns (V, F, part)."""
    V, F, n_merged = weld(V, F, 0.5 * tol_abs)
    if n_merged:
        report.repairs.append(f"welded {n_merged} vertex(es) that coincide in 3D")
    F, n_repeat = drop_repeated_faces(F)
    if n_repeat:
        report.repairs.append(f"removed {n_repeat} repeated face(s) (a part duplicated in place)")
    F, n_contact = drop_contact_faces(F)
    if n_contact:
        report.repairs.append(
            f"removed {n_contact} pair(s) of coincident opposite faces (blocks touching)"
        )
    if F.shape[0] == 0:
        raise MescherError(
            "F: expected faces left after clean-up, found none (every face lies on another, "
            "facing it: a sheet of two sides or a degenerate model)"
        )
    F, n_flip, part = orient_outward(V, F)
    if n_flip:
        n_parts = int(part.max()) + 1
        report.repairs.append(f"re-oriented {n_flip} face(s) outward ({n_parts} part(s))")
    return V, F, part


def _check_options(view, view_start, hidden, perceive) -> None:
    if view_start is not None and not (isinstance(view, str) and view == "auto"):
        raise MescherError(f"view_start: expected view='auto' with it, found view={view!r}")
    if isinstance(view, str) and view != "auto":
        raise MescherError(f"view: expected a direction (3,) or 'auto', found {view!r}")
    if hidden not in ("auto", True, False):
        raise MescherError(f"hidden: expected 'auto', True or False, found {hidden!r}")
    if hidden is True and perceive is not None:
        raise MescherError(
            f"hidden: expected False or 'auto' with perceive={perceive!r} (perceived depths are "
            "read on the visible surface), found True"
        )


def _facing(V, F, C, part, report):
    """Open parts (a relief, a sheet) have no outside: each is turned toward the view.
    Returns (F, N (#F, 3) camera-frame normals, front (#F,) bool)."""
    N = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    open_face = open_faces(F)
    k = int(part.max()) + 1
    is_open = np.bincount(part, weights=open_face, minlength=k) > 0
    is_open &= ~solid_like_parts(V, F, part)  # nearly closed: oriented by its volume already
    away = is_open & (np.bincount(part, weights=N[:, 2], minlength=k) < 0)
    if away.any():
        turn = away[part]
        F = F.copy()
        F[turn] = F[turn][:, [0, 2, 1]]
        N[turn] *= -1
        report.repairs.append(f"turned {int(away.sum())} open part(s) toward the viewer")
    nrm = np.linalg.norm(N, axis=1)
    front = N[:, 2] > FRONT_NZ * np.maximum(nrm, 1e-300)
    if not front.any():
        raise MescherError(f"F: expected faces facing the view, found none (of {F.shape[0]})")
    return F, N, front


def _part_tolerances(V, F, part, tol_abs, rel):
    """(#F,) each face's part's own precision: ``rel`` times the part's bounding-box diagonal,
    at most ``tol_abs`` (a scene's boxes are small beside its ground plane)."""
    n_parts = int(part.max()) + 1
    lo = np.full((n_parts, 3), np.inf)
    hi = np.full((n_parts, 3), -np.inf)
    np.minimum.at(lo, np.repeat(part, 3), V[F].reshape(-1, 3))
    np.maximum.at(hi, np.repeat(part, 3), V[F].reshape(-1, 3))
    return np.minimum(tol_abs, rel * np.linalg.norm(hi - lo, axis=1))[part]


def _glue_visible(
    xy,
    Fa,
    src,
    pl_all,
    C,
    F,
    N,
    front,
    tol_abs,
    ftol,
    bridge,
    perceive,
    report,
    joints=None,
    plain=False,
):
    """Classify, bridge, perceive and glue the visible map; occlusion edges still glued through
    their end fans are split and the map glued again (at most 4 passes).  ``plain``: no false
    edges and no hidden gaps bridged (steps are still joined).

    Returns (Fm, corner_vertex, xy, Z, arcs, false_edges, bridges, is_bridge, source)."""
    bridge = bridge and not plain
    E = axes_model = None
    n_model, model, steps = F.shape[0], (C, F), perceive is None
    for _ in range(5):  # occlusion edges that stay glued through their end fans get split
        Z = plane_depth(xy[Fa], pl_all[src][:, None, :])
        glue, arcs, fe = classify(
            xy, Fa, src, Z, C, F, front, tol_abs, ftol, n_model, false_edges=not plain
        )
        if steps:  # once: steps with a hidden riser get their riser band, then glue again
            steps = False
            hf, near = hidden_step_edges(xy, Fa, src, pl_all, C, F, N, front, glue, tol_abs)
            ext = None
            if hf.size:
                width = STEP_BAND * tol_abs / REL_TOL
                ext = add_step_bands(
                    xy, Fa, src, pl_all, C, F, N, front, ftol, hf, near, width, tol_abs
                )
            if ext is not None:
                xy, Fa, src, pl_all, C, F, N, front, ftol = ext
                continue
        if perceive is None:  # the top of a staircase seen over a wall rising to its bottom
            j = step_junctions(xy, Fa, src, pl_all, C, F, N, front, glue, tol_abs, n_model)
            glue, arcs, fe = glue_step_junctions(glue, arcs, fe, Fa, *j)
        is_bridge = np.zeros(Fa.shape[0], dtype=bool)
        bridges: list = []
        Fb, sb, Zb = Fa, src, Z
        if bridge:
            Fb, sb, Zb, is_bridge, glue, arcs, bridges = bridge_hidden_gaps(
                xy, Fa, src, Z, pl_all, N, glue, arcs, fe, tol_abs, C[F][:, :, :2], model
            )
        if perceive == "manhattan":
            if E is None:
                E = perceived_frame(xy, Fb, Zb)
                axes_model = model_face_axes(C, F, E)  # read from the model's own polygons
            Zb, report.snapped = perceive_manhattan(xy, Fb, Zb, axis=axes_model[sb], E=E)
            glue, arcs = reglue(glue, Fb, Zb, arcs, tol_abs)
        if joints and perceive is None:  # bar ends hidden behind bar ends: joined there
            seen = false_edge_junctions(xy, fe) + bridges
            j = join_ends(
                xy, Fb, sb, Zb, pl_all, C, F, glue, arcs, is_bridge, joints, tol_abs, seen
            )
            xy, Fb, sb, Zb, is_bridge, glue, arcs, more = j
            bridges = bridges + more
        Fm, corner_vertex = cut_and_glue(Fb, glue)
        h1, h2 = glue.h1[~glue.glued], glue.h2[~glue.glued]
        stuck = stuck_cuts(Fm, h1, h2)
        if stuck.size == 0:
            break
        xy, Fa, src = split_cut_faces(xy, Fa, src, h1[stuck], h2[stuck])
    if perceive is None:  # glued: the riser bands narrowed below any pixel
        xy, Zb = narrow_step_bands(xy, Fb, sb, Zb, pl_all, C, F, n_model, tol_abs)
    return Fm, corner_vertex, xy, Zb, arcs, fe, bridges, is_bridge | (sb >= n_model), sb


def _corner_of_vertex(Fm: np.ndarray, corner_vertex: np.ndarray) -> np.ndarray:
    """For each vertex of the glued faces ``Fm``, one corner of the visible map at it (the
    index its screen position is read at)."""
    first = np.zeros(int(Fm.max()) + 1, dtype=np.int64)
    first[Fm.reshape(-1)] = corner_vertex
    return first


def _lined_up_by_chance(g: tuple, part: np.ndarray, n_model: int, tol: float) -> str | None:
    """Did gluing join parts that only line up from this view?  ``"plain"``: a period from
    false edges, bar joints or hidden gaps, with no loop around an opening (glue again without
    them); ``"joints"``: bar joints that close no loop with a period (glue again without the
    joints: a joint is read only as part of a frame); None: keep the gluing.

    A closed chain of bars is read as a frame around a window
    (:func:`~.openings.period_around_opening`); blocks that merely line up from this view, with
    every loop through the joint running over their own faces, are not joined there.  Without
    bar joints, a loop through a ring of parts counts too (steps round a courtyard their far
    side hides); step junctions (a staircase climbing round a floored courtyard) are kept by
    the plain gluing.
    """
    Fm, corner_vertex, xy, Z, fe, bridges, src = g[0], g[1], g[2], g[3], g[5], g[6], g[8]
    kinds = {j.kind for j in false_edge_junctions(xy, fe) + bridges if j.depth_gap > tol}
    if not kinds - {"occluded continuation"}:
        return None
    xy = xy[_corner_of_vertex(Fm, corner_vertex)]
    size = float(np.linalg.norm(np.ptp(xy, axis=0)))
    shown = np.where(src < n_model, part[np.minimum(src, n_model - 1)], -1)
    ring = None if "bar joint" in kinds else RING_PARTS  # bar ends joined: a frame's window
    around = period_around_opening(Fm, xy, Z, tol, PERIOD_RTOL * size, shown, ring)
    if around is None:
        return "joints" if "bar joint" in kinds else None
    return None if around else "plain"


def _expectation_warning(report, V, F, C, front) -> None:
    """Warn when nothing impossible was found although the model looks built for it.

    Two signs that a junction was meant: silhouette vertices that *nearly* line up on screen
    (within 1% of the size) far apart in depth -- the view is slightly off, try ``view="auto"``
    -- and faces whose normals are near, but not exactly on, three orthogonal directions -- a
    sheared trick, try ``perceive="manhattan"``.
    """
    if any(j.depth_gap > 0 for j in report.junctions if j.kind != "occluded continuation"):
        return
    if report.snapped is not None and report.snapped.max(initial=0.0) > 1e-6:
        return  # the perceived (snapped) depths decide; the caller sees the periods
    diag = float(np.linalg.norm(np.ptp(V, axis=0)))
    vs = np.unique(F[front])
    P = C[vs]
    near = cKDTree(P[:, :2]).query_pairs(1e-2 * diag, output_type="ndarray")
    dz = np.abs(P[near[:, 0], 2] - P[near[:, 1], 2]) if near.size else np.zeros(0)
    hints = []
    if np.any(dz > 0.2 * diag):
        hints.append("view='auto' (vertices far apart in depth nearly line up on screen)")
    if report.snapped is None:
        hints.append("perceive='manhattan' (if the figure looks impossible by its right angles)")
    msg = "the result is possible (no junction glued, no period); try " + " or ".join(hints)
    report.warnings.append(msg)
    warnings.warn(f"see_model: {msg}", MescherWarning, stacklevel=4)


def _auto_view(V, F, tol_abs, start, perceive):
    """``view="auto"``: (view, up).  Without ``perceive``, the view from which junctions line
    up (:func:`find_model_view`).  With ``perceive="manhattan"`` the figure is read with right
    angles: of that view and a relief's fronts (:func:`relief_fronts`: the view a person takes
    of a relief, a physically realisable trick carved in layers), the first from which the
    perceived depths gain along a loop; else the first of them (a possible reading)."""

    def judge(v, u):
        return _false_edge_seen(V, F, v, u, tol_abs)

    def joint_judge(v, u, gap):  # mitred tips meeting: a crease joint of that gap
        return _joint_seen(V, F, v, u, tol_abs, gap)

    kw = dict(start=start, judge=judge, joint_judge=joint_judge)
    if perceive is None:
        return find_model_view(V, F, tol_abs, **kw)
    views, err = [], None
    try:
        views.append(find_model_view(V, F, tol_abs, **kw))
    except MescherError as e:
        err = e
    views += [(v, up_for_view(v)) for v in _fronts(V, F, start)]
    for v, u in views:  # a few candidates: the junction view, the relief's two sides
        if _perceived_period(V, F, v, u, tol_abs):
            return v, u
    if not views:
        raise err
    return views[0]


def _fronts(V, F, start) -> list:
    """:func:`relief_fronts`, those within :data:`START_ANGLE` of ``start`` when given."""
    fronts = relief_fronts(V, F)
    if start is None:
        return fronts
    s = np.asarray(start, np.float64).reshape(-1)
    if s.shape != (3,) or not np.linalg.norm(s) > 0:
        return []  # refused by find_model_view with its own message
    return [v for v in fronts if v @ s >= np.cos(START_ANGLE) * np.linalg.norm(s)]


def _perceived_period(V, F, v, up, tol) -> bool:
    """Do the depths read with right angles (``perceive="manhattan"``) from ``v`` gain along a
    loop by more than ``10 tol`` (a period a person perceives)?"""
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        try:
            vm = see_model(V, F, v, up, "manhattan", tol=tol / diag, hidden=False, snap=False)
        except MescherError:
            return False
    return depths_have_period(vm.F, vm.Z, 10.0 * tol)


def _relief_read(V, F, tol_abs, rel, start, bridge, hidden, err) -> VisibleModel | None:
    """No view lines up a junction (``err``), but a relief read with right angles is impossible
    from its front: the model seen from that front (possible, as carved), with a warning that
    suggests ``perceive="manhattan"``; None when it is no such relief."""
    for v in _fronts(V, F, start):  # its two sides, the carved one first
        up = up_for_view(v)
        if not _perceived_period(V, F, v, up, tol_abs):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MescherWarning)
            vm = see_model(V, F, v, up, tol=rel, bridge=bridge, hidden=hidden, snap=False)
        vm.report.reason = (
            f"the relief's front, its thin axis toward its carved side (no junction lines up: "
            f"{err}); {vm.report.reason}"
        )
        if _has_junction(vm.report, tol_abs):
            return vm  # a junction lines up from the front after all
        vm.report.warnings = [w for w in vm.report.warnings if not w.startswith("the result is")]
        msg = (
            f"view='auto': no view lines up a junction; the relief seen from its front "
            f"{(np.round(v, 4) + 0.0).tolist()} is possible as carved, impossible read with right "
            "angles: try perceive='manhattan'"
        )
        vm.report.warnings.append(msg)
        warnings.warn(f"see_model: {msg}", MescherWarning, stacklevel=3)
        return vm
    return None


def _false_edge_seen(V, F, v, up, tol) -> bool:
    """Does the visible surface from ``v`` glue a false edge with a depth gap (a junction)?"""
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        try:
            vm = see_model(V, F, v, up, tol=tol / diag, bridge=False, hidden=False)
        except MescherError:
            return False
    if not any(
        j.kind in ("false edge", "bar joint") and j.depth_gap > tol for j in vm.report.junctions
    ):
        return False
    return depths_have_period(vm.F, vm.Z, 10.0 * tol)
