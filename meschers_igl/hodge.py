"""Projection onto locally integrable 1-forms, Hodge decomposition, harmonic basis, periods.

A mescher's relative depth ``zeta`` is a closed 1-form (``d12 zeta = 0``, paper Eq. 2), so its
Hodge decomposition has no co-exact part (paper Eq. 3)::

    zeta = d01 z + omega,     d12 omega = 0,     d01^T star1 omega = 0.

``omega`` is harmonic; it is zero exactly when the mescher embeds in 3D.  Its integrals around
a homology basis (the *periods*) are the depth gained going once around each loop.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .errors import MescherError
from .solvers import factorize_spd


def _pinned_factor(A: sp.spmatrix, pins: np.ndarray):
    """Factor a PSD matrix whose kernel is spanned by per-component indicator vectors.

    Rows/columns ``pins`` (one per kernel vector) are removed, which makes the rest SPD; the
    returned solver gives the solution with ``x[pins] = 0`` of a *consistent* system.
    """
    n = A.shape[0]
    keep = np.ones(n, dtype=bool)
    keep[pins] = False
    idx = np.flatnonzero(keep)
    A = sp.csr_matrix(A)
    sub = A[idx][:, idx]
    solve = factorize_spd(sp.csc_matrix(sub)) if idx.size else None

    def apply(b: np.ndarray) -> np.ndarray:
        x = np.zeros(b.shape, dtype=np.float64)
        if solve is not None:
            x[idx] = solve(np.ascontiguousarray(b[idx]))
        return x

    return apply


def closed_projector(d12: sp.spmatrix):
    """The least-squares projection onto ``ker d12`` with unit ``star1`` (paper Eq. 3-4).

    Solves the KKT system ``[I d12^T; d12 0] [zeta; lam] = [zeta'; 0]`` through its Schur
    complement ``(d12 d12^T) lam = d12 zeta'``, ``zeta = zeta' - d12^T lam``.  ``d12 d12^T`` is
    singular on closed components (the sum of all oriented face boundaries is zero); one face
    per closed component is pinned, which is exact because the right-hand side is orthogonal
    to that kernel.

    Returns a function ``zeta' -> zeta`` (accepting (#E,) or (#E, k)).
    """
    D = sp.csr_matrix(d12)
    S = (D @ D.T).tocsr()
    nf = D.shape[0]
    # Faces adjacent through interior edges form the components of the dual graph.
    adj = (abs(D) @ abs(D).T).tocsr()
    ncomp, labels = csgraph.connected_components(adj, directed=False)
    # A component is closed when every edge of it has two faces.
    edge_deg = np.asarray(abs(D).sum(axis=0)).ravel()
    face_has_bd = np.asarray(abs(D) @ (edge_deg == 1).astype(float)).ravel() > 0
    comp_has_bd = np.bincount(labels, weights=face_has_bd.astype(float), minlength=ncomp) > 0
    first = np.full(ncomp, -1, dtype=np.int64)
    first[labels[::-1]] = np.arange(nf)[::-1]
    pins = first[~comp_has_bd]
    solve = _pinned_factor(S, pins)

    def project(zeta: np.ndarray) -> np.ndarray:
        return zeta - D.T @ solve(D @ zeta)

    return project


@dataclass(frozen=True)
class HodgeDecomposition:
    """``zeta = d01 @ z + omega`` with ``omega`` harmonic.

    Attributes
    ----------
    z : (#V,) float64
        Depth potential of the exact part, zero mean (mass-weighted) on each component.
    omega : (#E,) float64
        Harmonic part: closed and co-closed.
    """

    z: np.ndarray
    omega: np.ndarray


class ExactPartSolver:
    """Factor ``d01^T star1 d01`` (= ``-cotmatrix``) once; split 1-forms into exact + rest.

    The co-closed remainder of a closed form is its harmonic part.
    """

    def __init__(self, d01: sp.spmatrix, star1: np.ndarray, n_vertices: int, F: np.ndarray):
        self.d01 = sp.csr_matrix(d01)
        self.star1 = star1
        W = sp.diags(star1)
        self.K = (self.d01.T @ W @ self.d01).tocsr()
        rows = F[:, [0, 1, 2]].reshape(-1)
        cols = F[:, [1, 2, 0]].reshape(-1)
        A = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n_vertices, n_vertices))
        ncomp, labels = csgraph.connected_components(A, directed=False)
        first = np.full(ncomp, -1, dtype=np.int64)
        first[labels[::-1]] = np.arange(n_vertices)[::-1]
        self.labels, self.ncomp = labels, ncomp
        self._solve = _pinned_factor(self.K, first)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``x`` with ``K x = b`` and ``x = 0`` at the pinned vertices (first of each component).

        ``b`` (#V,) or (#V, k) must be consistent (zero sum on each component), as a divergence
        is; the heat method's Poisson step reuses this factorization.
        """
        return self._solve(np.asarray(b, dtype=np.float64))

    def potential(self, a: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
        """``z`` minimising ``|| d01 z - a ||_star1``, zero (weighted) mean per component."""
        rhs = self.d01.T @ (self.star1[:, None] * a if a.ndim == 2 else self.star1 * a)
        z = self._solve(rhs)
        w = np.ones(z.shape[0]) if weights is None else weights
        wsum = np.bincount(self.labels, weights=w, minlength=self.ncomp)
        if z.ndim == 1:
            mean = np.bincount(self.labels, weights=w * z, minlength=self.ncomp) / wsum
            return z - mean[self.labels]
        for k in range(z.shape[1]):  # columns, not mesh elements
            mean = np.bincount(self.labels, weights=w * z[:, k], minlength=self.ncomp) / wsum
            z[:, k] -= mean[self.labels]
        return z


def loop_matrix(loops: list[tuple[np.ndarray, np.ndarray]], n_edges: int) -> sp.csr_matrix:
    """(k, #E) signed incidence of k closed edge loops: ``(Gamma @ a)[i]`` integrates ``a``."""
    if not loops:
        return sp.csr_matrix((0, n_edges))
    rows = np.concatenate([np.full(e.size, i) for i, (e, _) in enumerate(loops)])
    cols = np.concatenate([e for e, _ in loops])
    data = np.concatenate([s for _, s in loops])
    return sp.csr_matrix((data, (rows, cols)), shape=(len(loops), n_edges))


def harmonic_basis(
    project_closed, exact: ExactPartSolver, Gamma: sp.csr_matrix, seed: int = 0
) -> np.ndarray:
    """(#E, k) harmonic 1-forms dual to the loops: ``Gamma @ H = I``.

    Harmonic projection ``r -> closed(r) - d01 z(closed(r))`` maps onto the k-dimensional
    harmonic space and fixes it, so k random forms (seeded) give a basis with probability one;
    the period matrix then makes it dual to the homology loops.
    """
    k = Gamma.shape[0]
    ne = Gamma.shape[1]
    if k == 0:
        return np.zeros((ne, 0))
    rng = np.random.default_rng(seed)
    R = rng.standard_normal((ne, k))
    C = project_closed(R)
    C = project_closed(C)  # one step of iterative refinement: d12 C drops to round-off
    H = C - exact.d01 @ exact.potential(C)
    P = np.asarray(Gamma @ H)
    cond = np.linalg.cond(P)
    if not np.isfinite(cond) or cond > 1e10:
        raise MescherError(
            "harmonic basis: the homology loops and harmonic forms are degenerate "
            f"(period matrix condition number {cond:.3g}); the mesh may be badly shaped"
        )
    return H @ np.linalg.inv(P)
