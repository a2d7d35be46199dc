"""Hidden-surface removal by exact 2D clipping (``shapely`` on a fixed grid) and the visible
map: the clipped pieces triangulated (``triangle``), near points merged, T-junctions split."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from ..errors import MescherError
from ..geometry2d import overlapping_pairs

#: Relative tolerance (of the model's bounding-box diagonal) for screen coincidence and depth
#: continuity: float32 coordinates are off by ~1e-7 of the size; gaps of 1e-5 are noise.
REL_TOL = 1e-5
#: Grid of every shapely overlay, relative to the model's size (exact shared coordinates).
REL_GRID = 1e-9
#: A period counts only above this share of the model's size: the conversion glues within
#: 1e-5 of the size per vertex, and a loop crosses a junction a handful of times.
PERIOD_RTOL = 1e-4


#: A face faces the viewer when its unit normal has n_z above this (edge-on faces are hidden).
FRONT_NZ = 1e-6


# ------------------------------------------------------------------------------ planar map
def face_planes(C: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(#F, 3) depth plane ``z = a x + b y + c`` of each (front-facing) face."""
    T = C[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    a = -n[:, 0] / n[:, 2]
    b = -n[:, 1] / n[:, 2]
    c = T[:, 0, 2] - a * T[:, 0, 0] - b * T[:, 0, 1]
    return np.stack([a, b, c], axis=1)


def plane_depth(P: np.ndarray, pl: np.ndarray) -> np.ndarray:
    return pl[..., 0] * P[..., 0] + pl[..., 1] * P[..., 1] + pl[..., 2]


def polygonal_only(g: np.ndarray) -> np.ndarray:
    """Keep the polygons of overlay results (grid snapping can leave collapsed lines or points
    in a collection, which the next overlay refuses as mixed-dimension)."""
    import shapely

    t = shapely.get_type_id(g)
    odd = np.flatnonzero((t != 3) & (t != 6) & ~shapely.is_empty(g))
    for k in odd.tolist():  # rare: only collections from degenerate overlaps
        parts = shapely.get_parts(g[k])
        parts = parts[np.isin(shapely.get_type_id(parts), (3, 6))]
        g[k] = shapely.union_all(parts) if parts.size else shapely.Polygon()
    return g


def clip_occluded(T: np.ndarray, pl: np.ndarray, tol: float, grid: float):
    """Visible pieces of front faces: (pieces, involved) with pieces a list of (face, polygon).

    Faces overlapping nothing are not touched (``involved`` False) and stay exact.
    """
    import shapely

    pairs, cen = overlapping_pairs(T, tol, centroids=True)
    involved = np.zeros(T.shape[0], dtype=bool)
    if pairs.shape[0] == 0:
        return [], involved
    i, j = pairs[:, 0], pairs[:, 1]
    dz = plane_depth(cen, pl[j]) - plane_depth(cen, pl[i])
    involved[i] = involved[j] = True
    # only faces that overlap something go through shapely (on the fixed grid)
    polys = np.empty(T.shape[0], dtype=object)
    inv_ids = np.flatnonzero(involved)
    polys[inv_ids] = shapely.set_precision(shapely.polygons(T[inv_ids]), grid)
    # faces that cross in 3D (interpenetrating parts): each is hidden only where the other is
    # nearer, the overlap cut along the line where their planes meet
    cross = _crossing_pairs(T, pl, i, j, tol)
    cb, cf, cocc = _crossing_occluders(polys, pl, i[cross], j[cross], dz[cross], tol, grid)
    # the farther face of every other overlapping pair is clipped by the nearer one
    keep = (np.abs(dz) > tol) & ~cross  # coplanar overlaps: neither hides the other
    back = np.r_[np.where(dz > 0, i, j)[keep], cb]
    front = np.r_[np.where(dz > 0, j, i)[keep], cf]
    occ = np.empty(back.size, dtype=object)
    occ[: back.size - cb.size] = polys[front[: back.size - cb.size]]
    occ[back.size - cb.size :] = cocc
    # visible part = face minus each face in front of it, one vectorised GEOS pass per rank
    # (the k-th occluder of every face at once): no Python loop over faces
    order = np.argsort(back, kind="stable")
    back, occ = back[order], occ[order]
    starts = np.flatnonzero(np.r_[True, back[1:] != back[:-1]])
    rank = np.arange(back.size) - np.repeat(starts, np.diff(np.r_[starts, back.size]))
    vis = polys.copy()
    for r in range(int(rank.max(initial=-1)) + 1):  # as many passes as the most occluders
        sel = rank == r
        b = back[sel]
        vis[b] = polygonal_only(shapely.difference(vis[b], occ[sel], grid_size=grid))
    pieces = [(int(f), vis[f]) for f in inv_ids.tolist()]
    return pieces, involved


def _crossing_pairs(T, pl, i, j, tol) -> np.ndarray:
    """(k,) bool: overlapping pairs whose depth difference may change sign where they overlap.

    ``T`` (n, 3, 2) screen triangles, ``pl`` their depth planes.  ``z_j - z_i`` is affine on
    the screen, so on each triangle it ranges between its values at the corners; the overlap
    lies in both, so a sign change there needs both ranges to hold values beyond ``tol`` on
    either side.
    """
    coef = (pl[j] - pl[i])[:, None, :]  # z_j - z_i = coef . (x, y, 1)
    di, dj = plane_depth(T[i], coef), plane_depth(T[j], coef)
    lo = np.maximum(di.min(axis=1), dj.min(axis=1))
    hi = np.minimum(di.max(axis=1), dj.max(axis=1))
    return (lo < -tol) & (hi > tol)


def _crossing_occluders(polys, pl, i, j, dzc, tol, grid):
    """For faces ``i``, ``j`` that may cross in 3D: (back, front, occluder polygon) entries,
    ``i`` hidden by the part of the overlap where ``j`` is nearer and ``j`` by the rest.  Pairs
    whose overlap after all lies on one side are one entry, the nearer face hiding the other;
    an overlap grid snapping leaves without area is left to the depths at its centroid
    (``dzc = z_j - z_i`` there), as any overlapping pair."""
    import shapely

    back, front, occ = [], [], []
    if i.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, dtype=object)
    over = shapely.intersection(polys[i], polys[j], grid_size=grid)
    for a, b, o, d in zip(i.tolist(), j.tolist(), over, dzc.tolist()):  # crossing: few
        o = shapely.convex_hull(o)  # two triangles overlap in a convex polygon
        coef = pl[b] - pl[a]  # z_b - z_a = coef . (x, y, 1)
        n = len(occ)
        for far, near, sign in ((a, b, 1.0), (b, a, -1.0)):
            part = _half_plane(o, sign * coef, tol)
            if part is not None:
                part = shapely.set_precision(part, grid)
                if not part.is_empty and part.area > 0:
                    back.append(far)
                    front.append(near)
                    occ.append(part)
        if len(occ) == n and abs(d) > tol:
            back.append(a if d > 0 else b)
            front.append(b if d > 0 else a)
            occ.append(polys[b if d > 0 else a])
    out = np.empty(len(occ), dtype=object)
    out[:] = occ
    return np.asarray(back, np.int64), np.asarray(front, np.int64), out


def _half_plane(poly, coef, tol):
    """The part of the convex polygon ``poly`` where ``coef . (x, y, 1) > 0`` (None if none)."""
    import shapely

    ring = np.asarray(poly.exterior.coords)[:-1] if hasattr(poly, "exterior") else None
    if ring is None or ring.shape[0] < 3:
        return None
    d = ring @ coef[:2] + coef[2]
    if np.all(d <= tol):
        return None
    if np.all(d >= -tol):
        return poly
    # Sutherland-Hodgman against one line: the corners on the positive side and the points
    # where the edges cross the line, in order (a few corners)
    out = []
    for k in range(ring.shape[0]):
        p, q, dp, dq = ring[k], ring[(k + 1) % ring.shape[0]], d[k], d[(k + 1) % ring.shape[0]]
        if dp > 0:
            out.append(p)
        if (dp > 0) != (dq > 0):
            out.append(p + (q - p) * (dp / (dp - dq)))
    return shapely.Polygon(out) if len(out) >= 3 else None


def triangulate_pieces(pieces, grid: float):
    """Constrained triangulation of the visible pieces: (P (n,2), tris (m,3), source (m,))."""
    import shapely
    import triangle as tr

    if not pieces:
        return np.zeros((0, 2)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    geoms = np.array([g for _, g in pieces], dtype=object)
    src = np.array([f for f, _ in pieces], dtype=np.int64)
    parts, idx = shapely.get_parts(geoms, return_index=True)
    polys_all = parts[shapely.get_type_id(parts) == 3]
    keepmask = shapely.area(polys_all) > grid * grid * 4
    polys = polys_all[keepmask]
    pidx = idx[shapely.get_type_id(parts) == 3][keepmask]
    if polys.size == 0:
        return np.zeros((0, 2)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    # node the boundaries on the grid (shapely splits crossing and overlapping segments), so
    # the triangulator gets a clean planar straight-line graph
    lines = shapely.union_all(shapely.boundary(polys), grid_size=grid)
    segs = shapely.get_parts(lines)
    coords, ridx = shapely.get_coordinates(segs, return_index=True)
    same = ridx[1:] == ridx[:-1]
    seg_pts = np.stack([coords[:-1][same], coords[1:][same]], axis=1)
    P, inv = np.unique(
        np.round(seg_pts.reshape(-1, 2) / grid).astype(np.int64), axis=0, return_inverse=True
    )
    P = P.astype(np.float64) * grid
    S = inv.reshape(-1, 2)
    S = S[S[:, 0] != S[:, 1]]
    S = np.unique(np.sort(S, axis=1), axis=0)
    out = tr.triangulate({"vertices": P, "segments": S}, "pQ")
    Pt = out["vertices"]
    Tt = np.asarray(out["triangles"], dtype=np.int64)
    # which visible piece each triangle lies in (pieces have disjoint interiors)
    cen = Pt[Tt].mean(axis=1)
    tree = shapely.STRtree(polys)
    qi, qp = tree.query(shapely.points(cen), predicate="within")
    source = np.full(Tt.shape[0], -1, dtype=np.int64)
    source[qi] = src[pidx[qp]]
    keep = source >= 0
    return Pt, Tt[keep], source[keep]


def merge_points(P: np.ndarray, tol: float) -> np.ndarray:
    """(n,) label of each point after merging points closer than ``tol`` (first index wins)."""
    n = P.shape[0]
    pairs = cKDTree(P).query_pairs(tol, output_type="ndarray")
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    return lab


def split_t_junctions(xy: np.ndarray, Ft: np.ndarray, src: np.ndarray, tol: float):
    """Split faces whose edges pass through other vertices (T-junctions), as fans.

    Only edges with a single incident face can carry a T-junction in a planar map; each pass
    splits one such edge per face at all vertices lying on it (within ``tol`` of it and more
    than ``tol`` along it from both ends), until none is left.
    """
    tree = cKDTree(xy)
    for _ in range(64):  # each pass removes the T-junctions of one edge per face
        he = np.stack([Ft[:, [1, 2]], Ft[:, [2, 0]], Ft[:, [0, 1]]], axis=1).reshape(-1, 2)
        key = np.minimum(he[:, 0], he[:, 1]) * xy.shape[0] + np.maximum(he[:, 0], he[:, 1])
        _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
        single = np.flatnonzero(cnt[inv] == 1)
        a, b = xy[he[single, 0]], xy[he[single, 1]]
        mid, half = 0.5 * (a + b), 0.5 * np.linalg.norm(b - a, axis=1)
        near = tree.query_ball_point(mid, half + tol)
        split: dict[int, tuple[int, list[int]]] = {}
        for s, cand in zip(single.tolist(), near):  # only boundary edges, few
            f, k = divmod(s, 3)
            if f in split:
                continue
            p, q = he[s]
            d = xy[q] - xy[p]
            L2 = float(d @ d)
            on = []
            for v in cand:
                # a face's own corners are never T-junctions of its edges: the pieces a split
                # leaves for the next pass may be thin enough for their apex to lie within
                # tol of the base, and splitting there would repeat a corner
                if v == p or v == q or v == Ft[f, k]:
                    continue
                # and a vertex within tol of an end, along the edge, is at that corner: split
                # there, a few points a tol apart split each other's edges back and forth
                w = xy[v] - xy[p]
                t = float(w @ d) / L2
                margin = tol / np.sqrt(L2)
                if margin < t < 1.0 - margin and abs(w[0] * d[1] - w[1] * d[0]) <= tol * np.sqrt(
                    L2
                ):
                    on.append((t, v))
            if on:
                split[f] = (k, [v for _, v in sorted(on)])
        if not split:
            return Ft, src
        keep = np.ones(Ft.shape[0], dtype=bool)
        newF, newS = [], []
        for f, (k, vs) in split.items():
            keep[f] = False
            c, p, q = Ft[f, k], Ft[f, (k + 1) % 3], Ft[f, (k + 2) % 3]
            chain = [p, *vs, q]
            for u, v in zip(chain[:-1], chain[1:]):
                newF.append([c, u, v])
                newS.append(src[f])
        Ft = np.vstack([Ft[keep], np.asarray(newF, dtype=np.int64)])
        src = np.concatenate([src[keep], np.asarray(newS, dtype=np.int64)])
    raise MescherError(
        "F: expected the visible map's T-junctions to resolve, found more after 64 passes"
    )


def visible_map(C: np.ndarray, F: np.ndarray, front: np.ndarray, tol_abs: float, grid: float):
    """The visible map of a model in camera coordinates ``C``: faces toward the viewer that
    overlap nothing as they are, clipped ones retriangulated; near points merged, slivers
    dropped, T-junctions split.

    Returns
    -------
    xy : (#P, 2) float64
    Fa : (#T, 3) int64
        Screen triangles, counter-clockwise.
    src : (#T,) int64
        Model face each triangle lies in.
    planes : (#F, 3) float64
        Depth plane ``z = a x + b y + c`` of each front face (zero rows elsewhere).
    """
    fid = np.flatnonzero(front)
    pl_all = np.zeros((F.shape[0], 3))
    pl_all[fid] = face_planes(C, F[fid])
    T = C[F[fid], :2]
    pieces, involved = clip_occluded(T, pl_all[fid], tol_abs, grid)
    # visible map: untouched faces as they are, clipped faces retriangulated
    Pt, Tt, st = triangulate_pieces(pieces, grid)
    quiet = fid[~involved]
    xy0 = C[:, :2]
    P = np.vstack([xy0, Pt])
    Fa = np.vstack([F[quiet], Tt + xy0.shape[0]])
    src = np.concatenate([quiet, fid[st]])
    lab = merge_points(P, tol_abs)
    usedp, Fa = np.unique(lab[Fa], return_inverse=True)
    Fa = Fa.reshape(-1, 3)
    first = np.full(usedp.size, -1)
    # the representative of a merged group: its first point (exact input positions win)
    pts = np.concatenate([F[quiet].reshape(-1), Tt.reshape(-1) + xy0.shape[0]])
    gi = np.searchsorted(usedp, lab[pts])
    first[gi[::-1]] = pts[::-1]
    xy = P[first]
    # drop faces that collapsed or lost their area to rounding (a cap whose apex lies on its
    # base edge within tol is a T-junction of the face across that edge, split there below, so
    # no hole is left)
    ok = _thick(xy, Fa, tol_abs)
    Fa, src = split_t_junctions(xy, Fa[ok], src[ok], tol_abs)
    # a T-vertex within tol of an edge but just outside its face makes fan pieces thinner than
    # tol, some turned over: a fold of zero width whose edges have four faces; dropped the same
    ok = _thick(xy, Fa, tol_abs)
    return xy, Fa[ok], src[ok], pl_all


def _thick(xy: np.ndarray, Fa: np.ndarray, tol: float) -> np.ndarray:
    """(#T,) bool: counter-clockwise triangles wider than ``tol`` across their longest edge."""
    T2 = xy[Fa]
    area2 = (T2[:, 1, 0] - T2[:, 0, 0]) * (T2[:, 2, 1] - T2[:, 0, 1]) - (
        T2[:, 2, 0] - T2[:, 0, 0]
    ) * (T2[:, 1, 1] - T2[:, 0, 1])
    longest = np.linalg.norm(T2 - T2[:, [1, 2, 0]], axis=2).max(axis=1)
    return area2 > tol * np.maximum(longest, tol)
