"""Compiled kernels (numba) for 2D triangle overlap: grid broad phase, exact narrow phase.

These are the inner loops of :mod:`meschers_igl.geometry2d` (which validates inputs and holds
the public API) and of :class:`meschers_igl.order.DepthOrder`.  Why numba and not a library:

* shapely 2 (GEOS) intersects polygons one pair at a time through Python objects
  (~10 us a pair: 40 s for the 3.8M overlapping pairs of a 1M-face torus, before the broad
  phase) and has no tolerance-aware "overlap with positive area" predicate; its STRtree query
  returns box candidates only.
* CGAL's Python bindings are not on PyPI for this platform, and libigl's
  ``tri_tri_intersect`` is 3D and per pair.
* A vectorized numpy version spends its time in temporaries: about 1 KB a pair, 17-25x
  libigl's cotmatrix + massmatrix at 1M faces.

So the broad phase (a uniform grid, each pair reported once by the cell holding the lower-left
corner of the two boxes' intersection), the separating-axis test and the intersection centroid
(Sutherland-Hodgman clipping + the shoelace formula) run here in one compiled pass.

All kernels are serial (``parallel=False``): the machines this runs on are shared, the
benchmark compares against single-threaded libigl, and serial kernels are deterministic.
``cache=True`` keeps the compiled code in ``__pycache__`` between processes.
"""

from __future__ import annotations

import numpy as np

from .jit import kernel

__all__ = [
    "arcs_from_depths",
    "barycentric_depths",
    "boxes_and_heights",
    "unique_sorted_pairs",
    "candidate_pairs_grid",
    "child_pairs",
    "grid_overlaps",
    "intersection_centroid",
    "overlap_pairs_sat",
    "pair_centroids",
    "sat_overlap",
    "sort_pairs",
]

#: the decorator of the kernels only compiled code calls (the others' helpers): compiled
#: without numba's CPython wrapper, the boxing and unboxing of their arguments and results for
#: a call from Python, which none makes (about a third of a small kernel's machine code, and of
#: its first-run compilation).  Calling one from Python crashes the interpreter: call the
#: kernels that use them.
_inner = kernel(no_cpython_wrapper=True)
# public kernels keep numba's Python entry: called from Python, an _inner kernel crashes
_public = kernel()


@_inner
def _max3(a: float, b: float, c: float) -> float:
    return max(max(a, b), c)


@_inner
def _min3(a: float, b: float, c: float) -> float:
    return min(min(a, b), c)


@_inner
def _separated(nx, ny, c):
    """Do the projections on the axis ``n`` overlap by ``<= tol * |n|``?  ``c``: the corners
    ``(a0x, a0y, a1x, a1y, a2x, a2y, b0x, b0y, b1x, b1y, b2x, b2y)`` and ``tol``."""
    a0x, a0y, a1x, a1y, a2x, a2y, b0x, b0y, b1x, b1y, b2x, b2y, tol = c
    pa0 = a0x * nx + a0y * ny
    pa1 = a1x * nx + a1y * ny
    pa2 = a2x * nx + a2y * ny
    pb0 = b0x * nx + b0y * ny
    pb1 = b1x * nx + b1y * ny
    pb2 = b2x * nx + b2y * ny
    lap = min(_max3(pa0, pa1, pa2), _max3(pb0, pb1, pb2)) - max(
        _min3(pa0, pa1, pa2), _min3(pb0, pb1, pb2)
    )
    return not lap > tol * np.sqrt(nx * nx + ny * ny)


@_public
def sat_overlap(T: np.ndarray, i: int, j: int, tol: float) -> bool:
    """Separating-axis test of the screen triangles ``T[i]`` and ``T[j]`` (T (n, 3, 2)).

    True when, along each of the six edge normals ``n = (e_y, -e_x)``, the projections
    ``n . p / |n|`` of the two triangles overlap by more than ``tol``.  Coordinates are shifted
    to ``T[i]``'s first corner first (fewer cancellation errors far from the origin).
    """
    ox, oy = T[i, 0, 0], T[i, 0, 1]
    a0x, a1x, a2x = T[i, 0, 0] - ox, T[i, 1, 0] - ox, T[i, 2, 0] - ox
    a0y, a1y, a2y = T[i, 0, 1] - oy, T[i, 1, 1] - oy, T[i, 2, 1] - oy
    b0x, b1x, b2x = T[j, 0, 0] - ox, T[j, 1, 0] - ox, T[j, 2, 0] - ox
    b0y, b1y, b2y = T[j, 0, 1] - oy, T[j, 1, 1] - oy, T[j, 2, 1] - oy
    c = (a0x, a0y, a1x, a1y, a2x, a2y, b0x, b0y, b1x, b1y, b2x, b2y, tol)
    # the normals of A's edges 0->1, 1->2, 2->0, then B's
    if _separated(a1y - a0y, a0x - a1x, c):
        return False
    if _separated(a2y - a1y, a1x - a2x, c):
        return False
    if _separated(a0y - a2y, a2x - a0x, c):
        return False
    if _separated(b1y - b0y, b0x - b1x, c):
        return False
    if _separated(b2y - b1y, b1x - b2x, c):
        return False
    return not _separated(b0y - b2y, b2x - b0x, c)


@_inner
def _ccw6(x0, y0, x1, y1, x2, y2):
    """Corners as a 6-tuple, corners 1 and 2 swapped when the triangle is clockwise."""
    e1x, e1y, e2x, e2y = x1 - x0, y1 - y0, x2 - x0, y2 - y0
    if e1x * e2y - e1y * e2x < 0:
        return (x0, y0, x2, y2, x1, y1)
    return (x0, y0, x1, y1, x2, y2)


# Room for the clipped polygon: each of the three half-plane clips emits at most two points per
# input point (a kept point and a crossing), whatever rounding does to convexity.
CLIP_ROOM = 24


@_public
def intersection_centroid(
    T: np.ndarray, i: int, j: int, buf: np.ndarray
) -> tuple[float, float, float]:
    """Centroid ``(cx, cy)`` and area of the intersection of triangles ``T[i]`` and ``T[j]``.

    ``A`` (counter-clockwise) is clipped by the three inner half-planes of ``B``
    (Sutherland-Hodgman), then the shoelace formula gives ``area = 1/2 sum p x q`` and
    ``centroid = sum (p + q)(p x q) / (6 area)``.  Clipping is continuous in the corners: edges
    that nearly coincide leave a sliver (or nothing) of about their gap's area, never a whole
    edge counted twice or dropped, so the centroid of an overlap is as well-conditioned as the
    overlap is (error ~ eps * size^3 / area).  Empty or degenerate intersections: the mean of
    the clipped polygon's points, or ``A``'s centroid when there are none; area 0.

    ``buf`` : (2, CLIP_ROOM, 2) float64 scratch space (allocated once by the caller).
    """
    ox, oy = T[i, 0, 0], T[i, 0, 1]
    A = _ccw6(
        T[i, 0, 0] - ox,
        T[i, 0, 1] - oy,
        T[i, 1, 0] - ox,
        T[i, 1, 1] - oy,
        T[i, 2, 0] - ox,
        T[i, 2, 1] - oy,
    )
    B = _ccw6(
        T[j, 0, 0] - ox,
        T[j, 0, 1] - oy,
        T[j, 1, 0] - ox,
        T[j, 1, 1] - oy,
        T[j, 2, 0] - ox,
        T[j, 2, 1] - oy,
    )
    P, Q = buf[0], buf[1]
    for c in range(3):
        P[c, 0], P[c, 1] = A[2 * c], A[2 * c + 1]
    n = 3
    for c in range(3):
        if n == 0:
            break
        d = (c + 1) % 3
        bx, by = B[2 * c], B[2 * c + 1]
        ex, ey = B[2 * d] - bx, B[2 * d + 1] - by
        m = 0
        for k in range(n):
            k1 = k + 1 if k + 1 < n else 0
            px, py, qx, qy = P[k, 0], P[k, 1], P[k1, 0], P[k1, 1]
            sp = ex * (py - by) - ey * (px - bx)  # > 0: left of B's edge, inside
            sq = ex * (qy - by) - ey * (qx - bx)
            if sp >= 0.0:
                Q[m, 0], Q[m, 1] = px, py
                m += 1
            if (sp >= 0.0) != (sq >= 0.0):
                t = sp / (sp - sq)
                Q[m, 0], Q[m, 1] = px + t * (qx - px), py + t * (qy - py)
                m += 1
        P, Q = Q, P
        n = m
    area2 = 0.0
    sx, sy, mx, my = 0.0, 0.0, 0.0, 0.0
    for k in range(n):
        k1 = k + 1 if k + 1 < n else 0
        cr = P[k, 0] * P[k1, 1] - P[k, 1] * P[k1, 0]
        area2 += cr
        sx += (P[k, 0] + P[k1, 0]) * cr
        sy += (P[k, 1] + P[k1, 1]) * cr
        mx += P[k, 0]
        my += P[k, 1]
    if area2 > 0.0:
        cx, cy = sx / (3.0 * area2), sy / (3.0 * area2)
    elif n > 0:
        cx, cy = mx / n, my / n
    else:
        cx, cy = (A[0] + A[2] + A[4]) / 3.0, (A[1] + A[3] + A[5]) / 3.0
    return cx + ox, cy + oy, 0.5 * max(area2, 0.0)


@kernel()
def overlap_pairs_sat(T: np.ndarray, pairs: np.ndarray, tol: float) -> np.ndarray:
    """(k,) bool: :func:`sat_overlap` of ``T[pairs[:, 0]]`` and ``T[pairs[:, 1]]`` (T (n, 3, 2))."""
    k = pairs.shape[0]
    out = np.empty(k, dtype=np.bool_)  # every entry written below
    for p in range(k):
        i, j = pairs[p, 0], pairs[p, 1]
        out[p] = sat_overlap(T, i, j, tol)
    return out


@_inner
def _grow(a: np.ndarray, need: int) -> np.ndarray:
    """``a (n, 2) int64`` copied into a new array of ``max(2n, need)`` rows (``a`` itself when
    it has ``need`` rows)."""
    if need <= a.shape[0]:
        return a
    # ``(cap, 2)`` and ``dtype=np.int64`` spelled as every other allocation of pairs is (a
    # ``dtype=a.dtype`` or a computed shape is another compilation of np.empty); an element loop,
    # not ``b[:n] = a``: array-to-array slice assignment compiles numba's shape-mismatch error
    # formatting (several seconds of first-run compilation)
    b = np.empty((max(2 * a.shape[0], need), 2), dtype=np.int64)
    for i in range(a.shape[0]):
        b[i, 0], b[i, 1] = a[i, 0], a[i, 1]
    return b


@_inner
def _cell_lists(c0: np.ndarray, c1: np.ndarray, ny: int, ncell: int, ok: np.ndarray):
    """Entries (ids of boxes with ``ok``) of each occupied grid cell: ``(cells, start, owner)``,
    CSR by cell.  Counting sort when the grid is small enough (``ncell`` cells), else a sort of
    the cells' ``(cx, cy)``.
    """
    n = c0.shape[0]
    total = 0
    for b in range(n):
        if ok[b]:
            total += (c1[b, 0] - c0[b, 0] + 1) * (c1[b, 1] - c0[b, 1] + 1)
    key = np.empty(total, dtype=np.int64)
    own = np.empty(total, dtype=np.int32)
    p = 0
    for b in range(n):
        if not ok[b]:
            continue
        for cx in range(c0[b, 0], c1[b, 0] + 1):
            for cy in range(c0[b, 1], c1[b, 1] + 1):
                key[p] = cx * ny + cy
                own[p] = b
                p += 1
    if ncell <= 4 * total + 1024:
        count = np.empty(ncell + 1, dtype=np.int64)
        for c in range(ncell + 1):  # zeroed in a loop: see sort_pairs
            count[c] = 0
        for q in range(total):
            count[key[q] + 1] += 1
        nocc = 0
        for c in range(ncell):
            if count[c + 1] > 0:
                nocc += 1
            count[c + 1] += count[c]
        owner = np.empty(total, dtype=np.int32)
        fill = count[:-1].copy()
        for q in range(total):
            c = key[q]
            owner[fill[c]] = own[q]
            fill[c] += 1
        cells = np.empty(nocc, dtype=np.int64)
        start = np.empty(nocc + 1, dtype=np.int64)
        r = 0
        for c in range(ncell):
            if count[c + 1] > count[c]:
                cells[r] = c
                start[r] = count[c]
                r += 1
        start[nocc] = total
        return cells, start, owner
    # a sparse grid: the keys' stable sorting permutation as that of the cells' ``(cx, cy)``,
    # by the two counting sorts of :func:`sort_pairs` (``O(total + nx + ny)``: the grid has at
    # most ~4n cells along each axis)
    cxy = np.empty((total, 2), dtype=np.int64)
    top = ny
    for q in range(total):
        cx = key[q] // ny
        cxy[q, 0], cxy[q, 1] = cx, key[q] - cx * ny
        top = max(top, cx + 1)
    srt = sort_pairs(cxy, top)
    owner = own[srt]
    skey = key[srt]
    nocc = 0
    for q in range(total):
        if q == 0 or skey[q] != skey[q - 1]:
            nocc += 1
    cells = np.empty(nocc, dtype=np.int64)
    start = np.empty(nocc + 1, dtype=np.int64)
    r = 0
    for q in range(total):
        if q == 0 or skey[q] != skey[q - 1]:
            cells[r] = skey[q]
            start[r] = q
            r += 1
    start[nocc] = total
    return cells, start, owner


@kernel()
def grid_overlaps(T, ok, lo, hi, origin, h, c0, c1, ny, ncell, tol, narrow, centroids, group):
    """All pairs of triangles whose boxes (and, with ``narrow``, whose triangles) overlap.

    Parameters
    ----------
    T : (n, 3, 2) float64
        Screen triangles (only their boxes when ``narrow`` is False).
    ok : (n,) bool
        Triangles to consider (the others pair with nothing).
    lo, hi : (n, 2) float64
        Their bounding boxes.
    origin : (2,) float64, h : float
        The grid: cell ``(cx, cy)`` covers ``origin + h * [cx, cx+1) x [cy, cy+1)``.
    c0, c1 : (n, 2) int64
        First and last cell of each box; ``ny`` cells along y, ``ncell`` cells in all.
    tol : float
        Boxes (triangles) overlapping by ``tol`` or less on an axis are not paired.
    narrow, centroids : bool
        Run the separating-axis test; compute intersection centroids (needs ``narrow``).
    group : (n,) int64 or (0,)
        When given, only pairs from different groups.

    Returns
    -------
    pairs : (k, 2) int64
        ``(i, j)``, ``i < j``, each overlapping pair once, sorted lexicographically.
    cen : (k, 2) float64
        Intersection centroids (``(0, 2)`` without ``centroids``).
    """
    cells, start, owner = _cell_lists(c0, c1, ny, ncell, ok)
    cap = max(1024, 4 * T.shape[0])
    pairs = np.empty((cap, 2), dtype=np.int64)
    cen = np.empty((cap if centroids else 1, 2), dtype=np.float64)
    k = 0
    use_group = group.shape[0] > 0
    blx = np.empty(64, dtype=np.float64)
    bly = np.empty(64, dtype=np.float64)
    buf = np.empty((2, CLIP_ROOM, 2), dtype=np.float64)
    bhx = np.empty(64, dtype=np.float64)
    bhy = np.empty(64, dtype=np.float64)
    bid = np.empty(64, dtype=np.int64)
    # the cell's triangles, copied: the pair loop stays in cache
    bt = np.empty((64, 3, 2), dtype=np.float64)
    for r in range(cells.shape[0]):
        s, e = start[r], start[r + 1]
        m = e - s
        if m < 2:
            continue
        if m > blx.shape[0]:
            blx, bly = np.empty(2 * m, dtype=np.float64), np.empty(2 * m, dtype=np.float64)
            bhx, bhy = np.empty(2 * m, dtype=np.float64), np.empty(2 * m, dtype=np.float64)
            bid = np.empty(2 * m, dtype=np.int64)
            bt = np.empty((2 * m, 3, 2), dtype=np.float64)
        for q in range(m):  # this cell's boxes, contiguous and sorted by lo x (insertion)
            b = owner[s + q]
            x = lo[b, 0]
            t = q
            while t > 0 and blx[t - 1] > x:
                bid[t], blx[t], bly[t] = bid[t - 1], blx[t - 1], bly[t - 1]
                bhx[t], bhy[t] = bhx[t - 1], bhy[t - 1]
                t -= 1
            bid[t], blx[t], bly[t] = b, x, lo[b, 1]
            bhx[t], bhy[t] = hi[b, 0], hi[b, 1]
        if narrow:  # element loops: an array-to-array assignment compiles numba's shape errors
            for q in range(m):
                for c in range(3):
                    bt[q, c, 0], bt[q, c, 1] = T[bid[q], c, 0], T[bid[q], c, 1]
        cxc = cells[r] // ny
        cyc = cells[r] - cxc * ny
        for p in range(m - 1):
            for q in range(p + 1, m):
                # sweep: boxes further on start further right, so none overlaps p by > tol
                if not bhx[p] - blx[q] > tol:
                    break
                mlo_x = max(blx[p], blx[q])
                if not min(bhx[p], bhx[q]) - mlo_x > tol:
                    continue
                mlo_y = max(bly[p], bly[q])
                if not min(bhy[p], bhy[q]) - mlo_y > tol:
                    continue
                # report the pair only in the cell holding the boxes' overlap's lower-left corner
                if np.int64(np.floor((mlo_x - origin[0]) / h)) != cxc:
                    continue
                if np.int64(np.floor((mlo_y - origin[1]) / h)) != cyc:
                    continue
                i, j, li, lj = bid[p], bid[q], p, q
                if i > j:
                    i, j, li, lj = j, i, q, p
                if use_group and group[i] == group[j]:
                    continue
                if narrow and not sat_overlap(bt, li, lj, tol):
                    continue
                if k == pairs.shape[0]:
                    pairs = _grow(pairs, k + 1)
                    if centroids:  # a loop here: ``_grow`` for float64 is a second compilation
                        grown = np.empty((pairs.shape[0], 2), dtype=np.float64)
                        for r in range(k):
                            grown[r, 0], grown[r, 1] = cen[r, 0], cen[r, 1]
                        cen = grown
                pairs[k, 0], pairs[k, 1] = i, j
                if centroids:
                    cx, cy, _ = intersection_centroid(bt, li, lj, buf)
                    cen[k, 0], cen[k, 1] = cx, cy
                k += 1
    perm = sort_pairs(pairs[:k], T.shape[0])
    out = np.empty((k, 2), dtype=np.int64)
    oc = np.empty((k if centroids else 0, 2), dtype=np.float64)
    for r in range(k):
        out[r, 0], out[r, 1] = pairs[perm[r], 0], pairs[perm[r], 1]
        if centroids:
            oc[r, 0], oc[r, 1] = cen[perm[r], 0], cen[perm[r], 1]
    return out, oc


def candidate_pairs_grid(
    lo: np.ndarray,
    hi: np.ndarray,
    origin: np.ndarray,
    h: float,
    c0: np.ndarray,
    c1: np.ndarray,
    ny: int,
    ncell: int,
    tol: float,
) -> np.ndarray:
    """Broad phase only: pairs of boxes overlapping by more than ``tol`` on both axes (sorted).

    Python, not compiled: called from compiled code with the constants ``False``,
    :func:`grid_overlaps` would be compiled a second time for them (numba specialises on
    literal arguments); called from here it reuses the compilation the narrow phase uses.
    """
    T = np.zeros((lo.shape[0], 3, 2))
    ok = np.ones(lo.shape[0], dtype=np.bool_)
    pairs, _ = grid_overlaps(
        T,
        ok,
        lo,
        hi,
        origin,
        h,
        c0,
        c1,
        int(ny),
        int(ncell),
        float(tol),
        False,
        False,
        np.zeros(0, dtype=np.int64),
    )
    return pairs


@kernel()
def child_pairs(
    T: np.ndarray,
    ok: np.ndarray,
    arcs: np.ndarray,
    child_start: np.ndarray,
    children: np.ndarray,
    tol: float,
) -> np.ndarray:
    """Arcs between overlapping children of the two ends of each parent arc.

    For each parent arc ``pa -> pb`` and children ``a`` of ``pa``, ``b`` of ``pb`` (CSR
    ``children[child_start[p]:child_start[p+1]]``), both with ``ok`` set, whose triangles
    overlap (:func:`sat_overlap` on the pair ``(min, max)``, exactly as the broad phase
    calls it), the arc ``a -> b``.

    Returns
    -------
    (k, 2) int64
        Arcs, unsorted, possibly repeated when the parents' arcs repeat.
    """
    cap = max(1024, 4 * arcs.shape[0])
    out = np.empty((cap, 2), dtype=np.int64)
    k = 0
    for r in range(arcs.shape[0]):
        pa, pb = arcs[r, 0], arcs[r, 1]
        for u in range(child_start[pa], child_start[pa + 1]):
            a = children[u]
            if not ok[a]:
                continue
            for v in range(child_start[pb], child_start[pb + 1]):
                b = children[v]
                if not ok[b]:
                    continue
                i, j = (a, b) if a < b else (b, a)
                if not sat_overlap(T, i, j, tol):
                    continue
                if k == out.shape[0]:
                    out = _grow(out, k + 1)
                out[k, 0], out[k, 1] = a, b
                k += 1
    return out[:k].copy()


@kernel()
def barycentric_depths(
    P: np.ndarray, T: np.ndarray, Z: np.ndarray, faces: np.ndarray
) -> np.ndarray:
    """``z_f(P[k])``: corner depths ``Z[f]`` of face ``f = faces[k]`` interpolated at ``P[k]``.

    Barycentric coordinates of ``P[k]`` in ``T[f] (3, 2)``, then ``sum_c b_c Z[f, c]``; the same
    operations as :func:`meschers_igl.geometry2d.barycentric`.
    """
    k = P.shape[0]
    out = np.empty(k, dtype=np.float64)
    for r in range(k):
        f = faces[r]
        v0x, v0y = T[f, 1, 0] - T[f, 0, 0], T[f, 1, 1] - T[f, 0, 1]
        v1x, v1y = T[f, 2, 0] - T[f, 0, 0], T[f, 2, 1] - T[f, 0, 1]
        v2x, v2y = P[r, 0] - T[f, 0, 0], P[r, 1] - T[f, 0, 1]
        den = v0x * v1y - v0y * v1x
        b1 = (v2x * v1y - v2y * v1x) / den
        b2 = (v0x * v2y - v0y * v2x) / den
        b0 = 1.0 - b1 - b2
        out[r] = b0 * Z[f, 0] + b1 * Z[f, 1] + b2 * Z[f, 2]
    return out


@_public
def sort_pairs(pairs: np.ndarray, n: int) -> np.ndarray:
    """Permutation sorting ``pairs (k, 2)`` (values in ``[0, n)``) lexicographically.

    Two stable counting sorts (by the second column, then the first): ``O(k + n)``.
    """
    k = pairs.shape[0]
    # np.empty and loops, not np.zeros or ``cnt[:] = 0``: each spelling is a compilation of
    # its own in each process
    cnt = np.empty(n + 1, dtype=np.int64)
    for c in range(n + 1):
        cnt[c] = 0
    for r in range(k):
        cnt[pairs[r, 1] + 1] += 1
    for c in range(n):
        cnt[c + 1] += cnt[c]
    tmp = np.empty(k, dtype=np.int64)
    for r in range(k):
        c = pairs[r, 1]
        tmp[cnt[c]] = r
        cnt[c] += 1
    for c in range(n + 1):
        cnt[c] = 0
    for r in range(k):
        cnt[pairs[r, 0] + 1] += 1
    for c in range(n):
        cnt[c + 1] += cnt[c]
    perm = np.empty(k, dtype=np.int64)
    for t in range(k):
        r = tmp[t]
        c = pairs[r, 0]
        perm[cnt[c]] = r
        cnt[c] += 1
    return perm


@kernel()
def boxes_and_heights(T: np.ndarray):
    """Bounding boxes ``lo, hi (n, 2)`` and smallest heights ``(n,)`` of triangles ``T (n, 3, 2)``.

    Height: ``2 * area / longest edge`` (0 when all corners coincide), one pass, the same
    operations as the numpy formula it replaces.
    """
    n = T.shape[0]
    lo = np.empty((n, 2), dtype=np.float64)
    hi = np.empty((n, 2), dtype=np.float64)
    ht = np.empty(n, dtype=np.float64)
    for f in range(n):
        for d in range(2):
            lo[f, d] = _min3(T[f, 0, d], T[f, 1, d], T[f, 2, d])
            hi[f, d] = _max3(T[f, 0, d], T[f, 1, d], T[f, 2, d])
        e1x, e1y = T[f, 1, 0] - T[f, 0, 0], T[f, 1, 1] - T[f, 0, 1]
        e2x, e2y = T[f, 2, 0] - T[f, 0, 0], T[f, 2, 1] - T[f, 0, 1]
        area2 = abs(e1x * e2y - e1y * e2x)
        d0x, d0y = T[f, 0, 0] - T[f, 1, 0], T[f, 0, 1] - T[f, 1, 1]
        d1x, d1y = T[f, 1, 0] - T[f, 2, 0], T[f, 1, 1] - T[f, 2, 1]
        d2x, d2y = T[f, 2, 0] - T[f, 0, 0], T[f, 2, 1] - T[f, 0, 1]
        lmax = np.sqrt(_max3(d0x**2 + d0y**2, d1x**2 + d1y**2, d2x**2 + d2y**2))
        ht[f] = area2 / lmax if lmax > 0.0 else 0.0
    return lo, hi, ht


@kernel()
def unique_sorted_pairs(pairs: np.ndarray, n: int) -> np.ndarray:
    """``pairs (k, 2)`` (values in ``[0, n)``) sorted lexicographically, duplicates removed."""
    perm = sort_pairs(pairs, n)
    out = np.empty((pairs.shape[0], 2), dtype=np.int64)
    k = 0
    for r in range(perm.shape[0]):
        a, b = pairs[perm[r], 0], pairs[perm[r], 1]
        if k == 0 or a != out[k - 1, 0] or b != out[k - 1, 1]:
            out[k, 0], out[k, 1] = a, b
            k += 1
    return out[:k].copy()


def arcs_from_depths(pairs: np.ndarray, dz: np.ndarray, tol: float) -> np.ndarray:
    """Arc ``i -> j`` for each pair ``(i, j)`` with ``dz > tol``, ``j -> i`` where ``dz < -tol``.

    ``dz = depth_j - depth_i`` (larger is nearer the viewer, so ``i`` is behind ``j``).  numpy,
    not compiled: two gathers cost a few ms at a million pairs, a kernel of its own ~0.2 s of
    first-run compilation.

    Returns
    -------
    (k, 2) int64
        The arcs, in the pairs' order (pairs with ``|dz| <= tol`` or ``nan`` make none).
    """
    back = dz < -tol
    sel = np.flatnonzero(back | (dz > tol))
    b = back[sel].view(np.int8).astype(np.intp)  # the column of the arc's tail
    return np.stack((pairs[sel, b], pairs[sel, 1 - b]), axis=1).astype(np.int64, copy=False)


@kernel()
def pair_centroids(T: np.ndarray, pairs: np.ndarray):
    """:func:`intersection_centroid` of ``T[pairs[:, 0]]`` and ``T[pairs[:, 1]]``: ``(cen, area)``."""
    k = pairs.shape[0]
    cen = np.empty((k, 2), dtype=np.float64)
    area = np.empty(k, dtype=np.float64)
    buf = np.empty((2, CLIP_ROOM, 2), dtype=np.float64)
    for r in range(k):
        cen[r, 0], cen[r, 1], area[r] = intersection_centroid(T, pairs[r, 0], pairs[r, 1], buf)
    return cen, area
