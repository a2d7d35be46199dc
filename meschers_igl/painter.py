"""What a viewer sees: a point-sampled painter's algorithm over a depth order, without a GPU.

A mescher is drawn back to front in a linear extension of its :class:`~meschers_igl.DepthOrder`
(paper Sec. 4.1). This module samples that picture exactly at pixel centres, in numpy: each pixel
shows the *last* face drawn that contains its centre. It is the oracle the picture tests use
("no back face visible", "isolines lie on the visible surface"): independent of OpenGL, of the
renderer's shading and of anti-aliasing.

A face is a *back face* when its screen triangle is clockwise, i.e. its camera-frame normal has
``n_z <= 0`` (the triangle's normal is ``(a, b, 2 A_xy) / |.|`` with ``A_xy`` the signed screen
area, so the sign of ``n_z`` is the sign of ``A_xy``). A closed figure seen from outside shows
front faces only.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import MescherError
from .validate import as_count

__all__ = ["backface_share", "pixel_grid", "visible_faces"]

# candidate (face, pixel) pairs evaluated per chunk: bounds the memory of one step (~0.5 GB)
_CHUNK = 8_000_000


def pixel_grid(
    xy: np.ndarray, size: int = 256, bounds: Any = None, margin: float = 0.05
) -> tuple[np.ndarray, tuple[float, float, float, float], tuple[int, int]]:
    """Pixel-centre grid over a screen box, with square pixels.

    Parameters
    ----------
    xy : (#V, 2) float64
        Screen positions (used only when ``bounds`` is None).
    size : int, default: 256
        Pixels along the longer side of the box.
    bounds : (xmin, xmax, ymin, ymax), optional
        The image's extent in screen units; default: the box of ``xy`` widened by ``margin``.
    margin : float, default: 0.05
        Relative margin around the box of ``xy``.

    Returns
    -------
    centres : (H, W, 2) float64
        Screen position of each pixel centre; row 0 is the top of the image (largest y).
    bounds : (4,) tuple
    shape : (H, W)
    """
    size = as_count(size, "size", minimum=2)
    if bounds is None:
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        pad = margin * float(max(hi - lo)) or 1.0
        bounds = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
    b = np.asarray(bounds, dtype=np.float64)
    if b.shape != (4,) or not np.all(np.isfinite(b)) or b[1] <= b[0] or b[3] <= b[2]:
        raise MescherError(
            f"bounds: expected (xmin, xmax, ymin, ymax) with xmin < xmax and ymin < ymax, "
            f"found {bounds!r}"
        )
    w_len, h_len = b[1] - b[0], b[3] - b[2]
    px = max(w_len, h_len) / size
    W, H = max(1, round(w_len / px)), max(1, round(h_len / px))
    xs = b[0] + (np.arange(W) + 0.5) * (w_len / W)
    ys = b[3] - (np.arange(H) + 0.5) * (h_len / H)
    centres = np.stack(np.meshgrid(xs, ys), axis=-1)
    return centres, (float(b[0]), float(b[1]), float(b[2]), float(b[3])), (H, W)


def _double_signed_area(T: np.ndarray) -> np.ndarray:
    """(k,) twice the signed area of screen triangles ``T`` (k, 3, 2); > 0 counter-clockwise."""
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    return e1[:, 0] * e2[:, 1] - e2[:, 0] * e1[:, 1]


def _barycentric(t: np.ndarray, p: np.ndarray, area2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric coordinates ``(l1, l2)`` of points ``p`` (k, 2) in triangles ``t`` (k, 3, 2)
    with twice-signed areas ``area2``, by signed sub-areas (exact sign for points off the edges)."""
    e1, e2, q = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0], p - t[:, 0]
    inv = 1.0 / area2
    return (q[:, 0] * e2[:, 1] - q[:, 1] * e2[:, 0]) * inv, (
        e1[:, 0] * q[:, 1] - e1[:, 1] * q[:, 0]
    ) * inv


def _draw_order(m: Any, order: Any) -> np.ndarray:
    n = len(m.F)
    if order is None:
        return np.arange(n, dtype=np.int64)
    if getattr(order, "n_faces", n) != n:
        raise MescherError(
            f"order: expected a DepthOrder over the mescher's {n} faces, found one over "
            f"{order.n_faces}"
        )
    return np.asarray(order.linear_extension(warn=False), dtype=np.int64)


def visible_faces(
    m: Any,
    order: Any = None,
    *,
    size: int = 256,
    bounds: Any = None,
    return_barycentric: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """The face seen at each pixel centre when faces are painted back to front.

    Parameters
    ----------
    m : Mescher
        Anything with ``F`` (#F, 3) and ``xy`` (#V, 2).
    order : DepthOrder, optional
        Faces are painted in ``order.linear_extension()``; default: in index order.
    size : int, default: 256
        Pixels along the longer side of the image.
    bounds : (xmin, xmax, ymin, ymax), optional
        The image's extent in screen units (see :func:`pixel_grid`).
    return_barycentric : bool, default: False
        Also return the barycentric coordinates of each pixel centre in its visible face.

    Returns
    -------
    faces : (H, W) int64
        Index of the visible face, -1 where no face covers the pixel centre.
    bary : (H, W, 3) float64
        Only with ``return_barycentric``: barycentric coordinates (NaN on the background).

    Notes
    -----
    A pixel centre ``p`` lies in triangle ``(a, b, c)`` when its barycentric coordinates are all
    ``>= -1e-12`` (a centre exactly on a shared edge belongs to both faces, and the later one
    wins, as in a rasterizer with a consistent fill rule). Zero-area triangles cover nothing.
    Candidate pixels are enumerated per face over its bounding box, vectorized over faces in
    chunks; the winner per pixel is the face with the largest rank in the draw order
    (``np.maximum.at``), so ties never depend on numpy's write order.
    """
    F = np.asarray(m.F, dtype=np.int64)
    xy = np.asarray(m.xy, dtype=np.float64)
    centres, (x0, x1, y0, y1), (H, W) = pixel_grid(xy, size, bounds)
    rank = np.empty(len(F), dtype=np.int64)
    rank[_draw_order(m, order)] = np.arange(len(F))

    T = xy[F]  # (#F, 3, 2)
    dx, dy = (x1 - x0) / W, (y1 - y0) / H
    # pixel index ranges of each face's bounding box (columns from x, rows from y downward)
    c_lo = np.clip(np.ceil((T[:, :, 0].min(1) - x0) / dx - 0.5), 0, W).astype(np.int64)
    c_hi = np.clip(np.floor((T[:, :, 0].max(1) - x0) / dx - 0.5), -1, W - 1).astype(np.int64)
    r_lo = np.clip(np.ceil((y1 - T[:, :, 1].max(1)) / dy - 0.5), 0, H).astype(np.int64)
    r_hi = np.clip(np.floor((y1 - T[:, :, 1].min(1)) / dy - 0.5), -1, H - 1).astype(np.int64)
    nc = np.maximum(c_hi - c_lo + 1, 0)
    nr = np.maximum(r_hi - r_lo + 1, 0)
    count = nc * nr
    area2 = _double_signed_area(T)
    count[area2 == 0] = 0

    best = np.full(H * W, -1, dtype=np.int64)
    faces_all = np.flatnonzero(count)
    csum = np.cumsum(count[faces_all])
    starts = np.searchsorted(csum, np.arange(0, csum[-1] if len(csum) else 0, _CHUNK), "left")
    bounds_idx = [*starts.tolist(), len(faces_all)]
    for a, b in zip(bounds_idx[:-1], bounds_idx[1:], strict=True):
        fs = faces_all[a:b]
        if len(fs) == 0:
            continue
        k = count[fs]
        f = np.repeat(fs, k)
        local = np.arange(len(f)) - np.repeat(np.cumsum(k) - k, k)
        col = c_lo[f] + local % nc[f]
        row = r_lo[f] + local // nc[f]
        p = centres[row, col]
        l1, l2 = _barycentric(T[f], p, area2[f])
        inside = (l1 >= -1e-12) & (l2 >= -1e-12) & (1.0 - l1 - l2 >= -1e-12)
        np.maximum.at(best, (row * W + col)[inside], rank[f[inside]])

    order_faces = np.argsort(rank)
    faces = np.where(best >= 0, order_faces[np.maximum(best, 0)], -1).reshape(H, W)
    if not return_barycentric:
        return faces
    bary = np.full((H, W, 3), np.nan)
    hit = faces >= 0
    l1, l2 = _barycentric(T[faces[hit]], centres[hit], area2[faces[hit]])
    bary[hit] = np.stack([1.0 - l1 - l2, l1, l2], axis=1)
    return faces, bary


def backface_share(m: Any, order: Any = None, *, size: int = 256, bounds: Any = None) -> float:
    """Share of the figure's pixels that show a back face (``n_z <= 0``).

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional
        The depth order the picture is painted in (see :func:`visible_faces`).
    size : int, default: 256
    bounds : (xmin, xmax, ymin, ymax), optional

    Returns
    -------
    float
        ``#{pixels whose visible face is clockwise on screen} / #{pixels covered}``, 0 for an
        empty picture. A closed surface seen from outside in a correct order gives 0.
    """
    faces = visible_faces(m, order, size=size, bounds=bounds)
    hit = faces >= 0
    if not hit.any():
        return 0.0
    T = np.asarray(m.xy, dtype=np.float64)[np.asarray(m.F)[faces[hit]]]
    return float(np.mean(_double_signed_area(T) <= 0))
