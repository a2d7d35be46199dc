"""Watertight surfaces of unions of axis-aligned boxes, the building block of the gallery.

Classic impossible figures are made of square bars and cubes.  Their union is a polycube on a
rectilinear grid whose lines pass through every box face; its boundary is extracted in one
vectorised pass (faces between a filled and an empty cell), so refining the grid (``h``) refines
the mesh without changing the shape.  Written by hand because neither libigl nor numpy has a
rectilinear-grid boundary extractor that keeps exact box corners (marching cubes would bevel
them).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import MescherError

Box = tuple[Sequence[float], Sequence[float]]


def _axis_nodes(breaks: np.ndarray, h: float) -> np.ndarray:
    """Grid coordinates: each interval between breakpoints split into ``ceil(len / h)`` parts."""
    breaks = np.unique(np.round(breaks, 12))
    lengths = np.diff(breaks)
    counts = np.maximum(1, np.ceil(lengths / h - 1e-9).astype(np.int64))
    # one linspace per interval (few dozen intervals at most)
    parts = [
        np.linspace(a, b, c, endpoint=False) for a, b, c in zip(breaks[:-1], breaks[1:], counts)
    ]
    return np.concatenate([*parts, breaks[-1:]])


def box_union_surface(
    boxes: Sequence[Box],
    h: float,
    cuts: Sequence[tuple[int, float, Sequence[float], Sequence[float]]] = (),
    splits: Sequence[tuple[int, float, Sequence[float], Sequence[float]]] = (),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangulated outward-oriented boundary of a union of boxes.

    Parameters
    ----------
    boxes : sequence of (lo (3,), hi (3,))
        Axis-aligned boxes; their union must be a manifold solid (no two cells touching along an
        edge only).
    h : float
        Largest grid spacing; every box face lies on grid lines whatever ``h``.
    cuts : sequence of (axis, value, lo (2,), hi (2,))
        Rectangles on the plane ``x[axis] == value`` (``lo``/``hi`` bound the two other
        coordinates, in increasing axis order) whose boundary faces are removed: the open ends
        of a cut model.
    splits : sequence of (axis, value, lo (2,), hi (2,))
        Rectangles *inside* the solid where the surface is cut open: the vertices on the
        rectangle are duplicated for the faces on the ``+axis`` side, so the solid's surface
        gets two boundary loops there (no faces are added).

    Returns
    -------
    V : (#V, 3) float64
    F : (#F, 3) int64
        Outward-oriented triangles (two per grid quad).
    side : (#V,) int64
        ``k + 1`` for duplicated vertices of split ``k`` (the ``+axis`` copy), else 0.
    """
    if h <= 0:
        raise MescherError(f"h: expected a positive grid spacing, found {h}")
    lo = np.array([b[0] for b in boxes], dtype=float)
    hi = np.array([b[1] for b in boxes], dtype=float)
    if np.any(hi <= lo):
        raise MescherError("boxes: expected lo < hi in every coordinate, found an empty box")
    extra = [[] for _ in range(3)]
    for axis, value, rlo, rhi in (*cuts, *splits):
        extra[axis].append(value)
        others = [a for a in range(3) if a != axis]
        for k, a in enumerate(others):
            extra[a] += [rlo[k], rhi[k]]
    nodes = [_axis_nodes(np.concatenate([lo[:, a], hi[:, a], extra[a]]), h) for a in range(3)]
    centers = [0.5 * (g[1:] + g[:-1]) for g in nodes]
    shape = tuple(c.size for c in centers)
    occ = np.zeros(shape, dtype=bool)
    for bl, bh in zip(lo, hi):  # a handful of boxes
        inside = [(c > bl[a]) & (c < bh[a]) for a, c in enumerate(centers)]
        occ |= inside[0][:, None, None] & inside[1][None, :, None] & inside[2][None, None, :]
    nshape = tuple(g.size for g in nodes)
    node_id = np.arange(np.prod(nshape)).reshape(nshape)

    quads = []
    centers_q = []
    for a in range(3):
        b, c = (a + 1) % 3, (a + 2) % 3
        pad = [(0, 0)] * 3
        pad[a] = (1, 1)
        o = np.pad(occ, pad)
        lo_cell = np.take(o, np.arange(o.shape[a] - 1), axis=a)
        hi_cell = np.take(o, np.arange(1, o.shape[a]), axis=a)
        for normal_sign, mask in ((1, lo_cell & ~hi_cell), (-1, ~lo_cell & hi_cell)):
            idx = np.argwhere(mask)  # (k, 3) cell-face index: plane index along a, cells in b, c
            if idx.size == 0:
                continue
            corners = []
            for db, dc in ((0, 0), (1, 0), (1, 1), (0, 1)):  # counter-clockwise around +a
                n = idx.copy()
                n[:, b] += db
                n[:, c] += dc
                corners.append(node_id[n[:, 0], n[:, 1], n[:, 2]])
            q = np.stack(corners, axis=1)
            quads.append(q if normal_sign > 0 else q[:, ::-1])
            ctr = np.empty((idx.shape[0], 3))
            ctr[:, a] = nodes[a][idx[:, a]]
            ctr[:, b] = centers[b][idx[:, b]]
            ctr[:, c] = centers[c][idx[:, c]]
            centers_q.append(ctr)
    Q = np.concatenate(quads)
    C = np.concatenate(centers_q)
    keep = np.ones(Q.shape[0], dtype=bool)
    for axis, value, rlo, rhi in cuts:
        others = [x for x in range(3) if x != axis]
        on = np.isclose(C[:, axis], value, atol=1e-9 * (1 + abs(value)))
        for k, x in enumerate(others):
            on &= (C[:, x] > rlo[k]) & (C[:, x] < rhi[k])
        keep &= ~on
    Q = Q[keep]
    C = C[keep]
    grid = np.stack(np.meshgrid(*nodes, indexing="ij"), axis=-1).reshape(-1, 3)
    side = np.zeros(grid.shape[0], dtype=np.int64)
    for k, (axis, value, rlo, rhi) in enumerate(splits):
        others = [x for x in range(3) if x != axis]
        P = grid[Q]  # (#Q, 4, 3)
        on = np.isclose(P[..., axis], value, atol=1e-9 * (1 + abs(value)))
        for j, x in enumerate(others):
            on &= (P[..., x] >= rlo[j] - 1e-12) & (P[..., x] <= rhi[j] + 1e-12)
        plus = C[:, axis] > value
        sel = on & plus[:, None]
        old = np.unique(Q[sel])
        new = grid.shape[0] + np.arange(old.size)
        remap = np.arange(grid.shape[0] + old.size)
        remap[old] = new
        Q = np.where(sel, remap[Q], Q)
        grid = np.concatenate([grid, grid[old]])
        side = np.concatenate([side, np.full(old.size, k + 1)])
    T = np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])
    used, F = np.unique(T, return_inverse=True)
    return grid[used], F.reshape(-1, 3).astype(np.int64), side[used]


def slant_cut(
    V: np.ndarray,
    axis: int,
    value: float,
    lo: Sequence[float],
    hi: Sequence[float],
    side: int,
    length: float,
    view: Sequence[float],
    region: tuple[Sequence[float], Sequence[float]] | None = None,
) -> np.ndarray:
    """Tilt the open end of a bar so that the cut plane contains the view direction.

    An axis-aligned cut through a bar that runs toward the viewer opens toward the camera: the
    inside of the bar shows through it (a visible back face). Cut models made by artists (and by
    ParadoxToolkit) cut bars in a plane that *contains* the view direction, so the cut is seen
    edge-on and covers nothing. This slides the bar's vertices along ``axis`` so that the open
    end at ``x[axis] == value`` lands on the plane ``x[axis] - value = g . (x_o - c)`` (``x_o``
    the two other coordinates, ``c`` the centre of the rectangle ``lo``..``hi``), with ``g`` the
    smallest slope whose plane contains ``view``: ``view[axis] = g . view_o``. The shift fades
    linearly to 0 at ``length`` from the cut into the bar (on the ``side`` of the cut), so the
    bar's walls stay in their planes and nothing else moves. Two ends that are translates of
    each other along ``view`` stay translates.

    Parameters
    ----------
    V : (#V, 3) float64
    axis : int
        The bar's axis (0, 1, 2).
    value : float
        Plane of the open end.
    lo, hi : (2,) float
        The open end's rectangle in the other two coordinates (increasing axis order).
    side : {+1, -1}
        The bar lies on ``x[axis] > value`` (+1) or ``x[axis] < value`` (-1).
    length : float
        Length of bar over which the tilt fades out; must exceed the largest shift.
    view : (3,) float
        Direction toward the camera.
    region : ((2,), (2,)), optional
        The bar's whole cross-section (default ``lo``, ``hi``), when the open end covers only
        part of it (a step's opening below its riser): the rest of the bar's end face moves
        onto the same plane, so it is seen edge-on too.

    Returns
    -------
    V : (#V, 3) float64
        A moved copy.
    """
    others = [a for a in range(3) if a != axis]
    v = np.asarray(view, dtype=float)
    g = v[axis] * v[others] / float(v[others] @ v[others])
    lo_, hi_ = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    centre = 0.5 * (lo_ + hi_)
    shift_max = float(np.abs(g) @ (0.5 * (hi_ - lo_)))
    if not shift_max < length:
        raise MescherError(
            f"length: expected more than the largest shift {shift_max:.4g} of the slanted cut, "
            f"found {length:.4g}"
        )
    eps = 1e-9 * (1.0 + float(np.abs(V).max()))
    x = V[:, axis]
    t = side * (x - value)  # distance into the bar
    o = V[:, others]
    r_lo, r_hi = (lo_, hi_) if region is None else map(np.asarray, region)
    inside = (t >= -eps) & (t <= length + eps) & np.all((o >= r_lo - eps) & (o <= r_hi + eps), 1)
    w = np.clip(1.0 - t / length, 0.0, 1.0)
    out = V.copy()
    out[inside, axis] += (w * ((o - centre) @ g))[inside]
    return out
