"""Normals and the light from the flat shades of a figure of boxes (a picture's faces).

Under one directional light a Lambertian face of normal ``n`` shades ``ambient + diffuse *
max(n . l, 0)``; three face orientations at right angles (a Manhattan frame) and their shades
fix the light, and the crease directions between faces on screen fix the frame itself.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import MescherError

__all__ = [
    "crease_directions",
    "crease_misfit",
    "crease_sines",
    "estimate_exposure",
    "estimate_light",
    "frames_from_creases",
    "normals_from_shading",
]


#: A boundary's ``sin^2`` off its crease counts at most this much in a frame's misfit (15
#: degrees): occlusion boundaries, which follow no crease, must not pull the frame.
CREASE_TRUNC = math.sin(math.radians(15.0)) ** 2


def normals_from_shading(
    shades: np.ndarray,
    light,
    ambient: float,
    boundary_dirs: np.ndarray | None = None,
    boundary_pairs: np.ndarray | None = None,
    boundary_weights: np.ndarray | None = None,
    n_angles: int = 1440,
    trunc: float = CREASE_TRUNC,
    level: float = 1.0 / 255.0,
) -> tuple[np.ndarray, float]:
    """Three orthonormal face normals whose Lambertian shades are ``shades``.

    ``n_k . l = s_k = (shade_k - ambient) / (1 - ambient)``, ``n_k = R e_k``: ``R^T l = s``.
    ``R = Q_theta R_0`` with ``R_0`` a rotation taking ``s/|s|`` to ``l`` and ``Q_theta`` a turn
    about ``l``; also mirrored frames.  Among the ``R`` with every ``n_k`` facing the viewer,
    the one whose crease projections ``(n_i x n_j)_xy`` best follow the region boundaries
    (``boundary_dirs`` between regions ``boundary_pairs``, length ``boundary_weights``) wins.

    Parameters
    ----------
    shades : (3,) float
    light : (3,) float
        Direction toward the light, camera frame.
    ambient : float
    boundary_dirs : (B, 2) float, optional
    boundary_pairs : (B, 2) int, optional
    boundary_weights : (B,) float, optional
    n_angles : int
        Turns about ``l`` tried.
    trunc : float
        Each boundary's ``sin^2`` counts at most this much (robust to occlusion boundaries).
    level : float
        How far a shade may be from the true one (a grey level's rounding).  With one face at
        the ambient shade its ``n . l`` is any the rounded lit shades allow, chosen by the
        creases with the turn (:func:`_dark_candidates`); 0: the root of ``|R^T l| = 1``.

    Returns
    -------
    normals : (3, 3) float64
        Row ``k``: the unit normal of region ``k`` (camera frame, ``n_z > 0``).
    misfit : float
        Weighted mean ``sin^2`` of the angle between boundaries and crease projections.
    """
    s = (np.asarray(shades, dtype=np.float64) - ambient) / (1.0 - ambient)
    if s.shape != (3,):
        raise MescherError(f"shades: expected three face shades, found {s.shape}")
    lvec = np.asarray(light, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    best = (math.inf, None)
    for sk in _dark_candidates(s, level / (1.0 - ambient)):
        cost, N = _best_turn(
            sk, lvec, boundary_dirs, boundary_pairs, boundary_weights, n_angles, trunc
        )
        if cost < best[0]:
            best = (cost, N)
    if best[1] is None:
        raise MescherError(
            "shades: expected three shades of orthogonal faces seen from the front, found none "
            "consistent with the light"
        )
    return best[1].copy(), best[0]


def _dark_candidates(
    s: np.ndarray, level: float, n: int = 17, spread: float = math.sin(math.radians(3.0))
) -> list[np.ndarray]:
    """The unit vectors ``R^T l`` the shades ``s`` allow (a face at the ambient shade: several).

    A face at the ambient shade says only ``n . l <= 0``; with the other two lit, ``|R^T l| =
    1`` gives it ``-sqrt(1 - s_i^2 - s_j^2)``, which is ill-conditioned near grazing (the
    derivative grows as ``1 / sqrt``): a grey level's rounding (``level``, in ``s`` units) on
    shades whose squares sum to nearly 1 moves the root by 0.2 and the normals by degrees.
    Where the roots the rounded shades allow (``s_i`` within ``level``) spread over more than
    ``spread`` (3 degrees of ``n . l``; the creases read the frame to about a degree), each of
    ``n`` evenly spaced ones is a candidate, the lit pair rescaled to keep ``|s| = 1``, and the
    creases choose among them.  Otherwise the one vector of :func:`_shadowed_root`.
    """
    s0 = _shadowed_root(s)
    dark = _turned_away(s)
    if dark.sum() != 1 or level <= 0:
        return [s0 / np.linalg.norm(s0)]
    lit = np.abs(s[~dark])
    lo = math.sqrt(max(0.0, 1.0 - float(((lit + level) ** 2).sum())))
    hi = math.sqrt(max(0.0, 1.0 - float((np.maximum(lit - level, 0.0) ** 2).sum())))
    if hi - lo <= spread:
        return [s0 / np.linalg.norm(s0)]
    out = []
    for r in np.unique(np.r_[np.linspace(lo, hi, n), -s0[dark]]):
        c = s.copy()
        c[dark] = -r
        c[~dark] = s[~dark] * math.sqrt(max(0.0, 1.0 - r * r)) / np.linalg.norm(s[~dark])
        out.append(c)
    return out


def _best_turn(s, lvec, boundary_dirs, boundary_pairs, boundary_weights, n_angles, trunc):
    """The frame ``R`` with ``R^T l = s`` (unit) whose creases best follow the boundaries, and
    its cost (:func:`normals_from_shading`); ``(inf, None)`` where no turn faces the viewer."""
    R0 = _rotation_taking(s, lvec)
    th = np.linspace(0.0, 2.0 * np.pi, n_angles, endpoint=False)
    K = np.array([[0, -lvec[2], lvec[1]], [lvec[2], 0, -lvec[0]], [-lvec[1], lvec[0], 0]])
    # Rodrigues: Q = I + sin K + (1 - cos) K^2, for all angles at once
    Q = np.eye(3)[None] + np.sin(th)[:, None, None] * K + (1 - np.cos(th))[:, None, None] * (K @ K)
    best = (math.inf, None)
    for mirror in (np.eye(3), np.diag([1.0, 1.0, -1.0])):
        # a mirror that keeps s (reflect through a plane containing s) keeps R^T l = s
        Ms = _reflection_fixing(s) if mirror[2, 2] < 0 else np.eye(3)
        Rs = Q @ (R0 @ Ms)  # (A, 3, 3); columns are the normals
        N = np.transpose(Rs, (0, 2, 1))  # rows n_k
        ok = (N[:, :, 2] > 1e-3).all(axis=1)
        cost = np.zeros(n_angles)
        if boundary_dirs is not None and len(boundary_dirs):
            d = np.asarray(boundary_dirs, dtype=np.float64)
            d = d / np.linalg.norm(d, axis=1, keepdims=True)
            pr = np.asarray(boundary_pairs, dtype=np.int64)
            wts = np.ones(len(d)) if boundary_weights is None else np.asarray(boundary_weights)
            c = np.cross(N[:, pr[:, 0]], N[:, pr[:, 1]])[..., :2]  # (A, B, 2)
            c = c / np.maximum(np.linalg.norm(c, axis=-1, keepdims=True), 1e-12)
            sin = c[..., 0] * d[None, :, 1] - c[..., 1] * d[None, :, 0]
            # truncated: occlusion boundaries (no crease) must not pull the frame
            cost = (np.minimum(sin**2, trunc) * wts).sum(axis=1) / wts.sum()
        cost = np.where(ok, cost, np.inf)
        a = int(np.argmin(cost))
        if cost[a] < best[0]:
            best = (float(cost[a]), N[a])
    return best


def crease_directions(
    dirs: np.ndarray, pairs: np.ndarray, weights: np.ndarray, labels: np.ndarray | None = None
) -> np.ndarray:
    """The screen direction of the crease between each two of three face groups.

    The boundary between groups ``i`` and ``j`` runs mostly along their crease; occlusions run
    elsewhere.  The crease is the mode of the boundary's orientations (length-weighted
    histogram of 1-degree bins, smoothed over 5), refined by the weighted mean of the doubled
    angles within 5 degrees of it.  With the ``labels`` the boundary was straightened from,
    the direction is then sharpened on the pixels themselves (:func:`_sharpen_crease`): a
    boundary within 15 degrees of a pixel axis is a staircase of long runs, and its
    straightened pieces keep the runs' direction (6.7 degrees read as 2.1).

    Parameters
    ----------
    dirs : (B, 2) float
        Boundary edge vectors (:func:`region_boundaries`).
    pairs : (B, 2) int
        The two groups on either side, in ``0, 1, 2``.
    weights : (B,) float
        Edge lengths.
    labels : (N, N) int, optional
        The group of each pixel (-1 off the figure), the image spanning ``[-1, 1]^2``.

    Returns
    -------
    (3, 2) float64
        Row ``k``: the unit crease direction between the two groups other than ``k`` (the
        screen projection of group ``k``'s normal's direction, up to sign).

    Raises
    ------
    MescherError
        Two groups that never meet.
    """
    d = np.asarray(dirs, dtype=np.float64)
    pr = np.sort(np.asarray(pairs, dtype=np.int64), axis=1)
    wts = np.asarray(weights, dtype=np.float64)
    ang = np.mod(np.arctan2(d[:, 1], d[:, 0]), np.pi)
    out = np.zeros((3, 2))
    for k in range(3):
        i, j = [g for g in range(3) if g != k]
        sel = (pr[:, 0] == i) & (pr[:, 1] == j)
        if not sel.any():
            raise MescherError(
                f"target: expected every two face orientations to meet along a crease, found "
                f"none between the shades {i} and {j}"
            )
        a, wt = ang[sel], wts[sel]
        hist = np.bincount(np.floor(np.degrees(a)).astype(np.int64) % 180, wt, minlength=180)
        smooth = sum(np.roll(hist, s_) for s_ in range(-2, 3))
        mode = math.radians(int(np.argmax(smooth)) + 0.5)
        near = np.abs(np.angle(np.exp(2j * (a - mode)))) < 2.0 * math.radians(5.0)
        z = (wt[near] * np.exp(2j * a[near])).sum()
        th = 0.5 * math.atan2(z.imag, z.real)
        if labels is not None:
            th = _sharpen_crease(labels, i, j, th)
        out[k] = (math.cos(th), math.sin(th))
    return out


def _sharpen_crease(
    labels: np.ndarray,
    i: int,
    j: int,
    th: float,
    reach_deg: float = 12.0,
    near_deg: float = 5.0,
    min_px: int = 6,
    max_width_px: float = 0.45,
) -> float:
    """The direction near ``th`` (radians, screen frame, y up) of the straight pieces of the
    pixel boundary between groups ``i`` and ``j``.

    The midpoints of the unit pixel edges between the two groups, joined where they touch,
    make the boundary's pieces; a piece of at least ``min_px`` midpoints that is straight (its
    midpoints within ``max_width_px`` of their least-squares line, rms: a digital straight
    line's stray at most half a pixel) and runs within ``near_deg`` of ``th`` gives its
    line's direction (where none does, those within ``near_deg`` of the longest within
    ``reach_deg``), and the pieces' directions are averaged (doubled angles, weighted by the
    inverse of their variance, the cube of their lengths).  Each piece is fitted on its own: the step edges of a flight, parallel
    but offset, must not line up into the flight's slope.  ``th`` where no piece qualifies.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    lab = np.asarray(labels)
    pts = []
    for a, b, off in ((lab[:, :-1], lab[:, 1:], (0.5, 0.0)), (lab[:-1], lab[1:], (0.0, 0.5))):
        r, c = np.nonzero(((a == i) & (b == j)) | ((a == j) & (b == i)))
        pts.append(np.stack([c + 0.5 + off[0], -(r + 0.5 + off[1])], axis=1))  # x right, y up
    P = np.concatenate(pts)
    if len(P) < min_px:
        return th
    near = cKDTree(P).query_pairs(1.01, output_type="ndarray")  # edges sharing a corner
    g = coo_matrix((np.ones(len(near)), (near[:, 0], near[:, 1])), shape=(len(P), len(P)))
    n_comp, comp = connected_components(g, directed=False)
    count = np.bincount(comp, minlength=n_comp).astype(np.float64)
    mean = np.stack([np.bincount(comp, P[:, k], n_comp) for k in (0, 1)], axis=1)
    mean /= np.maximum(count, 1.0)[:, None]
    Q = P - mean[comp]
    sxx = np.bincount(comp, Q[:, 0] ** 2, n_comp)
    sxy = np.bincount(comp, Q[:, 0] * Q[:, 1], n_comp)
    syy = np.bincount(comp, Q[:, 1] ** 2, n_comp)
    ang = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)  # each piece's principal direction
    tr, det = sxx + syy, sxx * syy - sxy**2
    small = 0.5 * tr - np.sqrt(np.maximum(0.25 * tr**2 - det, 0.0))  # across-line scatter
    width = np.sqrt(small / np.maximum(count, 1.0))
    off = np.abs(np.angle(np.exp(2j * (ang - th)))) / 2.0
    ok = (count >= min_px) & (width <= max_width_px) & (off <= math.radians(reach_deg))
    if not ok.any():
        return th
    # pieces within near_deg of th where there are any (a figure's lines off its axes, a
    # sloped piece, stay out); else the cluster of the heaviest piece (th on a pixel axis,
    # the runs of a staircase's long pieces, can be 8 degrees off)
    if (ok & (off <= math.radians(near_deg))).any():
        ok &= off <= math.radians(near_deg)
    else:
        top = int(np.argmax(np.where(ok, count, -1.0)))
        ok &= np.abs(np.angle(np.exp(2j * (ang - ang[top])))) / 2.0 <= math.radians(near_deg)
    # a line fitted to L midpoints half a pixel astray is off by ~ sqrt(3 / L^3) radians: each
    # piece weighs its inverse variance, L^3
    z = (count[ok] ** 3 * np.exp(2j * ang[ok])).sum()
    return 0.5 * math.atan2(z.imag, z.real)


def crease_sines(normals: np.ndarray, dirs: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(B,) signed sine of the angle between each boundary vector (``dirs``, between the
    regions ``pairs``) and the screen projection of its regions' crease ``n_i x n_j``."""
    c = np.cross(normals[pairs[:, 0]], normals[pairs[:, 1]])[:, :2]
    c = c / np.maximum(np.linalg.norm(c, axis=1, keepdims=True), 1e-12)
    d = dirs / np.maximum(np.linalg.norm(dirs, axis=1, keepdims=True), 1e-300)
    return c[:, 0] * d[:, 1] - c[:, 1] * d[:, 0]


def crease_misfit(normals: np.ndarray, dirs: np.ndarray, pairs: np.ndarray, lens) -> float:
    """A frame's misfit to the region boundaries: the length-weighted mean of
    ``min(sin^2, CREASE_TRUNC)`` (:func:`crease_sines`; what :func:`normals_from_shading`
    minimizes over its turns)."""
    sin = crease_sines(normals, dirs, pairs)
    w = np.asarray(lens, dtype=np.float64)
    return float(np.sum(np.minimum(sin**2, CREASE_TRUNC) * w) / max(w.sum(), 1e-300))


def frames_from_creases(creases: np.ndarray) -> np.ndarray:
    """The two right-angled frames whose face normals project along ``creases``.

    Under an orthographic view the unit normals ``n_k = (t_k d_k, z_k)`` of three orthogonal
    face directions have screen parts along the creases ``d_k`` (row ``k`` of ``creases``), and
    the screen rows of the orthonormal frame are orthonormal:
    ``sum_k t_k^2 d_k d_k^T = I`` (three linear equations in ``t_k^2``).  Then
    ``z_k = sqrt(1 - t_k^2)`` (facing the viewer) and the signs of ``t_k`` follow from
    ``n_i . n_j = 0``, up to one sign for all three: the two readings of a Necker figure,
    ``(x, y, z)`` and ``(-x, -y, z)``, the same picture under the light ``(l_x, l_y, l_z)``
    and ``(-l_x, -l_y, l_z)``.

    Parameters
    ----------
    creases : (3, 2) float
        Unit screen directions (either sign).

    Returns
    -------
    (2, 3, 3) float64
        Two readings; row ``k`` of each is the unit normal of face direction ``k``.

    Raises
    ------
    MescherError
        Directions that no right-angled frame projects to (some ``t_k^2`` outside (0, 1)).
    """
    d = np.asarray(creases, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    A = np.stack([d[:, 0] ** 2, d[:, 0] * d[:, 1], d[:, 1] ** 2])
    try:
        t2 = np.linalg.solve(A, np.array([1.0, 0.0, 1.0]))
    except np.linalg.LinAlgError:
        t2 = np.full(3, np.nan)
    if not np.all((t2 > 1e-6) & (t2 < 1.0 - 1e-6)):
        deg = np.round(np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 180.0, 1).tolist()
        raise MescherError(
            "target: expected lines along the projections of three right-angled directions, "
            f"found crease directions {deg} degrees, which no right-angled frame projects to"
        )
    t, z = np.sqrt(t2), np.sqrt(1.0 - t2)
    s = np.array([1.0, -np.sign(d[0] @ d[1]), -np.sign(d[0] @ d[2])])
    N = np.column_stack([(s * t)[:, None] * d, z])
    return np.stack([N, N * np.array([-1.0, -1.0, 1.0])])


def estimate_light(shades: np.ndarray, normals: np.ndarray, ambient: float) -> np.ndarray:
    """The direction toward the light that shades faces of ``normals`` with ``shades``.

    ``n_k . l = s_k = (shade_k - ambient) / (1 - ambient)`` for orthonormal ``n_k`` gives
    ``l = sum_k s_k n_k``.  A face at the ambient shade is turned away: its ``s_k`` is the
    negative root of ``|l| = 1``.

    Parameters
    ----------
    shades : (3,) float
    normals : (3, 3) float
        Orthonormal rows.
    ambient : float

    Returns
    -------
    (3,) float64
        Unit light direction, camera frame.
    """
    s = (np.asarray(shades, dtype=np.float64) - ambient) / (1.0 - ambient)
    s = _shadowed_root(s)
    lvec = np.asarray(normals, dtype=np.float64).T @ s
    return lvec / np.linalg.norm(lvec)


def estimate_exposure(shades, ambient: float, tol: float = 0.03, level: float = 6.0 / 255.0):
    """The brightness ``alpha`` of a picture of three lit orientations (a grey material, a
    renderer's exposure): their shades are ``alpha (ambient + (1 - ambient) c_k)``.

    For orthonormal normals ``c_k = n_k . l`` has ``sum_k c_k^2 = |l|^2 = 1`` whatever the
    light, so with ``u = 1 / alpha``: ``sum_k (u shade_k - ambient)^2 = (1 - ambient)^2``,
    a quadratic in ``u`` whose larger root is taken (every ``c_k`` then at least as large as
    with the smaller).  Where the darkest shade is within ``level`` of the ambient shade (a
    white figure's face turned away, its ``c_k`` not seen; a JPEG's read a few levels off)
    nothing fixes ``alpha``: 1.  So is it within ``tol`` of 1 (8-bit shades of a white
    figure: within 1%).  A darker figure with a face turned away (its darkest shade
    ``alpha * ambient``) is read as three lit faces: a brightness too high.

    Parameters
    ----------
    shades : (3,) float
        The three orientations' shades, in [0, 1].
    ambient : float

    Returns
    -------
    float
        ``alpha``; the shades over ``alpha`` are those of a white figure.

    Examples
    --------
    >>> round(estimate_exposure([0.749, 0.514, 0.267], 0.2), 3)  # a grey tribar
    0.85
    >>> estimate_exposure([0.84, 0.2, 0.2], 0.2)  # two faces turned away: nothing to say
    1.0
    """
    sh = np.asarray(shades, dtype=np.float64)
    a = float(ambient)
    if sh.shape != (3,) or not 0.0 <= a < 1.0 or abs(sh.min() - a) <= level:
        return 1.0
    S1, S2 = float(sh.sum()), float((sh**2).sum())
    disc = (a * S1) ** 2 - S2 * (3.0 * a * a - (1.0 - a) ** 2)
    if disc < 0.0:
        return 1.0
    alpha = S2 / (a * S1 + math.sqrt(disc))
    return 1.0 if abs(alpha - 1.0) <= tol else float(alpha)


def _turned_away(s: np.ndarray, eps: float = 0.02) -> np.ndarray:
    """(3,) bool: the face taken as turned away from the light, the darkest of those within
    ``eps`` of the ambient shade (``n . l`` units).  Of two such faces the other is lit at a
    grazing angle (two grey levels over the ambient shade): read as turned away too, the
    lit one's ``n . l`` was rescaled to 1 and the frame turned by 25 degrees."""
    s = np.asarray(s, dtype=np.float64)
    dark = s <= eps
    if dark.sum() > 1:
        dark = np.arange(len(s)) == int(np.argmin(s))
    return dark


def _shadowed_root(s: np.ndarray, eps: float = 0.02) -> np.ndarray:
    """``s`` with one face at the ambient shade given ``-sqrt(1 - |others|^2)``."""
    s = np.array(s, dtype=np.float64)
    dark = _turned_away(s, eps)
    if dark.sum() == 1:
        s[dark] = -math.sqrt(max(0.0, 1.0 - float((s[~dark] ** 2).sum())))
    return s


def _rotation_taking(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A rotation with ``R a = b`` (unit vectors)."""
    v = np.cross(a, b)
    c = float(a @ b)
    if np.linalg.norm(v) < 1e-12:
        if c > 0:
            return np.eye(3)
        p = np.eye(3)[np.argmin(np.abs(a))]
        u = np.cross(a, p)
        u /= np.linalg.norm(u)
        return 2.0 * np.outer(u, u) - np.eye(3)
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def _reflection_fixing(s: np.ndarray) -> np.ndarray:
    """A reflection through a plane that contains ``s`` (so it maps ``s`` to itself)."""
    p = np.eye(3)[np.argmin(np.abs(s))]
    u = np.cross(s, p)
    u /= np.linalg.norm(u)
    return np.eye(3) - 2.0 * np.outer(u, u)
