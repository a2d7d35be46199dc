"""The mescher: screen positions per vertex, relative depths per edge (Dodik et al. 2025, Sec. 3).

Example
-------
>>> import numpy as np
>>> from meschers_igl import Mescher
>>> F = np.array([[0, 1, 2]])
>>> xy = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
>>> m = Mescher.from_corner_depths(F, xy, np.array([[0.0, 1.0, 0.0]]))
>>> float(m.face_areas()[0])  # the local triangle (0,0,0), (1,0,1), (0,1,0)
0.7071067811865476
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.sparse as sp

from . import hodge as _hodge
from . import operators as ops
from . import subdivision as _sub
from . import topology as topo
from .cutmesh import cut_mesh_arrays
from .errors import MescherError
from .validate import (
    as_choice,
    as_faces,
    as_float_array,
    as_int_array,
    as_points,
    as_vector,
    check_referenced,
)

#: Relative tolerance of the local-integrability check, times the model's size.
INTEGRABILITY_RTOL = 1e-9
#: Relative tolerance (times the model's size) above which a period counts as impossible.
IMPOSSIBLE_RTOL = 1e-6


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


class Mescher:
    """A triangle mesh of an impossible (or possible) object seen head-on.

    Parameters
    ----------
    F : (#F, 3) array_like of int
        Oriented triangles; manifold and consistently oriented.
    xy : (#V, 2) array_like of float
        Screen positions (x right, y up).
    edges : (#E, 2) array_like of int
        Each edge of ``F`` exactly once, oriented tail -> head.
    zeta : (#E,) array_like of float
        Relative depths, ``zeta[e] = depth(head) - depth(tail)`` (larger is nearer).
    project : bool, default: False
        Project ``zeta`` onto the locally integrable forms first (paper Eq. 3-4, unit star1).
        Without it a ``zeta`` with ``d12 @ zeta != 0`` raises :class:`MescherError`.

    Notes
    -----
    Every user-visible array is read-only; operations return new meschers.
    """

    def __init__(self, F, xy, edges, zeta, project: bool = False):
        xy = as_points(xy, "xy", 2)
        if xy.shape[0] == 0:
            raise MescherError("xy: expected at least three vertices, found none")
        F = as_faces(F, "F", xy.shape[0])
        check_referenced(F, xy.shape[0], "xy")
        edges_in = as_int_array(edges, "edges", 2, 2)
        zeta = as_vector(zeta, "zeta", edges_in.shape[0])
        cedges, face_edges, signs = topo.edge_topology(F, xy.shape[0])
        perm, flip = topo.orient_edges_like(edges_in, cedges, xy.shape[0])
        # Keep the user's edge order and orientation: remap the incidence to it.
        inv = np.empty_like(perm)
        inv[perm] = np.arange(perm.size)
        face_edges = inv[face_edges]
        signs = signs * np.where(flip, -1.0, 1.0)[face_edges]
        self._set_arrays(F, xy, edges_in, zeta, face_edges, signs)
        if project:
            self._zeta = _readonly(self._closed_projector(self._zeta))
        else:
            self._check_integrable()

    def _set_arrays(self, F, xy, edges, zeta, face_edges, signs) -> None:
        self._F, self._xy, self._edges, self._zeta = F, xy, edges, zeta
        self._face_edges, self._signs = face_edges, signs
        for name in ("_F", "_xy", "_edges", "_zeta", "_face_edges", "_signs"):
            setattr(self, name, _readonly(getattr(self, name)))

    @classmethod
    def _trusted(cls, F, xy, edges, zeta, face_edges, signs) -> Mescher:
        """A mescher from canonical arrays an internal constructor has already validated (its
        own incidence ``face_edges, signs``): no checks, no copies beyond read-only views."""
        m = cls.__new__(cls)
        m._set_arrays(F, xy, edges, zeta, face_edges, signs)
        return m

    # ------------------------------------------------------------------ construction
    @classmethod
    def _from_halfedge_values(cls, F, xy, h) -> Mescher:
        """Canonical edges of validated ``F``; per-edge zeta averaged from the faces' half-edge
        values ``h`` (#F, 3) (paper Sec. 3.4), then projected onto integrable forms."""
        edges, face_edges, signs = topo.edge_topology(F, xy.shape[0])
        ne = edges.shape[0]
        fe = face_edges.reshape(-1)
        vals = (h * signs).reshape(-1)
        zeta = np.bincount(fe, weights=vals, minlength=ne) / np.bincount(fe, minlength=ne)
        m = cls._trusted(F, xy, edges, zeta, face_edges, signs)
        m._zeta = _readonly(m._closed_projector(np.array(m._zeta)))
        return m

    def _replace(self, xy=None, zeta=None) -> Mescher:
        """Same connectivity and edge orientation, new (already validated) xy and/or zeta.

        The homology generators are carried over, so ``periods()`` of the result are in this
        mescher's basis (smooth, with_xy, with_zeta, with_periods).
        """
        m = type(self)._trusted(
            self._F,
            self._xy if xy is None else xy,
            self._edges,
            self._zeta if zeta is None else zeta,
            self._face_edges,
            self._signs,
        )
        if "_generators" in self.__dict__:  # else recomputed: the same tree-cotree, same F
            m.__dict__["_generators"] = self._generators
        return m

    @classmethod
    def from_corner_depths(cls, F, xy, Z) -> Mescher:
        """A mescher from per-face corner depths (any per-face offset).

        Parameters
        ----------
        F : (#F, 3) int
        xy : (#V, 2) float
        Z : (#F, 3) float
            Depth of each face's corners; only differences within a face matter.  Values that
            two faces propose for their shared edge are averaged, then projected (Eq. 3-4).
        """
        xy = as_points(xy, "xy", 2)
        F = as_faces(F, "F", xy.shape[0])
        check_referenced(F, xy.shape[0], "xy")
        Z = as_float_array(Z, "Z", (F.shape[0], 3))
        # half-edge opposite corner i runs i+1 -> i+2
        h = Z[:, [2, 0, 1]] - Z[:, [1, 2, 0]]
        return cls._from_halfedge_values(F, xy, h)

    @classmethod
    def from_mesh(cls, V, F, view=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0)) -> Mescher:
        """An ordinary 3D mesh seen from ``view`` (orthographic): always possible.

        Parameters
        ----------
        V : (#V, 3) float
        F : (#F, 3) int
        view : (3,) float, default: (0, 0, 1)
            Direction from the object toward the camera.
        up : (3,) float, default: (0, 1, 0)
        """
        V = as_points(V, "V", 3)
        F = as_faces(F, "F", V.shape[0])
        check_referenced(F, V.shape[0], "V")
        C = V @ ops.view_frame(view, up).T
        edges, face_edges, signs = topo.edge_topology(F, V.shape[0])
        zeta = C[edges[:, 1], 2] - C[edges[:, 0], 2]
        return cls._trusted(F, np.ascontiguousarray(C[:, :2]), edges, zeta, face_edges, signs)

    @classmethod
    def from_cut_mesh(
        cls,
        V,
        F,
        view=(0.0, 0.0, 1.0),
        up=(0.0, 1.0, 0.0),
        tol=None,
        merge=None,
        return_map=False,
    ):
        """The mescher of a cut 3D model seen from ``view`` (paper Sec. 3.5; :mod:`.cutmesh`).

        The model is projected orthographically (camera coordinates ``V @ R.T``, ``R`` from
        :func:`meschers_igl.operators.view_frame`).  Boundary loops whose projections coincide
        vertex by vertex are glued, preferring the correspondence that is one translation along
        the view direction; vertices that coincide on screen but are not on the boundary
        (front/back pairs) are never merged.  Each edge gets ``zeta = depth(head) - depth(tail)``
        measured inside its faces; where the two faces of a glued edge disagree the values are
        averaged (with a :class:`MescherWarning`), and the result is projected onto locally
        integrable forms.  Around a loop through a cut, zeta sums to the cut's depth gap.

        Parameters
        ----------
        V : (#V, 3) array_like
            Vertex positions of the cut model (world frame).
        F : (#F, 3) array_like of int
            Oriented triangles (all outward, or all inward).
        view, up : (3,) array_like
            Direction from the model toward the camera; screen up.
        tol : float, optional
            Gluing tolerance relative to the bounding-box diagonal (default 1e-5).
        merge : (k, 2) array_like of int, optional
            Explicit vertex pairs to glue instead of the automatic loop pairing.
        return_map : bool, default: False
            Also return ``vmap`` (#V,): the mescher vertex of each input vertex (-1 if unused).

        Returns
        -------
        Mescher (face ``i`` is input face ``i``), and ``vmap`` with ``return_map``.

        Raises
        ------
        MescherError
            Bad arrays; ambiguous or partial loop coincidences (pass ``merge``); ``merge`` pairs
            that do not coincide on screen; a gluing that makes the surface non-manifold or
            non-orientable (the message names the input vertices).
        """
        a = cut_mesh_arrays(V, F, view=view, up=up, tol=tol, merge=merge)
        m = cls(a.F, a.xy, a.edges, a.zeta, project=True)
        return (m, a.vmap) if return_map else m

    @classmethod
    def from_model(
        cls,
        V,
        F,
        view=(0.0, 0.0, 1.0),
        up=(0.0, 1.0, 0.0),
        perceive=None,
        *,
        return_report=False,
        **kwargs,
    ):
        """Any 3D model -- cut models, closed solids, separate blocks, reliefs, soups -- as seen
        from ``view``, by :func:`meschers_igl.obtain.model_to_mescher` (which picks the route:
        a cut model open at a seam whose loops glue is glued there; anything else is seen).

        By default (``hidden="auto"``) the whole model, opened at its junctions and glued
        crosswise like a cut model: a closed surface whose false edges (two caps or edges that
        coincide on screen at different depths) and hidden gaps (a bar's pieces lined up behind
        a crossing bar, bridged through empty space) carry their depth gaps as periods; with
        ``hidden=False`` (and whenever no junction is found, or with ``perceive``) the visible
        surface only.  ``view="auto"`` finds the view where junctions line up (``view_start=``
        searches near a guess), ``perceive="manhattan"`` snaps normals to the perceived right
        angles.  See :func:`meschers_igl.obtain.see_model` (which returns arrays; the depth
        order is in ``report.arcs``, or use :func:`meschers_igl.obtain.model_to_mescher`).

        Returns
        -------
        Mescher, and the :class:`~meschers_igl.obtain.ConversionReport` with ``return_report``.
        """
        from .obtain.choose import drop_small_periods, obtain  # the one door's choice

        got = obtain(V, F, view=view, up=up, perceive=perceive, **kwargs)
        if got.cut is not None:
            a = got.cut
            m = cls(a.F, a.xy, a.edges, a.zeta, project=True)
        else:
            m = cls.from_corner_depths(got.seen.F, got.seen.xy, got.seen.Z)
        m = drop_small_periods(m, got.report)
        return (m, got.report) if return_report else m

    def with_xy(self, xy, order=None):
        """Same topology and depths, new screen positions.

        With a :class:`DepthOrder`, returns ``(mescher, order.follow(mescher))``: arcs kept
        where faces still overlap, new overlaps ordered from local depth.
        """
        xy = as_points(xy, "xy", 2, self.n_vertices)
        m = self._replace(xy=xy)
        return m if order is None else (m, order.follow(m))

    def with_zeta(self, zeta, project: bool = False) -> Mescher:
        """Same topology and screen positions, new relative depths (checked or projected)."""
        zeta = as_vector(zeta, "zeta", self.n_edges)
        m = self._replace(zeta=zeta)
        if project:
            m._zeta = _readonly(self._closed_projector(zeta))
        else:
            m._check_integrable()
        return m

    # ------------------------------------------------------------------ basic arrays
    F = property(lambda self: self._F, doc="(#F, 3) int64 oriented faces (read-only).")
    xy = property(lambda self: self._xy, doc="(#V, 2) float64 screen positions (read-only).")
    edges = property(lambda self: self._edges, doc="(#E, 2) int64 tail -> head (read-only).")
    zeta = property(lambda self: self._zeta, doc="(#E,) float64 relative depths (read-only).")
    face_edges = property(
        lambda self: self._face_edges, doc="(#F, 3) int64 edge opposite each corner."
    )
    face_edge_signs = property(
        lambda self: self._signs, doc="(#F, 3) float64 +1 where the edge follows the face."
    )
    n_vertices = property(lambda self: self._xy.shape[0])
    n_edges = property(lambda self: self._edges.shape[0])
    n_faces = property(lambda self: self._F.shape[0])

    def __repr__(self) -> str:
        return (
            f"Mescher(#V={self.n_vertices}, #E={self.n_edges}, #F={self.n_faces}, "
            f"chi={self.euler_characteristic()})"
        )

    def euler_characteristic(self) -> int:
        """``#V - #E + #F``."""
        return topo.euler_characteristic(self.n_vertices, self.n_edges, self.n_faces)

    def scale(self) -> float:
        """A length scale of the model: the diagonal of its screen box, or of the edge lengths."""
        box = float(np.linalg.norm(self._xy.max(axis=0) - self._xy.min(axis=0)))
        return max(box, float(np.abs(self._zeta).max(initial=0.0)), 1e-300)

    # ------------------------------------------------------------------ DEC
    @cached_property
    def d01(self) -> sp.csr_matrix:
        """(#E, #V) exterior derivative on 0-forms."""
        return topo.d01(self._edges, self.n_vertices)

    @cached_property
    def d12(self) -> sp.csr_matrix:
        """(#F, #E) exterior derivative on 1-forms."""
        return topo.d12(self._face_edges, self._signs, self.n_edges)

    def integrability_residual(self) -> np.ndarray:
        """(#F,) ``d12 @ zeta``: zero for a valid mescher (paper Eq. 2)."""
        return self.d12 @ self._zeta

    def _check_integrable(self) -> None:
        r = self.integrability_residual()
        tol = INTEGRABILITY_RTOL * self.scale()
        worst = float(np.abs(r).max())
        if worst > tol:
            f = int(np.argmax(np.abs(r)))
            raise MescherError(
                f"zeta: expected a locally integrable 1-form (d12 @ zeta == 0 within {tol:.3g}), "
                f"found residual {worst:.3g} at face {f} ({int((np.abs(r) > tol).sum())} faces "
                "over); pass project=True to project it onto the nearest integrable zeta"
            )

    @cached_property
    def _closed_projector(self):
        return _hodge.closed_projector(self.d12)

    # ------------------------------------------------------------------ local geometry
    @cached_property
    def _corner_depths(self) -> np.ndarray:
        return _readonly(ops.corner_depths(self._zeta, self._face_edges, self._signs))

    def corner_depths(self) -> np.ndarray:
        """(#F, 3) local corner depths, corner 0 at 0."""
        return self._corner_depths

    @cached_property
    def _local_corners(self) -> np.ndarray:
        return _readonly(ops.local_corners(self._xy, self._F, self._corner_depths))

    def local_corners(self) -> np.ndarray:
        """(#F, 3, 3) per-face corner positions (x, y, local depth)."""
        return self._local_corners

    @cached_property
    def _edge_lengths(self) -> np.ndarray:
        return _readonly(ops.edge_lengths(self._xy, self._edges, self._zeta))

    def edge_lengths(self) -> np.ndarray:
        """(#E,) lengths of the edges in their local triangles."""
        return self._edge_lengths

    def face_edge_lengths(self, mollified: bool = False) -> np.ndarray:
        """(#F, 3) lengths, column i opposite corner i (libigl convention).

        With ``mollified=True`` the lengths the intrinsic operators use (Sharp & Crane 2020);
        identical unless the mesh has (near-)degenerate triangles.
        """
        return self._l_moll if mollified else self._l_face

    @cached_property
    def _l_face(self) -> np.ndarray:
        return _readonly(self._edge_lengths[self._face_edges])

    @cached_property
    def _mollified(self) -> tuple[np.ndarray, float]:
        """The mollified lengths and the ``eps`` added to every edge (Sharp & Crane 2020)."""
        lm, eps = ops.mollify(self._l_face)
        return _readonly(lm), float(eps)

    @property
    def _l_moll(self) -> np.ndarray:
        return self._mollified[0]

    @property
    def _mollify_eps(self) -> float:
        return self._mollified[1]

    def mollification(self) -> float:
        """The length ``eps`` added to every edge by intrinsic mollification (0 for most meshes)."""
        return float(self._mollify_eps)

    @cached_property
    def _dbl_area(self) -> np.ndarray:
        return ops.double_areas_from_lengths(self._l_moll)

    def face_areas(self) -> np.ndarray:
        """(#F,) triangle areas (of the mollified metric; exact unless degenerate)."""
        return 0.5 * self._dbl_area

    def face_normals(self) -> np.ndarray:
        """(#F, 3) unit normals in the camera frame, z toward the viewer (cached, read-only)."""
        return self._face_normals

    @cached_property
    def _face_normals(self) -> np.ndarray:
        return _readonly(ops.face_normals(self._local_corners))

    def vertex_normals(self) -> np.ndarray:
        """(#V, 3) area-weighted unit vertex normals from the faces' local frames (cached)."""
        return self._vertex_normals

    @cached_property
    def _vertex_normals(self) -> np.ndarray:
        return _readonly(ops.vertex_normals(self._local_corners, self._F, self.n_vertices))

    # ------------------------------------------------------------------ operators
    @cached_property
    def _half_cot(self) -> np.ndarray:
        return ops.half_cotangents(self._l_moll, self._dbl_area)

    @cached_property
    def star0(self) -> sp.dia_matrix:
        """(#V, #V) barycentric vertex areas (one third of the incident face areas)."""
        a = np.bincount(
            self._F.reshape(-1),
            weights=np.repeat(self.face_areas() / 3.0, 3),
            minlength=self.n_vertices,
        )
        return sp.diags(a).tocsr()

    @cached_property
    def star1(self) -> sp.dia_matrix:
        """(#E, #E) cotangent weights ``(cot a + cot b) / 2``."""
        return sp.diags(
            ops.star1_from_half_cot(self._half_cot, self._face_edges, self.n_edges)
        ).tocsr()

    @cached_property
    def star2(self) -> sp.dia_matrix:
        """(#F, #F) inverse face areas."""
        with np.errstate(divide="ignore"):
            inv = 1.0 / self.face_areas()
        if not np.all(np.isfinite(inv)):
            raise MescherError("star2: found zero-area faces; mollification should prevent this")
        return sp.diags(inv).tocsr()

    def cotmatrix(self) -> sp.csc_matrix:
        """(#V, #V) negative semi-definite cotangent Laplacian (``igl.cotmatrix`` convention)."""
        return ops.cotmatrix(self._l_moll, self._F)

    def massmatrix(self, kind: str = "voronoi") -> sp.csc_matrix:
        """(#V, #V) lumped mass matrix, ``kind`` in {"voronoi", "barycentric"} like libigl."""
        kind = as_choice(kind, "kind", tuple(ops.MASS_TYPES))
        return ops.massmatrix(self._l_moll, self._F, kind)

    def grad(self) -> sp.csr_matrix:
        """(#F*3, #V) gradient in the camera frame, blocks x, y, z (``igl.grad`` layout)."""
        if self._mollify_eps > 0:  # lengths were mollified: gradients of that metric
            return ops.grad_mollified(self._local_corners, self._l_moll, self._F, self.n_vertices)
        return ops.grad(self._local_corners, self._F, self.n_vertices)

    def laplacian0(self) -> sp.csr_matrix:
        """``star0^-1 d01^T star1 d01`` (positive semi-definite 0-form Laplacian)."""
        inv0 = sp.diags(1.0 / self.star0.diagonal())
        return (inv0 @ self.d01.T @ self.star1 @ self.d01).tocsr()

    def laplacian1(self) -> sp.csr_matrix:
        """``star1^-1 d12^T star2 d12 + d01 star0^-1 d01^T star1`` (1-form Hodge Laplacian).

        Needs every cotangent weight non-zero (an edge between two right angles has weight 0;
        such meshes need an intrinsic Delaunay retriangulation or subdivision first).
        """
        w = self.star1.diagonal()
        if np.any(w == 0):
            raise MescherError(
                f"star1: expected non-zero cotangent weights to invert, found "
                f"{int((w == 0).sum())} zero weight(s) (first edge "
                f"{int(np.flatnonzero(w == 0)[0])})"
            )
        inv1 = sp.diags(1.0 / w)
        inv0 = sp.diags(1.0 / self.star0.diagonal())
        up = inv1 @ self.d12.T @ self.star2 @ self.d12
        down = self.d01 @ inv0 @ self.d01.T @ self.star1
        return (up + down).tocsr()

    # ------------------------------------------------------------------ Hodge / topology
    @cached_property
    def _exact_solver(self) -> _hodge.ExactPartSolver:
        return _hodge.ExactPartSolver(self.d01, self.star1.diagonal(), self.n_vertices, self._F)

    def exact_part_solver(self) -> _hodge.ExactPartSolver:
        """The cached factorization of ``d01^T star1 d01 = -cotmatrix()`` with one vertex per
        connected component pinned (shared by the Hodge decomposition and the heat method)."""
        return self._exact_solver

    def hodge(self) -> _hodge.HodgeDecomposition:
        """``zeta = d01 z + omega`` with ``omega`` harmonic (paper Eq. 3).

        ``z`` minimises ``||d01 z - zeta||_star1`` and has zero area-weighted mean on each
        connected component; ``omega`` is closed and co-closed (``d01^T star1 omega = 0``).
        """
        return self._hodge

    @cached_property
    def _hodge(self) -> _hodge.HodgeDecomposition:
        z = self._exact_solver.potential(np.asarray(self._zeta), self.star0.diagonal())
        omega = np.asarray(self._zeta) - self.d01 @ z
        return _hodge.HodgeDecomposition(_readonly(z), _readonly(omega))

    @cached_property
    def _generators(self) -> list[tuple[np.ndarray, np.ndarray]]:
        # Purely combinatorial (unit weights) so that the basis, and so the meaning of
        # periods(), survives with_periods, with_xy and smoothing of the same connectivity.
        return topo.generator_loops(self._edges, self._face_edges, self.n_vertices)

    def homology_generators(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Closed edge loops generating first homology (tree-cotree), ``(edges, signs)`` each.

        There are ``2g + b - 1`` loops per connected component with boundary (``b`` boundary
        loops, all but one of which are generators), ``2g`` per closed component.
        """
        return list(self._generators)

    def with_generators(self, loops) -> Mescher:
        """The same mescher with ``periods()`` measured around the given homology loops.

        Derived meschers (subdivided, smoothed, ``with_*``) keep their parent's loops by
        themselves; this is for loops from elsewhere (a file, another mescher's refined basis).

        Parameters
        ----------
        loops : sequence of ``(edges (k,) int, signs (k,) float)``
            Closed edge loops (``signs`` +-1: along or against the stored edge direction), as
            many as :meth:`homology_generators` returns.  Their independence in homology is
            checked when :meth:`harmonic_basis` is first needed.

        Raises
        ------
        MescherError
            Wrong count, indices out of range, signs other than +-1, or a loop that is not
            closed (naming the loop).
        """
        k = topo.tree_cotree(self._edges, self._face_edges, self.n_vertices).size
        loops = list(loops)
        if len(loops) != k:
            raise MescherError(f"loops: expected {k} homology loops, found {len(loops)}")
        out = []
        for i, (e, sg) in enumerate(loops):  # a handful of loops, each vectorised
            e = as_int_array(e, f"loops[{i}] edges", 1)
            sg = as_vector(sg, f"loops[{i}] signs", e.size)
            if e.size == 0 or e.min() < 0 or e.max() >= self.n_edges:
                raise MescherError(
                    f"loops[{i}]: expected edge indices in [0, {self.n_edges}), found "
                    f"{'none' if e.size == 0 else f'{int(e.min())}..{int(e.max())}'}"
                )
            if not np.all(np.abs(sg) == 1.0):
                raise MescherError(
                    f"loops[{i}]: expected signs +1 or -1, found {sg[np.abs(sg) != 1][:3]}"
                )
            boundary = self.d01[e].T @ sg  # net flow through each vertex: 0 on a closed loop
            if np.any(boundary != 0):
                raise MescherError(
                    f"loops[{i}]: expected a closed edge loop, found it open at vertices "
                    f"{np.flatnonzero(boundary)[:4].tolist()}"
                )
            out.append((e, sg))
        m = self._replace()
        m.__dict__["_generators"] = out
        return m

    @cached_property
    def _loop_matrix(self) -> sp.csr_matrix:
        return _hodge.loop_matrix(self._generators, self.n_edges)

    def harmonic_basis(self) -> np.ndarray:
        """(#E, k) harmonic 1-forms ``h_j`` dual to the generators: period of ``h_j`` on loop i
        is ``delta_ij``.  ``omega == harmonic_basis() @ periods()``."""
        return self._harmonic_basis

    @cached_property
    def _harmonic_basis(self) -> np.ndarray:
        H = _hodge.harmonic_basis(self._closed_projector, self._exact_solver, self._loop_matrix)
        return _readonly(H)

    def periods(self) -> np.ndarray:
        """(k,) depth gained going once around each homology generator (``Gamma @ zeta``)."""
        return np.asarray(self._loop_matrix @ np.asarray(self._zeta))

    def is_impossible(self, tol: float | None = None, order=None):
        """True when some period is non-zero (``omega != 0``): the mescher cannot embed in 3D.

        ``tol`` is relative to the model's size (default ``IMPOSSIBLE_RTOL``).  With a depth
        ``order``, also impossible when zeta integrates but no depth offset per connected part
        lets the bent embedding realise the order; the answer is then an
        :class:`~meschers_igl.impossibility.Impossibility` (truthy when impossible) whose
        ``kind`` says which: ``"zeta"``, ``"order"`` or ``None``.
        """
        if order is not None:
            from .impossibility import impossibility

            return impossibility(self, order, tol)
        tol = IMPOSSIBLE_RTOL if tol is None else float(tol)
        p = self.periods()
        return bool(p.size and np.abs(p).max() > tol * self.scale())

    def with_periods(self, values) -> Mescher:
        """The same surface with its harmonic part replaced so the periods equal ``values``.

        ``zeta' = d01 z + H @ values``: the exact part (and so the local shape) is kept.  An
        ordinary torus with ``values = (c, 0)`` climbs by ``c`` per turn: an impossible torus.
        """
        k = self._loop_matrix.shape[0]
        values = as_vector(values, "values", k)
        zeta = self.d01 @ self.hodge().z + self.harmonic_basis() @ values
        return self._replace(zeta=zeta)

    # ------------------------------------------------------------------ processing
    def subdivide(
        self,
        levels: int = 1,
        scheme: str = "midpoint",
        order=None,
        return_matrix: bool = False,
        return_face_parent: bool = False,
        force: bool = False,
    ):
        """1-to-4 subdivision, ``levels`` times (paper Sec. 4.2; :mod:`.subdivision`).

        Parameters
        ----------
        levels : int, default: 1
        scheme : {"midpoint", "loop"}
            ``"midpoint"``: xy midpoints, child zeta half the parallel parent edge's.
            ``"loop"``: Loop subdivision of the covering (of the surface a person sees).
            Both keep local integrability and the periods (in this mescher's homology basis);
            original vertices keep their indices.
        order : DepthOrder, optional
            Carried to the children and returned: parents' arcs where children overlap
            (``order.refine`` for midpoint subdivision; for Loop, whose moved xy create
            overlaps, :func:`meschers_igl.smoothing.follow_sheets`: a new overlap continues the
            order of the sheets next to it, local depth only where none reaches).
        return_matrix : bool
            Also return the (#V_child, #V) 0-form subdivision matrix.
        return_face_parent : bool
            Also return the (#F_child,) parent face of each child face.
        force : bool, default: False
            Skip the memory check: by default a result that would not fit in memory
            (``#F * 4**levels`` faces) is refused up front with a :class:`MescherError`.

        Returns
        -------
        Mescher, followed by the order, the matrix and the face parents when asked for.
        """
        from .smoothing import follow_sheets

        m = self
        S_total = sp.identity(self.n_vertices, format="csr")
        parent_total = np.arange(self.n_faces)
        steps = _sub.subdivide_levels(
            self._F,
            self._xy,
            self._edges,
            self._face_edges,
            self._signs,
            self._zeta,
            self._generators,
            levels,
            scheme,
            force=force,
        )
        for lvl in steps:
            m = type(self)._trusted(lvl.F, lvl.xy, lvl.edges, lvl.zeta, lvl.face_edges, lvl.signs)
            m.__dict__["_generators"] = lvl.generators  # the parent's basis, refined
            if order is not None:
                # Midpoint children lie inside their parents on screen, so the parents' arcs
                # are all there is to carry (refine, 4x faster than follow at 1M faces); Loop
                # moves xy and creates overlaps, which continue the order of the sheets next
                # to them (follow_sheets; local depth would flip it inside a sheet).
                order = (
                    order.refine(lvl.face_parent, m)
                    if scheme == "midpoint"
                    else follow_sheets(order, m, lvl.face_parent)
                )
            if return_matrix:
                S_total = (lvl.S @ S_total).tocsr()
            parent_total = parent_total[lvl.face_parent]
        out = [m]
        if order is not None:
            out.append(order)
        if return_matrix:
            out.append(S_total)
        if return_face_parent:
            out.append(parent_total)
        return out[0] if len(out) == 1 else tuple(out)

    def smooth(self, t_xy: float = 0.0, t_zeta: float = 0.0, iterations: int = 1, order=None):
        """Laplacian smoothing of xy and of the exact part of zeta (paper Sec. 4.4).

        The harmonic part and so every period is unchanged; ``smooth(0, 0)`` is the identity.
        See :func:`meschers_igl.smoothing.smooth`.  With a :class:`DepthOrder`, returns
        ``(mescher, follow_sheets(order, mescher))``: smoothing xy moves overlaps, and a new
        overlap continues the order of the two sheets next to it
        (:func:`meschers_igl.smoothing.follow_sheets`), so a crossing keeps its order.
        """
        from .smoothing import follow_sheets, smooth

        m = smooth(self, t_xy=t_xy, t_zeta=t_zeta, iterations=iterations)
        return m if order is None else (m, follow_sheets(order, m))

    def rotated(self, degrees: float, axis="y", order=None):
        """The mescher turned by ``degrees`` about ``axis`` ("x", "y", "z" or a direction).

        Each triangle's local 3D shape is turned; screen positions are re-projected onto
        exact forms (a Poisson solve) and depths onto locally integrable forms, so periods
        become ``R[2, 2] * periods()`` in this mescher's basis.  The identity at 0 degrees; a
        mescher that embeds turns exactly like its 3D mesh.  With a :class:`DepthOrder`,
        returns ``(mescher, order.follow(mescher))``.  See :func:`meschers_igl.rotation.rotate`.
        """
        from .rotation import rotate

        turn = rotate(self, degrees, axis, order=order)
        return turn.mescher if order is None else (turn.mescher, turn.order)

    def bent_embedding(self) -> tuple[np.ndarray, np.ndarray]:
        """``(V, F)``: 3D mesh with depth ``z`` from the Hodge decomposition (paper Sec. 4.6)."""
        from .embedding import bent_embedding

        return bent_embedding(self)

    def cut_embedding(self, cut_edges=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(V, F, vmap)``: 3D mesh integrated on the mescher cut open (paper Sec. 4.6).

        Default cut: exactly where breadth-first integration disagrees (a seam across each
        impossible loop); across it the depth jumps by the period.
        """
        from .embedding import cut_embedding

        return cut_embedding(self, cut_edges=cut_edges)

    def straight_cut(self, order=None, **kwargs):
        """Where an artist would cut this mescher: one straight screen line across one bar.

        Returns a :class:`~meschers_igl.embedding.StraightCut` (``.mescher`` split along the
        line, ``.cut_edges``, ``.jump``); ``cut.mescher.cut_embedding(cut.cut_edges)`` is a cut
        model whose seam is that line and whose jump is the period.  See
        :func:`meschers_igl.embedding.straight_cut` (``order`` picks the cut whose z-buffered
        model shows what the mescher shows in that order).
        """
        from .embedding import straight_cut

        return straight_cut(self, order, **kwargs)

    def heat_diffuse(self, u0, t: float, steps: int = 1) -> np.ndarray:
        """Backward Euler heat diffusion ``(M - tL) u = M u0`` (paper Eq. 5)."""
        from .geodesic import heat_diffuse

        return heat_diffuse(self, u0, t, steps=steps)

    def geodesic_distance(self, sources, method: str = "auto", **kwargs) -> np.ndarray:
        """(#V,) geodesic distance to the nearest source (one-off), by any registered method.

        See :func:`meschers_igl.geodesic.geodesic_distance` (default: the heat method,
        ``method="exact"``: window propagation).
        """
        from .geodesic import geodesic_distance

        return geodesic_distance(self, sources, method, **kwargs)

    def shortest_path(self, source: int, target: int, **kwargs):
        """A shortest polyline on the surface from ``source`` to ``target`` vertex."""
        from .geodesic import shortest_path

        return shortest_path(self, source, target, **kwargs)
