"""Openings: does an impossible loop go around something the figure does not cover?

A person reads a closed chain of bars as a frame around a window: the Penrose tribar's bars
enclose the triangle's opening, the impossible cube's bars its six windows, and whatever shows
through (the background, a floor the figure stands on) is not the figure's own surface.  Blocks
packed together that line up by accident from one view enclose nothing: every point inside a
loop through them is covered by those same blocks, and nobody sees a bar joint there.

:func:`period_around_opening` tells the two apart on the glued visible surface: a loop with a
period that winds around a hole of the surface's screen silhouette (a backdrop taken away).  The winding
number of a closed chain of directed edges around a point is the sum of the angles its edges
subtend there, so it needs no ordering of the loop's edges; around an uncovered point it is
the same for every loop of one homology class (a homotopy on the surface moves the loop only
over points the surface covers).

A staircase built of separate steps may hide its own courtyard behind its far side: its loop
then encloses no uncovered point, but it runs through a ring of at least :data:`RING_PARTS`
parts, where blocks lining up by chance close short loops through two or three.
"""

from __future__ import annotations

import numpy as np

from .. import topology as topo

__all__ = ["RING_PARTS", "opening_points", "period_around_opening", "periods", "winding_numbers"]

#: holes smaller than this fraction of the silhouette's area are slivers between faces
MIN_HOLE_AREA = 1e-5

#: a loop through at least this many separate parts is a ring of them (the fewest flights a
#: Penrose staircase turns through is four)
RING_PARTS = 4


def opening_points(xy: np.ndarray, F: np.ndarray, tol: float) -> np.ndarray:
    """A point inside each hole of the screen silhouette of the triangles ``xy[F]``.

    Parameters
    ----------
    xy : (n, 2) float
        Screen positions.
    F : (m, 3) int
        Triangles.
    tol : float
        Absolute tolerance: triangles are grown by it before their union, so faces meeting
        along an edge up to round-off leave no slit.

    Returns
    -------
    (h, 2) float
        One interior point (shapely's ``representative_point``) per hole larger than
        :data:`MIN_HOLE_AREA` of the silhouette.
    """
    import shapely  # the 2D polygon union: shapely (GEOS), vectorised over the triangles

    T = xy[F]
    polys = shapely.polygons(np.concatenate([T, T[:, :1]], axis=1))
    union = shapely.union_all(shapely.buffer(polys, tol, quad_segs=1))
    pts = []
    for g in getattr(union, "geoms", [union]):  # a few polygons
        for ring in g.interiors:  # a few holes
            hole = shapely.Polygon(ring)
            if hole.area > MIN_HOLE_AREA * union.area:
                pts.append(hole.representative_point().coords[0])
    return np.asarray(pts, dtype=float).reshape(-1, 2)


def winding_numbers(xy: np.ndarray, tail: np.ndarray, head: np.ndarray, pts: np.ndarray):
    """Winding numbers of the closed chain of directed edges ``tail -> head`` around ``pts``.

    ``w(p) = (1 / 2 pi) sum_e angle(xy[tail_e] - p, xy[head_e] - p)``, each angle in
    ``(-pi, pi]``: exact (an integer) for a closed chain and points off it.

    Parameters
    ----------
    xy : (n, 2) float
    tail, head : (k,) int
        The chain's edges, in any order.
    pts : (h, 2) float

    Returns
    -------
    (h,) int
    """
    a = xy[tail][None, :, :] - pts[:, None, :]
    b = xy[head][None, :, :] - pts[:, None, :]
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = (a * b).sum(axis=-1)
    return np.rint(np.arctan2(cross, dot).sum(axis=1) / (2.0 * np.pi)).astype(np.int64)


def periods(F: np.ndarray, xy: np.ndarray, Z: np.ndarray) -> tuple[list, np.ndarray, np.ndarray]:
    """The homology loops of the glued surface ``F`` and the depth each gains.

    What :meth:`meschers_igl.Mescher.from_corner_depths` and its ``periods()`` give, from the
    topology module directly: obtaining sits below the mescher class (which imports it), and
    the glued depths agree along every glued edge, so the edges' averages need no projection.

    Parameters
    ----------
    F : (#F, 3) int
    xy : (#V, 2) float
    Z : (#F, 3) float
        Each face's corner depths.

    Returns
    -------
    loops : list of ``(edges (k,) int, signs (k,) float)`` over ``edges``
    periods : (len(loops),) float
    edges : (#E, 2) int
    """
    edges, face_edges, signs = topo.edge_topology(F, xy.shape[0])
    h = Z[:, [2, 0, 1]] - Z[:, [1, 2, 0]]  # half-edge opposite corner i runs i+1 -> i+2
    fe = face_edges.reshape(-1)
    zeta = np.bincount(fe, weights=(h * signs).reshape(-1), minlength=edges.shape[0])
    zeta /= np.maximum(np.bincount(fe, minlength=edges.shape[0]), 1)
    loops = topo.generator_loops(edges, face_edges, xy.shape[0])
    return loops, np.array([float(zeta[e] @ s) for e, s in loops]), edges


def period_around_opening(
    F: np.ndarray,
    xy: np.ndarray,
    Z: np.ndarray,
    tol: float,
    period_tol: float,
    part: np.ndarray | None = None,
    ring: int | None = None,
) -> bool | None:
    """Does some homology loop of the glued surface with a period wind around an opening?

    The openings are the holes of the screen silhouette of the whole surface (a block in front
    of a ring of blocks covers its hole: no opening is seen there); with ``part``, also those
    left when a backdrop is taken away: a part of the 3D model whose screen box holds all the
    rest (a floor the figure stands on, a wall behind it) shows through an opening of the
    figure, glued to it where they touch, but is none of the figure's own surface.

    Parameters
    ----------
    F : (#F, 3) int
        The glued visible surface.
    xy : (#V, 2) float
    Z : (#F, 3) float
        Each face's corner depths.
    tol : float
        Absolute screen tolerance (see :func:`opening_points`).
    period_tol : float
        Periods of at most this size are round-off.
    part : (#F,) int, optional
        The 3D model part each face shows (``-1``: a face of no part, e.g. a band added
        between parts).
    ring : int, optional
        With ``part``: a loop with a period through faces of at least this many parts counts
        as well, opening or not -- a ring of separate steps climbing round a courtyard that
        its own far side hides from this view (Penrose stairs of columns); blocks lining up by
        chance close short loops through two or three.

    Returns
    -------
    bool or None
        False when every loop with a period encloses only the figure's own surface; None when
        the surface has no period.
    """
    loops, gained, edges = periods(F, xy, Z)
    if not np.any(np.abs(gained) > period_tol):
        return None
    if ring is not None and part is not None:
        face_edges = topo.edge_topology(F, xy.shape[0])[1]
        for (eidx, _), p in zip(loops, gained):  # a few loops
            on = np.isin(face_edges, eidx).any(axis=1)
            if abs(p) > period_tol and np.unique(part[on & (part >= 0)]).size >= ring:
                return True
    pts = opening_points(xy, F, tol)
    if part is not None:
        back = _backdrop(xy, F, np.asarray(part), tol)
        if back.any():
            pts = np.vstack([pts, opening_points(xy, F[~back], tol)])
    if pts.size == 0:
        return False
    for (eidx, sign), p in zip(loops, gained):  # a few loops
        if abs(p) <= period_tol:
            continue
        tail = np.where(sign > 0, edges[eidx, 0], edges[eidx, 1])
        head = np.where(sign > 0, edges[eidx, 1], edges[eidx, 0])
        if np.any(winding_numbers(xy, tail, head, pts) != 0):
            return True
    return False


def _backdrop(xy: np.ndarray, F: np.ndarray, part: np.ndarray, tol: float) -> np.ndarray:
    """Which faces belong to a backdrop: a part whose screen box holds the box of every other
    face (``part`` ``-1`` is no part).  Returns a (#F,) bool mask."""
    lo, hi = xy[F].min(axis=1), xy[F].max(axis=1)
    mask = np.zeros(F.shape[0], dtype=bool)
    for p in np.unique(part[part >= 0]):  # the component's parts (a few)
        own = part == p
        if own.all():
            continue
        rest_lo, rest_hi = lo[~own].min(axis=0), hi[~own].max(axis=0)
        if np.all(lo[own].min(axis=0) <= rest_lo + tol) and np.all(
            hi[own].max(axis=0) >= rest_hi - tol
        ):
            mask |= own
    return mask
