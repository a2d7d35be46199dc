"""Subdivision of meschers (paper Sec. 4.2): midpoint split of 1-forms, Loop for 0-forms.

One level splits every face in four (libigl ``upsample``'s face pattern: children of face ``f``
are ``4f .. 4f+3``).  New vertex ``#V + e`` sits on the midpoint of parent edge ``e``, so original
vertices keep their indices.

* ``"midpoint"``: xy at midpoints; every child edge is parallel to a parent edge at half its
  length, so its relative depth is half the parent's (the orthographic camera makes depth linear
  along an edge).  Values are halved *exactly*, so local integrability and the periods are kept
  bit for bit.
* ``"loop"``: xy and the exact part ``z`` of ``zeta`` (``zeta = d01 z + omega``) are Loop-smoothed
  with ``igl.loop_matrix``; the harmonic part ``omega`` is midpoint-subdivided as a 1-form, which
  keeps it closed and keeps its periods.
"""

from __future__ import annotations

from dataclasses import dataclass

import igl
import numpy as np
import scipy.sparse as sp

from . import topology as topo
from .errors import MescherError

#: child face pattern in terms of parent corners a, b, c (0, 1, 2) and edge midpoints
#: m_a (opposite a), m_b, m_c -- encoded as 0..2 for corners, 3..5 for m_a, m_b, m_c.
_CHILDREN = np.array(
    [
        [0, 5, 4],  # a, m_ab(=m_c), m_ca(=m_b)
        [1, 3, 5],  # b, m_bc(=m_a), m_ab
        [5, 3, 4],  # m_ab, m_bc, m_ca
        [3, 2, 4],  # m_bc, c, m_ca
    ]
)
#: For each child face and each of its corners i, the half-edge opposite i (child corner
#: i+1 -> i+2) is parallel to a parent half-edge: (parent corner opposite that edge, factor).
#: The child half-edge value is factor * 1/2 * parent half-edge value (parent half-edge
#: opposite corner j runs j+1 -> j+2).
_HALF_EDGE_MAP = np.array(
    [
        # child 0 [a, m_ab, m_ca]: m_ab->m_ca = 1/2 (b->c); m_ca->a = 1/2 (c->a); a->m_ab = 1/2 (a->b)
        [[0, 1], [1, 1], [2, 1]],
        # child 1 [b, m_bc, m_ab]: m_bc->m_ab = 1/2 (c->a); m_ab->b = 1/2 (a->b); b->m_bc = 1/2 (b->c)
        [[1, 1], [2, 1], [0, 1]],
        # child 2 [m_ab, m_bc, m_ca]: m_bc->m_ca = -1/2 (a->b); m_ca->m_ab = -1/2 (b->c);
        #                             m_ab->m_bc = -1/2 (c->a)
        [[2, -1], [0, -1], [1, -1]],
        # child 3 [m_bc, c, m_ca]: c->m_ca = 1/2 (c->a); m_ca->m_bc = 1/2 (a->b); m_bc->c = 1/2 (b->c)
        [[1, 1], [2, 1], [0, 1]],
    ]
)


@dataclass(frozen=True)
class SubdivisionStep:
    """One level of 1-to-4 refinement of a mesh's connectivity.

    Attributes
    ----------
    F : (4 #F, 3) int64 child faces
    face_parent : (4 #F,) int64 parent of each child face
    S_mid : (#V + #E, #V) midpoint subdivision matrix for 0-forms
    """

    F: np.ndarray
    face_parent: np.ndarray
    S_mid: sp.csr_matrix


def refine_connectivity(F: np.ndarray, edges: np.ndarray, face_edges: np.ndarray, n_vertices: int):
    """Child faces and the 0-form midpoint matrix for one level (vectorised)."""
    nf = F.shape[0]
    ne = edges.shape[0]
    corners = np.concatenate([F, n_vertices + face_edges], axis=1)  # (#F, 6)
    Fc = corners[:, _CHILDREN].reshape(-1, 3)  # children 4f..4f+3
    parent = np.repeat(np.arange(nf), 4)
    rows = np.concatenate([np.arange(n_vertices), np.repeat(n_vertices + np.arange(ne), 2)])
    cols = np.concatenate([np.arange(n_vertices), edges.reshape(-1)])
    vals = np.concatenate([np.ones(n_vertices), np.full(2 * ne, 0.5)])
    S = sp.csr_matrix((vals, (rows, cols)), shape=(n_vertices + ne, n_vertices))
    return SubdivisionStep(Fc, parent, S)


def subdivide_one_form(a: np.ndarray, face_edges, signs, Fc, n_child_vertices):
    """Midpoint subdivision of a closed 1-form; returns (child edges, incidence, child form).

    Each child half-edge gets exactly ``+-1/2`` of its parallel parent half-edge, so closed
    forms stay closed and loop integrals are unchanged (each parent edge is split in two halves).
    """
    h = signs * a[face_edges]  # parent half-edge values, opposite each corner (#F, 3)
    nf = h.shape[0]
    src = _HALF_EDGE_MAP[:, :, 0]
    fac = _HALF_EDGE_MAP[:, :, 1].astype(float)
    hc = 0.5 * fac[None] * h[:, src]  # (#F, 4 children, 3)
    hc = hc.reshape(4 * nf, 3)
    edges_c, fe_c, s_c = topo.edge_topology(Fc, n_child_vertices, check=False)
    # each child edge takes the value of one of its half-edges (both agree exactly)
    vals = np.empty(edges_c.shape[0])
    vals[fe_c.reshape(-1)] = (hc * s_c).reshape(-1)
    return edges_c, fe_c, s_c, vals


def loop_matrix_on(F: np.ndarray, edges: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """Loop's 0-form subdivision matrix with rows in this module's vertex numbering.

    ``igl.loop_matrix`` numbers the new (odd) vertices by libigl's own edge order; its
    ``upsample_matrix`` rows have the same numbering and name each odd vertex's edge, which
    lets us permute the rows to ``#V + e``.
    """
    S_loop, _ = igl.loop_matrix(F, n_vertices)
    S_up, _ = igl.upsample_matrix(F, n_vertices)
    S_loop, S_up = sp.csr_matrix(S_loop), sp.csr_matrix(S_up)
    ne = edges.shape[0]
    odd = S_up[n_vertices:].tocoo()
    # each odd row of the upsample matrix has exactly its edge's two endpoints
    order = np.lexsort((odd.col, odd.row))
    ends = odd.col[order].reshape(-1, 2)
    key_igl = ends.min(axis=1) * np.int64(n_vertices) + ends.max(axis=1)
    key_ours = edges.min(axis=1) * np.int64(n_vertices) + edges.max(axis=1)
    sorter = np.argsort(key_igl)
    pos = sorter[np.searchsorted(key_igl, key_ours, sorter=sorter)]
    if not np.array_equal(key_igl[pos], key_ours) or ne != key_igl.size:
        raise MescherError("F: libigl's Loop matrix does not match the mesh's edges")
    perm = np.concatenate([np.arange(n_vertices), n_vertices + pos])
    return S_loop[perm]


def refine_loops(loops, edges, edges_child, n_vertices):
    """Images of edge loops under one subdivision level: each parent edge becomes two halves.

    Keeping the parent's homology generators makes ``periods()`` of the child equal the
    parent's entry by entry (midpoint halves sum exactly).
    """
    nvc = int(edges_child.max()) + 1
    key_c = edges_child[:, 0] * np.int64(nvc) + edges_child[:, 1]
    out = []
    for e, s in loops:  # one vectorised step per generator loop
        t, h = edges[e, 0], edges[e, 1]
        a = np.where(s > 0, t, h)
        b = np.where(s > 0, h, t)
        mid = n_vertices + e
        ka = np.minimum(a, mid) * np.int64(nvc) + np.maximum(a, mid)
        kb = np.minimum(b, mid) * np.int64(nvc) + np.maximum(b, mid)
        ia, ib = np.searchsorted(key_c, ka), np.searchsorted(key_c, kb)
        ec = np.stack([ia, ib], axis=1).reshape(-1)
        sc = np.stack([np.where(a < mid, 1.0, -1.0), np.where(mid < b, 1.0, -1.0)], axis=1)
        out.append((ec.astype(np.int64), sc.reshape(-1)))
    return out
