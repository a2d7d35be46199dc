"""Accidental alignments: false edges that are a near object lying in front of a far edge.

Seen along a view with zero or equal components, an ordinary scene lines up edges at
different depths on screen (a box's top edge on the foot of the wall behind it, a table's
front edge on the far edge of the floor under it).  The general false-edge rule
(:func:`.glue.classify`) would glue them as junctions and the scene would come out impossible.
:func:`accidental_alignments` tells those from the junctions of impossible figures, whose
model edges pair up corner to corner on screen (a tribar's junction) or whose surfaces are
joined in 3D by a face seen edge-on.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .caps import planar_patches, unit_normals
from .records import EdgeSides

#: Screen offset (in tolerances) of the probes on either side of a far edge
#: (:func:`outline_seen`): beyond the merging tolerance of the visible map, so each probe lies
#: in the face beside the edge.
PROBE_OFFSET = 4.0


def joined_edge_on(C, F, TT, nbn, nbf, false_edge, front, tol) -> np.ndarray:
    """(k,) bool: false edges whose near and far model edges both bound one planar patch
    turned away from the viewer (``nbn``, ``nbf``: the near and far faces' other faces across
    their edges): that patch, seen edge-on, joins the two surfaces in 3D (a step's riser, a
    block's side seen along itself); its two edges meet on screen because it projects to a
    line, not by an alignment of separate surfaces."""
    rows = false_edge & (nbn >= 0) & (nbf >= 0)
    rows &= ~front[np.maximum(nbn, 0)] & ~front[np.maximum(nbf, 0)]
    if not rows.any():
        return rows
    patch = planar_patches(C, F, TT, tol)
    return rows & (patch[np.maximum(nbn, 0)] == patch[np.maximum(nbf, 0)])


def far_edge_kinds(C, F, sn, sf, nbf, turned, tol):
    """What the far model edge (of face ``sf``, its other face ``nbf``, -1: none) is to the
    near face ``sn`` of a false edge.

    Two unit normals count as one direction when they differ by at most ``tol / L`` (``L``
    the far edge's length): tilted by that much, a face moves by no more than the tolerance
    along the edge.

    Returns
    -------
    outline : (k,) bool
        An outline of the far object (its other face turned away or missing: ``turned``) or
        no edge at all (its other face in its plane: the far surface goes on).
    crease_hidden : (k,) bool
        A crease of the far object whose other face (toward the viewer) is not parallel to
        the near face: the near face cannot take that face's place, which goes on behind it.
    """
    ok = nbf >= 0
    nb = np.maximum(nbf, 0)
    ns, nf, nn = unit_normals(C, F[sf]), unit_normals(C, F[nb]), unit_normals(C, F[sn])
    off = np.einsum("kij,kj->ki", C[F[nb]] - C[F[sf, 0]][:, None], ns)
    E = C[F[sf]]
    L = np.linalg.norm(E - E[:, [1, 2, 0]], axis=2).max(axis=1)
    ntol = tol / np.maximum(L, 1e-300)
    flat = ok & (np.linalg.norm(ns - nf, axis=1) <= ntol) & np.all(np.abs(off) <= tol, axis=1)
    outline = turned | ~ok | flat
    return outline, ~outline & (np.linalg.norm(nn - nf, axis=1) > ntol)


def on_line(A: np.ndarray, B: np.ndarray, P: np.ndarray, Q: np.ndarray):
    """(k, 2) sorted parameters of the screen points ``P``, ``Q`` along the screen segment
    ``A B`` (0 at ``A``, ``|B - A|`` at ``B``), and ``|B - A|`` (k,)."""
    u = B[:, :2] - A[:, :2]
    L = np.linalg.norm(u, axis=1)
    u = u / np.maximum(L, 1e-300)[:, None]
    t = np.stack([((P[:, :2] - A[:, :2]) * u).sum(1), ((Q[:, :2] - A[:, :2]) * u).sum(1)], 1)
    return np.sort(t, axis=1), L


def _depth_at(xy, Fa, Z, X, at, tol):
    """The nearest visible depth at each screen point ``X``, the face giving it taken on to
    the point ``at`` (its plane there); -inf where no face covers ``X``."""
    from ..geometry2d import barycentric

    T = xy[Fa]
    lo, hi = T.min(axis=1), T.max(axis=1)
    box = np.all((lo <= X.max(axis=0) + tol) & (hi >= X.min(axis=0) - tol), axis=1)
    near = np.flatnonzero(box)
    k, f = np.nonzero(np.all((lo[near] <= X[:, None] + tol) & (hi[near] >= X[:, None] - tol), 2))
    f = near[f]
    b = barycentric(X[k], T[f])
    inside = np.all(b >= -1e-9, axis=1)
    k, f = k[inside], f[inside]
    z = (b[inside] * Z[f]).sum(axis=1)
    best = np.full(X.shape[0], -np.inf)
    np.maximum.at(best, k, z)
    top = z >= best[k]  # the nearest face at each point
    k, f = k[top], f[top]
    out = np.full(X.shape[0], -np.inf)
    out[k] = (barycentric(at[k], T[f]) * Z[f]).sum(axis=1)
    return out


def _line_stops(xy, Fa, a, u, n, L, tol) -> np.ndarray:
    """Sorted parameters in ``[0, L]`` along ``a + t u`` where the line meets the visible
    map's edges or passes its vertices (``n``: the line's unit normal)."""
    E = np.stack([Fa[:, [0, 1]], Fa[:, [1, 2]], Fa[:, [2, 0]]], axis=1).reshape(-1, 2)
    p, q = xy[E[:, 0]] - a, xy[E[:, 1]] - a
    dp, dq = p @ n, q @ n
    t = [(p @ u)[np.abs(dp) <= tol], (q @ u)[np.abs(dq) <= tol]]
    x = dp * dq < 0  # the edge crosses the line
    w = dp[x] / (dp[x] - dq[x])
    t.append((p[x] + w[:, None] * (q[x] - p[x])) @ u)
    return np.unique(np.clip(np.concatenate([[0.0, L], *t]), 0.0, L))


def outline_seen(xy, Fa, Z, A, B, side, tol) -> bool:
    """Is the far model edge ``A B`` (camera frame) seen somewhere as an outline against its
    backdrop: its own surface beside it on screen, on ``side`` (the sign of ``cross(b - a,
    x - a)`` on screen), at the edge's own depth, and across the edge nothing nearer (the
    background, or a surface at or behind the edge's depth: what lies behind or under it)?

    The edge is probed at the middle of each stretch between the points where it crosses
    the visible map's edges or passes its vertices, :data:`PROBE_OFFSET` tolerances to
    either side; each probe's face is taken on to the edge (its plane there)."""
    a, b = A[:2], B[:2]
    L = float(np.linalg.norm(b - a))
    if L <= 2 * tol:
        return False
    u = (b - a) / L
    n = side * np.array([-u[1], u[0]])  # toward the far surface
    t = _line_stops(xy, Fa, a, u, n, L, tol)
    keep = np.diff(t) > 2 * tol
    mid = (0.5 * (t[1:] + t[:-1]))[keep]
    if mid.size == 0:
        return False
    X = a + mid[:, None] * u
    z_edge = A[2] + (mid / L) * (B[2] - A[2])
    d = PROBE_OFFSET * tol
    z_far = _depth_at(xy, Fa, Z, X + d * n, X, tol)
    z_across = _depth_at(xy, Fa, Z, X - d * n, X, tol)
    own = np.abs(z_far - z_edge) <= d
    backdrop = z_across <= z_edge + d
    return bool(np.any(own & backdrop))


def accidental_alignments(
    xy, Fa, Z, C, F, TT, front, src, sides: EdgeSides, false_edge, tol
) -> np.ndarray:
    """(k,) bool: the false edges that are accidental alignments, not junctions.

    A false edge says the near surface is attached to the far model edge along it.  It is an
    alignment, a near object merely lying in front of that edge, when

    * the far edge is the far object's *outline* (its other face turned away, or no edge at
      all: its surface goes on in its plane) and either the two model edges do not pair up
      corner to corner on screen, or it is seen elsewhere along its length as an outline
      against its backdrop (:func:`outline_seen`: background, or a surface at or behind it
      -- the floor a wall stands on); or
    * the far edge is a crease of its object whose hidden face the near face cannot continue
      (:func:`far_edge_kinds`), and the two model edges do not pair up corner to corner on
      screen.  Where both ends of the near edge fall on both ends of the far edge, two
      vertex pairs coincide: the picture shows one edge with matching corners, as at a
      tribar's junction, and it stays glued.

    Each connected chain of false edges (one junction) with such an edge is an alignment,
    unless the chain holds a crease whose corners pair up with the near edge's: that chain is
    a junction (the Penrose columns' top tread on the first tread, its side running on along
    a silhouette).
    So is a false edge whose two sides are joined by a planar patch seen edge-on
    (:func:`joined_edge_on`): they meet on screen because that patch projects to a line.

    Parameters
    ----------
    xy : (#P, 2), Fa : (#T, 3), Z : (#T, 3)
        The visible map and its corner depths.
    C, F, TT, front : model (camera frame), its triangle adjacency and front faces.
    src : (#T,) int
        Source model face of each screen face.
    sides : EdgeSides
        The two sides of each shared screen edge on their model edges.
    false_edge : (k,) bool
    tol : float
        Absolute tolerance.
    """
    out = np.zeros(sides.h1.size, dtype=bool)
    fe = np.flatnonzero(false_edge)
    if fe.size == 0:
        return out
    hf, hn = sides.far_near("h", fe)
    sf, sn = src[hf // 3], src[hn // 3]
    mf, mn = sides.far_near("edge", fe)
    nbf, nbn = sides.far_near("across", fe)
    outline, crease = far_edge_kinds(C, F, sn, sf, nbf, sides.far_near("ends", fe)[0], tol)
    A, B = C[F[sf, mf]], C[F[sf, (mf + 1) % 3]]
    t, L = on_line(A, B, C[F[sn, mn]], C[F[sn, (mn + 1) % 3]])
    corners = (np.abs(t[:, 0]) <= tol) & (np.abs(t[:, 1] - L) <= tol)
    bad = crease & ~corners
    # an outline whose corners do not pair with the near edge's: the two edges merely overlap
    # on screen (an arch's post's side behind the other post's, a short box's side along a
    # tall box's); a junction's edges meet end to end, as a tribar's bar end on the column
    bad |= outline & ~corners
    cand = outline
    far_mid = xy[Fa[hf // 3]].mean(axis=1)
    # each probe of a far edge looks only at the faces near it (boxes within the probes'
    # reach): the same stops and depths, without passes over the whole map per edge
    T = xy[Fa]
    flo = np.minimum(np.minimum(T[:, 0], T[:, 1]), T[:, 2])
    fhi = np.maximum(np.maximum(T[:, 0], T[:, 1]), T[:, 2])
    reach = (PROBE_OFFSET + 2.0) * tol
    key = np.round(np.c_[A, B] / max(tol, 1e-300)).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inv = inv.reshape(-1)
    for j, i in enumerate(first.tolist()):  # each far model edge once (a few per junction)
        if not cand[i] or bad[i]:
            continue
        w = B[i, :2] - A[i, :2]
        c = far_mid[i] - A[i, :2]
        side = np.sign(w[0] * c[1] - w[1] * c[0])
        slo = np.minimum(A[i, :2], B[i, :2]) - reach
        shi = np.maximum(A[i, :2], B[i, :2]) + reach
        near = np.flatnonzero(np.all((flo <= shi) & (fhi >= slo), axis=1))
        if outline_seen(xy, Fa[near], Z[near], A[i], B[i], side, tol):
            bad[(inv == j) & cand] = True
    if bad.any():
        f, k = sides.h1[fe] // 3, sides.h1[fe] % 3
        p, q = Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]
        M = sp.coo_matrix((np.ones(fe.size), (p, q)), shape=(xy.shape[0],) * 2)
        _, lab = csgraph.connected_components(M, directed=False)
        out[fe] = np.isin(lab[p], lab[p[bad]]) & ~np.isin(lab[p], lab[p[crease & corners]])
    out[fe] |= joined_edge_on(C, F, TT, nbn, nbf, np.ones(fe.size, bool), front, tol)
    return out
