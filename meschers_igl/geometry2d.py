"""Robust 2D triangle overlap: a uniform-grid broad phase and an exact narrow phase.

The depth order of a mescher (:mod:`meschers_igl.order`) only relates faces whose *screen*
triangles overlap with positive area.  Faces that merely touch -- along a shared edge, at a
shared vertex, or along a seam whose two sides were rounded to float32 -- must not be related.
This module finds those pairs for a whole triangle soup at once:

1. **broad phase** (:func:`candidate_pairs`): each bounding box is binned into the cells of a
   uniform grid it covers; two boxes are a candidate when they share a cell, and each pair is
   reported once, by the cell that holds the lower-left corner of the two boxes' intersection
   (no ``np.unique`` over all pairs);
2. **narrow phase** (:func:`triangles_overlap`): the separating-axis test over the six edge
   normals of the two triangles, with a tolerance ``tol`` in screen units: two triangles overlap
   when their projections overlap by more than ``tol`` on *every* axis (for convex polygons the
   smallest such overlap is the penetration depth, so touching pairs are rejected);
3. **a point of the overlap** (:func:`intersection_centroids`): the centroid of the
   intersection polygon, from its boundary pieces (each edge clipped to the other triangle,
   Cyrus--Beck) and Green's theorem, vectorized over pairs.  Any linear function (e.g. a depth
   interpolated over a face) has its mean over the overlap at that point.

No library we depend on offers a batched 2D triangle-triangle overlap (libigl's
``tri_tri_intersect`` is 3D and per pair; networkx/scipy have none), hence the hand-written,
vectorized code.  Everything works in float64 on coordinates shifted to each pair's first
vertex, which keeps the arithmetic exact enough far from the origin.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

# float32 round-off of a coordinate is half an ulp (6e-8 relative); overlaps combine a few
# such coordinates, so 16 float32 epsilons of the model's size is safely above it and far below
# any overlap a person would see.
TOL_FACTOR = 16.0 * float(np.finfo(np.float32).eps)

# Pairs processed per narrow-phase chunk: bounds the temporary memory (~1 KB per pair).
_CHUNK = 1 << 20


def model_scale(points: np.ndarray) -> float:
    """Size of a point set for relative tolerances: ``max(bbox diagonal, max |coordinate|)``.

    The largest absolute coordinate enters because float32 round-off grows with it: a model far
    from the origin has larger absolute errors than its extent suggests.
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, points.shape[-1])
    if pts.size == 0:
        return 1.0
    diag = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    s = max(diag, float(np.abs(pts).max()))
    return s if s > 0.0 else 1.0


def default_tol(points: np.ndarray) -> float:
    """Default overlap tolerance in the units of ``points``: ``TOL_FACTOR * model_scale``."""
    return TOL_FACTOR * model_scale(points)


def _max3(a: np.ndarray) -> np.ndarray:
    """``a.max(axis=1)`` for an (n, 3, ...) array; numpy reduces a length-3 axis slowly."""
    return np.maximum(np.maximum(a[:, 0], a[:, 1]), a[:, 2])


def _min3(a: np.ndarray) -> np.ndarray:
    """``a.min(axis=1)`` for an (n, 3, ...) array."""
    return np.minimum(np.minimum(a[:, 0], a[:, 1]), a[:, 2])


def triangle_heights(T: np.ndarray) -> np.ndarray:
    """Smallest height of each screen triangle.

    Parameters
    ----------
    T : (n, 3, 2) float64
        Screen triangles.

    Returns
    -------
    (n,) float64
        ``2 * area / longest edge``: zero for a triangle seen edge-on or with coincident corners.
    """
    e1 = T[:, 1] - T[:, 0]
    e2 = T[:, 2] - T[:, 0]
    area2 = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    d = T - np.roll(T, -1, axis=1)
    lmax = np.sqrt(_max3(d[..., 0] ** 2 + d[..., 1] ** 2))
    out = np.zeros(T.shape[0])
    ok = lmax > 0.0
    out[ok] = area2[ok] / lmax[ok]
    return out


def _grid_cells(lo: np.ndarray, hi: np.ndarray, origin: np.ndarray, h: float):
    c0 = np.floor((lo - origin) / h).astype(np.int64)
    c1 = np.floor((hi - origin) / h).astype(np.int64)
    return c0, c1


def _choose_cell(lo: np.ndarray, hi: np.ndarray, origin: np.ndarray) -> float:
    """Cell size near the median box size, grown until boxes cover ~4 cells on average."""
    n = lo.shape[0]
    ext = hi - lo
    span = float(max((hi.max(axis=0) - lo.min(axis=0)).max(), 0.0))
    h = float(np.median(ext.max(axis=1)))
    # Never more than ~4n cells along an axis (degenerate or tiny boxes) nor a zero size.
    h = max(h, span / (4.0 * n + 1.0), np.finfo(np.float64).tiny)
    if span == 0.0:
        return 1.0
    for _ in range(8):
        c0, c1 = _grid_cells(lo, hi, origin, h)
        total = float(np.prod(c1 - c0 + 1, axis=1, dtype=np.float64).sum())
        if total <= 8.0 * n:
            break
        h *= max(np.sqrt(total / (4.0 * n)), 1.5)
    return h


def candidate_pairs(
    lo: np.ndarray, hi: np.ndarray, tol: float = 0.0, chunk: int = _CHUNK
) -> Iterator[np.ndarray]:
    """Broad phase: pairs of axis-aligned boxes that overlap by more than ``tol`` on both axes.

    Parameters
    ----------
    lo, hi : (n, 2) float64
        Box corners (``lo <= hi``).
    tol : float
        Boxes overlapping by ``tol`` or less on an axis are not paired.
    chunk : int
        Approximate number of raw candidate pairs handled at a time.

    Yields
    ------
    (k, 2) int64
        Pairs ``(i, j)`` with ``i < j``; every overlapping pair exactly once over all chunks.
    """
    n = lo.shape[0]
    if n < 2:
        return
    origin = lo.min(axis=0)
    h = _choose_cell(lo, hi, origin)
    c0, c1 = _grid_cells(lo, hi, origin, h)
    ncell = c1 - c0 + 1  # (n, 2) cells covered along x and y
    ny_grid = int(c1[:, 1].max()) + 1
    counts = ncell[:, 0] * ncell[:, 1]
    # Expand every box into the cells it covers (box-major order).
    owner = np.repeat(np.arange(n, dtype=np.int64), counts)
    t = np.arange(owner.size, dtype=np.int64) - np.repeat(np.cumsum(counts) - counts, counts)
    cx = c0[owner, 0] + t // ncell[owner, 1]
    cy = c0[owner, 1] + t % ncell[owner, 1]
    key = cx * ny_grid + cy
    srt = np.argsort(key, kind="stable")
    key, owner, cx, cy = key[srt], owner[srt], cx[srt], cy[srt]
    del srt, t
    # Per-entry copies of the boxes in cell order: the pairs below gather from nearby rows.
    elo_x, elo_y = lo[owner, 0], lo[owner, 1]
    ehi_x, ehi_y = hi[owner, 0], hi[owner, 1]
    # Entry p pairs with the later entries of its cell: positions p+1 .. end-1.
    bounds = np.flatnonzero(np.diff(key)) + 1
    starts = np.concatenate(([0], bounds))
    ends = np.concatenate((bounds, [key.size]))
    del key, bounds
    npair = np.repeat(ends, ends - starts) - np.arange(owner.size) - 1
    cum = np.cumsum(npair)
    # Split the entries into blocks of about `chunk` pairs each (an entry's pairs stay together).
    cuts = np.searchsorted(cum, np.arange(chunk, cum[-1] + chunk, chunk, dtype=np.int64))
    cuts = np.unique(np.concatenate(([0], np.minimum(cuts + 1, owner.size), [owner.size])))
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        cnt = npair[a:b]
        tot = int(cnt.sum())
        if tot == 0:
            continue
        p = np.repeat(np.arange(a, b, dtype=np.int64), cnt)
        q = p + 1 + np.arange(tot, dtype=np.int64) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        mlo_x = np.maximum(elo_x[p], elo_x[q])
        mlo_y = np.maximum(elo_y[p], elo_y[q])
        keep = np.minimum(ehi_x[p], ehi_x[q]) - mlo_x > tol
        keep &= np.minimum(ehi_y[p], ehi_y[q]) - mlo_y > tol
        # Report a pair only in the cell holding the lower-left corner of the boxes' overlap.
        keep &= np.floor((mlo_x - origin[0]) / h).astype(np.int64) == cx[p]
        keep &= np.floor((mlo_y - origin[1]) / h).astype(np.int64) == cy[p]
        i, j = owner[p[keep]], owner[q[keep]]
        yield np.stack((np.minimum(i, j), np.maximum(i, j)), axis=1)


def triangles_overlap(A: np.ndarray, B: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Narrow phase: do the triangles ``A[k]`` and ``B[k]`` overlap with positive area?

    Separating-axis test over the six edge normals ``n`` of the pair: the triangles overlap when,
    for every axis, ``min(max_A, max_B) - max(min_A, min_B) > tol`` where ``max_A`` is the largest
    projection ``n . a / |n|`` of a corner of ``A`` (a distance in screen units).  Triangles
    that only touch (overlap ``<= tol`` along some axis) are reported as not overlapping.
    Axes are tried one at a time on the pairs still in doubt (most candidates from the broad
    phase are separated by the first axes).

    Parameters
    ----------
    A, B : (k, 3, 2) float64
        Screen triangles, any orientation.  Neither may be degenerate (height ``<= tol``);
        filter those with :func:`triangle_heights` first.
    tol : float
        Overlap tolerance in screen units.

    Returns
    -------
    (k,) bool
    """
    return _sat(A[..., 0], A[..., 1], B[..., 0], B[..., 1], tol)


def _sat(ax, ay, bx, by, tol: float) -> np.ndarray:
    """:func:`triangles_overlap` on corner coordinates given as (k, 3) arrays."""
    ox, oy = ax[:, :1], ay[:, :1]
    # shift to A's first corner: fewer cancellation errors far from the origin
    ax, ay, bx, by = ax - ox, ay - oy, bx - ox, by - oy
    k = ax.shape[0]
    alive = np.arange(k)
    for side in range(2):
        for e in range(3):
            px, py = (ax, ay) if side == 0 else (bx, by)
            nx = py[:, (e + 1) % 3] - py[:, e]  # edge normal (ey, -ex)
            ny = px[:, e] - px[:, (e + 1) % 3]
            pa = ax * nx[:, None] + ay * ny[:, None]
            pb = bx * nx[:, None] + by * ny[:, None]
            lap = np.minimum(_max3(pa), _max3(pb)) - np.maximum(_min3(pa), _min3(pb))
            keep = lap > tol * np.sqrt(nx * nx + ny * ny)
            alive = alive[keep]
            ax, ay, bx, by = ax[keep], ay[keep], bx[keep], by[keep]
    out = np.zeros(k, dtype=bool)
    out[alive] = True
    return out


def _ccw(T: np.ndarray) -> np.ndarray:
    """Triangles with corners 1 and 2 swapped where needed to make them counter-clockwise."""
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    cw = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    T = T.copy()
    T[cw] = T[cw][:, [0, 2, 1]]
    return T


def intersection_centroids(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centroid and area of the intersection polygon of each pair of triangles.

    The boundary of the convex polygon ``A & B`` is made of the pieces of ``A``'s edges inside
    ``B`` and of ``B``'s edges inside ``A``; each piece is found by clipping the edge's parameter
    interval to the other triangle's three half-planes (Cyrus-Beck), a fixed amount of work
    per pair with no polygon bookkeeping.  With both triangles counter-clockwise the pieces are
    directed segments ``p -> q`` of the polygon's boundary, and Green's theorem gives

    ``area = 1/2 sum p x q``,  ``centroid = sum (p + q) (p x q) / (6 area)``

    without ordering the pieces.  An edge lying on the other triangle's edge line counts for
    ``A`` only (inclusive for ``A``'s edges, strict for ``B``'s), so a boundary shared by a
    folded pair is not counted twice.  Being the mean over a convex region inside both
    triangles, the centroid lies in both, and any function linear on each triangle takes at it
    its mean over the overlap.

    Parameters
    ----------
    A, B : (k, 3, 2) float64
        Pairs of non-degenerate screen triangles, any orientation.

    Returns
    -------
    centroid : (k, 2) float64
    area : (k,) float64
        Area of the intersection (0 where it is empty or degenerate; the centroid is then the
        mean of the clipped pieces' midpoints, or ``A``'s centroid when there are none).
    """
    o = A[:, 0, :].copy()
    A = _ccw(A - o[:, None, :])
    B = _ccw(B - o[:, None, :])
    k = A.shape[0]
    area2 = np.zeros(k)
    nx_, ny_ = np.zeros(k), np.zeros(k)
    mx, my = np.zeros(k), np.zeros(k)
    cnt = np.zeros(k)
    for S, C, strict in ((A, B, False), (B, A, True)):
        sx, sy = S[..., 0], S[..., 1]
        cx, cy = C[..., 0], C[..., 1]
        # inward normals (-ey, ex) of C's counter-clockwise edges, and their offsets n . c
        nx = [cy[:, c] - cy[:, (c + 1) % 3] for c in range(3)]
        ny = [cx[:, (c + 1) % 3] - cx[:, c] for c in range(3)]
        off = [nx[c] * cx[:, c] + ny[c] * cy[:, c] for c in range(3)]
        for e in range(3):
            px, py = sx[:, e], sy[:, e]
            dx, dy = sx[:, (e + 1) % 3] - px, sy[:, (e + 1) % 3] - py
            t0, t1 = np.zeros(k), np.ones(k)
            ok = np.ones(k, dtype=bool)
            for c in range(3):
                f = nx[c] * px + ny[c] * py - off[c]  # signed distance of p (times |n|)
                g = nx[c] * dx + ny[c] * dy  # its change along the edge
                par = g == 0.0
                ok &= ~par | ((f > 0.0) if strict else (f >= 0.0))
                t = -f / np.where(par, 1.0, g)
                t0 = np.where(g > 0.0, np.maximum(t0, t), t0)
                t1 = np.where(g < 0.0, np.minimum(t1, t), t1)
            ok &= t1 > t0
            ax, ay = px + t0 * dx, py + t0 * dy
            bx, by = px + t1 * dx, py + t1 * dy
            cr = np.where(ok, ax * by - ay * bx, 0.0)
            area2 += cr
            nx_ += (ax + bx) * cr
            ny_ += (ay + by) * cr
            mx += np.where(ok, 0.5 * (ax + bx), 0.0)
            my += np.where(ok, 0.5 * (ay + by), 0.0)
            cnt += ok
    # fallbacks for empty or degenerate intersections: mean of the pieces' midpoints, or A's
    # centroid when nothing is left
    cen = np.where(
        (cnt > 0)[:, None],
        np.stack((mx, my), axis=1) / np.maximum(cnt, 1.0)[:, None],
        A.mean(axis=1),
    )
    good = area2 > 0.0
    cen[good, 0] = nx_[good] / (3.0 * area2[good])
    cen[good, 1] = ny_[good] / (3.0 * area2[good])
    return cen + o, 0.5 * np.maximum(area2, 0.0)


def barycentric(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Barycentric coordinates of points ``P[k]`` in triangles ``T[k]``.

    Parameters
    ----------
    P : (k, 2) float64
    T : (k, 3, 2) float64
        Non-degenerate triangles.

    Returns
    -------
    (k, 3) float64
        ``b`` with ``b.sum(1) == 1`` and ``P == (b[:, :, None] * T).sum(1)``.
    """
    v0 = T[:, 1] - T[:, 0]
    v1 = T[:, 2] - T[:, 0]
    v2 = P - T[:, 0]
    den = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    b1 = (v2[:, 0] * v1[:, 1] - v2[:, 1] * v1[:, 0]) / den
    b2 = (v0[:, 0] * v2[:, 1] - v0[:, 1] * v2[:, 0]) / den
    return np.stack((1.0 - b1 - b2, b1, b2), axis=1)


def overlapping_pairs(
    T: np.ndarray,
    tol: float | None = None,
    faces: np.ndarray | None = None,
    centroids: bool = False,
    chunk: int = _CHUNK,
    pair_filter: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray | None]:
    """All pairs of screen triangles that overlap with positive area.

    Parameters
    ----------
    T : (n, 3, 2) float64
        Screen triangles (e.g. ``xy[F]``).
    tol : float, optional
        Overlap tolerance in screen units (default :func:`default_tol` of ``T``).  Triangles
        thinner than ``tol`` (seen edge-on) overlap nothing.
    faces : (m,) int64, optional
        Only consider these triangles (indices into ``T``); default all.
    centroids : bool, default: False
        Also return the centroid of each pair's intersection polygon.
    chunk : int
        Pairs per vectorized block (memory bound).
    pair_filter : callable, optional
        ``pair_filter(i, j) -> (k,) bool`` on candidate pairs (indices into ``T``, ``i < j``)
        before the narrow phase: only pairs it keeps are tested (e.g. pairs whose parent faces
        are ordered, in :meth:`DepthOrder.refine`).

    Returns
    -------
    pairs : (k, 2) int64
        ``(i, j)`` with ``i < j``, sorted lexicographically.
    centroid : (k, 2) float64 or None
    """
    T = np.asarray(T, dtype=np.float64)
    if tol is None:
        tol = default_tol(T)
    ids = np.arange(T.shape[0], dtype=np.int64) if faces is None else np.unique(faces)
    ids = ids[triangle_heights(T[ids]) > tol]
    if ids.size < 2:
        return np.zeros((0, 2), dtype=np.int64), (np.zeros((0, 2)) if centroids else None)
    S = T[ids]
    X, Y = np.ascontiguousarray(S[..., 0]), np.ascontiguousarray(S[..., 1])  # (m, 3) each
    out_p, out_c = [], []
    for cand in candidate_pairs(_min3(S), _max3(S), tol, chunk):
        if pair_filter is not None:
            cand = cand[pair_filter(ids[cand[:, 0]], ids[cand[:, 1]])]
        i, j = cand[:, 0], cand[:, 1]
        cand = cand[_sat(X[i], Y[i], X[j], Y[j], tol)]
        out_p.append(ids[cand])
        if centroids:
            out_c.append(intersection_centroids(S[cand[:, 0]], S[cand[:, 1]])[0])
    pairs = np.concatenate(out_p) if out_p else np.zeros((0, 2), dtype=np.int64)
    srt = np.lexsort((pairs[:, 1], pairs[:, 0]))
    pairs = pairs[srt]
    if not centroids:
        return pairs, None
    cen = np.concatenate(out_c) if out_c else np.zeros((0, 2))
    return pairs, cen[srt]
