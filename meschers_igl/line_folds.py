"""Which faces decide what is drawn over an interpolated occluding contour.

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
"""

from __future__ import annotations

import numpy as np

from .face_grid import ranges as _ranges

__all__ = ["NEAR_BASE", "crossed", "fold_ranks", "is_near", "triangles_overlap"]

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
