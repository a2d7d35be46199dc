"""Perceived right angles (``perceive="manhattan"``): what a person reads in a box-like drawing.

Sheared tricks (a closed torus that looks like a Penrose triangle) and reliefs (Reutersvärd's
cubes in bas-relief) look impossible only because a person assumes right angles.  A person reads
an axonometric drawing from the screen directions of its three edge families; so do we:

1. The **crease edges** (adjacent faces not coplanar) vote with their screen length for their
   screen direction (mod 180 degrees); the three strongest directions ``d_1, d_2, d_3`` are the
   projected axes.  Depth shears along the view do not change screen directions, so this reads
   the frame a person perceives, not the model's true one.
2. The **orthogonal frame** with those screen directions: its axes are ``e_i = (l_i d_i, w_i)``
   with ``[l_1 d_1, l_2 d_2, l_3 d_3]`` the first two rows of a rotation, i.e.
   ``sum_i l_i^2 d_i d_i^T = I_2`` -- three linear equations in ``l_i^2`` -- and
   ``w_i = +-sqrt(1 - l_i^2)`` with signs making the axes orthogonal (the classical solution of
   the axonometric drawing).
3. Each face's normal is **snapped** to the nearest axis (``|n . e_k|`` largest, within
   :data:`MAX_SNAP`), and its depths re-made on the snapped plane ``z = a x + b y``,
   ``(a, b) = -(e_x, e_y) / e_z``; the caller projects onto locally integrable forms (paper
   Eq. 3-4, ``Mescher.from_corner_depths``).  Where the snapped normals do not integrate, the
   result is impossible.

Reliefs.  A carved or printed relief that reads as an impossible box figure cannot have its
faces in exactly three families of parallel planes: on a connected surface glued along edges of
the three screen directions ``d_k``, per-family gradients ``g_k`` must satisfy ``(g_i - g_j) .
d_k^perp = 0``, which leaves ``g_k = t G_k + g`` (``G_k`` the right-angled ones, ``g`` a tilt),
and the loop integral is ``t`` times the perceived climb -- zero only for a flat relief.  So
the carver shears the blocks a little each (the faces are *near* three families) and the edge
reading above, not the normals, decides which axis each face is snapped to.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import MescherError

__all__ = ["model_face_axes", "perceived_frame", "perceive_manhattan", "snap_to_manhattan"]

#: Faces farther than this from every perceived axis keep their own normal (radians).
MAX_SNAP = np.radians(40.0)
#: Adjacent faces whose normals differ by less than this share a plane (not a crease).
CREASE = np.radians(1.0)
#: A face whose unit normal's z component is at most this does not face the viewer (a wall
#: seen edge-on, a back face).
FACING = 1e-6


def _normals(xy: np.ndarray, F: np.ndarray, Z: np.ndarray) -> np.ndarray:
    P = np.concatenate([xy[F], Z[:, :, None]], axis=2)
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    # a zero-area face (a sliver of a clipped soup) keeps a zero normal rather than NaN
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def _crease_directions(xy, F, n):
    """Screen angles (mod pi) and lengths of crease and boundary edges."""
    he = np.stack([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]], axis=1).reshape(-1, 2)
    key = np.minimum(he[:, 0], he[:, 1]) * xy.shape[0] + np.maximum(he[:, 0], he[:, 1])
    order = np.argsort(key, kind="stable")
    ks = key[order]
    first = np.r_[True, ks[1:] != ks[:-1]]
    last = np.r_[ks[1:] != ks[:-1], True]
    single = order[first & last]
    pair = np.flatnonzero(~last)  # positions of the first of two equal keys
    h1, h2 = order[pair], order[pair + 1]
    cosang = np.einsum("ij,ij->i", n[h1 // 3], n[h2 // 3])
    crease = np.r_[h1[cosang < np.cos(CREASE)], single]
    d = xy[he[crease, 1]] - xy[he[crease, 0]]
    L = np.linalg.norm(d, axis=1)
    theta = np.mod(np.arctan2(d[:, 1], d[:, 0]), np.pi)
    return theta[L > 0], L[L > 0]


def perceived_frame(xy: Any, F: Any, Z: Any) -> np.ndarray:
    """(3, 3) perceived orthogonal axes (rows, camera frame) of a box-like drawing.

    Parameters
    ----------
    xy : (#V, 2) float
    F : (#F, 3) int
    Z : (#F, 3) float
        Per-face corner depths (any per-face offset).

    Raises
    ------
    MescherError
        When the crease directions do not form an axonometric drawing of three orthogonal
        axes (fewer than three edge families, or no real solution).
    """
    xy, F, Z = np.asarray(xy, float), np.asarray(F, np.int64), np.asarray(Z, float)
    n = _normals(xy, F, Z)
    theta, L = _crease_directions(xy, F, n)
    if theta.size < 3:
        raise MescherError("F: expected crease edges in three directions, found fewer than 3")
    # histogram of directions (0.1 degree bins, circular), three strongest separated peaks
    nb = 1800
    b = np.minimum((theta / np.pi * nb).astype(np.int64), nb - 1)
    h = np.bincount(b, weights=L, minlength=nb)
    hs = h + np.roll(h, 1) + np.roll(h, -1)
    peaks = []
    for k in np.argsort(-hs).tolist():  # strongest bins first, few needed
        if hs[k] <= 0:
            break
        if all(min(abs(k - p), nb - abs(k - p)) > 100 for p in peaks):  # 10 degrees apart
            peaks.append(k)
        if len(peaks) == 3:
            break
    if len(peaks) < 3:
        raise MescherError(
            "F: expected crease edges in three screen directions (a box-like drawing), found "
            f"{len(peaks)}"
        )
    D = []
    for p in peaks:  # refine each direction as the weighted mean within 1 degree (doubled angles)
        dd = np.abs(((theta - (p + 0.5) * np.pi / nb) + np.pi / 2) % np.pi - np.pi / 2)
        sel = dd < np.radians(1.0)
        a = np.angle(np.sum(L[sel] * np.exp(2j * theta[sel]))) / 2
        D.append([np.cos(a), np.sin(a)])
    D = np.asarray(D)
    # sum_i l_i^2 d_i d_i^T = I_2: three linear equations in l_i^2
    A = np.stack([D[:, 0] ** 2, D[:, 0] * D[:, 1], D[:, 1] ** 2])
    l2 = np.linalg.solve(A, np.array([1.0, 0.0, 1.0]))
    if np.any(l2 <= 0) or np.any(l2 >= 1):
        raise MescherError(
            "F: expected edge directions of an axonometric drawing of three orthogonal axes, "
            f"found directions {np.degrees(np.arctan2(D[:, 1], D[:, 0])).round(3).tolist()} "
            "with no orthogonal frame"
        )
    ell, w = np.sqrt(l2), np.sqrt(1 - l2)
    E = np.column_stack([ell[:, None] * D, w])
    # signs of w so that the axes are orthogonal: e_i . e_j = 0
    s = np.ones(3)
    for j in (1, 2):
        s[j] = -np.sign((E[0, :2] @ E[j, :2]) / (w[0] * w[j]))
    E[:, 2] *= s
    return E


def _axis_from_edges(xy, F, n, E, adjacent_only: bool = False, hidden=None) -> np.ndarray:
    """(#F,) the perceived normal axis of each face, read from its plane's outline.

    Faces with equal normals form a plane region; the region's outline (half-edges whose
    partner lies in another region or nowhere -- not the diagonals inside it) runs along the
    two families spanning the face, so its perceived normal is the family with the least
    outline length, whatever the true (e.g. sheared) normal is.  ``hidden(he, twin)`` (optional)
    marks half-edges to leave out of the outline: where something in front cuts the face."""
    import scipy.sparse as sp
    import scipy.sparse.csgraph as csgraph
    from scipy.spatial import cKDTree

    D = E[:, :2] / np.linalg.norm(E[:, :2], axis=1, keepdims=True)
    # equal normals within 1e-6 (clustered, not rounded: rounding splits near-equal ones)
    nf = n.shape[0]
    he = np.stack([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]], axis=1).reshape(-1, 2)
    if adjacent_only:
        # polygons: faces joined across shared edges when their normals agree
        nv0 = np.int64(xy.shape[0])
        k1 = np.minimum(he[:, 0], he[:, 1]) * nv0 + np.maximum(he[:, 0], he[:, 1])
        o = np.argsort(k1, kind="stable")
        same = np.flatnonzero(k1[o][1:] == k1[o][:-1])
        fa, fb = o[same] // 3, o[same + 1] // 3
        keep = np.linalg.norm(n[fa] - n[fb], axis=1) <= 1e-6
        pairs = np.stack([fa[keep], fb[keep]], axis=1)
    else:
        pairs = cKDTree(n).query_pairs(1e-6, output_type="ndarray")
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(nf, nf))
    _, grp = csgraph.connected_components(A, directed=False)
    he = np.stack([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]], axis=1).reshape(-1, 2)
    g_he = np.repeat(grp, 3)
    nv = np.int64(xy.shape[0])
    fwd = he[:, 0] * nv + he[:, 1]
    rev = he[:, 1] * nv + he[:, 0]
    srt = np.argsort(fwd)
    pos = np.searchsorted(fwd[srt], rev)
    pos = np.minimum(pos, fwd.size - 1)
    twin = np.where(fwd[srt][pos] == rev, srt[pos], -1)
    outline = (twin < 0) | (g_he[np.maximum(twin, 0)] != g_he)
    if hidden is not None:  # occlusion edges say nothing about the face's own sides
        outline &= ~hidden(he, twin)
    d = xy[he[:, 1]] - xy[he[:, 0]]
    L = np.linalg.norm(d, axis=1)
    sin = np.abs(d[:, 0, None] * D[:, 1] - d[:, 1, None] * D[:, 0]) / np.maximum(L, 1e-300)[:, None]
    fam = (sin < np.sin(np.radians(0.5))) & outline[:, None]
    G = grp.max() + 1
    length = np.stack([np.bincount(g_he, weights=L * fam[:, i], minlength=G) for i in range(3)], 1)
    decided = np.sort(length, axis=1)[:, 1] > 0  # at least two families on the outline
    axis = np.where(decided, np.argmin(length, axis=1), -1)
    return axis[grp]


def model_face_axes(C: Any, F: Any, E: Any) -> np.ndarray:
    """(#F,) perceived normal axis of each face of a 3D model (camera frame ``C``), read from
    the outline of the model polygon it belongs to (adjacent coplanar faces), -1 if undecided.

    The model's own polygons (a sheared box face is still a parallelogram whose sides run along
    two edge families) are free of the clipping lines of the visible map.  Not quite in a model
    made by Boolean union (a relief whose blocks are extruded to a flat back): a block's wall,
    running from its silhouette back through the face of a block behind it, cuts that face in
    3D, along a direction that need not be one of the face's two sides.  Such an edge -- the
    face meets a face that does not face the viewer (a wall or a back face) rising in front of
    its plane (a concave edge) -- is where an occluder stands on the face, and is left out of
    the outline, as a person discounts an occluding contour.

    Parameters
    ----------
    C : (#V, 3) float
        Model vertices in the camera frame (z toward the viewer).
    F : (#F, 3) int
        Triangles, oriented outward.
    E : (3, 3) float
        The perceived frame (:func:`perceived_frame`).

    Returns
    -------
    (#F,) int64 in {-1, 0, 1, 2}
    """
    C, F, E = np.asarray(C, float), np.asarray(F, np.int64), np.asarray(E, float)
    T = C[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    scale = float(np.ptp(C, axis=0).max()) if C.size else 1.0

    def hidden(he, twin):
        f, g, has = np.arange(he.shape[0]) // 3, np.maximum(twin, 0) // 3, twin >= 0
        # the twin face's corner off the shared edge (the twin's corner opposite its
        # half-edge), measured from the face's plane; no twin: the edge's own tail (no rise)
        off = np.where(has, F[g, np.maximum(twin, 0) % 3], he[:, 0])
        rise = np.einsum("ij,ij->i", C[off] - C[he[:, 0]], n[f])
        return has & (n[f, 2] > FACING) & (n[g, 2] <= FACING) & (rise > 1e-9 * scale)

    return _axis_from_edges(C[:, :2], F, n, E, adjacent_only=True, hidden=hidden)


def perceive_manhattan(
    xy: Any, F: Any, Z: Any, axis: Any = None, E: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """Corner depths on the planes of snapped normals, and how far each face was snapped.

    Parameters
    ----------
    xy : (#V, 2), F : (#F, 3), Z : (#F, 3)
        A mescher's screen positions, faces and per-face corner depths.
    axis : (#F,) int, optional
        Perceived normal axis per face (e.g. from :func:`model_face_axes` of the source
        model), -1 where unknown; default: read from the mescher's own plane outlines.
    E : (3, 3), optional
        The perceived frame (default :func:`perceived_frame`).

    Returns
    -------
    Z : (#F, 3) float64
        Corner depths ``a x + b y`` of the snapped planes (faces left alone keep theirs).
    snapped : (#F,) float64
        Angle (radians) between each face's normal and its snapped normal (0 where left).
    """
    xy, F, Z = np.asarray(xy, float), np.asarray(F, np.int64), np.asarray(Z, float)
    E = perceived_frame(xy, F, Z) if E is None else np.asarray(E, float)
    n = _normals(xy, F, Z)
    k = _axis_from_edges(xy, F, n, E) if axis is None else np.asarray(axis, np.int64)
    # the drawing fixes the frame up to a Necker reversal (all w_i negated, the mirror image
    # through the screen): take the reading nearer the model's own normals (area-weighted)
    P = xy[F]
    u, w = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    area = 0.5 * np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
    kk = np.where(k >= 0, k, 0)

    def cost(Ec):
        e = Ec[kk] * np.where(Ec[kk, 2] < 0, -1.0, 1.0)[:, None]
        return float(area @ np.arccos(np.clip(np.einsum("ij,ij->i", n, e), -1, 1)))

    Er = E * np.array([1.0, 1.0, -1.0])
    if cost(Er) < cost(E):
        E = Er
    c = n @ E.T  # (#F, 3) cosines to the three axes
    k = np.where(k >= 0, k, np.argmax(np.abs(c), axis=1))
    ck = c[np.arange(F.shape[0]), k]
    e = E[k] * np.where(E[k, 2] < 0, -1.0, 1.0)[:, None]  # the side facing the viewer
    ang = np.arccos(np.clip(np.abs(ck), -1.0, 1.0))
    by_edges = k >= 0
    ok = (by_edges | (ang <= MAX_SNAP)) & (e[:, 2] > 1e-6)
    a = -e[:, 0] / np.where(ok, e[:, 2], 1.0)
    b = -e[:, 1] / np.where(ok, e[:, 2], 1.0)
    P = xy[F]
    Zs = a[:, None] * P[:, :, 0] + b[:, None] * P[:, :, 1]
    Zs = np.where(ok[:, None], Zs, Z)
    return Zs, np.where(ok, ang, 0.0)


def snap_to_manhattan(m: Any) -> tuple[Any, np.ndarray]:
    """A mescher as a person reads it: normals snapped to the perceived orthogonal frame.

    Parameters
    ----------
    m : Mescher

    Returns
    -------
    m_perceived : Mescher
        ``type(m).from_corner_depths(F, xy, Z_snapped)`` (averaged, then projected onto locally
        integrable forms, paper Eq. 3-4).
    snapped : (#F,) float64
        Angle each face's normal moved (radians).
    """
    F, xy = np.asarray(m.F), np.asarray(m.xy)
    Zs, ang = perceive_manhattan(xy, F, np.asarray(m.corner_depths()))
    return type(m).from_corner_depths(F, xy, Zs), ang
