"""Junctions on the whole model: caps (planar patches bounded by one loop), or bar ends of
other shapes, paired as the two ends of a broken bar -- a false edge where they coincide on
screen, a hidden gap where the bar runs behind an occluder -- and the model opened there and
glued crosswise."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from ..errors import MescherError
from .caps import (
    CAP_NORMAL_TOL,
    MAX_CAP_PAIRS,
    Cap,
    CapTable,
    cap_table,
    find_caps,
    junction_candidates,
    opposite_pairs,
    planar_patches,
    side_directions,
)
from .clip import FRONT_NZ
from .records import Junction, VisibleModel

__all__ = [
    "CAP_NORMAL_TOL",
    "MAX_CAP_PAIRS",
    "BarEnds",
    "Cap",
    "bar_end_pairs",
    "bridges_blocked",
    "winding_numbers",
    "close_junctions",
    "closed_surface",
    "crossing_behind",
    "find_caps",
    "junction_at",
    "may_be_junctions",
    "parts_and_front",
    "pairs_may_be_bars",
    "pieces_are_bars",
    "planar_patches",
    "pointed_end_pairs",
    "pointed_ends",
]

# ------------------------------------------------------------------------------ closed surface
#: Most distances (pairs x loop size^2) compared at once by :func:`_match_loop_pairs`.
_MATCH_CHUNK = 1 << 22


def _match_loop_pairs(V, table: CapTable, ij, tol):
    """Which pairs of caps ``ij`` (equal loop sizes) have loops congruent by a translation.

    Loops ``A``, ``B`` match when ``B[perm] == A + T`` to ``tol`` for the translation ``T``
    between their centroids and ``perm`` (each point of ``A + T``'s nearest in ``B``) a
    permutation; vectorized over the pairs of one loop size.

    Returns
    -------
    ok : (k,) bool
    T : (k, 3) float64
        The translations from ``ij[:, 0]``'s loop to ``ij[:, 1]``'s.
    """
    ok = np.zeros(ij.shape[0], dtype=bool)
    Ts = np.zeros((ij.shape[0], 3))
    size = table.size
    for n in np.unique(size[ij[:, 0]]).tolist() if ij.size else []:  # a few loop sizes
        rows = np.flatnonzero(size[ij[:, 0]] == n)
        step = max(1, _MATCH_CHUNK // (n * n))
        for s in range(0, rows.size, step):  # chunks of pairs
            r = rows[s : s + step]
            A, B = V[table.loop_rows(ij[r, 0])], V[table.loop_rows(ij[r, 1])]
            T = B.mean(axis=1) - A.mean(axis=1)
            D = np.linalg.norm((A + T[:, None])[:, :, None] - B[:, None], axis=3)
            perm = np.argmin(D, axis=2)
            d = np.take_along_axis(D, perm[:, :, None], axis=2)[:, :, 0]
            ps = np.sort(perm, axis=1)
            uniq = np.all(ps[:, 1:] != ps[:, :-1], axis=1)
            ok[r] = (d.max(axis=1) <= tol) & uniq
            Ts[r] = T
    return ok, Ts


#: Most (sample point, face) screen-box tests :func:`_covering` forms at once.
_COVER_CHUNK = 1 << 22


def _covering(P: np.ndarray, T: np.ndarray, tol: float):
    """The faces covering camera-frame points on screen, for all points at once.

    A face covers point ``k`` when its screen box holds it (to ``tol``) and its barycentric
    coordinates there are all at least -1e-9.

    Parameters
    ----------
    P : (k, 3) float64
        Camera-frame points.
    T : (m, 3, 3) float64
        Camera-frame triangles.

    Returns
    -------
    point, face : (c,) int64
        The covering (point, face) pairs.
    z : (c,) float64
        The face's depth at the point.
    """
    from ..geometry2d import barycentric

    x = P[:, :2]
    lo, hi = T[:, :, :2].min(axis=1), T[:, :, :2].max(axis=1)
    # the faces whose box meets the points' box (a superset of each point's)
    near = np.flatnonzero(np.all((lo <= x.max(axis=0) + tol) & (hi >= x.min(axis=0) - tol), axis=1))
    lo, hi = lo[near], hi[near]
    ks, fs = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    step = max(1, _COVER_CHUNK // max(near.size, 1))
    for s in range(0, x.shape[0], step):  # chunks of points
        xs = x[s : s + step, None]
        k, f = np.nonzero(np.all((lo <= xs + tol) & (hi >= xs - tol), axis=2))
        ks.append(k + s)
        fs.append(near[f])
    k, f = np.concatenate(ks), np.concatenate(fs)
    B = barycentric(x[k], T[f, :, :2])
    inside = np.all(B >= -1e-9, axis=1)
    k, f, B = k[inside], f[inside], B[inside]
    return k, f, (B * T[f, :, 2]).sum(axis=1)


def _tube_hidden(points, depth_gap, C, F, front, R, tol, own, margin) -> bool:
    """Are the 3D ``points`` (on a bridge) behind model faces nearer than both pieces?

    Each point must be covered on screen (:func:`_covering`) by a face toward the viewer
    nearer than ``max(z, z + depth_gap) + tol``.  Faces of the pieces' own parts (``own``,
    (#F,) bool) count only when they are nearer by more than ``margin`` (a bar's width): two
    blocks a hair apart cover the hair between them with their own faces, which hides
    nothing a viewer would complete.
    """
    P = points @ R.T
    T = C[F[front]]
    slack = np.where(own[front], margin, 0.0)
    k, f, z = _covering(P, T, tol)
    zmax = np.full(P.shape[0], -np.inf)
    np.maximum.at(zmax, k, z - slack[f])
    return bool(np.all(zmax > np.maximum(P[:, 2], P[:, 2] + depth_gap) + tol))


#: The ends of a bar broken at a crossing are seen edge-on (their planes hold the view, up to
#: this |cos|: a person's view is approximate); an end face seen shows that the bar stops.
CROSSING_EDGE_ON = 0.05
#: A crossing bar's band along the broken bar may differ from the gap by this share of the
#: gap (a person's view is approximate: a sliver of background beside the crossing bar).
CROSSING_SLACK = 0.35


#: The last model's adjacency and planar patches (its arrays are kept, so their ids stay its).
_PATCHES: dict = {}


def _own_bar_faces(V, F, be: BarEnds, tol) -> np.ndarray:
    """(#F,) bool: the two caps and the planar patches of the side faces next to them (the
    broken bar's own faces, which cover its gap on screen when it is seen along itself)."""
    key = (id(V), id(F), F.shape[0], tol)
    if _PATCHES.get("key") != key:  # one model's pairs are judged in a row: computed once
        TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
        _PATCHES.update(key=key, arrays=(V, F), TT=TT, patch=planar_patches(V, F, TT, tol))
    TT, patch = _PATCHES["TT"], _PATCHES["patch"]
    caps = np.concatenate([be.first.faces, be.second.faces])
    nbs = TT[caps].reshape(-1)
    return np.isin(patch, patch[np.r_[caps, nbs[nbs >= 0]]])


def _far_cover(P: np.ndarray, T: np.ndarray, tol: float, width: float) -> np.ndarray:
    """(k,) per camera-frame point ``P`` among the triangles ``T`` (:func:`_covering`): 1
    covered by a face farther than ``width`` and by nothing nearer than ``tol``, 2 covered by
    such a far face and by something nearer (the pieces), 0 not covered by a far face, -1
    covered only by nearer faces."""
    k, _, z = _covering(P, T, tol)
    far = np.bincount(k[z < P[k, 2] - width], minlength=P.shape[0]) > 0
    near = np.bincount(k[z > P[k, 2] + tol], minlength=P.shape[0]) > 0
    return np.where(far, 1 + near, -near.astype(np.int64))


def crossing_behind(points, c0, span, C, F, front, R, tol, width) -> bool:
    """Is the gap ``c0 -> c0 + span`` of a bar broken in line filled on screen by one bar
    lying behind it (the impossible cube's crossing)?

    Every sample ``points`` (3D, on the bridge) must be covered by front faces that are all
    farther than the bridge by more than the bar's screen ``width`` (nothing nearer, no
    background); and along the bridge's axis on screen the run of such far faces around the
    gap's middle must be as long as the gap, within :data:`CROSSING_SLACK` of it -- a bar
    crossing the gap, not a wall or floor behind everything (which covers far beyond it).
    """
    T = C[F[front]]
    if not np.all(_far_cover(points @ R.T, T, tol, width) == 1):
        return False
    s = np.linspace(-1.0, 2.0, 61)  # the axis from one gap length before to one after
    cover = _far_cover((c0[None] + s[:, None] * span[None]) @ R.T, T, tol, width) >= 1
    mid = int(np.argmin(np.abs(s - 0.5)))
    a = b = mid
    while a > 0 and cover[a - 1]:
        a -= 1
    while b < s.size - 1 and cover[b + 1]:
        b += 1
    run = s[b] - s[a] + (s[1] - s[0])
    return bool(cover[mid] and abs(run - 1.0) <= CROSSING_SLACK)


@dataclass(frozen=True)
class BarEnds:
    """Two caps that may be the ends of one broken bar (view-independent).

    Attributes
    ----------
    first, second : Cap
    T : (3,) float
        Translation from ``first``'s loop to ``second``'s.
    d : (3,) float or None
        The bar's direction at ``first`` (its side faces' common direction, pointing out of
        the cap), None when the caps' sides do not run along one direction.
    match : (n,) int64 or None
        Ends that are not flat (:func:`pointed_end_pairs`): for each vertex of ``first.loop``,
        the index in ``second.loop`` of the vertex on the same side edge of the bar.
    """

    first: Cap
    second: Cap
    T: np.ndarray
    d: np.ndarray | None
    match: np.ndarray | None = None


def bar_end_pairs(
    V: np.ndarray,
    F: np.ndarray,
    tol: float,
    TT: np.ndarray | None = None,
    R: Any = None,
    pointed: bool = True,
) -> list:
    """Pairs of caps -- planar patches bounded by one loop -- with opposite normals whose loops
    are congruent by a translation: the candidates for the two ends of a broken bar.  Each
    unordered pair comes once per orientation.  With ``pointed``, also the pairs of ends that
    are not flat (:func:`pointed_end_pairs`).

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
    tol : float
        Absolute tolerance.
    TT : (#F, 3) int64, optional
        ``igl.triangle_triangle_adjacency(F)[0]``.
    R : (3, 3) float64, optional
        A view frame: only pairs that can be junctions from it are returned, found on screen
        (caps that coincide, or that lie on one screen line along their bar) in linear time.
        Without it (the automatic view), every pair with opposite normals and equal loops is
        compared when there are at most :data:`MAX_CAP_PAIRS` of them; with more (a scene of
        equal blocks, a fine mesh whose facets have opposite facets), the pairs that may be a
        junction from some view (:func:`~.caps.junction_candidates`: caps in one plane, or
        two bars facing each other), the nearest first, up to :data:`MAX_CAP_PAIRS`.
    pointed : bool, optional
        Default True.

    Returns
    -------
    list of BarEnds
    """
    if TT is None:
        TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    patch = planar_patches(V, F, TT, tol)
    table = cap_table(V, F, TT, patch)
    out = _flat_pairs(V, F, TT, patch, tol, R, table)
    if pointed:
        Rf = None if R is None else np.asarray(R, dtype=np.float64)
        out += pointed_end_pairs(V, F, TT, patch, tol, Rf, table)
    return out


def _flat_pairs(V, F, TT, patch, tol, R, table: CapTable) -> list:
    """:func:`bar_end_pairs` of the flat caps (all of them at once)."""
    if len(table) < 2:
        return []
    size = table.size
    cen = table.centroids(V)
    D = side_directions(V, F, TT, patch, table)
    if R is None:
        ij, _ = opposite_pairs(size, table.normal, MAX_CAP_PAIRS)
        if ij is None:
            part = _components(F, TT)
            ij = junction_candidates(V, F, part, table, D, cen, tol, MAX_CAP_PAIRS)
    else:
        R = np.asarray(R, dtype=np.float64)
        s2 = cen @ R[:2].T
        cand = [cKDTree(s2).query_pairs(tol, output_type="ndarray")]
        # caps on one screen line along their bar: key (direction angle, offset of the line)
        rows = np.flatnonzero(~np.isnan(D[:, 0]))
        U = D[rows] @ R[:2].T
        nu = np.linalg.norm(U, axis=1)
        rows, U = rows[nu > 1e-9], U[nu > 1e-9] / nu[nu > 1e-9, None]
        U[(U[:, 0] < 0) | ((U[:, 0] == 0) & (U[:, 1] < 0))] *= -1.0
        if rows.size:
            off = U[:, 0] * s2[rows, 1] - U[:, 1] * s2[rows, 0]
            K = np.c_[np.arctan2(U[:, 1], U[:, 0]), off]
            K *= [np.linalg.norm(np.ptp(s2, axis=0)) + 1.0, 1.0]
            cand.append(rows[cKDTree(K).query_pairs(10 * tol, output_type="ndarray")])
        ij = np.unique(np.sort(np.vstack(cand).reshape(-1, 2), axis=1), axis=0)
    nrm = table.normal
    ij = ij[size[ij[:, 0]] == size[ij[:, 1]]]
    ij = ij[np.einsum("ij,ij->i", nrm[ij[:, 0]], nrm[ij[:, 1]]) <= -1.0 + CAP_NORMAL_TOL]
    ok, Ts = _match_loop_pairs(V, table, ij, tol)
    out = []
    for (i, j), T in zip(ij[ok].tolist(), Ts[ok]):  # the pairs of congruent caps
        a, b = table.cap(i), table.cap(j)
        da, db = D[i], D[j]
        facing = not np.isnan(da[0] + db[0]) and da @ db <= -1.0 + 1e-9
        out.append(BarEnds(a, b, T, da if facing else None))
        out.append(BarEnds(b, a, -T, db if facing else None))
    return out


def _components(F, TT) -> np.ndarray:
    """(#F,) the connected part of each face (faces joined across shared edges)."""
    f = np.repeat(np.arange(F.shape[0]), 3)
    ok = TT.reshape(-1) >= 0
    A = sp.coo_matrix((np.ones(int(ok.sum())), (f[ok], TT.reshape(-1)[ok])), (F.shape[0],) * 2)
    return csgraph.connected_components(A, directed=False)[1]


#: A face is a side face of a bar along ``d`` when its unit normal has |n . d| below this.
SIDE_TOL = 1e-6
#: Ends that are not flat have at most this many faces (a pointed or notched bar end).
MAX_END_FACES = 64
#: Bar directions searched for ends that are not flat: the most frequent edge directions
#: (a bar's side edges run along it), at most this many, each of at least 3 edges.
MAX_END_DIRECTIONS = 6


def _bar_directions(V: np.ndarray, F: np.ndarray):
    """The directions shared by at least 3 edges, the most frequent first (at most
    :data:`MAX_END_DIRECTIONS`): ``(k, 3)`` unit directions and, per direction, its edges."""
    E = np.sort(np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]], axis=1)
    E = E[np.unique(E[:, 0] * V.shape[0] + E[:, 1], return_index=True)[1]]
    u = V[E[:, 1]] - V[E[:, 0]]
    u /= np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-300)
    first = np.argmax(np.abs(u) > 1e-9, axis=1)  # sign: first non-zero component positive
    u *= np.sign(u[np.arange(u.shape[0]), first])[:, None]
    k = np.round(u / 1e-6).astype(np.int64) + (1 << 20)  # in [0, 2^21): one int64 key
    key = (k[:, 0] << 42) | (k[:, 1] << 21) | k[:, 2]
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    top = np.argsort(-cnt, kind="stable")[:MAX_END_DIRECTIONS]
    top = top[cnt[top] >= 3]
    inv = inv.reshape(-1)
    edges = [E[inv == t] for t in top.tolist()]
    return np.array([u[inv == t][0] for t in top.tolist()]).reshape(-1, 3), edges


def pointed_ends(V: np.ndarray, F: np.ndarray, TT: np.ndarray, patch: np.ndarray) -> list:
    """Bar ends that are not square caps: for a bar direction ``d`` (:func:`_bar_directions`),
    a connected set of at most :data:`MAX_END_FACES` faces none of which is a side face (unit
    normal with |n . d| > :data:`SIDE_TOL`), each at an end of an edge along ``d`` (a side
    edge of the bar), all turned one way along ``d``, bounded by one loop of side faces, and
    not one planar patch square to ``d`` (a cap, :func:`find_caps`): a pointed, roof-shaped,
    notched or bevelled end.  Only the faces at the side edges' ends are looked at (linear
    in them, not in the model).

    Returns
    -------
    list of Cap
        ``flat`` False, ``normal`` the bar's direction out of the end.
    """
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    corner_v = F.reshape(-1)
    by_vertex = np.argsort(corner_v, kind="stable")  # corners grouped by vertex
    start = np.searchsorted(corner_v[by_vertex], np.arange(V.shape[0] + 1))
    out = []
    dirs, edges = _bar_directions(V, F)
    for d, Ed in zip(dirs, edges):  # a few directions
        w = np.unique(Ed)
        cnt = start[w + 1] - start[w]
        at_w = np.repeat(start[w] - (np.cumsum(cnt) - cnt), cnt) + np.arange(cnt.sum())
        fs = np.unique(by_vertex[at_w] // 3)  # the faces at the side edges' ends
        s = n[fs] @ d
        fs, s = fs[np.abs(s) > SIDE_TOL], s[np.abs(s) > SIDE_TOL]
        if fs.size == 0:
            continue
        local = np.full(F.shape[0], -1, dtype=np.int64)
        local[fs] = np.arange(fs.size)
        nb = TT[fs]  # (k, 3)
        ln = np.where(nb >= 0, local[np.maximum(nb, 0)], -1)
        r, c = np.nonzero(ln >= 0)
        A = sp.coo_matrix((np.ones(r.size), (r, ln[r, c])), (fs.size,) * 2)
        label = csgraph.connected_components(A, directed=False)[1]
        # a component is an end when each neighbour outside it is a side face
        nbn = n[np.maximum(nb, 0)] @ d
        leak = (nb < 0) | ((ln < 0) & (np.abs(nbn) > SIDE_TOL))
        closed = np.bincount(label, weights=leak.any(axis=1), minlength=label.max() + 1) == 0
        o = np.argsort(label, kind="stable")
        at = np.flatnonzero(np.r_[True, label[o][1:] != label[o][:-1]])
        size = np.diff(np.r_[at, o.size])
        so = s[o]
        one_way = (np.minimum.reduceat(so, at) > 0) | (np.maximum.reduceat(so, at) < 0)
        po = patch[fs[o]]
        square = (np.minimum.reduceat(po, at) == np.maximum.reduceat(po, at)) & (
            np.minimum.reduceat(np.abs(so), at) >= 1.0 - CAP_NORMAL_TOL
        )
        keep = closed[label[o][at]] & (size <= MAX_END_FACES) & one_way & ~square
        for a, k in zip(at[keep].tolist(), size[keep].tolist()):  # the few shaped ends
            faces = np.sort(fs[o[a : a + k]])
            loop = _boundary_loop(F, TT, faces)
            if loop is not None:
                out.append(Cap(faces, loop, d * np.sign(so[a]), flat=False))
    return out


def _boundary_loop(F: np.ndarray, TT: np.ndarray, faces: np.ndarray):
    """The boundary of a set of faces as one loop of vertices (in the faces' orientation), or
    None when it is not one simple loop."""
    fe = np.repeat(faces, 3)
    corner = np.tile(np.arange(3), faces.size)
    nb = TT[faces].reshape(-1)
    he = (nb < 0) | ~np.isin(nb, faces)
    tail, head = F[fe[he], corner[he]], F[fe[he], (corner[he] + 1) % 3]
    nxt = dict(zip(tail.tolist(), head.tolist()))
    if tail.size == 0 or len(nxt) != tail.size:
        return None  # a vertex with two outgoing boundary edges: not a simple loop
    loop = [int(tail[0])]
    while len(loop) <= tail.size and nxt[loop[-1]] != loop[0]:
        loop.append(nxt[loop[-1]])
    return np.asarray(loop, np.int64) if len(loop) == tail.size else None


def pointed_end_pairs(
    V: np.ndarray,
    F: np.ndarray,
    TT: np.ndarray,
    patch: np.ndarray,
    tol: float,
    R: np.ndarray | None = None,
    caps: list | CapTable | None = None,
) -> list:
    """Pairs of bar ends, at least one of them not a square cap (:func:`pointed_ends`; the
    other may be one of ``caps``, :func:`find_caps` or its :class:`~.caps.CapTable`), facing
    opposite ways along one bar direction, whose loops are congruent by a translation once
    projected along the bar (one cross-section: the side edges of one bar), each with the
    vertex correspondence; whether they face each other depends on the view
    (:func:`junction_at`).

    A bar broken with pointed, bevelled or notched ends is completed by a viewer as one bar
    just as a bar broken with square caps (the ends' shapes lie in the gap, which the
    occluder hides).  Each unordered pair comes once per orientation; ``T`` is the translation
    between the loops' centroids.  With a view frame ``R``, only pairs whose ``T`` lies in the
    plane of the bar and the view (the pieces in line on screen) are kept.
    """
    shaped = pointed_ends(V, F, TT, patch)
    if not shaped:
        return []
    if isinstance(caps, CapTable):
        flat, fsize, fnrm, fcen = caps.cap, caps.size, caps.normal, caps.centroids(V)
    else:
        fl = [c for c in caps or [] if c.flat]
        flat, fsize = fl.__getitem__, np.array([c.loop.size for c in fl], np.int64)
        fnrm = np.array([c.normal for c in fl]).reshape(-1, 3)
        fcen = np.array([V[c.loop].mean(axis=0) for c in fl]).reshape(-1, 3)
    ns = len(shaped)
    size = np.r_[[e.loop.size for e in shaped], fsize]
    nrm = np.vstack([[e.normal for e in shaped], fnrm])
    cen = np.vstack([[V[e.loop].mean(axis=0) for e in shaped], fcen])
    later = np.arange(size.size)
    out: list = []
    for i, (a, d) in enumerate(zip(shaped, nrm)):  # the few shaped ends
        T = cen - cen[i]
        j = (size == size[i]) & (nrm @ d <= -1.0 + CAP_NORMAL_TOL)
        j &= (later > i) | (later >= ns)  # each pair of shaped ends once
        if R is not None:  # T = l d + g v: off the plane of d and the view by at most 2 tol
            c = np.cross(d, R[2])
            off = np.abs(T @ c) / max(np.linalg.norm(c), 1e-300)
            if np.linalg.norm(c) <= 1e-9:  # seen along the bar: T along it
                off = np.linalg.norm(np.cross(T, d), axis=1)
            j &= off <= 2 * tol
        Pa = V[a.loop] - np.outer(V[a.loop] @ d, d)  # projected along the bar
        for k in np.flatnonzero(j).tolist():  # the candidates
            b = shaped[k] if k < ns else flat(k - ns)
            Pb = V[b.loop] - np.outer(V[b.loop] @ d, d)
            D = np.linalg.norm(Pa[:, None] + (T[k] - (T[k] @ d) * d) - Pb[None], axis=2)
            m = np.argmin(D, axis=1)
            if D[np.arange(m.size), m].max() > tol or np.unique(m).size != m.size:
                continue
            out.append(BarEnds(a, b, T[k], d, m))
            out.append(BarEnds(b, a, -T[k], b.normal, np.argsort(m)))
    return out[: 2 * MAX_CAP_PAIRS]


#: Up to this many query points the winding number is summed over the faces directly (one
#: pass per point); libigl's hierarchy costs about as much as 15 such passes to build.
_DIRECT_WINDING = 12


def winding_numbers(V: np.ndarray, F: np.ndarray, P: np.ndarray) -> np.ndarray:
    """(#P,) generalized winding numbers of the points ``P`` (k, 3) with respect to the
    triangles ``(V, F)``: the sum of the faces' signed solid angles over 4 pi (Van Oosterom
    and Strackee's formula), as ``igl.winding_number``; a few points summed directly, more
    with libigl's hierarchy."""
    if P.shape[0] > _DIRECT_WINDING:
        return igl.winding_number(V, F, P)
    T = V[F]
    out = np.zeros(P.shape[0])
    for k, p in enumerate(P):  # a few points
        A, B, C = T[:, 0] - p, T[:, 1] - p, T[:, 2] - p
        a, b, c = (np.linalg.norm(X, axis=1) for X in (A, B, C))
        num = np.einsum("ij,ij->i", A, np.cross(B, C))
        den = a * b * c + c * np.einsum("ij,ij->i", A, B)
        den += a * np.einsum("ij,ij->i", B, C) + b * np.einsum("ij,ij->i", C, A)
        out[k] = np.arctan2(num, den).sum() / (2.0 * np.pi)
    return out


def bridges_blocked(V: np.ndarray, F: np.ndarray, R: np.ndarray, pairs: list) -> np.ndarray:
    """Does the bridge :func:`junction_at` would build for each pair from view ``R`` run
    through a solid?

    The bridge's axis, ``c0 + s l d`` for ``s`` in (1/1000, 1/4, 1/2, 3/4) with ``c0`` the
    first cap's centroid and ``T = l d + g v`` solved in least squares, is blocked where
    libigl's generalized winding number exceeds 1/2.  So is a pair either of whose caps rests
    on another part (a tower standing on its ground slab: just outside the flat cap, a
    thousandth of ``l`` along its normal, lies a solid): that end is not broken off.  One winding-number call for all pairs: its
    set-up is what a call costs, so judging a scene's thousands of pairs one by one grew
    with pairs times faces.

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
    R : (3, 3) float64
        ``view_frame(view, up)``.
    pairs : list of BarEnds

    Returns
    -------
    (#pairs,) bool
        False for pairs with no bar direction (no bridge to build).
    """
    v = R[2]
    out = np.zeros(len(pairs), dtype=bool)
    k = [i for i, be in enumerate(pairs) if be.d is not None and be.first.normal @ be.d > 0]
    if not k:
        return out
    d = np.array([pairs[i].d for i in k])
    T = np.array([pairs[i].T for i in k])
    M = np.stack([d, np.broadcast_to(v, d.shape)], axis=2)  # (k, 3, 2)
    # lstsq's solution, batched: the same cut-off of small singular values (3 eps)
    ell = (np.linalg.pinv(M, 3.0 * np.finfo(np.float64).eps) @ T[:, :, None])[:, 0, 0]
    c0 = np.array([V[pairs[i].first.loop].mean(axis=0) for i in k])
    axis = c0[:, None] + np.array([0.25, 0.5, 0.75])[None, :, None] * (ell[:, None] * d)[:, None]
    c1 = np.array([V[pairs[i].second.loop].mean(axis=0) for i in k])
    n0 = np.array([pairs[i].first.normal for i in k])
    n1 = np.array([pairs[i].second.normal for i in k])
    past = 1e-3 * np.abs(ell)[:, None]
    rests = np.stack([c0 + past * n0, c1 + past * n1], axis=1)  # (k, 2, 3)
    w = winding_numbers(V, F, np.concatenate([axis, rests], axis=1).reshape(-1, 3)).reshape(-1, 5)
    flat = np.array([[pairs[i].first.flat, pairs[i].second.flat] for i in k])
    w[:, 3:] *= flat  # past a shaped end's loop lies its own point or roof
    out[k] = np.any(np.abs(w) > 0.5, axis=1)
    return out


def may_be_junctions(pairs: list, R: np.ndarray, tol: float, bridge: bool) -> np.ndarray:
    """(#pairs,) bool, False only for pairs :func:`junction_at` surely finds no junction for
    from view ``R``: the caps do not coincide on screen, and ``T = l d + g v`` has no solution
    with ``l > 0`` (or no bar direction ``d``).  Vectorized over the pairs, with twice the
    tolerance (a superset: :func:`junction_at` decides), so that a scene's many pairs on one
    screen line are not each solved on their own."""
    out = np.zeros(len(pairs), dtype=bool)
    if not pairs:
        return out
    v = R[2]
    T = np.array([be.T for be in pairs])
    gap = T @ v
    out |= (np.linalg.norm(T - gap[:, None] * v, axis=1) <= 2 * tol) & (np.abs(gap) > 0.5 * tol)
    if not bridge:
        return out
    k = [i for i, be in enumerate(pairs) if be.d is not None and be.first.normal @ be.d > 0]
    if not k:
        return out
    d = np.array([pairs[i].d for i in k])
    M = np.stack([d, np.broadcast_to(v, d.shape)], axis=2)  # (k, 3, 2)
    x = (np.linalg.pinv(M, 3.0 * np.finfo(np.float64).eps) @ T[k, :, None])[:, :, 0]
    res = np.linalg.norm((M @ x[:, :, None])[:, :, 0] - T[k], axis=1)
    out[k] |= (x[:, 0] > 0.5 * tol) & (res <= 2 * tol)
    return out


def pieces_are_bars(V: np.ndarray, F: np.ndarray, part: np.ndarray, be: BarEnds) -> bool:
    """Does each piece run along the bar from its cap farther than the cap is wide?

    A viewer completes a bar behind an occluder from two *bars* in line (elongated pieces:
    good continuation); blocks as long as they are wide -- a grid of cubes or tiles -- are
    separate objects, however they line up.  A piece's length is its part's extent along the
    bar's direction ``be.d`` back from its cap (a frame's whole extent when the pieces belong
    to one welded frame); the cap's width is the largest distance between its loop's points.
    """
    d = be.d
    out = []
    for cap, sign in ((be.first, 1.0), (be.second, -1.0)):  # the two pieces
        P = V[cap.loop]
        width = float(np.linalg.norm(P[:, None] - P[None], axis=2).max())
        verts = np.unique(F[part == part[cap.faces[0]]])
        length = float(np.max(sign * ((P.mean(axis=0) - V[verts]) @ d)))
        out.append(length > width)
    return all(out)


#: Most (piece, vertex) products :func:`pairs_may_be_bars` forms at once.
_EXTENT_CHUNK = 1 << 22


def pairs_may_be_bars(
    V: np.ndarray, F: np.ndarray, part: np.ndarray, pairs: list, slack: float | None = None
) -> np.ndarray:
    """(#pairs,) bool: :func:`pieces_are_bars` for all pairs at once, as a superset within
    ``slack`` (default 1e-9 of the model's size; 0: exactly the rule): False for pairs without
    a bar direction pointing out of the first cap, and where a piece is not longer along the
    bar than its cap is wide by more than ``slack``.

    Each piece's length is ``c . d - min x . d`` over its part's vertices ``x`` (one matrix
    product per part holding pieces), its width the largest distance between its loop's
    points (per loop size)."""
    out = np.zeros(len(pairs), dtype=bool)
    rows = [i for i, be in enumerate(pairs) if be.d is not None and be.first.normal @ be.d > 0]
    if not rows:
        return out
    caps = [c for i in rows for c in (pairs[i].first, pairs[i].second)]
    dirs = (
        np.repeat([pairs[i].d for i in rows], 2, axis=0) * np.tile([1.0, -1.0], len(rows))[:, None]
    )
    size = np.array([c.loop.size for c in caps])
    cen, width = np.zeros((size.size, 3)), np.zeros(size.size)
    for n in np.unique(size).tolist():  # a few loop sizes
        k = np.flatnonzero(size == n)
        P = V[np.array([caps[i].loop for i in k.tolist()])]
        cen[k] = P.mean(axis=1)
        step = max(1, _EXTENT_CHUNK // (n * n))
        for s in range(0, k.size, step):  # chunks of pieces
            Q = P[s : s + step]
            width[k[s : s + step]] = np.linalg.norm(Q[:, :, None] - Q[:, None], axis=3).max((1, 2))
    cpart = part[np.array([c.faces[0] for c in caps])]
    length = np.full(size.size, -np.inf)
    fo = np.argsort(part, kind="stable")
    bounds = np.searchsorted(part[fo], np.arange(int(part.max()) + 2))
    for p in np.unique(cpart).tolist():  # the parts holding pieces
        X = V[np.unique(F[fo[bounds[p] : bounds[p + 1]]])]
        k = np.flatnonzero(cpart == p)
        step = max(1, _EXTENT_CHUNK // X.shape[0])
        for s in range(0, k.size, step):  # chunks of pieces
            r = k[s : s + step]
            length[r] = np.einsum("ij,ij->i", cen[r], dirs[r]) - (dirs[r] @ X.T).min(axis=1)
    if slack is None:
        slack = 1e-9 * (1.0 + float(np.abs(V).max()))
    out[rows] = np.all((length + slack > width).reshape(-1, 2), axis=1)
    return out


def _end_seen(V, F, cap: Cap, v) -> bool:
    """Is a face of the bar end ``cap`` seen from ``v`` (not edge-on to
    :data:`CROSSING_EDGE_ON`)?"""
    if cap.flat:
        return bool(abs(cap.normal @ v) > CROSSING_EDGE_ON)
    T = V[F[cap.faces]]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    return bool(np.max(np.abs(n @ v) / np.linalg.norm(n, axis=1)) > CROSSING_EDGE_ON)


def junction_at(V, F, C, R, be: BarEnds, tol, front, part, bridge, blocked=None):
    """What the bar ends ``be`` are from view ``R``: ("false edge", gap, None),
    ("hidden gap", g, ell), ("crossing", 0, ell) or None.

    Pieces in line in 3D (``g`` = 0) hidden behind nearer faces are no junction: joining them
    would change the topology without a period (a grid of blocks would be joined into a
    lattice).  They are a **crossing** (the impossible cube's trick) when both ends are seen
    edge-on (:data:`CROSSING_EDGE_ON`) and the gap between them is filled on screen by one bar
    lying *behind* them, its band as wide as the gap
    (:func:`crossing_behind`): a viewer completes the broken bar behind the crossing bar,
    which contradicts the depths elsewhere (impossible through the depth order).

    ``blocked``: :func:`bridges_blocked` for ``be``, when computed for many pairs at once."""
    v = R[2]
    gap = float(be.T @ v)
    if np.linalg.norm(be.T - gap * v) <= tol and abs(gap) > tol:
        # both caps contain the view and coincide on screen: a false edge
        if not (be.first.flat and be.second.flat) or abs(be.first.normal @ v) > 1e-6 or gap < 0:
            return None  # (each unordered pair once: the one gaining depth)
        return "false edge", gap, None
    d = be.d
    if not bridge or d is None or be.first.normal @ d <= 0:
        return None
    M = np.stack([d, v], axis=1)
    (ell, g), *_ = np.linalg.lstsq(M, be.T, rcond=None)
    if ell <= tol or np.linalg.norm(M @ [ell, g] - be.T) > tol:
        return None
    P0 = V[be.first.loop]
    c0 = P0.mean(axis=0)
    axis = c0 + np.array([[0.25], [0.5], [0.75]]) * ell * d
    # the bridge must run through empty space (not through a block in between) and be hidden
    # (libigl's generalized winding number: ~1 inside a solid)
    if blocked is None:
        blocked = bool(np.any(np.abs(winding_numbers(V, F, axis)) > 0.5))
    if blocked:
        return None
    S = [0.9 * P0 + 0.1 * c0 + s * ell * d for s in (0.25, 0.5, 0.75)] + [axis]
    if abs(g) <= tol:
        if _end_seen(V, F, be.first, v) or _end_seen(V, F, be.second, v):
            return None  # an end face seen: the bar visibly stops there
        if not pieces_are_bars(V, F, part, be):
            return None  # blocks as long as they are wide: separate objects
        width = float(np.ptp(P0 @ R[:2].T, axis=0).max())
        own = _own_bar_faces(V, F, be, tol)
        if crossing_behind(np.vstack(S), c0, ell * d, C, F, front & ~own, R, tol, width):
            return "crossing", 0.0, float(ell)
        return None
    if not pieces_are_bars(V, F, part, be):
        return None  # blocks as long as they are wide (tiles, cubes): separate objects
    own = np.isin(part, part[[be.first.faces[0], be.second.faces[0]]])
    width = float(np.ptp(P0, axis=0).max())
    if not _tube_hidden(np.vstack(S), g, C, F, front, R, tol, own, width):
        return None
    return "hidden gap", float(g), float(ell)


def parts_and_front(V, F, TT, R):
    """The connected part of each face, camera-frame vertices ``V R^T`` and the faces turned
    toward the viewer (by more than :data:`~.clip.FRONT_NZ`)."""
    part = _components(F, TT)
    C = V @ R.T
    N = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    front = N[:, 2] > FRONT_NZ * np.maximum(np.linalg.norm(N, axis=1), 1e-300)
    return part, C, front


def close_junctions(V, F, R, tol: float, bridge: bool = True, pairs: list | None = None):
    """Open a closed model at its junctions so that the cut-model gluing closes it crosswise.

    Pairs of *caps* (:func:`bar_end_pairs`: planar patches bounded by one loop, normals
    opposite, loops congruent by a translation ``T``) are the two ends of a bar the artist
    broke:

    * **false edge**: ``T`` is along the view (the caps coincide on screen, each containing the
      view direction, e.g. a capped U-tribar): both caps are removed; the two open loops
      coincide on screen and are glued crosswise by the cut-model path, ``|T|`` is the period;
    * **hidden gap** (``bridge``): ``T = l d + g v`` with ``d`` the bar's direction (the common
      direction of the faces beside each cap, pointing from one cap to the other), the bridge
      between them through empty space and hidden behind nearer faces: both caps are removed
      and the bar is continued from the first cap by ``l d`` (a tube of the same cross-section,
      the first piece's depth); its end loop coincides on screen with the second cap's loop,
      ``g`` apart in depth: the period.  Pieces in line in 3D (``g`` = 0) are left apart.
      Ends that are not square caps (pointed, notched, bevelled: :func:`pointed_end_pairs`)
      are bridged alike, the tube running along the first piece's side edges up to the
      second end's loop moved by ``-g v`` (each side edge its own length).

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
        A cleaned model (welded, oriented outward).
    R : (3, 3) float64
        ``view_frame(view, up)``.
    tol : float
        Absolute tolerance.
    bridge : bool
        Also bridge hidden gaps.
    pairs : list of BarEnds, optional
        :func:`bar_end_pairs` of the model, when already computed.

    Returns
    -------
    V2 : (#V2, 3) float64
        ``V`` with the tube ends appended.
    F2 : (#F2, 3) int64
        Faces of the opened model (caps removed, tubes added).
    source : (#F2,) int64
        Face of ``F`` each face comes from, -1 for tube faces (-2 for the tube of a crossing,
        which a viewer places behind the crossing bar).
    junctions : list of Junction
    """
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    if pairs is None:
        pairs = bar_end_pairs(V, F, tol, TT, R)
    part, C, front = parts_and_front(V, F, TT, R)
    used, drop, junctions = np.zeros(F.shape[0], dtype=bool), [], []
    newV, newF, tube_code = [], [], []
    nV = V.shape[0]
    may = may_be_junctions(pairs, R, tol, bridge)
    pairs = [be for be, m in zip(pairs, may.tolist()) if m]
    blocked = np.zeros(len(pairs), bool)
    if bridge:  # a bridge needs two bars (all pairs at once); a false edge does not
        bars = pairs_may_be_bars(V, F, part, pairs)
        keep = bars | may_be_junctions(pairs, R, tol, False)
        pairs, bars = [be for be, k in zip(pairs, keep.tolist()) if k], bars[keep]
        blocked = np.zeros(len(pairs), bool)  # (junction_at finds no bridge between non-bars)
        blocked[bars] = bridges_blocked(V, F, R, [pairs[i] for i in np.flatnonzero(bars)])
    for be, bl in zip(pairs, blocked.tolist()):  # the candidate pairs
        if used[be.first.faces].any() or used[be.second.faces].any():  # an end used already
            continue
        found = junction_at(V, F, C, R, be, tol, front, part, bridge, bl)
        if found is None:
            continue
        kind, gap, ell = found
        used[be.first.faces] = used[be.second.faces] = True
        drop += [be.first.faces, be.second.faces]
        loop = be.first.loop
        if kind != "false edge":
            ends = nV + np.arange(loop.size)
            nV += loop.size
            if be.match is None:
                newV.append(V[loop] + ell * be.d)
            else:  # up to the other end's loop, moved along the view onto the first's depth
                newV.append(V[be.second.loop[be.match]] - gap * R[2])
            nxt = np.roll(np.arange(loop.size), -1)
            p, q, pe, qe = loop, loop[nxt], ends, ends[nxt]
            newF += [np.stack([p, q, qe], 1), np.stack([p, qe, pe], 1)]
            tube_code += [-2 if kind == "crossing" else -1] * (2 * loop.size)
        pos = C[be.second.loop, :2].mean(axis=0)  # where the two sides are glued
        junctions.append(Junction(kind, pos, abs(gap), int(loop.size)))
    if not junctions:
        return V, F, np.arange(F.shape[0]), []
    keep = np.ones(F.shape[0], dtype=bool)
    keep[np.concatenate(drop)] = False
    tubes = np.vstack(newF) if newF else np.zeros((0, 3), np.int64)
    V2 = np.vstack([V, *newV]) if newV else V
    F2 = np.vstack([F[keep], tubes]).astype(np.int64)
    source = np.concatenate([np.flatnonzero(keep), np.asarray(tube_code, np.int64)])
    return V2, F2, source, junctions


def closed_surface(V, F, R, tol, rel, bridge, report, strict):
    """The whole model opened at its junctions and glued crosswise (``hidden=True``), or None."""
    from types import SimpleNamespace

    from ..cutmesh import glue_cut_mesh
    from ..order import DepthOrder

    V2, F2, source, junctions = close_junctions(V, F, R, tol, bridge)
    try:
        g = glue_cut_mesh(V2, F2, view=R[2], up=R[1], tol=rel)
    except MescherError as err:
        if strict:
            raise
        msg = f"the closed surface could not be glued ({err}); the visible surface instead"
        report.warnings.append(msg)
        return None
    for p in g["pairings"]:  # cut loops the model came with (a cut model)
        pos = g["xy"][g["vmap"][p.loop_a]].mean(axis=0)
        if not any(np.linalg.norm(pos - j.position) <= 10 * tol for j in junctions):
            junctions.append(Junction("false edge", pos, abs(p.depth_gap), int(p.loop_a.size)))
    if not junctions:
        if strict:
            raise MescherError(
                "hidden: expected junctions to glue (caps that pair up, hidden gaps, cut loops "
                "that coincide on screen), found none"
            )
        return None
    Z = (V2 @ R.T)[F2][:, :, 2]
    order = DepthOrder.from_embedding(SimpleNamespace(F=g["F"], xy=g["xy"]), Z)
    report.junctions = junctions
    report.route = "closed"
    report.reason = (
        f"{len(junctions)} junction(s) found: the whole model opened there and glued crosswise"
    )
    report.arcs = behind_crossing(
        np.asarray(order.arcs, np.int64).reshape(-1, 2), V2, F2, Z, source
    )
    report.n_arcs = int(report.arcs.shape[0])
    report.source_face = np.maximum(source, -1)
    report.repairs.append(
        f"kept the hidden side: {len(junctions)} junction(s) opened and glued crosswise, "
        f"{int(np.count_nonzero(source < 0))} bridge face(s)"
    )
    return VisibleModel(F=g["F"], xy=g["xy"], Z=Z, arcs=report.arcs, report=report)


def behind_crossing(arcs, V2, F2, Z, source):
    """The depth-order arcs with each crossing's tube (``source == -2``) put behind the model
    faces lying wholly behind it by more than its own width (the crossing bar a viewer sees
    in front of it); other arcs unchanged."""
    tube = source == -2
    if not tube.any() or arcs.shape[0] == 0:
        return arcs
    T = V2[F2]
    width = np.linalg.norm(T - T[:, [1, 2, 0]], axis=2).min(axis=1)
    i, j = arcs[:, 0], arcs[:, 1]  # i behind j
    flip = tube[j] & (source[i] >= 0) & (Z[i].max(axis=1) < Z[j].min(axis=1) - width[j])
    return np.where(flip[:, None], arcs[:, ::-1], arcs)
