"""Gluing the visible map: each shared screen edge is continuous, a false edge (glued
crosswise: its depth gap becomes a period) or a true occlusion (cut, with a depth-order arc).
A step whose riser hides behind the upper tread's front edge is joined by a thin riser band
carrying the real depth step (:func:`hidden_step_edges`, :func:`add_step_bands`)."""

from __future__ import annotations

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .alignment import accidental_alignments
from .caps import unit_normals
from .clip import face_planes, merge_points, plane_depth, split_t_junctions
from .records import EdgeSides, FalseEdges, Glue, Junction


# ------------------------------------------------------------------------------ gluing
def edge_on_source(xy, E, src, C, F, tol):
    """Index k of the source face's edge that screen edge E lies on (-1: inside the face).

    ``k`` is libigl's convention: edge ``k`` runs ``F[f, k] -> F[f, (k + 1) % 3]``.
    """
    out = np.full(E.shape[0], -1, dtype=np.int64)
    p, q = xy[E[:, 0]], xy[E[:, 1]]
    for k in range(3):
        a = C[F[src, k], :2]
        b = C[F[src, (k + 1) % 3], :2]
        d = b - a
        L = np.linalg.norm(d, axis=1)
        L = np.where(L > 0, L, 1.0)

        wp, wq = p - a, q - a
        dp = np.abs(wp[:, 0] * d[:, 1] - wp[:, 1] * d[:, 0]) / L
        dq = np.abs(wq[:, 0] * d[:, 1] - wq[:, 1] * d[:, 0]) / L
        out[(dp <= tol) & (dq <= tol) & (out < 0)] = k
    return out


def flat_edges(C: np.ndarray, F: np.ndarray, s: np.ndarray, nb: np.ndarray, tol: float):
    """(k,) bool: model face ``nb[i]`` (-1: none) lies in the plane of face ``s[i]`` (its three
    corners within ``tol`` of it), so the edge they share is no crease."""
    ok = nb >= 0
    n = unit_normals(C, F[s])
    off = np.einsum("kij,kj->ki", C[F[np.maximum(nb, 0)]] - C[F[s, :1]], n)
    return ok & np.all(np.abs(off) <= tol, axis=1)


def interior_edges(Fa: np.ndarray, n: int):
    """(pairs of faces sharing an edge, the edge's vertices, corner index in each face).

    Each half-edge pairs with at most one running the other way: the ``r``-th of an edge's
    half-edges one way (in face order) with its ``r``-th the other way.  An edge of two faces
    gives one pair; where faces overlap along an edge (a sliver left by clipping, a strip laid
    over a face), pairing more would glue one half-edge to two others (a non-manifold edge)
    or two running the same way (each end of the edge to the other).
    """
    he = np.stack([Fa[:, [1, 2]], Fa[:, [2, 0]], Fa[:, [0, 1]]], axis=1).reshape(-1, 2)
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    way = he[:, 0] < he[:, 1]
    order = np.lexsort((way, key))  # by edge, then way; face order kept within each
    ks, ws = key[order], way[order]
    new = np.r_[True, (ks[1:] != ks[:-1]) | (ws[1:] != ws[:-1])]
    first = np.flatnonzero(new)
    rank = np.arange(ks.size) - first[np.cumsum(new) - 1]
    o2 = np.lexsort((ws, rank, ks))  # the r-th of each way side by side
    k2, r2, w2 = ks[o2], rank[o2], ws[o2]
    same = np.flatnonzero((k2[1:] == k2[:-1]) & (r2[1:] == r2[:-1]) & (w2[1:] != w2[:-1]))
    h1, h2 = order[o2[same]], order[o2[same + 1]]
    return h1, h2, he


def classify(xy, Fa, src, Z, C, F, front, tol, ftol=None, n_model=None, false_edges=True):
    """Per shared screen edge: glue (continuous or false edge) or cut with an arc.

    ``ftol`` (#F,): per model face, the tolerance of its own part (``tol`` relative to the
    part's size, not the scene's): a false edge needs both model edges to coincide on screen
    to their parts' precision, so blocks a hair apart in a large scene are not glued.
    Model faces from ``n_model`` on are riser bands (:func:`add_step_bands`): their edges are
    never a silhouette, so they take no part in a false edge.  ``false_edges=False`` glues
    continuous edges only (every depth jump is an occlusion).
    """
    ftol = np.full(F.shape[0], tol) if ftol is None else ftol
    h1, h2, he = interior_edges(Fa, xy.shape[0])
    f1, f2 = h1 // 3, h2 // 3
    E = he[h1]  # p -> q as in face f1
    # depth of p and q in each face (corner positions of the half-edge)
    k1 = h1 % 3
    z1p, z1q = Z[f1, (k1 + 1) % 3], Z[f1, (k1 + 2) % 3]
    k2 = h2 % 3
    # in f2 the half-edge runs q -> p
    z2q, z2p = Z[f2, (k2 + 1) % 3], Z[f2, (k2 + 2) % 3]
    dp, dq = z2p - z1p, z2q - z1q
    continuous = (np.abs(dp) <= tol) & (np.abs(dq) <= tol)
    parallel = np.abs(dp - dq) <= tol
    # does each side end there on its own surface (silhouette or boundary of the model)?
    TT, _ = igl.triangle_triangle_adjacency(F)
    TT = np.asarray(TT)

    def ends(fs):
        s = src[fs]
        k = edge_on_source(xy, E, s, C, F, np.minimum(ftol[src[f1]], ftol[src[f2]]))
        nb = np.where(k >= 0, TT[s, np.maximum(k, 0)], 0)
        on = (k >= 0) & (s < (F.shape[0] if n_model is None else n_model))
        # an edge between two faces of one plane is the triangulation's, not a feature of the
        # surface: what lies along it on screen lies inside the face (the same shape meshed
        # otherwise has no edge there)
        on &= ~flat_edges(C, F, s, nb, tol)
        return on, on & ((nb < 0) | ~front[np.maximum(nb, 0)]), np.maximum(k, 0), nb

    (on1, e1, m1, nb1), (on2, e2, m2, nb2) = ends(f1), ends(f2)
    far1 = (dp + dq) > 0  # face 2 nearer
    # a false edge: both sides lie on an edge of their own model face and the nearer side ends
    # there (silhouette or boundary); the farther side may turn a crease whose other face the
    # nearer one hides -- the viewer sees one crease or one flat continuation
    false_edge = ~continuous & parallel & on1 & on2 & np.where(far1, e2, e1) & false_edges
    # ... unless the near object merely lies in front of the far edge
    sides = EdgeSides(h1, h2, far1, m1, m2, nb1, nb2, e1, e2)
    false_edge &= ~accidental_alignments(xy, Fa, Z, C, F, TT, front, src, sides, false_edge, tol)
    glue = continuous | false_edge
    cut = ~glue
    # true occlusion: the far face gets an arc to the near one
    arcs = np.stack([np.where(far1, f1, f2), np.where(far1, f2, f1)], axis=1)[cut]
    return (
        Glue(h1, h2, glue, continuous),
        arcs.astype(np.int64),
        FalseEdges(
            E[false_edge],
            0.5 * (dp + dq)[false_edge],
            np.where(far1, h1, h2)[cut & ~np.where(far1, e1, e2)],
        ),
    )


def reglue(glue: dict, Fb: np.ndarray, Z: np.ndarray, arcs: np.ndarray, tol: float):
    """Glued edges whose (perceived) depths on the two sides are no longer parallel become
    occlusions (cut, far -> near arc); parallel jumps stay glued (perceived false edges)."""
    h1, h2, ok = glue.h1, glue.h2, glue.glued.copy()
    a = he_depth(Z, h1)
    b = he_depth(Z, h2)[:, ::-1]  # the partner runs the other way
    d = b - a  # (k, 2): depth jump at tail and head
    # the model's own continuous edges stay glued (a crease a person sees; the projection onto
    # integrable forms reconciles the snapped planes there)
    jump = ok & (np.abs(d[:, 0] - d[:, 1]) > tol)
    bad = jump & ~glue.continuous
    # the model's own continuous edges become cuts too, unless that cuts the loops a person
    # follows (a relief whose snapped planes disagree at every crease): then they stay glued
    # and the projection onto integrable forms reconciles the snapped planes there
    cut_all = glue.with_glued(ok & ~jump)
    if betti1(cut_and_glue(Fb, cut_all)[0]) >= betti1(
        cut_and_glue(Fb, glue.with_glued(ok & ~bad))[0]
    ):
        bad = jump
    if bad.any():
        ok[bad] = False
        far1 = d[bad].sum(axis=1) > 0
        f1, f2 = h1[bad] // 3, h2[bad] // 3
        new = np.stack([np.where(far1, f1, f2), np.where(far1, f2, f1)], axis=1)
        arcs = np.vstack([arcs, new]).astype(np.int64)
    return glue.with_glued(ok), arcs


def betti1(F: np.ndarray) -> int:
    """First Betti number of a triangle mesh (orientable, manifold): ``E - V - F + C + closed``
    with ``C`` its connected parts and ``closed`` those without boundary (``b2``)."""
    he = np.stack([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]], axis=1).reshape(-1, 2)
    n = int(F.max(initial=0)) + 1
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    f = np.repeat(np.arange(F.shape[0]), 3)
    A = sp.coo_matrix((np.ones(f.size), (f, he[:, 0])), shape=(F.shape[0], n)).tocsr()
    A = sp.bmat([[None, A], [A.T, None]])
    k, lab = csgraph.connected_components(A, directed=False)
    comp = lab[: F.shape[0]]
    used = np.unique(F)
    parts = np.unique(comp)
    open_part = np.zeros(k, dtype=bool)
    open_part[comp[f[(cnt[inv] == 1)]]] = True
    n_closed = int(np.count_nonzero(~open_part[parts]))
    return int(cnt.size - used.size - F.shape[0] + parts.size + n_closed)


def stuck_cuts(Fm: np.ndarray, h1: np.ndarray, h2: np.ndarray) -> np.ndarray:
    """Cut edges whose two sides still share both end vertices after gluing (indices)."""
    f1, k1, f2, k2 = h1 // 3, h1 % 3, h2 // 3, h2 % 3
    a1, b1 = Fm[f1, (k1 + 1) % 3], Fm[f1, (k1 + 2) % 3]
    b2, a2 = Fm[f2, (k2 + 1) % 3], Fm[f2, (k2 + 2) % 3]
    return np.flatnonzero((a1 == a2) & (b1 == b2))


def split_cut_faces(xy, Fa, src, h1, h2):
    """Split both faces of each stuck cut edge at the edge's midpoint, one new vertex per side."""
    hs = np.concatenate([h1, h2])
    f, k = hs // 3, hs % 3
    _, first = np.unique(f, return_index=True)  # one split per face per pass
    f, k = f[first], k[first]
    a, b, c = Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3], Fa[f, k]
    m = xy.shape[0] + np.arange(f.size)
    xy = np.vstack([xy, 0.5 * (xy[a] + xy[b])])
    keep = np.ones(Fa.shape[0], dtype=bool)
    keep[f] = False
    Fa = np.vstack([Fa[keep], np.stack([a, m, c], 1), np.stack([m, b, c], 1)])
    src = np.concatenate([src[keep], src[f], src[f]])
    return xy, Fa, src


def false_edge_junctions(xy, fe) -> list:
    """Chains of false edges (connected on screen) as junctions."""
    E = fe.E
    if E.shape[0] == 0:
        return []
    n = xy.shape[0]
    A = sp.coo_matrix((np.ones(E.shape[0]), (E[:, 0], E[:, 1])), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    comp = lab[E[:, 0]]
    out = []
    for c in np.unique(comp).tolist():  # one per junction, few
        s = comp == c
        mid = 0.5 * (xy[E[s, 0]] + xy[E[s, 1]])
        out.append(
            Junction(
                "false edge", mid.mean(axis=0), float(np.median(np.abs(fe.gap[s]))), int(s.sum())
            )
        )
    return out


def cut_and_glue(Fa, glue):
    """Mescher faces: corners united across glued half-edge pairs (connected components).

    Returns
    -------
    Fm : (#F, 3) int64
        Faces over the mescher's vertices.
    corner_vertex : (3 #F,) int64
        Planar (screen) vertex of each corner, to take the mescher vertices' positions from.
    """
    nf = Fa.shape[0]
    h1, h2, ok = glue.h1, glue.h2, glue.glued
    g1, g2 = h1[ok], h2[ok]
    f1, k1, f2, k2 = g1 // 3, g1 % 3, g2 // 3, g2 % 3
    # half-edge k of face f runs corner k+1 -> k+2; its partner runs the other way
    c1p, c1q = 3 * f1 + (k1 + 1) % 3, 3 * f1 + (k1 + 2) % 3
    c2q, c2p = 3 * f2 + (k2 + 1) % 3, 3 * f2 + (k2 + 2) % 3
    rows = np.concatenate([c1p, c1q])
    cols = np.concatenate([c2p, c2q])
    n = 3 * nf
    A = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    _, Fm = np.unique(lab, return_inverse=True)
    return Fm.reshape(-1, 3).astype(np.int64), Fa.reshape(-1)


def he_depth(Z, h):
    """(k, 2) depths of the tail and head of half-edges ``h`` (= 3 f + k)."""
    f, k = h // 3, h % 3
    return np.stack([Z[f, (k + 1) % 3], Z[f, (k + 2) % 3]], axis=1)


def depths_have_period(F: np.ndarray, Z: np.ndarray, tol: float) -> bool:
    """Do the per-face corner depths ``Z`` fail to integrate on the glued surface ``F``?

    Edge values ``zeta`` (the faces' depth differences, averaged per edge) are integrable iff
    ``zeta = d01 z`` for some ``z``: the least-squares residual (``scipy.sparse.linalg.lsqr``)
    exceeds ``tol`` somewhere exactly when a loop gains depth (a period spreads over its edges).
    """
    from scipy.sparse.linalg import lsqr

    n = int(F.max()) + 1
    a = F.reshape(-1)
    b = F[:, [1, 2, 0]].reshape(-1)
    dz = (Z[:, [1, 2, 0]] - Z).reshape(-1)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    uk, inv = np.unique(key, return_inverse=True)
    sgn = np.where(a < b, 1.0, -1.0)
    zeta = np.bincount(inv, weights=sgn * dz) / np.bincount(inv)
    lo, hi = uk // n, uk % n
    m = uk.size
    D = sp.csr_matrix(
        (np.r_[-np.ones(m), np.ones(m)], (np.r_[np.arange(m), np.arange(m)], np.r_[lo, hi])),
        shape=(m, n),
    )
    z = lsqr(D, zeta, atol=1e-14, btol=1e-14, iter_lim=10 * n)[0]
    return bool(np.abs(D @ z - zeta).max(initial=0.0) > tol)


# ------------------------------------------------------------------------------ hidden steps
#: Screen width of the riser band of a hidden step, relative to the model's size: a sliver
#: (seen edge-on by a person) well above the tolerance, so it stays a face of its own.
STEP_BAND = 1e-3


def hidden_step_edges(xy, Fa, src, pl, C, F, N, front, glue: Glue, tol: float):
    """Far half-edges (``3 f + k``) of the cuts that are steps with a hidden riser, and the
    near side's source face of each.

    A tread's front edge lies over a lower tread of the same orientation: the cut's two sides
    have parallel source planes (the gap is the same along the edge), the nearer side lies on
    an edge of its model face whose other face looks away (the riser, hidden behind the edge)
    and that riser reaches down to the farther tread's plane (a step, not a slab floating over
    a floor).  One far half-edge per far face.
    """
    cut = np.flatnonzero(~glue.glued)
    if cut.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    h1, h2 = glue.h1[cut], glue.h2[cut]
    Z = plane_depth_of(xy, Fa, pl, src)
    d = he_depth(Z, h2)[:, ::-1] - he_depth(Z, h1)  # side 2 minus side 1 at tail and head
    far1 = d.sum(axis=1) > 0
    hn, hf = np.where(far1, h2, h1), np.where(far1, h1, h2)
    sn, sf = src[hn // 3], src[hf // 3]
    n = N / np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)
    ok = (np.abs(d[:, 0] - d[:, 1]) <= tol) & (np.abs(d).min(axis=1) > tol)
    ok &= np.linalg.norm(n[sn] - n[sf], axis=1) <= 1e-6
    kn = hn % 3
    E = np.stack([Fa[hn // 3, (kn + 1) % 3], Fa[hn // 3, (kn + 2) % 3]], axis=1)
    k = edge_on_source(xy, E, sn, C, F, tol)
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0])
    riser = np.where(k >= 0, TT[sn, np.maximum(k, 0)], -1)
    ok &= (riser >= 0) & ~front[np.maximum(riser, 0)]
    P = C[F[np.maximum(riser, 0)]]  # (m, 3, 3) the riser's corners, camera frame
    below = P[..., 2] - plane_depth(P[..., :2], pl[sf][:, None, :])
    ok &= below.min(axis=1) <= tol  # the riser reaches the far tread's plane
    ok &= _meets_riser(C, F, N, TT, sf, np.maximum(riser, 0), tol)
    hf, sn = hf[ok], sn[ok]
    _, first = np.unique(hf // 3, return_index=True)
    return hf[first], sn[first]


def _meets_riser(C, F, N, TT, sf, riser, tol) -> np.ndarray:
    """(m,) does the far tread (model face ``sf`` or a coplanar neighbour) have an edge in the
    plane of ``riser``: the lower tread ends at the riser, as a step's does (a bar seen over
    another bar does not)."""
    n = N / np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)
    cand = np.concatenate([sf[:, None], TT[sf]], axis=1)  # (m, 4): the face and its neighbours
    valid = cand >= 0
    cand = np.maximum(cand, 0)
    P = C[F[cand]]  # (m, 4, 3, 3)
    # a neighbour counts when it lies in the far face's plane
    off = np.einsum("mfvk,mk->mfv", P - C[F[sf, 0]][:, None, None, :], n[sf])
    valid &= np.abs(off).max(axis=2) <= tol
    dist = np.abs(np.einsum("mfvk,mk->mfv", P - C[F[riser, 0]][:, None, None, :], n[riser]))
    on = dist <= tol
    edge_in = (on & on[:, :, [1, 2, 0]]).any(axis=2)
    return (edge_in & valid).any(axis=1)


def plane_depth_of(xy, Fa, pl, src) -> np.ndarray:
    """(#F, 3) corner depths of the screen faces from their source faces' planes."""
    return plane_depth(xy[Fa], pl[src][:, None, :])


def add_step_bands(xy, Fa, src, pl, C, F, N, front, ftol, hf, near, width: float, tol: float):
    """Carve a riser band along each hidden step's far half-edge ``hf``: the far face
    ``(c, p, q)`` becomes the band ``p, q, q', p'`` (``p' = p + t (c - p)``, screen width
    ``width``) and the rest ``(p', q', c)``; the band runs from the near tread's (source face
    ``near``) depth at
    ``p, q`` to the far tread's at ``p', q'`` (a riser a person sees edge-on).  The band's two
    triangles become model faces of their own (appended to ``C``, ``F``, ``N``, ``front``,
    ``pl``, ``ftol``), so the gluing finds them continuous with both treads.  Neighbours whose
    edges now pass through ``p'`` or ``q'`` are split.

    Returns the extended ``(xy, Fa, src, pl, C, F, N, front, ftol)``, or None when no face is
    wide enough for a band.
    """
    f, k = hf // 3, hf % 3
    c, p, q = Fa[f, k], Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]
    pq = xy[q] - xy[p]
    L = np.linalg.norm(pq, axis=1)
    cp = xy[c] - xy[p]
    h = np.abs(pq[:, 0] * cp[:, 1] - pq[:, 1] * cp[:, 0]) / np.maximum(L, 1e-300)
    t = np.minimum(width / np.maximum(h, 1e-300), 0.25)
    keep = t * np.minimum(L, h) > 5.0 * tol
    if not keep.any():
        return None
    f, c, p, q, t, near = f[keep], c[keep], p[keep], q[keep], t[keep], near[keep]
    m = f.size
    n0 = xy.shape[0]
    xy = np.vstack([xy, xy[p] + t[:, None] * (xy[c] - xy[p]), xy[q] + t[:, None] * (xy[c] - xy[q])])
    p2, q2 = n0 + np.arange(m), n0 + m + np.arange(m)
    # the band in 3D: near tread at p, q; far tread at p', q'
    zn = plane_depth(xy[np.stack([p, q], 1)], pl[near][:, None, :])
    zf = plane_depth(xy[np.stack([p2, q2], 1)], pl[src[f]][:, None, :])
    c0 = C.shape[0]
    P3 = np.concatenate(
        [
            np.c_[xy[p], zn[:, 0]],
            np.c_[xy[q], zn[:, 1]],
            np.c_[xy[q2], zf[:, 1]],
            np.c_[xy[p2], zf[:, 0]],
        ]
    )
    i = c0 + np.arange(m)
    Fnew = np.concatenate(
        [np.stack([i, i + m, i + 2 * m], 1), np.stack([i, i + 2 * m, i + 3 * m], 1)]
    )
    C = np.vstack([C, P3])
    f0 = F.shape[0]
    F = np.vstack([F, Fnew])
    N = np.vstack([N, np.cross(C[Fnew[:, 1]] - C[Fnew[:, 0]], C[Fnew[:, 2]] - C[Fnew[:, 0]])])
    front = np.concatenate([front, np.ones(2 * m, dtype=bool)])
    pl = np.vstack([pl, face_planes(C, Fnew)])
    ftol = np.concatenate([ftol, np.full(2 * m, tol)])
    out = np.ones(Fa.shape[0], dtype=bool)
    out[f] = False
    Fa = np.vstack(
        [Fa[out], np.stack([p, q, q2], 1), np.stack([p, q2, p2], 1), np.stack([p2, q2, c], 1)]
    )
    src = np.concatenate([src[out], f0 + np.arange(m), f0 + m + np.arange(m), src[f]])
    # bands of faces sharing an edge may put their points on it at one place: one vertex there
    lab = merge_points(xy, tol)
    rep = np.full(int(lab.max()) + 1, xy.shape[0])
    np.minimum.at(rep, lab, np.arange(xy.shape[0]))
    Fa = rep[lab[Fa]]
    good = (Fa[:, 0] != Fa[:, 1]) & (Fa[:, 1] != Fa[:, 2]) & (Fa[:, 2] != Fa[:, 0])
    used, Fa = np.unique(Fa[good], return_inverse=True)
    xy, Fa, src = xy[used], Fa.reshape(-1, 3), src[good]
    Fa, src = split_t_junctions(xy, Fa, src, tol)
    return xy, Fa, src, pl, C, F, N, front, ftol


#: The riser bands are drawn this fraction of :data:`STEP_BAND` wide in the finished map
#: (:func:`narrow_step_bands`): 1e-4 of the size, a twentieth of a pixel at 500 pixels.
#: Narrower bands are steeper than the depth-order check's extrapolation tolerates (at 1e-5 of
#: the size a stepped grid seen from (1, 1, 1) reads as an unrealisable order).
BAND_DRAWN = 1e-1


def _far_corners(xy, Fb, sb, C, F, band, n_model):
    """(#band, 3) bool: the band faces' corners on the lower tread's side.

    :func:`add_step_bands` appends its model faces as one block, ``(p, q, q2)`` then
    ``(p, q2, p2)`` over the 3D corners ``p, q`` (near) then ``q2, p2`` (far), ``m`` of each; a
    screen corner is far when it lies nearer the line ``q2 p2`` than the line ``p q``."""
    c0, m = int(F[n_model:].min()), (F.shape[0] - n_model) // 2
    k = F[sb[band], 0] - c0
    P = C[c0 + np.arange(4 * m), :2].reshape(4, m, 2)
    X = xy[Fb[band]]

    def dist(a, b):
        d = b - a
        w = X - a[:, None]
        cr = np.abs(w[..., 0] * d[:, None, 1] - w[..., 1] * d[:, None, 0])
        return cr / np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]

    return dist(P[3, k], P[2, k]) < dist(P[0, k], P[1, k])


def narrow_step_bands(xy, Fb, sb, Zb, pl, C, F, n_model: int, tol: float, shrink=BAND_DRAWN):
    """Narrow every riser band of the finished map toward the upper tread's edge.

    The band (model faces from ``n_model`` on, :func:`add_step_bands`) is a riser seen
    edge-on: in the picture the lower tread meets the upper tread's edge, as the z-buffer shows
    it.  Gluing needs it wide enough to tell from its edge (:data:`STEP_BAND`); once glued, each
    far corner ``v`` moves toward its nearest near corner ``u`` of the band,
    ``u + shrink (v - u)``, staying on the far face's edge (no face turns over).  The topology
    is unchanged; each corner at a moved vertex takes its face's plane there, a band's corner
    the plane of the tread face continuous with it, so the depths stay continuous.

    Returns the new ``(xy, Zb)``.
    """
    band = np.flatnonzero(sb >= n_model)
    if band.size == 0:
        return xy, Zb
    far = _far_corners(xy, Fb, sb, C, F, band, n_model)
    Vb = Fb[band]
    fi = np.repeat(np.arange(band.size), 3).reshape(-1, 3)[far]
    v = Vb[far]
    cand = np.where(far[fi], -1, Vb[fi])  # near corners of the same band face
    d = np.linalg.norm(xy[np.maximum(cand, 0)] - xy[v][:, None], axis=2)
    d = np.where(cand >= 0, d, np.inf)
    ok = np.isfinite(d.min(axis=1))
    u = cand[np.arange(v.size), np.argmin(d, axis=1)][ok]
    v, dmin = v[ok], d.min(axis=1)[ok]
    order = np.argsort(dmin, kind="stable")
    vs, first = np.unique(v[order], return_index=True)
    if vs.size == 0:
        return xy, Zb
    us = u[order][first]
    moved = np.zeros(xy.shape[0], dtype=bool)
    moved[vs] = True
    f, c = np.nonzero(moved[Fb])
    z_old, at_v = Zb[f, c], Fb[f, c]
    is_band = sb[f] >= n_model
    own = np.where(is_band, -1, sb[f])
    tf, tv, tz = f[~is_band], at_v[~is_band], z_old[~is_band]
    for i in np.flatnonzero(is_band).tolist():  # a few corners per band
        hit = (tv == at_v[i]) & (np.abs(tz - z_old[i]) <= tol)
        if hit.any():
            own[i] = sb[tf[np.argmax(hit)]]
    # a vertex where some band corner continues no tread stays where it is
    stay = np.zeros(xy.shape[0], dtype=bool)
    stay[at_v[own < 0]] = True
    go = ~stay[vs]
    vs, us = vs[go], us[go]
    keep = ~stay[at_v]
    f, c, own = f[keep], c[keep], own[keep]
    xy = xy.copy()
    xy[vs] = xy[us] + shrink * (xy[vs] - xy[us])
    Zb = Zb.copy()
    Zb[f, c] = plane_depth(xy[Fb[f, c]], pl[own])
    return xy, Zb
