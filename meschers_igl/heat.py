"""Heat diffusion, heat-method geodesic distances and shortest paths on meschers.

A mescher has a discrete metric (per-edge lengths, DESIGN.md), so intrinsic processing works on it
although it cannot be embedded: paper Section 4.3.  Everything here is intrinsic and needs only

* the 0-form operators ``L = m.cotmatrix()`` (negative semi-definite, libigl's convention),
  ``M = m.massmatrix()``, the per-face gradient ``G = m.grad()`` and face areas ``A``, or
* the per-face edge lengths ``l = m.face_edge_lengths()`` (libigl: column ``i`` opposite corner
  ``i``), from which the same operators are rebuilt on a refined or intrinsic-Delaunay
  triangulation of the same piecewise-flat surface.

The heat method (Crane, Weischedel, Wardetzky 2013; "The heat method for distance computation",
CACM 2017) in this module's sign conventions:

1. heat: ``(M - t L) u = M delta_sources`` (paper Eq. 5 with ``u0`` the sources' indicator);
2. unit field: ``X = -G u / |G u|`` per face (points away from the sources);
3. Poisson: ``-L d = G^T A X`` (``G^T A G = -L``), with one vertex per connected component
   pinned so that the matrix is positive definite; then ``d`` is shifted per component so that
   ``min(d[sources]) = 0``; components without a source get ``inf``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from . import topology
from .errors import MescherError
from .solvers import factorize_spd
from .validate import as_choice, as_index_array, as_positive

__all__ = [
    "HeatGeodesicSolver",
    "SurfacePath",
    "geodesic_distance",
    "heat_diffuse",
    "shortest_path",
]

#: source sets up to this size are held at one common value in the Poisson step (k solves)
#: relative heat below which the gradient direction is not trusted (see _far_gradient)
_FAR_RATIO = 1e-290
_MAX_PINNED_SOURCES = 256
_BOUNDARY = ("neumann", "dirichlet", "average")
_METHODS = ("standard", "accurate")
# "accurate" preset: two levels of midpoint refinement, intrinsic Delaunay, t = h^2 on the
# refined mesh.  Mean relative error on the 48 x 16 impossible torus (4 sources, against the
# covering oracle): standard 4.6%; refine=1: 2.6% (t = h^2), 2.2% (t = h^2 / 2); refine=2: 1.5%;
# refine=2 + iDT: 1.5%; smaller t_factor (0.1-0.25) is worse near the sources.
_ACCURATE = {"refine": 2, "intrinsic_delaunay": True, "t_factor": 1.0}


# ----------------------------------------------------------------------------------------------
# heat diffusion (paper Eq. 5)
# ----------------------------------------------------------------------------------------------
def heat_diffuse(m: Any, u0: Any, t: float, steps: int = 1) -> np.ndarray:
    """Diffuse ``u0`` by backward Euler steps of the heat equation (paper Eq. 5).

    Solves ``(M - t L) u_{k+1} = M u_k`` ``steps`` times, with ``L = m.cotmatrix()`` (negative
    semi-definite) and ``M = m.massmatrix()`` (Voronoi).  This is the mass-weighted form of the
    paper's ``(I + t Delta) u = u0`` with ``Delta = -M^-1 L``; it keeps the total heat
    ``1^T M u`` exactly (``1^T L = 0``).

    Parameters
    ----------
    m : Mescher
    u0 : (#V,) or (#V, k) array_like
        Initial values (several columns are diffused together).
    t : float
        Time step, > 0 (units of length squared).
    steps : int, default: 1
        Number of backward Euler steps (total time ``steps * t``).

    Returns
    -------
    u : (#V,) or (#V, k) float64
    """
    n = m.n_vertices
    u = np.asarray(u0, dtype=np.float64)
    if u.ndim not in (1, 2) or u.shape[0] != n or not np.all(np.isfinite(u)):
        raise MescherError(
            f"u0: expected a finite array of shape ({n},) or ({n}, k), found {u.shape}"
        )
    t = as_positive(t, "t")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise MescherError(f"steps: expected an integer >= 1, found {steps!r}")
    M = m.massmatrix()
    A = _regularize_unused(M - t * m.cotmatrix(), m.F, n)
    solve = factorize_spd(A)
    for _ in range(int(steps)):
        u = solve(M @ u)
    return u


# ----------------------------------------------------------------------------------------------
# intrinsic triangulations: (l, F) helpers, all vectorized
# ----------------------------------------------------------------------------------------------
def _regularize_unused(A: sp.spmatrix, F: np.ndarray, n: int) -> sp.csr_matrix:
    """Put 1 on the diagonal of vertices that no face uses (their rows are empty)."""
    unused = np.ones(n, dtype=bool)
    unused[F.reshape(-1)] = False
    if unused.any():
        A = A + sp.diags(unused.astype(np.float64))
    return sp.csr_matrix(A)


def _layout(l: np.ndarray) -> np.ndarray:
    """(#F, 3, 2) planar corners of each triangle from its edge lengths (counter-clockwise).

    Corner 0 at the origin, corner 1 on the +x axis; corner 2 from the law of cosines
    (hand-written: libigl has no intrinsic layout in its Python bindings).
    """
    l0, l1, l2 = l[:, 0], l[:, 1], l[:, 2]
    x2 = (l1**2 + l2**2 - l0**2) / (2.0 * l2)
    y2 = np.sqrt(np.maximum(l1**2 - x2**2, 0.0))
    P = np.zeros((l.shape[0], 3, 2))
    P[:, 1, 0] = l2
    P[:, 2, 0] = x2
    P[:, 2, 1] = y2
    return P


def _cot_gram(l: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-face Gram matrices of the hat-function gradients, and face areas.

    ``K[f, i, j] = grad(phi_i) . grad(phi_j)`` on face ``f``: ``-cot(theta_k) / (2 A)`` off the
    diagonal (``k`` the third corner) and minus the row sum on it (Heron area, cotangents from
    the law of cosines).  ``A K`` is the face's block of ``-L``.
    """
    sq = l**2
    s = 0.5 * l.sum(axis=1)
    area = np.sqrt(np.maximum(s * (s - l[:, 0]) * (s - l[:, 1]) * (s - l[:, 2]), 0.0))
    area_safe = np.maximum(area, np.finfo(float).tiny)
    # cot at corner i: (l_j^2 + l_k^2 - l_i^2) / (4 A)
    cot = (sq[:, [1, 2, 0]] + sq[:, [2, 0, 1]] - sq) / (4.0 * area_safe[:, None])
    K = np.empty((l.shape[0], 3, 3))
    for i in range(3):  # three corners, not a loop over faces
        j, k = (i + 1) % 3, (i + 2) % 3
        K[:, j, k] = K[:, k, j] = -cot[:, i] / (2.0 * area_safe)
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        K[:, i, i] = -(K[:, i, j] + K[:, i, k])
    return K, area


def _midpoint_refine(l: np.ndarray, F: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, int]:
    """One 1-to-4 midpoint split of an intrinsic mesh; original vertices keep their indices.

    The new vertex on edge ``e`` is ``n + e``.  Each child is the parent scaled by 1/2 (the
    middle one rotated), so child lengths are parent lengths / 2 in permuted columns; the
    piecewise-flat surface is unchanged, only the triangulation is finer.
    """
    edges, fe, _ = topology.edge_topology(F, n, check=False)
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    ma, mb, mc = n + fe[:, 0], n + fe[:, 1], n + fe[:, 2]  # midpoints opposite a, b, c
    la, lb, lc = 0.5 * l[:, 0], 0.5 * l[:, 1], 0.5 * l[:, 2]
    Fn = np.concatenate(
        [
            np.stack([a, mc, mb], 1),
            np.stack([b, ma, mc], 1),
            np.stack([c, mb, ma], 1),
            np.stack([ma, mb, mc], 1),
        ]
    )
    ln = np.concatenate(
        [
            np.stack([la, lb, lc], 1),
            np.stack([lb, lc, la], 1),
            np.stack([lc, la, lb], 1),
            np.stack([la, lb, lc], 1),
        ]
    )
    return ln, Fn, n + edges.shape[0]


def _intrinsic_operators(
    l: np.ndarray, F: np.ndarray, n: int
) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix, np.ndarray]:
    """``L, M, G, area`` of the intrinsic mesh ``(l, F)`` with ``n`` vertices.

    ``L = igl.cotmatrix_intrinsic``, ``M = igl.massmatrix_intrinsic`` (Voronoi), and
    ``G`` (#F*2, n): ``igl.grad`` of each face laid out in its own plane (a triangle soup),
    gathered back to vertices.  Per-face frames differ, which is harmless: the heat method only
    uses ``|G u|`` and ``G^T A X`` with ``X`` in the same frames, and ``G^T A G = -L``.
    """
    nf = F.shape[0]
    L = igl.cotmatrix_intrinsic(l, F)
    M = igl.massmatrix_intrinsic(l, F, igl.MASSMATRIX_TYPE_VORONOI)
    if L.shape[0] < n:  # libigl sizes by F.max() + 1
        L.resize((n, n))
        M.resize((n, n))
    P = _layout(l).reshape(-1, 2)
    soup = np.arange(3 * nf, dtype=np.int64).reshape(nf, 3)
    G = igl.grad(P, soup)
    S = sp.csr_matrix((np.ones(3 * nf), (np.arange(3 * nf), F.reshape(-1))), shape=(3 * nf, n))
    area = 0.5 * igl.doublearea(P, soup).reshape(-1)
    return sp.csr_matrix(L), sp.csr_matrix(M), sp.csr_matrix(G @ S), area


# ----------------------------------------------------------------------------------------------
# heat method
# ----------------------------------------------------------------------------------------------
class HeatGeodesicSolver:
    """Geodesic distance by the heat method on a mescher; factor once, query many sources.

    Parameters
    ----------
    m : Mescher
    t : float, optional
        Heat time.  Default ``t_factor * h^2`` with ``h`` the mean edge length of the mesh the
        heat flows on (after refinement): Crane et al.'s standard choice for ``t_factor = 1``.
    method : {"standard", "accurate"}, default: "standard"
        ``"standard"``: the heat method on the mescher's own operators (``m.cotmatrix()``,
        ``m.massmatrix()``, ``m.grad()``).  ``"accurate"``: two levels of intrinsic midpoint
        refinement, then the intrinsic Delaunay triangulation; distances are read back at the
        original vertices (about 3x less error, 16x the faces).  Keywords given explicitly
        override the preset.
    intrinsic_delaunay : bool, optional
        Build every operator (heat and Poisson Laplacians, gradient, divergence) on the intrinsic
        Delaunay triangulation of the same surface (``igl.intrinsic_delaunay_triangulation`` on
        the edge lengths).  Gradient and divergence must live on the same triangulation as the
        Poisson Laplacian (``G^T A G = -L``), otherwise the integrated field is not the one that
        was normalized; so all three move to the intrinsic mesh, whose vertices are the
        original ones.
    boundary : {"average", "neumann", "dirichlet"}, default: "average"
        Boundary condition of the heat step on meshes with boundary: zero flux, zero value, or
        the mean of both solutions (Crane et al. 2013, Section 3.3, which recommend it).
    refine : int, optional
        Levels of intrinsic midpoint refinement (1-to-4 split; the surface is unchanged).
    t_factor : float, optional
        ``t = t_factor * h^2`` when ``t`` is not given.
    solver : {"auto", "cholespy", "splu"}, default: "auto"
        Factorization backend (:func:`meschers_igl.solvers.factorize_spd`).

    Attributes
    ----------
    t : float
        The heat time used.
    n_vertices : int
        Vertices of the mescher (distances are returned for these).
    """

    def __init__(
        self,
        m: Any,
        t: float | None = None,
        method: str = "standard",
        intrinsic_delaunay: bool | None = None,
        boundary: str = "average",
        refine: int | None = None,
        t_factor: float | None = None,
        solver: str = "auto",
    ) -> None:
        method = as_choice(method, "method", _METHODS)
        preset = _ACCURATE if method == "accurate" else {}
        if intrinsic_delaunay is None:
            intrinsic_delaunay = bool(preset.get("intrinsic_delaunay", False))
        if refine is None:
            refine = int(preset.get("refine", 0))
        if t_factor is None:
            t_factor = float(preset.get("t_factor", 1.0))
        if (
            isinstance(refine, bool)
            or not isinstance(refine, (int, np.integer))
            or not 0 <= refine <= 4
        ):
            raise MescherError(f"refine: expected an integer in [0, 4], found {refine!r}")
        t_factor = as_positive(t_factor, "t_factor")
        self.boundary = as_choice(boundary, "boundary", _BOUNDARY)
        self.method = method
        self.intrinsic_delaunay = bool(intrinsic_delaunay)
        self.refine = int(refine)
        self.m = m
        n = self.n_vertices = int(m.n_vertices)
        F = np.asarray(m.F, dtype=np.int64)
        # mollified lengths (Sharp & Crane 2020): equal to the plain ones unless some face is
        # nearly degenerate, and they keep every cotangent finite
        lm = np.asarray(m.face_edge_lengths(mollified=True), dtype=np.float64)
        # (m.grad() is the gradient of that same mollified metric, so G^T A G = -L holds for
        # the mescher's own operators on degenerate meshes too)
        if self.intrinsic_delaunay or self.refine > 0:
            nn = n
            for _ in range(self.refine):
                lm, F, nn = _midpoint_refine(lm, F, nn)
            h = float(lm.mean())
            if self.intrinsic_delaunay:
                lm, F = igl.intrinsic_delaunay_triangulation(lm, F)[:2]
            L, M, G, area = _intrinsic_operators(lm, F, nn)
        else:
            nn = n
            h = float(np.mean(m.edge_lengths()))
            L = sp.csr_matrix(m.cotmatrix())
            M = sp.csr_matrix(m.massmatrix())
            G = sp.csr_matrix(m.grad())
            area = np.asarray(m.face_areas(), dtype=np.float64)
        self.t = as_positive(t, "t") if t is not None else t_factor * h * h
        self.h = h
        self._n_inner = nn
        self._dim = G.shape[0] // max(F.shape[0], 1)
        self._G = G
        self._GtA = sp.csr_matrix(G.T @ sp.diags(np.tile(area, self._dim)))
        self._M = M
        # heat step (Neumann): (M - t L) u = M u0
        self._heat = factorize_spd(_regularize_unused(M - self.t * L, F, nn), backend=solver)
        # heat step (Dirichlet): the same restricted to interior vertices
        bnd = np.zeros(nn, dtype=bool)
        if F.shape[0]:
            _, fe, _ = topology.edge_topology(F, nn, check=False)
            be = topology.boundary_edge_mask(fe, int(fe.max()) + 1)
            bface, bcorner = np.nonzero(be[fe])
            bnd[F[bface, (bcorner + 1) % 3]] = True
            bnd[F[bface, (bcorner + 2) % 3]] = True
        self._bnd = bnd
        self._solver = solver
        self._Ah = _regularize_unused(M - self.t * L, F, nn)
        self._L, self._F_inner = L, F
        self._far: list = []  # lazily factored heat steps with longer times, see _far_gradient
        self._heat_d = None
        if bnd.any() and self.boundary != "neumann":
            self._heat_d = self._dirichlet_factor(bnd)
        # Poisson: -L pinned at one vertex per connected component (makes it definite)
        ncomp, label = topology.connected_components(F, nn) if F.shape[0] else (nn, np.arange(nn))
        pinned = np.zeros(nn, dtype=bool)
        pinned[np.unique(label, return_index=True)[1]] = True
        self._free = np.flatnonzero(~pinned)
        K = (-L).tocsr()[self._free][:, self._free]
        self._poisson = factorize_spd(K, backend=solver) if self._free.size else None
        self._label = label[:n]
        self._label_inner = label
        self._ncomp = ncomp

    # ------------------------------------------------------------------------------------------
    def _dirichlet_factor(self, fixed: np.ndarray):
        """Factor of the heat matrix restricted to the vertices not in ``fixed``."""
        free = np.flatnonzero(~fixed)
        if free.size == 0:
            return None
        return free, factorize_spd(self._Ah[free][:, free], backend=self._solver)

    def _heat_solve(self, src: np.ndarray) -> np.ndarray:
        """Heat step from the sources' indicator with the chosen boundary condition."""
        nn = self._n_inner
        u0 = np.zeros(nn)
        u0[src] = 1.0
        b = self._M @ u0
        b[src] += (b[src] == 0) * 1.0  # an unused (isolated) source vertex
        if self._heat_d is None:
            return self._heat(b)
        # Dirichlet: u = 0 on the boundary.  A source on the boundary stays free (a Dirac on a
        # zero-value vertex would vanish); that needs its own factorization, once per query.
        fixed = self._bnd.copy()
        fixed[src] = False
        free, solve = (
            self._heat_d if fixed.sum() == self._bnd.sum() else self._dirichlet_factor(fixed)
        )
        u_d = np.zeros(nn)
        u_d[free] = solve(b[free])
        if self.boundary == "dirichlet":
            return u_d
        return 0.5 * (self._heat(b) + u_d)

    def distance(self, sources: Any) -> np.ndarray:
        """Geodesic distance from a vertex or a set of vertices (to the nearest one).

        Parameters
        ----------
        sources : int or (k,) array_like of int
            Vertex indices in ``[0, #V)``.

        Returns
        -------
        d : (#V,) float64
            ``d >= 0`` up to the method's error, ``min(d[sources]) == 0`` in each connected
            component that holds a source, ``inf`` on components without one.
        """
        src = as_index_array(sources, "sources", self.n_vertices)
        nn, dim = self._n_inner, self._dim
        u = self._heat_solve(src)
        gu = (self._G @ u).reshape(dim, -1)
        self._far_gradient(u, src, gu)
        # Normalize after scaling by the largest component: far from the source the heat is
        # ~1e-280 and squaring it underflows (|grad u|^2 == 0 gave 5-8% mean error on a
        # 1.3M-face sphere, against 0.4% with the scaling).
        amax = np.abs(gu).max(axis=0)
        gs = np.divide(gu, amax, out=np.zeros_like(gu), where=amax > 0)
        norm = np.sqrt((gs * gs).sum(axis=0))
        X = -np.divide(gs, norm, out=np.zeros_like(gs), where=norm > 0)
        rhs = self._GtA @ X.reshape(-1)
        d = np.zeros(nn)
        if self._poisson is not None:
            d[self._free] = self._poisson(rhs[self._free])
            S = np.unique(src)
            if 1 < S.size <= _MAX_PINNED_SOURCES:
                d = self._pin_sources(d, S)
        d = d[: self.n_vertices]
        # shift per component so that the nearest source is at 0; no source: unreachable
        label = self._label
        shift = np.full(self._ncomp, np.inf)
        np.minimum.at(shift, label[src], d[src])
        out = d - shift[label]
        out[~np.isfinite(shift[label])] = np.inf
        return out

    __call__ = distance

    def _far_gradient(self, u: np.ndarray, src: np.ndarray, gu: np.ndarray) -> None:
        """Replace the gradient where the heat has (nearly) underflowed, in place.

        One backward-Euler step decays like ``exp(-d / sqrt(t))``; on large meshes (about 1M
        faces at ``t = h^2`` the far side of a sphere is at 1e-283) the heat can reach the
        denormal range, where it has no digits left and its gradient is noise.  There the
        direction comes from a heat step with a 100x longer time (10x slower decay), factored
        once on first need; repeated while some face is still that faint.
        """
        F = self._F_inner
        if F.shape[0] == 0:
            return
        scale = float(np.abs(u).max())
        weak = np.abs(u)[F].max(axis=1) < _FAR_RATIO * scale
        level = 0
        while weak.any() and level < 3:
            if level == len(self._far):
                t_far = self.t * 100.0 ** (level + 1)
                A = _regularize_unused(self._M - t_far * self._L, F, self._n_inner)
                self._far.append(factorize_spd(A, backend=self._solver))
            u0 = np.zeros(self._n_inner)
            u0[src] = 1.0
            b = self._M @ u0
            b[src] += (b[src] == 0) * 1.0
            v = self._far[level](b)
            gv = (self._G @ v).reshape(gu.shape)
            gu[:, weak] = gv[:, weak]
            weak &= np.abs(v)[F].max(axis=1) < _FAR_RATIO * float(np.abs(v).max())
            level += 1

    def _pin_sources(self, d0: np.ndarray, S: np.ndarray) -> np.ndarray:
        """Poisson solution with ``d`` equal at all sources of a component (Dirichlet at a set).

        The factor pins one vertex ``p`` per component.  Point loads ``mu_j`` at the sources,
        ``d = d0 + K_p^-1 E_S mu``, with ``d[s_j]`` equal within each component and
        ``sum_j mu_j = 0`` there (the dropped equation at ``p``: ``1^T G^T A X = 0``) give the
        solution of ``-L d = G^T A X`` away from the sources with ``d`` constant on them; ``k``
        extra solves, one ``k x k`` system.  Without it each source of a set sits at its own
        offset and the error doubles (9.8% vs 3.7% on the impossible torus, two sources).
        """
        nn, k = d0.size, S.size
        col = np.full(nn, -1, dtype=np.int64)
        col[self._free] = np.arange(self._free.size)
        E = np.zeros((self._free.size, k))
        ok = col[S] >= 0
        E[col[S[ok]], np.flatnonzero(ok)] = 1.0
        Gm = np.zeros((nn, k))
        Gm[self._free] = self._poisson(E)
        lab = self._label_inner[S]
        rows, rhs = [], []
        for c in np.unique(lab):  # one block per component holding sources (few)
            js = np.flatnonzero(lab == c)
            for j in js[1:]:
                rows.append(Gm[S[j]] - Gm[S[js[0]]])
                rhs.append(d0[S[js[0]]] - d0[S[j]])
            r = np.zeros(k)
            r[js] = 1.0
            rows.append(r)
            rhs.append(0.0)
        mu = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)[0]
        return d0 + Gm @ mu


def geodesic_distance(m: Any, sources: Any, **kwargs: Any) -> np.ndarray:
    """One-off heat-method distance: ``HeatGeodesicSolver(m, **kwargs).distance(sources)``.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) array_like of int
    **kwargs
        Passed to :class:`HeatGeodesicSolver` (``t``, ``method``, ``intrinsic_delaunay``,
        ``boundary``, ``refine``, ``t_factor``, ``solver``).

    Returns
    -------
    d : (#V,) float64
    """
    as_index_array(sources, "sources", int(m.n_vertices))  # fail before factoring
    return HeatGeodesicSolver(m, **kwargs).distance(sources)


# ----------------------------------------------------------------------------------------------
# shortest paths
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SurfacePath:
    """A polyline on a mescher, from ``source`` to ``target``.

    Each segment lies in one face; consecutive points share that face.

    Attributes
    ----------
    faces : (n,) int64
        ``faces[k]`` holds segment ``k`` (points ``k`` and ``k + 1``); ``faces[n-1]`` repeats
        ``faces[n-2]``.  A single-point path (``source == target``) has one incident face.
    bary : (n, 3) float64
        Barycentric coordinates of point ``k`` in face ``faces[k]`` (corners ``F[faces[k]]``).
    xy : (n, 2) float64
        Screen positions of the points.
    depth : (n,) float64
        Local depth along the path: zeta integrated from the source (``depth[0] = 0``); it is
        well defined along a path although a mescher has no global depth.
    length : float
        Intrinsic length (sum of segment lengths in the mescher's metric).
    source, target : int
    """

    faces: np.ndarray
    bary: np.ndarray
    xy: np.ndarray
    depth: np.ndarray
    length: float
    source: int
    target: int
    segment_lengths: np.ndarray = field(repr=False, default=None)

    @property
    def n_points(self) -> int:
        return int(self.bary.shape[0])


class _MeshData:
    """Per-face data for tracing: corners, neighbours, Gram matrices, vertex-to-face map."""

    def __init__(self, m: Any) -> None:
        self.F = np.asarray(m.F, dtype=np.int64)
        nf, n = self.F.shape[0], int(m.n_vertices)
        self.l = np.asarray(m.face_edge_lengths(mollified=True), dtype=np.float64)
        self.K, self.area = _cot_gram(self.l)
        _, fe, _ = topology.edge_topology(self.F, n, check=False)
        ef = topology.edge_faces(fe, int(fe.max()) + 1)
        # neighbour across the edge opposite each corner (-1 on the boundary)
        other = np.where(ef[fe, 0] == np.arange(nf)[:, None], ef[fe, 1], ef[fe, 0])
        self.opp = other
        # vertex -> incident faces (CSR)
        self.vf = sp.csr_matrix(
            (np.ones(3 * nf), (self.F.reshape(-1), np.repeat(np.arange(nf), 3))), shape=(n, nf)
        )

    def faces_of(self, v: int) -> np.ndarray:
        return self.vf.indices[self.vf.indptr[v] : self.vf.indptr[v + 1]]


def _seg_len2(l: np.ndarray, w: np.ndarray) -> float:
    """Squared length of a displacement with barycentric change ``w`` (sum 0) in a triangle."""
    return float(-(w[1] * w[2] * l[0] ** 2 + w[2] * w[0] * l[1] ** 2 + w[0] * w[1] * l[2] ** 2))


def _trace(md: _MeshData, d: np.ndarray, target: int, is_src: np.ndarray) -> list[tuple]:
    """Trace from ``target`` down ``-grad d``; return strips ``(v_start, faces, v_end)``.

    A strip is a sequence of faces that consecutive ones share an edge, entered at a vertex
    and left at a vertex; strips break where the trace meets a vertex (valleys of ``d``, where
    the field on both sides of an edge points at the edge, and boundaries are followed along
    the edge).  Hand-written: a sequential walk of O(path length) steps; no library traces
    barycentric rays across faces.
    """
    F, K, opp = md.F, md.K, md.opp
    eps = 1e-12
    strips: list[tuple] = []
    v = int(target)
    max_steps = 4 * F.shape[0] + 16
    steps = 0
    visited_vertices = {v}
    while not is_src[v]:
        fan = md.faces_of(v)
        # a face of the fan that holds a source: go straight to it
        hit = fan[is_src[F[fan]].any(axis=1)]
        if hit.size:
            f = int(hit[0])
            s = int(F[f][is_src[F[f]]][0])
            strips.append((v, [f], s))
            return strips
        # descent wedge: moving from corner c along -grad d enters the face
        corner = np.argmax(F[fan] == v, axis=1)
        W = -np.einsum("fij,fj->fi", K[fan], d[F[fan]])
        wc = W[np.arange(fan.size), corner]
        others = W.copy()
        others[np.arange(fan.size), corner] = np.inf
        ok = (wc < 0) & (others.min(axis=1) >= -eps * np.abs(W).max(axis=1))
        if ok.any():
            f = int(fan[np.flatnonzero(ok)[np.argmin(wc[ok])]])
            b = np.zeros(3)
            b[F[f] == v] = 1.0
            faces = [f]
            v_end = None
            while v_end is None:
                steps += 1
                if steps > max_steps:
                    raise MescherError(
                        "target: the trace down the distance gradient did not reach the source"
                    )
                w = -K[f] @ d[F[f]]
                neg = w < 0
                s_exit = np.where(neg, -b / np.where(neg, w, -1.0), np.inf)
                s_exit[b <= eps] = np.where(neg[b <= eps], 0.0, np.inf)
                i = int(np.argmin(s_exit))
                if s_exit[i] == 0.0 or not np.isfinite(s_exit[i]):
                    # valley or stationary: follow the edge we are on to its lower end
                    v_end = _lower_end(F[f], b, d)
                    break
                b = np.maximum(b + s_exit[i] * w, 0.0)
                b[i] = 0.0
                b /= b.sum()
                if (b > 1.0 - 1e-9).any():  # reached a corner
                    v_end = int(F[f][np.argmax(b)])
                    break
                g = int(opp[f, i])
                if g < 0:  # boundary: slide along it to the lower end
                    v_end = _lower_end(F[f], b, d)
                    break
                # express b in g: the edge's two vertices keep their weights
                bg = np.zeros(3)
                for c in range(3):  # three corners
                    bg[c] = b[F[f] == F[g, c]].sum() if (F[f] == F[g, c]).any() else 0.0
                faces.append(g)
                src_g = is_src[F[g]]
                if src_g.any():
                    v_end = int(F[g][src_g][0])
                    break
                wg = -K[g] @ d[F[g]]
                ig = int(np.argmax(bg == 0.0))
                if wg[ig] < 0:  # the field on the far side points back: valley
                    faces.pop()
                    v_end = _lower_end(F[f], b, d)
                    break
                f, b = g, bg
            strips.append((v, faces, v_end))
            v = v_end
        else:
            # no descent wedge: steepest descending edge
            nb = np.unique(F[fan])
            nb = nb[nb != v]
            down = nb[d[nb] < d[v]]
            if down.size == 0:
                # a spurious local minimum of an inaccurate field: finish along edges
                strips.extend(_edge_path(md, v, is_src))
                return strips
            u = int(down[np.argmin(d[down] - d[v])])
            f = int(fan[(F[fan] == u).any(axis=1)][0])
            strips.append((v, [f], u))
            v = u
        if v in visited_vertices and not is_src[v]:  # the field loops: finish along edges
            strips.extend(_edge_path(md, v, is_src))
            return strips
        visited_vertices.add(v)
    return strips


def _edge_path(md: _MeshData, v: int, is_src: np.ndarray) -> list[tuple]:
    """Fallback: Dijkstra along edges (intrinsic lengths) from ``v`` to the nearest source,
    as one-face strips.  Used only where the traced field is unusable (a spurious minimum)."""
    F, l = md.F, md.l
    n = is_src.size
    rows = F[:, [1, 2, 0]].reshape(-1)
    cols = F[:, [2, 0, 1]].reshape(-1)
    W = sp.csr_matrix((l.reshape(-1), (rows, cols)), shape=(n, n))
    W = W.maximum(W.T)
    _, pred = csgraph.dijkstra(W, directed=False, indices=v, return_predecessors=True)
    srcs = np.flatnonzero(is_src)
    dist = csgraph.dijkstra(W, directed=False, indices=v)
    s = int(srcs[np.argmin(dist[srcs])])
    if not np.isfinite(dist[s]):
        raise MescherError(f"target: no path from vertex {v} to a source")
    chain = [s]
    while chain[-1] != v:
        chain.append(int(pred[chain[-1]]))
    chain.reverse()
    out = []
    for a, b in zip(chain[:-1], chain[1:]):
        fan = md.faces_of(a)
        f = int(fan[(F[fan] == b).any(axis=1)][0])
        out.append((a, [f], b))
    return out


def _lower_end(Ff: np.ndarray, b: np.ndarray, d: np.ndarray) -> int:
    """Of the (one or two) corners with weight, the one with the lower distance."""
    cand = Ff[b > 0]
    return int(cand[np.argmin(d[cand])])


def _funnel(
    md: _MeshData, v0: int, faces: list[int], v1: int
) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Shortest path from vertex ``v0`` to ``v1`` inside a strip of faces (unfolded).

    The strip is laid out in the plane face by face from intrinsic edge lengths; the "simple
    stupid funnel" (Mononen's string pulling, Lee-Preparata) gives the taut path.  Returns
    segments ``(face, bary_start, bary_end)``.  Hand-written: no library does string pulling
    on an unfolded intrinsic strip.
    """
    F, l = md.F, md.l
    f0 = faces[0]
    P = _layout(l[[f0]])[0]
    pos = {int(F[f0, c]): P[c] for c in range(3)}
    portals = []  # (left vertex, right vertex, left xy, right xy)
    for k in range(1, len(faces)):
        f, g = faces[k - 1], faces[k]
        shared = [int(x) for x in F[g] if x in pos and (F[f] == x).any()]
        a, bv = shared[0], shared[1]
        third_prev = int(next(x for x in F[f] if x not in (a, bv)))
        pa, pb, pp = pos[a], pos[bv], pos[third_prev]
        cg = int(np.argmax((F[g] != a) & (F[g] != bv)))
        c = int(F[g, cg])
        # lengths in g: |a c| and |b c|
        la = l[g, int(np.argmax(F[g] == bv))]  # opposite b: edge (c, a)
        lb = l[g, int(np.argmax(F[g] == a))]  # opposite a: edge (b, c)
        e = pb - pa
        L2 = float(e @ e)
        x = (la**2 - lb**2 + L2) / (2.0 * L2)
        y = np.sqrt(max(la**2 - x * x * L2, 0.0) / L2)
        nrm = np.array([-e[1], e[0]])
        side = np.sign(nrm @ (pp - pa)) or 1.0
        pc = pa + x * e - side * y * nrm
        cross = e[0] * (pp - pa)[1] - e[1] * (pp - pa)[0]
        left, right = (bv, a) if cross > 0 else (a, bv)
        portals.append((left, right, pos[left].copy(), pos[right].copy()))
        pos = {a: pa, bv: pb, c: pc}
    start = next(P[c] for c in range(3) if F[f0, c] == v0)
    end = pos[v1]
    # string pulling over portals [start] + portals + [end]
    pts_l = [start] + [p[2] for p in portals] + [end]
    pts_r = [start] + [p[3] for p in portals] + [end]
    ids_l = [v0] + [p[0] for p in portals] + [v1]
    ids_r = [v0] + [p[1] for p in portals] + [v1]

    def area2(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])

    corners = [(0, start, v0)]  # (portal index, xy, vertex)
    apex, apex_i = start, 0
    left, right, li, ri = start, start, 0, 0
    i = 1
    npt = len(pts_l)
    while i < npt:
        pl, pr = pts_l[i], pts_r[i]
        # right side
        if area2(apex, right, pr) >= 0:
            if np.array_equal(apex, right) or area2(apex, left, pr) < 0:
                right, ri = pr, i
            else:
                apex, apex_i = left, li
                corners.append((li, left, ids_l[li]))
                left, right, li, ri = apex, apex, apex_i, apex_i
                i = apex_i + 1
                continue
        if area2(apex, left, pl) <= 0:
            if np.array_equal(apex, left) or area2(apex, right, pl) > 0:
                left, li = pl, i
            else:
                apex, apex_i = right, ri
                corners.append((ri, right, ids_r[ri]))
                left, right, li, ri = apex, apex, apex_i, apex_i
                i = apex_i + 1
                continue
        i += 1
    if corners[-1][0] != npt - 1:
        corners.append((npt - 1, end, v1))
    # crossing parameter of the taut path on every portal (0 at left, 1 at right)
    tpar = np.zeros(npt)
    for (ia, pa_, _), (ib, pb_, _) in zip(corners[:-1], corners[1:]):
        tpar[ia] = 0.0 if np.array_equal(pa_, pts_l[ia]) else 1.0
        for k in range(ia + 1, ib):
            q0, q1 = pts_l[k], pts_r[k]
            dq, dp = q1 - q0, pb_ - pa_
            den = dp[0] * dq[1] - dp[1] * dq[0]
            s = ((q0[0] - pa_[0]) * dp[1] - (q0[1] - pa_[1]) * dp[0]) / den if den != 0 else 0.0
            tpar[k] = min(max(s, 0.0), 1.0)
    # barycentric points per face: point k on portal k (k = 1..npt-2), start/end at vertices
    segs = []
    for k, f in enumerate(faces):
        ends = []
        for j in (k, k + 1):
            bb = np.zeros(3)
            if j == 0:
                bb[F[f] == v0] = 1.0
            elif j == npt - 1:
                bb[F[f] == v1] = 1.0
            else:
                bb[F[f] == ids_l[j]] += 1.0 - tpar[j]
                bb[F[f] == ids_r[j]] += tpar[j]
            ends.append(bb)
        segs.append((int(f), ends[0], ends[1]))
    return segs


def shortest_path(
    m: Any, source: Any, target: Any, solver: HeatGeodesicSolver | None = None, **kwargs: Any
) -> SurfacePath:
    """Shortest path on a mescher from ``source`` to ``target`` (vertices).

    The heat-method distance from ``source`` is traced from ``target`` down its per-face
    gradient (barycentric rays crossing edges), and each traced strip of faces is then
    unfolded with the intrinsic edge lengths and pulled taut by a funnel algorithm, so the
    result is the shortest path within the faces the trace crossed.

    Parameters
    ----------
    m : Mescher
    source, target : int
        Vertex indices.
    solver : HeatGeodesicSolver, optional
        A solver for ``m`` to reuse; otherwise one is built with ``**kwargs``
        (default ``intrinsic_delaunay=True``).

    Returns
    -------
    SurfacePath

    Raises
    ------
    MescherError
        On indices out of range, or when ``target`` cannot be reached from ``source``
        (different connected components).
    """
    n = int(m.n_vertices)
    s = int(as_index_array(source, "source", n)[0]) if np.ndim(source) == 0 else None
    t = int(as_index_array(target, "target", n)[0]) if np.ndim(target) == 0 else None
    if s is None:
        raise MescherError(f"source: expected one vertex index, found {np.shape(source)}")
    if t is None:
        raise MescherError(f"target: expected one vertex index, found {np.shape(target)}")
    if solver is None:
        # the trace only needs a descent direction: the standard t on the intrinsic Delaunay
        # triangulation is cheap and robust on obtuse meshes
        kwargs.setdefault("intrinsic_delaunay", True)
        solver = HeatGeodesicSolver(m, **kwargs)
    elif solver.m is not m:
        raise MescherError(
            "solver: expected a HeatGeodesicSolver built for this mescher, found one for another"
        )
    md = _MeshData(m)
    Fm = md.F
    if s == t:
        f = int(md.faces_of(s)[0]) if md.faces_of(s).size else -1
        bb = np.zeros((1, 3))
        if f >= 0:
            bb[0, Fm[f] == s] = 1.0
        return SurfacePath(
            np.array([f]), bb, np.asarray(m.xy)[[s]].copy(), np.zeros(1), 0.0, s, t, np.zeros(0)
        )
    d = solver.distance(s)
    if not np.isfinite(d[t]):
        raise MescherError(
            f"target: vertex {t} is not reachable from source {s} (another connected component)"
        )
    is_src = np.zeros(n, dtype=bool)
    is_src[s] = True
    strips = _trace(md, d, t, is_src)
    segs = []
    for v0, faces, v1 in strips:
        segs.extend(_funnel(md, v0, faces, v1))
    # reverse: source -> target; drop zero-length segments
    segs = [(f, b1, b0) for f, b0, b1 in reversed(segs)]
    lens = np.array([np.sqrt(max(_seg_len2(md.l[f], b1 - b0), 0.0)) for f, b0, b1 in segs])
    keep = lens > 1e-12 * max(float(lens.max(initial=0.0)), 1e-300)
    segs = [sg for sg, k in zip(segs, keep) if k]
    lens = lens[keep]
    faces = np.array([sg[0] for sg in segs] + [segs[-1][0]], dtype=np.int64)
    bary = np.array([sg[1] for sg in segs] + [segs[-1][2]])
    xy = np.asarray(m.xy, dtype=np.float64)
    pts_xy = np.einsum("ki,kij->kj", bary, xy[Fm[faces]])
    Z = np.asarray(m.corner_depths(), dtype=np.float64)
    dz = np.array([(b1 - b0) @ Z[f] for f, b0, b1 in segs])
    depth = np.concatenate([[0.0], np.cumsum(dz)])
    return SurfacePath(faces, bary, pts_xy, depth, float(lens.sum()), s, t, lens)
