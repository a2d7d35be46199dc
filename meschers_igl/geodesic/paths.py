"""Shortest paths on meschers.

A mescher's metric is its per-edge lengths (:doc:`/conventions`), so a path on it is a polyline
whose segments each lie in one face, measured in that face's intrinsic geometry
(:mod:`meschers_igl.intrinsic`).

* :func:`shortest_path`: candidates from a distance field (any method of
  :func:`~meschers_igl.geodesic.geodesic_solver`, the heat method by default) and from
  Dijkstra, unfolded and pulled taut (funnel), then shortened around the vertices they bend at
  until they are geodesics (FlipOut's wedge condition), and tried on the other side of nearby
  cone vertices; the shortest wins.
* :func:`shortest_path_through` (waypoints) and :func:`shortest_loops` (a closed geodesic per
  homology generator) build on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numba
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .. import intrinsic, topology
from ..errors import MescherError
from ..validate import as_index_array
from .exact import NO_PARENT, ExactGeodesicSolver
from .methods import GeodesicSolver

__all__ = [
    "SurfacePath",
    "shortest_loops",
    "shortest_path",
    "shortest_path_through",
]


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
        # paths are unfolded and measured in the true metric; mollification (which adds eps to
        # every length: +4.5% along a 0.001-degree fan) only serves the trace's direction field
        self.l = np.asarray(m.face_edge_lengths(), dtype=np.float64)
        self.K, self.area = intrinsic.hat_gradient_gram(m.face_edge_lengths(mollified=True))
        self.tiny = 1e-12 * float(self.l.mean()) if self.l.size else 0.0
        self.cone = None  # angle defects, on first need (_cone_detours)
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


def _backtrack(
    md: _MeshData, d: np.ndarray, via: np.ndarray, image: np.ndarray, target: int, is_src
) -> list[tuple]:
    """The exact shortest path to ``target`` as strips ``(v_start, faces, v_end)``, traced back
    through where each exact distance came from (:meth:`ExactGeodesicSolver.parents`).

    A vertex whose distance came through a window lies on a straight line (in the unfolding)
    to the window's source image, and that image is a vertex ``p`` (a source, or a saddle or
    boundary vertex the path bends at) with ``d[v] = d[p] + |v - p|``: the line is walked face
    by face, unfolding each next face across the edge it leaves by, until a corner lands on the
    image.  A vertex whose distance came along an edge steps to that edge's other end.  Each
    step lowers ``d``, so the walk ends at a source.  Sequential by nature (each face is placed
    from the previous one): a Python loop over the faces the path crosses.
    """
    F = md.F
    strips: list[tuple] = []
    v = int(target)
    for _ in range(F.shape[0] + 16):  # each step lowers d: at most one per vertex
        if is_src[v]:
            return strips
        h = int(via[v])
        if h == NO_PARENT:
            raise MescherError(f"target: vertex {v} has no exact distance to trace back")
        if h < 0:  # along the edge from u
            u = -h - 1
            fan = md.faces_of(v)
            strips.append((v, [int(fan[(F[fan] == u).any(axis=1)][0])], u))
            v = u
            continue
        faces, p = _walk_to_image(md, d, h, v, image[v])
        if not d[p] < d[v]:
            raise MescherError(f"target: the trace back from vertex {v} did not descend")
        strips.append((v, faces, p))
        v = p
    raise MescherError("target: the trace back did not reach a source")


def _walk_to_image(
    md: _MeshData, d: np.ndarray, h: int, v: int, img: np.ndarray
) -> tuple[list[int], int]:
    """Walk the straight line from vertex ``v`` to the point ``img`` (in half-edge ``h``'s
    frame: ``F[f, c+1]`` at the origin, ``F[f, c+2]`` at ``(l, 0)``, face ``f`` above) through
    the faces it crosses, to the vertex at ``img``.

    The line leaves ``v`` through a face of ``v``'s fan whose corner holds its direction (the
    fan unfolded around ``v`` from face ``f``; around a saddle more than one face may, and the
    one whose line lands on a vertex is taken), then crosses one edge per face.  A vertex ``u``
    the line meets with ``d[u] + |u v| = d[v]`` ends the walk: a shortest path runs through it
    (a window's border ray runs through the vertex that split it, and beyond it the faces on
    either side of the line unfold differently).

    Returns
    -------
    faces : list of int
        The first holds ``v``, the last the vertex.
    u : int
        The vertex.

    Raises
    ------
    MescherError
        When no line from ``v`` lands on such a vertex.
    """
    F, l = md.F, md.l
    f, c = divmod(h, 3)
    P = np.zeros((3, 2))
    P[(c + 2) % 3, 0] = l[f, c]
    P[c] = intrinsic.place_apex(
        P[(c + 1) % 3], P[(c + 2) % 3], l[f, (c + 2) % 3], l[f, (c + 1) % 3]
    )
    start = P[np.flatnonzero(F[f] == v)[0]].copy()
    ray = np.asarray(img, dtype=np.float64) - start
    reach = float(np.hypot(*ray))
    tol = 1e-9 * (reach + float(l[f].max()))
    for g, Pg in _fan_faces_holding(md, v, f, P, ray, tol):
        found = _walk_line(md, d, v, g, Pg, start, ray, reach, tol)
        if found is not None:
            return found
    raise MescherError(f"target: the line back from vertex {v} lands on no vertex")


def _unfold(md: _MeshData, g: int, Pg: np.ndarray, k: int) -> tuple[int, np.ndarray]:
    """The face across the edge opposite corner ``k`` of face ``g`` (corners at ``Pg``),
    unfolded into the same plane: ``(face, (3, 2) corner positions)``; face -1 at a boundary."""
    F, l = md.F, md.l
    n = int(md.opp[g, k])
    if n < 0:
        return n, Pg
    a, b = F[g, (k + 1) % 3], F[g, (k + 2) % 3]
    Pn = np.zeros((3, 2))
    ia, ib = np.flatnonzero(F[n] == a)[0], np.flatnonzero(F[n] == b)[0]
    iw = 3 - ia - ib
    Pn[ia], Pn[ib] = Pg[(k + 1) % 3], Pg[(k + 2) % 3]
    side = -np.sign(_cross(Pn[ib] - Pn[ia], Pg[k] - Pn[ia]))  # away from the face before
    Pn[iw] = intrinsic.place_apex(Pn[ia], Pn[ib], l[n, ib], l[n, ia], side)
    return n, Pn


def _fan_faces_holding(md: _MeshData, v: int, f: int, P: np.ndarray, ray: np.ndarray, tol):
    """The faces of ``v``'s fan, unfolded around ``v`` from face ``f`` (both ways round), whose
    corner at ``v`` holds the direction ``ray``: yields ``(face, (3, 2) corner positions)``."""
    F = md.F
    deg = md.vf.indptr[v + 1] - md.vf.indptr[v]
    kv = int(np.flatnonzero(F[f] == v)[0])
    for first in ((kv + 1) % 3, (kv + 2) % 3):  # cross the edge opposite this corner first
        g, Pg, k = f, P, first
        for step in range(deg):  # at most once round the fan
            kv = int(np.flatnonzero(F[g] == v)[0])
            e1, e2 = Pg[(kv + 1) % 3] - Pg[kv], Pg[(kv + 2) % 3] - Pg[kv]
            turn = np.sign(_cross(e1, e2))
            inside = turn * _cross(e1, ray) >= -tol * np.hypot(*e1) and turn * _cross(
                ray, e2
            ) >= -tol * np.hypot(*e2)
            if inside and (step > 0 or first == (kv + 1) % 3):  # f itself once
                yield g, Pg
            edge = (F[g, (k + 1) % 3], F[g, (k + 2) % 3])  # v and the vertex it is shared with
            shared = edge[1] if edge[0] == v else edge[0]
            g, Pg = _unfold(md, g, Pg, k)
            if g < 0 or g == f:
                break
            k = int(np.flatnonzero(F[g] == shared)[0])  # next: the other edge at v


def _walk_line(md, d, v, g, Pg, start, ray, reach, tol):
    """Follow the line from ``v`` (at ``start`` in face ``g``, corners at ``Pg``) along
    ``ray``; ``(faces, u)`` at the first vertex ``u`` on it with ``d[u] + |u v| = d[v]``, or
    ``None`` when it passes ``ray``'s end or leaves the mesh without meeting one."""
    F = md.F

    def lands(q: np.ndarray, u: int) -> bool:
        w = q - start
        along = float(w @ ray) / reach
        return (
            abs(_cross(ray, w)) / reach <= tol
            and 0.0 < along <= reach + tol
            and d[u] + along <= d[v] + tol
        )

    faces = [g]
    kv = int(np.flatnonzero(F[g] == v)[0])
    for k in ((kv + 1) % 3, (kv + 2) % 3):
        if lands(Pg[k], int(F[g, k])):
            return faces, int(F[g, k])
    k, tau = kv, 0.0  # leave through the edge opposite corner k
    for _ in range(F.shape[0]):  # at most every face once
        g, Pg = _unfold(md, g, Pg, k)
        if g < 0:
            return None
        faces.append(g)
        iw = int(np.flatnonzero(~np.isin(F[g], F[faces[-2]]))[0])
        if lands(Pg[iw], int(F[g, iw])):
            return faces, int(F[g, iw])
        best = None  # leave through one of the two edges at the new vertex
        for kk in ((iw + 1) % 3, (iw + 2) % 3):
            # the edge opposite corner kk runs from Pg[kk+1] to Pg[kk+2]
            t_ray, t_edge = _intersect(start, ray, Pg[(kk + 1) % 3], Pg[(kk + 2) % 3])
            if -1e-9 <= t_edge <= 1.0 + 1e-9 and t_ray > tau and (best is None or t_ray > best[0]):
                best = (t_ray, kk)
        if best is None or best[0] > 1.0 + 1e-9:
            return None
        tau, k = best
    return None


def _cross(u: np.ndarray, w: np.ndarray) -> float:
    return float(u[0] * w[1] - u[1] * w[0])


def _intersect(p: np.ndarray, r: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[float, float]:
    """``(t, u)`` with ``p + t r = q0 + u (q1 - q0)`` (``(-inf, nan)`` for parallel lines)."""
    e = q1 - q0
    den = _cross(r, e)
    if den == 0.0:
        return -np.inf, np.nan
    w = q0 - p
    return _cross(w, e) / den, _cross(w, r) / den


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


_dbl_area = intrinsic.double_area_kernel()  # Kahan's Heron formula, compiled


@numba.njit(cache=True)
def _area2(a0, a1, b0, b1, c0, c1) -> float:
    return (b0 - a0) * (c1 - a1) - (c0 - a0) * (b1 - a1)


@numba.njit(cache=True)
def _funnel_kernel(F, l, faces, v0, v1):  # pragma: no cover - compiled
    """Unfold a strip of faces and pull the path from ``v0`` to ``v1`` taut in it.

    The strip is laid out face by face from the intrinsic lengths (the first face as
    :func:`meschers_igl.intrinsic.layout`, each next apex as :func:`intrinsic.place_apex`), then
    the "simple stupid funnel" (Mononen's string pulling; Lee-Preparata) finds the taut path.
    Hand-written in numba: no library pulls strings on an unfolded intrinsic strip, and both
    walks are sequential (each face is placed from the previous one; the funnel's apex moves
    along the strip).

    Returns corner point indices, corner vertices, corner positions, and per point ``k`` (point
    ``k`` lies on the portal between ``faces[k-1]`` and ``faces[k]``) the crossing parameter
    ``tpar`` (0 at the left end, 1 at the right) and the portal's left and right vertices.
    """
    n = faces.shape[0]
    npt = n + 1
    pl = np.empty((npt, 2))
    pr = np.empty((npt, 2))
    il = np.empty(npt, np.int64)
    ir = np.empty(npt, np.int64)
    cv = np.empty(3, np.int64)
    cp = np.zeros((3, 2))
    f0 = faces[0]
    for c in range(3):
        cv[c] = F[f0, c]
    L0, L1, L2 = l[f0, 0], l[f0, 1], l[f0, 2]
    cp[1, 0] = L2
    if L2 > 0:
        cp[2, 0] = (L1 * L1 + L2 * L2 - L0 * L0) / (2.0 * L2)
        cp[2, 1] = _dbl_area(L0, L1, L2) / L2
    for c in range(3):
        if cv[c] == v0:
            pl[0, 0] = pr[0, 0] = cp[c, 0]
            pl[0, 1] = pr[0, 1] = cp[c, 1]
    il[0] = ir[0] = v0
    for k in range(1, n):
        g = faces[k]
        # the portal: the two vertices of g that the previous face has
        ka = -1
        kb = -1
        kc = -1
        for c in range(3):
            found = False
            for q in range(3):
                if cv[q] == F[g, c]:
                    found = True
            if found:
                if ka < 0:
                    ka = c
                else:
                    kb = c
            else:
                kc = c
        a, b, cc = F[g, ka], F[g, kb], F[g, kc]
        pa0 = pa1 = pb0 = pb1 = pp0 = pp1 = 0.0
        for q in range(3):
            if cv[q] == a:
                pa0, pa1 = cp[q, 0], cp[q, 1]
            elif cv[q] == b:
                pb0, pb1 = cp[q, 0], cp[q, 1]
            else:
                pp0, pp1 = cp[q, 0], cp[q, 1]
        la = l[g, kb]  # |c a| is opposite b
        lb = l[g, ka]  # |c b| is opposite a
        e0, e1 = pb0 - pa0, pb1 - pa1
        cross = e0 * (pp1 - pa1) - e1 * (pp0 - pa0)
        side = -1.0 if cross >= 0 else 1.0  # the apex on the far side of the portal
        LL = e0 * e0 + e1 * e1
        x = 0.0
        y = 0.0
        if LL > 0:
            x = (la * la - lb * lb + LL) / (2.0 * LL)
            y = _dbl_area(lb, la, np.sqrt(LL)) / LL
        pc0 = pa0 + x * e0 - side * y * e1
        pc1 = pa1 + x * e1 + side * y * e0
        if cross > 0:
            il[k], ir[k] = b, a
            pl[k, 0], pl[k, 1], pr[k, 0], pr[k, 1] = pb0, pb1, pa0, pa1
        else:
            il[k], ir[k] = a, b
            pl[k, 0], pl[k, 1], pr[k, 0], pr[k, 1] = pa0, pa1, pb0, pb1
        cv[0], cv[1], cv[2] = a, b, cc
        cp[0, 0], cp[0, 1], cp[1, 0], cp[1, 1], cp[2, 0], cp[2, 1] = pa0, pa1, pb0, pb1, pc0, pc1
    for c in range(3):
        if cv[c] == v1:
            pl[n, 0] = pr[n, 0] = cp[c, 0]
            pl[n, 1] = pr[n, 1] = cp[c, 1]
    il[n] = ir[n] = v1
    # string pulling
    ci = np.empty(npt + 1, np.int64)
    cx = np.empty((npt + 1, 2))
    cvid = np.empty(npt + 1, np.int64)
    nc = 0
    ci[0], cx[0, 0], cx[0, 1], cvid[0] = 0, pl[0, 0], pl[0, 1], v0
    nc = 1
    ax, ay = pl[0, 0], pl[0, 1]
    lx, ly, rx, ry = ax, ay, ax, ay
    api, li, ri = 0, 0, 0
    i = 1
    while i < npt:
        qlx, qly, qrx, qry = pl[i, 0], pl[i, 1], pr[i, 0], pr[i, 1]
        restart = False
        if _area2(ax, ay, rx, ry, qrx, qry) >= 0:
            if (ax == rx and ay == ry) or _area2(ax, ay, lx, ly, qrx, qry) < 0:
                rx, ry, ri = qrx, qry, i
            else:
                ax, ay, api = lx, ly, li
                ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = li, lx, ly, il[li]
                nc += 1
                rx, ry, ri = ax, ay, api
                i = api + 1
                restart = True
        if not restart and _area2(ax, ay, lx, ly, qlx, qly) <= 0:
            if (ax == lx and ay == ly) or _area2(ax, ay, rx, ry, qlx, qly) > 0:
                lx, ly, li = qlx, qly, i
            else:
                ax, ay, api = rx, ry, ri
                ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = ri, rx, ry, ir[ri]
                nc += 1
                lx, ly, li = ax, ay, api
                rx, ry, ri = ax, ay, api
                i = api + 1
                restart = True
        if restart:
            lx, ly, li = ax, ay, api
            rx, ry, ri = ax, ay, api
            continue
        i += 1
    if ci[nc - 1] != npt - 1:
        ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = npt - 1, pl[n, 0], pl[n, 1], v1
        nc += 1
    # where the taut path crosses each portal
    tpar = np.zeros(npt)
    for c in range(nc - 1):
        ia, ib = ci[c], ci[c + 1]
        pa0, pa1, pb0, pb1 = cx[c, 0], cx[c, 1], cx[c + 1, 0], cx[c + 1, 1]
        tpar[ia] = 0.0 if (pa0 == pl[ia, 0] and pa1 == pl[ia, 1]) else 1.0
        dp0, dp1 = pb0 - pa0, pb1 - pa1
        for k in range(ia + 1, ib):
            dq0, dq1 = pr[k, 0] - pl[k, 0], pr[k, 1] - pl[k, 1]
            den = dp0 * dq1 - dp1 * dq0
            t = 0.0
            if den != 0:
                t = ((pl[k, 0] - pa0) * dp1 - (pl[k, 1] - pa1) * dp0) / den
            tpar[k] = min(max(t, 0.0), 1.0)
    return ci[:nc], cvid[:nc], cx[:nc].copy(), tpar, il, ir


def _funnel(md: _MeshData, v0: int, faces, v1: int):
    """:func:`_funnel_kernel` on ``md``: (corner indices, corner vertices, corner xy, tpar,
    left ids, right ids)."""
    return _funnel_kernel(md.F, md.l, np.asarray(faces, dtype=np.int64), int(v0), int(v1))


def _segments(md: _MeshData, faces, tpar, il, ir) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Barycentric start and end of the path in each face of a funnelled strip (vectorized)."""
    faces = np.asarray(faces, dtype=np.int64)
    Ff = md.F[faces]
    k = np.arange(faces.size)

    def bary(j):
        return (Ff == il[j][:, None]) * (1.0 - tpar[j])[:, None] + (Ff == ir[j][:, None]) * tpar[j][
            :, None
        ]

    return faces, bary(k), bary(k + 1)


def shortest_path(
    m: Any, source: Any, target: Any, solver: GeodesicSolver | None = None
) -> SurfacePath:
    """Shortest path on a mescher from ``source`` to ``target`` (vertices).

    The path is traced back through the exact distance field (window propagation, stopped once
    ``target`` is final): from ``target`` straight to the source image of the window that gave
    its distance (a vertex: the source, or a saddle or boundary vertex the path bends at), and
    on from there (:func:`_backtrack`).  Each leg is unfolded on the faces it crosses and pulled
    taut (funnel), so the path lies on the mescher's faces and its length is the exact distance
    to round-off.

    Should the trace back fail to reach the exact distance (it is checked), candidate paths are
    built as a fallback: the distance field traced from ``target`` down its per-face gradient,
    the same from the other end, and the shortest path along edges, each pulled taut and
    shortened around the vertices it bends at until both angles there are >= pi (FlipOut's
    condition for a locally shortest path, Sharp & Crane 2020), then tried past the sharpest
    cone vertices next to it.  That yields *a* geodesic, not always the shortest: on a CAD
    prism whose caps are fans of slivers the gradient of the interpolated field leads around
    the side walls while the shortest path crosses a cap (+5% and +25% measured), a geodesic
    of another homotopy class that no swing at its own corners and no detour past a nearby
    cone reaches -- which is why the exact trace back comes first.

    Parameters
    ----------
    m : Mescher
    source, target : int
        Vertex indices.
    solver : GeodesicSolver, optional
        A solver for ``m``: an :class:`~meschers_igl.geodesic.ExactGeodesicSolver` is reused for
        the exact field; any other method's field seeds the fallback candidates.

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
    if solver is not None and solver.m is not m:
        raise MescherError(
            "solver: expected a geodesic solver built for this mescher, found one for another"
        )
    md = _MeshData(m)
    if s == t:
        f = int(md.faces_of(s)[0]) if md.faces_of(s).size else -1
        bb = np.zeros((1, 3))
        if f >= 0:
            bb[0, md.F[f] == s] = 1.0
        return SurfacePath(
            np.array([f]), bb, np.asarray(m.xy)[[s]].copy(), np.zeros(1), 0.0, s, t, np.zeros(0)
        )
    exact = solver if isinstance(solver, ExactGeodesicSolver) else ExactGeodesicSolver(m)
    d, via, image = exact.parents(s, targets=t)
    if not np.isfinite(d[t]):
        raise MescherError(
            f"target: vertex {t} is not reachable from source {s} (another connected component)"
        )
    is_src = np.zeros(n, dtype=bool)
    is_src[s] = True
    try:
        pieces = _pieces(md, _backtrack(md, d, via, image, t, is_src))
        path = _surface_path(m, md, pieces[::-1], s, t, reverse=True)
        if path.length <= d[t] * (1.0 + 1e-9) + md.tiny:
            return path
    except MescherError:  # the trace back got lost: the candidates below remain
        pass
    if solver is None or solver is exact:
        return _geodesic_candidates(m, md, d, lambda: exact.distance(t, targets=s), s, t)
    return _geodesic_candidates(m, md, solver.distance(s), lambda: solver.distance(t), s, t)


def _geodesic_candidates(
    m: Any, md: _MeshData, d: np.ndarray, d_from_target, s: int, t: int
) -> SurfacePath:
    """The shortest of the geodesics shortened from candidate paths (see :func:`shortest_path`):
    the traces down the field ``d`` (from ``s``) and ``d_from_target()``, and the edge path."""
    n = d.size
    is_src = np.zeros(n, dtype=bool)
    is_src[s] = True
    # candidates: the trace down the distance, and the shortest edge path; each is pulled
    # taut and shortened around its corners until it is a geodesic; the shorter one wins
    candidates = [_edge_path(md, t, is_src)]
    try:
        candidates.append(_trace(md, d, t, is_src))
    except MescherError:  # the trace got lost in an unusable field: the edge path remains
        pass
    best = None
    for strips in candidates:
        pieces = _shorten(md, _pieces(md, strips))
        length = sum(p[3] for p in pieces)
        if best is None or length < best[0]:
            best = (length, pieces)
    # and the trace from the other end: near the cut locus, where two geodesics are almost
    # equally short, the field of one end can come down the wrong side of a bump, that of the
    # other end need not
    path = _surface_path(m, md, _cone_detours(md, best[1])[::-1], s, t, reverse=True)
    is_tgt = np.zeros(n, dtype=bool)
    is_tgt[t] = True
    try:
        back = _shorten(md, _pieces(md, _trace(md, d_from_target(), s, is_tgt)))
    except MescherError:
        return path
    # its pieces are listed source -> target, each running that way
    other = _surface_path(m, md, _cone_detours(md, back), s, t, reverse=False)
    return other if other.length < path.length else path


def _surface_path(
    m: Any, md: _MeshData, pieces: list[tuple], s: int, t: int, reverse: bool = False
) -> SurfacePath:
    """The :class:`SurfacePath` of taut pieces (listed from ``s`` to ``t``; each piece runs
    the other way when ``reverse``)."""
    segs = []
    for va, faces, vb, _ in pieces:
        _, _, _, tpar, il, ir = _funnel(md, va, faces, vb)
        ff, b0, b1 = _segments(md, faces, tpar, il, ir)
        piece = list(zip(ff.tolist(), b0, b1))
        segs.extend([(f, e, a) for f, a, e in reversed(piece)] if reverse else piece)
    # drop zero-length segments
    lens = np.array([np.sqrt(max(_seg_len2(md.l[f], b1 - b0), 0.0)) for f, b0, b1 in segs])
    keep = lens > 1e-12 * max(float(lens.max(initial=0.0)), 1e-300)
    segs = [sg for sg, k in zip(segs, keep) if k]
    lens = lens[keep]
    Fm = md.F
    faces = np.array([sg[0] for sg in segs] + [segs[-1][0]], dtype=np.int64)
    bary = np.array([sg[1] for sg in segs] + [segs[-1][2]])
    xy = np.asarray(m.xy, dtype=np.float64)
    pts_xy = np.einsum("ki,kij->kj", bary, xy[Fm[faces]])
    Z = np.asarray(m.corner_depths(), dtype=np.float64)
    dz = np.array([(b1 - b0) @ Z[f] for f, b0, b1 in segs])
    depth = np.concatenate([[0.0], np.cumsum(dz)])
    return SurfacePath(faces, bary, pts_xy, depth, float(lens.sum()), int(s), int(t), lens)


def shortest_path_through(m: Any, points: Any, solver: GeodesicSolver | None = None) -> SurfacePath:
    """The shortest path through the given vertices in order: geodesics between neighbours.

    Parameters
    ----------
    m : Mescher
    points : (k,) array_like of int
        Vertices to visit, ``k >= 2`` (repeats allowed; a closed tour ends where it began).
    solver : GeodesicSolver, optional
        Reused for every leg (:func:`shortest_path`; an exact solver is built once otherwise).

    Returns
    -------
    SurfacePath
        From ``points[0]`` to ``points[-1]``; ``depth`` integrates zeta along the whole path.
    """
    pts = as_index_array(points, "points", int(m.n_vertices))
    if pts.ndim != 1 or pts.size < 2:
        raise MescherError(f"points: expected at least two vertex indices, found {pts.size}")
    solver = ExactGeodesicSolver(m) if solver is None else solver
    legs = [shortest_path(m, int(a), int(b), solver=solver) for a, b in zip(pts[:-1], pts[1:])]
    legs = [p for p in legs if p.n_points > 1] or legs[:1]
    faces = [legs[0].faces[:-1]] + [p.faces[:-1] for p in legs[1:]] + [legs[-1].faces[-1:]]
    bary = [p.bary[:-1] for p in legs] + [legs[-1].bary[-1:]]
    xy = [p.xy[:-1] for p in legs] + [legs[-1].xy[-1:]]
    off = np.cumsum([0.0] + [p.depth[-1] for p in legs])
    depth = [p.depth[:-1] + o for p, o in zip(legs, off)] + [legs[-1].depth[-1:] + off[-2]]
    seg = np.concatenate([p.segment_lengths for p in legs])
    return SurfacePath(
        np.concatenate(faces), np.concatenate(bary), np.concatenate(xy), np.concatenate(depth),
        float(seg.sum()), int(pts[0]), int(pts[-1]), seg,
    )  # fmt: skip


def shortest_loops(m: Any, rounds: int = 50) -> list[SurfacePath]:
    """A closed geodesic around each homology generator (``m.homology_generators()``).

    Each generator's edge loop is pulled taut and shortened around its bending vertices like a
    path (:func:`shortest_path`), with the loop re-rooted at one of its corners after each
    round so that every vertex it passes gets its turn; swings are homotopies, so the loop
    stays in its generator's class.  On an impossible mescher the loop around the impossible
    generator is a shortest way around the impossible loop: its ``depth[-1]`` is the period
    (the depth gained going once around).

    The result is *locally* shortest (no swing shortens it) and never longer than the
    generator's edge loop; it is the shortest in its class only when the shortening from the
    generator reaches that one.  A polyhedral surface can hold several closed geodesics in one
    class (on a torus, loops through rows of saddle vertices as well as the inner equator), and
    the one found depends on where the generator starts -- a known limitation.

    Parameters
    ----------
    m : Mescher
    rounds : int, default: 50
        At most this many re-rootings per loop.

    Returns
    -------
    list of SurfacePath
        Closed (``source == target``), one per generator, in the generators' order.
    """
    md = _MeshData(m)
    edges = np.asarray(m.edges)
    out = []
    for eidx, sg in m.homology_generators():  # one loop per generator (few)
        tail = np.where(sg > 0, edges[eidx, 0], edges[eidx, 1])
        head = np.where(sg > 0, edges[eidx, 1], edges[eidx, 0])
        strips = []
        for a, b in zip(tail.tolist(), head.tolist()):  # the generator's edges
            fan = md.faces_of(a)
            strips.append((a, [int(fan[(md.F[fan] == b).any(axis=1)][0])], b))
        pieces = _pieces(md, strips)
        prev = np.inf
        for _ in range(rounds):
            pieces = _shorten(md, pieces)
            length = sum(p[3] for p in pieces)
            if length > prev * (1.0 - 1e-12) and len(pieces) > 1:
                break
            prev = length
            if len(pieces) > 1:  # re-root at the corner in the middle: the old root is free
                k = len(pieces) // 2
                pieces = pieces[k:] + pieces[:k]
            else:  # one straight piece from the root back to it: force a corner mid-strip
                va, faces, _, _ = pieces[0]
                k = len(faces) // 2
                w = int(next(x for x in md.F[faces[k]] if x != va))
                pieces = _taut(md, w, faces[k:], va) + _taut(md, va, faces[: k + 1], w)
        root = pieces[0][0]
        out.append(_surface_path(m, md, pieces, root, root))
    return out


# ----------------------------------------------------------------------------------------------
# geodesic shortening around vertices (FlipOut's wedge condition, on unfolded strips)
# ----------------------------------------------------------------------------------------------
def _taut(md: _MeshData, v0: int, faces: list[int], v1: int) -> list[tuple]:
    """Funnel a strip and split it at the taut path's corners.

    Returns pieces ``(va, faces, vb, length)``: straight in their unfolded strip, from corner
    vertex ``va`` to ``vb``.
    """
    ci, cv, cx, _, _, _ = _funnel(md, v0, faces, v1)
    seg = np.hypot(*(cx[1:] - cx[:-1]).T)
    out = []
    for k in range(ci.size - 1):  # corners of one taut path: few
        # a piece from a vertex to itself without length would pin its corner: dropped (one
        # with a length is a closed loop, kept)
        if cv[k] != cv[k + 1] or seg[k] > md.tiny:
            out.append((int(cv[k]), faces[ci[k] : ci[k + 1]], int(cv[k + 1]), float(seg[k])))
    return out


def _pieces(md: _MeshData, strips: list[tuple]) -> list[tuple]:
    """Taut pieces of a path given as strips ``(v_start, faces, v_end)`` (target -> source)."""
    out = []
    for v0, faces, v1 in strips:
        out.extend(_taut(md, v0, list(faces), v1))
    return out


def _fan_arcs(md: _MeshData, v: int, f_in: int, f_out: int) -> list[list[int]]:
    """The faces from ``f_in`` to ``f_out`` (both included) around vertex ``v``, both ways.

    An arc that runs into the boundary is left out.  Walking crosses, in each face, the edge
    at ``v`` opposite the corner after (or before) ``v``: consistent orientation makes that one
    direction of rotation throughout.
    """
    if f_in == f_out:
        return [[f_in]]
    F, opp = md.F, md.opp
    arcs = []
    for step in (1, 2):
        arc, f, ok = [f_in], f_in, False
        for _ in range(md.vf.indptr[v + 1] - md.vf.indptr[v] + 1):  # at most the fan's size
            c = int(np.argmax(F[f] == v))
            g = int(opp[f, (c + step) % 3])
            if g < 0 or g == f_in:
                break
            arc.append(g)
            if g == f_out:
                ok = True
                break
            f = g
        if ok:
            arcs.append(arc)
    return arcs


def _dedupe(faces: list[int]) -> list[int]:
    out = [faces[0]]
    for f in faces[1:]:
        if f != out[-1]:
            out.append(f)
    return out


def _shorten(md: _MeshData, pieces: list[tuple], max_steps: int = 100000) -> list[tuple]:
    """Shorten a piecewise-taut path around its corner vertices until it is a geodesic.

    At each corner vertex ``v`` the path may swing to either side of ``v``: the two pieces
    meeting at ``v`` are joined with the faces of ``v``'s fan on that side and pulled taut
    again.  A swing is kept when it is shorter.  When no swing shortens, every corner has an
    angle >= pi on both sides, which is the condition for a locally shortest path through
    vertices (Sharp & Crane 2020, "You can find geodesic paths in triangle meshes by just
    flipping edges", Sec. 3: FlipOut's wedge condition).  FlipOut straightens such a wedge by
    intrinsic edge flips; here the wedge is unfolded on the mescher's own faces instead, which
    needs only edge lengths too and keeps the result on the input faces (no intrinsic-edge
    tracing back).  Each swing strictly shortens the path, so the loop ends.  Sequential by
    nature (each swing changes the next corner's neighbourhood): a Python loop over corners.
    """
    pieces = list(pieces)
    j, steps = 0, 0
    while j < len(pieces) - 1 and steps < max_steps:
        steps += 1
        A, B = pieces[j], pieces[j + 1]
        v, cur = A[2], A[3] + B[3]
        # the path enters v's star at A's trailing run of faces around v and leaves it at
        # B's leading run: cut both runs and go around v one way or the other
        inc_a = (md.F[A[1]] == v).any(axis=1)
        inc_b = (md.F[B[1]] == v).any(axis=1)
        i0 = len(A[1]) - int(np.argmin(inc_a[::-1])) if not inc_a.all() else 0
        j0 = int(np.argmin(inc_b)) - 1 if not inc_b.all() else len(B[1]) - 1
        best = None
        for arc in _fan_arcs(md, v, A[1][i0], B[1][j0]):
            new = _taut(md, A[0], _dedupe(A[1][:i0] + arc + B[1][j0 + 1 :]), B[2])
            length = sum(p[3] for p in new)
            if length < cur * (1.0 - 1e-12) and (best is None or length < best[0]):
                best = (length, new)
        if best is None:
            j += 1
        else:
            pieces[j : j + 2] = best[1]
            j = max(j - 1, 0)  # the previous corner's neighbourhood changed
    return pieces


def _cone_detours(md: _MeshData, pieces: list[tuple], tries: int = 8) -> list[tuple]:
    """Try the other side of the cone vertices next to a geodesic; keep what is shorter.

    Geodesics between two points differ by the side on which they pass cone vertices (angle sum
    below 2 pi: a box corner); swings at the path's own corners cannot cross a cone the path
    does not touch.  For the ``tries`` sharpest cones on the faces a geodesic crosses, the path
    is forced through the cone and shortened again, which lets it swing past on the other side
    (on a CAD box the trace and Dijkstra may both come down the wrong face next to a corner:
    +2.8% without this).
    """
    if md.cone is None:
        ang = intrinsic.corner_angles(md.l)
        total = np.bincount(md.F.reshape(-1), weights=ang.reshape(-1), minlength=md.vf.shape[0])
        bnd = np.zeros(md.vf.shape[0], dtype=bool)
        bf, bc = np.nonzero(md.opp < 0)
        bnd[md.F[bf, (bc + 1) % 3]] = bnd[md.F[bf, (bc + 2) % 3]] = True
        md.cone = np.where(bnd, 0.0, np.maximum(2.0 * np.pi - total, 0.0))  # angle defect
    length = sum(p[3] for p in pieces)
    for _ in range(3):  # a few rounds: each kept detour is strictly shorter
        on_path = {p[0] for p in pieces} | {p[2] for p in pieces}
        cand = []
        for j, piece in enumerate(pieces):  # pieces of one path: few
            for c in np.unique(md.F[piece[1]]).tolist():
                if c not in on_path and md.cone[c] > 1e-6:
                    cand.append((md.cone[c], j, c))
        best = None
        for _, j, c in sorted(cand, reverse=True)[:tries]:
            va, faces, vb, _ = pieces[j]
            inc = np.flatnonzero((md.F[faces] == c).any(axis=1))
            forced = (
                pieces[:j]
                + _taut(md, va, faces[: inc[0] + 1], c)
                + _taut(md, c, faces[inc[-1] :], vb)
                + pieces[j + 1 :]
            )
            new = _shorten(md, forced)
            new_len = sum(p[3] for p in new)
            if new_len < length * (1.0 - 1e-12) and (best is None or new_len < best[0]):
                best = (new_len, new)
        if best is None:
            break
        length, pieces = best
    return pieces
