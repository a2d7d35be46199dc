"""Exact geodesic distance by window propagation on the intrinsic mesh (compiled).

**Algorithm.** Chen-Han window propagation with Xin & Wang's improvements ("ICH": Xin, Wang
2009, "Improving Chen and Han's algorithm on the discrete geodesic problem", ACM TOG 28(4)),
run on the *intrinsic* mesh: faces, their edge lengths and which faces share an edge.  Nothing
else is needed, so it runs on an impossible mescher as it is (a mescher is locally Euclidean:
unfolding a window across an edge uses the two faces' edge lengths only), with no covering.

A *window* is an interval ``[b0, b1]`` of an edge, seen from the face it is about to enter, with
the planar image ``s = (sx, sy)`` (``sy <= 0``) of a source or pseudo-source at distance
``sigma``: ``d(q) = sigma + |s - q|`` on the interval.  Each edge's frame puts its start vertex
at the origin, its end on the positive x-axis and the face being entered at ``y > 0``.  A window
entering face ``ABC`` through ``AB`` gives ``C`` the distance ``sigma + |s - C|`` when ``C`` is
visible through ``[b0, b1]`` and splits into at most two children on ``AC`` and ``CB``, mapped
into the next faces by the rigid motion (or reflection) their shared edge defines.  Saddle
vertices (angle sum > 2 pi) and boundary vertices are pseudo-sources: once their distance is
known they relax their neighbours along edges and emit windows into their *shadow* only: a
shortest path turns by at least ``pi`` on both sides of a vertex it passes (else a shortcut
beside the vertex is shorter), so from a vertex of total angle ``theta`` reached from the ring
direction ``b`` it goes on only in ``[b + pi, b + theta - pi]`` (a wedge of ``theta - 2 pi``; at
a boundary vertex ``[0, b - pi]`` and ``[b + pi, theta]``, nothing when ``theta <= pi``).
Windows and pseudo-source events go through one priority queue keyed by the least distance they
can give, so the vertex distances used for pruning are nearly final when a window is taken out.

**Pruning.** Each rule removes a part of a window only where a known path is *strictly* shorter
(by more than a 1e-12 relative slack), so the windows carrying a shortest path are never
removed and the result stays exact:

1. ``d(A) + b1 < sigma + |s - b1|``: ``A``'s route along the edge beats the window everywhere
   (``sigma + |s - q| - (d(A) + q)`` decreases in ``q``); else the prefix where it wins is cut
   (closed-form crossing);
2. the mirror image for ``B`` (a suffix);
3. ``d(C) >= sigma`` and ``d(C) + |C - b_i| < sigma + |s - b_i|`` at both ends (for
   ``d(C) >= sigma`` the set where ``C`` wins is the convex side of a hyperbola branch, so it
   holds on the whole interval once it holds at both ends);
4. MMP's trimming (Mitchell, Mount, Papadimitriou 1987; Surazhsky et al. 2005): a new window
   is compared with the windows still queued on its edge (either side); where one of them is
   strictly nearer at an end of the other, that end is cut back to the crossing of the two
   distance functions (a quadratic, at most two roots).  Interior pieces are not cut (no
   window is split), so the edge's windows may overlap but never lose a shortest path.

**Merging.** A window split at a vertex ``C`` goes on as two children on either side of ``C``;
when ``C`` is flat the two are pieces of one unfolding and meet again behind it, on one edge,
with the same source image.  Touching windows of one edge side whose sources agree to 1e-12
(relative) are merged into one.  Without this a flat region multiplies windows: every vertex
between the source and an edge cuts the fan of rays reaching it, and the pieces arrive one by
one (40 windows per face on a flat 100k-face sheet, ``O(n^1.5)``); with it, 2.

**Why hand-written.** libigl's ``igl.exact_geodesic`` (Kirsanov's MMP) and ``pygeodesic``
take 3D vertex positions, not a mescher's edge lengths, so an impossible mescher would need a
covering of several sheets (:func:`meschers_igl.covering.covering_distance` keeps that route
as an independent oracle); this module needs only the lengths and runs as one numba kernel.
Queued windows live in contiguous per-edge blocks, and each pair of overlapping windows is
resolved with one root solve.  Its cost against libigl and the heat method is in
:doc:`/results` (``benchmarks/bench_exact_geodesic.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import intrinsic, progress
from ..errors import MescherError
from ..validate import as_index_array
from .windows import (
    C_CREATED,
    C_EMITTED,
    C_HEAP,
    C_MAX_BLOCK,
    DONE,
    GROW_ARENA,
    GROW_HEAP,
    GROW_WINDOWS,
    NO_PARENT,
    REPORT,
    SADDLE_TOL,
    TWO_PI,
    MeshArrays,
    QueryArrays,
    propagate,
    walk_rings,
)

__all__ = ["ExactGeodesicSolver"]


# ----------------------------------------------------------------------------------------------
# set-up (numpy) and public API
# ----------------------------------------------------------------------------------------------
#: items taken out of the queue per kernel call (about half a second); between calls a query
#: reports its progress (a bar after a few seconds: smooth meshes of 1M faces take minutes)
_POPS_PER_CALL = 1 << 20
#: first sizes of the window table, the edge blocks' arena and the heap (doubled as needed)
_FIRST_SIZE = 1024


class _State:
    """The state of one query's window propagation, carried across kernel calls.

    The kernel writes into these arrays in place and never grows them: when one might overflow
    in the next step it returns, and :meth:`grow` doubles it (see :func:`propagate`).
    """

    def __init__(self, nv: int, n_edges: int, sources: np.ndarray, mdeg: int) -> None:
        cap = _FIRST_SIZE
        self.dist = np.full(nv, np.inf)
        self.dist[sources] = 0.0
        self.emitted = np.full(nv, np.inf)  # distance at which a pseudo-source last emitted
        self.bpos = np.full(nv, np.nan)  # ring position of the direction a distance came from
        self.via = np.full(nv, NO_PARENT, np.int64)  # where each distance came from (propagate)
        self.vimg = np.zeros((nv, 2), np.float64)
        self.wh = np.empty(cap, np.int64)  # window table: half-edge
        self.wb = np.empty((cap, 5), np.float64)  # b0, b1, sx, sy, sigma
        self.state = np.empty(cap, np.int8)  # QUEUED (and in its edge's block) or DEAD
        self.pos = np.empty(cap, np.int64)  # its index in its edge's block
        self.free = np.empty(cap, np.int64)  # slots of popped windows, reused
        # edge blocks: capacity 4 << bcls[e] at bstart[e] of the arena (aw: window id; alo, ahi:
        # its extent in the edge's common frame), bn[e] used; freed blocks reused per capacity
        self.bstart = np.full(n_edges, -1, np.int64)
        self.bcls = np.zeros(n_edges, np.int64)
        self.bn = np.zeros(n_edges, np.int64)
        self.fhead = np.full(64, -1, np.int64)  # free blocks of capacity 4 << k, through aw
        self.aw = np.empty(4 * cap, np.int64)
        self.alo = np.empty(4 * cap, np.float64)
        self.ahi = np.empty(4 * cap, np.float64)
        # the queue: sources first (all keys 0: a heap as they stand)
        k = sources.size
        self.hk = np.zeros(max(cap, 2 * k), np.float64)
        self.hv = np.empty(self.hk.size, np.int64)
        self.hv[:k] = -(sources + 1)
        # the children of one step (at most two per corner of a vertex): half-edge; b0, b1, sx,
        # sy, sigma
        self.kids_h = np.empty(2 * mdeg, np.int64)
        self.kids_b = np.empty((2 * mdeg, 5), np.float64)
        self.ctr = np.zeros(7, dtype=np.int64)  # indexed by the C_* names
        self.ctr[C_HEAP], self.ctr[C_MAX_BLOCK] = k, 4

    def arrays(self) -> QueryArrays:
        return QueryArrays(*(getattr(self, name) for name in QueryArrays._fields))

    def grow(self, status: int) -> None:
        """Double the array the kernel ran short of (``status``: one of the ``GROW_*`` codes)."""

        def twice(a: np.ndarray) -> np.ndarray:
            b = np.empty((2 * a.shape[0], *a.shape[1:]), a.dtype)
            b[: a.shape[0]] = a
            return b

        if status == GROW_HEAP:
            self.hk, self.hv = twice(self.hk), twice(self.hv)
        elif status == GROW_WINDOWS:
            self.wh, self.wb, self.state = twice(self.wh), twice(self.wb), twice(self.state)
            self.pos, self.free = twice(self.pos), twice(self.free)
        elif status == GROW_ARENA:
            self.aw, self.alo, self.ahi = twice(self.aw), twice(self.alo), twice(self.ahi)
        else:  # pragma: no cover - the kernel returns 0-4 only
            raise RuntimeError(f"exact geodesic kernel: unknown status {status}")


class ExactGeodesicSolver:
    """Exact geodesic distances on a mescher (or any intrinsic triangle mesh), set up once.

    Parameters
    ----------
    m : Mescher, optional
        Its faces, ``face_edges`` and ``edge_lengths()`` are used (the intrinsic metric).
    F : (#F, 3) array_like of int, optional
        Faces, with ``l``, instead of ``m`` (an ordinary mesh: ``l`` from ``igl.edge_lengths``).
    l : (#F, 3) array_like, optional
        Edge lengths, column ``i`` opposite corner ``i``; edges are shared by two faces when
        they join the same two vertices (``F`` must then be edge-manifold).

    Notes
    -----
    The set-up is vectorised numpy (frames of each half-edge, twins, saddle and boundary
    vertices); :meth:`distance` runs the compiled window propagation (module docstring).
    """

    def __init__(self, m: Any = None, *, F: Any = None, l: Any = None) -> None:
        self.m = m
        if m is not None:
            F = np.asarray(m.F, dtype=np.int64)
            fe = np.asarray(m.face_edges, dtype=np.int64)
            lf = np.asarray(m.edge_lengths(), dtype=np.float64)[fe]
            nv = int(m.n_vertices)
        else:
            if F is None or l is None:
                raise MescherError("m: expected a Mescher, or F and l, found neither")
            F = np.asarray(F, dtype=np.int64)
            lf = np.asarray(l, dtype=np.float64)
            if F.ndim != 2 or F.shape[1] != 3 or lf.shape != F.shape:
                raise MescherError(
                    f"F, l: expected (#F, 3) faces and lengths, found {F.shape} and {lf.shape}"
                )
            nv = int(F.max()) + 1 if F.size else 0
            fe = self._edge_ids(F, nv)
        nf = F.shape[0]
        self.n_vertices = nv
        # half-edge h = 3 f + c: the edge opposite corner c, from F[f, c+1] to F[f, c+2]
        L = lf.reshape(-1)
        lac = np.roll(lf, -2, axis=1).reshape(-1)  # |A C|: opposite corner c+2
        lbc = np.roll(lf, -1, axis=1).reshape(-1)  # |B C|: opposite corner c+1
        fx, fy = intrinsic.apex_offsets(L, lac, lbc)
        # twins: the two half-edges of each edge
        he = fe.reshape(-1)
        order = np.argsort(he, kind="stable")
        se = he[order]
        cnt = np.bincount(he)
        if cnt.size and cnt.max() > 2:
            raise MescherError(
                f"F: expected an edge-manifold mesh (at most 2 faces per edge), "
                f"found an edge with {int(cnt.max())} faces"
            )
        pair = np.flatnonzero(se[1:] == se[:-1])
        twin = np.full(3 * nf, -1, dtype=np.int64)
        twin[order[pair]] = order[pair + 1]
        twin[order[pair + 1]] = order[pair]
        start = np.roll(F, -1, axis=1).reshape(-1)  # F[f, c+1]
        rev = np.zeros(3 * nf, dtype=np.bool_)
        has = twin >= 0
        rev[has] = start[has] != start[twin[has]]
        # the common frame of an edge is that of its first half-edge
        hidx = np.arange(3 * nf)
        cflip = has & (twin < hidx) & rev
        # pseudo-sources: saddles and boundary vertices
        cang = np.ascontiguousarray(intrinsic.corner_angles(lf).reshape(-1), dtype=np.float64)
        ang = np.bincount(F.reshape(-1), cang, minlength=nv)
        pseudo = ang > TWO_PI + SADDLE_TOL
        bnd = ~has
        pseudo[start[bnd]] = True
        pseudo[np.roll(F, -2, axis=1).reshape(-1)[bnd]] = True
        # corners of each vertex (CSR): the half-edge opposite the corner
        corner_v = F.reshape(-1)
        vorder = np.argsort(corner_v, kind="stable")
        vptr = np.zeros(nv + 1, dtype=np.int64)
        np.cumsum(np.bincount(corner_v, minlength=nv), out=vptr[1:])
        ne = int(he.max()) + 1 if he.size else 0
        # one dtype, layout and writeable copy per argument (a mescher's arrays are read-only),
        # so the kernel compiles (and caches) once
        f64 = [np.array(a, dtype=np.float64, order="C") for a in (L, fx, fy)]
        i64 = [np.array(a, dtype=np.int64, order="C") for a in (twin, he, vptr, vorder)]
        Fc = np.array(F, dtype=np.int64, order="C")
        # one-rings, for the shadows of pseudo-sources (_shadow)
        rings = walk_rings(Fc, i64[0], cang, i64[2], i64[3], nv)
        mdeg = int(max(2, np.diff(vptr).max(initial=0)))

        def flags(a: np.ndarray) -> np.ndarray:
            return np.array(a, dtype=np.bool_, order="C")

        fl, fx, fy = f64
        twin, hedge, vptr, vcorner = i64
        cpos, csgn, theta, vbnd = rings
        self._mesh = MeshArrays(
            F=Fc,
            fl=fl,
            fx=fx,
            fy=fy,
            twin=twin,
            rev=flags(rev),
            hedge=hedge,
            pseudo=flags(pseudo),
            vptr=vptr,
            vcorner=vcorner,
            cflip=flags(cflip),
            cang=cang,
            cpos=cpos,
            csgn=csgn,
            theta=theta,
            vbnd=vbnd,
            mdeg=np.int64(mdeg),
        )
        self._n_edges = ne
        # vertices per connected component, for the progress of a query
        if nf:
            from .. import topology

            _, self._label = topology.connected_components(F, nv)
        else:
            self._label = np.arange(nv)
        self.n_windows = 0  # windows created by the last query
        self.n_emitted = 0  # of them, sent by pseudo-sources (and sources) into their shadows

    @staticmethod
    def _edge_ids(F: np.ndarray, nv: int) -> np.ndarray:
        from .. import topology

        _, fe, _ = topology.edge_topology(F, nv, check=False)
        return np.asarray(fe, dtype=np.int64)

    def distance(self, sources: Any, targets: Any = None) -> np.ndarray:
        """Exact distance to the nearest source.

        Parameters
        ----------
        sources : int or (k,) array_like of int
        targets : int or (t,) array_like of int, optional
            Stop as soon as these vertices' distances are final (the propagation grows like
            the disc around the sources: a near pair costs a fraction of the whole field).

        Returns
        -------
        d : (#V,) float64
            ``inf`` on connected components without a source.  With ``targets``: exact at the
            targets and at every vertex no farther than the farthest target, ``inf`` beyond.
        """
        return self._run(sources, targets).dist

    def parents(self, sources: Any, targets: Any = None) -> tuple[np.ndarray, ...]:
        """Exact distances and where each came from, to trace shortest paths back exactly.

        Returns
        -------
        d : (#V,) float64
            As :meth:`distance`.
        via : (#V,) int64
            ``h >= 0``: ``d[v]`` came through a window on half-edge ``h = 3 f + c`` (the edge
            opposite corner ``c`` of face ``f``, from ``F[f, c+1]`` at the origin to
            ``F[f, c+2]`` on the positive x-axis, face ``f`` above it); ``-(u + 1)``: along the
            edge from vertex ``u``; :data:`NO_PARENT`: a source or an unreached vertex.
        image : (#V, 2) float64
            For ``via[v] >= 0``: the window's source image in that frame (below the x-axis); the
            straight line from ``v`` to it is the last leg of a shortest path, and it ends at
            the vertex there (a source or a saddle or boundary vertex).
        """
        st = self._run(sources, targets)
        return st.dist, st.via, st.vimg

    def _run(self, sources: Any, targets: Any) -> _State:
        src = np.array(np.unique(as_index_array(sources, "sources", self.n_vertices)), np.int64)
        tgt = np.empty(0, np.int64)
        if targets is not None:
            tgt = np.array(np.unique(as_index_array(targets, "targets", self.n_vertices)), np.int64)
        st = _State(self.n_vertices, self._n_edges, src, int(self._mesh.mdeg))
        # the vertices the query reaches: those of the sources' components
        reach = int(np.isin(self._label, self._label[src]).sum()) if src.size else 0
        with progress.Meter("exact geodesics", total=reach) as bar:
            while True:
                status = propagate(self._mesh, st.arrays(), st.ctr, _POPS_PER_CALL, tgt)
                if status == DONE:
                    break
                if status == REPORT:
                    bar.update(int(np.count_nonzero(st.dist < np.inf)))
                else:
                    st.grow(status)
        self.n_windows, self.n_emitted = int(st.ctr[C_CREATED]), int(st.ctr[C_EMITTED])
        if tgt.size and st.ctr[C_HEAP] > 0:  # stopped early: beyond the farthest target, not final
            st.dist[st.dist > st.dist[tgt].max()] = np.inf
        return st
