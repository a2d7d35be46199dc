"""Conversions to the two 3D representations earlier work used (paper Sec. 4.6).

* **bent**: drop the harmonic part and integrate: ``V = (x, y, z)`` with ``z`` from the Hodge
  decomposition.  Local depth differences equal the exact part ``d01 z``.
* **cut**: cut the surface open along edges that meet every impossible loop, integrate ``zeta``
  across the remaining edges (breadth-first over faces), and duplicate vertices whose corners
  disagree.  Depth differences equal ``zeta`` on every edge; across the cut the jump equals the
  period of the loop it cuts.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as sla

from . import topology as topo
from .errors import MescherError
from .validate import as_index_array


def bent_embedding(m) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)``: the mescher with its harmonic part removed, embedded in 3D."""
    z = np.asarray(m.hodge().z)
    return np.column_stack([m.xy, z]), np.array(m.F)


def default_cut(m) -> np.ndarray:
    """Edges of the homology generator loops (a cut that makes every loop contractible)."""
    gens = m.homology_generators()
    if not gens:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate([e for e, _ in gens]))


def cut_embedding(m, cut_edges=None, tol: float | None = None):
    """Integrate ``zeta`` on the mescher cut open along ``cut_edges``.

    Parameters
    ----------
    m : Mescher
    cut_edges : (k,) int, optional
        Edge indices to cut along; default: the homology generators' edges.
    tol : float, optional
        Corners of one vertex whose depths differ by more than this are split apart
        (default ``1e-9 * m.scale()``).

    Returns
    -------
    V : (#Vc, 3) float64
        Cut-model vertices (x, y, depth).
    F : (#F, 3) int64
        Faces (face i is the mescher's face i).
    vmap : (#Vc,) int64
        Mescher vertex of each cut-model vertex.

    Raises
    ------
    MescherError
        If ``cut_edges`` leave an impossible loop uncut (depths would disagree inside a piece).
    """
    ne, nf = m.n_edges, m.n_faces
    cut = np.zeros(ne, dtype=bool)
    if cut_edges is None:
        cut[default_cut(m)] = True
    elif np.size(cut_edges):
        cut[as_index_array(cut_edges, "cut_edges", ne)] = True
    tol = 1e-9 * m.scale() if tol is None else float(tol)
    ef = topo.edge_faces(np.asarray(m.face_edges), ne)
    inner = (ef[:, 1] >= 0) & ~cut
    a, b = ef[inner, 0], ef[inner, 1]
    Z = np.asarray(m.corner_depths())
    F = np.asarray(m.F)
    # Depth offset between the two faces of an inner edge: both must agree at the edge's tail.
    e_in = np.flatnonzero(inner)
    tail = m.edges[e_in, 0]
    za = Z[a, np.argmax(F[a] == tail[:, None], axis=1)]
    zb = Z[b, np.argmax(F[b] == tail[:, None], axis=1)]
    # Spanning forest over faces through uncut edges, then offsets by one triangular solve in
    # BFS order: o[child] - o[parent] = za - zb (a sequential recurrence done by sparse algebra).
    A = sp.csr_matrix((np.arange(1, a.size + 1, dtype=float), (a, b)), shape=(nf, nf))
    A = A + A.T
    ncomp, labels = csgraph.connected_components(A, directed=False)
    offset_rows, offset_cols, delta = [], [], np.zeros(nf)
    order_all = []
    for c in range(ncomp):  # components of the cut surface, not faces
        root = int(np.flatnonzero(labels == c)[0])
        order, pred = csgraph.breadth_first_order(A, root, directed=False)
        order_all.append(order)
        child, par = order[1:], pred[order[1:]]
        eid = np.asarray(A[child, par]).ravel().astype(np.int64) - 1  # index into (a, b)
        # o_child = o_par + (depth of shared tail in par) - (depth in child)
        d = np.where(a[eid] == par, za[eid] - zb[eid], zb[eid] - za[eid])
        offset_rows.append(child)
        offset_cols.append(par)
        delta[child] = d
    rows = np.concatenate(offset_rows) if offset_rows else np.zeros(0, np.int64)
    cols = np.concatenate(offset_cols) if offset_cols else np.zeros(0, np.int64)
    perm = np.concatenate(order_all)
    pos = np.empty(nf, dtype=np.int64)
    pos[perm] = np.arange(nf)
    T = sp.csr_matrix(
        (np.concatenate([np.ones(nf), -np.ones(rows.size)]),
         (np.concatenate([pos, pos[rows]]), np.concatenate([pos, pos[cols]]))),
        shape=(nf, nf),
    )  # fmt: skip
    o = np.empty(nf)
    o[perm] = sla.spsolve_triangular(T, delta[perm], lower=True)
    Zg = Z + o[:, None]
    # Corners glued across uncut inner edges become one cut-model vertex.
    ia = np.argmax(F[a] == tail[:, None], axis=1)
    ib = np.argmax(F[b] == tail[:, None], axis=1)
    head = m.edges[e_in, 1]
    ja = np.argmax(F[a] == head[:, None], axis=1)
    jb = np.argmax(F[b] == head[:, None], axis=1)
    ca = np.concatenate([3 * a + ia, 3 * a + ja])
    cb = np.concatenate([3 * b + ib, 3 * b + jb])
    C = sp.csr_matrix((np.ones(ca.size), (ca, cb)), shape=(3 * nf, 3 * nf))
    nv, lab = csgraph.connected_components(C, directed=False)
    vmap = np.zeros(nv, dtype=np.int64)
    vmap[lab] = F.reshape(-1)
    depth = np.zeros(nv)
    depth[lab] = Zg.reshape(-1)
    spread = np.abs(Zg.reshape(-1) - depth[lab])
    if spread.max(initial=0.0) > tol:
        raise MescherError(
            "cut_edges: expected a cut that opens every impossible loop, found corners of one "
            f"vertex whose integrated depths differ by {spread.max():.3g}; add the generator "
            "edges (default cut) to cut_edges"
        )
    V = np.column_stack([np.asarray(m.xy)[vmap], depth])
    return V, lab.reshape(-1, 3).astype(np.int64), vmap
