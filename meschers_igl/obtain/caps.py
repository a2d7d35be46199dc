"""Caps of a closed model -- planar patches bounded by one loop, the candidates for the ends of
a broken bar -- and the direction of the bar behind each, found for all patches at once.

Every rule here is per patch (per cap), applied to all of them in array passes: a model of
100k faces has tens of thousands of patches, and a Python loop over them costs seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

#: Unit normals closer than this (1 - cos) count as equal or opposite when caps are paired.
CAP_NORMAL_TOL = 1e-9
#: Normals are compared as integer keys on this grid (per component).
NORMAL_KEY = 1e-6


@dataclass(frozen=True)
class Cap:
    """A bar's end bounded by one loop: a planar patch (a cap: its normal), or with ``flat``
    False a pointed, roof-shaped or notched end (``normal``: the bar's direction out of it)."""

    faces: np.ndarray
    loop: np.ndarray
    normal: np.ndarray
    flat: bool = True


def unit_normals(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(#F, 3) unit face normals (zero rows for degenerate faces)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    return n


def direction_keys(u: np.ndarray) -> np.ndarray:
    """(k,) int64: one key per row of unit vectors ``u`` (k, 3), equal exactly when the rows
    round to the same point of the :data:`NORMAL_KEY` grid (each component in [-1, 1] takes
    21 bits)."""
    k = np.round(u / NORMAL_KEY).astype(np.int64) + (1 << 20)
    return (k[:, 0] << 42) | (k[:, 1] << 21) | k[:, 2]


def planar_patches(V: np.ndarray, F: np.ndarray, TT: np.ndarray, tol: float) -> np.ndarray:
    """(#F,) label of the coplanar patch of each face (faces joined across shared edges)."""
    n = unit_normals(V, F)
    f = np.repeat(np.arange(F.shape[0]), 3)
    g = TT.reshape(-1)
    ok = g >= 0
    f, g = f[ok], g[ok]
    same = (np.einsum("ij,ij->i", n[f], n[g]) >= 1.0 - CAP_NORMAL_TOL) & (
        np.abs(np.einsum("ij,ij->i", V[F[g, 0]] - V[F[f, 0]], n[f])) <= tol
    )
    A = sp.coo_matrix((np.ones(int(same.sum())), (f[same], g[same])), shape=(F.shape[0],) * 2)
    return csgraph.connected_components(A, directed=False)[1]


@dataclass(frozen=True)
class CapTable:
    """The caps of a model as arrays, one row per cap, in increasing patch order.

    Attributes
    ----------
    patch : (k,) int64
        The planar patch of each cap.
    normal : (k, 3) float64
        Its unit normal (that of its lowest-numbered face).
    face_start : (k + 1,) int64, faces : (#,) int64
        Cap ``i``'s faces, ascending: ``faces[face_start[i]:face_start[i + 1]]``.
    loop_start : (k + 1,) int64, loops : (#,) int64
        Cap ``i``'s boundary loop, in the faces' orientation, from the tail of its first
        boundary half-edge (faces ascending, corners 0, 1, 2):
        ``loops[loop_start[i]:loop_start[i + 1]]``.
    """

    patch: np.ndarray
    normal: np.ndarray
    face_start: np.ndarray
    faces: np.ndarray
    loop_start: np.ndarray
    loops: np.ndarray
    made: dict = field(default_factory=dict, compare=False, repr=False)

    def __len__(self) -> int:
        return int(self.patch.size)

    @property
    def size(self) -> np.ndarray:
        """(k,) loop sizes."""
        return np.diff(self.loop_start)

    def cap(self, i: int) -> Cap:
        """Cap ``i`` as a :class:`Cap` (the same object each time: pairs sharing a cap share
        it)."""
        if i not in self.made:
            f, lo = self.face_start, self.loop_start
            faces, loop = self.faces[f[i] : f[i + 1]], self.loops[lo[i] : lo[i + 1]]
            self.made[i] = Cap(faces, loop, self.normal[i])
        return self.made[i]

    def caps(self) -> list:
        """Every cap as a :class:`Cap`."""
        return [self.cap(i) for i in range(len(self))]

    def centroids(self, V: np.ndarray) -> np.ndarray:
        """(k, 3) mean of each loop's points (``V[loop].mean(axis=0)``, to the bit)."""
        out = np.zeros((len(self), 3))
        size = self.size
        for n in np.unique(size).tolist():  # a few loop sizes
            rows = np.flatnonzero(size == n)
            out[rows] = V[self.loop_rows(rows)].mean(axis=1)
        return out

    def loop_rows(self, rows: np.ndarray) -> np.ndarray:
        """(len(rows), n) the loops of caps ``rows``, all of one size ``n``."""
        n = int(self.size[rows[0]]) if rows.size else 0
        return self.loops[self.loop_start[rows][:, None] + np.arange(n)]


def _no_caps() -> CapTable:
    z = np.zeros(0, np.int64)
    return CapTable(z, np.zeros((0, 3)), np.zeros(1, np.int64), z, np.zeros(1, np.int64), z)


def cap_table(V: np.ndarray, F: np.ndarray, TT: np.ndarray, patch: np.ndarray) -> CapTable:
    """Patches bounded by a single loop whose normal has an opposite among the patches (the
    candidates for the two ends of a broken bar); others are never caps.

    A patch is a cap when its boundary half-edges (those whose neighbour lies in another
    patch, or none) form one cycle: each vertex the tail of at most one of them and the head
    of at most one, each head a tail, one cycle.  Normals are opposite when their keys
    (:func:`direction_keys`) are.  All patches at once: the cycles are the connected
    components of the successor map, the order along each from its first half-edge is found
    by pointer doubling (log of the longest loop passes).
    """
    nF = F.shape[0]
    if nF == 0:
        return _no_caps()
    n = unit_normals(V, F)
    k = int(patch.max()) + 1
    fo = np.argsort(patch, kind="stable")  # faces grouped by patch, ascending in each
    fstart = np.searchsorted(patch[fo], np.arange(k + 1))
    pn = n[fo[fstart[:-1]]]  # each patch's lowest-numbered face's normal
    key = direction_keys(pn)
    is_cand = np.isin(direction_keys(-pn), key)
    # boundary half-edges of candidate patches, grouped by patch (faces, corners ascending)
    fe = np.repeat(np.arange(nF), 3)
    nb = TT.reshape(-1)
    bd = (nb < 0) | (patch[np.maximum(nb, 0)] != patch[fe])
    he = np.flatnonzero(bd & is_cand[patch[fe]])
    pe = patch[fe[he]]
    order = np.argsort(pe, kind="stable")
    he, pe = he[order], pe[order]
    tail = F.reshape(-1)[he]
    head = F[fe[he], (he % 3 + 1) % 3]
    m = he.size
    if m == 0:
        return _no_caps()
    starts = np.flatnonzero(np.r_[True, pe[1:] != pe[:-1]])
    seg = np.cumsum(np.r_[False, pe[1:] != pe[:-1]])  # half-edge -> its patch's segment
    nV = np.int64(V.shape[0])
    tkey, hkey = pe * nV + tail, pe * nV + head
    bad = np.zeros(starts.size, dtype=bool)
    ts = np.sort(tkey)
    bad[seg[np.isin(tkey, ts[1:][ts[1:] == ts[:-1]])]] = True  # a vertex two edges leave
    hs = np.sort(hkey)
    bad[seg[np.isin(hkey, hs[1:][hs[1:] == hs[:-1]])]] = True  # a vertex two edges enter
    to = np.argsort(tkey, kind="stable")
    at = np.minimum(np.searchsorted(tkey[to], hkey), m - 1)
    found = tkey[to][at] == hkey
    bad[seg[~found]] = True  # an edge leading to no edge of the patch
    succ = np.where(found, to[at], np.arange(m))
    _, comp = csgraph.connected_components(
        sp.coo_matrix((np.ones(m), (np.arange(m), succ)), shape=(m, m)), directed=False
    )
    one = np.minimum.reduceat(comp, starts) == np.maximum.reduceat(comp, starts)
    ok = one & ~bad
    # position of each half-edge along its loop from the segment's first (pointer doubling)
    first = starts[seg]
    nxt = np.where(succ == first, np.arange(m), succ)  # each loop broken before its first
    nxt[~ok[seg]] = np.arange(m)[~ok[seg]]
    dist = (nxt != np.arange(m)).astype(np.int64)  # steps to the loop's last half-edge
    while True:  # about log2(longest loop) passes
        jump = nxt[nxt]
        if np.array_equal(jump, nxt):
            break
        dist = dist + dist[nxt]
        nxt = jump
    size = np.diff(np.r_[starts, m])
    pos = size[seg] - 1 - dist
    keep = ok[seg]
    caps = np.flatnonzero(ok)
    loop_start = np.r_[0, np.cumsum(size[caps])].astype(np.int64)
    base = np.full(starts.size, -1, np.int64)
    base[caps] = loop_start[:-1]
    loops = np.zeros(loop_start[-1], np.int64)
    loops[base[seg[keep]] + pos[keep]] = tail[keep]
    cp = pe[starts[caps]]
    cnt = fstart[cp + 1] - fstart[cp]
    face_start = np.r_[0, np.cumsum(cnt)].astype(np.int64)
    faces = fo[np.repeat(fstart[cp] - face_start[:-1], cnt) + np.arange(face_start[-1])]
    return CapTable(cp.astype(np.int64), pn[cp], face_start, faces, loop_start, loops)


def find_caps(V, F, TT, patch, tol=None) -> list:
    """:func:`cap_table` as a list of :class:`Cap` (``tol`` is not used: the patches carry it)."""
    return cap_table(V, F, TT, patch).caps()


def side_directions(V: np.ndarray, F: np.ndarray, TT: np.ndarray, patch, table: CapTable):
    """The common direction of the side faces next to each cap (a prism's lateral edges).

    For cap ``i``, its neighbours outside it (ascending face numbers) with unit normals
    ``n_0, n_1, ...``: two side planes that are not parallel meet along the bar's direction
    ``d``, the first largest ``n_0 x n_k`` normalised; ``d`` is kept when every ``|n_k . d|``
    is at most 1e-6 and turned to point out of the cap.  None for caps with fewer than two
    neighbours (a loose patch), no two non-parallel side planes (``|n_0 x n_k| < 1e-6``) or
    sides along no one direction.  All caps at once.

    Returns
    -------
    D : (k, 3) float64
        NaN rows where there is no direction.
    """
    k = len(table)
    D = np.full((k, 3), np.nan)
    if k == 0:
        return D
    cnt = np.diff(table.face_start)
    cap_of = np.repeat(np.arange(k), cnt)
    nb = TT[table.faces]  # (#, 3)
    ci = np.repeat(cap_of, 3)
    nb = nb.reshape(-1)
    out = (nb >= 0) & (patch[np.maximum(nb, 0)] != table.patch[ci])
    nF = np.int64(F.shape[0])
    u = np.unique(ci[out] * nF + nb[out])  # (cap, neighbour) ascending, once each
    ci, nb = u // nF, u % nF
    if ci.size == 0:
        return D
    starts = np.flatnonzero(np.r_[True, ci[1:] != ci[:-1]])
    caps = ci[starts]
    many = np.diff(np.r_[starts, ci.size]) >= 2
    seg = np.cumsum(np.r_[False, ci[1:] != ci[:-1]])  # row -> its cap's segment
    n = unit_normals(V, F[nb])
    c = np.cross(n[starts][seg], n)
    cn = np.linalg.norm(c, axis=1)
    cmax = np.maximum.reduceat(cn, starts)
    hit = np.flatnonzero(cn == cmax[seg])
    kk = hit[np.r_[True, seg[hit][1:] != seg[hit][:-1]]]  # the first largest per cap
    ok = many & (cmax >= 1e-6)
    d = c[kk] / np.where(ok, cmax, 1.0)[:, None]
    off = np.abs(np.einsum("ij,ij->i", n, d[seg]))
    ok &= np.maximum.reduceat(off, starts) <= 1e-6
    d *= np.where(np.einsum("ij,ij->i", d, table.normal[caps]) > 0, 1.0, -1.0)[:, None]
    D[caps[ok]] = d[ok]
    return D


# ------------------------------------------------------------------------- candidate pairs
#: Without a view, every pair of caps with opposite normals and equal loop sizes is compared
#: up to this many pairs; beyond it (a scene of thousands of equal blocks, a fine mesh whose
#: facets have opposite facets) only the pairs that may be a junction from some view, the
#: nearest first, up to this many (:func:`junction_candidates`).
MAX_CAP_PAIRS = 20000
#: Loops up to this size get their exact width (largest distance between their points).
_EXACT_WIDTH = 64
#: Most (direction, corner) products :func:`may_be_bars` forms before it keeps every cap.
_BAR_BUDGET = 60_000_000


def _group_ids(size: np.ndarray, normal: np.ndarray):
    """(own, opposite): an int64 id of each cap's (loop size, normal key) and of the group it
    pairs with (loop size, opposite key); ids are equal exactly when the groups are."""
    keys = np.r_[direction_keys(normal), direction_keys(-normal)]
    _, kid = np.unique(keys, return_inverse=True)
    kid = kid.reshape(-1).astype(np.int64)
    base = np.int64(2 * size.size + 1)
    k = size.size
    return size * base + kid[:k], size * base + kid[k:]


def opposite_pairs(size: np.ndarray, normal: np.ndarray, limit: int):
    """All pairs ``i < j`` of caps with equal loop sizes and opposite normal keys, in
    lexicographic order, or None when there are more than ``limit`` of them (counted first,
    not formed).  Returns ``(ij, count)``."""
    k = size.size
    own, opp = _group_ids(size, normal)
    order = np.lexsort((np.arange(k), own))  # by group, then index
    ck = own[order] * k + order
    lo = np.searchsorted(ck, opp * k + np.arange(k), side="right")  # partners j > i
    hi = np.searchsorted(ck, (opp + 1) * k, side="left")
    cnt = np.maximum(hi - lo, 0)
    total = int(cnt.sum())
    if total > limit:
        return None, total
    i = np.repeat(np.arange(k), cnt)
    at = np.repeat(lo - (np.cumsum(cnt) - cnt), cnt) + np.arange(total)
    return np.stack([i, order[at]], axis=1).reshape(-1, 2), total


def may_be_bars(V, F, part, table: CapTable, D, cen, tol) -> np.ndarray:
    """(k,) bool: may each cap end a *bar*, a piece longer along its direction ``D`` back
    from the cap than the cap is wide (the test of :func:`~.junctions.pieces_are_bars`, one
    cap at a time)?  A superset: False only where the piece is surely not longer.

    The piece's length is bounded above with the direction rounded to its key (one pass over
    the model's corners per distinct direction, with a slack for the rounding and for the
    other cap's direction, opposite to 4.5e-5), the width below by the exact width for loops
    up to :data:`_EXACT_WIDTH` points, else the largest distance from the loop's first point.
    Caps without a direction are False.
    """
    has = ~np.isnan(D[:, 0])
    out = has.copy()
    rows = np.flatnonzero(has)
    if rows.size == 0:
        return out
    X = V[np.unique(F)]
    diag = float(np.linalg.norm(np.ptp(X, axis=0)))
    slack = 1e-4 * (diag + float(np.abs(X).max())) + 2.0 * tol
    width = np.zeros(len(table))
    size = table.size
    for n in np.unique(size[rows]).tolist():  # a few loop sizes
        r = rows[size[rows] == n]
        P = V[table.loop_rows(r)]  # (r, n, 3)
        if n <= _EXACT_WIDTH:
            step = max(1, (1 << 22) // (n * n))
            for s in range(0, r.size, step):  # chunks of caps
                Q = P[s : s + step]
                width[r[s : s + step]] = np.linalg.norm(Q[:, :, None] - Q[:, None], axis=3).max(
                    axis=(1, 2)
                )
        else:
            width[r] = np.linalg.norm(P - P[:, :1], axis=2).max(axis=1)
    keys = direction_keys(D[rows])
    uk, inv = np.unique(keys, return_inverse=True)
    if uk.size * F.size > _BAR_BUDGET:
        return out  # too many directions to bound: every cap with one may end a bar
    fo = np.argsort(part, kind="stable")
    corners = F[fo].reshape(-1)
    pstart = 3 * np.searchsorted(part[fo], np.arange(int(part.max()) + 1))
    cpart = part[table.faces[table.face_start[:-1]]]
    inv = inv.reshape(-1)
    for u in range(uk.size):  # the distinct bar directions
        r = rows[inv == u]
        proj = V @ D[r[0]]
        low = np.minimum.reduceat(proj[corners], pstart)[cpart[r]]
        length = np.einsum("ij,ij->i", cen[r], D[r]) - low
        out[r] = length + slack > width[r]
    return out


def _cluster_pairs(cl: np.ndarray, side: np.ndarray, cen: np.ndarray, limit: int):
    """Pairs ``(a, b)`` of caps in one cluster (``cl``, -1 for none), ``a`` on side False and
    ``b`` on side True: all of them, except in a cluster with more than ``limit`` pairs, where
    each ``a`` takes its nearest ``b`` (centroids), as many as ``limit`` over its ``a``'s
    allow but at least 16 (the nearest pairs of the cluster are among them)."""
    _, dense = np.unique(cl, return_inverse=True)
    dense = dense.reshape(-1) - int(np.any(cl < 0))  # -1 stays -1
    a = np.flatnonzero((dense >= 0) & ~side)
    b = np.flatnonzero((dense >= 0) & side)
    if a.size == 0 or b.size == 0:
        return np.zeros((0, 2), np.int64)
    b = b[np.argsort(dense[b], kind="stable")]
    bc = dense[b]
    lo, hi = np.searchsorted(bc, dense[a], "left"), np.searchsorted(bc, dense[a], "right")
    na = np.bincount(dense[a], minlength=int(dense.max()) + 1)
    nb = np.bincount(bc, minlength=na.size)
    big = na * nb > limit
    small = ~big[dense[a]]
    cnt = np.where(small, hi - lo, 0)
    at = np.repeat(lo - (np.cumsum(cnt) - cnt), cnt) + np.arange(int(cnt.sum()))
    out = [np.stack([np.repeat(a, cnt), b[at]], axis=1)]
    for c in np.flatnonzero(big).tolist():  # the few crowded clusters
        A, B = a[dense[a] == c], b[bc == c]
        k = min(B.size, max(16, limit // A.size))
        idx = cKDTree(cen[B]).query(cen[A], k=k)[1].reshape(A.size, k)
        out.append(np.stack([np.repeat(A, k), B[idx].reshape(-1)], axis=1))
    return np.vstack(out)


def junction_candidates(V, F, part, table: CapTable, D, cen, tol, limit) -> np.ndarray:
    """Pairs ``i < j`` of caps (equal loop sizes, opposite normal keys) that may be a junction
    from some view, at most ``limit``, the nearest first; lexicographic order.

    Without a view a pair can be a false edge only when both caps lie in one plane (from
    ``T / |T|`` they coincide, each seen edge-on: ``|n . T|`` within ``2 tol + 1e-5`` of the
    model's size), and a bridge (hidden gap, crossing) only between two *bars* facing each
    other (:func:`may_be_bars`, bar directions opposite).  Caps are clustered -- one plane
    (offsets chained ``2 tol + 1e-5`` of the size apart), or one pair of opposite groups for
    the bars -- and paired within clusters (:func:`_cluster_pairs`).
    """
    k = len(table)
    size = table.size
    own, opp = _group_ids(size, table.normal)
    valid = (own != opp) & np.isin(opp, own)
    side = own > opp
    pid = np.where(valid, np.minimum(own, opp), -1)
    X = V[np.unique(F)]
    w = 2.0 * tol + 1e-5 * float(np.linalg.norm(np.ptp(X, axis=0)))
    # a plane offset per cap along one normal per pair of groups (its lowest cap's, side False)
    o = np.zeros(k)
    rows = np.flatnonzero(valid)
    if rows.size == 0:
        return np.zeros((0, 2), np.int64)
    rows = rows[np.lexsort((rows, pid[rows]))]
    first = np.r_[True, pid[rows][1:] != pid[rows][:-1]]
    rep = rows[first][np.cumsum(first) - 1]
    m = table.normal[rep] * np.where(side[rep], -1.0, 1.0)[:, None]
    o[rows] = np.einsum("ij,ij->i", cen[rows], m)
    rows = rows[np.lexsort((o[rows], pid[rows]))]
    cut = np.r_[True, (pid[rows][1:] != pid[rows][:-1]) | (np.diff(o[rows]) > w)]
    plane = np.full(k, -1, np.int64)
    plane[rows] = np.cumsum(cut) - 1
    P = _cluster_pairs(plane, side, cen, limit)
    P = P[np.abs(o[P[:, 0]] - o[P[:, 1]]) <= w]
    bars = valid & may_be_bars(V, F, part, table, D, cen, tol)
    B = _cluster_pairs(np.where(bars, pid, -1), side, cen, limit)
    B = B[np.einsum("ij,ij->i", D[B[:, 0]], D[B[:, 1]]) <= -1.0 + 1e-9]
    ij = np.unique(np.sort(np.vstack([P, B]), axis=1), axis=0)
    if ij.shape[0] > limit:  # the nearest pairs
        near = np.argsort(np.linalg.norm(cen[ij[:, 1]] - cen[ij[:, 0]], axis=1), kind="stable")
        ij = ij[np.sort(near[:limit])]
    return ij
