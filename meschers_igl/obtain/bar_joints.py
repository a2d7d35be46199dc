"""Joints of bar ends hidden exactly behind other bar ends (the three-box Penrose triangle).

A bar whose end lies exactly behind another bar's end -- the hidden end's corners coincide on
screen with the near end's corners, ``t`` apart in depth -- is read as joined to it there: an
L-joint whose corner block is the near bar's end.  Moved toward the viewer by ``t`` (along the
view, which changes nothing on screen), the far bar's faces continue the near end's faces in
their planes; the loop of bars then fails to close by ``t``: the period.

On the visible map this is built as follows (:func:`prepare_joints`, then :func:`join_ends`):

* the **joint planes**: a near model plane (through a near corner) and a far one (through a far
  corner) with the same normal, the near one ``t`` in front of the far one;
* the **joint lines**: visible edges where a near plane's face ends (a crease or an outline of
  the near bar) while, across the edge, the far plane's face runs on hidden behind a nearer
  face -- the far bar leaves the corner block there;
* the **hidden strips**: the far plane's hidden part across each joint line (up to where the
  far bar comes out from behind the near bar), added behind the faces covering them,
  continuous with the far bar's visible faces, and glued across the joint line to the near
  plane's face (a false edge whose depth gap is ``t``); the near bar's face beyond the line
  (the block's face the far bar enters through) is cut from it there.

**Crease joints** (:func:`corner_gaps`): two mitred bar ends whose tips meet at one point on
screen -- a cube frame with its corner cut away, each bar pulled back along itself -- share
one pair of corners, ``t`` apart.  There the far bar's face through its corner is not in a
near plane: its edge runs exactly behind a near crease from the shared corner (same 3D
direction, so ``t`` behind all along), and the face bends away behind the near bar, oblique to
the near face (a mitre; a square end is a block's side, read by the other rules).  Its
hidden part across that crease is the strip, glued to the near face on the crease's other
side: a false edge that is a crease once glued.  From the model alone (``view="auto"``),
:func:`crease_pairs` lists the pairs of corners that form one seen along the direction joining
them.

The rule only reads joints where the visible map glues no other junction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..geometry2d import barycentric, overlapping_pairs, polygon_triangles
from .caps import unit_normals
from .clip import plane_depth
from .directions import unique_rows
from .glue import cut_and_glue, edge_on_source, interior_edges
from .records import Glue, Junction

#: Most model vertices compared for coincident pairs (a dense mesh has no bar ends to join).
MAX_VERTICES = 200_000
#: Smallest eigenvalue of ``sum n n^T`` over a vertex's faces (unit normals ``n``) for a corner
#: (:func:`corner_vertices`): 0 for normals in one plane (a flat face, a straight crease); a box
#: corner with one triangle per face gives 1.
CORNER_EIG = 1e-6
#: Most coincident pairs a gap may have to be a joint of bar ends (a cross-section's corners).
MAX_PAIRS = 64
#: Most gaps examined (those with the most pairs first): a scene lining up many vertex pairs
#: along the view is no tribar.
MAX_GAPS = 8
#: A hidden strip's corner within this many tolerances of a map vertex is that vertex (the
#: strip is eroded and dilated by the tolerance with mitred joins, which bevel a sharp corner
#: and move it by several tolerances).
SNAP_CORNER = 20.0
#: A crease joint's far face is a mitre: the cosine between its normal and the near face's
#: is above this (about 3 degrees off square, beyond what jitter of 1e-3 of a bar's size tilts a
#: face; mitres are cut at tens of degrees).
MITRE_COS = 0.05


@dataclass(frozen=True)
class HiddenStrip:
    """A far plane's hidden part across a joint line.

    Attributes
    ----------
    ring : (n, 2) float64
        The strip's outline on screen (counter-clockwise, not closed).
    faces : (k,) int64
        The far plane's front model faces (their screen triangles assign each strip triangle
        its source face).
    gap : float
        Depth gap ``t`` of the joint.
    """

    ring: np.ndarray
    faces: np.ndarray
    gap: float


def _one_end(P: np.ndarray, tol: float) -> bool:
    """Do the points ``P`` (k, 3) lie in one plane (to ``tol``), as the corners of one bar's end
    do?  Pairs lined up by accident along the view (a lattice of blocks seen along one of its
    vectors) are spread through the model instead."""
    if P.shape[0] < 4:
        return True
    Q = P - P.mean(axis=0)
    return bool(np.abs(Q @ np.linalg.svd(Q)[2][2]).max() <= tol)


def _lattice(gaps: np.ndarray, tol: float) -> bool:
    """Are the depth gaps shared by two or more vertex pairs (sorted) three or more integer
    multiples of one step (their smallest difference)?  Then blocks repeat along the view (a
    staircase seen along the vector from one step to the next): each repetition lines up pairs
    at a multiple of the step, and no gap is one bar end hidden behind another."""
    if gaps.size < 3:
        return False
    step = float(np.diff(gaps).min())
    if step <= 10.0 * tol:
        return False
    k = gaps / step
    return bool(np.all(np.abs(k - np.rint(k)) * step <= 2.0 * tol))


def corner_vertices(C: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(#V,) bool: the vertices a person sees as corners: where faces of three or more planes
    meet (the unit normals of the faces around it span space: :data:`CORNER_EIG`), or on the
    model's boundary.

    A vertex inside a flat face or partway along a straight crease (normals of one or two
    planes) is the triangulation's (a quad grid's subdivision): the same shape meshed
    otherwise has none there, so such vertices that coincide on screen say nothing about the
    figure (a bar's grid vertices line up along its diagonal like a lattice of blocks).
    """
    n = unit_normals(C, F)
    nv, at = C.shape[0], F.reshape(-1)
    nn = np.repeat(n, 3, axis=0)
    M = np.zeros((nv, 3, 3))
    for a in range(3):  # sum n n^T over each vertex's faces (the lower triangle, symmetric)
        for b in range(a + 1):
            M[:, a, b] = np.bincount(at, weights=nn[:, a] * nn[:, b], minlength=nv)
    corner = np.linalg.eigvalsh(M, UPLO="L")[:, 0] > CORNER_EIG
    he = np.sort(F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    key, cnt = np.unique(he[:, 0] * nv + he[:, 1], return_counts=True)
    open_edge = key[cnt == 1]
    corner[open_edge // nv] = corner[open_edge % nv] = True
    return corner


def _gap_groups(C: np.ndarray, F: np.ndarray, tol: float):
    """Pairs of corner vertices (:func:`corner_vertices`) that coincide on screen more than
    10 ``tol`` apart in depth, grouped by equal gaps (to ``tol``).

    Returns ``(t, near, far, starts, ends, vs, P)`` -- gaps, near and far ends (indices into
    ``vs``), each group ``starts[k]:ends[k]``, the corner vertices ``vs`` and their points
    ``P`` -- or None when there are none, or when the gaps shared by two or more pairs are
    three or more multiples of one step (:func:`_lattice`: repeated blocks seen along their
    repeat)."""
    vs = np.unique(F)
    if vs.size < 2 or vs.size > MAX_VERTICES:
        return None
    vs = vs[corner_vertices(C, F)[vs]]
    if vs.size < 2:
        return None
    P = C[vs]
    pr = cKDTree(P[:, :2]).query_pairs(tol, output_type="ndarray")
    if pr.size == 0:
        return None
    dz = P[pr[:, 1], 2] - P[pr[:, 0], 2]
    near = np.where(dz > 0, pr[:, 1], pr[:, 0])
    far = np.where(dz > 0, pr[:, 0], pr[:, 1])
    t = np.abs(dz)
    keep = t > 10.0 * tol
    near, far, t = near[keep], far[keep], t[keep]
    order = np.argsort(t, kind="stable")
    near, far, t = near[order], far[order], t[order]
    cut = np.flatnonzero(np.diff(t) > tol) + 1
    starts, ends = np.r_[0, cut], np.r_[cut, t.size]
    if t.size == 0 or _lattice(t[starts[ends - starts >= 2]], tol):
        return None
    return t, near, far, starts, ends, vs, P


def coincident_gaps(C: np.ndarray, F: np.ndarray, tol: float) -> list:
    """Depth gaps shared by two or more pairs of model vertices that coincide on screen.

    Parameters
    ----------
    C : (#V, 3) float64
        Camera-frame vertices.
    F : (#F, 3) int64
    tol : float
        Absolute tolerance (screen and depth).

    Returns
    -------
    list of (gap, near, far)
        ``gap`` > 10 ``tol``; ``near``, ``far`` (k,) int64 the vertices of its pairs, the near
        one ``gap`` in front of the far one, the far ones in one plane (one bar's end).  At
        most :data:`MAX_GAPS`, the most pairs first; none when the gaps are three or more
        multiples of one step (:func:`_lattice`: repeated blocks seen along their repeat).
    """
    g = _gap_groups(C, F, tol)
    if g is None:
        return []
    t, near, far, starts, ends, vs, P = g
    out = []
    for s, e in zip(starts.tolist(), ends.tolist()):  # a few gaps
        if 2 <= e - s <= MAX_PAIRS and _one_end(P[far[s:e]], tol):
            out.append((float(t[s:e].mean()), vs[near[s:e]], vs[far[s:e]]))
    out.sort(key=lambda g: -g[1].size)  # stable: equal counts keep the smaller gap first
    return out[:MAX_GAPS]


def corner_gaps(C: np.ndarray, F: np.ndarray, tol: float) -> list:
    """Single pairs of corners that coincide on screen (the tips of two mitred bar ends meeting
    at a point: the impossible cube with its corner cut away), each as :func:`coincident_gaps`
    lists a gap (``near``, ``far`` of size 1): the pairs of the gaps with the fewest pairs
    first (a gap may be shared by a pair elsewhere that lines up by accident), at most
    :data:`MAX_GAPS`.  They are read as *crease joints* only (:func:`joint_lines` with
    ``crease``)."""
    g = _gap_groups(C, F, tol)
    if g is None:
        return []
    t, near, far, starts, ends, vs, P = g
    size = ends - starts
    rows = [
        r
        for k in np.argsort(size, kind="stable").tolist()
        if size[k] <= MAX_PAIRS
        for r in range(int(starts[k]), int(ends[k]))
    ][:MAX_GAPS]
    return [(float(t[r]), vs[near[r : r + 1]], vs[far[r : r + 1]]) for r in rows]


#: Most corners :func:`crease_pairs` compares (a fine mesh, every vertex a corner, has no bar
#: tips; its parallel edges would pair up by the million).
MAX_CREASE_CORNERS = 2000
#: Most (near crease, far edge) candidates :func:`crease_pairs` forms before the exact tests;
#: beyond, a model of many parallel mitred edges is no single joint of two tips: none.
MAX_CREASE_CANDIDATES = 100_000
#: Edges at two corners are compared when their unit directions differ by at most this chord
#: (a first cut; the exact test is that the shorter edge's far end is within 4 ``tol`` of
#: the other edge's line).
CREASE_DIR = 1e-4
#: Faces meeting at an edge at a smaller angle than this (radians) make no crease.
CREASE_ANGLE = 1e-4
#: A mitre is as far from parallel to the near face as from square to it: ``|n_f . n_g|``
#: below this (about 3 degrees; a file's round-off tilts faces of one plane by far less).
OBLIQUE_MAX = float(np.sqrt(1.0 - MITRE_COS**2))


def _edge_records(V: np.ndarray, F: np.ndarray, corner: np.ndarray, tol: float):
    """The creases at the corners (``corner``, (#V,) bool): each manifold edge whose two faces
    meet at an angle over :data:`CREASE_ANGLE`, once from each end that is a corner.

    Returns ``(n, vert, e, L, faces, m)``: the unit face normals (#F, 3); per record the corner
    (k,), the unit direction of the edge away from it (k, 3), the edge's length (k,), its two
    faces (k, 2) and, for each, the unit direction in the face's plane normal to the edge
    pointing into the face (k, 2, 3)."""
    n = unit_normals(V, F)
    he = F[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    at = np.flatnonzero(corner[he].any(axis=1))  # half-edges at a corner (both of an edge)
    he, opp = he[at], F[:, [2, 0, 1]].reshape(-1)[at]  # opp: the vertex across each
    key = np.sort(he, axis=1)
    _, inv, cnt = np.unique(
        key[:, 0] * V.shape[0] + key[:, 1], return_inverse=True, return_counts=True
    )
    inv = inv.reshape(-1)
    o = np.argsort(inv, kind="stable")
    o = o[cnt[inv[o]] == 2]  # manifold edges: their two half-edges side by side
    h1, h2 = o[0::2], o[1::2]
    f1, f2 = at[h1] // 3, at[h2] // 3
    bent = np.einsum("ij,ij->i", n[f1], n[f2]) < np.cos(CREASE_ANGLE)
    h1, h2, f1, f2 = h1[bent], h2[bent], f1[bent], f2[bent]
    a, b = he[h1, 0], he[h1, 1]
    vert, other = np.r_[a, b], np.r_[b, a]
    d = V[other] - V[vert]
    L = np.linalg.norm(d, axis=1)
    faces = np.stack([np.r_[f1, f1], np.r_[f2, f2]], axis=1)
    third = np.stack([np.r_[opp[h1], opp[h1]], np.r_[opp[h2], opp[h2]]], axis=1)
    keep = corner[vert] & (L > 4 * tol)
    vert, d, L, faces, third = vert[keep], d[keep], L[keep], faces[keep], third[keep]
    e = d / L[:, None]
    w = V[third] - V[vert][:, None]
    m = w - np.einsum("kij,kj->ki", w, e)[:, :, None] * e[:, None]
    m /= np.maximum(np.linalg.norm(m, axis=2, keepdims=True), 1e-300)
    return n, vert, e, L, faces, m


def _parallel_groups(e: np.ndarray) -> np.ndarray:
    """(k,) label of each unit direction ``e`` (k, 3): the connected sets of directions within
    :data:`CREASE_DIR` (chord) of each other."""
    W, inv, _ = unique_rows(e)
    k = W.shape[0]
    pq = cKDTree(W).query_pairs(CREASE_DIR, output_type="ndarray")
    A = coo_matrix((np.ones(pq.shape[0]), (pq[:, 0], pq[:, 1])), shape=(k, k))
    return connected_components(A, directed=False)[1][inv]


def crease_pairs(V: np.ndarray, F: np.ndarray, tol: float) -> tuple:
    """Pairs of corners that form a crease joint (:func:`corner_gaps`) from the direction
    joining them, whatever the view: the candidates for a view of two mitred tips meeting.

    A pair ``(p, q)`` seen along ``v = (p - q) / |p - q|`` (``p`` near, ``t = |p - q|`` in
    front of ``q``) is one when, at ``p``, a crease between faces ``g`` and ``h`` and, at
    ``q``, an edge of a face ``f`` leave in the same 3D direction ``e`` (to 4 ``tol`` at the
    shorter edge's end: the far edge runs exactly ``t`` behind the near crease on screen) and

    * ``f`` is a mitre: oblique to ``g`` (``MITRE_COS < |n_f . n_g| <``
      :data:`OBLIQUE_MAX`), so it bends away behind the near bar instead of continuing
      ``g``'s plane or meeting it square (boxes);
    * ``g``, ``h`` and ``f`` face the viewer (``n . v > 0``, outward normals), the crease is
      not seen end-on (a stretch over 4 ``tol`` on screen);
    * on screen, ``f`` lies on ``h``'s side of the crease (hidden behind it) and ``g`` on the
      other side: ``f``'s hidden part is glued to ``g`` across the crease.

    Parameters
    ----------
    V : (#V, 3) float64
        Vertices of a model whose parts are oriented outward.
    F : (#F, 3) int64
    tol : float
        Absolute tolerance.

    Returns
    -------
    near, far : (k,) int64
        The corners ``p`` and ``q`` of each distinct pair.
    view : (k, 3) float64
        ``v``, unit, toward the camera.
    gap : (k,) float64
        ``t`` (over 10 ``tol``).

    Empty when the model has more than :data:`MAX_CREASE_CORNERS` corners or more than
    :data:`MAX_CREASE_CANDIDATES` pairs of parallel edges with oblique faces.
    """
    none = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0))
    corner = np.zeros(V.shape[0], dtype=bool)
    used = np.unique(F)
    corner[used] = corner_vertices(V, F)[used]
    if np.count_nonzero(corner) > MAX_CREASE_CORNERS:
        return none
    n, vert, e, L, faces, m = _edge_records(V, F, corner, tol)
    if vert.size < 2:
        return none
    group = _parallel_groups(e)
    o = np.argsort(group, kind="stable")
    starts = np.searchsorted(group[o], np.arange(int(group.max()) + 2))
    big = np.flatnonzero(np.diff(starts) >= 2)
    cand, total = [], 0
    for k in big.tolist():  # groups of parallel edges: mitred faces against near faces
        r = o[starts[k] : starts[k + 1]]
        N = n[faces[r]]  # (s, 2, 3)
        for gs, fs in ((0, 0), (0, 1), (1, 0), (1, 1)):  # which face is g, which f
            c = np.abs(N[:, gs] @ N[:, fs].T)
            i, j = np.nonzero((c > MITRE_COS) & (c < OBLIQUE_MAX))
            total += i.size
            if total > MAX_CREASE_CANDIDATES:
                return none
            cand.append(np.stack([r[i], r[j], np.full(i.size, gs), np.full(i.size, fs)], 1))
    if not cand:
        return none
    i, j, gs, fs = np.vstack(cand).T
    D = V[vert[i]] - V[vert[j]]
    t = np.linalg.norm(D, axis=1)
    v = D / np.maximum(t, 1e-300)[:, None]
    short = np.minimum(L[i], L[j])
    ev = np.einsum("ij,ij->i", e[i], v)
    ok = (t > 10 * tol) & (np.linalg.norm(e[i] - e[j], axis=1) * short <= 4 * tol)
    ok &= short * np.sqrt(np.maximum(1.0 - ev**2, 0.0)) > 4 * tol
    g, h, f = faces[i, gs], faces[i, 1 - gs], faces[j, fs]
    for x in (g, h, f):  # all three toward the viewer
        ok &= np.einsum("ij,ij->i", n[x], v) > 1e-6
    s = np.cross(v, e[i])  # screen normal of the crease
    side_g = np.sign(np.einsum("ij,ij->i", m[i, gs], s))
    side_h = np.sign(np.einsum("ij,ij->i", m[i, 1 - gs], s))
    side_f = np.sign(np.einsum("ij,ij->i", m[j, fs], s))
    ok &= (side_g != 0) & (side_h == -side_g) & (side_f == side_h)
    pq, first = np.unique(np.stack([vert[i], vert[j]], 1)[ok], axis=0, return_index=True)
    k = np.flatnonzero(ok)[first]
    return pq[:, 0], pq[:, 1], v[k], t[k]


def _planes(C, F, faces):
    """(k, 4) unit normal and offset ``n . x`` of model ``faces`` (camera frame)."""
    T = C[F[faces]]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    return np.c_[n, np.einsum("ij,ij->i", n, T[:, 0])]


def _through(P4, faces, F, verts, tol):
    """The planes (k, 4) of the faces among ``faces`` (planes ``P4``) incident to one of
    ``verts``, each once."""
    inc = np.isin(F[faces], verts).any(axis=1)
    if not inc.any():
        return np.zeros((0, 4))
    P = P4[inc]
    _, first = np.unique(np.round(P / (8 * tol)).astype(np.int64), axis=0, return_index=True)
    return P[np.sort(first)]


def _same_plane(P4, key, tol, ntol):
    """(k,) bool: planes ``P4`` equal to ``key`` (unit normals within ``ntol``, offsets within
    ``2 tol``)."""
    return (np.abs(P4[:, :3] - key[:3]).max(axis=1) <= ntol) & (
        np.abs(P4[:, 3] - key[3]) <= 2 * tol
    )


def _inside(X, T, tol):
    """(k, m) bool: screen points ``X`` (k, 2) inside screen triangles ``T`` (m, 3, 2)."""
    k, m = X.shape[0], T.shape[0]
    B = barycentric(np.repeat(X, m, axis=0), np.tile(T, (k, 1, 1)))
    h = tol / np.maximum(np.linalg.norm(T - T[:, [1, 2, 0]], axis=2).max(axis=1), 1e-300)
    return (B >= -np.tile(h, k)[:, None]).all(axis=1).reshape(k, m)


def joint_lines(
    xy: np.ndarray,
    Fa: np.ndarray,
    src: np.ndarray,
    pl: np.ndarray,
    C: np.ndarray,
    F: np.ndarray,
    front: np.ndarray,
    gap: float,
    near: np.ndarray,
    far: np.ndarray,
    tol: float,
    grid: float,
    crease: bool = False,
) -> list:
    """Visible edges where a near plane's face ends and the far plane runs on hidden across
    (the stretch of each edge that the far plane lies under).

    With ``crease`` (one pair of corners: :func:`corner_gaps`), the far plane is *not* the
    near one's: the far face bends away from the near face along the edge, which it meets
    exactly ``gap`` behind at both ends of the stretch (its edge lies behind the near
    crease, a false edge that is a crease once glued).

    Returns
    -------
    list of (p, q, side, far_faces, cover)
        Screen end points of the edge, the unit screen normal toward the far plane's hidden
        side, the far plane's front model faces, and the map faces in the plane of the near
        face beyond the edge.
    """
    faces = np.flatnonzero(front)
    P4 = _planes(C, F, faces)
    # normals agree when their planes part by at most 4 tol across the model, as their
    # offsets may (a person's one plane; a file's rounding tilts small faces by more than 1e-6)
    ntol = 4.0 * tol / max(float(np.linalg.norm(np.ptp(C[F].reshape(-1, 3), axis=0))), 1e-300)
    gkeys, fkeys = _through(P4, faces, F, near, tol), _through(P4, faces, F, far, tol)
    Psrc = _planes(C, F, src)
    h1, h2, he = interior_edges(Fa, xy.shape[0])
    out = []
    for gk in gkeys:  # a few planes through the near corners
        if abs(gk[2]) <= 1e-6:
            continue
        par = [np.abs(fk[:3] - gk[:3]).max() <= ntol for fk in fkeys]
        if crease:  # far planes bending away from the near one (seen: not edge-on) at a mitre:
            # oblique to it; a far face square to the near one is a block's side, whose edges
            # line up behind a near crease along many views of a scene of blocks
            match = [
                fk
                for fk, p in zip(fkeys, par)
                if not p and abs(fk[2]) > 1e-6 and abs(fk[:3] @ gk[:3]) > MITRE_COS
            ]
        else:  # the near plane continued, gap behind
            match = [fk for fk, p in zip(fkeys, par) if p]
            match = [fk for fk in match if abs((gk[3] - fk[3]) - gk[2] * gap) <= 4 * tol][:1]
        for fk in match:  # a few far planes
            key = (faces, P4, Psrc, (h1, h2), ntol, grid)
            out += _lines_of(xy, Fa, src, pl, C, F, key, gk, fk, gap, tol)
    return out


def _lines_of(xy, Fa, src, pl, C, F, key, gk, fk, gap, tol):
    """:func:`joint_lines` for one near plane ``gk`` and one far plane ``fk``; ``key``: the
    front faces, their planes, the map faces' planes, the map's interior half-edge pairs,
    the normal tolerance and the grid."""
    import shapely

    faces, P4, Psrc, (h1, h2), ntol, grid = key
    crease = np.abs(fk[:3] - gk[:3]).max() > ntol
    in_g = _same_plane(Psrc, gk, tol, ntol)
    fpl = faces[_same_plane(P4, fk, tol, ntol)]
    under = shapely.union_all(shapely.polygons(C[F[fpl], :2]), grid_size=grid)
    out = []
    for ha, hb in ((h1, h2), (h2, h1)):  # the near plane's face on either side
        sel = in_g[ha // 3] & ~in_g[hb // 3]
        sel[sel] = _ends_there(xy, Fa, src, C, F, ha[sel], tol)
        for i in np.flatnonzero(sel).tolist():  # a few edges per joint
            line = _joint_line(xy, Fa, pl, src, ha[i], hb[i], under, fk, tol)
            if line is None:
                continue
            if crease:  # the far face meets the stretch exactly gap behind, at both ends
                ends = np.vstack(line[:2])
                if np.abs(_plane_z(gk, ends) - _plane_z(fk, ends) - gap).max() > 4 * tol:
                    continue
            # the near bar's face beyond the line: its plane
            cover = np.flatnonzero(_same_plane(Psrc, Psrc[hb[i] // 3], tol, ntol))
            out.append((*line, fpl, cover))
    return out


def _plane_z(P4: np.ndarray, X: np.ndarray) -> np.ndarray:
    """(k,) depth of the plane ``P4`` (unit normal, offset; camera frame) at screen points
    ``X`` (k, 2)."""
    return (P4[3] - X @ P4[:2]) / P4[2]


def _ends_there(xy, Fa, src, C, F, ha, tol) -> np.ndarray:
    """(k,) bool: the map edges of half-edges ``ha`` lie on an edge of their source face (the
    near face ends there)."""
    f, k = ha // 3, ha % 3
    E = np.stack([Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]], axis=1)
    return edge_on_source(xy, E, src[f], C, F, tol) >= 0


def _joint_line(xy, Fa, pl, src, ha, hb, under, fk, tol):
    """(p, q, side): the stretch of the edge of half-edges ``ha`` (near plane's face) and
    ``hb`` that the far plane ``fk`` (screen region ``under``) lies under, hidden on ``hb``'s
    side behind ``hb``'s face; else None."""
    f, k = ha // 3, ha % 3
    p, q = xy[Fa[f, (k + 1) % 3]], xy[Fa[f, (k + 2) % 3]]
    d = q - p
    L = float(np.linalg.norm(d))
    if L <= 4 * tol:
        return None
    n = np.array([d[1], -d[0]]) / L  # face ha lies left of p -> q: n points right, to hb
    # the stretch under the far plane, on the far side of the edge (its ends where the
    # edge itself meets the region's outline, when it does)
    shift = 8 * tol * n
    ts = _stretches(p + shift, q + shift, under)
    if not ts:
        return None
    a, b = max(ts, key=lambda r: r[1] - r[0])
    for a0, b0 in _stretches(p, q, under):  # a few pieces
        if min(b, b0) - max(a, a0) > 0.5 * (b - a):
            a, b = a0, b0
            break
    if (b - a) * L <= 4 * tol:
        return None
    p, q = p + a * d, p + b * d
    probe = p + np.array([[0.1], [0.5], [0.9]]) * (q - p) + shift
    z_far = plane_depth(probe, np.array([-fk[0] / fk[2], -fk[1] / fk[2], fk[3] / fk[2]]))
    z_b = plane_depth(probe, pl[src[hb // 3]])
    if np.any(z_b <= z_far + tol):
        return None  # the far plane is not hidden there
    return p, q, n


def _stretches(p, q, region) -> list:
    """Parameter ranges ``(a, b)`` in [0, 1] of the segment ``p q`` inside ``region``."""
    import shapely

    d = q - p
    L2 = float(d @ d)
    seg = shapely.intersection(shapely.LineString([p, q]), region)
    out = []
    for g in shapely.get_parts(seg):
        if shapely.get_type_id(g) == 1 and not g.is_empty:
            t = np.sort((np.asarray(g.coords)[[0, -1]] - p) @ d / L2)
            out.append((float(t[0]), float(t[1])))
    return out


def hidden_strips(
    xy: np.ndarray,
    Fa: np.ndarray,
    src: np.ndarray,
    C: np.ndarray,
    F: np.ndarray,
    lines: list,
    gap: float,
    tol: float,
    grid: float,
    crease: bool = False,
) -> list:
    """The far planes' hidden parts across the joint ``lines`` (:func:`joint_lines`), each
    the part on the line's far side that touches it.  List of :class:`HiddenStrip`.

    With ``crease`` (a crease joint's mitre face), a strip corner within :data:`SNAP_CORNER`
    tolerances of a map vertex is put on it: the mitred erosion below bevels a sharp corner."""
    import shapely

    if not lines:
        return []
    span = float(np.ptp(xy, axis=0).max()) * 4.0
    out = []
    groups: dict = {}
    for p, q, n, fpl, cover in lines:
        groups.setdefault(tuple(fpl.tolist()), []).append((p, q, n, cover))
    for key, segs in groups.items():  # one far plane at a time
        fpl = np.asarray(key, dtype=np.int64)
        proj = shapely.union_all(shapely.polygons(C[F[fpl], :2]), grid_size=grid)
        seen = shapely.union_all(shapely.polygons(xy[Fa[np.isin(src, fpl)]]), grid_size=grid)
        hid = shapely.difference(proj, seen, grid_size=grid)
        # without the slivers that round-off leaves along the visible pieces' edges
        hid = shapely.buffer(shapely.buffer(hid, -tol, join_style="mitre"), tol, join_style="mitre")
        hid = shapely.set_precision(hid, grid)
        for p, q, n, cover in segs:
            front = shapely.buffer(shapely.union_all(shapely.polygons(xy[Fa[cover]])), 2 * tol)
            d = (q - p) / np.linalg.norm(q - p)
            a, b = p - span * d, q + span * d
            half = shapely.Polygon([a, b, b + span * n, a + span * n])
            part = shapely.intersection(hid, half, grid_size=grid)
            seg = shapely.LineString([p, q])
            for g in shapely.get_parts(part):
                if shapely.get_type_id(g) != 3 or g.area <= tol * tol:
                    continue
                if shapely.distance(g, seg) > tol or len(g.interiors):
                    continue
                # the far bar comes out from behind there: the strip meets its visible faces
                rim = shapely.intersection(g.exterior, shapely.buffer(seen, tol))
                if shapely.length(rim) <= 4 * tol:
                    continue
                if not shapely.covers(front, g):  # hidden behind the near bar's face
                    continue
                g = shapely.geometry.polygon.orient(g, 1.0)
                ring = np.asarray(g.exterior.coords)[:-1]
                if crease:  # a sharp corner the mitred erosion bevelled: onto the map's
                    # vertex, or the far face's own corner hidden there (where its edge
                    # leaves the crease, exactly gap behind it)
                    at = np.vstack([xy, C[F[fpl], :2].reshape(-1, 2)])
                    d, k = cKDTree(at).query(ring)
                    ring = np.where((d <= SNAP_CORNER * tol)[:, None], at[k], ring)
                step = np.linalg.norm(ring - np.roll(ring, 1, axis=0), axis=1)
                ring = ring[step > tol]  # grid round-off can repeat a corner
                if ring.shape[0] >= 3:
                    out.append(HiddenStrip(ring, fpl, gap))
    return out


def _with_points_on(ring: np.ndarray, pts: np.ndarray, tol: float) -> np.ndarray:
    """The ring with every point of ``pts`` lying on one of its edges inserted in order."""
    out = []
    for a, b in zip(ring, np.roll(ring, -1, axis=0)):  # a few edges per strip
        out.append(a)
        d = b - a
        L2 = float(d @ d)
        if L2 <= 0:
            continue
        w = pts - a
        t = (w @ d) / L2
        dist = np.abs(w[:, 0] * d[1] - w[:, 1] * d[0]) / np.sqrt(L2)
        on = (dist <= tol) & (t * np.sqrt(L2) > tol) & ((1 - t) * np.sqrt(L2) > tol)
        out += [pts[i] for i in np.flatnonzero(on)[np.argsort(t[on])]]
    return np.asarray(out)


@dataclass(frozen=True)
class Joints:
    """What :func:`prepare_joints` found: the hidden strips to add once glued."""

    strips: list

    def __bool__(self) -> bool:
        return bool(self.strips)


def prepare_joints(
    xy: np.ndarray,
    Fa: np.ndarray,
    src: np.ndarray,
    pl: np.ndarray,
    C: np.ndarray,
    F: np.ndarray,
    front: np.ndarray,
    tol: float,
    grid: float,
) -> tuple:
    """Find the joints of bar ends and split the visible map where the hidden strips' corners
    fall inside its edges.  Returns ``(xy, Fa, src, joints)``."""
    strips = []
    for gap, near, far in coincident_gaps(C, F, tol):  # a few gaps
        lines = joint_lines(xy, Fa, src, pl, C, F, front, gap, near, far, tol, grid)
        strips += hidden_strips(xy, Fa, src, C, F, lines, gap, tol, grid)
    for gap, near, far in corner_gaps(C, F, tol):  # a few single pairs: crease joints
        lines = joint_lines(xy, Fa, src, pl, C, F, front, gap, near, far, tol, grid, True)
        strips += hidden_strips(xy, Fa, src, C, F, lines, gap, tol, grid, True)
    strips = _distinct_strips(strips, tol)
    if strips:
        pts = np.vstack([s.ring for s in strips])
        xy, Fa, src = split_edges_at(xy, Fa, src, pts, tol)
    return xy, Fa, src, Joints(strips)


def _distinct_strips(strips: list, tol: float) -> list:
    """The strips, each hidden region once: a strip mostly inside one kept before (the same
    gap; more than half its area) was reached again from another piece of the same joint
    line (a near face's edge split by the triangulation), its corners found along nearly
    parallel lines a little apart."""
    import shapely

    kept, polys = [], []
    for s in strips:  # a few strips
        poly = shapely.make_valid(shapely.Polygon(s.ring))
        area = poly.area
        dup = any(
            abs(k.gap - s.gap) <= 4 * tol
            and shapely.intersection(poly, q).area > 0.5 * min(area, q.area)
            for k, q in zip(kept, polys)
        )
        if not dup:
            kept.append(s)
            polys.append(poly)
    return kept


def split_edges_at(
    xy: np.ndarray, Fa: np.ndarray, src: np.ndarray, pts: np.ndarray, tol: float
) -> tuple:
    """Add each point of ``pts`` lying inside an edge of the map (not at a vertex) as a vertex,
    splitting both faces of that edge.  Returns ``(xy, Fa, src)``."""
    d, _ = cKDTree(xy).query(pts)
    pts = pts[d > tol]
    for x in pts:  # a few strip corners
        E = np.stack([Fa[:, [1, 2]], Fa[:, [2, 0]], Fa[:, [0, 1]]], axis=1).reshape(-1, 2)
        a, b = xy[E[:, 0]], xy[E[:, 1]]
        dv = b - a
        L = np.maximum(np.linalg.norm(dv, axis=1), 1e-300)
        w = x - a
        t = np.einsum("ij,ij->i", w, dv) / L**2
        dist = np.abs(w[:, 0] * dv[:, 1] - w[:, 1] * dv[:, 0]) / L
        hit = np.flatnonzero((dist <= tol) & (t * L > tol) & ((1 - t) * L > tol))
        if hit.size == 0:
            continue
        v = xy.shape[0]
        xy = np.vstack([xy, x])
        f, k = hit // 3, hit % 3
        c, p, q = Fa[f, k], Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]
        keep = np.ones(Fa.shape[0], dtype=bool)
        keep[f] = False
        new = np.vstack(
            [np.stack([c, p, np.full_like(c, v)], 1), np.stack([c, np.full_like(c, v), q], 1)]
        )
        Fa = np.vstack([Fa[keep], new])
        src = np.concatenate([src[keep], src[f], src[f]])
    return xy, Fa, src


def _strip_triangles(xy, strip: HiddenStrip, C, F, tol):
    """Triangles of ``strip`` over ``xy`` (new vertices appended) and their source faces.
    Returns ``(xy, tris (m, 3), src (m,))`` or None when the strip does not triangulate."""
    ring = _with_points_on(strip.ring, xy, tol)
    d, idx = cKDTree(xy).query(ring)
    T = polygon_triangles(ring)  # None for a ring doubling back on itself
    if T is None:
        return None
    Q = ring[T]
    new = d > tol
    vid = np.where(new, xy.shape[0] + np.cumsum(new) - 1, idx)
    xy = np.vstack([xy, ring[new]])
    inside = _inside(Q.mean(axis=1), C[F[strip.faces], :2], tol)
    if not inside.any(axis=1).all():
        return None
    return xy, vid[T], strip.faces[np.argmax(inside, axis=1)]


def join_ends(
    xy: np.ndarray,
    Fb: np.ndarray,
    sb: np.ndarray,
    Zb: np.ndarray,
    pl: np.ndarray,
    C: np.ndarray,
    F: np.ndarray,
    glue: Glue,
    arcs: np.ndarray,
    is_bridge: np.ndarray,
    joints: Joints,
    tol: float,
    seen: list | tuple = (),
) -> tuple:
    """Add the hidden strips of ``joints`` behind the faces covering them and glue them: to
    the far bar's visible faces and to each other where the depth is continuous, to the near
    plane's faces across the joint lines where the depth gap is the joint's (the near bar's
    face beyond the line is cut from it there).

    ``seen``: the junctions glued so far (false edges, bridges); with one of them, nothing
    is added.  Returns ``(xy, Fb, sb, Zb, is_bridge, glue, arcs, junctions)``, the input
    unchanged (and no junction) when no strip glues across its gap.
    """
    none = (xy, Fb, sb, Zb, is_bridge, glue, arcs, [])
    if not joints or any(j.depth_gap > tol and j.kind != "occluded continuation" for j in seen):
        return none  # another junction is glued already
    xy0, nf, tris, srcs, gaps = xy, Fb.shape[0], [], [], []
    for s in joints.strips:  # a few strips: each must join both bars
        got = _strip_triangles(xy, s, C, F, tol)
        if got is None:
            continue
        xy1, T, st = got
        Fn = np.vstack([Fb, T])
        Zn = np.vstack([Zb, plane_depth(xy1[T], pl[st][:, None, :])])
        _, b, jump = _strip_pairs(Fn, Zn, nf, np.array([s.gap]), tol)
        if jump.any() and np.any(~jump & (b < 3 * nf)):  # glued across, and to the far bar
            xy = xy1
            tris.append(T)
            srcs.append(st)
            gaps.append(s.gap)
    if not tris:
        return none
    S, sS = np.vstack(tris), np.concatenate(srcs)
    Fn = np.vstack([Fb, S])
    sn = np.concatenate([sb, sS])
    Zn = np.vstack([Zb, plane_depth(xy[S], pl[sS][:, None, :])])
    gaps = np.asarray(gaps)
    g1, g2, jump = _strip_pairs(Fn, Zn, nf, gaps, tol)
    glue0, arcs0 = glue, arcs
    glued = glue.glued.copy()
    # the partner a strip takes across a joint line is freed from its old pair
    mapped = g2 < 3 * nf
    taken = np.isin(glue.h1, g2[mapped]) | np.isin(glue.h2, g2[mapped])
    glued[taken] = False
    glue = Glue(
        np.concatenate([glue.h1, g1]),
        np.concatenate([glue.h2, g2]),
        np.concatenate([glued, np.ones(g1.size, dtype=bool)]),
        np.concatenate([glue.continuous & ~taken, ~jump]),
    )
    # strip faces lie behind the visible faces they overlap on screen
    strip = np.r_[np.zeros(nf, dtype=bool), np.ones(S.shape[0], dtype=bool)]
    pairs, _ = overlapping_pairs(xy[Fn], tol)
    mixed = strip[pairs[:, 0]] & ~strip[pairs[:, 1]] | ~strip[pairs[:, 0]] & strip[pairs[:, 1]]
    pr = pairs[mixed]
    behind = np.where(strip[pr[:, 0]], pr[:, 0], pr[:, 1])
    ahead = np.where(strip[pr[:, 0]], pr[:, 1], pr[:, 0])
    arcs = np.vstack([arcs, np.stack([behind, ahead], axis=1)]).astype(np.int64)
    he = g1[jump]
    f, k = he // 3, he % 3
    mid = 0.5 * (xy[Fn[f, (k + 1) % 3]] + xy[Fn[f, (k + 2) % 3]])
    if not _manifold(cut_and_glue(Fn, glue)[0]):
        return (xy0, Fb, sb, Zb, is_bridge, glue0, arcs0, [])
    junction = Junction("bar joint", mid.mean(axis=0), float(np.median(gaps)), int(jump.sum()))
    is_bridge = np.r_[is_bridge, np.ones(S.shape[0], dtype=bool)]
    return xy, Fn, sn, Zn, is_bridge, glue, arcs, [junction]


def _manifold(Fm: np.ndarray) -> bool:
    """Does every edge of ``Fm`` have at most two faces, traversed opposite ways?"""
    he = np.stack([Fm[:, [1, 2]], Fm[:, [2, 0]], Fm[:, [0, 1]]], axis=1).reshape(-1, 2)
    n = int(Fm.max()) + 1
    directed = np.unique(he[:, 0] * n + he[:, 1]).size == he.shape[0]
    und = np.unique(
        np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1]), return_counts=True
    )[1]
    return bool(directed and und.max(initial=0) <= 2)


def _strip_pairs(Fn, Zn, nf, gaps, tol):
    """Half-edge pairs (strip half-edge, partner) to glue, and which glue across a gap.

    A strip half-edge ``u -> v`` pairs with the half-edge ``v -> u`` of a map face or another
    strip: glued where the depths agree at both ends (continuous), or where the partner lies
    one of ``gaps`` in front at both ends (across a joint line)."""
    n = int(Fn.max()) + 1
    he = np.stack([Fn[:, [1, 2]], Fn[:, [2, 0]], Fn[:, [0, 1]]], axis=1).reshape(-1, 2)
    zt = np.stack([Zn[:, [1, 2]], Zn[:, [2, 0]], Zn[:, [0, 1]]], axis=1).reshape(-1, 2)
    hs = np.arange(3 * nf, he.shape[0])
    key = he[:, 0] * n + he[:, 1]
    rev = he[hs, 1] * n + he[hs, 0]
    order = np.argsort(key, kind="stable")
    pos = np.searchsorted(key[order], rev)
    pos = np.minimum(pos, key.size - 1)
    found = key[order][pos] == rev
    a, b = hs[found], order[pos[found]]
    keep = (b < 3 * nf) | (a < b)  # strip-strip pairs once
    a, b = a[keep], b[keep]
    dz = zt[b][:, ::-1] - zt[a]  # partner minus strip at the strip edge's tail and head
    cont = np.abs(dz).max(axis=1) <= tol
    jump = np.zeros(a.size, dtype=bool)
    for g in np.unique(np.round(gaps / tol)).tolist():  # a few gaps
        jump |= (np.abs(dz - g * tol).max(axis=1) <= 4 * tol) & (b < 3 * nf)
    ok = cont | jump
    return a[ok], b[ok], jump[ok]
