"""Shortest paths and exact geodesic distances on meschers.

A mescher's metric is its per-edge lengths (DESIGN "How operators are built"), so a path on it is
a polyline whose segments each lie in one face, measured in that face's intrinsic geometry
(:mod:`meschers_igl.intrinsic`).

* :func:`shortest_path`: trace down the heat-method distance (:mod:`meschers_igl.heat`), unfold
  the strip of faces crossed and pull it taut (funnel).
* :func:`geodesic_distance`: the heat method, or ``method="exact"``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from . import intrinsic, topology
from .errors import MescherError
from .heat import HeatGeodesicSolver
from .validate import as_index_array

__all__ = ["SurfacePath", "geodesic_distance", "shortest_path"]


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
        self.K, self.area = intrinsic.hat_gradient_gram(self.l)
        fe = np.asarray(m.face_edges)  # the mescher's edge topology
        ef = topology.edge_faces(fe, int(m.n_edges))
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
    P = intrinsic.layout(l[[f0]])[0]
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
        # c on the other side of the portal a-b than the previous face's third corner
        side = -(np.sign(e[0] * (pp - pa)[1] - e[1] * (pp - pa)[0]) or 1.0)
        pc = intrinsic.place_apex(pa, pb, la, lb, side)
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


# ----------------------------------------------------------------------------------------------
# distances
# ----------------------------------------------------------------------------------------------
def exact_geodesic_distance(m: Any, sources: Any, max_sheets: int = 64) -> np.ndarray:
    """Exact intrinsic distance on a mescher (MMP on a covering unrolled as far as needed).

    A mescher is locally isometric to its covering (:mod:`meschers_igl.covering`): ``K`` copies
    of the mescher cut open, glued so that depth climbs by the period from one to the next.
    ``igl.exact_geodesic`` (Mitchell-Mount-Papadimitriou window propagation) runs on the
    covering from the sources' lifts on the middle sheet, and ``d(v)`` is the minimum over the
    lifts of ``v``.  That is exact when no shorter path leaves the sheets built: every path that
    leaves crosses a *frontier* edge (a covering boundary edge that is interior on the mescher),
    and no point of a frontier edge ``ab`` is nearer than ``min(d(a), d(b)) - |ab| / 2``; when
    some ``d(v)`` exceeds that bound the covering is rebuilt with twice the sheets.  A possible
    mescher is its own covering (one sheet, no frontier), so there this is
    ``igl.exact_geodesic`` on the mescher's embedding.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) array_like of int
    max_sheets : int, default: 64
        Give up (``MescherError``) beyond this many sheets.

    Returns
    -------
    d : (#V,) float64
        ``inf`` on connected components without a source.

    Raises
    ------
    MescherError
        Bad sources; a mescher whose periods are not multiples of one period (two independent
        impossible loops need a lattice of sheets); more than ``max_sheets`` sheets needed.
    """
    import igl

    from .covering import covering_from_cut

    n = int(m.n_vertices)
    src = np.unique(as_index_array(sources, "sources", n))
    e_count = np.bincount(np.asarray(m.face_edges).reshape(-1), minlength=int(m.n_edges))
    lengths = np.asarray(m.edge_lengths(), dtype=np.float64)
    K = 3
    while True:
        cov = covering_from_cut(m, K)
        mid = cov.K // 2
        lift = np.full((cov.K, n), -1, dtype=np.int64)
        lift[cov.sheet, cov.vmap] = np.arange(cov.vmap.size)
        vs = lift[mid, src]
        vs = vs[vs >= 0]  # sources no face uses have no lift (their distance stays inf)
        nc = cov.V.shape[0]
        dc = np.full(nc, np.inf)
        if vs.size:
            dc = np.asarray(
                igl.exact_geodesic(
                    np.ascontiguousarray(cov.V),
                    np.ascontiguousarray(cov.F),
                    VS=np.ascontiguousarray(vs),
                    VT=np.arange(nc, dtype=np.int64),
                ),  # fmt: skip
                dtype=np.float64,
            ).reshape(-1)
            # libigl returns 0 or DBL_MAX on components without a source: unreachable
            _, comp = topology.connected_components(cov.F, nc)
            dc[~np.isin(comp, comp[vs]) | ~(dc < 1e300)] = np.inf
        d = np.full(n, np.inf)
        np.minimum.at(d, cov.vmap, dc)
        d[src] = 0.0
        if cov.period == 0.0:
            return d
        # frontier: covering boundary edges that are interior edges of the mescher
        _, fec, _ = topology.edge_topology(cov.F, nc, check=False)
        cnt = np.bincount(fec.reshape(-1))
        bf, bc = np.nonzero(cnt[fec] == 1)
        me = np.asarray(m.face_edges)[cov.fmap[bf], bc]
        front = e_count[me] == 2
        a = cov.F[bf[front], (bc[front] + 1) % 3]
        b = cov.F[bf[front], (bc[front] + 2) % 3]
        bound = np.minimum(dc[a], dc[b]) - 0.5 * lengths[me[front]]
        reach = np.isfinite(d)
        if not front.any() or not reach.any() or d[reach].max() < bound.min(initial=np.inf):
            return d
        if 2 * K > max_sheets:
            raise MescherError(
                f"max_sheets: expected enough sheets for exact distances, found {max_sheets} "
                "too few (shortest paths wind around the impossible loop more often)"
            )
        K = 2 * K + 1  # odd, so the middle sheet stays in the middle


def geodesic_distance(m: Any, sources: Any, method: str = "auto", **kwargs: Any) -> np.ndarray:
    """Geodesic distance on a mescher from a vertex or a set of vertices (to the nearest one).

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) array_like of int
    method : {"auto", "standard", "robust", "refined", "accurate", "exact"}, default: "auto"
        ``"exact"``: :func:`exact_geodesic_distance` (MMP on a covering; equals
        ``igl.exact_geodesic`` on an ordinary mesh).  Any other value: the heat method
        (:class:`meschers_igl.heat.HeatGeodesicSolver`, whose docstring says what ``"auto"``
        chooses when).
    **kwargs
        Passed to the heat solver, or ``max_sheets`` to the exact one.

    Returns
    -------
    d : (#V,) float64
    """
    if method == "exact":
        return exact_geodesic_distance(m, sources, **kwargs)
    as_index_array(sources, "sources", int(m.n_vertices))  # fail before factoring
    return HeatGeodesicSolver(m, method=method, **kwargs).distance(sources)
