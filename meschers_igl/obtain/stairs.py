"""Step junctions of staircases: the top tread's edge seen over a wall that rises to the
bottom tread of the same staircase, which climbs step by step back to the top.

A person reads the strip of wall between the tread's edge and the tread above as a riser
facing the viewer: the near tread steps *up* onto the far one.  Where the near tread is the
staircase's top (no step rises from it), the far one its bottom (no step rises onto it) and a
chain of rising steps leads from the far one to the near one (:func:`step_graph`), the loop
near tread, wall strip, far tread, ..., near tread climbs the same way at every step: the
Penrose stairs.  The edge is then glued to the wall, a false edge whose depth gap is the climb
per turn seen along the view (the strip counts as the last riser).  A box in front of a wall,
a flight before a higher wall, stepped grids keep their cut: no chain of rising steps leads
from the wall's tread back to the near tread; a spiral seen with its drop in view keeps it: the
strip is taller than :data:`MAX_JUNCTION_RISE` risers.
"""

from __future__ import annotations

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .clip import plane_depth
from .glue import edge_on_source, he_depth
from .records import FalseEdges, Glue

#: Two unit normals are the same direction (treads of one staircase), or perpendicular (a
#: riser or wall beside a tread), to this much.
NORMAL_TOL = 1e-6


#: The strip of wall between a tread's edge and the tread above reads as one riser when it is
#: at most this many of the staircase's rises (the least rise of its steps) tall; a taller
#: strip is a wall seen behind the tread (a spiral's drop seen from above).  Measured: the
#: Penrose staircases of the development set from their given views 2.3 and 1.0; a step-column
#: spiral with its drop in sight 3.9 (a 3-step ring from (0.7, 0.45, 1)) to 14.
MAX_JUNCTION_RISE = 3.0


def _unit(N: np.ndarray) -> np.ndarray:
    return N / np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)


def tread_edge_over_wall(xy, Fa, src, pl, C, F, n, front, glue: Glue, tol: float, n_model: int):
    """Cut screen edges where a tread's silhouette edge lies over a wall perpendicular to it.

    The two sides of the cut have a constant depth gap along the edge (the tread's edge runs
    parallel to the wall), the near side lies on an edge of its model face whose other face
    looks away (the riser behind the tread's edge, or the flight's back) and the far side's
    model face contains the near face's normal (a wall standing on the near tread's plane).
    ``n``: (#F, 3) the model faces' unit normals (camera frame).

    Returns
    -------
    idx : (m,) int64
        Indices into ``glue.h1``, ``glue.h2`` of the candidate edges.
    near, far : (m,) int64
        Their near and far half-edges (``3 f + k``).
    dz : (m,) float64
        Depth of the second side (``glue.h2``) minus the first, the mean over the edge's ends.
    """
    cut = np.flatnonzero(~glue.glued)
    none = (np.zeros(0, np.int64),) * 3 + (np.zeros(0),)
    if cut.size == 0:
        return none
    h1, h2 = glue.h1[cut], glue.h2[cut]
    Z = plane_depth(xy[Fa], pl[src][:, None, :])
    d = he_depth(Z, h2)[:, ::-1] - he_depth(Z, h1)  # side 2 minus side 1 at tail and head
    far1 = d.sum(axis=1) > 0
    hn, hf = np.where(far1, h2, h1), np.where(far1, h1, h2)
    sn, sf = src[hn // 3], src[hf // 3]
    ok = (np.abs(d[:, 0] - d[:, 1]) <= tol) & (np.abs(d).min(axis=1) > tol)
    ok &= (sn < n_model) & (sf < n_model) & front[sf]
    ok &= np.abs(np.einsum("ij,ij->i", n[sn], n[sf])) <= NORMAL_TOL
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return none
    hn, hf, sn = hn[idx], hf[idx], sn[idx]
    kn = hn % 3
    E = np.stack([Fa[hn // 3, (kn + 1) % 3], Fa[hn // 3, (kn + 2) % 3]], axis=1)
    k = edge_on_source(xy, E, sn, C, F, tol)
    TT = np.asarray(igl.triangle_triangle_adjacency(F[:n_model])[0])
    nb = np.where(k >= 0, TT[sn, np.maximum(k, 0)], -1)
    keep = (k >= 0) & ((nb < 0) | ~front[np.maximum(nb, 0)])
    # the tread's whole edge lies over walls (not its corner beside a lower tread)
    km = np.maximum(k, 0)
    model_len = np.linalg.norm(C[F[sn, (km + 1) % 3], :2] - C[F[sn, km], :2], axis=1)
    seen = np.linalg.norm(xy[E[:, 1]] - xy[E[:, 0]], axis=1)
    key = sn * 3 + km
    cover = np.zeros(int(key.max()) + 1)
    np.add.at(cover, key[keep], seen[keep])
    keep &= cover[key] >= model_len - 2.0 * tol
    dz = d[idx].mean(axis=1)
    return cut[idx][keep], hn[keep], hf[keep], dz[keep]


def step_graph(Fa, src, C, F, n, glue: Glue, up: np.ndarray, tol: float, n_model: int):
    """Treads and the rising steps between them on the glued visible map, for one tread
    direction ``up`` (a unit normal, camera frame).

    Treads are connected pieces of faces whose model face has normal ``up``, at one height
    ``up . p``; risers are connected pieces of faces whose model face is perpendicular to
    ``up`` (walls and risers) or a riser band (model faces from ``n_model`` on), each piece in
    one plane.  A riser piece is a step from each tread it stands on (glued at a valley: the
    tread lies in front of its plane; a band stands on its lower tread) up to each higher
    tread it carries (glued at a ridge); a wall glued to treads only along its top joins none.
    ``n``: (#F, 3) the model faces' unit normals (camera frame).

    Returns
    -------
    node : (#Fa,) int64
        Tread node of each screen face (-1: not a tread).
    riser : (#Fa,) int64
        Riser piece of each screen face (-1: not a riser).
    height : (#nodes,) float64
        Height of each tread along ``up``.
    A : (#nodes, #nodes) scipy.sparse.csr_matrix
        ``A[i, j] = 1``: a riser piece joins tread ``i`` to the higher tread ``j``.
    touch : scipy.sparse.csr_matrix
        ``touch[r, i] = 1``: riser piece ``r`` is glued to tread ``i``.
    """
    s = src
    cos = n[s] @ up
    h = np.einsum("ij,j->i", C[F[s, 0]], up)
    is_tread = (s < n_model) & (np.abs(cos - 1.0) <= NORMAL_TOL)
    is_riser = (s >= n_model) | (np.abs(cos) <= NORMAL_TOL)
    g1, g2 = glue.h1[glue.glued] // 3, glue.h2[glue.glued] // 3
    nf = Fa.shape[0]

    def pieces(mask, same):
        e = mask[g1] & mask[g2] & same
        M = sp.coo_matrix((np.ones(int(e.sum())), (g1[e], g2[e])), shape=(nf, nf))
        _, lab = csgraph.connected_components(M, directed=False)
        _, lab_m = np.unique(lab[mask], return_inverse=True)
        out = np.full(nf, -1, dtype=np.int64)
        out[mask] = lab_m.reshape(-1)
        return out

    node = pieces(is_tread, np.abs(h[g1] - h[g2]) <= tol)
    riser = pieces(is_riser, np.einsum("ij,ij->i", n[s[g1]], n[s[g2]]) >= 1.0 - NORMAL_TOL)
    n_nodes, n_risers = int(node.max()) + 1, int(riser.max()) + 1
    height = np.zeros(max(n_nodes, 0))
    height[node[is_tread]] = h[is_tread]
    # riser piece -> tread it is glued to (either order); a riser's tread is below it (a
    # valley: the tread lies in front of the riser's plane) or above it (a ridge); a band
    # is both (it lies between its two treads)
    a = np.concatenate([g1, g2])
    b = np.concatenate([g2, g1])
    e = (riser[a] >= 0) & (node[b] >= 0)
    a, b = a[e], b[e]
    sa = s[a]
    cb = C[F[s[b]]].mean(axis=1)  # a point of the tread's model face
    side = np.einsum("ij,ij->i", cb - C[F[sa, 0]], n[sa])
    band = sa >= n_model
    shape = (max(n_risers, 0), n_nodes)

    def incidence(m):
        M = sp.coo_matrix((np.ones(int(m.sum())), (riser[a[m]], node[b[m]])), shape=shape)
        M = M.tocsr()
        M.data[:] = 1.0
        return M

    touch = incidence(np.ones(a.size, dtype=bool))
    below, above = incidence(band | (side > tol)), incidence(band | (side < -tol))
    # tread i -> tread j: a riser piece stands on i and carries j, j higher (a step up)
    J = (below.T @ above).tocoo()
    rise = height[J.col] - height[J.row] > tol
    A = sp.coo_matrix(
        (np.ones(int(rise.sum())), (J.row[rise], J.col[rise])), shape=(n_nodes, n_nodes)
    ).tocsr()
    return node, riser, height, A, touch


def climbs_to(A, sources: np.ndarray, target: int) -> bool:
    """Does a chain of rising steps (edges of ``A``) lead from one of ``sources`` to
    ``target``?"""
    for s in np.unique(sources).tolist():  # the few treads above one wall strip
        reach = csgraph.breadth_first_order(A, s, directed=True, return_predecessors=False)
        if target in set(reach.tolist()):
            return True
    return False


def tread_above(P: np.ndarray, up: np.ndarray, wall: np.ndarray, C, F, n, tol: float):
    """The tread directly above each point ``P`` (camera frame) on its wall (model face
    ``wall``): the model face of normal ``up`` with an edge in the wall's plane that the line
    ``P + s up`` (``s > 0``) meets, the nearest one; -1 where none.  Returns (tread, rise ``s``).
    ``n``: (#F, 3) the model faces' unit normals (camera frame).
    """
    cand = np.flatnonzero(np.abs(n @ up - 1.0) <= NORMAL_TOL)
    out, rise = np.full(P.shape[0], -1, dtype=np.int64), np.full(P.shape[0], np.inf)
    if cand.size == 0:
        return out, rise
    T = C[F[cand]]  # (t, 3, 3)
    for i in range(P.shape[0]):  # a few junction candidates
        m, o = n[wall[i]], C[F[wall[i], 0]]
        s = np.einsum("tvk,k->tv", T, up)[:, 0] - P[i] @ up  # rise to each tread's plane
        q = P[i] + s[:, None] * up  # (t, 3) the point above P on each tread's plane
        on = np.abs(np.einsum("tvk,k->tv", T - o, m)) <= tol  # corners in the wall's plane
        a, b = T[:, :, None, :], T[:, None, :, :]  # every corner pair (an edge when both on)
        ab = b - a
        w = q[:, None, None, :] - a
        t = np.clip(
            np.einsum("tijk,tijk->tij", w, ab)
            / np.maximum(np.einsum("tijk,tijk->tij", ab, ab), 1e-300),
            0.0,
            1.0,
        )
        dist = np.linalg.norm(w - t[..., None] * ab, axis=3)
        hit = ((dist <= tol) & on[:, :, None] & on[:, None, :]).any(axis=(1, 2)) & (s > tol)
        if hit.any():
            k = np.flatnonzero(hit)[np.argmin(s[hit])]
            out[i], rise[i] = cand[k], s[k]
    return out, rise


def step_junctions(xy, Fa, src, pl, C, F, N, front, glue: Glue, tol: float, n_model: int):
    """Cut edges to glue as step junctions (:mod:`.stairs`): a tread's silhouette edge over a
    wall (:func:`tread_edge_over_wall`) whose visible strip rises to the tread directly above
    (:func:`tread_above`), from which a chain of rising steps leads back to the near tread
    (:func:`step_graph`, :func:`climbs_to`), the strip no taller than :data:`MAX_JUNCTION_RISE`
    of the staircase's least rise.

    Returns (indices into ``glue.h1``, far half-edges, ``dz``), as
    :func:`tread_edge_over_wall`, for the edges kept.
    """
    n = _unit(N)  # the model faces' unit normals, for every step below
    idx, hn, hf, dz = tread_edge_over_wall(xy, Fa, src, pl, C, F, n, front, glue, tol, n_model)
    empty = np.zeros(0, np.int64)
    if idx.size == 0:
        return empty, empty, np.zeros(0)
    ups = n[src[hn // 3]]
    key = np.round(ups / NORMAL_TOL).astype(np.int64)
    _, grp = np.unique(key, axis=0, return_inverse=True)
    grp = grp.reshape(-1)
    keep = np.zeros(idx.size, dtype=bool)
    for g in np.unique(grp).tolist():  # one staircase direction, rarely two
        sel = np.flatnonzero(grp == g)
        up = ups[sel[0]]
        node, riser, height, A, touch = step_graph(Fa, src, C, F, n, glue, up, tol, n_model)
        # far point of each edge (its midpoint on the wall) and the tread directly above it
        ff, kf = hf[sel] // 3, hf[sel] % 3
        P = 0.5 * (xy[Fa[ff, (kf + 1) % 3]] + xy[Fa[ff, (kf + 2) % 3]])
        P = np.c_[P, plane_depth(P, pl[src[ff]])]
        top, rise = tread_above(P, up, src[ff], C, F, n, tol)
        Ac = A.tocoo()
        step = (height[Ac.col] - height[Ac.row]).min() if Ac.nnz else 0.0
        for i, j in enumerate(sel.tolist()):  # a few candidate edges
            r, a = riser[ff[i]], node[hn[j] // 3]
            if r < 0 or a < 0 or top[i] < 0 or rise[i] > MAX_JUNCTION_RISE * step:
                continue
            treads = touch[r].indices
            hit = treads[np.abs(height[treads] - (P[i] @ up + rise[i])) <= tol]
            # the staircase's top over a wall rising to its bottom: no step rises from the
            # near tread nor onto the far one, and the far one climbs to the near one
            top_ok = A[int(a)].nnz == 0 if hit.size else False
            hit = hit[np.asarray(A[:, hit].sum(axis=0)).reshape(-1) == 0]
            keep[j] = top_ok and hit.size > 0 and climbs_to(A, hit, int(a))
    return idx[keep], hf[keep], dz[keep]


def glue_step_junctions(glue: Glue, arcs: np.ndarray, fe: FalseEdges, Fa, idx, hf, dz):
    """Glue the step junctions ``idx`` (indices into ``glue.h1``): their occlusion arcs go,
    they join the false edges (``dz``: depth of the second side minus the first) and leave the
    occluded edges."""
    if idx.size == 0:
        return glue, arcs, fe
    cut = np.flatnonzero(~glue.glued)
    keep_arc = ~np.isin(cut, idx)
    glued = glue.glued.copy()
    glued[idx] = True
    h1 = glue.h1[idx]
    k = h1 % 3
    E = np.stack([Fa[h1 // 3, (k + 1) % 3], Fa[h1 // 3, (k + 2) % 3]], axis=1)
    fe = FalseEdges(
        np.vstack([fe.E, E]),
        np.concatenate([fe.gap, dz]),
        fe.occluded[~np.isin(fe.occluded, hf)],
    )
    return glue.with_glued(glued), arcs[keep_arc], fe
