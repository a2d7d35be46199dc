"""Line drawings of meschers: the lines a person draws, with the right lines in front.

A mescher drawn back to front in its depth order (paper Sec. 4.1, :mod:`.painter`) shows a
picture; its line drawing is the set of curves where that picture changes from one piece of
surface to another, or turns a sharp corner:

* **sources** -- curves on the surface that may become lines:

  - *boundary* edges (one face);
  - *crease* edges, whose dihedral angle (between the two faces' normals, which zeta fixes
    face by face) exceeds ``crease_angle``;
  - *seams of the order*: smooth edges between two faces facing the same way with a face of
    another sheet drawn between them, over the earlier one (an impossible order flips there:
    :func:`meschers_igl.line_folds.order_seams`);
  - *occluding contours*, where the surface turns away from the viewer.  On a faceted mescher
    these are the mesh edges between a face seen from the front (counter-clockwise on screen)
    and one seen from the back or edge-on; on a smooth one (e.g. after Loop subdivision) the
    *interpolated* contour: the zero set of ``g = n_z`` linearly interpolated from the vertex
    normals inside each face (Hertzmann and Zorin 2000, "Illustrating smooth surfaces"; the
    construction the paper's occluding contours of meshes refer to), a curve that crosses
    faces instead of zig-zagging along their edges.

* **visibility**, exactly, from the order: a line is seen where one of its own faces shows
  beside it.  A side of a source segment ``a + t (b - a)`` is covered where a face drawn after
  its own faces on that side (a larger rank in the order's linear extension) holds the
  segment strictly inside, or has it on an edge and lies on that side (three half-planes: an
  interval of ``t``); where both sides are covered the line is hidden, so it stops exactly
  where it passes behind a face (a T-junction).  A seam of the order is seen where the side
  of its later face shows that face and the other side does not show its own.  Faces of the
  two-ring of an interpolated contour's face (its fold) neither hide it nor count as beyond
  it: they fold under it, and a vertex-normal curve cannot be made consistent with them (the
  known limit of the method); the fold's faces seen from behind are its underside, and their
  seams of the order are left to the contour.
  Its own rank is the last of its fold's faces under it on screen, and a face that a face of
  its fold is drawn over nearby crosses the fold there and hides nothing
  (:mod:`meschers_igl.line_folds`).

* **kinds**, from what the picture shows on either side of a visible piece (the last face
  drawn just left and just right of its midpoint): ``"outline"`` where the background is on
  one side (the figure against the paper), ``"crease"`` where the two sides are the crease's
  own two faces, ``"occlusion"`` otherwise (one piece of surface in front of another; visible
  boundaries and contours over other surface are occlusion lines).

Pieces of one kind and visibility that meet end to end are joined into polylines (a compiled
walk) without the points where they go straight on, so a bar's edge made of many mesh edges
is one two-point line.  Everything else is array work over a uniform grid of the faces' boxes.
:func:`line_drawing` returns a :class:`LineDrawing`; ``pyvista_views.draw`` writes it as SVG or
PDF; :mod:`meschers_igl.line_pixels` measures it against the painter's picture.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from .errors import MescherError
from .face_grid import FaceGrid as _FaceGrid
from .face_grid import ranges as _ranges
from .geometry2d import default_tol, triangle_heights
from .jit import kernel
from .line_folds import NEAR_BASE as _NEAR_BASE
from .line_folds import (
    complement_intervals,
    crossed,
    fold_ranks,
    lines_of_only,
    order_seams,
    seam_hidden,
    seam_partners,
)
from .line_folds import is_near as _is_near
from .painter import _draw_order
from .topology import edge_faces
from .validate import as_choice, as_positive

__all__ = [
    "CONTOUR_MODES",
    "KINDS",
    "LineDrawing",
    "crease_edges",
    "interpolated_contours",
    "line_drawing",
]

#: Line kinds, in the order of the codes in :attr:`LineDrawing.kind`.
KINDS = ("outline", "occlusion", "crease")
OUTLINE, OCCLUSION, CREASE = 0, 1, 2
#: How occluding contours are found (see :func:`line_drawing`).
CONTOUR_MODES = ("auto", "mesh", "interpolated")

# A point is inside a face when all its barycentric coordinates exceed this (strictly inside:
# a line lying on an occluder's edge, e.g. a glued seam or a collinear neighbour, stays visible).
_INSIDE = 1e-9
# Pieces shorter than this share of the model's size are dropped; side probes go this far.
_MIN_PIECE = 1e-9
_PROBE = 1e-7


@dataclass(frozen=True)
class LineDrawing:
    """Polylines of a mescher's line drawing, in screen units.

    Attributes
    ----------
    points : (#P, 2) float64
        Polyline vertices, one polyline after another.
    offsets : (#L + 1,) int64
        Polyline ``i`` is ``points[offsets[i]:offsets[i + 1]]``; a closed one repeats its first
        point at its end.
    kind : (#L,) int8
        Index into :data:`KINDS` (``"outline"``, ``"occlusion"``, ``"crease"``).
    visible : (#L,) bool
        False for hidden lines (only with ``hidden=True``).
    closed : (#L,) bool
    box : (xmin, xmax, ymin, ymax)
        The mescher's screen box (the default framing of a picture of it).
    """

    points: np.ndarray
    offsets: np.ndarray
    kind: np.ndarray
    visible: np.ndarray
    closed: np.ndarray
    box: tuple[float, float, float, float]

    @property
    def n_lines(self) -> int:
        return int(self.kind.shape[0])

    def _select(self, kind: Any, visible: Any) -> np.ndarray:
        keep = np.ones(self.n_lines, dtype=bool)
        if kind is not None:
            names = (kind,) if isinstance(kind, str) else tuple(kind)
            codes = [KINDS.index(as_choice(k, "kind", KINDS)) for k in names]
            keep &= np.isin(self.kind, codes)
        if visible is not None:
            keep &= self.visible == bool(visible)
        return np.flatnonzero(keep)

    def polylines(self, kind: Any = None, visible: Any = True) -> list[np.ndarray]:
        """The polylines of some kinds (a name or names of :data:`KINDS`; None: all) and
        visibility (True, False, None: both), each a (k, 2) float64 array."""
        return [
            self.points[self.offsets[i] : self.offsets[i + 1]] for i in self._select(kind, visible)
        ]

    def segments(self, kind: Any = None, visible: Any = True) -> np.ndarray:
        """(#S, 2, 2) float64: every segment of the chosen polylines."""
        idx = self._select(kind, visible)
        if idx.size == 0:
            return np.zeros((0, 2, 2))
        n = self.offsets[idx + 1] - self.offsets[idx] - 1
        start = np.repeat(self.offsets[idx], n) + _ranges(n)
        return np.stack([self.points[start], self.points[start + 1]], axis=1)

    def length(self, kind: Any = None, visible: Any = True) -> float:
        """Total length of the chosen lines (screen units)."""
        s = self.segments(kind, visible)
        return float(np.linalg.norm(s[:, 1] - s[:, 0], axis=1).sum())


# ------------------------------------------------------------------------------- small helpers
def _double_area(T: np.ndarray) -> np.ndarray:
    """Twice the signed screen areas of triangles ``T`` (k, 3, 2), 0 for triangles thinner
    than the overlap tolerance (seen edge-on: they cover nothing, as for the depth order)."""
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    a2 = e1[:, 0] * e2[:, 1] - e2[:, 0] * e1[:, 1]
    if len(T):
        a2[triangle_heights(T) <= default_tol(T.reshape(-1, 2))] = 0.0
    return a2


def _contains(T: np.ndarray, P: np.ndarray, area2: np.ndarray, tol: float) -> np.ndarray:
    """Barycentric coordinates of ``P[k]`` in ``T[k]`` all ``>= tol`` (orientation-free)."""
    s = np.sign(area2)
    ok = np.ones(len(P), dtype=bool)
    for i in range(3):
        a, b = T[:, i], T[:, (i + 1) % 3]
        e, q = b - a, P - a
        ok &= s * (e[:, 0] * q[:, 1] - e[:, 1] * q[:, 0]) / np.abs(area2) >= tol
    return ok


# ------------------------------------------------------------------------------ the sources
def crease_edges(m: Any, crease_angle: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """Dihedral angles of a mescher's interior edges and which are creases.

    The angle at edge ``e`` between faces ``f`` and ``g`` is the angle between their unit
    normals, ``arccos(n_f . n_g)`` in degrees (0 for a flat edge, 90 at a box's edge); the
    normals come from each face's local corners ``(x, y, depth)`` integrated from zeta
    (:meth:`Mescher.face_normals`), so the angle is intrinsic to the surface a person sees.

    Parameters
    ----------
    m : Mescher
    crease_angle : float, default: 30
        Degrees; edges with a larger dihedral angle are creases.

    Returns
    -------
    angle : (#E,) float64
        Degrees; NaN on boundary edges.
    crease : (#E,) bool
    """
    crease_angle = as_positive(crease_angle, "crease_angle", allow_zero=True)
    return _dihedral(m, edge_faces(np.asarray(m.face_edges), m.n_edges), crease_angle)


def _dihedral(m: Any, ef: np.ndarray, crease_angle: float) -> tuple[np.ndarray, np.ndarray]:
    N = np.asarray(m.face_normals())
    inner = ef[:, 1] >= 0
    angle = np.full(m.n_edges, np.nan)
    cos = np.einsum("ij,ij->i", N[ef[inner, 0]], N[ef[inner, 1]])
    angle[inner] = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    return angle, inner & (np.nan_to_num(angle, nan=0.0) > crease_angle)


def interpolated_contours(m: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The interpolated occluding contour: where ``n_z`` of the vertex normals, interpolated
    linearly inside each face, is zero.

    On each edge ``(i, j)`` whose ends have ``g_i = n_z(i)`` and ``g_j`` of opposite signs the
    contour crosses at ``xy_i + t (xy_j - xy_i)``, ``t = g_i / (g_i - g_j)``; a face with two
    such edges holds one contour segment between them.  A zero ``g`` counts as positive, so
    every face has zero or two crossings and the segments join into closed curves or end on
    the boundary.

    Parameters
    ----------
    m : Mescher

    Returns
    -------
    face : (#S,) int64
        Face holding each segment.
    edge : (#S, 2) int64
        The two crossed edges (segment ends, shared with the neighbouring faces' segments).
    P : (#E, 2) float64
        Crossing point of every edge (NaN where the edge is not crossed).
    """
    g = np.asarray(m.vertex_normals())[:, 2]
    pos = g >= 0
    E = np.asarray(m.edges)
    xy = np.asarray(m.xy)
    crossed = pos[E[:, 0]] != pos[E[:, 1]]
    P = np.full((m.n_edges, 2), np.nan)
    gi, gj = g[E[crossed, 0]], g[E[crossed, 1]]
    t = (gi / (gi - gj))[:, None]
    P[crossed] = xy[E[crossed, 0]] + t * (xy[E[crossed, 1]] - xy[E[crossed, 0]])
    fe = np.asarray(m.face_edges)
    c = crossed[fe]
    faces = np.flatnonzero(c.sum(axis=1) == 2)
    cols = np.argsort(~c[faces], axis=1, kind="stable")[:, :2]
    edge = np.take_along_axis(fe[faces], cols, axis=1)
    return faces, edge, P


# --------------------------------------------------------------------------- visibility
def _hidden_intervals(
    src: _Sources, sc: _Scene, tol: float
) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Parameter intervals ``(seg, t0, t1)`` where segment ``A + t (B - A)`` is hidden, and the
    break points ``(seg, t)`` where it crosses the boundary of any face.

    ``thr`` (#S, 2) holds, for the left and the right side of each segment, the last rank of
    its own faces on that side (``len(rank)`` where it has none: that side never shows it).  A
    side is covered where a face ``g`` with ``rank[g] > thr`` holds the segment strictly
    inside, or has it on one of its edges (both ends within ``tol`` of the edge's line) and
    lies on that side.  For segments with an ``anchor`` face (interpolated contours) faces
    ``near`` the anchor are skipped, ``thr`` is the last rank of those under the segment
    (:func:`.line_folds.fold_ranks`) and a face crossed by the fold nearby hides nothing
    (:func:`.line_folds.crossed`).  The segment is hidden where both sides are covered: a
    line is seen wherever one of its own faces shows beside it.
    """
    A, B, thr, anchor, near = src.A, src.B, src.thr, src.anchor, src.near
    T, area2, rank, scale, grid = sc.T, sc.area2, sc.rank, sc.scale, sc.grid
    n = len(A)
    pad = tol + 1e-12 * scale  # faces whose edge lies within tol of a segment are met too
    s, g = grid.pairs(np.minimum(A, B) - pad, np.maximum(A, B) + pad)
    is_near = _is_near(near, anchor[s], g)
    Tg, a, d = T[g], A[s], B[s] - A[s]
    inv = np.sign(area2[g]) / np.abs(area2[g])
    t0 = np.zeros(len(s))
    t1 = np.ones(len(s))
    c0 = np.zeros(len(s))  # closed interval along an edge of g the segment lies on
    c1 = np.ones(len(s))
    along = np.zeros(len(s), dtype=bool)
    side = np.zeros(len(s), dtype=bool)  # g lies left of the segment
    for i in range(3):
        v, w, u = Tg[:, i], Tg[:, (i + 1) % 3], Tg[:, (i + 2) % 3]
        e = w - v
        alpha = (e[:, 0] * (a[:, 1] - v[:, 1]) - e[:, 1] * (a[:, 0] - v[:, 0])) * inv
        beta = (e[:, 0] * d[:, 1] - e[:, 1] * d[:, 0]) * inv
        up, down = beta > 0, beta < 0
        # on the edge's line: both ends within the overlap tolerance of it (the order's own
        # tolerance: nearly coincident sheets of a model stored to a few digits are one line)
        h = np.abs(area2[g]) / np.maximum(np.linalg.norm(e, axis=1), 1e-300)
        on = (np.abs(alpha) * h <= tol) & (np.abs(alpha + beta) * h <= tol)
        with np.errstate(divide="ignore", invalid="ignore"):
            r = -alpha / beta  # alpha + beta t > 0: strictly inside, exact crossing
            rc = r  # closed: the edge of g is covered up to its ends, exactly
        t0 = np.where(up & ~on, np.maximum(t0, r), t0)
        t1 = np.where(down & ~on, np.minimum(t1, r), t1)
        t1 = np.where(on | (~(up | down) & (alpha <= 0)), -1.0, t1)
        c0 = np.where(up & ~on, np.maximum(c0, rc), c0)
        c1 = np.where(down & ~on, np.minimum(c1, rc), c1)
        along |= on
        left_of = (d[:, 0] * (u[:, 1] - a[:, 1]) - d[:, 1] * (u[:, 0] - a[:, 0])) > 0
        side = np.where(on, left_of, side)
    strict = t1 > t0 + _MIN_PIECE  # touching at a point hides nothing
    on_edge = along & (c1 > c0)
    rg = rank[g]
    under = is_near & (strict | on_edge)
    thr = fold_ranks(thr, anchor, rank, area2, s[under], rg[under])
    far = ~is_near
    # a face the contour's fold passes in front of nearby crosses it there: it hides nothing
    late = far & (strict | on_edge) & (anchor[s] >= 0) & (rg > thr[s, 0])
    far[late] = ~crossed(near, anchor[s[late]], g[late], T, rank, area2)
    s, g, rg, t0, t1, c0, c1 = s[far], g[far], rg[far], t0[far], t1[far], c0[far], c1[far]
    strict, on_edge, side = strict[far], on_edge[far], side[far]
    none = np.arange(n)
    covered, parts = [], []
    for k, this_side in ((0, side), (1, ~side)):
        later = rg > thr[s, k]
        cov = strict & later
        cov_e = on_edge & this_side & later
        no_own = none[thr[:, k] >= len(rank)]  # a side without its own face is always covered
        cs = np.concatenate([s[cov], s[cov_e], no_own])
        c_lo = np.concatenate([t0[cov], c0[cov_e], np.zeros(len(no_own))])
        c_hi = np.concatenate([t1[cov], c1[cov_e], np.ones(len(no_own))])
        covered.append((cs, c_lo, c_hi))
        parts.append(complement_intervals(n, cs, c_lo, c_hi))  # where this side shows its own face
    hidden = complement_intervals(n, *(np.concatenate([p[i] for p in parts]) for i in range(3)))
    if src.seam.any():
        hidden = seam_hidden(hidden, covered, parts, src.seam, src.thr)
    # where the segment enters or leaves any face: what lies beside it may change there
    bs = np.concatenate([s[strict], s[strict], s[on_edge], s[on_edge]])
    bt = np.concatenate([t0[strict], t1[strict], c0[on_edge], c1[on_edge]])
    inner = (bt > 0.0) & (bt < 1.0)
    return hidden, (bs[inner], bt[inner])


def _top_faces(P, T, area2, rank, draw, anchor, near, scale, grid) -> np.ndarray:
    """The last face drawn that contains each point (closed faces), -1 for none; faces
    ``near`` a point's anchor face are skipped."""
    top = np.full(len(P), -1, dtype=np.int64)
    if len(P) == 0:
        return top
    pad = 1e-12 * scale
    pi, g = grid.pairs(P - pad, P + pad)
    inside = _contains(T[g], P[pi], area2[g], -1e-12)
    pi, g = pi[inside], g[inside]
    hit = _is_near(near, anchor[pi], g)
    pi, g = pi[~hit], g[~hit]
    best = np.full(len(P), -1, dtype=np.int64)
    np.maximum.at(best, pi, rank[g])
    top[best >= 0] = draw[best[best >= 0]]
    return top


def _side_ranks(xy, F, E, f1, f2, rank, area2) -> np.ndarray:
    """(#S, 2): last rank among an edge's own faces left and right of it (``len(rank)`` where
    it has none; faces seen edge-on cover nothing and do not count)."""
    n = len(rank)
    out = np.full((len(E), 2), -1, dtype=np.int64)
    a, d = xy[E[:, 0]], xy[E[:, 1]] - xy[E[:, 0]]
    for f in (f1, f2):
        has = (f >= 0) & (area2[np.maximum(f, 0)] != 0)
        fs = np.maximum(f, 0)
        # the face's corner off the edge decides its side
        other = xy[F[fs]].sum(axis=1) - xy[E[:, 0]] - xy[E[:, 1]]
        left = (d[:, 0] * (other[:, 1] - a[:, 1]) - d[:, 1] * (other[:, 0] - a[:, 0])) > 0
        for k, on in ((0, left), (1, ~left)):
            sel = has & on
            out[sel, k] = np.maximum(out[sel, k], rank[fs[sel]])
    out[out < 0] = n
    return out


# ------------------------------------------------------------------------------ joining
def _walk_chains(n_nodes, u, v):
    """Join pieces ``(u[k], v[k])`` (node ids) into maximal chains through degree-2 nodes.

    Returns the node sequence of all chains, their offsets and whether each is closed.  The
    pieces at each node (CSR, by piece) come from numpy; the walk is compiled
    (:func:`_walk_csr`).
    """
    m = u.shape[0]
    ends = np.empty(2 * m, dtype=np.int64)
    ends[0::2], ends[1::2] = u, v
    start = np.zeros(n_nodes + 1, dtype=np.int64)
    np.cumsum(np.bincount(ends, minlength=n_nodes), out=start[1:])
    return _walk_csr(start, ends, np.ascontiguousarray(u), np.ascontiguousarray(v))


@kernel()
def _walk_csr(start, ends, u, v):  # pragma: no cover - compiled
    """:func:`_walk_chains` given the pieces' ends ``ends (2m,)`` (``u[k], v[k]`` at ``2k, 2k+1``)
    and their count per node as offsets ``start (n_nodes + 1,)``."""
    m = u.shape[0]
    n_nodes = start.shape[0] - 1
    # the pieces at each node, ``inc[start[i]:start[i + 1]]``, by a stable counting sort of the
    # ends (a node's pieces by piece index, u's end before v's; ``// 2`` is the piece): a loop
    # here, not a sort kernel of its own (one compilation fewer)
    inc = np.empty(2 * m, dtype=np.int64)
    fill = np.empty(n_nodes, dtype=np.int64)
    for i in range(n_nodes):
        fill[i] = start[i]
    for q in range(2 * m):
        inc[fill[ends[q]]] = q // 2
        fill[ends[q]] += 1
    # np.empty and a loop, not np.zeros: one allocation spelling for all kernels (a compilation
    # each, per process)
    used = np.empty(m, dtype=np.bool_)
    nodes = np.empty(2 * m + 1, dtype=np.int64)
    offsets = np.empty(m + 1, dtype=np.int64)
    closed = np.empty(m, dtype=np.bool_)
    offsets[0] = 0
    for k in range(m):
        used[k] = False
    n_out = 0
    n_lines = 0
    for phase in range(2):
        for s in range(n_nodes if phase == 0 else m):
            if phase == 0:
                if start[s + 1] - start[s] == 2:
                    continue
                node = s
            else:
                if used[s]:
                    continue
                node = u[s]
            while True:
                k = -1
                for a in range(start[node], start[node + 1]):
                    if not used[inc[a]]:
                        k = inc[a]
                        break
                if k < 0:
                    break
                first = node
                nodes[n_out] = node
                n_out += 1
                cur = node
                while k >= 0:
                    used[k] = True
                    cur = v[k] if u[k] == cur else u[k]
                    nodes[n_out] = cur
                    n_out += 1
                    if start[cur + 1] - start[cur] != 2 and phase == 0:
                        break
                    k = -1
                    for a in range(start[cur], start[cur + 1]):
                        if not used[inc[a]]:
                            k = inc[a]
                            break
                closed[n_lines] = cur == first
                n_lines += 1
                offsets[n_lines] = n_out
                if phase == 1:
                    break
    return nodes[:n_out], offsets[: n_lines + 1], closed[:n_lines]


def _join(P0, P1, group, scale, seam):
    """Polylines from pieces ``P0 -> P1``, joined end to end within each ``group`` value where
    exactly two pieces meet (ends are one node when they agree to ``1e-9`` of the model's
    size); points where a polyline goes straight on are dropped.  Also returns which
    polylines are made of ``seam`` pieces only."""
    m = len(P0)
    if m == 0:
        return (
            np.zeros((0, 2)),
            np.zeros(1, dtype=np.int64),
            np.zeros(0, dtype=np.int64),
            np.zeros(0, dtype=bool),
            np.zeros(0, dtype=bool),
        )
    # ends closer than the tolerance are one point (clusters of a k-d tree's close pairs: a
    # rounding grid would split points that straddle a cell border)
    ends = np.concatenate([P0, P1])
    close = cKDTree(ends).query_pairs(_MIN_PIECE * scale, output_type="ndarray")
    adj = sp.coo_matrix((np.ones(len(close)), (close[:, 0], close[:, 1])), shape=(2 * m, 2 * m))
    _, point = csgraph.connected_components(adj, directed=False)
    keys = np.c_[point, np.r_[group, group]]
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.ravel()
    inv = np.stack([inv[:m], inv[m:]], axis=1)
    pts = np.zeros((len(uniq), 2))
    pts[inv[:, 0]] = P0
    pts[inv[:, 1]] = P1
    # a piece drawn twice (coincident sources, e.g. the two sides of a seam) is drawn once
    inv, dup = np.unique(np.sort(inv, axis=1), axis=0, return_inverse=True)
    nodes, offsets, closed = _walk_chains(len(uniq), inv[:, 0].copy(), inv[:, 1].copy())
    seam_line = lines_of_only(seam, dup.ravel(), inv, nodes, offsets)
    line_group = uniq[nodes[offsets[:-1]], 1].astype(np.int64)
    X = pts[nodes]
    n = len(X)
    line_of = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    first, last = offsets[:-1][line_of], offsets[1:][line_of] - 1
    # neighbours of every point along its polyline; a closed one wraps around (its last point
    # repeats the first)
    prev = np.where(
        np.arange(n) == first, np.where(closed[line_of], last - 1, -1), np.arange(n) - 1
    )
    nxt = np.where(np.arange(n) == last, -1, np.arange(n) + 1)
    ok = (prev >= 0) & (nxt >= 0)
    a = X[np.maximum(nxt, 0)] - X
    b = X - X[np.maximum(prev, 0)]
    cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    dot = np.einsum("ij,ij->i", a, b)
    la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    straight = ok & (cross <= 1e-9 * la * lb) & (dot > 0)
    # a closed polyline starts at a corner: rotate it to its first point that is not straight
    k = np.diff(offsets)
    corner = np.where(straight, n, np.arange(n) - first)
    start = np.full(len(k), n)
    np.minimum.at(start, line_of, corner)
    rot = np.where(closed & (start < n), start, 0)
    j = np.arange(n) - first  # position along the polyline
    m_open = k - 1  # distinct points of a closed polyline
    src = np.where(
        closed[line_of],
        first
        + np.where(
            j == k[line_of] - 1, rot[line_of], (j + rot[line_of]) % np.maximum(m_open[line_of], 1)
        ),
        np.arange(n),
    )
    X, straight = X[src], straight[src]
    keep = ~straight
    counts = np.bincount(line_of[keep], minlength=len(offsets) - 1)
    new_off = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    return X[keep], new_off, line_group, closed, seam_line


# ------------------------------------------------------------------------------ front door
def line_drawing(
    m: Any,
    order: Any = None,
    *,
    crease_angle: float = 30.0,
    contours: str = "auto",
    hidden: bool = False,
    min_length: float = 0.002,
) -> LineDrawing:
    """The line drawing of a mescher seen in its depth order.

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional
        Faces are painted in ``order.linear_extension()`` (default: index order), as by the
        renderer and :func:`meschers_igl.painter.visible_faces`.
    crease_angle : float, default: 30
        Dihedral angle (degrees) above which an edge is a crease (:func:`crease_edges`).
    contours : {"auto", "mesh", "interpolated"}, default: "auto"
        Occluding contours along mesh edges (between front- and back-facing faces: the
        outline the picture shows face by face) or interpolated inside faces from the vertex
        normals (smooth curves for smooth meschers, :func:`interpolated_contours`).  ``"auto"``:
        interpolated when no edge is a crease (a smooth surface), else along mesh edges.
    hidden : bool, default: False
        Also return the hidden parts of the lines (``visible`` False).
    min_length : float, default: 0.002
        Interpolated-contour and seam polylines shorter than this share of the model's size
        are left out (specks where the interpolated contour and the mesh's own fold disagree,
        or where a face between barely reaches under a seam: under 2 pixels in a 1000-pixel
        picture).  0 keeps everything.

    Returns
    -------
    LineDrawing

    Notes
    -----
    Cost: one grid broad phase of the source segments against the faces' boxes and one of the
    side probes, then array clipping; linear in the number of (segment, face) box contacts.
    """
    contours = as_choice(contours, "contours", CONTOUR_MODES)
    crease_angle = as_positive(crease_angle, "crease_angle", allow_zero=True)
    sc = _Scene.of(m, order)
    src = _sources(m, sc, crease_angle, contours)
    (hs, h0, h1), breaks = _hidden_intervals(src, sc, default_tol(sc.xy))
    n_seg = len(src.A)
    vs, v0, v1 = complement_intervals(n_seg, hs, h0, h1)
    pieces = [(vs, v0, v1, np.ones(len(vs), dtype=bool))]
    if hidden:
        ws, w0, w1 = complement_intervals(n_seg, vs, v0, v1)
        ws, w0, w1 = (a[~src.seam[ws]] for a in (ws, w0, w1))  # a seam has no hidden part
        pieces.append((ws, w0, w1, np.zeros(len(ws), dtype=bool)))
    ps, p0, p1, vis = (np.concatenate([p[i] for p in pieces]) for i in range(4))
    ps, vis, Q0, Q1 = _split_at(ps, p0, p1, vis, breaks, src, sc.scale)
    kind = _kinds(ps, vis, Q0, Q1, src, sc)
    # pieces join within one kind, visibility and source (mesh edges or interpolated contours)
    group = (kind * 2 + vis.astype(np.int64)) * 2 + (src.anchor[ps] >= 0)
    return _polylines(Q0, Q1, group, src.seam[ps], sc, min_length)


@dataclass(frozen=True)
class _Scene:
    """A mescher's screen triangles in their drawing order, binned once."""

    F: np.ndarray
    xy: np.ndarray
    E: np.ndarray
    T: np.ndarray
    area2: np.ndarray
    draw: np.ndarray
    rank: np.ndarray
    ef: np.ndarray
    scale: float
    box: tuple[float, float, float, float]
    grid: _FaceGrid
    arcs: np.ndarray

    @classmethod
    def of(cls, m: Any, order: Any) -> _Scene:
        try:
            F = np.asarray(m.F, dtype=np.int64)
            xy = np.asarray(m.xy, dtype=np.float64)
            E = np.asarray(m.edges, dtype=np.int64)
        except AttributeError:
            raise MescherError(f"m: expected a Mescher, found {type(m).__name__}") from None
        draw = _draw_order(m, order)
        rank = np.empty(len(F), dtype=np.int64)
        rank[draw] = np.arange(len(F))
        T = xy[F]
        area2 = _double_area(T)
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        return cls(
            F,
            xy,
            E,
            T,
            area2,
            draw,
            rank,
            edge_faces(np.asarray(m.face_edges), len(E)),
            float(max(hi - lo)) or 1.0,
            (float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])),
            _FaceGrid(T, area2),
            np.zeros((0, 2), np.int64) if order is None else np.asarray(order.arcs, np.int64),
        )


@dataclass(frozen=True)
class _Sources:
    """Source segments ``A -> B``: per side the last rank of their own faces (``thr``), the
    face holding an interpolated contour (``anchor``, -1 for mesh edges), the edge's faces
    (``own``), which are creases, which are seams of the order (smooth edges seen only where
    one side shows its own face, :func:`.line_folds.order_seams`), and the near relation of
    contour faces (sorted keys)."""

    A: np.ndarray
    B: np.ndarray
    thr: np.ndarray
    anchor: np.ndarray
    own: np.ndarray
    is_crease: np.ndarray
    seam: np.ndarray
    near: np.ndarray | None


def _sources(m: Any, sc: _Scene, crease_angle: float, contours: str) -> _Sources:
    """Boundary, crease and (mesh) contour edges, the order's seams, or interpolated contour
    segments."""
    F, xy, E, ef, area2, rank = sc.F, sc.xy, sc.E, sc.ef, sc.area2, sc.rank
    _, crease = _dihedral(m, ef, crease_angle)
    boundary = ef[:, 1] < 0
    f1, f2 = ef[:, 0], ef[:, 1]
    f2p = np.maximum(f2, 0)
    front = area2 > 0
    contour_edge = ~boundary & (front[f1] != front[f2p])
    if contours == "auto":
        contours = "interpolated" if not crease.any() else "mesh"
    src = boundary | crease | (contour_edge if contours == "mesh" else False)
    fold_part, near = _interpolated_sources(m, sc) if contours == "interpolated" else (None, None)
    # a smooth edge between faces facing the same way, with a face of another sheet drawn
    # between them: the order's seam, a line where the later face shows and the earlier not;
    # faces of an interpolated contour's fold (the two-ring of its faces) seen from behind are
    # its underside, beyond the contour that stands for them: their seams are left to it
    cand = ~src & ~contour_edge & (area2[f1] != 0) & (area2[f2p] != 0)
    if near is not None:
        fold = np.zeros(len(F), dtype=bool)
        fold[near % _NEAR_BASE] = True
        cand &= ~((fold[f1] | fold[f2p]) & (area2[f1] < 0))
    smooth = np.flatnonzero(cand)
    seam = np.zeros(len(E), dtype=bool)
    seam[smooth] = order_seams(f1[smooth], f2[smooth], rank, sc.arcs)
    # an edge onto a face seen edge-on, across which the surface goes on smoothly, is a seam
    # (a line only where no partner runs along it)
    partner, (ge, g0, g1) = seam_partners(
        m, ef, area2, crease_angle, uncovered=True, tol_abs=_MIN_PIECE * sc.scale
    )
    ge, g0, g1 = ge[src[ge]], g0[src[ge]], g1[src[ge]]
    src &= partner < 0
    # an edge whose faces all cover nothing on screen (seen edge-on) is never drawn
    src &= (area2[f1] != 0) | (~boundary & (area2[f2p] != 0))
    src |= seam
    src &= np.linalg.norm(xy[E[:, 1]] - xy[E[:, 0]], axis=1) > _MIN_PIECE * sc.scale
    e = np.flatnonzero(src)
    e = np.concatenate([e, ge])
    t0 = np.concatenate([np.zeros(len(e) - len(ge)), g0])[:, None]
    t1 = np.concatenate([np.ones(len(e) - len(ge)), g1])[:, None]
    a, b = xy[E[e, 0]], xy[E[e, 1]]
    parts = [
        (
            a + t0 * (b - a),
            a + t1 * (b - a),
            _side_ranks(xy, F, E[e], f1[e], f2[e], rank, area2),
            np.full(len(e), -1, dtype=np.int64),
            np.stack([f1[e], f2[e]], axis=1),
            crease[e],
            seam[e],
        )
    ]
    if fold_part is not None:
        parts.append(fold_part)
    cat = [np.concatenate([p[i] for p in parts]) for i in range(7)]
    return _Sources(*cat, near)


def _interpolated_sources(m: Any, sc: _Scene) -> tuple[tuple | None, np.ndarray | None]:
    """The interpolated contour's segments as sources (the fields of :class:`_Sources`) and
    the near relation of their faces (their folds: two-rings), or ``(None, None)``."""
    F, rank = sc.F, sc.rank
    nF, nV = len(F), len(sc.xy)
    cf, cedge, CP = interpolated_contours(m)
    ok = np.linalg.norm(CP[cedge[:, 1]] - CP[cedge[:, 0]], axis=1) > _MIN_PIECE * sc.scale
    cf, cedge = cf[ok], cedge[ok]
    if len(cf) == 0:
        return None, None
    VF = sp.csr_matrix((np.ones(3 * nF), (np.repeat(np.arange(nF), 3), F.ravel())), shape=(nF, nV))
    FV = VF.T.tocsr()
    r1 = VF[cf] @ FV  # faces sharing a corner with each contour face
    r2 = ((r1 @ VF) @ FV).tocoo()  # and with those: the two-ring of each contour face
    near = np.unique(cf[r2.row] * np.int64(_NEAR_BASE) + r2.col)
    # the fold's last rank under each segment is found with the visibility
    # (line_folds.fold_ranks); until then its own face's
    own_rank = np.stack([rank[cf], rank[cf]], axis=1)
    none = np.zeros(len(cf), dtype=bool)
    part = (
        CP[cedge[:, 0]],
        CP[cedge[:, 1]],
        own_rank,
        cf,
        np.full((len(cf), 2), -1, dtype=np.int64),
        none,
        none,
    )
    return part, near


def _split_at(ps, p0, p1, vis, breaks, src: _Sources, scale: float):
    """Pieces ``[p0, p1]`` of segments ``ps`` cut where their segment crosses a face's boundary
    (what lies beside it may change there); returns the pieces' segments, visibility and ends."""
    bs, bt = breaks
    key, first = np.unique(bs * 4.0 + bt, return_index=True)
    bt = bt[first]
    lo_i = np.searchsorted(key, ps * 4.0 + p0, "right")
    hi_i = np.searchsorted(key, ps * 4.0 + p1, "left")
    n_sub = np.maximum(hi_i - lo_i, 0) + 1
    piece = np.repeat(np.arange(len(ps)), n_sub)
    j = _ranges(n_sub)
    bp = lo_i[piece] + j - 1  # break point at the start of sub-piece j (j >= 1)
    last = max(len(bt) - 1, 0)
    at = (lambda i: bt[np.clip(i, 0, last)]) if len(bt) else (lambda i: np.zeros(len(i)))
    s0 = np.where(j == 0, p0[piece], at(bp))
    s1 = np.where(j == n_sub[piece] - 1, p1[piece], at(bp + 1))
    ps, vis = ps[piece], vis[piece]
    A, B = src.A[ps], src.B[ps]
    d = B - A
    sel = (s1 - s0) * np.linalg.norm(d, axis=1) > _MIN_PIECE * scale
    ps, vis, s0, s1, A, B, d = ps[sel], vis[sel], s0[sel], s1[sel], A[sel], B[sel], d[sel]
    # a source's own ends exactly (A + 1 (B - A) may differ from B in the last bit)
    Q0 = np.where((s0 <= 0.0)[:, None], A, A + s0[:, None] * d)
    Q1 = np.where((s1 >= 1.0)[:, None], B, A + s1[:, None] * d)
    return ps, vis, Q0, Q1


def _kinds(ps, vis, Q0, Q1, src: _Sources, sc: _Scene) -> np.ndarray:
    """Kind of each piece from the faces drawn just left and right of its midpoint."""
    d = Q1 - Q0
    mid = 0.5 * (Q0 + Q1)
    nrm = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.linalg.norm(d, axis=1)[:, None]
    probe = _PROBE * sc.scale
    P = np.concatenate([mid + probe * nrm, mid - probe * nrm])
    anc2 = np.concatenate([src.anchor[ps], src.anchor[ps]])
    top = _top_faces(P, sc.T, sc.area2, sc.rank, sc.draw, anc2, src.near, sc.scale, sc.grid)
    left, right = top[: len(ps)], top[len(ps) :]
    o1, o2 = src.own[ps, 0], src.own[ps, 1]
    is_crease = (o2 >= 0) & (((left == o1) & (right == o2)) | ((left == o2) & (right == o1)))
    kind = np.where(
        (left < 0) | (right < 0), OUTLINE, np.where(is_crease, CREASE, OCCLUSION)
    ).astype(np.int64)
    # a hidden piece is drawn by what it would be if seen: a crease or an occluding line
    return np.where(vis, kind, np.where(src.is_crease[ps], CREASE, OCCLUSION))


def _polylines(Q0, Q1, group, seam, sc: _Scene, min_length: float) -> LineDrawing:
    """Join the pieces and leave out specks of interpolated contours (group bit 0) and of
    polylines made of the order's seams alone."""
    X, offsets, line_group, closed, seam_line = _join(Q0, Q1, group, sc.scale, seam)
    keep = np.ones(len(line_group), dtype=bool)
    if min_length > 0:
        # specks: an interpolated contour is not the mesh's own fold, and where the two
        # disagree near faces drawn over the fold its visibility flickers in short pieces;
        # a seam shows where a face between reaches under it, at times only by a corner
        seg = np.linalg.norm(np.diff(X, axis=0), axis=1)
        csum = np.concatenate([[0.0], np.cumsum(seg)])
        length = csum[offsets[1:] - 1] - csum[offsets[:-1]]
        keep = ~(((line_group % 2 == 1) | seam_line) & (length < min_length * sc.scale))
    sel = np.flatnonzero(keep)
    n_pts = np.diff(offsets)[sel]
    pts = X[np.repeat(offsets[:-1][sel], n_pts) + _ranges(n_pts)]
    line_group = line_group[sel] // 2
    return LineDrawing(
        points=pts,
        offsets=np.concatenate([[0], np.cumsum(n_pts)]).astype(np.int64),
        kind=(line_group // 2).astype(np.int8),
        visible=(line_group % 2).astype(bool),
        closed=closed[sel],
        box=sc.box,
    )
