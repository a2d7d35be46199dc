"""Regions of a label image as polygons with straight boundaries that neighbours share.

The step between segmenting a picture and triangulating it (:mod:`.picture`): a region's pixels
become shapely boxes, the pixel boundaries between regions become lines made straight, and the
lines are polygonized again, so that two regions meet along one boundary.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import MescherError

__all__ = ["node_constraints", "region_polygons"]


def pixel_to_screen(res: int) -> float:
    return 2.0 / res


def labels_at(labels: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """(P,) the labels of the pixels holding the screen points ``Q`` (P, 2) of a square label
    image spanning ``[-1, 1]^2`` (row 0 at the top); points off the image take its edge's."""
    N = labels.shape[0]
    px = pixel_to_screen(N)
    j = np.clip(np.floor((Q[:, 0] + 1.0) / px).astype(np.int64), 0, N - 1)
    i = np.clip(np.floor((1.0 - Q[:, 1]) / px).astype(np.int64), 0, N - 1)
    return labels[i, j]


def _pixel_boxes(mask: np.ndarray):
    """The pixels of a mask as shapely boxes, one per run along a row (screen units)."""
    import shapely

    H, W = mask.shape
    px = pixel_to_screen(W)
    ii, jj = np.nonzero(mask)
    start = np.r_[True, (np.diff(jj) != 1) | (np.diff(ii) != 0)]
    run_id = np.cumsum(start) - 1
    j0 = jj[start]
    j1 = np.bincount(run_id).astype(np.int64) + j0
    r = ii[start]
    return shapely.box(-1.0 + j0 * px, 1.0 - (r + 1) * px, -1.0 + j1 * px, 1.0 - r * px)


def _tips_through_corners(labels: np.ndarray, passes: int = 8, every: bool = False) -> np.ndarray:
    """``labels`` with each 2 x 2 checkerboard of four tips (``every``: each 2 x 2
    checkerboard) made whole along its main diagonal.

    A block ``a b / b a`` whose four pixels are each a tip (at most one 4-neighbour of its
    own label) is a face's thin tip crossing a pixel corner between two faces' tips (a bar's
    dark wedge, under a pixel wide, between two faces of one light shade, seen antialiased):
    four regions meet at one point, and the pieces around it lost the lift's cuts there (the
    box cube antialiased under three of six lights: period -99%).  Either diagonal made
    whole gives it back (within 1%); the top right pixel takes the main diagonal's label.
    A block where two regions' corners meet (a pixel of it with two neighbours of its own
    label) is left: there the two pairs are four faces, and the point keeps them apart (the
    box cube z-buffered at 256 px under two lights: made whole, -0.8% -> -21%).

    Parameters
    ----------
    labels : (H, W) int
        Region per pixel (-1: the background, which counts as a region here).
    passes : int
        Rounds over the blocks left (a change may make a block next to it).
    every : bool
        Every block, tips or not: a face's spike a pixel wide meeting a face of its shade at a
        pixel corner is one face there as often as not; :func:`.picture.mescher_from_picture`
        reads a picture both ways and keeps the reading that climbs more.

    Returns
    -------
    (H, W) int64
    """
    L = np.array(labels, dtype=np.int64, copy=True)
    P = np.pad(L, 1, constant_values=np.iinfo(np.int64).min)  # outside: no label
    for _ in range(passes):
        P[1:-1, 1:-1] = L
        own = sum(
            (P[1 + dy : P.shape[0] - 1 + dy, 1 + dx : P.shape[1] - 1 + dx] == L)
            for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))
        )
        tip = own <= 1
        a, b, c, d = L[:-1, :-1], L[:-1, 1:], L[1:, :-1], L[1:, 1:]
        four = (a == d) & (b == c) & (a != b)
        if not every:
            four &= tip[:-1, :-1] & tip[:-1, 1:] & tip[1:, :-1] & tip[1:, 1:]
        rows, cols = np.nonzero(four)
        if not len(rows):
            break
        # blocks next to each other share pixels: each pass takes those two apart or more
        keep = np.ones(len(rows), dtype=bool)
        taken = np.zeros(L.shape, dtype=bool)
        for n, (r, c0) in enumerate(zip(rows.tolist(), cols.tolist())):  # a few per picture
            if taken[r : r + 2, c0 : c0 + 2].any():
                keep[n] = False
            taken[r : r + 2, c0 : c0 + 2] = True
        L[rows[keep], cols[keep] + 1] = L[rows[keep], cols[keep]]
    return L


def region_polygons(
    labels: np.ndarray,
    tolerance_px: float | None = None,
    extra_lines=(),
    straighten: str = "douglas-peucker",
    corners: bool = False,
):
    """The regions of a label image as polygons with straight, shared boundaries.

    The pixel boundaries between regions (and the background) are merged into lines between
    junctions (``shapely.line_merge``), each line is simplified on its own with its ends kept
    (pixel staircases become straight), and the lines are polygonized again.  Neighbours thus
    share one simplified boundary.

    Parameters
    ----------
    labels : (H, W) int
        Region index per pixel, -1 for the background; the image spans ``[-1, 1]^2``.
    tolerance_px : float, optional
        Douglas-Peucker's tolerance (default 0.75 pixels), or how far the step midpoints of a
        straight run may lie from its line (default 0.6 pixels; a digitized edge's lie within
        0.5).
    straighten : {"douglas-peucker", "fit"}
        ``"douglas-peucker"`` (:func:`_douglas_peucker`): the unit steps' midpoints
        simplified; its chord between two midpoints strays up to a pixel from the edge, so a
        pixel step of a long edge may stay as a corner (a notch where it turns inward).
        ``"fit"`` (:func:`_straighten`): straight runs of the midpoints, each given its line
        (along the figure's own edge directions where the run fits one), corners where
        neighbouring lines cross: the corners to a fraction of a pixel and never a pixel step,
        at any resolution and pixel phase.  Not the default: on the box model ``stairs``
        (:mod:`meschers_igl.inverse.models`) the lift's period comes 6-7% short with it at
        128 pixels (4-6% with Douglas-Peucker), 21-22% at 256 and 17% at 512 (18-27%,
        22-24%), for four of six lights; the hidden-line rules (:mod:`.occlusion`) draw one straight line where a
        flight's turn hides a staircase of edges, and the error follows that, not the
        outline.
    corners : bool
        Make a face's thin tip that crosses a pixel corner whole first
        (:func:`_tips_through_corners`), as the pieces a mescher is lifted on need; the lines
        a frame is read from (:func:`.faces.split_shared_shade`) and a drawing's regions keep
        the pixels as they are.
    extra_lines : sequence of shapely LineString
        More boundaries inside regions (hidden occlusion lines, :func:`hidden_occlusions`):
        they split the pieces they cross and become constraints too.

    Returns
    -------
    polygons : list of shapely Polygon
        The pieces, each inside one region.
    region : (P,) int64
        Each piece's region: the majority label of the pixel centres it holds.
    lines : list of shapely LineString
        The simplified boundary lines (constraints of the triangulation).
    """
    import shapely

    H, W = labels.shape
    if H != W:
        raise MescherError(f"labels: expected a square image, found {labels.shape}")
    px = pixel_to_screen(W)
    if corners:
        labels = _tips_through_corners(labels)
    K = int(labels.max()) + 1
    regions = [shapely.union_all(_pixel_boxes(labels == k)) for k in range(K)]
    edges = shapely.union_all([shapely.boundary(r) for r in regions])
    merged = shapely.line_merge(edges)
    lines = [g for g in getattr(merged, "geoms", [merged])]
    if straighten == "douglas-peucker":
        tol = 0.75 if tolerance_px is None else tolerance_px
        lines = [_douglas_peucker(g, px, tol) for g in lines]
    elif straighten == "fit":
        tol = 0.6 if tolerance_px is None else tolerance_px
        split = [_split(g, px, tol) for g in lines]
        dirs = _dominant_directions([r for r in split if r is not None])
        lines = [
            g if r is None else shapely.LineString(_straighten(r, tol, dirs) * px)
            for g, r in zip(lines, split)
        ]
    else:
        raise MescherError(f"straighten: expected 'douglas-peucker' or 'fit', found {straighten!r}")
    lines += list(extra_lines)
    # straightened neighbours may cross: node them again so that every piece closes
    lines = list(shapely.get_parts(shapely.union_all(lines)))
    pieces = list(shapely.get_parts(shapely.polygonize(lines)))
    # the label of each piece: majority of the pixel centres inside it
    c = -1.0 + (2.0 * np.arange(W) + 1.0) / W
    X, Y = np.meshgrid(c, -c)
    region = np.full(len(pieces), -1, dtype=np.int64)
    for i, poly in enumerate(pieces):
        x0, y0, x1, y1 = poly.bounds
        sel = (X >= x0) & (X <= x1) & (Y >= y0) & (Y <= y1)
        inside = shapely.contains_xy(poly, X[sel], Y[sel])
        lab = labels[sel][inside]
        if lab.size:  # background counts too: a hole stays a hole
            region[i] = np.bincount(lab + 1).argmax() - 1
    keep = region >= 0
    return [p for p, k in zip(pieces, keep) if k], region[keep], lines


def _douglas_peucker(line, px: float, tolerance_px: float):
    """A pixel staircase made straight: midpoints of its unit steps, then Douglas-Peucker.

    The corners of a digital line stray up to a pixel from it; the midpoints of its unit
    steps stray at most half a pixel and alternate around it, so a tolerance under a pixel
    leaves one segment per straight boundary.  The ends (junctions) are kept.
    """
    import shapely

    c = np.asarray(shapely.segmentize(line, px * 1.0001).coords)
    closed = bool(np.allclose(c[0], c[-1]))
    if len(c) > 3:
        mid = 0.5 * (c[1:] + c[:-1])
        c = np.vstack([mid, mid[:1]]) if closed else np.vstack([c[:1], mid, c[-1:]])
    return shapely.simplify(shapely.LineString(c), tolerance_px * px, preserve_topology=False)


def _thickness(P: np.ndarray) -> float:
    """Half the thickness of the thinnest strip holding the points ``P`` (pixel units), measured
    along the image axis nearer the strip's normal.

    The midpoints of the unit steps of a digitized straight edge lie within half a pixel of the
    edge along that axis (each step separates two pixel centres the edge passes between), so
    such a run measures at most 0.5; a corner of the edge makes the run thicker.
    """
    import shapely

    if len(P) <= 2:
        return 0.0
    hull = shapely.convex_hull(shapely.multipoints(P))
    if not isinstance(hull, shapely.Polygon):
        return 0.0  # collinear
    H = np.asarray(hull.exterior.coords)
    e = np.diff(H, axis=0)
    n = np.stack([-e[:, 1], e[:, 0]], 1) / np.linalg.norm(e, axis=1, keepdims=True)
    proj = H[:-1] @ n.T  # (m, m): every hull vertex against every edge normal
    # the thinnest strip has a hull edge on its side (rotating calipers)
    return float((np.ptp(proj, axis=0) / np.abs(n).max(axis=1)).min() / 2.0)


def _runs(P: np.ndarray, tol: float, window: int = 6) -> list[int]:
    """Break indices ``0 = b_0 < ... < b_k = len(P) - 1``: runs ``P[b_i : b_{i+1} + 1]`` each within
    ``tol`` of a line (:func:`_thickness`), split where they stray most from their chord;
    each break then moves (up to ``window`` points) to where its two runs are thinnest, and
    neighbours merge while the merged run stays that straight."""
    out, todo = [], [(0, len(P) - 1)]
    while todo:  # split: Douglas-Peucker's point, the straight-strip test
        i, j = todo.pop()
        if j - i < 2 or _thickness(P[i : j + 1]) <= tol:
            out.append(i)
            continue
        d = P[j] - P[i]
        L = np.linalg.norm(d)
        w = P[i + 1 : j] - P[i]
        dist = np.abs(w[:, 0] * d[1] - w[:, 1] * d[0]) / L if L > 0 else np.linalg.norm(w, axis=1)
        k = i + 1 + int(np.argmax(dist))
        todo += [(k, j), (i, k)]
    b = sorted(out) + [len(P) - 1]
    for _ in range(3):
        b = _merge(P, b, tol)
        for m in range(1, len(b) - 1):  # Douglas-Peucker's point is off a blunt corner's tip
            i, k, j = b[m - 1], b[m], b[m + 1]
            ks = np.arange(max(i + 1, k - window), min(j - 1, k + window) + 1)
            worst = [max(_thickness(P[i : q + 1]), _thickness(P[q : j + 1])) for q in ks]
            b[m] = int(ks[np.argmin(np.round(worst, 9) + 1e-12 * np.abs(ks - k))])
    return _merge(P, b, tol)


def _merge(P: np.ndarray, b: list[int], tol: float) -> list[int]:
    """Breaks ``b`` less those between two runs that together stay within ``tol``."""
    b = list(b)
    merged = True
    while merged and len(b) > 2:
        merged = False
        for m in range(1, len(b) - 1):
            if _thickness(P[b[m - 1] : b[m + 1] + 1]) <= tol:
                del b[m]
                merged = True
                break
    return b


def _dominant_directions(runs, min_px: float = 6.0, share: float = 0.1, bin_deg: float = 2.0):
    """(D,) angles (radians, modulo pi) the long runs of all lines take most: the screen
    directions of the figure's edges.  Each run of at least ``min_px`` pixels votes its length
    for its least-squares direction; a direction is a peak of the votes (bins of ``bin_deg``
    degrees, smoothed over three) holding ``share`` of them."""
    ang, w = [], []
    for P, b, *_ in runs:
        for i0, i1 in zip(b[:-1], b[1:]):
            L = float(np.linalg.norm(P[i1] - P[i0]))
            if L >= min_px:
                u = _line_fit(P[i0 : i1 + 1])[1]
                ang.append(math.atan2(u[1], u[0]) % math.pi)
                w.append(L)
    if not w:
        return np.zeros(0)
    nb = int(round(180.0 / bin_deg))
    h = np.bincount((np.asarray(ang) / math.pi * nb).astype(np.int64) % nb, w, minlength=nb)
    hs = h + np.roll(h, 1) + np.roll(h, -1)
    peak = (hs >= np.roll(hs, 1)) & (hs > np.roll(hs, -1)) & (hs >= share * h.sum())
    out = []
    for k in np.nonzero(peak)[0]:  # the votes' circular mean over the peak's three bins
        sel = np.abs(((np.asarray(ang) / math.pi * nb - k - 0.5 + nb / 2) % nb) - nb / 2) <= 1.5
        z = np.sum(np.asarray(w)[sel] * np.exp(2j * np.asarray(ang)[sel]))
        out.append((np.angle(z) / 2.0) % math.pi)
    return np.asarray(out)


def _line_fit(P: np.ndarray, dirs=(), tol: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """The line of a run: a point on it and its unit direction.

    Of the ``dirs`` (angles) the run's points fit within ``tol`` (:func:`_thickness`'s measure),
    the one nearest its total-least-squares direction, through their mean; else the
    least-squares line.  A run of a few pixels fits a wide fan of directions (three
    midpoints: about 15 degrees), and the figure's own edge direction pins it.
    """
    c = P.mean(axis=0)
    if len(P) < 2:
        return c, np.array([1.0, 0.0])
    _, _, vt = np.linalg.svd(P - c, full_matrices=False)
    u = vt[0]
    if len(dirs):
        D = np.stack([np.cos(dirs), np.sin(dirs)], 1)
        N = np.stack([-D[:, 1], D[:, 0]], 1)
        proj = P @ N.T  # (n, D)
        fits = np.ptp(proj, axis=0) / np.abs(N).max(axis=1) / 2.0 <= tol
        if fits.any():
            return c, D[np.nonzero(fits)[0][np.argmax(np.abs(D[fits] @ u))]]
    return c, u


def _off(Q: np.ndarray, fit) -> np.ndarray:
    """How far the points ``Q`` lie off the line ``fit = (point, direction)``, along the image
    axis nearer its normal (:func:`_thickness`'s measure)."""
    c, u = fit
    n = np.array([-u[1], u[0]])
    return np.abs((Q - c) @ n) / np.abs(n).max()


def _meet(c0, u0, c1, u1, near: np.ndarray, reach: float, min_sin: float = 0.1):
    """Where two fitted lines cross, if they cross at an angle (``|sin| > min_sin``) within
    ``reach`` of one of the points ``near`` (k, 2); else the projections of their mean on
    each (a jog between parallel runs)."""
    den = u0[0] * u1[1] - u0[1] * u1[0]
    if abs(den) > min_sin:
        w = c1 - c0
        X = c0 + ((w[0] * u1[1] - w[1] * u1[0]) / den) * u0
        if np.linalg.norm(near - X, axis=1).min() <= reach:
            return [X]
    q = near.mean(axis=0)
    return [c0 + ((q - c0) @ u0) * u0, c1 + ((q - c1) @ u1) * u1]


def _split(line, px: float, tolerance_px: float):
    """A boundary line's unit-step midpoints (pixel units) cut into straight runs: ``(P, b,
    closed, c)`` (:func:`_runs`; ``c`` the pixel corners); None for a line of a few steps."""
    import shapely

    c = np.asarray(shapely.segmentize(line, px * 1.0001).coords) / px
    if len(c) <= 3:
        return None
    closed = bool(np.allclose(c[0], c[-1]))
    P = 0.5 * (c[1:] + c[:-1])
    if not closed:
        return P, _runs(P, tolerance_px), closed, c
    # a closed line: runs found from the middle of its longest run (a break at the start could
    # not move), then started at a corner they found
    P = P[:-1]
    n = len(P)
    for _ in range(2):
        b = _runs(np.vstack([P, P[:1]]), tolerance_px)
        m = int(np.argmax(np.diff(b)))
        P = np.roll(P, -((b[m] + b[m + 1]) // 2), axis=0)
    b = _runs(np.vstack([P, P[:1]]), tolerance_px)
    if len(b) < 3:
        return None
    if _thickness(np.vstack([P[b[-2] :], P[: b[1] + 1]])) <= tolerance_px:
        b = b[:-1]  # the start is no corner: the last run goes on into the first
    s = b[1]
    b = [q - s for q in b[1:]] + [n]  # the start, n - s, where it is a corner
    P = np.roll(P, -s, axis=0)
    P = np.vstack([P, P[:1]])
    return P, sorted(set(b)), closed, c


def _straighten(split, tolerance_px: float, dirs=()):
    """A pixel staircase (:func:`_split`) as straight runs fitted with sub-pixel accuracy.

    The midpoints of the unit steps lie within half a pixel of the digitized edge (along the
    nearer image axis); each run of them within ``tolerance_px`` of one line gets its line
    (:func:`_line_fit`, along one of ``dirs`` where it fits) and a corner is where
    neighbouring lines cross.  A pixel step of a straight edge is thus never a corner, as it is
    for Douglas-Peucker on the midpoints, whose chord between two midpoints strays up to a
    pixel from the edge.  The ends of an open line (junctions, pixel corners) are kept.

    Returns
    -------
    (k, 2) float64
        The straight line's points, pixel units (a closed line's last is its first).
    """
    P, b, closed, c = split
    # each run: its points' range, its line, the points its corners are sought near
    runs = [
        [i0, i1, _line_fit(P[i0 : i1 + 1], dirs, tolerance_px), i0, i1]
        for i0, i1 in zip(b[:-1], b[1:])
    ]
    k = 0 if closed else 1
    while k < len(runs) - (0 if closed else 1) and len(runs) > 3:
        # a run at a corner of a digitized corner (the flat row at a sharp corner's tip):
        # its points lie on one of its neighbours' lines, which cross there
        prev, (i0, i1, *_), nxt = runs[k - 1], runs[k], runs[(k + 1) % len(runs)]
        Q = P[i0 : i1 + 1]
        if np.all(np.minimum(_off(Q, prev[2]), _off(Q, nxt[2])) <= tolerance_px) and (
            len(_meet(*prev[2], *nxt[2], Q, 2.0)) == 1
        ):
            prev[4], nxt[3] = i0, i1
            del runs[k]
            k = max(k - 1, 0 if closed else 1)
            continue
        k += 1

    def near(r0, r1):  # the points between two runs, the run taken out between them
        return P[r0[4] : r1[3] + 1] if r0[4] <= r1[3] else P[[r0[4], r1[3]]]

    pts = []
    for r0, r1 in zip(runs[:-1], runs[1:]):
        pts += _meet(*r0[2], *r1[2], near(r0, r1), 2.0)
    if closed:
        ends = _meet(*runs[-1][2], *runs[0][2], near(runs[-1], runs[0]), 2.0)
        pts = ends[-1:] + pts + ends[-1:] if len(ends) == 1 else ends[1:] + pts + ends
        return np.asarray(pts)
    return np.asarray([c[0]] + pts + [c[-1]])


def node_constraints(chains, grid: float) -> tuple[np.ndarray, np.ndarray]:
    """The vertices and segments of polylines, snap-rounded to ``grid`` and noded.

    A constrained triangulation needs a planar straight-line graph: segments that meet only at
    shared vertices.  Boundaries traced from a picture may leave a vertex a rounding error off
    another segment (a T-junction the segment does not know of), or two segments crossing;
    Triangle's quality refinement can then crash the process (a segfault, which no ``try``
    catches).  Snap rounding (GEOS through ``shapely.unary_union(..., grid_size=grid)``) moves
    every vertex to the grid, merges vertices of one grid cell and splits every segment at each
    vertex and crossing it passes within the grid: the result is a planar graph whose segments
    cover the input's to within ``grid``.

    Parameters
    ----------
    chains : sequence of (k_i, 2) array_like
        Polylines (screen units); those with fewer than two points are ignored.
    grid : float
        The snapping grid (``> 0``; e.g. a thousandth of a pixel).

    Returns
    -------
    verts : (#V, 2) float64
        Distinct vertices on the grid.
    segs : (#S, 2) int64
        Sorted vertex pairs, each once, no segment of length 0.
    """
    import shapely

    if not (np.isfinite(grid) and grid > 0):
        raise MescherError(f"grid: expected a positive number, found {grid}")
    lines = [shapely.linestrings(np.asarray(c, dtype=np.float64)) for c in chains if len(c) >= 2]
    if not lines:
        return np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64)
    noded = shapely.unary_union(shapely.multilinestrings(lines), grid_size=grid)
    coords, part = shapely.get_coordinates(shapely.get_parts(noded), return_index=True)
    within = part[1:] == part[:-1]  # consecutive points of one line: a segment
    a, b = coords[:-1][within], coords[1:][within]
    key = np.round(np.concatenate([a, b]) / grid).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inv = inv.reshape(-1)
    verts = np.concatenate([a, b])[first]
    segs = np.sort(np.stack([inv[: len(a)], inv[len(a) :]], axis=1), axis=1)
    segs = np.unique(segs[segs[:, 0] != segs[:, 1]], axis=0)
    return verts, segs.astype(np.int64)
