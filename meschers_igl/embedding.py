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

from . import topology as topo
from .errors import MescherError
from .validate import as_index_array


def bent_embedding(m) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)``: the mescher with its harmonic part removed, embedded in 3D."""
    z = np.asarray(m.hodge().z)
    return np.column_stack([m.xy, z]), np.array(m.F)


def cut_embedding(m, cut_edges=None, tol: float | None = None):
    """Integrate ``zeta`` on the mescher cut open.

    Faces are integrated breadth-first across a spanning forest of the dual graph; every other
    interior edge is glued back when both sides agree on the depths of its endpoints.  With the
    default ``cut_edges=None`` the cut is exactly the set of edges where they disagree -- a
    seam across every loop with a non-zero period, on closed surfaces and on surfaces with
    boundary alike (a ring is cut across, from boundary to boundary).

    Parameters
    ----------
    m : Mescher
    cut_edges : (k,) int, optional
        Edge indices to cut along instead; it is an error if they leave an impossible loop
        uncut (depths would disagree across an uncut edge).
    tol : float, optional
        Depth agreement tolerance (default ``1e-9 * m.scale()``).

    Returns
    -------
    V : (#Vc, 3) float64
        Cut-model vertices (x, y, depth).
    F : (#F, 3) int64
        Faces (face i is the mescher's face i).
    vmap : (#Vc,) int64
        Mescher vertex of each cut-model vertex.
    """
    ne, nf = m.n_edges, m.n_faces
    user_cut = np.zeros(ne, dtype=bool)
    if cut_edges is not None and np.size(cut_edges):
        user_cut[as_index_array(cut_edges, "cut_edges", ne)] = True
    tol = 1e-9 * m.scale() if tol is None else float(tol)
    ef = topo.edge_faces(np.asarray(m.face_edges), ne)
    F = np.asarray(m.F)
    Z = np.asarray(m.corner_depths())
    inner = np.flatnonzero((ef[:, 1] >= 0) & ~user_cut)
    a, b = ef[inner, 0], ef[inner, 1]
    tail, head = m.edges[inner, 0], m.edges[inner, 1]
    ia = np.argmax(F[a] == tail[:, None], axis=1)
    ib = np.argmax(F[b] == tail[:, None], axis=1)
    ja = np.argmax(F[a] == head[:, None], axis=1)
    jb = np.argmax(F[b] == head[:, None], axis=1)
    # Spanning forest over faces through the uncut edges; offsets o (one per face) summed
    # down the tree: o[child] - o[parent] = depth jump across the shared edge.
    A = sp.csr_matrix((np.arange(1, a.size + 1, dtype=float), (a, b)), shape=(nf, nf))
    A = (A + A.T).tocsr()
    pred = topo.spanning_forest(A)
    child = np.flatnonzero(pred >= 0)
    par = pred[child]
    eid = np.asarray(A[child, par]).ravel().astype(np.int64) - 1  # index into (a, b)
    za, zb = Z[a, ia], Z[b, ib]
    delta = np.zeros(nf)
    delta[child] = np.where(a[eid] == par, za[eid] - zb[eid], zb[eid] - za[eid])
    o = topo.integrate_on_tree(pred, delta)
    Zg = Z + o[:, None]
    # Glue back every uncut edge whose two sides agree at both endpoints.
    mismatch = np.maximum(np.abs(Zg[a, ia] - Zg[b, ib]), np.abs(Zg[a, ja] - Zg[b, jb]))
    agree = mismatch <= tol
    if cut_edges is not None and not agree.all():
        raise MescherError(
            "cut_edges: expected a cut that opens every impossible loop, found "
            f"{int((~agree).sum())} uncut edge(s) whose sides disagree in depth by up to "
            f"{mismatch.max():.3g} (first: edge {int(inner[np.argmax(~agree)])}); "
            "pass cut_edges=None for an automatic cut"
        )
    g = agree
    ca = np.concatenate([3 * a[g] + ia[g], 3 * a[g] + ja[g]])
    cb = np.concatenate([3 * b[g] + ib[g], 3 * b[g] + jb[g]])
    C = sp.csr_matrix((np.ones(ca.size), (ca, cb)), shape=(3 * nf, 3 * nf))
    nv, lab = csgraph.connected_components(C, directed=False)
    vmap = np.zeros(nv, dtype=np.int64)
    vmap[lab] = F.reshape(-1)
    depth = np.zeros(nv)
    depth[lab] = Zg.reshape(-1)
    spread = np.abs(Zg.reshape(-1) - depth[lab])
    if spread.max(initial=0.0) > tol:  # tolerance drift along a chain of glued corners
        raise MescherError(
            f"cut_embedding: corners of one vertex disagree in depth by {spread.max():.3g} "
            f"after gluing (tol {tol:.3g}); pass a larger tol"
        )
    V = np.column_stack([np.asarray(m.xy)[vmap], depth])
    return V, lab.reshape(-1, 3).astype(np.int64), vmap
