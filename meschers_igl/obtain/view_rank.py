"""Ranking the directions of :func:`~meschers_igl.obtain.view.find_view`'s vote that tie.

On a model built of separate boxes (a Penrose tribar of an x-bar, a y-bar and a column, as
modelling tools make it), box corners line up along many lattice directions, two vertex pairs
each -- as many as line up at the junction.  The number of pairs cannot tell them apart, nor can
the pairs' length.  A person tells the junction by two things:

* **flush**: at the junction, the corners that coincide on screen are drawn as one: every
  outline (feature) edge leaving one of them runs along an edge leaving the other, in the same
  screen direction, and the other way round -- the bars' sides merge into one line.  Corners
  that line up by accident meet at an angle (a box's top corner on another's bottom corner).
* **far through the model**: the junction joins parts the model keeps apart; walking from one
  corner to the other through the model (along its edges, crossing between parts where they
  touch or overlap) is a detour round the figure's loop, much longer than the straight segment
  between them.  Corners lining up by accident along a bar, or across a corner where two boxes
  meet, are joined nearly straight.

A direction's rank is the detour ratio (path through the model over straight distance) that at
least two of its flush pairs reach (a junction lines up an edge: two pairs); directions with
fewer than two flush pairs are not ranked.  The caller judges the first few.
"""

from __future__ import annotations

import igl
import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra

from ..operators import up_for_view
from .bar_joints import crease_pairs
from .caps import unit_normals

#: Directions ranked at most (the best-supported first, as the vote orders them).
MAX_RANKED_DIRECTIONS = 200
#: At most this many ranked directions are judged (each from its two sides).
MAX_RANKED_VIEWS = 4
#: Supporting pairs of one direction examined at most.
MAX_PAIRS_PER_DIRECTION = 64
#: Two feature edges run along each other on screen when their unit screen directions differ
#: by at most this (chord length).
FLUSH_TOL = 1e-4
#: Faces meeting at an edge at a smaller angle than this (radians) make no outline edge.
FEATURE_ANGLE = 1e-4


def feature_adjacency(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The outline edges at each vertex: edges where the faces meet at an angle over
    :data:`FEATURE_ANGLE`, or open or non-manifold edges (a flat face's diagonals are none).

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64

    Returns
    -------
    start : (#V + 1,) int64, nbr : (2 #E,) int64
        The neighbours of vertex ``i`` along outline edges are ``nbr[start[i]:start[i + 1]]``.
    """
    n = V.shape[0]
    E = np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    Nf = np.repeat(unit_normals(V, F), 3, axis=0)
    _, first, inv, cnt = np.unique(
        E[:, 0] * n + E[:, 1], return_index=True, return_inverse=True, return_counts=True
    )
    inv = inv.reshape(-1)
    bent = np.einsum("ij,ij->i", Nf, Nf[first[inv]]) < np.cos(FEATURE_ANGLE)
    feat = np.zeros(first.size, dtype=bool)
    np.logical_or.at(feat, inv, bent)
    feat |= cnt != 2
    Eu = E[first[feat]]
    a, b = np.r_[Eu[:, 0], Eu[:, 1]], np.r_[Eu[:, 1], Eu[:, 0]]
    o = np.argsort(a, kind="stable")
    return np.searchsorted(a[o], np.arange(n + 1)), b[o]


def flush_pairs(
    V: np.ndarray, adj: tuple[np.ndarray, np.ndarray], P: np.ndarray, v: np.ndarray
) -> np.ndarray:
    """Which vertex pairs, coinciding on screen from a view, are flush: each outline edge at
    one end runs on screen along one at the other end, in the same direction, both ways (edges
    seen end-on left out; an end with none is not flush).

    Parameters
    ----------
    V : (#V, 3) float64
    adj : (start, nbr)
        :func:`feature_adjacency`.
    P : (k, 2) int64
        Vertex pairs.
    v : (3,) float64
        Unit view.

    Returns
    -------
    (k,) bool
    """
    start, nbr = adj
    out = np.zeros(P.shape[0], dtype=bool)

    def screen(p):
        d = V[nbr[start[p] : start[p + 1]]] - V[p]
        s = d - np.outer(d @ v, v)
        ns = np.linalg.norm(s, axis=1)
        keep = ns > FLUSH_TOL * np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        return s[keep] / ns[keep, None]

    for k, (p, q) in enumerate(P.tolist()):
        A, B = screen(p), screen(q)
        if A.shape[0] == 0 or B.shape[0] == 0:
            continue
        close = np.linalg.norm(A[:, None] - B[None], axis=2) <= FLUSH_TOL
        out[k] = bool(close.any(axis=1).all() and close.any(axis=0).all())
    return out


def model_graph(V: np.ndarray, F: np.ndarray, tol: float) -> csr_matrix:
    """The model as a graph to walk through: its edges, and between parts (connected sets of
    faces) that touch or overlap, each vertex of one within ``tol`` of the other's surface or
    inside it joined to the corners of the other's nearest face.

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
    tol : float
        Absolute distance at which parts touch.

    Returns
    -------
    (#V, #V) scipy.sparse.csr_matrix
        Symmetric; entries the steps' lengths (touching vertices a step of ``1e-300``).
    """
    n = V.shape[0]
    E = np.unique(np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    rows, cols = [E[:, 0]], [E[:, 1]]
    part = np.asarray(igl.facet_components(F)[1], dtype=np.int64)
    vpart = np.full(n, -1, dtype=np.int64)
    vpart[F.reshape(-1)] = np.repeat(part, 3)
    lo = np.full((part.max(initial=-1) + 1, 3), np.inf)
    hi = np.full_like(lo, -np.inf)
    np.minimum.at(lo, part, V[F].min(axis=1))
    np.maximum.at(hi, part, V[F].max(axis=1))
    used = np.flatnonzero(vpart >= 0)
    for b in range(lo.shape[0]):  # each part: the other parts' vertices in its box
        near = used[
            (vpart[used] != b)
            & np.all(V[used] >= lo[b] - tol, axis=1)
            & np.all(V[used] <= hi[b] + tol, axis=1)
        ]
        if near.size == 0:
            continue
        Fb = F[part == b]
        d2, face, _ = igl.point_mesh_squared_distance(V[near], V, Fb)
        inside = np.abs(igl.winding_number(V, Fb, V[near])) > 0.5
        k = np.flatnonzero((d2 <= tol * tol) | inside)
        rows.append(np.repeat(near[k], 3))
        cols.append(Fb[np.asarray(face)[k]].reshape(-1))
    r, c = np.concatenate(rows), np.concatenate(cols)
    w = np.linalg.norm(V[r] - V[c], axis=1) + 1e-300  # touching vertices: a zero-length step
    return coo_matrix((np.r_[w, w], (np.r_[r, c], np.r_[c, r])), shape=(n, n)).tocsr()


def rank_directions(V: np.ndarray, F: np.ndarray, cands: list, tol: float) -> list:
    """The candidate views lining up a flush junction, the farthest through the model first.

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
    cands : list of (view, up, pairs)
        As :func:`~meschers_igl.obtain.view.find_view` returns them (``pairs`` (k, 2), the
        vertex pairs coinciding from ``view``).
    tol : float
        Absolute distance at which parts touch (:func:`model_graph`).

    Returns
    -------
    list of (view, up, pairs)
        Those of ``cands`` with two flush pairs (:func:`flush_pairs`, the first
        :data:`MAX_PAIRS_PER_DIRECTION` judged) whose ends are joined through the model by a
        detour (a path longer than their segment); in decreasing order of the detour ratio
        (path over segment) that two of them reach, ties in the order of ``cands``.
    """
    adj = feature_adjacency(V, F)
    flush = []
    for v, _, P in cands:
        P = P[:MAX_PAIRS_PER_DIRECTION]
        f = P[flush_pairs(V, adj, P, v)]
        flush.append(f if f.shape[0] >= 2 else None)
    src = np.unique(np.concatenate([f[:, 0] for f in flush if f is not None] + [[]]))
    if src.size == 0:
        return []
    src = src.astype(np.int64)
    dist = dijkstra(model_graph(V, F, tol), indices=src)
    row = np.full(V.shape[0], -1)
    row[src] = np.arange(src.size)
    scored = []
    for k, f in enumerate(flush):
        if f is None:
            continue
        straight = np.linalg.norm(V[f[:, 1]] - V[f[:, 0]], axis=1)
        ratio = np.sort(dist[row[f[:, 0]], f[:, 1]] / straight)[::-1]
        if ratio[1] > 1.0 + 1e-9:
            scored.append((-ratio[1], k))
    scored.sort()
    return [cands[k] for _, k in scored]


def ranked_views(
    V: np.ndarray,
    F: np.ndarray,
    cands: list,
    v: np.ndarray | None,
    tol: float,
    start: np.ndarray | None,
    within: float,
    same: float,
) -> list:
    """The views to judge of the candidates: the first :data:`MAX_RANKED_VIEWS` of
    :func:`rank_directions`, each from its two sides (the same pairs coincide from both, and a
    bar's end hidden exactly behind an edge is found from one side or the other as round-off
    decides), ``v_z >= 0`` first.

    Parameters
    ----------
    V, F, cands, tol
        As :func:`rank_directions`.
    v : (3,) float64 or None
        A view already judged: candidates with ``|w . v| >= same`` are left out.
    start : (3,) float64 or None
        With it, only the sides within ``within`` radians of it.
    within, same : float

    Returns
    -------
    list of (view, up)
    """
    near = np.cos(within)

    def sides(w):
        return [s * w for s in (1.0, -1.0) if start is None or (s * w) @ start >= near]

    cands = [c for c in cands if (v is None or abs(c[0] @ v) < same) and sides(c[0])]
    ranked = rank_directions(V, F, cands, tol)[:MAX_RANKED_VIEWS]
    return [(u, up_for_view(u)) for w, _, _ in ranked for u in sides(w)]


#: Most pairs of corners forming a crease joint (:func:`crease_views`) judged from their
#: direction (each by seeing the model from it).
MAX_CREASE_VIEWS = 4
#: Crease views whose heights ``v_z`` agree to this (each with the next lower) are as high as
#: each other (mirror images of a symmetric model, its file's round-off apart: 0.06 degrees).
HEIGHT_TIE = 1e-3


def crease_views(
    V, F, tol: float, start, within: float, same: float, limit: int = MAX_CREASE_VIEWS
) -> list:
    """``(view, gap)`` of the pairs of corners forming a crease joint (:func:`~.bar_joints.crease_pairs`),
    within ``within`` of ``start`` when given, in the order a person takes them: from above
    the horizon (``v_z >= 0``, the modelling tools' camera) first, then the nearest tips
    (the smallest gap, gaps within 10 ``tol`` of each other tied: a designed joint pulls the
    tips back by a bar's width, mitres lining up across the model are far apart), then the
    highest camera (to :data:`HEIGHT_TIE`), then the larger ``v_y`` (``find_view``'s
    convention at ``v_z = 0``); each direction once (directions within ``same`` radians are
    one), the first ``limit``."""
    _, _, W, gap = crease_pairs(V, F, tol)
    if start is not None:
        near = W @ start >= np.cos(within)
        W, gap = W[near], gap[near]
    if gap.size == 0:
        return []
    # ties: runs of gaps (heights) each within 10 tol (HEIGHT_TIE) of the one before
    o = np.argsort(gap, kind="stable")
    tied = np.empty(gap.size, dtype=np.int64)
    tied[o] = np.cumsum(np.r_[0, np.diff(gap[o]) > 10.0 * tol])
    o = np.lexsort((-W[:, 2], tied))
    step = (np.diff(tied[o]) > 0) | (-np.diff(W[o, 2]) > HEIGHT_TIE)
    tied[o] = np.cumsum(np.r_[0, step])
    order = np.lexsort((-W[:, 1], tied, W[:, 2] < 0))
    out: list = []
    for k in order.tolist():  # each direction once (pairs repeating along it: one view)
        if len(out) >= limit:
            break
        if not any(W[k] @ w >= np.cos(same) for w, _ in out):
            out.append((W[k], float(gap[k])))
    return out
