"""Folds and flips of the depth order: which faces decide what is drawn over an interpolated
occluding contour, and where the order's own seams are lines.

An interpolated contour (:func:`meschers_igl.lines.interpolated_contours`) is a stand-in for
the mesh's own fold: the surface turns away within a ring or two of faces around it, and those
faces (its *fold*: the two-ring of the face holding a segment, the relation ``near``) overlap
each other on screen.  They neither hide the contour nor decide alone whether it is seen; the
rules here say how the rest of the picture meets it:

* the fold is drawn up to the last of *its faces that lie under the segment on screen*
  (:func:`fold_ranks`): a face of the fold elsewhere on screen never shows beside the segment;
* a face ``g`` drawn after those does not hide the segment if a face of the fold drawn after
  ``g`` overlaps ``g`` on screen (:func:`crossed`): the fold passes in front of ``g`` within its
  two-ring, so ``g`` and the fold cross there (an impossible figure's depth order may flip
  between neighbouring faces of one sheet), and the fold's line is seen where they cross.
  Without this rule the contour's visibility flickers at the faces' size where ``g``'s rank
  falls between the ranks of the fold's faces, and the contour is drawn as dashes.

A face ``g`` drawn after every face of the fold that overlaps it hides the contour as any
occluder does (with exact T-junctions).

The same flip makes lines of its own: where an edge between two faces ``f`` and ``g`` of one
sheet (facing the same way, no line source) has a face ``h`` of another sheet drawn between
them (``rank[g] < rank[h] < rank[f]``, ``h`` over ``g`` by an arc of the order) the painter
shows ``f`` on one side of the edge and ``h`` on the other, an occlusion line along the edge
(:func:`order_seams` finds such edges; :mod:`meschers_igl.lines` draws them where ``f`` shows
and ``g`` does not, :func:`seam_hidden`).  Two such lines stay out: those among a fold's faces
seen from behind (its underside, beyond the contour that stands for it, on screen slivers of
the surface), and polylines of seams alone shorter than the drawing's ``min_length`` (where a
face between reaches under an edge by a corner; :func:`lines_of_only`).

A strip of faces seen edge-on (a cut in a plane through the view, a riser seen exactly from
its side) covers nothing: a face on one side of it and a face on the other that continue each
other on screen are one sheet, and the strip's edges are no line (:func:`seam_partners`), but
only along the stretch where both sides meet it; beyond, the edge is a line like any other.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .face_grid import ranges as _ranges

__all__ = [
    "NEAR_BASE",
    "complement_intervals",
    "crossed",
    "fold_ranks",
    "is_near",
    "lines_of_only",
    "order_seams",
    "seam_hidden",
    "seam_partners",
    "triangles_overlap",
]

#: Key base of the "near" relation (``anchor * NEAR_BASE + face``): above any face count.
NEAR_BASE = 1 << 31


def is_near(near: np.ndarray | None, anchor: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Is face ``g[k]`` near ``anchor[k]``?  ``near``: sorted keys ``anchor * NEAR_BASE +
    face`` (None: nothing is near); anchors < 0 have no neighbours."""
    out = np.zeros(len(g), dtype=bool)
    if near is None or len(near) == 0 or len(g) == 0:
        return out
    has = anchor >= 0
    q = anchor[has] * np.int64(NEAR_BASE) + g[has]
    pos = np.minimum(np.searchsorted(near, q), len(near) - 1)
    out[has] = near[pos] == q
    return out


def fold_ranks(
    thr: np.ndarray,
    anchor: np.ndarray,
    rank: np.ndarray,
    area2: np.ndarray,
    s_under: np.ndarray,
    r_under: np.ndarray,
) -> np.ndarray:
    """``thr`` (#S, 2) with the rows of interpolated-contour segments (``anchor >= 0``) set to
    the last rank among the faces of their fold under them on screen: their own face (unless
    seen edge-on) and the near faces overlapping the segment, given as pairs ``(s_under,
    rank r_under)``."""
    anc = np.flatnonzero(anchor >= 0)
    if len(anc) == 0:
        return thr
    own = anchor[anc]
    last = np.full(len(anchor), -1, dtype=np.int64)
    last[anc] = np.where(area2[own] != 0, rank[own], -1)
    np.maximum.at(last, s_under, r_under)
    out = thr.copy()
    out[anc] = last[anc, None]
    return out


def triangles_overlap(T1: np.ndarray, T2: np.ndarray) -> np.ndarray:
    """(k,) bool: screen triangles ``T1[k]`` and ``T2[k]`` (k, 3, 2) share an area (no
    separating axis among their six edge normals; touching along an edge or at a corner, to
    ``1e-12`` of their coordinates, is no overlap)."""
    ok = np.ones(len(T1), dtype=bool)
    if len(T1) == 0:
        return ok
    size = np.maximum(np.abs(T1).max(axis=(1, 2)), np.abs(T2).max(axis=(1, 2)))
    for T in (T1, T2):
        for i in range(3):
            e = T[:, (i + 1) % 3] - T[:, i]
            nrm = np.stack([-e[:, 1], e[:, 0]], axis=1)
            p1 = np.einsum("kij,kj->ki", T1, nrm)
            p2 = np.einsum("kij,kj->ki", T2, nrm)
            eps = 1e-12 * size * np.linalg.norm(nrm, axis=1)
            ok &= ~(
                (p1.max(axis=1) <= p2.min(axis=1) + eps) | (p2.max(axis=1) <= p1.min(axis=1) + eps)
            )
    return ok


def crossed(
    near: np.ndarray | None,
    anchor: np.ndarray,
    g: np.ndarray,
    T: np.ndarray,
    rank: np.ndarray,
    area2: np.ndarray,
) -> np.ndarray:
    """(k,) bool: does a face of the fold of ``anchor[k]`` (its near faces, seen face-on) drawn
    after face ``g[k]`` overlap ``g[k]`` on screen?  Then ``g[k]`` crosses the fold there and
    does not hide the contour (see the module notes)."""
    out = np.zeros(len(g), dtype=bool)
    if near is None or len(near) == 0 or len(g) == 0:
        return out
    base = np.int64(NEAR_BASE)
    lo = np.searchsorted(near, anchor * base)
    k = np.searchsorted(near, (anchor + 1) * base) - lo
    pair = np.repeat(np.arange(len(g)), k)
    h = near[np.repeat(lo, k) + _ranges(k)] - np.repeat(anchor, k) * base
    later = (rank[h] > rank[g[pair]]) & (area2[h] != 0)
    pair, h = pair[later], h[later]
    Th, Tg = T[h], T[g[pair]]
    boxes = np.all(Th.min(axis=1) < Tg.max(axis=1), axis=1) & np.all(
        Tg.min(axis=1) < Th.max(axis=1), axis=1
    )  # separated boxes: no overlap, without the six axes
    pair, Th, Tg = pair[boxes], Th[boxes], Tg[boxes]
    hit = triangles_overlap(Th, Tg)
    out[pair[hit]] = True
    return out


def order_seams(f: np.ndarray, g: np.ndarray, rank: np.ndarray, arcs: np.ndarray) -> np.ndarray:
    """(k,) bool: does the order put a face ``h`` over the earlier of faces ``f[k]``, ``g[k]``
    (an arc from it to ``h``: they overlap on screen) and is ``h`` drawn before the later one?
    Then the order flips across their shared edge: where ``h`` lies under it the painter shows
    the later face on one side and ``h`` on the other (see the module notes).

    Parameters
    ----------
    f, g : (k,) int64
        The two faces of each edge.
    rank : (#F,) int64
        Position of every face in the drawing order.
    arcs : (#A, 2) int64
        The order's arcs ``(behind, in front)``.
    """
    out = np.zeros(len(f), dtype=bool)
    if len(f) == 0 or len(arcs) == 0:
        return out
    behind = arcs[:, 0]
    if np.any(behind[1:] < behind[:-1]):
        arcs = arcs[np.argsort(behind, kind="stable")]
        behind = arcs[:, 0]
    n = len(rank)
    start = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(behind, minlength=n), out=start[1:])
    over = rank[arcs[:, 1]]
    # the first rank drawn over each face: no face between where it comes after the later one
    has = start[1:] > start[:-1]
    first = np.full(n, n, dtype=np.int64)
    first[has] = np.minimum.reduceat(over, start[:-1][has])
    low = np.where(rank[f] < rank[g], f, g)
    lo_r, hi_r = np.minimum(rank[f], rank[g]), np.maximum(rank[f], rank[g])
    maybe = np.flatnonzero(first[low] < hi_r)
    k = start[low[maybe] + 1] - start[low[maybe]]
    pair = np.repeat(maybe, k)
    rh = over[np.repeat(start[low[maybe]], k) + _ranges(k)]
    between = (rh > lo_r[pair]) & (rh < hi_r[pair])
    out[pair[between]] = True
    return out


def seam_hidden(hidden: tuple, covered: list, shown: list, seam: np.ndarray, thr: np.ndarray):
    """Hidden intervals ``(seg, lo, hi)`` of a line drawing's sources with those of the order's
    seams (``seam`` True) replaced: a seam is seen where the side of its later face (the larger
    of ``thr[s]``) shows that face and the other side does not show its own.  ``covered[k]``
    and ``shown[k]`` are the intervals where side ``k`` is covered by a later face and where it
    shows its own face."""
    later = np.argmax(thr, axis=1)
    sets = [(hidden, ~seam)]
    for k in (0, 1):
        sets.append((covered[k], seam & (later == k)))  # the later face covered
        sets.append((shown[k], seam & (later != k)))  # the earlier face shows
    out = []
    for (s, lo, hi), want in sets:
        keep = want[s]
        out.append((s[keep], lo[keep], hi[keep]))
    return tuple(np.concatenate([o[i] for o in out]) for i in range(3))


def lines_of_only(
    flag: np.ndarray, dup: np.ndarray, pairs: np.ndarray, nodes: np.ndarray, offsets: np.ndarray
) -> np.ndarray:
    """(#L,) bool: is every piece of each joined polyline a ``flag``-ged piece?

    Parameters
    ----------
    flag : (#P,) bool
        Per piece before duplicates were merged (a merged piece is flagged when all its
        copies are).
    dup : (#P,) int64
        The merged piece of each piece.
    pairs : (#U, 2) int64
        Node pairs of the merged pieces, sorted (as :func:`numpy.unique` returns them).
    nodes, offsets : int64
        The polylines as node sequences (``nodes[offsets[i]:offsets[i + 1]]``).
    """
    alone = np.ones(len(pairs), dtype=bool)
    np.logical_and.at(alone, dup, flag)
    n_lines = len(offsets) - 1
    if n_lines == 0:
        return np.zeros(0, dtype=bool)
    base = np.int64(max(int(pairs.max()), int(nodes.max())) + 1)
    code = pairs[:, 0] * base + pairs[:, 1]
    step = np.ones(len(nodes) - 1, dtype=bool)
    step[offsets[1:-1] - 1] = False  # no piece from a polyline's last node to the next one's
    a, b = nodes[:-1][step], nodes[1:][step]
    piece = np.searchsorted(code, np.minimum(a, b) * base + np.maximum(a, b))
    line = np.repeat(np.arange(n_lines), np.diff(offsets) - 1)
    return np.bincount(line[~alone[piece]], minlength=n_lines) == 0


def complement_intervals(n: int, seg: np.ndarray, t0: np.ndarray, t1: np.ndarray):
    """``(seg, lo, hi)``: the parts of ``[0, 1]`` of each of ``n`` segments outside the union
    of the intervals ``[t0, t1]`` given for it."""
    o = np.lexsort((t0, seg))
    seg, t0, t1 = seg[o], t0[o], t1[o]
    # running maximum of the interval ends within each segment (keys of earlier segments are
    # smaller, so one cumulative maximum over all serves every segment)
    run = np.maximum.accumulate(seg * 4.0 + t1) - seg * 4.0
    first = np.ones(len(seg), dtype=bool)
    first[1:] = seg[1:] != seg[:-1]
    prev = np.where(first, 0.0, np.concatenate([[0.0], run[:-1]]))
    gap = t0 > prev
    last = np.ones(len(seg), dtype=bool)
    last[:-1] = seg[1:] != seg[:-1]
    tail = last & (run < 1.0)
    untouched = np.setdiff1d(np.arange(n), seg)
    out_s = np.concatenate([seg[gap], seg[tail], untouched])
    out_lo = np.concatenate([prev[gap], run[tail], np.zeros(len(untouched))])
    out_hi = np.concatenate([t0[gap], np.ones(tail.sum()), np.ones(len(untouched))])
    return out_s, out_lo, out_hi


def seam_partners(
    m: Any,
    ef: np.ndarray,
    area2: np.ndarray,
    crease_angle: float,
    uncovered: bool = False,
    tol_abs: float = 0.0,
) -> Any:
    """(#E,) the face that continues the surface across faces seen edge-on, or -1.

    A cut in a plane containing the view leaves a strip of faces of zero screen area between
    two faces that continue each other on screen (the seam of an impossible figure).  For an
    edge ``e`` between a face ``f`` and a face of such a strip, the partner is a face ``g``
    attached to the same strip (faces seen edge-on joined through their edges) on the other
    side of ``e``'s screen line, along an overlapping stretch of it, facing the same way as
    ``f`` and within ``crease_angle`` of its normal: in the picture ``f`` and ``g`` are one
    smooth sheet, and ``e`` is no line.

    With ``uncovered`` also returns ``(edge, t0, t1)``: the stretches ``[t0, t1]`` (of
    ``E[edge, 0] -> E[edge, 1]``, longer than ``2 tol_abs``) of the partnered edges along
    which no partner's edge runs.
    """
    partner = np.full(len(ef), -1, dtype=np.int64)
    flat = area2 == 0
    none = (np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0))
    if not flat.any():
        return (partner, none) if uncovered else partner
    nF = len(area2)
    inner = ef[:, 1] >= 0
    f0, f1 = ef[:, 0], np.maximum(ef[:, 1], 0)
    both = inner & flat[f0] & flat[f1]
    adj = sp.coo_matrix((np.ones(int(both.sum())), (f0[both], f1[both])), shape=(nF, nF))
    _, comp = csgraph.connected_components(adj, directed=False)
    one = inner & (flat[f0] != flat[f1])
    e_att = np.flatnonzero(one)
    h = np.where(flat[f0[e_att]], f0[e_att], f1[e_att])
    f = np.where(flat[f0[e_att]], f1[e_att], f0[e_att])
    c = comp[h]
    o = np.argsort(c, kind="stable")
    e_att, f, c = e_att[o], f[o], c[o]
    # every ordered pair of attachments to one strip
    start = np.searchsorted(c, c, "left")
    k = np.searchsorted(c, c, "right") - start
    i = np.repeat(np.arange(len(c)), k)
    j = np.repeat(start, k) + _ranges(k)
    keep = i != j
    i, j = i[keep], j[keep]
    xy = np.asarray(m.xy)
    E = np.asarray(m.edges)
    F = np.asarray(m.F)
    N = np.asarray(m.face_normals())
    a0, a1 = xy[E[e_att[i], 0]], xy[E[e_att[i], 1]]
    d = a1 - a0
    length = np.linalg.norm(d, axis=1)
    ok = length > 0
    u = d / np.where(ok, length, 1.0)[:, None]

    def side(P):
        q = P - a0
        return u[:, 0] * q[:, 1] - u[:, 1] * q[:, 0]

    fi, fj = f[i], f[j]
    ok &= side(xy[F[fi]].mean(axis=1)) * side(xy[F[fj]].mean(axis=1)) < 0
    ok &= (area2[fi] > 0) == (area2[fj] > 0)
    ok &= np.einsum("ij,ij->i", N[fi], N[fj]) >= np.cos(np.radians(crease_angle))
    # the partner's edge lies on the same screen line and overlaps this one along it
    b0, b1 = xy[E[e_att[j], 0]], xy[E[e_att[j], 1]]
    tol = 1e-9 * np.maximum(length, 1e-300)
    ok &= (np.abs(side(b0)) <= tol) & (np.abs(side(b1)) <= tol)
    tb0 = np.einsum("ij,ij->i", b0 - a0, u)
    tb1 = np.einsum("ij,ij->i", b1 - a0, u)
    ok &= (np.maximum(tb0, tb1) > tol) & (np.minimum(tb0, tb1) < length - tol)
    partner[e_att[i[ok]]] = fj[ok]
    if not uncovered:
        return partner
    # the stretches of each partnered edge no partner's edge runs along: there the surface
    # does not go on across the strip, and the edge is a line (a stair's tread beyond the end
    # of the riser seen edge-on under it meets the ground: the outline's jog)
    e, lo, hi = e_att[i[ok]], np.minimum(tb0, tb1)[ok], np.maximum(tb0, tb1)[ok]
    lo, hi = np.clip(lo / length[ok], 0.0, 1.0), np.clip(hi / length[ok], 0.0, 1.0)
    ids, inv = np.unique(e, return_inverse=True)
    k, g0, g1 = complement_intervals(len(ids), inv, lo, hi)
    keep = (g1 - g0) * np.linalg.norm(xy[E[ids[k], 1]] - xy[E[ids[k], 0]], axis=1) > 2.0 * tol_abs
    return partner, (ids[k[keep]], g0[keep], g1[keep])
