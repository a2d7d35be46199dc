"""How well a line drawing matches the painter's picture, pixel by pixel: the oracle of
:mod:`meschers_igl.lines`.

The painter's picture (:func:`meschers_igl.painter.visible_faces`) changes from one piece of
surface to another along its *line pixels* (:func:`visible_face_edges`: neighbouring pixels
whose faces are not one smooth sheet between them, found by walking the mesh between the two
pixel centres); :func:`line_agreement` gives the recall and precision of a drawing against
them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .line_folds import seam_partners
from .lines import LineDrawing, _dihedral, _double_area, _ranges
from .topology import edge_faces
from .validate import as_positive

__all__ = ["line_agreement", "visible_face_edges"]


def visible_face_edges(
    faces: np.ndarray,
    m: Any,
    bounds: Any,
    *,
    crease_angle: float = 30.0,
    max_steps: int = 64,
) -> np.ndarray:
    """Pixels where a visible-face map changes from one piece of surface to another: the line
    pixels a correct line drawing must pass next to.

    Two 4-neighbouring pixels showing faces ``f != g`` (or one showing the background) are a
    line pair unless the surface is one smooth sheet between them: walking on the mesh from
    ``f`` along the screen segment between the two pixel centres, face to face across the
    edges the segment crosses, reaches ``g`` at the second centre without crossing a line edge
    (a boundary, a crease, or an edge between a front- and a back-facing face).  The walk
    makes the test exact whatever the faces' size (a Loop-subdivided crease is a band of
    faces narrower than a pixel).  Both pixels of a line pair are marked.

    Parameters
    ----------
    faces : (H, W) int64
        Visible face per pixel, -1 for background (:func:`meschers_igl.painter.visible_faces`
        with the same ``bounds``, or a renderer's face-id image).
    m : Mescher
    bounds : (xmin, xmax, ymin, ymax)
        The image's extent in screen units (pixel centres as in
        :func:`meschers_igl.painter.pixel_grid`).
    crease_angle : float, default: 30
    max_steps : int, default: 64
        Faces crossed at most between two pixel centres; a walk that has not arrived by then
        counts as a line.

    Returns
    -------
    (H, W) bool
    """
    F = np.asarray(m.F)
    xy = np.asarray(m.xy, dtype=np.float64)
    fe = np.asarray(m.face_edges)
    ef = edge_faces(fe, m.n_edges)
    crease_angle = as_positive(crease_angle, "crease_angle", allow_zero=True)
    _, crease = _dihedral(m, ef, crease_angle)
    area2 = _double_area(xy[F])
    front = area2 > 0
    inner = ef[:, 1] >= 0
    smooth = inner & ~crease
    smooth[inner] &= front[ef[inner, 0]] == front[ef[inner, 1]]
    partner = seam_partners(m, ef, area2, crease_angle)
    smooth |= partner >= 0  # a seam across a face seen edge-on: the walk goes on to the partner
    H, W = faces.shape
    x0, x1, y0, y1 = (float(b) for b in bounds)
    dx, dy = (x1 - x0) / W, (y1 - y0) / H
    out = np.zeros(faces.shape, dtype=bool)
    for di, dj in ((0, 1), (1, 0)):
        f = faces[: H - di, : W - dj]
        g = faces[di:, dj:]
        diff = f != g
        line = diff & ((f < 0) | (g < 0))
        r, c = np.nonzero(diff & (f >= 0) & (g >= 0))
        if len(r):
            P = np.stack([x0 + (c + 0.5) * dx, y1 - (r + 0.5) * dy], axis=1)
            Q = P + np.array([dj * dx, -di * dy])
            same = _walk_to(
                f[r, c], g[r, c], P, Q, F, xy, fe, ef, smooth, partner, area2, max_steps
            )
            line[r, c] = ~same
        out[: H - di, : W - dj] |= line
        out[di:, dj:] |= line
    return out


def _walk_to(f, g, P, Q, F, xy, fe, ef, smooth, partner, area2, max_steps) -> np.ndarray:
    """For each pair, does the walk from face ``f`` at ``P`` toward ``Q`` across smooth edges
    end in face ``g``?"""
    n = len(f)
    cur = f.copy()
    result = np.zeros(n, dtype=bool)
    active = np.ones(n, dtype=bool)
    d = Q - P
    for _ in range(max_steps):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        fc = cur[idx]
        arrived = fc == g[idx]
        result[idx[arrived]] = True
        active[idx[arrived]] = False
        idx, fc = idx[~arrived], fc[~arrived]
        if idx.size == 0:
            break
        T = xy[F[fc]]
        a2 = area2[fc]
        # barycentric coordinate of corner i along P + t d: l_i(t) = alpha_i + beta_i t; the
        # segment leaves through the edge opposite the corner whose coordinate reaches 0 last
        # before... first, with beta < 0
        t_exit = np.full((len(idx), 3), np.inf)
        for i in range(3):
            v, w = T[:, (i + 1) % 3], T[:, (i + 2) % 3]
            e = w - v
            alpha = (e[:, 0] * (P[idx, 1] - v[:, 1]) - e[:, 1] * (P[idx, 0] - v[:, 0])) / a2
            beta = (e[:, 0] * d[idx, 1] - e[:, 1] * d[idx, 0]) / a2
            with np.errstate(divide="ignore", invalid="ignore"):
                t = -alpha / beta
            t_exit[:, i] = np.where(beta < 0, t, np.inf)
        k = np.argmin(t_exit, axis=1)
        t = t_exit[np.arange(len(idx)), k]
        stays = ~(t < 1.0)  # Q is in this face, and it is not g: another sheet is seen at Q
        active[idx[stays]] = False
        idx, fc, k = idx[~stays], fc[~stays], k[~stays]
        e = fe[fc, k]
        cross_ok = smooth[e]
        active[idx[~cross_ok]] = False
        idx, fc, e = idx[cross_ok], fc[cross_ok], e[cross_ok]
        nxt = np.where(ef[e, 0] == fc, ef[e, 1], ef[e, 0])
        cur[idx] = np.where((area2[nxt] == 0) & (partner[e] >= 0), partner[e], nxt)
    return result


def line_agreement(
    lines: LineDrawing,
    m: Any,
    order: Any = None,
    *,
    size: int = 512,
    bounds: Any = None,
    tol: float = 1.5,
    crease_angle: float = 30.0,
) -> tuple[float, float]:
    """Recall and precision of a line drawing against the painter's picture, in pixels.

    The picture is :func:`meschers_igl.painter.visible_faces` at ``size``; its line pixels are
    :func:`visible_face_edges`; the drawing's pixels are those its visible polylines pass
    through (sampled every 0.2 pixel).  Recall: the share of line pixels within ``tol`` pixels
    of a drawn pixel; precision: the share of drawn pixels within ``tol`` of a line pixel.

    Returns
    -------
    (recall, precision) : (float, float)
        1.0 where there is nothing to find.
    """
    from scipy import ndimage

    from .painter import pixel_grid, visible_faces

    faces = visible_faces(m, order, size=size, bounds=bounds)
    _, b, (H, W) = pixel_grid(np.asarray(m.xy), size, bounds)
    gt = visible_face_edges(faces, m, b, crease_angle=crease_angle)
    S = lines.segments()
    drawn = np.zeros((H, W), dtype=bool)
    if len(S):
        px = (b[1] - b[0]) / W
        n = np.maximum(np.ceil(np.linalg.norm(S[:, 1] - S[:, 0], axis=1) / (0.2 * px)), 1)
        n = n.astype(np.int64)
        t = (_ranges(n + 1) / np.repeat(n, n + 1))[:, None]
        s = np.repeat(np.arange(len(S)), n + 1)
        P = S[s, 0] + t * (S[s, 1] - S[s, 0])
        col = np.clip(((P[:, 0] - b[0]) / px).astype(np.int64), 0, W - 1)
        row = np.clip(((b[3] - P[:, 1]) / ((b[3] - b[2]) / H)).astype(np.int64), 0, H - 1)
        drawn[row, col] = True
    recall = float(np.mean(ndimage.distance_transform_edt(~drawn)[gt] <= tol)) if gt.any() else 1.0
    precision = (
        float(np.mean(ndimage.distance_transform_edt(~gt)[drawn] <= tol)) if drawn.any() else 1.0
    )
    return recall, precision
