"""Cutting a picture's mesh open where one surface passes in front of another.

:func:`meschers_igl.inverse.picture.mescher_from_picture` cuts its triangulation along the
occlusions it reads before the lift, so that each side keeps its own depth.  The cuts must not
cut the surface apart: a loop that carries the figure's period runs round the outline or a
hole, so visible occlusions stop short of the outline (:func:`_off_outline`), a hidden line
touches the boundary at most once per piece of the cut (:func:`_one_contact`), and slits that
end a pixel or two short of a hole run on to it (:func:`_to_holes`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["cut_along"]


def _off_outline(F: np.ndarray, xy: np.ndarray, edges: np.ndarray, cut: np.ndarray):
    """The cut edges without a vertex on the figure's outline (its outer boundary loop).

    An occlusion line that reaches the outline in the picture ends, on the real figure, at a
    corner of the face passing in front, with a sliver of that face between the corner and the
    outline (the Penrose tribar's cap); at 64-160 pixels the sliver is sometimes lost.  Cuts
    therefore stop one edge short of the outline, which stays one closed loop of the surface:
    the loop the figure's period is measured on (:func:`.metrics.figure_period`).  Cuts may
    open onto holes.
    """
    from ..topology import boundary_loops

    loops = boundary_loops(F)
    if cut.size == 0 or not loops:
        return cut
    area = []
    for lp in loops:  # shoelace: a handful of loops
        p, q = xy[lp], xy[np.roll(lp, -1)]
        area.append(float((p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]).sum()))
    outline = np.zeros(len(xy), dtype=bool)
    outline[loops[int(np.argmax(area))]] = True
    return cut[~outline[edges[cut]].any(axis=1)]


def _split_near_outline(chains, outline, pixel: float, at_px: float = 1.5):
    """Boundary chains with a vertex ``at_px`` pixels from each end on the figure's outline.

    A cut along an occlusion stops one edge short of the outline (:func:`_off_outline`); the
    triangulation keeps a long straight constraint as one edge, so without this vertex a cut
    could stop tens of pixels short and the surface would stay whole across the hidden step.
    Chains on the outline itself are left alone.
    """
    import shapely

    out = []
    d = at_px * pixel
    for c in chains:  # a few dozen chains
        if len(c) < 2 or shapely.LineString(c).hausdorff_distance(outline) < 1e-9:
            out.append(c)
            continue
        if shapely.distance(shapely.LineString(c), outline) > 1e-9:
            out.append(c)
            continue
        split = c
        for end, nxt in ((0, 1), (-1, -2)):
            seg = c[nxt] - c[end]
            L = float(np.linalg.norm(seg))
            if L > 2.0 * d and shapely.distance(shapely.Point(c[end]), outline) < 1e-9:
                q = c[end] + seg * (d / L)
                if end == 0:
                    split = np.vstack([split[:1], q, split[1:]])
                else:
                    split = np.vstack([split[:-1], q, split[-1:]])
        out.append(split)
    return out


def _on_boundary(F: np.ndarray, n: int) -> np.ndarray:
    """(n,) bool: the vertices on the mesh's boundary loops (outline and holes)."""
    from ..topology import boundary_loops

    on = np.zeros(n, dtype=bool)
    for lp in boundary_loops(F):
        on[lp] = True
    return on


def cut_along(xy: np.ndarray, F: np.ndarray, edges: np.ndarray, cut: np.ndarray):
    """Cut a triangle mesh open along some of its edges (``igl.cut_mesh``).

    Parameters
    ----------
    xy : (#V, 2) float
    F : (#F, 3) int
    edges : (#E, 2) int
        All edges (any orientation).
    cut : (C,) int
        Indices into ``edges`` of the edges to cut.

    Returns
    -------
    xy : (#V', 2) float64
    F : (#F, 3) int64
        Same faces, cut vertices duplicated (a vertex keeps one copy per side).
    """
    import igl

    n = len(xy)
    key = np.sort(edges[cut], axis=1)
    keys = set((key[:, 0] * n + key[:, 1]).tolist())
    a, b = F, F[:, [1, 2, 0]]  # igl: column i is the edge F[i] -> F[i + 1]
    k = np.minimum(a, b) * n + np.maximum(a, b)
    C = np.isin(k, np.fromiter(keys, dtype=np.int64, count=len(keys)))
    if not C.any():
        return np.asarray(xy, dtype=np.float64), np.asarray(F, dtype=np.int64)
    V = np.column_stack([xy, np.zeros(n)])
    Vc, Fc, _ = igl.cut_mesh(V, np.asarray(F, dtype=np.int64), C)
    # a cut through a vertex whose faces all stay on one side leaves a copy no face uses
    Fc = np.asarray(Fc, dtype=np.int64)
    used = np.unique(Fc)
    remap = np.full(len(Vc), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return np.ascontiguousarray(np.asarray(Vc)[used, :2]), remap[Fc]


def _one_contact(F: np.ndarray, edges: np.ndarray, cut: np.ndarray, lines: list) -> np.ndarray:
    """``cut`` and the edges of each of ``lines`` (index arrays into ``edges``, in turn), each
    line without its edges on the boundary (outline or holes) where its piece of the cut
    touches the boundary already.

    A connected cut that meets the boundary twice would cut the surface apart (from a hole to
    the outline: the loop that carries the figure's period); one contact only opens it.  A
    line that joins two pieces of the cut that touch the boundary already is left out.
    """
    import scipy.sparse.csgraph as csgraph

    on = _on_boundary(F, len(edges) and int(edges.max()) + 1)
    cut = np.asarray(cut, dtype=np.int64)

    def contacts(ln):  # boundary vertices on the cut's pieces that ln joins
        both = np.union1d(cut, ln)
        e = edges[both]
        G = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(len(on),) * 2)
        _, comp = csgraph.connected_components(G, directed=False)
        mine = np.isin(comp, comp[edges[ln].ravel()])
        return np.count_nonzero(on & mine & (np.bincount(e.ravel(), minlength=len(on)) > 0))

    for ln in lines:  # a dozen lines
        if ln.size and contacts(ln) > 1:
            ln = ln[~on[edges[ln]].any(axis=1)]
            if ln.size and contacts(ln) > 1:  # it joins two pieces that touch already
                continue
        cut = np.union1d(cut, ln)
    return cut


def _to_holes(
    F: np.ndarray, xy: np.ndarray, edges: np.ndarray, cut: np.ndarray, seen, reach: float
) -> list:
    """Paths that run slits of the cut on to a hole: per tip, the mesh edges (indices into
    ``edges``) of the shortest path from it to a hole's outline, where that is within
    ``reach`` (screen units along the edges).

    A *slit* is a piece of the cut (two edges at least: a lone interior edge opens nothing)
    that touches no boundary; its tips taken are those of visible occlusions (``seen``), not
    of hidden lines.  An occlusion runs on to the hole's corner where it ends, but its last
    pixel or two may follow a crease's direction on screen (a pixel staircase) and go
    unflagged: the cut stops short, and the slit's loop holds part of the step the hole's
    loop should climb (the impossible cube's front bar over the back bar, both bar faces
    along it at the ambient shade: 0.21 of the step 1.41, the hole's loop 1.20).  The outline
    is left out: cuts stop short of it on purpose (:func:`_off_outline`).
    """
    import scipy.sparse.csgraph as csgraph

    from ..topology import boundary_loops

    cut = np.asarray(cut, dtype=np.int64)
    loops = boundary_loops(F)
    if cut.size == 0 or len(loops) < 2:
        return []
    n = len(xy)
    area = [  # the outline encloses the holes: the largest |area|, either orientation
        abs(float((xy[lp, 0] * xy[np.roll(lp, -1), 1] - xy[np.roll(lp, -1), 0] * xy[lp, 1]).sum()))
        for lp in loops
    ]
    on = np.zeros(n, dtype=bool)
    for lp in loops:
        on[lp] = True
    hole = np.zeros(n, dtype=bool)
    for k, lp in enumerate(loops):
        if k != int(np.argmax(area)):
            hole[lp] = True
    deg = np.bincount(edges[cut].ravel(), minlength=n)
    ok = np.zeros(n, dtype=bool)
    ok[edges[seen].ravel()] = True
    ok[edges[np.setdiff1d(cut, seen)].ravel()] = False
    # slits: pieces of the cut that touch no boundary and open (two edges at least: a lone
    # interior edge cuts nothing)
    e = edges[cut]
    C = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    _, comp = csgraph.connected_components(C, directed=False)
    n_edges = np.bincount(comp[e[:, 0]], minlength=n)
    slit = (n_edges >= 2) & ~np.isin(np.arange(n), comp[on & (deg > 0)])
    tips = np.nonzero((deg == 1) & ~on & ok & slit[comp])[0]
    if tips.size == 0:
        return []
    L = np.linalg.norm(xy[edges[:, 1]] - xy[edges[:, 0]], axis=1)
    G = sp.coo_matrix((L, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    dist, pred = csgraph.dijkstra(
        G, directed=False, indices=tips, limit=reach, return_predecessors=True
    )
    key = {(int(min(a, b)), int(max(a, b))): e for e, (a, b) in enumerate(edges.tolist())}
    out = []
    for t in range(len(tips)):  # a handful of tips
        d = np.where(hole, dist[t], np.inf)
        v = int(np.argmin(d))
        if not np.isfinite(d[v]):
            continue
        path = []
        while v != tips[t]:
            u = int(pred[t, v])
            path.append(key[(min(u, v), max(u, v))])
            v = u
        out.append(np.asarray(path, dtype=np.int64))
    return out


def _through_creases(
    F: np.ndarray,
    xy: np.ndarray,
    edges: np.ndarray,
    cut: np.ndarray,
    seen: np.ndarray,
    creases: np.ndarray,
    pairs: np.ndarray,
    straight_deg: float = 10.0,
) -> list:
    """The vertices where two visible occlusions end and a crease runs on straight through,
    from one side of the cut to the other, each with one of its two cut edges.

    Two occlusion lines meeting at an angle at a vertex split its fan in two.  Where the two
    sides hold the two halves of one straight crease between the same two regions, the edge
    of a box goes on through the vertex: the surfaces in front and behind meet there (a bar's
    end joined to the frame it seems to pass, as in the impossible cube), and the depth jump
    of both occlusions closes at it.  Cut through, the vertex would open the holes on its two
    sides into one (:func:`keep_junctions` keeps the surface whole there).

    Parameters
    ----------
    F : (#F, 3) int
    xy : (#V, 2) float
    edges : (#E, 2) int
    cut : (C,) int
        Indices into ``edges``.
    seen : (S,) int
        The cut's visible occlusions (indices into ``edges``): both edges at the vertex are.
    creases : (K,) int
        Indices into ``edges`` of the region boundaries not cut.
    pairs : (K, 2) int
        The two regions of each crease, sorted.
    straight_deg : float
        How far from a straight line the crease's two halves may turn.

    Returns
    -------
    list of (vertex, edge)
    """

    cut, creases, pairs = (np.asarray(a, dtype=np.int64) for a in (cut, creases, pairs))
    n = len(xy)
    if cut.size < 2 or creases.size < 2:
        return []
    on = _on_boundary(F, n)
    deg = np.bincount(edges[cut].ravel(), minlength=n)
    cdeg = np.bincount(edges[creases].ravel(), minlength=n)
    cos_straight = -np.cos(np.radians(straight_deg))

    def away(e, v):  # (k,) angles and (k, 2) unit directions of the edges e leaving v
        o = np.where(edges[e, 0] == v, edges[e, 1], edges[e, 0])
        d = xy[o] - xy[v]
        return np.arctan2(d[:, 1], d[:, 0]), d / np.linalg.norm(d, axis=1, keepdims=True)

    out = []
    for v in np.nonzero((deg == 2) & (cdeg >= 2) & ~on)[0]:  # a handful of junctions
        ce = cut[(edges[cut] == v).any(axis=1)]
        a_c, u_c = away(ce, v)
        if not np.isin(ce, seen).all() or float(u_c[0] @ u_c[1]) < cos_straight:
            continue  # a hidden line's, or one occlusion going on straight
        at = (edges[creases] == v).any(axis=1)
        a_k, u_k = away(creases[at], v)
        lo, hi = np.sort(a_c)
        side = (a_k > lo) & (a_k < hi)  # the sector of the fan each crease lies in
        kp = pairs[at]
        i, j = np.triu_indices(len(a_k), 1)
        through = (
            (side[i] != side[j])
            & (kp[i] == kp[j]).all(axis=1)
            & ((u_k[i] * u_k[j]).sum(axis=1) < cos_straight)
        )
        if through.any():
            out.append((int(v), int(ce[0])))
    return out


def _split_at(xy, F, region, edges, v: int, e: int, length: float):
    """Split edge ``e`` (one end ``v``) ``length`` from ``v``, its two faces in four: the
    arrays with the new vertex, faces (their parents' regions) and edges appended, ``e`` now
    naming the piece at ``v``; and the index of the piece away from ``v``."""
    a, b = edges[e]
    o = b if a == v else a
    t = length / float(np.linalg.norm(xy[o] - xy[v]))
    m = len(xy)
    xy = np.vstack([xy, xy[v] + t * (xy[o] - xy[v])])
    new_F, new_reg, new_e = [], [], [(m, o)]
    F = F.copy()
    for f in np.nonzero((F == v).any(axis=1) & (F == o).any(axis=1))[0]:  # two faces
        row = F[f].copy()
        new_F.append(np.where(row == v, m, row))  # (m, o, c) in the face's order
        F[f] = np.where(row == o, m, row)  # (v, m, c)
        new_reg.append(region[f])
        new_e.append((m, int(row[(row != v) & (row != o)][0])))
    edges = np.vstack([edges, new_e])
    edges[e] = (v, m)
    F = np.vstack([F, np.asarray(new_F, dtype=F.dtype).reshape(-1, 3)])
    region = np.concatenate([region, np.asarray(new_reg, dtype=region.dtype)])
    return xy, F, region, edges, len(edges) - len(new_e)


def keep_junctions(xy, F, region, edges, cut, seen, ids, pairs, length: float):
    """The cut less a piece ``length`` long at each vertex where two occlusions end and a
    crease runs on through (:func:`_through_creases`): the surface stays whole there.

    The cut edge at such a vertex is split ``length`` from it (its two faces in four) and the
    piece at the vertex left whole: the surfaces are glued over that length only, where the
    occlusions' depth jump is near zero (a whole edge, up to 16 pixels long on a straight
    boundary, shifts the period by 5%).

    Parameters
    ----------
    xy : (#V, 2) float
    F : (#F, 3) int
    region : (#F,) int
    edges : (#E, 2) int
    cut, seen : (C,) int, (S,) int
        The edges to cut and the visible occlusions among them (indices into ``edges``).
    ids : (B,) int
        The region boundaries (indices into ``edges``); ``pairs`` (B, 2) their regions.
    length : float
        Screen units.

    Returns
    -------
    xy, F, region, edges, cut
        Old vertex, face and edge indices kept; new ones appended.
    """
    cut = np.asarray(cut, dtype=np.int64)
    whole = ~np.isin(ids, cut)
    at = _through_creases(F, xy, edges, cut, seen, ids[whole], pairs[whole])
    xy, F, region, edges = (np.asarray(a) for a in (xy, F, region, edges))
    for v, e in at:  # a handful of junctions
        if v not in edges[e] or e not in cut:  # one cut edge between two junctions: split once
            continue
        L = float(np.linalg.norm(np.diff(xy[edges[e]], axis=0)))
        cut = cut[cut != e]
        if L > 2.0 * length:
            xy, F, region, edges, far = _split_at(xy, F, region, edges, v, e, length)
            cut = np.append(cut, far)
    return xy, F, region, edges, cut
