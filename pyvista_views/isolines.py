"""Isolines of a scalar field on the *visible* layer of a mescher.

A mescher overlaps itself on screen, so the contours of a per-vertex field computed on the whole
surface (``igl.isolines`` on the screen positions) include the contours of hidden sheets.  Only
the parts of a contour that lie on a level of the surface the viewer *sees* are kept:

1. the visible face at each pixel comes from the renderer itself
   (:func:`pyvista_views.gl.face_id_image`: the layer drawn once more with face-id colours);
2. each contour segment is cut into pieces of at most ``step`` pixels; a piece is kept when
   the visible face ``g`` at its midpoint ``p`` has the contour's level within ``tol`` pixels:
   ``|u_g(p) - L| <= tol * pixel * |grad u_g|``, with ``u_g`` the field's linear interpolant
   on ``g`` (first-order distance from ``p`` to ``g``'s own level line).

A piece of a hidden sheet's contour is dropped unless the visible surface has the same level
within ``tol`` pixels there (then the two contours coincide on screen anyway), so every line
pixel lies on a level of the visible surface, and lines neither cross nor dangle where a sheet
passes behind another.  The kept segments are the libigl contour's own (shared end points where
nothing was cut), so the lines are as smooth as the piecewise-linear field.
"""

from __future__ import annotations

from collections.abc import Sequence

import igl
import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_count, as_float_array


def levels_of(isolines: int | Sequence[float], clim: Sequence[float]) -> np.ndarray:
    """Contour levels: ``k`` evenly spaced inside ``clim`` (ends excluded), or the given levels.

    Returns
    -------
    (L,) float64
    """
    if isinstance(isolines, (int, np.integer, bool, np.bool_)):
        lo, hi = float(clim[0]), float(clim[1])
        return np.linspace(lo, hi, as_count(isolines, "isolines") + 2)[1:-1]
    return as_float_array(isolines, "isolines", (-1,))


def _face_gradients(xy: np.ndarray, F: np.ndarray, u: np.ndarray, faces: np.ndarray) -> tuple:
    """Screen-space data of the linear interpolant on ``faces``: corner 0, the inverse of the
    edge matrix rows (for barycentrics), values at the corners and the gradient (k, 2)."""
    P = xy[F[faces]]  # (k, 3, 2)
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    det = np.where(det == 0, np.inf, det)  # zero-area faces cover no pixel; never divide by 0
    U = u[F[faces]]
    du1, du2 = U[:, 1] - U[:, 0], U[:, 2] - U[:, 0]
    grad = np.stack(
        [(du1 * e2[:, 1] - du2 * e1[:, 1]) / det, (du2 * e1[:, 0] - du1 * e2[:, 0]) / det], axis=1
    )
    return P[:, 0], U[:, 0], grad


def visible_isolines(
    xy: np.ndarray,
    F: np.ndarray,
    values: np.ndarray,
    levels: np.ndarray,
    face_map: np.ndarray,
    bounds: Sequence[float],
    z: float = 0.0,
    *,
    tol: float = 1.0,
    step: float = 0.5,
) -> pv.PolyData:
    """Contours of ``values`` where they lie on a level of the visible surface (module doc).

    Parameters
    ----------
    xy : (#V, 2) float64
        Screen positions.
    F : (#F, 3) int64
    values : (#V,) float64
        The field, linear on each face.
    levels : (L,) float64
    face_map : (H, W) int64
        Visible face per pixel, -1 on the background (:func:`pyvista_views.gl.face_id_image`,
        or :func:`meschers_igl.painter.visible_faces` with the same grid).
    bounds : (xmin, xmax, ymin, ymax)
        Extent of ``face_map``: pixel (r, c) covers ``x in xmin + [c, c+1] dx``,
        ``y in ymax - [r+1, r] dy``.
    z : float
        Depth given to the lines (in front of the layer they annotate).
    tol, step : float
        Pixels: how far a piece may be from the visible level, and the longest piece tested.

    Returns
    -------
    pyvista.PolyData
        Line segments with ``cell_data["level"]`` (index into ``levels``).
    """
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    F = np.ascontiguousarray(F, dtype=np.int64)
    u = np.ascontiguousarray(values, dtype=np.float64)
    levels = np.ascontiguousarray(levels, dtype=np.float64)
    H, W = face_map.shape
    xmin, xmax, ymin, ymax = (float(b) for b in bounds)
    dx, dy = (xmax - xmin) / W, (ymax - ymin) / H
    if levels.size == 0 or F.shape[0] == 0:
        return pv.PolyData()
    unreached = ~np.isfinite(u)
    F_known = F
    if unreached.any():  # contour only faces whose three values are known
        F_known = F[~unreached[F].any(axis=1)]
        u = np.where(unreached, 0.0, u)
        if F_known.shape[0] == 0:
            return pv.PolyData()
    iV, iE, level = igl.isolines(xy, F_known, u, levels)
    if iE.shape[0] == 0:
        return pv.PolyData()
    a, b = iV[iE[:, 0]], iV[iE[:, 1]]
    # Pieces of at most `step` pixels along each segment (vectorized over all pieces).
    length_px = np.hypot((b[:, 0] - a[:, 0]) / dx, (b[:, 1] - a[:, 1]) / dy)
    n_pieces = np.maximum(np.ceil(length_px / step).astype(np.int64), 1)
    seg = np.repeat(np.arange(iE.shape[0]), n_pieces)
    first = np.cumsum(n_pieces) - n_pieces
    k = np.arange(seg.shape[0]) - first[seg]
    t0 = k / n_pieces[seg]
    t1 = (k + 1) / n_pieces[seg]
    p0 = a[seg] + t0[:, None] * (b[seg] - a[seg])
    p1 = a[seg] + t1[:, None] * (b[seg] - a[seg])
    mid = 0.5 * (p0 + p1)
    col = np.floor((mid[:, 0] - xmin) / dx).astype(np.int64)
    row = np.floor((ymax - mid[:, 1]) / dy).astype(np.int64)
    inside = (col >= 0) & (col < W) & (row >= 0) & (row < H)
    g = np.full(seg.shape[0], -1, dtype=np.int64)
    g[inside] = face_map[row[inside], col[inside]]
    keep = g >= 0
    if keep.any():
        idx = np.flatnonzero(keep)
        faces, inverse = np.unique(g[idx], return_inverse=True)
        c0, u0, grad = _face_gradients(xy, F, u, faces)
        d = mid[idx] - c0[inverse]
        u_visible = u0[inverse] + np.einsum("ij,ij->i", d, grad[inverse])
        slope = np.hypot(grad[inverse, 0] * dx, grad[inverse, 1] * dy)  # value change per pixel
        gap = np.abs(u_visible - levels[level[seg[idx]]])
        scale = np.abs(levels).max() if levels.size else 1.0
        keep[idx] = gap <= tol * slope + 1e-12 * max(scale, 1.0)
    whole = np.bincount(seg[keep], minlength=iE.shape[0]) == n_pieces
    # Whole segments keep libigl's shared end points; cut ones become their kept pieces.
    part = keep & ~whole[seg]
    points = np.concatenate([iV, p0[part], p1[part]])
    n_v, n_part = iV.shape[0], int(part.sum())
    lines = np.concatenate(
        [
            iE[whole],
            np.stack([n_v + np.arange(n_part), n_v + n_part + np.arange(n_part)], axis=1),
        ]
    )
    if lines.shape[0] == 0:
        return pv.PolyData()
    used, remap = np.unique(lines, return_inverse=True)
    P = np.zeros((used.shape[0], 3))
    P[:, :2] = points[used]
    P[:, 2] = z
    cells = np.concatenate([np.full((lines.shape[0], 1), 2), remap.reshape(-1, 2)], axis=1)
    out = pv.PolyData(P, lines=cells.ravel())
    out.cell_data["level"] = np.concatenate([level[whole], level[seg[part]]])
    return out


def check_vertex_field(location: str, name: str = "isolines") -> None:
    """Isolines need a per-vertex field (linear on each face)."""
    if location != "vertex":
        raise MescherError(
            f"{name}: expected per-vertex scalars to contour, found per-face scalars"
        )
