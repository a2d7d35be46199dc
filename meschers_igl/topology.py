"""Combinatorics of a mescher: edges, exterior derivatives, boundary loops, homology basis.

Nothing here looks at geometry except the tree-cotree basis, which may take edge weights.

Conventions (:doc:`/conventions`): ``edges[e] = (tail, head)``; a 1-form value on edge ``e`` is the
change from tail to head.  ``face_edges[f, i]`` is the edge *opposite* corner ``i`` of face
``f``, i.e. between ``F[f, (i+1)%3]`` and ``F[f, (i+2)%3]`` (libigl's column convention for
per-face edge lengths), and ``face_edge_signs[f, i]`` is ``+1`` when that edge is stored in the
direction ``F[f, (i+1)%3] -> F[f, (i+2)%3]`` (the face's boundary orientation), else ``-1``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .errors import MescherError

#: corner ``i`` is opposite the half-edge ``_NEXT[i] -> _PREV[i]``
_NEXT = np.array([1, 2, 0])
_PREV = np.array([2, 0, 1])


def half_edges(F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tails and heads of the face-boundary half-edges, (#F, 3) each, column i opposite corner i."""
    return F[:, _NEXT], F[:, _PREV]


def undirected_keys(tail: np.ndarray, head: np.ndarray, n: int) -> np.ndarray:
    """int64 key ``min * n + max`` of each vertex pair, the same for both directions."""
    lo = np.minimum(tail, head)
    hi = np.maximum(tail, head)
    return lo * np.int64(n) + hi


_undirected_keys = undirected_keys  # the name this module's functions use


def edge_lookup(
    edges: np.ndarray, n_vertices: int, tail: np.ndarray, head: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Edge index and direction of each vertex pair ``tail -> head``.

    Parameters
    ----------
    edges : (#E, 2) int64
        Any order and orientation.
    n_vertices : int
    tail, head : (k,) int64

    Returns
    -------
    e : (k,) int64
        Index of the edge joining ``tail`` and ``head``, ``-1`` where there is none.
    sign : (k,) float64
        ``+1`` where ``edges[e]`` is stored as ``(tail, head)``, ``-1`` where reversed, so a
        1-form integrates from ``tail`` to ``head`` as ``sign * a[e]``.
    """
    key = undirected_keys(edges[:, 0], edges[:, 1], n_vertices)
    sorter = np.argsort(key)
    q = undirected_keys(np.asarray(tail), np.asarray(head), n_vertices)
    if key.size == 0:
        return np.full(q.shape, -1, dtype=np.int64), np.ones(q.shape)
    pos = np.minimum(np.searchsorted(key, q, sorter=sorter), key.size - 1)
    e = sorter[pos].astype(np.int64)
    e = np.where(key[e] == q, e, -1)
    sign = np.where(edges[np.maximum(e, 0), 0] == tail, 1.0, -1.0)
    return e, sign


def spanning_forest(A: sp.spmatrix, roots: np.ndarray | None = None) -> np.ndarray:
    """(#V,) breadth-first spanning forest of a graph as a predecessor array.

    One tree per connected component, rooted at its smallest vertex unless ``roots`` (one per
    component) are given; ``pred[root] < 0``.  One ``csgraph.dijkstra`` call (unit weights,
    ``min_only``) for all components.
    """
    A = sp.csr_matrix(A)
    if roots is None:
        _, label = csgraph.connected_components(A, directed=False)
        roots = np.unique(label, return_index=True)[1]
    _, pred, _ = csgraph.dijkstra(
        A,
        directed=False,
        indices=np.asarray(roots),
        unweighted=True,
        min_only=True,
        return_predecessors=True,
    )
    return np.asarray(pred, dtype=np.int64)


def integrate_on_tree(pred: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Sum of ``step`` along each node's path to its root in a predecessor forest.

    The one spanning-tree integrator of the package: depths from ``zeta`` on a vertex tree
    (:mod:`.covering`), per-face offsets on a dual tree (:mod:`.embedding`), depth orders.

    Parameters
    ----------
    pred : (..., n) int
        ``pred[..., v]`` the parent of ``v``, negative at roots (scipy's ``-9999``).
        Leading dimensions are independent forests (e.g. one per source).
    step : (..., n) float
        Value carried by the arc ``pred[v] -> v`` (ignored at roots).

    Returns
    -------
    (..., n) float64
        ``phi[v] = phi[pred[v]] + step[v]``, ``phi[root] = 0``.

    Notes
    -----
    Pointer jumping: after ``r`` rounds each node holds the sum over its next ``2**r``
    ancestors, so ``O(log depth)`` vectorised passes replace a sequential walk down the tree.
    """
    pred = np.asarray(pred)
    p = np.where(pred < 0, np.arange(pred.shape[-1]), pred).astype(np.int64)
    acc = np.where(pred < 0, 0.0, np.asarray(step, dtype=np.float64))
    while True:
        pp = np.take_along_axis(p, p, axis=-1)
        if np.array_equal(pp, p):
            return acc
        acc = acc + np.take_along_axis(acc, p, axis=-1)
        p = pp


def integrate_one_form(
    edges: np.ndarray, a: np.ndarray, n_vertices: int, pred: np.ndarray | None = None
) -> np.ndarray:
    """(#V,) potential ``phi`` with ``phi[head] - phi[tail] = a[e]`` along a spanning forest.

    Exact on every edge when ``a`` is exact; otherwise the tree edges hold and the others
    carry the mismatch (the harmonic part's periods on the cotree edges).

    Parameters
    ----------
    edges : (#E, 2) int64
    a : (#E,) float64 1-form
    n_vertices : int
    pred : (#V,) int, optional
        The forest (default :func:`spanning_forest` of the edge graph); ``phi`` is 0 at roots.
    """
    if pred is None:
        A = sp.csr_matrix(
            (np.ones(edges.shape[0]), (edges[:, 0], edges[:, 1])), shape=(n_vertices, n_vertices)
        )
        pred = spanning_forest(A + A.T)
    child = np.flatnonzero(pred >= 0)
    e, sign = edge_lookup(edges, n_vertices, pred[child], child)
    if np.any(e < 0):
        raise MescherError("pred: expected a forest of the mesh's edges, found a non-edge arc")
    step = np.zeros(n_vertices)
    step[child] = sign * np.asarray(a, dtype=np.float64)[e]
    return integrate_on_tree(pred, step)


def edge_topology(
    F: np.ndarray, n_vertices: int | None = None, check: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unique edges of ``F`` and the face-to-edge incidence.

    Parameters
    ----------
    F : (#F, 3) int64
        Oriented triangles.
    n_vertices : int, optional
        Number of vertices (default ``F.max() + 1``).
    check : bool, default: True
        Raise :class:`MescherError` on non-manifold edges (more than two faces) and on
        inconsistently oriented neighbours (the two faces traverse their edge the same way).

    Returns
    -------
    edges : (#E, 2) int64
        Each edge once, ``tail < head``, sorted lexicographically.
    face_edges : (#F, 3) int64
        Edge opposite each corner.
    face_edge_signs : (#F, 3) float64
        ``+1`` where the stored edge runs along the face's boundary orientation.
    """
    n = int(F.max()) + 1 if n_vertices is None else int(n_vertices)
    tail, head = half_edges(F)
    key = _undirected_keys(tail, head, n).reshape(-1)
    # A stable argsort + run detection is ~15x faster than np.unique(return_inverse) at 3M keys.
    order = np.argsort(key, kind="stable")
    sk = key[order]
    new = np.empty(sk.shape, dtype=bool)
    new[:1] = True
    np.not_equal(sk[1:], sk[:-1], out=new[1:])
    run = np.cumsum(new) - 1
    face_edges = np.empty(key.shape, dtype=np.int64)
    face_edges[order] = run
    face_edges = face_edges.reshape(-1, 3)
    ukey = sk[new]
    edges = np.stack([ukey // n, ukey % n], axis=1)
    signs = np.where(tail < head, 1.0, -1.0)
    if check:
        counts = np.diff(np.append(np.flatnonzero(new), sk.size))
        if counts.max(initial=0) > 2:
            e = int(np.argmax(counts))
            raise MescherError(
                f"F: expected a manifold mesh (at most two faces per edge), found "
                f"{int((counts > 2).sum())} non-manifold edge(s) (first: vertices "
                f"{edges[e].tolist()} shared by {int(counts[e])} faces)"
            )
        # Coherent orientation: an interior edge's two half-edges have opposite signs.
        s = signs.reshape(-1)[order]
        pair = ~new[1:]  # sk[k+1] == sk[k]: two faces share this edge
        same = pair & (s[1:] == s[:-1])
        if same.any():
            k = int(np.flatnonzero(same)[0])
            fa, fb = order[k] // 3, order[k + 1] // 3
            raise MescherError(
                f"F: expected consistently oriented faces, found {int(same.sum())} edge(s) "
                f"traversed the same way by both faces (first: edge "
                f"{edges[run[k]].tolist()} in faces {int(fa)} and {int(fb)}); "
                "the surface may be non-orientable"
            )
    return edges, face_edges, signs


def orient_edges_like(
    edges_in: np.ndarray, edges: np.ndarray, n_vertices: int, name: str = "edges"
) -> tuple[np.ndarray, np.ndarray]:
    """Match user edges to the canonical edges of ``F``.

    Returns ``perm`` and ``flip`` such that user edge ``k`` is canonical edge ``perm[k]``,
    reversed where ``flip[k]``.  Raises when the user's set is not exactly F's edge set.
    """
    if edges_in.shape[0] != edges.shape[0]:
        raise MescherError(
            f"{name}: expected the {edges.shape[0]} edges of F, found {edges_in.shape[0]} edges"
        )
    if edges_in.min() < 0 or edges_in.max() >= n_vertices:
        raise MescherError(
            f"{name}: expected vertex indices in [0, {n_vertices}), found "
            f"{int(edges_in.min())}..{int(edges_in.max())}"
        )
    key_in = _undirected_keys(edges_in[:, 0], edges_in[:, 1], n_vertices)
    key = edges[:, 0] * np.int64(n_vertices) + edges[:, 1]  # canonical: sorted, tail < head
    perm = np.searchsorted(key, key_in)
    perm = np.minimum(perm, key.size - 1)
    bad = key[perm] != key_in
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise MescherError(
            f"{name}: expected exactly the edges of F, found {int(bad.sum())} edge(s) that are "
            f"not edges of F (first: row {k} = {edges_in[k].tolist()})"
        )
    if np.unique(perm).size != perm.size:
        raise MescherError(f"{name}: expected each edge of F once, found duplicated edges")
    if np.any(edges_in[:, 0] == edges_in[:, 1]):
        raise MescherError(f"{name}: expected two distinct endpoints per edge, found a loop")
    flip = edges_in[:, 0] > edges_in[:, 1]
    return perm, flip


def d01(edges: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """Exterior derivative on 0-forms, (#E, #V): ``(d01 u)[e] = u[head] - u[tail]``."""
    m = edges.shape[0]
    rows = np.repeat(np.arange(m), 2)
    data = np.tile([-1.0, 1.0], m)
    return sp.csr_matrix((data, (rows, edges.reshape(-1))), shape=(m, n_vertices))


def d12(face_edges: np.ndarray, face_edge_signs: np.ndarray, n_edges: int) -> sp.csr_matrix:
    """Exterior derivative on 1-forms, (#F, #E): the oriented sum around each face."""
    nf = face_edges.shape[0]
    rows = np.repeat(np.arange(nf), 3)
    return sp.csr_matrix(
        (face_edge_signs.reshape(-1), (rows, face_edges.reshape(-1))), shape=(nf, n_edges)
    )


def edge_faces(face_edges: np.ndarray, n_edges: int) -> np.ndarray:
    """(#E, 2) faces on each side of each edge, ``-1`` where there is none (boundary)."""
    ef = np.full((n_edges, 2), -1, dtype=np.int64)
    fe = face_edges.reshape(-1)
    faces = np.repeat(np.arange(face_edges.shape[0]), 3)
    order = np.argsort(fe, kind="stable")
    fe_s, f_s = fe[order], faces[order]
    first = np.ones(fe_s.size, dtype=bool)
    first[1:] = fe_s[1:] != fe_s[:-1]
    ef[fe_s[first], 0] = f_s[first]
    ef[fe_s[~first], 1] = f_s[~first]
    return ef


def boundary_edge_mask(face_edges: np.ndarray, n_edges: int) -> np.ndarray:
    """(#E,) True for edges with a single incident face."""
    return np.bincount(face_edges.reshape(-1), minlength=n_edges) == 1


def boundary_loops(F: np.ndarray) -> list[np.ndarray]:
    """Boundary loops of an oriented manifold mesh, each an int64 vertex array in order.

    Loops follow the faces' orientation (the boundary half-edges' direction).
    """
    tail, head = half_edges(F)
    n = int(F.max()) + 1
    key = _undirected_keys(tail, head, n).reshape(-1)
    uniq, counts = np.unique(key, return_counts=True)
    single = np.isin(key, uniq[counts == 1])
    t, h = tail.reshape(-1)[single], head.reshape(-1)[single]
    if t.size == 0:
        return []
    # successor map along boundary half-edges (manifold boundary: one outgoing per vertex);
    # walking the loops is linear in the boundary length, which is tiny next to #F.
    nxt = dict(zip(t.tolist(), h.tolist()))
    loops, seen = [], set()
    for start in t.tolist():
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = nxt.get(v, start)
        loops.append(np.asarray(loop, dtype=np.int64))
    return loops


def connected_components(F: np.ndarray, n_vertices: int) -> tuple[int, np.ndarray]:
    """Number of vertex-connected components and a (#V,) label per vertex."""
    rows = F[:, [0, 1, 2]].reshape(-1)
    cols = F[:, [1, 2, 0]].reshape(-1)
    A = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n_vertices, n_vertices))
    return csgraph.connected_components(A, directed=False)


def euler_characteristic(n_vertices: int, n_edges: int, n_faces: int) -> int:
    """``V - E + F``."""
    return int(n_vertices - n_edges + n_faces)


def tree_cotree(
    edges: np.ndarray,
    face_edges: np.ndarray,
    n_vertices: int,
    edge_weights: np.ndarray | None = None,
) -> np.ndarray:
    """Indices of the edges generating first homology (Eppstein's tree-cotree).

    A spanning forest ``T`` of the primal graph and a spanning forest ``C`` of the dual graph
    avoiding ``T``; every edge in neither closes one homology generator.  With boundary, the dual
    forest treats the outside as one extra dual vertex per boundary-free component... here simply
    as a single "infinite" dual node, so boundary loops (all but one per component) become
    generators too, as in relative-to-nothing homology of a surface with boundary.

    Parameters
    ----------
    edges : (#E, 2) int64
    face_edges : (#F, 3) int64
    n_vertices : int
    edge_weights : (#E,) float64, optional
        Primal tree is a shortest-path tree by these weights (shorter generators), default unit.

    Returns
    -------
    (k,) int64 edge indices, ``k = 2g + b - c`` summed over components (``b`` boundary loops).
    """
    ne = edges.shape[0]
    nf = face_edges.shape[0]
    w = np.ones(ne) if edge_weights is None else np.asarray(edge_weights, dtype=float)
    w = np.maximum(w, 1e-300)
    # Primal spanning forest: minimum spanning tree keeps generators short and is libigl-free
    # vectorised scipy (csgraph) work.
    A = sp.csr_matrix((w, (edges[:, 0], edges[:, 1])), shape=(n_vertices, n_vertices))
    T = csgraph.minimum_spanning_tree(A).tocoo()
    key = _undirected_keys(edges[:, 0], edges[:, 1], n_vertices)  # any stored orientation
    tkey = np.minimum(T.row, T.col).astype(np.int64) * n_vertices + np.maximum(T.row, T.col)
    in_tree = np.isin(key, tkey)
    # Dual graph over faces (+ one node for "outside" joined to boundary edges), edges not in T.
    ef = edge_faces(face_edges, ne)
    outside = nf
    a = ef[:, 0]
    b = np.where(ef[:, 1] < 0, outside, ef[:, 1])
    cand = ~in_tree
    # Weight dual edges by 1/(1+w) so longer primal edges are preferred in the cotree; any
    # spanning forest is correct, this only shapes which loops come out.
    dw = 1.0 / (1.0 + w[cand])
    D = sp.csr_matrix((dw, (a[cand], b[cand])), shape=(nf + 1, nf + 1))
    C = csgraph.minimum_spanning_tree(D + D.T).tocoo()
    # Recover which candidate edges the dual MST used (match by endpoints; at most one edge
    # joins two faces in a manifold mesh, boundary edges to "outside" can repeat, any one is fine).
    ca, cb = np.minimum(C.row, C.col), np.maximum(C.row, C.col)
    ckey = ca.astype(np.int64) * (nf + 1) + cb
    idx = np.flatnonzero(cand)
    ea, eb = np.minimum(a[idx], b[idx]), np.maximum(a[idx], b[idx])
    ekey = ea.astype(np.int64) * (nf + 1) + eb
    order = np.argsort(ekey, kind="stable")
    pos = np.searchsorted(ekey[order], ckey)
    in_cotree = np.zeros(ne, dtype=bool)
    in_cotree[idx[order[pos]]] = True
    return np.flatnonzero(~in_tree & ~in_cotree)


def generator_loops(
    edges: np.ndarray,
    face_edges: np.ndarray,
    n_vertices: int,
    edge_weights: np.ndarray | None = None,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Homology generators as closed edge loops.

    Each generator edge ``(u, v)`` closed through the primal spanning tree gives the loop
    ``u -> v -> (tree path) -> u``.

    Returns
    -------
    list of ``(edge_indices (k,), signs (k,))``; the loop integral of a 1-form ``a`` is
    ``signs @ a[edge_indices]``.
    """
    ne = edges.shape[0]
    w = np.ones(ne) if edge_weights is None else np.asarray(edge_weights, dtype=float)
    w = np.maximum(w, 1e-300)
    A = sp.csr_matrix((w, (edges[:, 0], edges[:, 1])), shape=(n_vertices, n_vertices))
    gens = tree_cotree(edges, face_edges, n_vertices, edge_weights)
    if gens.size == 0:
        return []
    Tm = csgraph.minimum_spanning_tree(A)
    Tsym = (Tm + Tm.T).tocsr()
    key = _undirected_keys(edges[:, 0], edges[:, 1], n_vertices)
    sorter = np.argsort(key)  # user edges may come in any order and orientation
    # Root each tree component and record parents (one scipy BFS per connected component).
    ncomp, labels = csgraph.connected_components(Tsym, directed=False)
    parent = np.full(n_vertices, -1, dtype=np.int64)
    for c in range(ncomp):  # loop over components, not faces or edges
        root = int(np.flatnonzero(labels == c)[0])
        order, pred = csgraph.breadth_first_order(Tsym, root, directed=False)
        parent[order[1:]] = pred[order[1:]]

    def path_to_root(v: int) -> list[int]:
        out = [v]
        while parent[out[-1]] >= 0:
            out.append(int(parent[out[-1]]))
        return out

    loops = []
    for g in gens.tolist():  # one loop per generator: O(k * tree depth)
        u, v = int(edges[g, 0]), int(edges[g, 1])
        pu, pv = path_to_root(u), path_to_root(v)
        on_u = {x: i for i, x in enumerate(pu)}
        iv = next(i for i, x in enumerate(pv) if x in on_u)
        iu = on_u[pv[iv]]
        # u -> v along the generator, v up to the common ancestor, back down to u
        verts = np.asarray([u] + pv[: iv + 1] + pu[:iu][::-1], dtype=np.int64)
        t, h = verts[:-1], verts[1:]
        k = np.minimum(t, h) * np.int64(n_vertices) + np.maximum(t, h)
        eidx = sorter[np.searchsorted(key, k, sorter=sorter)]
        loops.append((eidx.astype(np.int64), np.where(edges[eidx, 0] == t, 1.0, -1.0)))
    return loops
