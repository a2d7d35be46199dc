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

import numpy as np

from .. import intrinsic
from ..errors import MescherError
from ..validate import as_index_array
from .exact import ExactGeodesicSolver
from .methods import GeodesicSolver
from .shortening import _cone_detours, _edge_path, _shorten, _trace
from .unfold import (
    _cross,
    _funnel,
    _intersect,
    _MeshData,
    _pieces,
    _seg_len2,
    _segments,
    _taut,
    _unfold,
)
from .windows import NO_PARENT

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
        faces=np.concatenate(faces),
        bary=np.concatenate(bary),
        xy=np.concatenate(xy),
        depth=np.concatenate(depth),
        length=float(seg.sum()),
        source=int(pts[0]),
        target=int(pts[-1]),
        segment_lengths=seg,
    )


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
