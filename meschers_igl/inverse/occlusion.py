"""Occlusions a picture of boxes shows, and the ones it hides between faces of one shade.

A boundary between two shade regions that does not run along their crease is an occlusion: an
edge of the face in front (:func:`occlusion_chains` tells which side that is), and so is the
crossbar of a T-junction on both sides of its stem (:func:`crossbar_occlusions`).  Where such an
edge meets a crease, the picture often stops showing it though the edge goes on, because the
face behind it changes to one of the same shade as a face next to it (a stair's tread over the
tread below).  :func:`hidden_occlusions` follows those edges on.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from .faces import _abs_sin
from .regions import labels_at


def _screen_axes(normals: np.ndarray) -> np.ndarray:
    """(K, 2) unit screen projections of the region normals (the box's edge directions)."""
    return normals[:, :2] / np.maximum(np.linalg.norm(normals[:, :2], axis=1, keepdims=True), 1e-12)


def _region_angles(xy: np.ndarray, F: np.ndarray, region: np.ndarray, K: int) -> np.ndarray:
    """(#V, K) the angle each region takes around each vertex (corner angles summed)."""
    P3 = xy[F]
    u = np.roll(P3, -1, axis=1) - P3
    w = np.roll(P3, 1, axis=1) - P3
    ang = np.abs(np.arctan2(u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0], (u * w).sum(-1)))
    key = (F * K + region[:, None]).ravel()
    return np.bincount(key, weights=ang.ravel(), minlength=len(xy) * K).reshape(len(xy), K)


def _labelled(labels: np.ndarray, E, X, lab: int, t0: float, t1: float, px: float) -> bool:
    """Whether the pixels under the segment ``E -> X`` from ``t0`` to ``t1`` (screen units along
    it) all hold region ``lab`` (an empty stretch does not)."""
    L = float(np.linalg.norm(X - E))
    t = np.arange(t0, t1, 0.5 * px)
    if t.size == 0:
        return False
    Q = E[None] + t[:, None] * ((X - E) / L)[None]
    return bool(np.all(labels_at(labels, Q) == lab))


def _between(labels, E, X, lab: int, px: float, side_px: float = 1.0) -> bool:
    """Whether ``lab``'s pixels lie on both sides of the segment ``E -> X``, ``side_px``
    pixels off it, away from its ends (a line between two faces of one shade, not along the
    edge of a strip of that shade)."""
    L = float(np.linalg.norm(X - E))
    if L < 4.0 * px:  # too short to run along a strip
        return True
    u = (X - E) / L
    n = side_px * px * np.array([-u[1], u[0]])
    return all(
        _labelled(labels, E + s * n, X + s * n, lab, 1.5 * px, L - 2.0 * px, px)
        for s in (1.0, -1.0)
    )


def _to_notch(labels, E, u, notch_xy, lab: int, px: float, cos_pivot: float, min_px: float):
    """The nearest notch within the pivot angle of the ray ``E + t u``, reached through
    ``lab``'s pixels (the last 1.5 pixels reach the outline); None where there is none."""
    to = notch_xy - E
    dist = np.linalg.norm(to, axis=1)
    cos = (to @ u) / np.maximum(dist, 1e-300)
    ok = np.nonzero((cos > cos_pivot) & (dist >= min_px * px))[0]
    if ok.size == 0:
        return None
    X = notch_xy[ok[np.argmin(dist[ok])]]
    L = float(np.linalg.norm(X - E))
    return X if _labelled(labels, E, X, lab, 0.5 * px, L - 1.5 * px, px) else None


def hidden_occlusions(
    labels: np.ndarray,
    xy: np.ndarray,
    F: np.ndarray,
    region: np.ndarray,
    edges: np.ndarray,
    ids: np.ndarray,
    pairs: np.ndarray,
    occluding: np.ndarray,
    normals: np.ndarray,
    reflex_deg: float = 20.0,
    min_px: float = 2.0,
    pivot_deg: float = 12.0,
    margin: float = 0.15,
):
    """Occlusion lines that go on between two faces of the same shade, where no picture shows them.

    Both rules start where the boundary between two regions ``A`` (in front,
    :func:`occlusion_chains`) and ``R`` turns from an occlusion into a crease, at a junction
    ``E``, and use that an occluding contour of a box is an edge of the face in front, along the
    screen projection of one of the other two normals:

    - *behind*: ``A`` has a convex corner at ``E`` and ``R`` a reflex one (over ``180 +
      reflex_deg`` degrees).  ``A``'s object goes on with a face of ``R``'s shade (a stair's
      next tread over the tread below, joined to ``A`` along the crease), whose contour goes on
      too, invisible: along its other edge direction, the screen projection of ``A``'s normal
      (which lies in ``R``'s plane), through ``R``'s pixels.
    - *onward*: ``R`` has a convex corner at ``E`` and ``A`` a reflex one.  The face behind
      changes, at the crease, from ``R`` to a face of ``A``'s shade (a tread in front of the
      wall below it and then of the next tread, where a flight turns), so ``A``'s edge goes on
      straight, invisible: along the screen projection of ``R``'s normal (which lies in
      ``A``'s plane), away from the chain, through ``A``'s pixels.

    A behind line ends at a notch of the figure's outline or of a hole (a corner over ``180 +
    reflex_deg`` degrees: the face in front's edge ends where the face behind's edge
    disappears), or at an onward junction of the region it crosses whose third axis it runs
    along (a V of the treads' region on a flight's far side: the nearer tread's edge ends on
    the lower tread's back edge, which it hides; no onward ray starts there), the nearest
    within ``pivot_deg`` of its direction and at least ``min_px`` pixels on.  An onward line
    needs more (a pixel step of the outline is a notch too): it
    ends where it meets a line drawn or another onward ray, before its notch (with ``A``'s
    pixels on both sides, not along a strip of them) or, with none, before it leaves ``A``'s
    pixels, and is left out where it meets neither.  Where a flight turns, the turning
    tread's edge and the next tread's edge meet behind the tread in front of both, whose own
    edge turns at its corner and runs on, along ``A``'s other axis, to a notch: the line
    from the nearest notch no other line reached, along that axis, through ``A``'s pixels
    to the first of the two.  The step edge that goes on is the next tread's, so the line
    along the front tread's edge lies one riser's screen height off it, parallel.

    Parameters
    ----------
    labels : (N, N) int
        Shade region per pixel, -1 outside the figure.
    xy : (#V, 2) float
    F : (#F, 3) int
    region : (#F,) int
        Region of each face.
    edges : (#E, 2) int
    ids, pairs : (B,) int, (B, 2) int
        Region-boundary edges and their two regions.
    occluding : (B,) bool
        Which of them are occlusions (not along their crease).
    normals : (3, 3) float
        Region normals.
    reflex_deg : float
    min_px : float
    pivot_deg : float
    margin : float
        The front side must fit the chain's direction better by this much (``|sin|``).

    Returns
    -------
    list of (2, 2) float64 arrays
        Each hidden line from its junction ``E`` to where it leaves the figure or meets another
        hidden line (screen units).
    """
    px = 2.0 / labels.shape[0]
    K = int(normals.shape[0])
    axes2 = _screen_axes(normals)
    around = _region_angles(xy, F, region, K)
    reflex = np.pi + math.radians(reflex_deg)
    convex = np.pi - math.radians(reflex_deg)
    # junctions: a vertex with an occlusion and a crease edge between the same two regions
    ends = edges[ids]  # (B, 2)
    pk = np.sort(pairs, axis=1)

    def incident(sel):  # {(vertex, region, region)} of the boundary edges selected
        p = np.repeat(pk[sel], 2, axis=0)
        return set(zip(ends[sel].ravel().tolist(), p[:, 0].tolist(), p[:, 1].tolist()))

    junctions = incident(occluding) & incident(~occluding)
    front, other = {}, {}  # (vertex, region pair) -> front region / the chain's other tip
    for va, vb, a_, b_, f in occlusion_chains(xy, ends, pk, occluding, normals, margin):
        front[(va, a_, b_)] = front[(vb, a_, b_)] = f
        other[(va, a_, b_)], other[(vb, a_, b_)] = vb, va
    # the figure's angle at each vertex: outline and hole corners are under 2 pi; notches reflex
    total = around.sum(axis=1)
    notch = np.nonzero((total < 2.0 * np.pi - 1e-6) & (total > reflex))[0]
    cos_pivot = math.cos(math.radians(pivot_deg))
    rays = []  # (E, direction, region crossed, A's other axis: None behind, axis)
    ends_at = []  # (E, A, A's other axis) where A turns reflex: a behind line's end
    for v, a, b in sorted(junctions):  # a handful
        A = front.get((v, a, b))
        if A is None:
            continue
        R = b if A == a else a
        E = xy[v]
        if around[v, R] > reflex and around[v, A] < convex:
            rays += [(E, s * axes2[A], R, None, A) for s in (1.0, -1.0)]
        elif around[v, A] > reflex and around[v, R] < convex:
            ends_at.append((E, A, 3 - A - R))
            # A's edge goes on straight: the chain seen is a piece of it, min_px long at least
            seen = E - xy[other[(v, a, b)]]
            L = float(np.linalg.norm(seen))
            if L >= min_px * px and abs(seen @ axes2[R]) > cos_pivot * L:
                # the ray and the third axis (A's other edge direction)
                rays.append((E, np.sign(seen @ axes2[R]) * axes2[R], A, 3 - A - R, R))
    return _end_rays(labels, rays, xy[notch], px, cos_pivot, min_px, axes2, ends_at)


def _end_rays(
    labels, rays, notch_xy, px: float, cos_pivot: float, min_px: float, axes2, ends_at=()
):
    """Each ray ``(E, u, region, other axis or None, axis)`` as a line to where it ends.

    Behind rays end at their notch or at a junction of ``ends_at`` (``(point, region,
    axis)``: where ``region``, the one the ray crosses, is in front and turns reflex, for a
    ray along ``axis``), none crossing another (:func:`_uncrossed`).  From a junction a behind
    line ends at no onward ray starts (the face in front of its region ends there); the
    others end at a line or another ray, with the corner lines (:func:`_onward_lines`).
    """
    out, onward = [], []
    for E, u, lab, other_axis, axis in rays:
        if other_axis is not None:
            onward.append((E, u, lab, other_axis))
            continue
        at = [P for P, r, w in ends_at if r == lab and w == axis]
        at = np.concatenate([notch_xy.reshape(-1, 2), np.reshape(at, (-1, 2))])
        X = _to_notch(labels, E, u, at, lab, px, cos_pivot, min_px) if len(at) else None
        if X is not None:
            out.append(np.stack([E, X]))
    reached = {_point_key(q[1]) for q in out}
    onto = []
    for E, u, lab, other_axis in onward:
        if _point_key(E) in reached:
            continue
        X = _to_notch(labels, E, u, notch_xy, lab, px, cos_pivot, min_px) if len(notch_xy) else None
        if X is not None and not _between(labels, E, X, lab, px):
            X = None
        reach = float(np.linalg.norm(X - E)) if X is not None else _run(labels, E, u, lab, px)
        onto.append((E, u, lab, X, reach, other_axis))
    out = _uncrossed(out, min_px * px)
    return out + _onward_lines(labels, onto, out, notch_xy, px, min_px, axes2)


def _point_key(p) -> tuple:
    """A screen point as a set key: the same junction or notch reached by two lines."""
    return tuple(np.round(p, 9))


def _uncrossed(lines: list, margin: float) -> list:
    """The lines less each that crosses a shorter one, both more than ``margin`` from their
    ends.

    A hidden line is an edge of a face in front; two such edges cannot cross, for where two
    faces' edges meet one face hides the other's edge (a T, not an X).  Of two that cross the
    longer goes: a behind ray from a figure's tip runs on across a flight's steps to a notch
    far off (the box stairs at 256 pixels, IllusionEscalier at 512).
    """
    L = [float(np.linalg.norm(q[1] - q[0])) for q in lines]
    drop = set()
    for i, (E, X) in enumerate(lines):  # a handful
        u = (X - E) / max(L[i], 1e-300)
        for j, (P, Q) in enumerate(lines):
            if j == i or L[j] >= L[i]:
                continue
            ts = _cross(E, u, P, Q)
            if ts is None:
                continue
            s_m = margin / max(L[j], 1e-300)
            if margin < ts[0] < L[i] - margin and s_m < ts[1] < 1.0 - s_m:
                drop.add(i)
    return [q for i, q in enumerate(lines) if i not in drop]


def _run(labels: np.ndarray, E, u, lab: int, px: float) -> float:
    """How far the ray ``E + t u`` runs through ``lab``'s pixels (from one pixel on)."""
    N = labels.shape[0]
    t = np.arange(px, 4.0, 0.5 * px)
    Q = E[None] + t[:, None] * u[None]
    j = np.floor((Q[:, 0] + 1.0) / px).astype(np.int64)
    i = np.floor((1.0 - Q[:, 1]) / px).astype(np.int64)
    inside = (i >= 0) & (i < N) & (j >= 0) & (j < N)
    hit = ~inside
    hit[inside] = labels[i[inside], j[inside]] != lab
    return float(t[np.argmax(hit)]) if hit.any() else float(t[-1])


def _cross(E, u, P, Q):
    """``(t, s)`` with ``E + t u = P + s (Q - P)``; None for parallel lines."""
    d = Q - P
    den = u[0] * d[1] - u[1] * d[0]
    if abs(den) < 1e-9:
        return None
    w = P - E
    return (w[0] * d[1] - w[1] * d[0]) / den, (w[0] * u[1] - w[1] * u[0]) / den


def _onward_lines(labels, onto, drawn, notch_xy, px: float, min_px: float, axes2) -> list:
    """End the onward rays ``(E, u, region, notch or None, reach, other axis)``.

    Each ends where it first meets a line already ``drawn`` or another onward ray (within that
    ray's reach, its notch or how far it runs through its region's pixels); one that meets
    neither is left out, for a notch alone does not end it (a pixel step of the outline is a
    notch too, and a hole's corner starts such a ray).  Two onward rays that end on each
    other meet at a corner of the face in front of one of them (a tread's corner where a
    flight turns); that face's other edge runs from the corner on to a notch nobody else
    reached, along its other axis: the line from the nearest such notch, through the
    region's pixels, to where it meets one of the two.
    """
    out = []
    for k, (E, u, lab, X, reach, _) in enumerate(onto):  # a handful
        best, end = reach if X is not None else np.inf, X
        segs = [(P, Q) for P, Q in drawn]
        segs += [(E2, E2 + r2 * u2) for j, (E2, u2, _, _, r2, _) in enumerate(onto) if j != k]
        for P, Q in segs:
            ts = _cross(E, u, P, Q)
            if ts is not None and min_px * px <= ts[0] < best and -1e-9 <= ts[1] <= 1.0 + 1e-9:
                best, end = ts[0], E + ts[0] * u
        if end is X:  # a notch alone: a pixel step of the outline is one too
            continue
        if end is not None and _labelled(labels, E, end, lab, px, best - 0.5 * px, px):
            out.append((np.stack([E, end]), lab, k, end is not X))
    lines = [ln for ln, *_ in out]
    used = [_point_key(ln[1]) for ln in lines]
    free = [q for q in notch_xy if _point_key(q) not in used]
    corners = []
    for ln, lab, k, met in out:
        if not met:
            continue
        w = axes2[onto[k][5]]
        best = None
        for q in free:  # the notches around the figure
            for sg in (1.0, -1.0):
                ts = _cross(q, sg * w, ln[0], ln[1])
                if ts is None or not (min_px * px <= ts[0]) or not (0.0 <= ts[1] <= 1.0):
                    continue
                P = q + ts[0] * sg * w
                if (best is None or ts[0] < best[0]) and _labelled(
                    labels, q, P, lab, 1.5 * px, ts[0] - 0.5 * px, px
                ):
                    best = (ts[0], P, q)
        if best is not None:
            corners.append(np.stack([best[1], best[2]]))
    return lines + corners


def occlusion_chains(
    xy: np.ndarray,
    ends: np.ndarray,
    pairs: np.ndarray,
    occluding: np.ndarray,
    normals: np.ndarray,
    margin: float = 0.15,
) -> list[tuple[int, int, int, int, int]]:
    """Occlusion chains and the face in front of each.

    A chain is a path of connected occlusion edges between the same two regions.  The front
    face holds its chain's pieces in its plane (an occluding contour runs along the edges of
    the face in front, and may turn its corners): of the two sides, the one whose in-plane
    axes (screen projections of the other two normals) the pieces follow better, by
    ``margin`` in length-weighted ``|sin|`` to the nearest axis.  Weighed piece by piece, a
    tooth whose pixel staircase hooks at both ends (end to end between the two sides' axes)
    still tells its face.

    Parameters
    ----------
    xy : (#V, 2) float
    ends : (B, 2) int
        Vertices of the region-boundary edges.
    pairs : (B, 2) int
        Their two regions, sorted.
    occluding : (B,) bool
    normals : (K, 3) float
    margin : float

    Returns
    -------
    list of (tip_a, tip_b, region_a, region_b, front)
        Chains with two tips (no loops, no branches) and a clear front.
    """
    import scipy.sparse.csgraph as csgraph

    K = int(normals.shape[0])
    axes2 = _screen_axes(normals)
    occ_i = np.nonzero(occluding)[0]
    out: list[tuple[int, int, int, int, int]] = []
    if occ_i.size == 0:
        return out
    ends_o = ends[occ_i]
    pid = pairs[occ_i, 0] * K + pairs[occ_i, 1]
    # join edges that share a vertex and a region pair: nodes are (vertex, pair)
    node, inv = np.unique(
        np.stack([ends_o.ravel(), np.repeat(pid, 2)], 1), axis=0, return_inverse=True
    )
    inv = inv.reshape(-1, 2)
    G = sp.coo_matrix((np.ones(len(inv)), (inv[:, 0], inv[:, 1])), shape=(len(node),) * 2)
    n_ch, ch = csgraph.connected_components(G, directed=False)
    deg = np.bincount(inv.ravel(), minlength=len(node))
    order = np.argsort(ch[inv[:, 0]], kind="stable")
    in_c = np.split(order, np.cumsum(np.bincount(ch[inv[:, 0]], minlength=n_ch))[:-1])
    for c in range(n_ch):  # a handful of chains
        nodes = np.nonzero(ch == c)[0]
        tips = nodes[deg[nodes] == 1]
        if tips.size != 2:
            continue
        va, vb = int(node[tips[0], 0]), int(node[tips[1], 0])
        if np.linalg.norm(xy[vb] - xy[va]) < 1e-12:
            continue
        a_, b_ = divmod(int(node[tips[0], 1]), K)
        # each piece of the chain along one of the front face's edge directions: the pieces'
        # |sin| to the side's nearest in-plane axis, weighted by length
        d = xy[node[inv[in_c[c]][:, 1], 0]] - xy[node[inv[in_c[c]][:, 0], 0]]
        fit = []
        for side in (a_, b_):
            others = [k for k in range(K) if k != side]
            sin = np.min(np.abs(d[:, :1] * axes2[others, 1] - d[:, 1:] * axes2[others, 0]), 1)
            fit.append(float(sin.sum() / max(np.linalg.norm(d, axis=1).sum(), 1e-300)))
        if abs(fit[0] - fit[1]) < margin:
            continue
        out.append((va, vb, a_, b_, a_ if fit[0] < fit[1] else b_))
    return out


def crossbar_occlusions(
    xy: np.ndarray,
    ends: np.ndarray,
    pairs: np.ndarray,
    occluding: np.ndarray,
    normals: np.ndarray,
    max_sin: float,
    pixel: float,
    margin: float = 0.15,
) -> np.ndarray:
    """``occluding`` with the crossbars of T-junctions run on.

    A bar seen ending against a bar in front: the front face ``A``'s edge (the crossbar)
    passes in front of one face ``Q`` of the bar behind (an occlusion chain ``A | Q``,
    :func:`occlusion_chains`), then, past the junction where the bar behind's edge (the stem,
    the boundary ``Q | S``) ends, of its other face ``S``.  When the bar in front runs along
    the bar behind's third axis (the projection of ``Q``'s normal, ``n_A x n_S``), the stretch
    ``A | S`` runs along the crease of ``A`` and ``S``, and nothing in its own direction tells
    it from a crease.  The crossbar does, where the chain ``A | Q`` runs along that same crease
    (within ``max_sin``, end to end: ``A``'s edge goes on straight) and the stem is convex
    (``Q``'s normal leans from the junction toward ``Q``'s side): the stem is then the bar
    behind's edge, one line of ``Q`` and ``S``, so at the junction ``S`` lies as deep as ``Q``,
    behind ``A``; along a straight line the depths of ``A``'s edge and of ``S``'s plane part
    linearly, so apart at the junction they are apart all along, and the whole ``A | S``
    stretch, from the junction to where that boundary ends (another junction, the outline or a
    hole), is an occlusion too.  (Were ``A | S`` a crease instead, ``S`` a wall standing on
    ``A``'s edge and ending at the stem, the convex end of the wall would face the viewer: a
    face of ``Q``'s orientation standing on ``A``, which meets ``A`` along the projection of
    ``S``'s normal, not along the crossbar.)  A concave stem (two faces of an inner corner
    behind ``A``, or the silhouette of such a wall) is left alone.

    Parameters
    ----------
    xy : (#V, 2) float
    ends : (B, 2) int
        Vertices of the region-boundary edges.
    pairs : (B, 2) int
        Their two regions.
    occluding : (B,) bool
    normals : (K, 3) float
        Region normals.
    max_sin : float
        ``|sin|`` within which a direction follows a crease (the occlusion test's).
    pixel : float
        A pixel's size (screen units).  A chain's ends are known to about a pixel, so only a
        chain ``pixel / max_sin`` long at least tells its direction within ``max_sin``; a
        shorter one (a pixel step where two lines meet) starts nothing.
    margin : float
        :func:`occlusion_chains`' margin for telling the face in front.

    Returns
    -------
    (B,) bool
        ``occluding`` and the crossbars run on.
    """
    ends = np.asarray(ends, dtype=np.int64)
    pk = np.sort(np.asarray(pairs, dtype=np.int64), axis=1)
    occ = np.asarray(occluding, dtype=bool).copy()
    if ends.size == 0:
        return occ
    n = len(xy)
    deg = np.bincount(ends.ravel(), minlength=n)
    # boundary edges at each vertex, as a CSR table (vertex -> edge indices)
    inc = sp.csr_matrix(
        (np.ones(2 * len(ends)), (ends.ravel(), np.repeat(np.arange(len(ends)), 2))),
        shape=(n, len(ends)),
    )

    def at(v):
        return inc.indices[inc.indptr[v] : inc.indptr[v + 1]]

    for _ in range(len(ends)):  # each round runs on at least one edge; a few rounds
        grown = False
        for va, vb, a_, b_, A in occlusion_chains(xy, ends, pk, occ, normals, margin):
            Q = b_ if A == a_ else a_
            if np.linalg.norm(xy[vb] - xy[va]) * max_sin < pixel:
                continue
            for v, w in ((va, vb), (vb, va)):  # the tip v, seen from the other tip w
                u = xy[v] - xy[w]
                here = at(v)
                for e in here[~occ[here]]:
                    S = int(pk[e, 0] + pk[e, 1] - A) if A in pk[e] else -1
                    if S < 0 or S == Q:
                        continue
                    stem = (pk[here, 0] == min(Q, S)) & (pk[here, 1] == max(Q, S))
                    if not stem.any():
                        continue
                    o = ends[e, 0] + ends[e, 1] - v
                    crease = np.cross(normals[A], normals[S])[:2]
                    crease = crease / max(float(np.linalg.norm(crease)), 1e-12)
                    along = _abs_sin(u[None], crease[None])[0, 0] < max_sin
                    # straight on (not back along the chain), and the stem convex: Q's
                    # normal leans from the junction toward Q's side, the chain's
                    convex = u @ normals[Q, :2] < 0
                    if not (along and convex and u @ (xy[o] - xy[v]) > 0):
                        continue
                    # the A | S boundary from the junction on, to the next junction
                    prev, cur = v, int(e)
                    while not occ[cur] and (pk[cur] == pk[e]).all():
                        occ[cur] = grown = True
                        nxt = int(ends[cur, 0] + ends[cur, 1] - prev)
                        if deg[nxt] != 2:
                            break
                        cand = at(nxt)
                        prev, cur = nxt, int(cand[cand != cur][0])
        if not grown:
            break
    return occ


def hidden_steps(xy, F, edges, cut, hidden, hidden_edges, normals, region, max_sin=0.05):
    """Climbs the lift must make in place, where a hidden step cannot be cut open.

    A hidden line between two faces of one orientation (a tread over the tread below) is cut
    so that each side keeps its own depth; the step between them is then read from how the
    two sides join elsewhere (a flight's treads join through their coplanar walls).  Where a
    flight turns, the corner line (:func:`_onward_lines`: the turning tread's edge over the
    tread behind) cannot be cut to its notch: with the rest of the turn's cut reaching a
    hole, it would cut the figure apart (``_one_contact`` leaves part of it whole), and
    nothing else joins the two treads.  Two parallel faces joined there are one plane: the
    step is lost (a whole step of the Penrose stairs' climb).  The picture shows nothing of
    that step's height, but the next step's: the riser the corner line lies off the onward
    line parallel to it (the next tread's edge, which ends on the same line).  The tread in
    front climbs that much over the one behind where they join, as a person reading the
    stairs as even takes it; an uneven turn comes out off by the difference.

    Parameters
    ----------
    xy : (#V, 2) float
    F : (#F, 3) int
    edges : (#E, 2) int
    cut : (C,) int
        The edges cut open.
    hidden : list of (2, 2) float
        The hidden lines (:func:`hidden_occlusions`), each from its start to its end.
    hidden_edges : list of (k_i,) int
        The edges on each hidden line.
    normals : (K, 3) float
    region : (#F,) int
    max_sin : float
        Lines within this ``|sin|`` are parallel.

    Returns
    -------
    (#F, 3) float64 or None
        Per face, the extra climb its half-edge opposite each corner is asked for (the order
        of :func:`.turn._slope_wishes`), None where there is none: on the faces in front
        around the part of a corner line left whole, the climb of the step from the faces
        behind.
    """
    extra = np.zeros((len(F), 3))
    for i, (seg, he) in enumerate(zip(hidden, hidden_edges)):  # a handful of lines
        whole = he[~np.isin(he, cut)]
        L = float(np.linalg.norm(seg[1] - seg[0]))
        if whole.size == 0 or L == 0.0:
            continue
        u = (seg[1] - seg[0]) / L
        nrm = np.array([-u[1], u[0]])
        tol = 1e-6 * max(L, 1.0)
        # the line it starts on, and the parallel line that ends on that one too
        on = [k for k, s in enumerate(hidden) if k != i and _near_segment(seg[0], s, 1e3 * tol)]
        par = [
            j
            for j, s in enumerate(hidden)
            if j != i
            and any(_near_segment(s[1], hidden[k], 1e3 * tol) for k in on)
            and _abs_sin((s[1] - s[0])[None], u[None])[0, 0] < max_sin
        ]
        if not par:
            continue
        off = float((hidden[par[0]][0] - seg[0]) @ nrm)  # the riser, toward the side behind
        neck = np.zeros(len(xy), dtype=bool)
        neck[edges[whole].ravel()] = True
        side = (xy[F].mean(axis=1) - seg[0]) @ nrm
        front = neck[F].any(axis=1) & (np.sign(side) == -np.sign(off))
        lab = np.bincount(region[neck[F].any(axis=1)], minlength=len(normals)).argmax()
        n = normals[lab]
        across = abs(float(n[0] * u[1] - n[1] * u[0])) / max(np.hypot(n[0], n[1]), 1e-12)
        if across < 0.1 or not front.any():
            continue
        # planes of normal n a distance s apart: s |n_xy x u| apart on screen across the line
        # and s / n_z apart in depth at one screen point; the one in front is nearer
        climb = abs(off) / (across * np.hypot(n[0], n[1])) / n[2]
        val = np.where(neck[F[front]], 0.0, climb)  # (f, 3) corner heights over the plane
        # the half-edge opposite corner c runs c+1 -> c+2
        extra[front] += val[:, [2, 0, 1]] - val[:, [1, 2, 0]]
    return extra if np.any(extra) else None


def _near_segment(p, seg, tol: float) -> bool:
    """Whether the point ``p`` lies within ``tol`` of the segment ``seg`` ((2, 2))."""
    d = seg[1] - seg[0]
    t = float(np.clip((p - seg[0]) @ d / max(float(d @ d), 1e-300), 0.0, 1.0))
    return bool(np.linalg.norm(seg[0] + t * d - p) <= tol)
