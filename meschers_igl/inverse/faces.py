"""Face orientations of a picture from shades and lines together.

A z-buffered figure of boxes under one directional light shades each face orientation one grey.
Two orientations may share a grey: both turned away from the light (both at the ambient
shade), or lit at equal angles.  The picture then shows two shades, and nothing but geometry
tells the two orientations of the shared shade apart.  The geometry does: in an orthographic
view of three right-angled directions ``n_A, n_B1, n_B2`` every edge of the figure runs along
the screen projection ``d_A, d_B1, d_B2`` of one of them, and a face of normal ``n_B1`` has
edges along ``d_A`` and ``d_B2`` only.  A chord of the shared region drawn along ``d_A``
therefore stays on one face and ends on an edge along ``d_B2`` (the face is ``B1``) or along
``d_B1`` (it is ``B2``): the lines at the ends of each chord name its face.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import MescherError

__all__ = ["OUTLINE_RATIO", "line_directions", "split_shared_shade"]

#: How many times farther an end of a chord on the outline may be than a disagreeing end
#: inside the figure and still win (:func:`_resolve_ends`).  Over eight two-shade pictures of
#: the acceptance models (cube, tribar, stairs and five development models, 128 pixels, one
#: light each) the pixels put on the wrong face were fewest between 6 and 12 (2433 at 8,
#: 2557 with the outline always first; on the cube 275 -> 189 of 5355).
OUTLINE_RATIO = 8.0

#: Grey levels (of 255) over the ambient shade under which a shade is the ambient one: faces
#: turned away from the light (``n . l <= 0``), not lit at a grazing angle.
AMBIENT_LEVELS = 2.0


def _split_costs(v: np.ndarray, w: np.ndarray):
    """Every split of sorted ``v`` (weights ``w``) into three contiguous groups ``v[:a]``,
    ``v[a:b]``, ``v[b:]``: ``a, b`` (n-1, n-1) grids, their weighted sums of squares about
    the groups' means (``inf`` where ``a >= b``) and the prefix sums of ``w`` (n+1,)."""
    n = len(v)
    W1 = np.r_[0.0, np.cumsum(w)]
    S1 = np.r_[0.0, np.cumsum(w * v)]
    S2 = np.r_[0.0, np.cumsum(w * v * v)]

    def cost(i, j):  # weighted sum of squares of v[i:j]
        ww = np.maximum(W1[j] - W1[i], 1e-300)
        with np.errstate(over="ignore", invalid="ignore"):
            return S2[j] - S2[i] - (S1[j] - S1[i]) ** 2 / ww

    a, b = np.meshgrid(np.arange(1, n), np.arange(1, n), indexing="ij")
    total = np.where(a < b, cost(0, a) + cost(a, b) + cost(b, n), np.inf)
    return a, b, total, W1


def _groups(n: int, a: int, b: int) -> np.ndarray:
    """(n,) group index 0, 1, 2 of the split at ``a, b``."""
    g = np.zeros(n, dtype=np.int64)
    g[a:] = 1
    g[b:] = 2
    return g


def _three_means(v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Group index (0, 1, 2) of sorted values ``v`` (weights ``w``): least weighted variance.

    The optimal 1D k-means groups are contiguous in sorted order; with prefix sums every pair
    of split points is tried at once (``O(n^2)``, ``n`` the number of distinct faces).
    """
    n = len(v)
    if n < 3:
        return np.minimum(np.arange(n), 2)
    a, b, total, _ = _split_costs(v, w)
    i, j = np.unravel_index(int(np.argmin(total)), total.shape)
    return _groups(n, a[i, j], b[i, j])


def _three_means_ranked(
    v: np.ndarray, w: np.ndarray, min_weight: float, min_gap: float
) -> list[np.ndarray]:
    """The groupings of sorted ``v`` (weights ``w``) into three contiguous groups that split
    only where ``v`` jumps by more than ``min_gap``, each group weighing at least
    ``min_weight``: group indices (n,), least weighted variance first."""
    n = len(v)
    if n < 3:
        return []
    a, b, total, W1 = _split_costs(v, w)
    jump = np.r_[np.inf, np.diff(v)] > min_gap  # jump[k]: v[k] - v[k - 1]
    ok = np.isfinite(total) & jump[a] & jump[b]
    ok &= (W1[a] >= min_weight) & (W1[b] - W1[a] >= min_weight) & (W1[n] - W1[b] >= min_weight)
    total = np.where(ok, total, np.inf)
    ranked = np.argsort(total, axis=None)[: int(ok.sum())]
    return [_groups(n, a.flat[r], b.flat[r]) for r in ranked]


def _segments(lines, tolerance: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(S, 2) starts and (S, 2) ends of the straight pieces of shapely lines.

    ``tolerance`` > 0: each line simplified first (Douglas-Peucker): a shallow pixel staircase
    left in steps becomes one segment along its true direction.
    """
    import shapely

    a, b = [], []
    for g in lines:
        if tolerance > 0:
            g = shapely.simplify(g, tolerance, preserve_topology=False)
        for part in shapely.get_parts(g):
            c = np.asarray(part.coords)
            if len(c) >= 2:
                a.append(c[:-1])
                b.append(c[1:])
    if not a:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.concatenate(a), np.concatenate(b)


def line_directions(
    starts: np.ndarray,
    ends: np.ndarray,
    k: int = 3,
    apart_deg: float = 12.0,
    min_length: float = 0.0,
):
    """The ``k`` main directions of a set of segments (length-weighted modes, mod 180 degrees).

    A length-weighted histogram of the segments' angles (1-degree bins, smoothed over 5) gives
    the strongest mode; the bins within ``apart_deg`` of it are cleared and the next mode
    taken.  Each mode is refined by the weighted mean of the doubled angles within 5 degrees.

    Parameters
    ----------
    starts, ends : (S, 2) float
    k : int
    apart_deg : float
    min_length : float
        Shorter segments are left out: a shallow line's pixel steps, each a segment of a pixel
        or two along a diagonal, add up along a long line to a mode of their own.

    Returns
    -------
    (k, 2) float64
        Unit directions, strongest first.

    Raises
    ------
    MescherError
        Fewer than ``k`` directions with any length.
    """
    d = np.asarray(ends, dtype=np.float64) - np.asarray(starts, dtype=np.float64)
    w = np.linalg.norm(d, axis=1)
    w = np.where(w >= min_length, w, 0.0)
    ang = np.mod(np.arctan2(d[:, 1], d[:, 0]), np.pi)
    hist = np.bincount(np.floor(np.degrees(ang)).astype(np.int64) % 180, w, minlength=180)
    smooth = sum(np.roll(hist, s) for s in range(-2, 3))
    out = []
    for _ in range(k):
        m = int(np.argmax(smooth))
        if not smooth[m] > 0:
            raise MescherError(
                f"target: expected lines in {k} directions (the edges of a figure of boxes), "
                f"found {len(out)}"
            )
        mode = math.radians(m + 0.5)
        near = np.abs(np.angle(np.exp(2j * (ang - mode)))) < 2.0 * math.radians(5.0)
        z = (w[near] * np.exp(2j * ang[near])).sum()
        th = 0.5 * math.atan2(z.imag, z.real) if abs(z) > 0 else mode
        out.append((math.cos(th), math.sin(th)))
        off = (np.arange(180) - m + 90) % 180 - 90
        smooth = np.where(np.abs(off) <= apart_deg, 0.0, smooth)
    return np.array(out)


def _abs_sin(d: np.ndarray, u: np.ndarray) -> np.ndarray:
    """``|sin|`` of the angles between the rows of ``d`` and each unit row of ``u``: (S, U)."""
    dn = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    return np.abs(dn[:, None, 0] * u[None, :, 1] - dn[:, None, 1] * u[None, :, 0])


def _chord_exits(region: np.ndarray, figure: np.ndarray, step: np.ndarray):
    """Where the chord from each pixel of ``region`` along ``step`` (pixels) leaves it.

    Returns, per pixel of the region, the exit point (pixel coordinates ``(col, row)`` of the
    midpoint between the last sample inside and the first outside), its distance in pixels,
    whether the chord left the ``figure`` there (onto the ground), and the pixel indices
    ``(rows, cols)``.  Leaving the image counts as leaving the figure.
    """
    H, W = region.shape
    rows, cols = np.nonzero(region)
    p = np.stack([cols + 0.5, rows + 0.5], axis=1).astype(np.float64)
    exit_at = np.full_like(p, np.nan)
    dist = np.full(len(p), np.inf)
    ground = np.zeros(len(p), dtype=bool)
    live = np.ones(len(p), dtype=bool)
    h = 0.5
    for t in np.arange(h, 2.0 * (H + W), h):
        if not live.any():
            break
        q = p[live] + t * step
        c, r = np.floor(q[:, 0]).astype(np.int64), np.floor(q[:, 1]).astype(np.int64)
        inside = (c >= 0) & (c < W) & (r >= 0) & (r < H)
        out = ~inside
        out[inside] = ~region[r[inside], c[inside]]
        gone = ~inside
        gone[inside] = ~figure[r[inside], c[inside]]
        idx = np.nonzero(live)[0][out]
        exit_at[idx] = p[idx] + (t - 0.5 * h) * step
        dist[idx] = t - 0.5 * h
        ground[idx] = gone[out]
        live[idx] = False
    return exit_at, dist, ground, np.stack([rows, cols], axis=1)


def _nearest_segment(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Index of the segment ``a[s] -> b[s]`` nearest each point (chunks of points)."""
    out = np.zeros(len(pts), dtype=np.int64)
    ab = b - a
    L2 = np.maximum((ab * ab).sum(axis=1), 1e-300)
    for i in range(0, len(pts), 2048):
        p = pts[i : i + 2048, None, :]
        t = np.clip(((p - a[None]) * ab[None]).sum(axis=-1) / L2[None], 0.0, 1.0)
        q = a[None] + t[..., None] * ab[None]
        out[i : i + 2048] = np.argmin(((p - q) ** 2).sum(axis=-1), axis=1)
    return out


def _end_votes(region, figure, step, sa, sb, dB, tol_deg: float):
    """The face each end of each pixel's chord names: 0 (``B1``), 1 (``B2``) or -1 (none).

    ``sa, sb``: the lines' segments in pixel coordinates (x right, y down); ``dB``: (2, 2) the
    directions ``d_B1, d_B2`` (screen, y up).  Returns the votes of the ``+step`` and ``-step``
    ends, their distances (inf where no vote), whether each end is on the outline, and the
    pixels ``(rows, cols)``.
    """
    d = (sb - sa) * np.array([1.0, -1.0])
    votes, dists, grounds = [], [], []
    for sgn in (1.0, -1.0):
        ex, dist, ground, rc = _chord_exits(region, figure, sgn * step)
        grounds.append(ground)
        sn = _abs_sin(d[_nearest_segment(ex, sa, sb)], dB)  # (P, 2): |sin| to d_B1, d_B2
        told = sn.min(axis=1) < math.sin(math.radians(tol_deg))
        # an end on a line along d_B2 is on B1 (vote 0), along d_B1 on B2 (vote 1)
        votes.append(np.where(told, 1 - np.argmin(sn, axis=1), -1))
        dists.append(np.where(told, dist, np.inf))
    return votes, dists, grounds, rc


def _resolve_ends(votes, dists, grounds, outline_ratio: float = OUTLINE_RATIO) -> np.ndarray:
    """The face of each pixel from the votes of the two ends of its chord.

    An end that names no face (-1) leaves the other's vote.  Where both name one they agree
    or the nearer wins, except that an end on the outline counts ``outline_ratio`` times
    nearer than it is against an end inside the figure.  The outline is first because it is
    the edge of the front face there, while a line inside the figure may be the edge of a face
    in front of the pixel's; but a long chord may leave its face across an edge no line shows
    (two faces of one shade meeting) and end on another face's outline, while a line a few
    pixels away is the pixel's own crease.

    Parameters
    ----------
    votes : pair of (P,) int
        Face named by the ``+step`` and ``-step`` ends (0, 1, or -1 for none).
    dists : pair of (P,) float
        Distances of the ends (pixels; inf where no vote).
    grounds : pair of (P,) bool
        Whether each end is on the outline.
    outline_ratio : float
        ``>= 1``; ``inf`` puts the outline always first.

    Returns
    -------
    (P,) int64
        0, 1, or -1 where neither end names a face.
    """
    if not outline_ratio >= 1.0:
        raise MescherError(f"outline_ratio: expected a number >= 1, found {outline_ratio}")
    (v0, v1), (d0, d1), (g0, g1) = votes, dists, grounds
    e0, e1 = np.array(d0, dtype=np.float64), np.array(d1, dtype=np.float64)
    first0, first1 = g0 & ~g1 & (v0 >= 0), g1 & ~g0 & (v1 >= 0)
    e0[first0] /= outline_ratio
    e1[first1] /= outline_ratio
    face = np.where(e0 <= e1, v0, v1)
    return np.where(v0 < 0, v1, np.where(v1 < 0, v0, face)).astype(np.int64)


def _outer_ground(mask: np.ndarray) -> np.ndarray:
    """The ground outside the figure: background pixels 4-connected to the image's border.

    The rest of the background are the figure's holes.  Where the two ends of a chord of the
    shared shade disagree (:func:`split_shared_shade`), only an end on this outer outline comes
    first; a hole's outline counts as a line inside the figure: a hole is closed by the faces
    around it, and a chord reaching it has often crossed an unseen edge between faces of the
    shared shade where the figure turns around the hole.  Over the fourteen two-shade pictures
    of the acceptance benchmark (development models and box models, six lights, 128 pixels),
    of the pixels whose two ends disagree with one end on the outline, that end named the true
    face at 80% of the 3359 on the outer outline and at 38% of the 488 on a hole's (the
    Reutersvärd relief's and the Escher cube's); their wrong pixels 376 -> 322 and 456 -> 411
    (before the majority pass), the others' labels unchanged.
    """
    from scipy.ndimage import binary_fill_holes

    return ~binary_fill_holes(mask)  # holes: background not 4-connected to the border


def _majority(labels: np.ndarray, region: np.ndarray, passes: int) -> np.ndarray:
    """``labels`` (1 or 2 on ``region``) after ``passes`` of a 3 x 3 majority inside it.

    Each pixel of ``region`` takes the label (1 or 2) that more of its 3 x 3 neighbourhood
    (itself included) holds; ties and pixels outside ``region`` keep theirs.
    """
    from scipy.ndimage import uniform_filter

    out = labels.copy()
    for _ in range(passes):
        c1 = uniform_filter((out == 1).astype(np.float64), 3, mode="constant")
        c2 = uniform_filter((out == 2).astype(np.float64), 3, mode="constant")
        out = np.where(region & (c1 > c2 + 1e-9), 1, np.where(region & (c2 > c1 + 1e-9), 2, out))
    return out


def _refine_frame(R, d, owner, order, light, shade_a: float, shade_b: float, ambient: float):
    """The frame (rows ``n_A, n_B1, n_B2``) nearest ``R`` that fits the lines and the shades.

    Least squares over a rotation ``exp([w]) R``: each segment ``d`` (of the direction
    ``owner``, -1 for none; ``order`` maps rows to directions) lies along the projection of its row's
    normal (``|sin|``, weighted by ``sqrt(length)``), and the Lambertian shades are met
    (``n_A``: ``shade_a``; ``n_B1, n_B2``: ``shade_b``, or turned away where it is ambient),
    each shade weighted as the whole length of the lines.
    """
    from scipy.optimize import least_squares
    from scipy.spatial.transform import Rotation

    keep = np.nonzero(owner >= 0)[0]
    d, row = d[keep], np.argsort(order)[owner[keep]]  # the row whose normal each follows
    ln = np.linalg.norm(d, axis=1)
    wt = np.sqrt(ln / ln.sum())
    u = d / np.maximum(ln, 1e-300)[:, None]
    s = (np.array([shade_a, shade_b, shade_b]) - ambient) / (1.0 - ambient)
    turned = s < AMBIENT_LEVELS / 255.0 / (1.0 - ambient)  # at the ambient shade: n . l <= 0

    def res(w):
        N = R @ Rotation.from_rotvec(w).as_matrix().T
        p = N[row, :2] / np.maximum(np.linalg.norm(N[row, :2], axis=1, keepdims=True), 1e-12)
        line = wt * (u[:, 0] * p[:, 1] - u[:, 1] * p[:, 0])
        c = N @ light
        shade = np.where(turned, np.maximum(c, 0.0), c - s)
        return np.r_[line, shade]

    w = least_squares(res, np.zeros(3), method="lm" if len(d) >= 3 else "trf").x
    N = R @ Rotation.from_rotvec(w).as_matrix().T
    return N * np.sign(N[:, 2:3])


def _two_groups(cshade, size, total, line_step: float, min_share: float):
    """Two shade groups of the faces (split at the largest jump), or None."""
    big = np.nonzero(size >= 0.25 * min_share * total)[0]
    v = np.sort(cshade[big])
    if len(v) < 2:
        return None
    gaps = np.diff(v)
    g = int(np.argmax(gaps))
    if not gaps[g] > line_step:
        return None
    cut = 0.5 * (v[g] + v[g + 1])
    grp = (cshade > cut).astype(np.int64)
    share = np.bincount(grp, weights=size, minlength=2) / total
    if share.min() < min_share:
        return None
    return grp


def split_shared_shade(
    mask: np.ndarray,
    grey: np.ndarray,
    comp_group: np.ndarray,
    light,
    ambient: float,
    tol_deg: float = 12.0,
    outline_ratio: float = OUTLINE_RATIO,
    smooth: int = 1,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Three face orientations from a picture showing two shades (one shared by two of them).

    The figure's lines (the straightened boundaries of the two shade regions and the outline)
    run in three main directions (:func:`line_directions`), the projections of the three
    right-angled face directions, and :func:`.shading.frames_from_creases` gives the frame
    (two Necker readings).  Which direction is ``d_A`` (of the unshared orientation), which
    shade is shared and which reading holds is chosen by the light: the least squared misfit
    of the predicted Lambertian shades over the 12 choices.  The frame is then refined by
    least squares on the lines within 5 degrees of their direction and on the shades.  Each
    pixel of the shared shade takes the face named by the lines at the ends of its chord along
    ``d_A``; where the two ends disagree, :func:`_resolve_ends` weighs them by distance, an
    end on the outer outline (:func:`_outer_ground`; a hole's outline counts as a line inside
    the figure) ``outline_ratio`` times more than one inside the figure.  Pixels whose chords
    end on no telling line take their nearest decided neighbour's face.  Last, each pixel of the shared shade
    takes the face most of its 3 x 3 neighbours hold (``smooth`` passes): the chords of
    neighbouring pixels end a pixel apart and may name different lines where the lines meet,
    leaving single pixels and ragged one-pixel teeth along the unseen crease; a face is no
    single pixel, and ragged boundaries become needless constraints (and near-touching ones)
    of the triangulation that follows.

    Parameters
    ----------
    mask : (N, N) bool
        Figure pixels.
    grey : (N, N) float
        Grey level per pixel.
    comp_group : (N, N) int
        Shade group (0 darker, 1 lighter) per figure pixel, -1 elsewhere.
    light : (3,) float
        Direction toward the light (camera frame).
    ambient : float
    tol_deg : float
        A line within this angle of ``d_B1`` or ``d_B2`` names a face.
    outline_ratio : float
        An end on the outer outline outweighs a disagreeing end inside the figure (or on a
        hole's outline) up to this many times farther (:func:`_resolve_ends`).
    smooth : int
        Passes of a 3 x 3 majority between the two faces of the shared shade
        (:func:`_majority`).

    Returns
    -------
    labels : (N, N) int64
        Orientation per pixel (0, 1, 2; -1 on the background).
    shades : (3,) float64
        Mean grey per orientation.
    normals : (3, 3) float64
        Row ``k``: unit normal of orientation ``k`` (camera frame, ``n_z > 0``).
    """
    from .regions import region_polygons
    from .shading import frames_from_creases

    if not (isinstance(smooth, (int, np.integer)) and smooth >= 0):
        raise MescherError(f"smooth: expected an integer >= 0, found {smooth!r}")
    lvec = np.asarray(light, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    N = mask.shape[0]
    _, _, lines = region_polygons(np.where(mask, comp_group, -1))
    a, b = _segments(lines, 2.0 / N)  # a pixel: shallow staircases straight, steps kept
    dirs = line_directions(a, b, 3)
    # which direction is d_A, which shade is shared, which Necker reading: the light says,
    # by the least misfit of the predicted Lambertian shades
    d = b - a
    px = 2.0 / N
    owner = np.argmin(_abs_sin(d, dirs), axis=1)
    # the shade most of a group's pixels hold (a bevel's pixels must not lift it off ambient)
    shade = np.array([np.median(grey[comp_group == g]) for g in (0, 1)])
    best = (math.inf, None, None, None)
    for kA in range(3):
        order = [kA] + [k for k in range(3) if k != kA]
        for R in frames_from_creases(dirs[order]):  # rows: n_A, n_B1, n_B2
            pred = ambient + (1.0 - ambient) * np.maximum(R @ lvec, 0.0)
            for shared in (0, 1):
                mis = (pred[0] - shade[1 - shared]) ** 2 + ((pred[1:] - shade[shared]) ** 2).sum()
                if mis < best[0]:
                    best = (mis, shared, R, order)
    _, shared, R, order = best
    near = np.where(_abs_sin(d, dirs).min(axis=1) < math.sin(math.radians(5.0)), owner, -1)
    R = _refine_frame(R, d, near, order, lvec, shade[1 - shared], shade[shared], ambient)
    # chords along d_A through the shared shade: pixel steps (x right, y down)
    proj = R[:, :2] / np.linalg.norm(R[:, :2], axis=1, keepdims=True)
    step = proj[0] * np.array([1.0, -1.0])
    region = mask & (comp_group == shared)
    sa = np.stack([(a[:, 0] + 1.0) / px, (1.0 - a[:, 1]) / px], axis=1)
    sb = np.stack([(b[:, 0] + 1.0) / px, (1.0 - b[:, 1]) / px], axis=1)
    # only the outer outline comes first; a hole's outline counts as a line inside the figure
    votes, dists, grounds, rc = _end_votes(
        region, ~_outer_ground(mask), step, sa, sb, proj[1:], tol_deg
    )
    face = _resolve_ends(votes, dists, grounds, outline_ratio)
    labels = np.full(mask.shape, -1, dtype=np.int64)
    labels[mask & (comp_group != shared)] = 0
    labels[rc[:, 0], rc[:, 1]] = np.where(face >= 0, face + 1, -2)
    undecided = labels == -2
    if not (labels >= 1).any():
        raise MescherError(
            "target: expected lines that tell two faces of one shade apart, found none"
        )
    if undecided.any():  # chords ending on no telling line: the nearest decided pixel's face
        from scipy.ndimage import distance_transform_edt

        _, (ri, ci) = distance_transform_edt(labels < 1, return_indices=True)
        labels = np.where(undecided, labels[ri, ci], labels)
    labels = _majority(labels, region, smooth)
    shades = np.array(
        [grey[labels == k].mean() if (labels == k).any() else np.nan for k in range(3)]
    )
    if np.isnan(shades).any():
        raise MescherError("target: expected both faces of the shared shade, found one")
    return labels, shades, R.copy()
