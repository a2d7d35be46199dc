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
``tri_tri_intersect`` is 3D and per pair; networkx/scipy have none; shapely works one pair at a
time through Python objects), hence hand-written code: the loops run compiled, in
:mod:`meschers_igl.overlap` (numba), one pass over the grid cells doing all three steps.
Everything works in float64 on coordinates shifted to each pair's first triangle's first
vertex, which keeps the arithmetic exact enough far from the origin.
"""

from __future__ import annotations

import numpy as np

from . import overlap as _kernels

# float32 round-off of a coordinate is half an ulp (6e-8 relative); overlaps combine a few
# such coordinates, so 16 float32 epsilons of the model's size is safely above it and far below
# any overlap a person would see.
TOL_FACTOR = 16.0 * float(np.finfo(np.float32).eps)


def model_scale(points: np.ndarray) -> float:
    """Size of a point set for relative tolerances: ``max(bbox diagonal, max |coordinate|)``.

    The largest absolute coordinate enters because float32 round-off grows with it: a model far
    from the origin has larger absolute errors than its extent suggests.
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, points.shape[-1])
    if pts.size == 0:
        return 1.0
    # a reduction per column (a strided 1-D pass, as fast as a compiled loop); numpy reduces the
    # short trailing axis of ``pts.min(axis=0)`` about 10x slower
    mn = np.array([pts[:, c].min() for c in range(pts.shape[1])])
    mx = np.array([pts[:, c].max() for c in range(pts.shape[1])])
    diag = float(np.linalg.norm(mx - mn))
    s = max(diag, float(np.abs(mn).max()), float(np.abs(mx).max()))
    return s if s > 0.0 else 1.0


def default_tol(points: np.ndarray) -> float:
    """Default overlap tolerance in the units of ``points``: ``TOL_FACTOR * model_scale``."""
    return TOL_FACTOR * model_scale(points)


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
    T = np.ascontiguousarray(T, dtype=np.float64)
    return _kernels.boxes_and_heights(T)[2]


def _grid_cells(lo: np.ndarray, hi: np.ndarray, origin: np.ndarray, h: float):
    c0 = np.floor((lo - origin) / h).astype(np.int64)
    c1 = np.floor((hi - origin) / h).astype(np.int64)
    return c0, c1


def _choose_cell(lo: np.ndarray, hi: np.ndarray, origin: np.ndarray) -> float:
    """Cell size twice the median box size, grown until boxes cover ~4 cells on average.

    Twice the median (boxes cover ~1.6 cells on a regular mesh) rather than the median (~3.2):
    each pair is then met in fewer shared cells, and the sweep along x inside a cell
    (:func:`meschers_igl.overlap.grid_overlaps`) keeps the larger cells cheap (measured ~10%
    faster at 1M faces).
    """
    n = lo.shape[0]
    ext = hi - lo
    span = float(max((hi.max(axis=0) - lo.min(axis=0)).max(), 0.0))
    h = 2.0 * float(np.median(ext.max(axis=1)))
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


def _grid(lo: np.ndarray, hi: np.ndarray):
    """Grid for the broad phase: ``(origin, h, c0, c1, ny, ncell)``."""
    origin = lo.min(axis=0)
    h = _choose_cell(lo, hi, origin)
    c0, c1 = _grid_cells(lo, hi, origin, h)
    ny = int(c1[:, 1].max()) + 1
    ncell = (int(c1[:, 0].max()) + 1) * ny
    return origin, h, c0, c1, ny, ncell


def candidate_pairs(lo: np.ndarray, hi: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Broad phase: pairs of axis-aligned boxes that overlap by more than ``tol`` on both axes.

    Each box is binned into the cells of a uniform grid it covers (cell size near the median
    box, :func:`_choose_cell`); two boxes are a candidate when they share a cell, and each pair
    is reported once, by the cell that holds the lower-left corner of the two boxes'
    intersection.  Compiled (:func:`meschers_igl.overlap.candidate_pairs_grid`).

    Parameters
    ----------
    lo, hi : (n, 2) float64
        Box corners (``lo <= hi``).
    tol : float
        Boxes overlapping by ``tol`` or less on an axis are not paired.

    Returns
    -------
    (k, 2) int64
        Pairs ``(i, j)`` with ``i < j``, every overlapping pair exactly once, sorted
        lexicographically.
    """
    lo = np.ascontiguousarray(lo, dtype=np.float64)
    hi = np.ascontiguousarray(hi, dtype=np.float64)
    n = lo.shape[0]
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    return _kernels.candidate_pairs_grid(lo, hi, *_grid(lo, hi), float(tol))


def triangles_overlap(A: np.ndarray, B: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Narrow phase: do the triangles ``A[k]`` and ``B[k]`` overlap with positive area?

    Separating-axis test over the six edge normals ``n`` of the pair: the triangles overlap when,
    for every axis, ``min(max_A, max_B) - max(min_A, min_B) > tol`` where ``max_A`` is the largest
    projection ``n . a / |n|`` of a corner of ``A`` (a distance in screen units).  Triangles
    that only touch (overlap ``<= tol`` along some axis) are reported as not overlapping.
    Compiled (:func:`meschers_igl.overlap.sat_overlap`).

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
    A = np.asarray(A, dtype=np.float64)
    k = A.shape[0]
    T = np.ascontiguousarray(np.concatenate((A, np.asarray(B, dtype=np.float64))))
    idx = np.arange(k, dtype=np.int64)
    return _kernels.overlap_pairs_sat(T, np.stack((idx, idx + k), axis=1), float(tol))


def intersection_centroids(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centroid and area of the intersection polygon of each pair of triangles.

    ``A`` is clipped by the three inner half-planes of ``B`` (Sutherland-Hodgman) and the
    shoelace formula gives

    ``area = 1/2 sum p x q``,  ``centroid = sum (p + q) (p x q) / (6 area)``

    over the clipped polygon's edges ``p -> q``.  Clipping is continuous in the corners, so
    edges that nearly coincide (a folded pair, duplicated faces) change the result by about
    their gap, and the centroid is as well-conditioned as the overlap (error about
    ``eps * size^3 / area``).  Being the mean over a convex region inside both triangles, the
    centroid lies in both, and any function linear on each triangle takes at it its mean over
    the overlap.

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
    A = np.asarray(A, dtype=np.float64)
    B = np.asarray(B, dtype=np.float64)
    k = A.shape[0]
    T = np.ascontiguousarray(np.concatenate((A, B)))
    idx = np.arange(k, dtype=np.int64)
    return _kernels.pair_centroids(T, np.stack((idx, idx + k), axis=1))


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
    groups: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray | None]:
    """All pairs of screen triangles that overlap with positive area.

    Broad phase (grid), narrow phase (separating axes) and, on request, the centroid of each
    pair's intersection polygon, in one compiled pass (:func:`meschers_igl.overlap.grid_overlaps`).

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
    groups : (n,) int, optional
        A label per triangle: only pairs with different labels are reported (e.g. front and
        back faces in :meth:`DepthOrder.put_in_front`).

    Returns
    -------
    pairs : (k, 2) int64
        ``(i, j)`` with ``i < j``, sorted lexicographically.
    centroid : (k, 2) float64 or None
    """
    T = np.ascontiguousarray(T, dtype=np.float64)
    if tol is None:
        tol = default_tol(T)
    n = T.shape[0]
    lo, hi, ht = _kernels.boxes_and_heights(T)
    ok = ht > tol
    if faces is not None:
        chosen = np.zeros(n, dtype=bool)
        chosen[np.asarray(faces, dtype=np.int64)] = True
        ok &= chosen
    if n < 2 or np.count_nonzero(ok) < 2:
        return np.zeros((0, 2), dtype=np.int64), (np.zeros((0, 2)) if centroids else None)
    group = (
        np.zeros(0, dtype=np.int64)
        if groups is None
        else np.ascontiguousarray(np.asarray(groups, dtype=np.int64))
    )
    pairs, cen = _kernels.grid_overlaps(
        T, ok, lo, hi, *_grid(lo, hi), float(tol), True, bool(centroids), group
    )
    return pairs, (cen if centroids else None)


def polygon_triangles(P: np.ndarray) -> np.ndarray | None:
    """Triangles of a simple polygon, counter-clockwise, with no new points; None if it is not
    simple.

    A constrained Delaunay triangulation (``triangle``), so consecutive collinear corners make
    no flat triangles as a fan would.  The polygon is checked first (shapely: a valid polygon,
    no repeated corner): given a ring that doubles back on itself or repeats a corner, Triangle
    crashes the process (a segfault, which no ``try`` catches).

    Parameters
    ----------
    P : (n, 2) float
        The corners in order (not closed).

    Returns
    -------
    (n - 2, 3) int64 or None
        Corner indices into ``P``.
    """
    import shapely
    import triangle as tr

    P = np.asarray(P, dtype=np.float64)
    n = P.shape[0]
    if n < 3 or np.unique(P, axis=0).shape[0] != n or not shapely.Polygon(P).is_valid:
        return None
    seg = np.stack([np.arange(n), (np.arange(n) + 1) % n], axis=1)
    out = tr.triangulate({"vertices": P, "segments": seg}, "pQ")
    if out["vertices"].shape[0] != n or "triangles" not in out:
        return None
    T = np.asarray(out["triangles"], dtype=np.int64)
    Q = P[T]
    a2 = (Q[:, 1, 0] - Q[:, 0, 0]) * (Q[:, 2, 1] - Q[:, 0, 1]) - (Q[:, 2, 0] - Q[:, 0, 0]) * (
        Q[:, 1, 1] - Q[:, 0, 1]
    )
    T[a2 < 0] = T[a2 < 0][:, [0, 2, 1]]
    return T
