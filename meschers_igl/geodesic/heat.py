"""Heat diffusion and the heat method for geodesic distance on meschers.

A mescher has a discrete metric (per-edge lengths, :doc:`/conventions`), so intrinsic processing
works on it although it cannot be embedded: paper Section 4.3.  Everything here is intrinsic and needs only

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

``method="geometry_central"`` is potpourri3d's variant of the same (barycentric masses, heat
from a unit without mass, a screened Poisson step on the tufted cover); ``method="auto"``
uses it or a refined triangulation, whichever is measured better (:func:`choose_method`).

Every method is reached through :func:`meschers_igl.geodesic.geodesic_solver`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .. import intrinsic, topology
from ..errors import MescherError
from ..operators import intrinsic_operators
from ..solvers import factorize_spd
from ..validate import as_choice, as_index_array, as_positive

__all__ = [
    "HeatGeodesicSolver",
    "choose_method",
    "heat_diffuse",
    "saddle_relief",
]

#: relative heat below which the gradient direction is not trusted (see _far_gradient)
_FAR_RATIO = 1e-290
#: source sets up to this size are held at one common value in the Poisson step (k solves)
_MAX_PINNED_SOURCES = 256
_BOUNDARY = ("neumann", "dirichlet", "average")
METHODS = ("auto", "standard", "robust", "refined", "accurate", "geometry_central")
#: presets: (levels of intrinsic midpoint refinement, intrinsic Delaunay)
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


#: "auto" does not refine meshes whose :func:`saddle_relief` is above this (crumpled meshes)
CRUMPLED_RELIEF = 6.0


#: an edge is Delaunay when its cotangent weight (cot a + cot b) / 2 is >= -DELAUNAY_TOL; the
#: intrinsic Delaunay flips use the same test (so the cocircular quads of a grid, weight 0 up
#: to round-off, are left alone; see intrinsic.intrinsic_delaunay)
DELAUNAY_TOL = 1e-9


#: geometry-central's ``flipToDelaunay`` tolerance on the edge weight (``delaunayEPS``)
PEER_DELAUNAY_TOL = 1e-6
#: geometry-central's Poisson shift, ``(L + 1e-6 I) phi = div X`` on the tufted cover
PEER_POISSON_SHIFT = 1e-6


def _flipped_double(l: np.ndarray, F: np.ndarray, fe: np.ndarray, n: int):
    """The double of ``(l, F)`` (a mirror copy glued along the boundary) flipped to intrinsic
    Delaunay with :data:`PEER_DELAUNAY_TOL`, its faces folded back onto the ``n`` vertices.

    Interior vertices get a second copy ``n + v`` while flipping (they are distinct points of
    the double), boundary vertices and boundary edges are shared by both sheets.
    """
    ne = int(fe.max()) + 1
    deg = np.bincount(fe.reshape(-1), minlength=ne)
    bface, bcorner = np.nonzero(deg[fe] == 1)
    back = np.arange(n, 2 * n)
    back[F[bface, (bcorner + 1) % 3]] = F[bface, (bcorner + 1) % 3]
    back[F[bface, (bcorner + 2) % 3]] = F[bface, (bcorner + 2) % 3]
    rev = [0, 2, 1]  # the back sheet is oppositely oriented
    l2 = np.r_[l, l[:, rev]]
    F2 = np.r_[F, back[F][:, rev]]
    fe2 = np.r_[fe, np.where(deg[fe] == 1, fe, fe + ne)[:, rev]]
    lt, Ft, _ = intrinsic.intrinsic_delaunay(l2, F2, tol=PEER_DELAUNAY_TOL, face_edges=fe2)
    return lt, np.where(Ft >= n, Ft - n, Ft)


def saddle_relief(m: Any) -> float:
    """How crumpled ``m`` is at the scale of its edges: ``sqrt(#F)`` times the mean saddle defect.

    ``relief = sqrt(#F) * mean_v max(0, -K_v)`` over interior vertices, with ``K_v = 2 pi -
    (sum of corner angles at v)`` the angle defect (intrinsic: from the edge lengths, so it
    applies to meschers too).  On a smooth surface sampled with spacing ``h`` a vertex's defect
    is its integrated curvature, ``O(h^2)``, so the relief is ``O(h)`` and vanishes under
    refinement; vertex-scale relief (noise of the order of an edge length) makes ``O(1)``
    saddle cones, and the relief grows like ``sqrt(#F)``.  The heat method's discretization
    error is ``O(h)``, i.e. ``O(1 / sqrt(#F))`` of the size: refinement pays when that error,
    not the cones, dominates (see :func:`choose_method` for the measured boundary).

    Returns
    -------
    relief : float
        0 on meshes without interior saddle vertices (convex shapes, flat sheets).
    """
    F = np.asarray(m.F, dtype=np.int64)
    if F.shape[0] == 0:
        return 0.0
    n = int(m.n_vertices)
    ang = intrinsic.corner_angles(np.asarray(m.face_edge_lengths(mollified=True)))
    K = 2.0 * np.pi - np.bincount(F.reshape(-1), weights=ang.reshape(-1), minlength=n)
    fe = np.asarray(m.face_edges)
    bface, bcorner = np.nonzero(np.bincount(fe.reshape(-1))[fe] == 1)
    inner = np.bincount(F.reshape(-1), minlength=n) > 0
    inner[F[bface, (bcorner + 1) % 3]] = False
    inner[F[bface, (bcorner + 2) % 3]] = False
    if not inner.any():
        return 0.0
    return float(np.sqrt(F.shape[0]) * np.maximum(-K[inner], 0.0).mean())


def choose_method(m: Any) -> str:
    """The heat-method variant ``method="auto"`` uses on ``m``.

    The rules, in this order:

    1. ``"geometry_central"`` (potpourri3d's heat method itself, equal to round-off) when
       :func:`saddle_relief` is above :data:`CRUMPLED_RELIEF` (= 6): crumpled meshes.
    2. ``"refined"`` (one intrinsic midpoint refinement, then intrinsic Delaunay) on meshes
       with at most :data:`AUTO_REFINE_MAX_FACES` faces.
    3. ``"refined"`` on larger meshes with a corner angle below :data:`SLIVER_DEGREES`.
    4. ``"geometry_central"`` otherwise.

    So the default is never worse than potpourri3d's ``MeshHeatMethodDistanceSolver``: by
    construction where it is that method, and by a measured margin where it refines (the
    measurements, on 47 meshes, and the cost of refining are in :doc:`/results`; the tests
    check the margin on 18 meshes).  ``"standard"`` (the mescher's operators, equal to libigl's
    heat method) and ``"robust"`` are never chosen: they differ from potpourri3d's method by
    Voronoi masses and a pinned rather than screened Poisson step.
    """
    F = np.asarray(m.F)
    if F.shape[0] == 0:
        return "standard"
    if saddle_relief(m) > CRUMPLED_RELIEF:
        return "geometry_central"
    if F.shape[0] <= AUTO_REFINE_MAX_FACES:
        return "refined"
    # one pass over the cotangents: an angle below SLIVER_DEGREES has cot above cot(SLIVER)
    hc = intrinsic.half_cotangents(np.asarray(m.face_edge_lengths(mollified=True)))
    if float(hc.max()) > 0.5 / np.tan(np.radians(SLIVER_DEGREES)):
        return "refined"
    return "geometry_central"


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


@dataclass(frozen=True)
class _HeatOptions:
    """The variant a :class:`HeatGeodesicSolver` runs, after ``"auto"`` and the presets."""

    method: str
    boundary: str
    intrinsic_delaunay: bool
    refine: int
    t_factor: float
    pin_sets: bool  # source sets held at one value in the Poisson step (else potpourri3d's shift)

    @classmethod
    def resolve(cls, m, method, intrinsic_delaunay, boundary, refine, t_factor) -> _HeatOptions:
        method = as_choice(method, "method", METHODS)
        requested = method
        if method == "auto":
            method = choose_method(m)
            if method == "geometry_central" and (
                refine is not None
                or intrinsic_delaunay is not None
                or boundary not in (None, "neumann")
            ):
                method = "robust"  # the closest preset that takes those keywords
        t_factor = 1.0 if t_factor is None else as_positive(t_factor, "t_factor")
        if method == "geometry_central":
            for name, value in (("refine", refine), ("intrinsic_delaunay", intrinsic_delaunay)):
                if value is not None:
                    raise MescherError(
                        f"{name}: method='geometry_central' fixes it (intrinsic Delaunay, no "
                        f"refinement), found {value!r}"
                    )
            if boundary is not None and as_choice(boundary, "boundary", _BOUNDARY) != "neumann":
                raise MescherError(
                    "boundary: method='geometry_central' solves the heat step with Neumann "
                    f"conditions (as potpourri3d), found {boundary!r}"
                )
            # potpourri3d's offsets on source sets when asked for by name; auto pins them
            return cls(method, "neumann", True, 0, t_factor, requested != "geometry_central")
        p_refine, p_idt = _PRESETS[method]
        refine = p_refine if refine is None else refine
        if (
            isinstance(refine, bool)
            or not isinstance(refine, (int, np.integer))
            or not 0 <= refine <= 4
        ):
            raise MescherError(f"refine: expected an integer in [0, 4], found {refine!r}")
        boundary = as_choice("average" if boundary is None else boundary, "boundary", _BOUNDARY)
        idt = p_idt if intrinsic_delaunay is None else bool(intrinsic_delaunay)
        return cls(method, boundary, idt, int(refine), t_factor, True)


@dataclass(frozen=True)
class _HeatSystem:
    """The operators the heat method runs on, on the mesh the heat flows on (the mescher, its
    refined or intrinsic Delaunay triangulation, or potpourri3d's tufted cover); vertices
    ``[0, #V)`` are the mescher's."""

    t: float  # heat time
    h: float  # mean edge length of that mesh
    n: int  # its vertices
    F: np.ndarray  # its faces
    dim: int  # gradient blocks per face (3 in the camera frame, 2 intrinsic)
    G: sp.csr_matrix  # per-face gradient
    GtA: sp.csr_matrix  # divergence: G^T diag(area)
    M: sp.csr_matrix  # mass
    L: sp.csr_matrix  # cotangent Laplacian (negative semi-definite)
    Ah: sp.csr_matrix  # heat matrix M - t L (rows of unused vertices regularized)
    heat: Any  # solve with Ah (Neumann)
    poisson: Any  # solve with -L pinned once per component (or screened, potpourri3d)
    bnd: np.ndarray  # boundary vertices (for the Dirichlet heat step)
    label: np.ndarray  # connected component of each vertex
    ncomp: int
    peer: bool  # potpourri3d's variant: heat from a unit without mass, mean shift on sets


def _heat_system(m: Any, opt: _HeatOptions, t: float | None, solver: str) -> _HeatSystem:
    """The presets' operators: the mescher's own, or rebuilt from its lengths after
    ``opt.refine`` levels of intrinsic midpoint refinement and intrinsic Delaunay flips."""
    n = int(m.n_vertices)
    F = np.asarray(m.F, dtype=np.int64)
    # mollified lengths (Sharp & Crane 2020): equal to the plain ones unless some face is
    # nearly degenerate, and they keep every cotangent finite (m.grad() is the gradient of
    # that same metric, so G^T A G = -L holds for the mescher's own operators too)
    lm = np.asarray(m.face_edge_lengths(mollified=True), dtype=np.float64)
    own = not (opt.intrinsic_delaunay or opt.refine > 0)
    nn = n
    if own:
        h = float(np.mean(m.edge_lengths()))
        L, M, G = (sp.csr_matrix(x) for x in (m.cotmatrix(), m.massmatrix(), m.grad()))
        area = np.asarray(m.face_areas(), dtype=np.float64)
        fe = np.asarray(m.face_edges)  # the mescher's own edge topology, not recomputed
    else:
        edges, fe = np.asarray(m.edges), np.asarray(m.face_edges)
        for level in range(opt.refine):
            if level:  # the refined mesh's edges (the first level uses the mescher's)
                edges, fe, _ = topology.edge_topology(F, nn, check=False)
            lm, F, nn = intrinsic.midpoint_refine(lm, F, edges, fe, nn)
        if opt.refine:
            fe = topology.edge_topology(F, nn, check=False)[1]
        h = float(lm.mean())
        if opt.intrinsic_delaunay:
            # flips beyond round-off only: the result does not depend on vertex order
            lm, F, fe = intrinsic.intrinsic_delaunay(lm, F, tol=DELAUNAY_TOL, face_edges=fe)
        L, M, G, area = intrinsic_operators(lm, F, nn)
    t = as_positive(t, "t") if t is not None else opt.t_factor * h * h
    dim = G.shape[0] // max(F.shape[0], 1)
    Ah = _regularize_unused(M - t * L, F, nn)
    bnd = np.zeros(nn, dtype=bool)
    if F.shape[0]:
        be = np.bincount(fe.reshape(-1), minlength=int(fe.max()) + 1) == 1
        bface, bcorner = np.nonzero(be[fe])
        bnd[F[bface, (bcorner + 1) % 3]] = True
        bnd[F[bface, (bcorner + 2) % 3]] = True
    # Poisson: -L pinned at one vertex per connected component (makes it definite)
    if own and solver == "auto":
        # the mescher already factors d01^T star1 d01 = -L with the same pins (first vertex of
        # each component) for its Hodge decomposition: reuse it
        ex = m.exact_part_solver()
        label, ncomp, poisson = np.asarray(ex.labels), int(ex.ncomp), ex.solve
    else:
        ncomp, label = topology.connected_components(F, nn) if F.shape[0] else (nn, np.arange(nn))
        poisson = _pinned_poisson(L, label, solver)
    return _HeatSystem(
        t=t,
        h=h,
        n=nn,
        F=F,
        dim=dim,
        G=G,
        GtA=sp.csr_matrix(G.T @ sp.diags(np.tile(area, dim))),
        M=M,
        L=L,
        Ah=Ah,
        heat=factorize_spd(Ah, backend=solver),
        poisson=poisson,
        bnd=bnd,
        label=np.asarray(label),
        ncomp=int(ncomp),
        peer=False,
    )


def _pinned_poisson(L: sp.csr_matrix, label: np.ndarray, solver: str):
    """Solve ``-L x = b`` with ``x = 0`` at the first vertex of each component."""
    nn = L.shape[0]
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

    return poisson


def _peer_system(m: Any, opt: _HeatOptions, t: float | None, solver: str) -> _HeatSystem:
    """``method="geometry_central"``: potpourri3d's heat method, operator for operator.

    geometry-central's ``HeatMethodDistanceSolver`` (robust Laplacian on, potpourri3d's
    default) builds the intrinsic tufted cover of the mesh: two copies of every face,
    oppositely oriented, glued edge by edge (Sharp & Crane 2020).  On a manifold mesh that
    is two sheets sharing the vertices, joined along the boundary (the double).  It mollifies
    by ``1e-5`` mean edge lengths, flips edges of weight below ``-1e-6`` to Delaunay, and
    factors ``M + t L`` (barycentric lumped masses, ``t`` the squared mean edge length of the
    flipped cover) and ``L + 1e-6 I``.  Here: the mesh's intrinsic Delaunay triangulation
    with the same tolerance, every operator doubled (two sheets); only when a boundary edge
    of it would flip on the cover (opposite angle above 90 degrees: on the double its two
    opposite angles are that one twice) is the double itself flipped and folded back onto
    the vertices.
    """
    n = int(m.n_vertices)
    F = np.asarray(m.F, dtype=np.int64)
    l = np.asarray(m.face_edge_lengths(mollified=True), dtype=np.float64)
    fe = np.asarray(m.face_edges, dtype=np.int64)
    lt, Ft, fet = intrinsic.intrinsic_delaunay(l, F, tol=PEER_DELAUNAY_TOL, face_edges=fe)
    sheets = 2.0
    if F.shape[0]:
        deg = np.bincount(fet.reshape(-1))
        bcorner = deg[fet] == 1
        # cover weight of a boundary edge: cot(opposite angle) from both of its copies
        if bcorner.any() and 4.0 * intrinsic.half_cotangents(lt)[bcorner].min() < (
            -2.0 * PEER_DELAUNAY_TOL
        ):
            lt, Ft = _flipped_double(l, F, fe, n)
            sheets = 1.0
    L, _, G, area = intrinsic_operators(lt, Ft, n)
    mass = np.bincount(Ft.reshape(-1), weights=np.repeat(area / 3.0, 3), minlength=n)
    h = float(lt.mean()) if lt.size else 1.0  # mean edge length of the cover (see above)
    t = as_positive(t, "t") if t is not None else opt.t_factor * h * h
    M = sp.diags(sheets * mass).tocsr()
    L = sp.csr_matrix(sheets * L)
    Ah = _regularize_unused(M - t * L, Ft, n)
    K = sp.csr_matrix(-L + PEER_POISSON_SHIFT * sp.identity(n))
    ncomp, label = topology.connected_components(F, n) if F.shape[0] else (n, np.arange(n))
    return _HeatSystem(
        t=t,
        h=h,
        n=n,
        F=Ft,
        dim=2,
        G=G,
        GtA=sp.csr_matrix(G.T @ sp.diags(np.tile(sheets * area, 2))),
        M=M,
        L=L,
        Ah=Ah,
        heat=factorize_spd(Ah, backend=solver),
        poisson=factorize_spd(K, backend=solver),
        bnd=np.zeros(n, dtype=bool),
        label=np.asarray(label),
        ncomp=int(ncomp),
        peer=True,
    )


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
    method : {"auto", "standard", "robust", "refined", "accurate", "geometry_central"}
        Default ``"auto"``.  ``"standard"``: the heat method on the mescher's own operators
        (``m.cotmatrix()``, ``m.massmatrix()``, ``m.grad()``) and its cached factorization of
        ``-L``; on an ordinary mesh this equals libigl's heat method.  ``"robust"``: every
        operator on the intrinsic Delaunay triangulation.  ``"refined"``: one level of
        intrinsic midpoint refinement, then intrinsic Delaunay (4x the faces).
        ``"accurate"``: two levels, then intrinsic Delaunay (16x the faces, about 3x less
        error).  ``"geometry_central"``: potpourri3d's ``MeshHeatMethodDistanceSolver`` with its
        defaults, reproduced to round-off (see ``_peer_system``): intrinsic Delaunay with
        geometry-central's tolerance, barycentric masses, ``t = h^2``, heat from a unit at each
        source, the screened Poisson step ``(L + 1e-6 I) phi = div X`` on its tufted cover,
        and for source sets its shift (the mean over the sources is 0).  ``"auto"`` chooses
        per mesh (:func:`choose_method`, with the measured errors): ``"refined"`` on meshes of
        at most :data:`AUTO_REFINE_MAX_FACES` faces that are not crumpled
        (:func:`saddle_relief` <= :data:`CRUMPLED_RELIEF`) and on larger ones with a sliver,
        ``"geometry_central"`` elsewhere, so that it is never worse than potpourri3d; source
        sets are then held at 0 together (see ``_pin_sources``; 0.23-0.96x potpourri3d's error
        on sets of 2-4 sources, five meshes).  Distances are always read back at the original vertices.
        Keywords given explicitly override the preset (``"geometry_central"`` takes only
        ``t``, ``t_factor`` and ``solver``; where auto would choose it, ``refine``,
        ``intrinsic_delaunay`` or a ``boundary`` other than Neumann make it ``"robust"``).
    intrinsic_delaunay : bool, optional
        Build every operator (heat and Poisson Laplacians, gradient, divergence) on the intrinsic
        Delaunay triangulation of the same surface (edge flips on the lengths,
        :func:`meschers_igl.intrinsic.intrinsic_delaunay` with ``tol = DELAUNAY_TOL``: edges
        within round-off of cocircular are not flipped, so the result does not depend on the
        vertex order or position).  Gradient and divergence must live on the same
        triangulation as the Poisson Laplacian (``G^T A G = -L``), otherwise the integrated
        field is not the one that was normalized; so all three move to the intrinsic mesh,
        whose vertices are the original ones.
    boundary : {"average", "neumann", "dirichlet"}, optional
        Boundary condition of the heat step on meshes with boundary: zero flux, zero value, or
        the mean of both solutions (Crane et al. 2013, Section 3.3, which recommend it); the
        default is ``"average"``, except ``"neumann"`` (the only one) for
        ``"geometry_central"``, whose heat flows on the mesh's double.
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
        boundary: str | None = None,
        refine: int | None = None,
        t_factor: float | None = None,
        solver: str = "auto",
    ) -> None:
        opt = _HeatOptions.resolve(m, method, intrinsic_delaunay, boundary, refine, t_factor)
        self.method, self.boundary = opt.method, opt.boundary
        self.intrinsic_delaunay, self.refine = opt.intrinsic_delaunay, opt.refine
        self.m = m
        self.n_vertices = int(m.n_vertices)
        self._solver = solver
        self._pin_sets = opt.pin_sets
        self._far: list = []  # lazily factored heat steps with longer times, see _far_gradient
        build = _peer_system if opt.method == "geometry_central" else _heat_system
        self._sys = build(m, opt, t, solver)
        self.t, self.h = self._sys.t, self._sys.h
        self._heat_d = None  # the Dirichlet heat step, factored when a boundary condition asks
        if self._sys.bnd.any() and self.boundary != "neumann":
            self._heat_d = self._dirichlet_factor(self._sys.bnd)
        self._label = self._sys.label[: self.n_vertices]

    # ------------------------------------------------------------------------------------------
    def _dirichlet_factor(self, fixed: np.ndarray):
        """Factor of the heat matrix restricted to the vertices not in ``fixed``."""
        free = np.flatnonzero(~fixed)
        if free.size == 0:
            return None
        return free, factorize_spd(self._sys.Ah[free][:, free], backend=self._solver)

    def _heat_solve(self, src: np.ndarray) -> np.ndarray:
        """Heat step from the sources' indicator with the chosen boundary condition."""
        nn = self._sys.n
        u0 = np.zeros(nn)
        u0[src] = 1.0
        b = self._sys.M @ u0
        b[src] += (b[src] == 0) * 1.0  # an unused (isolated) source vertex
        if self._heat_d is None:
            return self._sys.heat(b)
        # Dirichlet: u = 0 on the boundary.  A source on the boundary stays free (a Dirac on a
        # zero-value vertex would vanish); that needs its own factorization, once per query.
        fixed = self._sys.bnd.copy()
        fixed[src] = False
        free, solve = (
            self._heat_d if fixed.sum() == self._sys.bnd.sum() else self._dirichlet_factor(fixed)
        )
        u_d = np.zeros(nn)
        u_d[free] = solve(b[free])
        if self.boundary == "dirichlet":
            return u_d
        return 0.5 * (self._sys.heat(b) + u_d)

    def distance(self, sources: Any, targets: Any = None) -> np.ndarray:
        """Geodesic distance from a vertex or a set of vertices (to the nearest one).

        Parameters
        ----------
        sources : int or (k,) array_like of int
            Vertex indices in ``[0, #V)``.
        targets : int or (t,) array_like of int, optional
            Checked only: the heat method solves for the whole field at once.

        Returns
        -------
        d : (#V,) float64
            ``d >= 0`` up to the method's error, ``min(d[sources]) == 0`` in each connected
            component that holds a source, ``inf`` on components without one.
        """
        src = as_index_array(sources, "sources", self.n_vertices)
        if targets is not None:
            as_index_array(targets, "targets", self.n_vertices)
        dim = self._sys.dim
        if self._sys.peer:  # potpourri3d: the heat of a unit at each source, no mass
            b = np.zeros(self._sys.n)
            np.add.at(b, src, 1.0)
            u = self._sys.heat(b)
        else:
            u = self._heat_solve(src)
        gu = (self._sys.G @ u).reshape(dim, -1)
        self._far_gradient(u, src, gu)
        # Normalize after scaling by the largest component: far from the source the heat is
        # ~1e-280 and squaring it underflows (|grad u|^2 == 0 gave 5-8% mean error on a
        # 1.3M-face sphere, against 0.4% with the scaling).
        amax = np.abs(gu).max(axis=0)
        gs = np.divide(gu, amax, out=np.zeros_like(gu), where=amax > 0)
        norm = np.sqrt((gs * gs).sum(axis=0))
        X = -np.divide(gs, norm, out=np.zeros_like(gs), where=norm > 0)
        rhs = self._sys.GtA @ X.reshape(-1)
        d = self._sys.poisson(rhs)
        S = np.unique(src)
        if self._pin_sets and 1 < S.size <= _MAX_PINNED_SOURCES:
            d = self._pin_sources(d, S)
        d = d[: self.n_vertices]
        label = self._label
        shift = np.full(self._sys.ncomp, np.inf)
        if self._sys.peer and not self._pin_sets:
            # potpourri3d: the mean over the sources is 0 (per component here)
            cnt = np.bincount(label[src], minlength=self._sys.ncomp)
            tot = np.bincount(label[src], weights=d[src], minlength=self._sys.ncomp)
            np.divide(tot, cnt, out=shift, where=cnt > 0)
        else:  # shift per component so that the nearest source is at 0
            np.minimum.at(shift, label[src], d[src])
        # no source: unreachable
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
        F = self._sys.F
        if F.shape[0] == 0:
            return
        scale = float(np.abs(u).max())
        weak = np.abs(u)[F].max(axis=1) < _FAR_RATIO * scale
        level = 0
        while weak.any() and level < 3:
            if level == len(self._far):
                t_far = self.t * 100.0 ** (level + 1)
                A = _regularize_unused(self._sys.M - t_far * self._sys.L, F, self._sys.n)
                self._far.append(factorize_spd(A, backend=self._solver))
            u0 = np.zeros(self._sys.n)
            u0[src] = 1.0
            b = self._sys.M @ u0
            b[src] += (b[src] == 0) * 1.0
            v = self._far[level](b)
            gv = (self._sys.G @ v).reshape(gu.shape)
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
        Gm = self._sys.poisson(E)
        lab = self._sys.label[S]
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
