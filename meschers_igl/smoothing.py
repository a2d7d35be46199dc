"""Laplacian smoothing of meschers (paper Sec. 4.4).

Screen positions are smoothed like any 0-form; ``zeta`` is split by its Hodge decomposition
``zeta = d01 z + omega`` and only the exact part is smoothed -- ``omega`` spans the kernel of the
1-form Laplacian, so it (and with it every period) is left unchanged::

    xy'   = (M - t_xy L)^-1 M xy
    zeta' = omega + d01 (M - t_zeta L)^-1 M z

(mass-weighted backward Euler, ``L`` the negative semi-definite cotangent matrix).  The paper
prints ``omega + d01((I + tL)^-1 z - z)``; the ``- z`` would cancel the exact part it smooths, so
we read it as the update above, which is what its figures show.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp

from .errors import MescherError, MescherWarning
from .progress import track
from .solvers import factorize_spd
from .validate import as_count, as_positive


def heat_operator(m, t: float):
    """Factor ``M - t L`` once for mescher ``m``; returns ``u -> (M - tL)^-1 M u``."""
    M = m.massmatrix()
    solve = factorize_spd(sp.csc_matrix(M - t * m.cotmatrix()))

    def apply(u: np.ndarray) -> np.ndarray:
        return solve(M @ u)

    return apply


#: smoothed screen extent / original below which the shape is gone (a point, up to round-off)
COLLAPSED = 1e-6
#: ... and below which a warning says how much it shrank
SHRUNK = 0.05


def _kept_shape(xy: np.ndarray, new: np.ndarray, t: float) -> np.ndarray:
    """``new``, refused when smoothing for time ``t`` shrank the figure to a point and warned
    about when it shrank below ``SHRUNK`` of its size (backward Euler divides each mode by
    ``1 + lambda t``: a time far above ``size^2`` leaves only the mean)."""
    size = float(np.ptp(xy, axis=0).max())
    ratio = float(np.ptp(new, axis=0).max()) / size if size > 0 else 1.0
    if not np.all(np.isfinite(new)) or ratio < COLLAPSED:
        raise MescherError(
            f"t_xy: expected a smoothing time that keeps the figure (about size^2 = {size**2:.3g} "
            f"or less), found {t:g}: every vertex moved to one point"
        )
    if ratio < SHRUNK:
        warnings.warn(
            f"t_xy = {t:g} shrank the figure to {ratio:.2%} of its size (size^2 = {size**2:.3g})",
            MescherWarning,
            stacklevel=3,
        )
    return new


def smooth(m, t_xy: float = 0.0, t_zeta: float = 0.0, iterations: int = 1):
    """Smooth screen positions and/or the exact part of the depths (see module docstring).

    Parameters
    ----------
    m : Mescher
    t_xy, t_zeta : float >= 0
        Diffusion times; 0 leaves that part unchanged.  With equal times the joint smoothing
        uses one factorization.
    iterations : int, default: 1
        Repeat, rebuilding the operators from the smoothed mescher each time (as for curvature
        flow); the periods stay fixed throughout.

    Returns
    -------
    Mescher
    """
    t_xy = as_positive(t_xy, "t_xy", allow_zero=True)
    t_zeta = as_positive(t_zeta, "t_zeta", allow_zero=True)
    iterations = as_count(iterations, "iterations")
    # each iteration factors a #V x #V system: ~1 s per iteration at 1M faces
    for _ in track(range(iterations), "smooth", total=iterations, work=m.n_faces * iterations):
        if t_xy == 0 and t_zeta == 0:
            return m
        xy, zeta = np.asarray(m.xy), np.asarray(m.zeta)
        ops = {t: heat_operator(m, t) for t in {t_xy, t_zeta} if t > 0}
        if t_xy > 0:
            xy = _kept_shape(xy, ops[t_xy](xy), t_xy)
        if t_zeta > 0:
            h = m.hodge()
            zeta = h.omega + m.d01 @ ops[t_zeta](np.asarray(h.z))
        m = m.with_xy(xy) if t_xy > 0 else m  # both keep the homology basis
        m = m.with_zeta(zeta) if t_zeta > 0 else m
    return m


def follow_sheets(order, m_new, face_parent=None, *, max_rings: int = 32, tol: float | None = None):
    """The depth order carried to a mescher whose screen positions moved, sheet by sheet.

    :meth:`DepthOrder.follow` carries the arcs of pairs that still overlap and orders the pairs
    that start to overlap from local depth.  Where an impossible figure crosses itself (a back
    bar drawn over a front bar, the bars at equal depth) local depth says the opposite of the
    figure's order, or nothing at all (a tie leaves the pair unordered and the painter draws
    either face first), so the faces that smoothing slides into a crossing's edge came out on
    the wrong side: specks of the hidden bar inside the front one.  Loop subdivision moves
    screen positions too: children of faces that did not overlap come to overlap.

    The rule here: an overlap that appears continues the overlap of the same two sheets next to
    it.  A new pair ``(a, b)`` (overlapping now, no arc between their parents before) takes the
    direction of the arcs between faces next to ``a`` (sharing a vertex) and faces next to
    ``b`` -- the carried arcs (of pairs that still overlap) and the pairs already settled this
    way -- by majority, repeated until no pair changes, so the order spreads from the old
    overlap over the new one, one ring per round (at most ``max_rings`` rounds).  Only pairs
    the spreading never reaches keep local depth, and so do new pairs of faces sharing a vertex
    (a fold of one sheet: one chart of the lift holds both, so their local depth is their
    order).  Arcs that would close a cycle with the carried ones are reconciled as in
    :meth:`DepthOrder.follow` (the carried arcs win, then the spread ones).

    Parameters
    ----------
    order : DepthOrder
        The order of the mescher before the move.
    m_new : Mescher
        The mescher after the move.
    face_parent : (#F_new,) array_like of int, optional
        Face of ``order``'s mescher each face of ``m_new`` comes from (subdivision), as in
        :meth:`DepthOrder.follow`; default: the same faces.
    max_rings : int, default: 32
        Rounds of spreading.
    tol : float, optional
        Overlap tolerance, as in :meth:`DepthOrder.follow`.

    Returns
    -------
    DepthOrder
        Attached to ``m_new``.
    """
    from .geometry2d import default_tol, overlapping_pairs
    from .order import DepthOrder
    from .order_graph import reconcile_arcs

    max_rings = as_count(max_rings, "max_rings", minimum=1)
    followed = order.follow(m_new, face_parent, tol=tol)
    n, n_old = int(m_new.n_faces), int(order.n_faces)
    old = np.asarray(order.arcs, dtype=np.int64).reshape(-1, 2)
    if old.shape[0] == 0:
        return followed
    parent = np.arange(n) if face_parent is None else np.asarray(face_parent, dtype=np.int64)
    F = np.asarray(m_new.F, dtype=np.int64)
    T = np.ascontiguousarray(np.asarray(m_new.xy, dtype=np.float64)[F])
    pairs = overlapping_pairs(T, default_tol(T) if tol is None else float(tol), centroids=True)[0]
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    old_keys = np.unique(
        np.concatenate((old[:, 0] * n_old + old[:, 1], old[:, 1] * n_old + old[:, 0]))
    )
    new = pairs[~np.isin(parent[pairs[:, 0]] * n_old + parent[pairs[:, 1]], old_keys)]
    arcs = np.asarray(followed.arcs, dtype=np.int64).reshape(-1, 2)
    carried = arcs[np.isin(parent[arcs[:, 0]] * n_old + parent[arcs[:, 1]], old_keys)]
    if new.shape[0] == 0:
        return followed
    nv = int(F.max()) + 1
    incidence = sp.csr_matrix(
        (np.ones(F.size), (np.repeat(np.arange(n), 3), F.reshape(-1))), shape=(n, nv)
    )
    near = ((incidence @ incidence.T) > 0).astype(np.float64).tocsr()  # faces sharing a vertex
    # two faces sharing a vertex lie in one chart of the lift: their local depth is their order
    own = np.asarray(near[new[:, 0], new[:, 1]]).ravel() > 0
    near_a, near_b = near[new[:, 0]], near[new[:, 1]]
    direction = np.zeros(new.shape[0], dtype=np.int8)  # +1: a -> b, -1: b -> a, 0: open
    direction[own] = 2  # settled by local depth below
    R = sp.csr_matrix((np.ones(carried.shape[0]), (carried[:, 0], carried[:, 1])), shape=(n, n))
    for _ in range(max_rings):
        open_ = np.flatnonzero(direction == 0)
        if open_.size == 0:
            break
        a, b = near_a[open_], near_b[open_]
        forward = np.asarray((a @ R).multiply(b).sum(axis=1)).ravel()
        backward = np.asarray((b @ R).multiply(a).sum(axis=1)).ravel()
        vote = np.sign(forward - backward).astype(np.int8)
        if not vote.any():
            break
        direction[open_] = vote
        settled = new[open_[vote != 0]]
        settled[vote[vote != 0] < 0] = settled[vote[vote != 0] < 0][:, ::-1]
        R = R + sp.csr_matrix(
            (np.ones(settled.shape[0]), (settled[:, 0], settled[:, 1])), shape=(n, n)
        )
    direction[own] = 0
    spread = np.concatenate((new[direction > 0], new[direction < 0][:, ::-1]))
    spread = reconcile_arcs(n, carried, spread)
    hard = np.concatenate((carried, spread))
    # pairs the spreading never reached: local depth, as follow gave it
    open_keys = np.concatenate(
        (
            new[direction == 0, 0] * n + new[direction == 0, 1],
            new[direction == 0, 1] * n + new[direction == 0, 0],
        )
    )
    local = arcs[np.isin(arcs[:, 0] * n + arcs[:, 1], open_keys)]
    local = reconcile_arcs(n, hard, local)
    return DepthOrder(n, np.concatenate((hard, local)), m=m_new)
