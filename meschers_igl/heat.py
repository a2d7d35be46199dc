"""Heat diffusion and the heat method for geodesic distance on meschers.

A mescher has a discrete metric (per-edge lengths, DESIGN.md), so intrinsic processing works on it
although it cannot be embedded: paper Section 4.3.  Everything here is intrinsic and needs only

* the 0-form operators ``L = m.cotmatrix()`` (negative semi-definite, libigl's convention),
  ``M = m.massmatrix()``, the per-face gradient ``G = m.grad()`` and face areas ``A``, or
* the per-face edge lengths ``l = m.face_edge_lengths()`` (libigl: column ``i`` opposite corner
  ``i``), from which the same operators are rebuilt (:func:`meschers_igl.operators.
  intrinsic_operators`) on a refined or intrinsic-Delaunay triangulation of the same
  piecewise-flat surface (:mod:`meschers_igl.intrinsic`).

The heat method (Crane, Weischedel, Wardetzky 2013; "The heat method for distance computation",
CACM 2017) in this module's sign conventions:

1. heat: ``(M - t L) u = M delta_sources`` (paper Eq. 5 with ``u0`` the sources' indicator);
2. unit field: ``X = -G u / |G u|`` per face (points away from the sources);
3. Poisson: ``-L d = G^T A X`` (``G^T A G = -L``), with one vertex per connected component
   pinned so that the matrix is positive definite; then ``d`` is shifted per component so that
   ``min(d[sources]) = 0``; components without a source get ``inf``.

Shortest paths and exact distances are in :mod:`meschers_igl.paths`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from . import intrinsic, topology
from .errors import MescherError
from .operators import intrinsic_operators
from .solvers import factorize_spd
from .validate import as_choice, as_index_array, as_positive

__all__ = [
    "HeatGeodesicSolver",
    "choose_method",
    "geodesic_distance",
    "heat_diffuse",
]

#: relative heat below which the gradient direction is not trusted (see _far_gradient)
_FAR_RATIO = 1e-290
#: source sets up to this size are held at one common value in the Poisson step (k solves)
_MAX_PINNED_SOURCES = 256
_BOUNDARY = ("neumann", "dirichlet", "average")
METHODS = ("auto", "standard", "robust", "refined", "accurate")
#: presets: (levels of intrinsic midpoint refinement, intrinsic Delaunay).  "accurate": mean
#: relative error on the 48 x 16 impossible torus (4 sources, against the covering oracle):
#: standard 4.6%; refine=1: 2.6% (t = h^2), 2.2% (t = h^2 / 2); refine=2: 1.5%; refine=2 + iDT:
#: 1.5%; smaller t_factor (0.1-0.25) is worse near the sources.
_PRESETS = {
    "standard": (0, False),
    "robust": (0, True),
    "refined": (1, True),
    "accurate": (2, True),
}
#: "auto" picks "refined" when some corner angle is below this (degrees): a sliver
SLIVER_DEGREES = 1.0
#: "auto" picks "refined" on meshes with at most this many faces: the refined mesh then has at
#: most 100k faces, and the refined solver costs about what the standard one costs at 100k
#: faces (query 16-20 ms against 18-21 ms, set-up 1.1-1.3 s against 0.9-1.0 s, on tori)
AUTO_REFINE_MAX_FACES = 25_000


#: an edge is Delaunay when its cotangent weight (cot a + cot b) / 2 is >= -DELAUNAY_TOL; the
#: intrinsic Delaunay flips use the same test (so the cocircular quads of a grid, weight 0 up
#: to round-off, are left alone; see intrinsic.intrinsic_delaunay)
DELAUNAY_TOL = 1e-9


def choose_method(m: Any) -> str:
    """The heat-method variant ``method="auto"`` uses on ``m``, and why (see the solver).

    The rules, in this order:

    1. ``"refined"`` (one intrinsic midpoint refinement, then intrinsic Delaunay) on meshes
       with at most :data:`AUTO_REFINE_MAX_FACES` faces, whatever their triangles.
    2. ``"refined"`` on larger meshes when some corner angle is below :data:`SLIVER_DEGREES`
       (CAD tessellations, fans of needles): the gradient of a sliver is unreliable even after
       flipping.
    3. ``"robust"`` (intrinsic Delaunay, as potpourri3d's default) when some edge is not
       Delaunay (weight below ``-DELAUNAY_TOL``: obtuse triangles).
    4. ``"standard"`` otherwise (every edge Delaunay, no sliver): the mescher's own operators;
       on an ordinary mesh the result equals libigl's heat method.

    Why refine small meshes: the heat method's error is first order in the edge length, and
    refinement halves it without changing the surface.  Against exact distances (mean relative
    error over sources 0, 7, 20, 60, 100; ``tests/meschers_igl/test_heat.py``, potpourri3d
    1.4's ``MeshHeatMethodDistanceSolver`` with its defaults)::

        mesh (faces)                     potpourri3d  standard  robust   auto = refined
        sliver box (228)                 0.1480       0.1857    0.1418   0.1010  (0.68x)
        sliver box, finer (764)          0.1731       0.1903    0.1645   0.0922  (0.53x)
        obtuse sheet (3042)              0.0130       0.4859    0.0105   0.0095  (0.73x)
        torus 48 x 16 (1536)             0.0466       0.0467    0.0467   0.0261  (0.56x)
        icosphere 3 (1280)               0.0151       0.0151    0.0151   0.0094  (0.62x)
        uv sphere 40 x 20 (1520)         0.0177       0.0169    0.0169   0.0124  (0.70x)
        perturbed torus (1536)           0.0548       0.0511    0.0567   0.0362  (0.66x)
        perturbed icosphere (1280)       0.0129       0.0153    0.0129   0.0091  (0.71x)
        PyVista's ant (912)              0.0792       0.0811    0.0780   0.0597  (0.75x)
        PyVista's nut (1046)             0.0385       0.0385    0.0385   0.0230  (0.60x)
        impossible torus (1536) [*]      0.0474       0.0464    0.0484   0.0267  (0.56x)

    [*] exact distances on a 3-sheet covering; potpourri3d runs on that covering.  The choice
    before (rules 2-4 at every size) was worse than potpourri3d on the torus, both perturbed
    meshes and the impossible torus: the heat method on the mesh itself is within a few
    percent of potpourri3d's either way, and only a finer triangulation is clearly better.
    Its price is 3.5-4.5x the query time and 6-7x the precomputation (two factorizations of
    four times the size), which is why it stops at :data:`AUTO_REFINE_MAX_FACES`: there the
    refined solver costs what the standard one costs at 100k faces (torus, 25k faces: 16-20 ms
    per query and 1.1-1.3 s to set up, against 18-21 ms and 0.9-1.0 s for standard at 100k;
    libigl at 25k: 3.7 ms and 0.11 s, potpourri3d 5.6 ms and 0.13 s;
    ``benchmarks/bench_geodesics.py --sizes 25000 100000``).

    Where refinement does not help: crumpled meshes, whose vertices are cones of large angle
    defect (every vertex moved at random by 0.5-1 mean edge length; median defect 0.8-1.4
    rad).  There the error is 1.12-1.22x potpourri3d's refined, 1.03-1.05x robust, and
    0.79-0.93x standard (the plain mesh Laplacian, negative weights and all).  A likely reason:
    shortest paths on such a surface pass through saddle vertices (a quarter of their inner
    points are vertices, against 0-1% on a smooth torus or sphere), and the intrinsic Delaunay
    flips and the refinement's flat midpoints both take the discrete heat flow away from the
    mesh's own edges.  No rule here detects such meshes; pass ``method="standard"`` for scans
    that noisy.

    Near the limit the margin holds (refined / potpourri3d at 20-24k faces, sources 0, 7,
    2000, exact distances by window propagation: torus 0.75, icosphere 5 0.77, torus with
    vertices moved by 0.2 edge lengths 0.81), except on crumpled meshes (bumpy sphere of 20k
    faces, relief about one edge length: 1.15).  Above it (rules 2-4) the default runs the
    same heat method as potpourri3d on the mesh itself, so its error is within a few percent
    of potpourri3d's, either side: standard / potpourri3d measured 1.005 (torus, 25k faces),
    1.018 (torus, 100k), 0.98 (icosphere 5), 0.92 (uv sphere, 40k); on that bumpy sphere
    robust 1.034, standard 1.005.  Two differences remain, and neither is an accuracy choice one
    could copy to be never worse: potpourri3d lumps masses barycentrically (libigl's Voronoi
    masses here, so that "standard" equals libigl; on a Delaunay torus that is 0.0467 against
    0.0466, on the uv sphere 0.0169 against 0.0177), and it solves ``(L + 1e-6 I) phi = div X``
    on its intrinsic tufted cover, whose Laplacian is twice the mesh's on a closed manifold,
    i.e. ``(L + 5e-7 I)`` on the mesh.  That screening shrinks every distance by an amount that
    grows with the resolution: it helps on tori, where the heat method overestimates far
    distances, and hurts on spheres.  With barycentric masses and that screening the heat
    method here reproduces potpourri3d's distances to 3e-14 (48 x 16 torus, icosphere 3).
    """
    F = np.asarray(m.F)
    if F.shape[0] == 0:
        return "standard"
    if F.shape[0] <= AUTO_REFINE_MAX_FACES:
        return "refined"
    l = np.asarray(m.face_edge_lengths(mollified=True), dtype=np.float64)
    # one pass over the cotangents: an angle below SLIVER_DEGREES has cot above cot(SLIVER),
    # an edge is Delaunay when its weight (cot a + cot b) / 2 >= 0 (intrinsic.is_delaunay)
    hc = intrinsic.half_cotangents(l)
    if float(hc.max()) > 0.5 / np.tan(np.radians(SLIVER_DEGREES)):
        return "refined"
    fe = np.asarray(m.face_edges).reshape(-1)
    w = np.bincount(fe, weights=hc.reshape(-1), minlength=int(m.n_edges))
    if float(w.min()) < -DELAUNAY_TOL:
        return "robust"
    return "standard"


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


def _regularize_unused(A: sp.spmatrix, F: np.ndarray, n: int) -> sp.csr_matrix:
    """Put 1 on the diagonal of vertices that no face uses (their rows are empty)."""
    unused = np.ones(n, dtype=bool)
    unused[F.reshape(-1)] = False
    if unused.any():
        A = A + sp.diags(unused.astype(np.float64))
    return sp.csr_matrix(A)


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
    method : {"auto", "standard", "robust", "refined", "accurate"}, default: "auto"
        ``"standard"``: the heat method on the mescher's own operators (``m.cotmatrix()``,
        ``m.massmatrix()``, ``m.grad()``) and its cached factorization of ``-L``; on an
        ordinary mesh this equals libigl's heat method.  ``"robust"``: every operator on the
        intrinsic Delaunay triangulation (potpourri3d's default).  ``"refined"``: one level of
        intrinsic midpoint refinement, then intrinsic Delaunay (4x the faces).
        ``"accurate"``: two levels, then intrinsic Delaunay (16x the faces, about 3x less
        error).  ``"auto"`` chooses per mesh (:func:`choose_method`, which gives the measured
        errors): ``"refined"`` on meshes of at most :data:`AUTO_REFINE_MAX_FACES` faces
        (0.53-0.75x potpourri3d's error on the eleven meshes measured) and on larger ones with
        a corner angle below :data:`SLIVER_DEGREES` degree; otherwise ``"robust"`` when some
        edge is not Delaunay (obtuse triangles), ``"standard"`` when every edge is (then equal
        to libigl's heat method, and the query time at 100k faces is unchanged).  Distances
        are always read back at the original vertices.  Keywords given explicitly override
        the preset.
    intrinsic_delaunay : bool, optional
        Build every operator (heat and Poisson Laplacians, gradient, divergence) on the intrinsic
        Delaunay triangulation of the same surface (edge flips on the lengths,
        :func:`meschers_igl.intrinsic.intrinsic_delaunay` with ``tol = DELAUNAY_TOL``: edges
        within round-off of cocircular are not flipped, so the result does not depend on the
        vertex order or position).  Gradient and divergence must live on the same
        triangulation as the Poisson Laplacian (``G^T A G = -L``), otherwise the integrated
        field is not the one that was normalized; so all three move to the intrinsic mesh,
        whose vertices are the original ones.
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
        method: str = "auto",
        intrinsic_delaunay: bool | None = None,
        boundary: str = "average",
        refine: int | None = None,
        t_factor: float | None = None,
        solver: str = "auto",
    ) -> None:
        method = as_choice(method, "method", METHODS)
        if method == "auto":
            method = choose_method(m)
        p_refine, p_idt = _PRESETS[method]
        if intrinsic_delaunay is None:
            intrinsic_delaunay = p_idt
        if refine is None:
            refine = p_refine
        if t_factor is None:
            t_factor = 1.0
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
        own = not (self.intrinsic_delaunay or self.refine > 0)
        if own:
            nn = n
            h = float(np.mean(m.edge_lengths()))
            L = sp.csr_matrix(m.cotmatrix())
            M = sp.csr_matrix(m.massmatrix())
            G = sp.csr_matrix(m.grad())
            area = np.asarray(m.face_areas(), dtype=np.float64)
            fe = np.asarray(m.face_edges)  # the mescher's own edge topology, not recomputed
        else:
            nn = n
            edges, fe = np.asarray(m.edges), np.asarray(m.face_edges)
            for level in range(self.refine):
                if level:  # the refined mesh's edges (the first level uses the mescher's)
                    edges, fe, _ = topology.edge_topology(F, nn, check=False)
                lm, F, nn = intrinsic.midpoint_refine(lm, F, edges, fe, nn)
            if self.refine:
                fe = topology.edge_topology(F, nn, check=False)[1]
            h = float(lm.mean())
            if self.intrinsic_delaunay:
                # flips beyond round-off only: the result does not depend on vertex order
                lm, F, fe = intrinsic.intrinsic_delaunay(lm, F, tol=DELAUNAY_TOL, face_edges=fe)
            L, M, G, area = intrinsic_operators(lm, F, nn)
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
            be = np.bincount(fe.reshape(-1), minlength=int(fe.max()) + 1) == 1
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
        if own and solver == "auto":
            # the mescher already factors d01^T star1 d01 = -L with the same pins (first
            # vertex of each component) for its Hodge decomposition: reuse it
            ex = m.exact_part_solver()
            label, ncomp = np.asarray(ex.labels), int(ex.ncomp)
            self._poisson = ex.solve
        else:
            ncomp, label = (
                topology.connected_components(F, nn) if F.shape[0] else (nn, np.arange(nn))
            )
            pinned = np.zeros(nn, dtype=bool)
            pinned[np.unique(label, return_index=True)[1]] = True
            free = np.flatnonzero(~pinned)
            K = (-L).tocsr()[free][:, free]
            factor = factorize_spd(K, backend=solver) if free.size else None

            def poisson(b: np.ndarray) -> np.ndarray:
                x = np.zeros(b.shape)
                if factor is not None:
                    x[free] = factor(np.ascontiguousarray(b[free]))
                return x

            self._poisson = poisson
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
        dim = self._dim
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
        d = self._poisson(rhs)
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
        E = np.zeros((nn, k))
        E[S, np.arange(k)] = 1.0  # a load on a pinned vertex is dropped by the solve
        Gm = self._poisson(E)
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
        ``boundary``, ``refine``, ``t_factor``, ``solver``).  For exact distances see
        :func:`meschers_igl.paths.geodesic_distance` (``method="exact"``).

    Returns
    -------
    d : (#V,) float64
    """
    as_index_array(sources, "sources", int(m.n_vertices))  # fail before factoring
    return HeatGeodesicSolver(m, **kwargs).distance(sources)
