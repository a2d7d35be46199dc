"""The depth order of a mescher's faces (paper Sec. 3.5, "Depth Ordering"; rendering Sec. 4.1).

A mescher stores relative depth only *along* its surface.  Where two parts of the surface
overlap on screen, which one is in front is a separate piece of data: a directed graph over
faces with an arc ``i -> j`` when face ``i`` is perceived *behind* face ``j``.  The order is
partial -- only faces that overlap on screen are related -- so it never asks for one absolute
depth of an impossible object.  Rendering draws the faces in a linear extension of the order
(a topological sort), back to front.

The arcs live in an ``(k, 2)`` int64 array; :attr:`DepthOrder.graph` is a networkx view for
users and cycle reports.  Sorting, cycle detection and feedback-arc breaking work on the arrays
(:mod:`meschers_igl.order_graph`): building a networkx ``DiGraph`` for 1M faces alone takes
11-20 s, while Kahn's algorithm on CSR sorts it in under a second.  Which faces
overlap on screen, and where, comes from :mod:`meschers_igl.geometry2d` (compiled kernels in
:mod:`meschers_igl.overlap`).  Operations that move screen positions carry the order with
:meth:`DepthOrder.follow`.
"""

from __future__ import annotations

import warnings
from typing import Any

import networkx as nx
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from . import overlap
from .errors import MescherError, MescherWarning
from .geometry2d import (
    TOL_FACTOR,
    default_tol,
    model_scale,
    overlapping_pairs,
    triangle_heights,
)
from .order_graph import (
    canonical_arcs,
    feedback_arc_set,
    format_cycles,
    in_sorted,
    path_integrals,
    reconcile_arcs,
    shortest_cycle_through,
    strong_components,
    subgraph_arcs,
    topological_sort,
)
from .topology import (
    edge_faces,
    integrate_one_form,
    spanning_forest,
)
from .validate import as_count, as_float_array, as_index_array, as_int_array, as_positive

__all__ = ["DepthOrder"]

# zeta is treated as exact (path-independent) when a spanning forest's potential reproduces it
# to this relative accuracy (float64 round-off accumulated along long tree paths stays far below).
_EXACT_RTOL = 1e-9
# from_local_depth on impossible meschers: exact shortest paths (one Dijkstra per source vertex,
# stopped at its targets) while #sources * #V stays below this; shared patch seeds beyond.
_EXACT_PATH_WORK = 30_000_000
# refine: child pairs tested per parent arc directly while their number stays below this many
# per child face (plus a constant); beyond it (parents with very many children) the grid.
_REFINE_WORK_PER_CHILD = 64
_REFINE_WORK_MIN = 1_000_000


# ---------------------------------------------------------------------------------- helpers
def _screen(m: Any, name: str = "m") -> tuple[np.ndarray, np.ndarray]:
    """``(F, xy)`` of a mescher-like object, or a clear error."""
    try:
        F, xy = np.asarray(m.F), np.asarray(m.xy)
    except AttributeError:
        raise MescherError(
            f"{name}: expected a Mescher (with F and xy), found {type(m).__name__}"
        ) from None
    return F, xy


def _tol(tol: Any, T: np.ndarray) -> float:
    return default_tol(T) if tol is None else as_positive(tol, "tol", allow_zero=True)


def _arcs_from_depths(pairs: np.ndarray, dz: np.ndarray, tol: float) -> np.ndarray:
    """Arc ``i -> j`` where ``dz = depth_j - depth_i > tol``, ``j -> i`` where ``dz < -tol``."""
    return overlap.arcs_from_depths(np.ascontiguousarray(pairs), np.ascontiguousarray(dz), tol)


def _depth_change(cen: np.ndarray, pairs: np.ndarray, T: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """``z_j(c) - z_i(c)`` for pairs ``(i, j)``: corner depths ``Z (n, 3)`` of faces ``T (n, 3, 2)``
    interpolated (barycentric) at the points ``cen (k, 2)``."""
    # writable C arrays always: a read-only one would be another type to numba, compiled again
    T, Z, cen = (np.require(a, np.float64, ["C", "W"]) for a in (T, Z, cen))
    zj = overlap.barycentric_depths(cen, T, Z, np.ascontiguousarray(pairs[:, 1]))
    return zj - overlap.barycentric_depths(cen, T, Z, np.ascontiguousarray(pairs[:, 0]))


# ---------------------------------------------------------------------------------- class
class DepthOrder:
    """A partial depth order over the faces of a mescher (paper Sec. 3.5).

    Parameters
    ----------
    n_faces : int
        Number of faces; the graph's nodes are ``0 .. n_faces - 1``.
    arcs : (k, 2) array_like of int, optional
        Arcs ``(i, j)``: face ``i`` is behind face ``j``.  Duplicates are merged; a self-loop
        or an index out of range raises :class:`MescherError`.
    m : Mescher, optional
        The mescher whose faces these are.  Only :meth:`put_in_front` uses it (to find which
        faces overlap on screen); the constructors below set it.

    Notes
    -----
    The order is a set of arcs: two orders are equal (``==``) when they have the same number of
    faces and the same arcs.  :meth:`put_in_front` is the only method that changes an order
    (in place); :meth:`refine` returns a new one.
    """

    __hash__ = None  # mutable (put_in_front)

    def __init__(self, n_faces: int, arcs: Any = None, *, m: Any = None):
        self._n = as_count(n_faces, "n_faces")
        self._arcs = canonical_arcs(arcs, self._n)
        self._arcs.flags.writeable = False
        if m is not None:
            F, _ = _screen(m)
            if F.shape[0] != self._n:
                raise MescherError(
                    f"m: expected a mescher with {self._n} faces (n_faces), "
                    f"found {F.shape[0]} faces"
                )
        self._m = m
        self._graph: nx.DiGraph | None = None

    # ------------------------------------------------------------------ basic access
    @property
    def n_faces(self) -> int:
        """Number of faces (graph nodes)."""
        return self._n

    @property
    def arcs(self) -> np.ndarray:
        """(k, 2) int64 read-only arcs ``(behind, in front)``, unique and sorted."""
        return self._arcs

    @property
    def n_arcs(self) -> int:
        """Number of arcs."""
        return int(self._arcs.shape[0])

    @property
    def graph(self) -> nx.DiGraph:
        """The order as a frozen ``networkx.DiGraph``: nodes ``0 .. n_faces-1``, arc ``i -> j``
        when face ``i`` is behind face ``j``.

        Built on first access (slow for millions of faces); frozen because it is a
        view: change the order with :meth:`put_in_front` or build a new ``DepthOrder``.
        """
        if self._graph is None:
            G = nx.DiGraph()
            G.add_nodes_from(range(self._n))
            G.add_edges_from(self._arcs.tolist())
            self._graph = nx.freeze(G)
        return self._graph

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DepthOrder):
            return NotImplemented
        return self._n == other._n and np.array_equal(self._arcs, other._arcs)

    def __repr__(self) -> str:
        return f"DepthOrder(n_faces={self._n}, n_arcs={self.n_arcs})"

    def copy(self) -> DepthOrder:
        """An independent copy (same arcs and mescher)."""
        return DepthOrder(self._n, self._arcs, m=self._m)

    # ------------------------------------------------------------------ persistence
    def to_arrays(self) -> tuple[int, np.ndarray]:
        """``(n_faces, arcs)`` for saving: ``from_arrays(*order.to_arrays()) == order``."""
        return self._n, self._arcs.copy()

    @classmethod
    def from_arrays(cls, n_faces: int, arcs: Any, *, m: Any = None) -> DepthOrder:
        """Inverse of :meth:`to_arrays` (arcs validated like the constructor's)."""
        if isinstance(n_faces, np.ndarray) and n_faces.ndim == 0:
            n_faces = n_faces.item()  # np.load gives 0-d arrays
        return cls(n_faces, arcs, m=m)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_embedding(cls, m: Any, Zc: Any, *, tol: float | None = None) -> DepthOrder:
        """The order of a cut embedding: which of two overlapping faces is nearer the viewer.

        Faces ``i`` and ``j`` get an arc only when their screen triangles ``m.xy[m.F]`` overlap
        with positive area (penetration above ``tol``; touching along an edge or at a vertex is
        not overlapping).  Let ``c`` be the centroid of the intersection polygon and
        ``z_f(c) = sum_k b_k(c) Zc[f, k]`` the depth of face ``f`` interpolated there
        (barycentric ``b``); since depth is linear on each face, ``z_j(c) - z_i(c)`` is the mean
        depth difference over the whole overlap.  The arc is ``i -> j`` when it is above ``tol``
        (``j`` in front), ``j -> i`` below ``-tol``, and there is none in between (faces that
        cross in 3D at their overlap's centroid).

        Parameters
        ----------
        m : Mescher
            Supplies ``F`` (#F, 3) and ``xy`` (#V, 2).
        Zc : (#F, 3) array_like of float
            Absolute camera-space depth of each face's corners in the cut embedding (larger is
            nearer the viewer), e.g. ``(V @ R.T)[F][:, :, 2]``.
        tol : float, optional
            Length tolerance for overlaps and depth differences; default
            ``16 * float32 eps * model size`` (float32 round-off of a seam creates no arc).

        Returns
        -------
        DepthOrder
        """
        F, xy = _screen(m)
        Zc = as_float_array(Zc, "Zc", (F.shape[0], 3))
        T = xy[F]
        tol = _tol(tol, T)
        pairs, cen = overlapping_pairs(T, tol, centroids=True)
        dz = _depth_change(cen, pairs, T, Zc)
        ztol = max(tol, TOL_FACTOR * float(np.abs(Zc).max(initial=0.0)))
        return cls(F.shape[0], _arcs_from_depths(pairs, dz, ztol), m=m)

    @classmethod
    def from_local_depth(
        cls,
        m: Any,
        *,
        tol: float | None = None,
        radius: float | None = None,
        _force_paths: bool = False,
    ) -> DepthOrder:
        """The order from the mescher's own relative depths, for meschers without a cut model.

        For each pair of faces ``i, j`` overlapping on screen (as in :meth:`from_embedding`)
        the depth difference at the overlap's centroid ``c`` is

        ``dz = integral of zeta along a short path v_i -> v_j + z_j(c) - z_i(c)``,

        with ``v_f`` corner 0 of face ``f`` and ``z_f(c)`` the local depth in face ``f``
        (``m.corner_depths()``, corner 0 at 0) interpolated at ``c``.  ``dz > tol`` gives
        ``i -> j``, ``dz < -tol`` gives ``j -> i``.  Faces in different connected components
        have no path between them and get no arc.

        The path is a shortest path in the vertex graph weighted by the *local 3D* edge length
        ``sqrt(|dxy|^2 + zeta^2)``, the surface's own metric (a screen-length metric would let a
        path climb steep, nearly edge-on strips for free).  On a globally integrable mescher the
        integral does not depend on the path at all, and one spanning forest gives every pair
        (``dz = phi(v_j) - phi(v_i) + ...`` with ``phi`` zeta integrated from a root).  On an
        impossible mescher it depends on the path's homotopy class, so the paths are real
        shortest paths: one ``scipy.sparse.csgraph.dijkstra`` tree per source vertex ``v_i``
        (blocks of sources per call), zeta integrated along each tree by pointer jumping.  When
        ``#sources * #V`` exceeds 3e7, or ``radius`` is given, sources share trees: the faces on
        the ``i`` side are grouped into patches (mesh-connected faces within a screen cell of
        size ``radius``), one tree grows from each patch's seed and each pair is integrated from
        ``v_i`` back to the seed, then out to ``v_j`` -- a path within about ``radius`` of the
        shortest one.

        Pairs whose two shortest paths of different homotopy class have (nearly) the same length
        are ambiguous by nature: the percept is unstable there, and which one wins is not
        specified.

        Parameters
        ----------
        m : Mescher
        tol : float, optional
            As in :meth:`from_embedding`.
        radius : float, optional
            Screen size of the patches sharing one Dijkstra tree (impossible meschers only);
            by default exact per-source trees when affordable, else 1/20 of the screen box
            diagonal.  Smaller is more faithful and slower.

        Returns
        -------
        DepthOrder
        """
        F, xy = _screen(m)
        _local_inputs(m)  # a clear error before any work
        n = F.shape[0]
        T = xy[F]
        tol = _tol(tol, T)
        pairs, cen = overlapping_pairs(T, tol, centroids=True)
        if pairs.shape[0] == 0:
            return cls(n, None, m=m)
        dz = _local_depth_changes(m, pairs, cen, radius, _force_paths)
        return cls(n, _arcs_from_depths(pairs, dz, tol), m=m)

    # ------------------------------------------------------------------ editing
    def put_in_front(
        self, front_faces: Any, back_faces: Any, *, m: Any = None, tol: float | None = None
    ) -> DepthOrder:
        """Put one group of faces in front of another, where they overlap on screen.

        For every pair ``(b, f)`` with ``b`` in ``back_faces``, ``f`` in ``front_faces`` whose
        screen triangles overlap with positive area, the arc ``b -> f`` is added; every existing
        arc ``f -> b`` from a front face to a back face (overlapping or not) contradicts the
        request and is removed.  Pairs that do not overlap get no new arc: the order stays
        partial and local (paper Sec. 3.5).  The order is changed **in place**; ``self`` is
        returned so calls can be chained.

        Parameters
        ----------
        front_faces, back_faces : array_like of int
            Disjoint, non-empty groups of face indices.
        m : Mescher, optional
            Mescher providing the screen triangles; default the one this order was built from.
        tol : float, optional
            Overlap tolerance as in :meth:`from_embedding`.

        Returns
        -------
        DepthOrder
            ``self``.
        """
        front = np.unique(as_index_array(front_faces, "front_faces", self._n))
        back = np.unique(as_index_array(back_faces, "back_faces", self._n))
        both = np.intersect1d(front, back)
        if both.size:
            raise MescherError(
                "front_faces, back_faces: expected disjoint groups, found "
                f"{both.size} face(s) in both (first: {int(both[0])})"
            )
        if m is None:
            m = self._m
        if m is None:
            raise MescherError(
                "m: put_in_front needs the screen triangles to find overlapping faces; expected "
                "m=<Mescher> (or an order built by from_embedding / from_local_depth), found None"
            )
        F, xy = _screen(m)
        if F.shape[0] != self._n:
            raise MescherError(
                f"m: expected a mescher with {self._n} faces (n_faces), found {F.shape[0]}"
            )
        T = xy[F]
        is_f = np.zeros(self._n, dtype=bool)
        is_f[front] = True
        is_b = np.zeros(self._n, dtype=bool)
        is_b[back] = True
        pairs, _ = overlapping_pairs(
            T,
            _tol(tol, T),
            faces=np.concatenate((front, back)),
            groups=is_f,  # one face from each group
        )
        i, j = pairs[:, 0], pairs[:, 1]
        new = np.concatenate((pairs[is_b[i] & is_f[j]], pairs[is_f[i] & is_b[j]][:, ::-1]))
        old = self._arcs[~(is_f[self._arcs[:, 0]] & is_b[self._arcs[:, 1]])]
        self._arcs = canonical_arcs(np.concatenate((old, new)), self._n)
        self._arcs.flags.writeable = False
        self._graph = None
        return self

    def refine(self, face_parent: Any, m_child: Any, *, tol: float | None = None) -> DepthOrder:
        """Carry the order to a subdivided mescher.

        Child faces ``a, b`` get the arc ``a -> b`` when their parents had the arc
        ``parent[a] -> parent[b]`` and the children overlap on screen (positive area, as in
        :meth:`from_embedding`).  Children of one parent, or of unrelated parents, stay
        unrelated.  This is complete only when children lie inside their parents on screen
        (midpoint subdivision); where xy moved (Loop), overlaps appear that no parent arc
        covers: :meth:`follow` orders those too.

        Parameters
        ----------
        face_parent : (#F_child,) array_like of int
            Parent face of each child face, in ``[0, n_faces)``.
        m_child : Mescher
            The subdivided mescher (its ``F`` and ``xy``).
        tol : float, optional
            Overlap tolerance as in :meth:`from_embedding`.

        Returns
        -------
        DepthOrder
            A new order over the child faces, attached to ``m_child``.
        """
        F, xy = _screen(m_child, "m_child")
        nc = F.shape[0]
        parent = self._parents(face_parent, nc)
        if self.n_arcs == 0:
            return DepthOrder(nc, None, m=m_child)
        T = np.ascontiguousarray(xy[F], dtype=np.float64)
        tol = _tol(tol, T)
        cnt = np.bincount(parent, minlength=self._n)
        work = int((cnt[self._arcs[:, 0]] * cnt[self._arcs[:, 1]]).sum())
        if work <= _REFINE_WORK_PER_CHILD * nc + _REFINE_WORK_MIN:
            # Children of the two ends of each parent arc, tested directly (compiled): no broad
            # phase needed, and exactly the pairs the grid would find and keep.
            start = np.concatenate(([0], np.cumsum(cnt)))
            children = np.argsort(parent, kind="stable")
            ok = triangle_heights(T) > tol
            arcs = overlap.child_pairs(T, ok, self._arcs, start, children, tol)
        else:  # a few parents with very many children: the grid, then keep ordered parents
            n = np.int64(self._n)
            keys = self._arcs[:, 0] * n + self._arcs[:, 1]  # sorted (canonical arcs)
            related = np.isin(parent, self._arcs)  # only children of faces with arcs
            pairs, _ = overlapping_pairs(T, tol, faces=np.flatnonzero(related))
            pa, pb = parent[pairs[:, 0]], parent[pairs[:, 1]]
            fwd = in_sorted(keys, pa * n + pb)
            bwd = in_sorted(keys, pb * n + pa)
            arcs = np.concatenate((pairs[fwd], pairs[bwd][:, ::-1]))
        return DepthOrder(nc, arcs, m=m_child)

    def follow(
        self,
        m_new: Any,
        face_parent: Any = None,
        *,
        tol: float | None = None,
        radius: float | None = None,
    ) -> DepthOrder:
        """The order carried to a mescher whose screen positions moved (paper Sec. 3.5, 4.2).

        Loop subdivision, xy smoothing, :meth:`Mescher.with_xy` and inverse rendering move
        screen positions, so faces start or stop overlapping.  For each pair of faces ``a, b``
        of ``m_new`` that overlap on screen (positive area, as in :meth:`from_embedding`):

        * when their parents (``face_parent``; the faces themselves by default) have an arc
          ``parent[a] -> parent[b]``, the pair gets ``a -> b`` (and ``b -> a`` for the reverse
          arc): the order is carried;
        * otherwise -- an overlap that appeared, or one between children of one face -- the pair
          is ordered from local depth (:meth:`from_local_depth`'s rule on ``m_new``), unless
          that would close a cycle with the carried arcs: then the carried arcs win
          (:func:`meschers_igl.order_graph.reconcile_arcs`: such an arc is reversed when the
          carried arcs imply the reverse, else dropped).

        Pairs that no longer overlap get no arc: overlaps that vanish drop their arcs.  With
        ``m_new`` equal to the order's mescher and no parents this returns the order restricted
        to overlapping pairs, plus local-depth arcs for overlapping pairs it left unordered.

        Parameters
        ----------
        m_new : Mescher
            The mescher after the move (its ``F``, ``xy`` and, for new overlaps, its depths).
        face_parent : (#F_new,) array_like of int, optional
            Face of this order's mescher each face of ``m_new`` comes from (subdivision);
            default: the same faces (``m_new`` must then have ``n_faces`` faces).
        tol : float, optional
            Overlap tolerance as in :meth:`from_embedding`.
        radius : float, optional
            As in :meth:`from_local_depth`.

        Returns
        -------
        DepthOrder
            A new order over the faces of ``m_new``, attached to it.
        """
        F, xy = _screen(m_new, "m_new")
        nc = F.shape[0]
        if face_parent is None:
            if nc != self._n:
                raise MescherError(
                    f"m_new: expected a mescher with {self._n} faces (n_faces) when no "
                    f"face_parent is given, found {nc}"
                )
            parent = np.arange(nc, dtype=np.int64)
        else:
            parent = self._parents(face_parent, nc)
        T = np.ascontiguousarray(xy[F], dtype=np.float64)
        tol = _tol(tol, T)
        pairs, cen = overlapping_pairs(T, tol, centroids=True)
        n = np.int64(self._n)
        pa, pb = parent[pairs[:, 0]], parent[pairs[:, 1]]
        if self.n_arcs:
            keys = self._arcs[:, 0] * n + self._arcs[:, 1]  # sorted (canonical arcs)
            fwd, bwd = in_sorted(keys, pa * n + pb), in_sorted(keys, pb * n + pa)
        else:
            fwd = bwd = np.zeros(pairs.shape[0], dtype=bool)
        carried = np.concatenate((pairs[fwd], pairs[bwd][:, ::-1]))
        new = np.flatnonzero(~(fwd | bwd))
        if new.size == 0:
            return DepthOrder(nc, carried, m=m_new)
        _local_inputs(m_new)
        dz = _local_depth_changes(m_new, pairs[new], cen[new], radius)
        # local depth must not overrule the carried order (on an impossible figure the two can
        # disagree): new arcs that close a cycle with carried ones are reversed or dropped
        local = reconcile_arcs(nc, carried, _arcs_from_depths(pairs[new], dz, tol))
        return DepthOrder(nc, np.concatenate((carried, local)), m=m_new)

    def _parents(self, face_parent: Any, nc: int) -> np.ndarray:
        """Validated ``face_parent``: one face of this order per child face."""
        parent = as_int_array(face_parent, "face_parent", 1)
        if parent.shape[0] != nc:
            raise MescherError(
                f"face_parent: expected one parent per child face ({nc}, the faces of the new "
                f"mescher), found {parent.shape[0]}"
            )
        if nc and (parent.min() < 0 or parent.max() >= self._n):
            bad = parent[(parent < 0) | (parent >= self._n)][0]
            raise MescherError(
                f"face_parent: expected parent faces in [0, {self._n}), found {int(bad)}"
            )
        return parent

    # ------------------------------------------------------------------ analysis
    def cycles(self, *, warn: bool = True) -> list[list[int]]:
        """Cycles of the order, one per strongly connected group of faces; never raises.

        A cycle means no drawing order can honour every arc (e.g. three long faces each partly
        over the next).  Each strongly connected component with more than one face is reported
        by a shortest cycle through its lowest-numbered face.

        Parameters
        ----------
        warn : bool, default: True
            Emit a :class:`MescherWarning` naming the faces of each cycle when there is any.

        Returns
        -------
        list of list of int
            ``[f0, f1, ..., fk]`` with arcs ``f0 -> f1 -> ... -> fk -> f0`` (each face behind the
            next); empty for an acyclic order.
        """
        out = []
        for comp in strong_components(self._n, self._arcs):
            sub = subgraph_arcs(self._arcs, comp, self._n)
            out.append(comp[shortest_cycle_through(comp.size, sub)].tolist())
        if out and warn:
            warnings.warn(
                f"depth order has {len(out)} cycle(s) of faces, each face behind the next: "
                f"{format_cycles(out)}; linear_extension() breaks the fewest arcs it can",
                MescherWarning,
                stacklevel=2,
            )
        return out

    def feedback_arcs(self) -> np.ndarray:
        """(r, 2) int64 arcs :meth:`linear_extension` breaks: empty for an acyclic order.

        Found by the Eades-Lin-Smyth greedy heuristic in each strongly connected component,
        then made minimal (no arc of the set can be restored without closing a cycle).
        """
        order, complete = topological_sort(self._n, self._arcs)
        if complete:
            return np.zeros((0, 2), dtype=np.int64)
        return feedback_arc_set(self._n, self._arcs)

    def linear_extension(self, *, warn: bool = True) -> np.ndarray:
        """A back-to-front drawing order of all faces.

        On an acyclic order, a topological sort (Kahn's algorithm, a level at a time on a CSR
        adjacency): for every arc ``i -> j``, ``i`` comes before ``j``.  With cycles, the arcs of
        :meth:`feedback_arcs` are dropped first (and a :class:`MescherWarning` names them), so
        every other arc is still honoured.

        Returns
        -------
        (#F,) int64
            A permutation of ``0 .. n_faces-1``; draw ``faces[order]`` in sequence.
        """
        order, complete = topological_sort(self._n, self._arcs)
        if complete:
            return order
        fas = feedback_arc_set(self._n, self._arcs)
        keys = self._arcs[:, 0] * np.int64(self._n) + self._arcs[:, 1]
        drop = np.isin(keys, fas[:, 0] * np.int64(self._n) + fas[:, 1])
        order, complete = topological_sort(self._n, self._arcs[~drop])
        if not complete:  # cannot happen: feedback_arc_set leaves a DAG
            raise RuntimeError("internal error: the depth order is still cyclic after breaking")
        if warn:
            shown = ", ".join(f"{a}->{b}" for a, b in fas[:10].tolist())
            more = f" and {fas.shape[0] - 10} more" if fas.shape[0] > 10 else ""
            warnings.warn(
                f"depth order has cycles; the drawing order breaks {fas.shape[0]} of its "
                f"{self.n_arcs} arcs (behind->front): {shown}{more}",
                MescherWarning,
                stacklevel=2,
            )
        return order


def _local_inputs(m: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(edges, zeta, corner_depths)`` of a mescher, or a clear error."""
    try:
        return np.asarray(m.edges), np.asarray(m.zeta), np.asarray(m.corner_depths())
    except AttributeError:
        raise MescherError(
            f"m: expected a Mescher (with edges, zeta, corner_depths), found {type(m).__name__}"
        ) from None


def _local_depth_changes(
    m: Any, pairs: np.ndarray, cen: np.ndarray, radius: float | None, force_paths: bool = False
) -> np.ndarray:
    """Depth change ``dz`` from face ``i`` to face ``j`` at the centroid of each pair's overlap,
    from the mescher's own relative depths (see :meth:`DepthOrder.from_local_depth`).

    Pairs in different connected components have no path between them: ``dz = 0`` (no arc).
    """
    F, xy = _screen(m)
    edges, zeta, Zl = _local_inputs(m)
    nv = xy.shape[0]
    T = np.ascontiguousarray(xy[F], dtype=np.float64)
    dz = np.zeros(pairs.shape[0])
    w = np.sqrt(((xy[edges[:, 1]] - xy[edges[:, 0]]) ** 2).sum(axis=1) + zeta**2)
    w = np.maximum(w, 1e-12 * model_scale(xy))  # csgraph would drop zero-length edges
    G = sp.csr_matrix(
        (
            np.concatenate((w, w)),
            (
                np.concatenate((edges[:, 0], edges[:, 1])),
                np.concatenate((edges[:, 1], edges[:, 0])),
            ),
        ),
        shape=(nv, nv),
    )
    ncomp, comp = csgraph.connected_components(G, directed=False)
    vi, vj = F[pairs[:, 0], 0], F[pairs[:, 1], 0]
    sel = np.flatnonzero(comp[vi] == comp[vj]) if ncomp > 1 else np.arange(pairs.shape[0])
    if sel.size < pairs.shape[0]:
        pairs, cen, vi, vj = pairs[sel], cen[sel], vi[sel], vj[sel]
    local = _depth_change(cen, pairs, T, Zl)
    # One spanning forest (a tree per component): exact when zeta is exact.
    roots = np.unique(comp, return_index=True)[1]
    phi = integrate_one_form(edges, zeta, nv, spanning_forest(G, roots))
    resid = zeta - (phi[edges[:, 1]] - phi[edges[:, 0]])
    scale = max(model_scale(xy), float(np.abs(phi).max()))
    if np.abs(resid).max(initial=0.0) <= _EXACT_RTOL * scale and not force_paths:
        dz[sel] = phi[vj] - phi[vi] + local
    else:
        dz[sel] = local + _path_depths(m, w, F, T, pairs, vi, vj, radius)
    return dz


def _path_depths(
    m: Any,
    w: np.ndarray,
    F: np.ndarray,
    T: np.ndarray,
    pairs: np.ndarray,
    vi: np.ndarray,
    vj: np.ndarray,
    radius: float | None,
) -> np.ndarray:
    """zeta integrated from ``vi`` to ``vj`` along short paths (impossible meschers).

    A shortest-path search from a seed vertex ``s`` (edge lengths ``w``) gives ``phi_s(v)``,
    zeta integrated from ``s`` to ``v`` along the path, and the pair's depth change is
    ``phi_s(v_j) - phi_s(v_i)`` (:func:`meschers_igl.order_graph.path_integrals`: one compiled
    Dijkstra per seed, stopped once its targets are settled).  When the work allows
    (``#sources * #V <= _EXACT_PATH_WORK`` and no ``radius``), every source ``v_i`` is its own
    seed: exact shortest paths.  Otherwise seeds are shared by patches (:func:`_patch_seeds`).
    """
    nv = np.asarray(m.xy).shape[0]
    edges, zeta = np.asarray(m.edges), np.asarray(m.zeta)
    sources = np.unique(vi)
    if radius is None and sources.size * nv <= _EXACT_PATH_WORK:
        # few enough sources: a search per source vertex, i.e. exact shortest paths
        seeds, seed_of_pair = sources, np.searchsorted(sources, vi)
    else:
        seeds, seed_of_pair = _patch_seeds(m, F, T, pairs, radius)
    srt = np.argsort(seed_of_pair, kind="stable")
    tstart = 2 * np.concatenate(([0], np.cumsum(np.bincount(seed_of_pair, minlength=seeds.size))))
    target = np.stack((vi[srt], vj[srt]), axis=1).reshape(-1)
    phi = path_integrals(edges, w, zeta, nv, seeds, (tstart, target)).reshape(-1, 2)
    out = np.empty(pairs.shape[0])
    out[srt] = phi[:, 1] - phi[:, 0]
    return np.nan_to_num(out, nan=0.0)  # unreachable (other component): no arc


def _patch_seeds(
    m: Any, F: np.ndarray, T: np.ndarray, pairs: np.ndarray, radius: float | None
) -> tuple[np.ndarray, np.ndarray]:
    """One seed vertex per patch of ``i``-side faces, and the seed index of each pair.

    A patch is a set of faces connected through shared mesh edges within one screen cell of
    size ``radius``, so that the path ``v_i -> seed -> v_j`` stays close to the shortest one.
    """
    n = F.shape[0]
    xy = np.asarray(m.xy)
    if radius is None:
        radius = float(np.linalg.norm(xy.max(axis=0) - xy.min(axis=0))) / 20.0 or 1.0
    else:
        radius = as_positive(radius, "radius")
    fi = np.unique(pairs[:, 0])
    cell_of = np.full((n, 2), -1, dtype=np.int64)
    cell_of[fi] = np.floor((T[fi].mean(axis=1) - xy.min(axis=0)) / radius).astype(np.int64)
    member = np.zeros(n, dtype=bool)
    member[fi] = True
    ef = edge_faces(np.asarray(m.face_edges), int(np.asarray(m.edges).shape[0]))
    ef = ef[(ef >= 0).all(axis=1)]
    same = (cell_of[ef[:, 0]] == cell_of[ef[:, 1]]).all(axis=1)
    link = ef[member[ef[:, 0]] & member[ef[:, 1]] & same]
    A = sp.csr_matrix((np.ones(link.shape[0]), (link[:, 0], link[:, 1])), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    patches, first = np.unique(lab[fi], return_index=True)
    return F[fi[first], 0], np.searchsorted(patches, lab[pairs[:, 0]])
