"""The view from which a staircase reads as Penrose stairs (``view="auto"`` on stairs).

Penrose stairs are built as an *open* ring of steps: flights turning one way round a well, each
step a tread (a face looking up) one rise above the last, the top step far from the bottom one
in 3D.  From one view the bottom step sits on screen exactly where the step after the top would
be, and the ring looks closed and climbing for ever.  Their junction is usually hidden (a tread's
edge lines up with a wall), so pairs of caps or bar ends do not find the view; the stairs' own
structure does:

1. the **up axis** ``n``: a face normal shared by treads at many levels (:func:`stair_chain`);
2. the **chain**: the treads, lowest first, each touching the last in plan and one rise above it
   (the longest such chain); its **flights** (runs of steps in one horizontal direction) must
   turn one way, two or three times, into an open ring (:func:`penrose_flights`);
3. the **wrap**: the missing step between the top tread (centroid ``c_t``) and the bottom one
   (``c_0``) is a step of the top flight (run ``s``, rise ``h``) or of the bottom flight; for the
   bottom step to sit on screen where that step would be, ``c_0 - c_t - s - h n`` must lie along
   the view.  So each wrap gives one view ``v`` (``v . n > 0``: the treads seen from above);
4. **what a person sees** from ``v``: the view is taken only where the treads are seen from above
   at an elevation in ``[MIN_ELEVATION, MAX_ELEVATION]``, at most :data:`MAX_EDGE_ON` of the model
   is seen edge-on, every step of the chain moves on screen, and the missing step's tread and
   riser show on screen as the model's own step does: sample points of the missing tread see the
   other end's tread, those of its riser (when it faces the viewer) a face parallel to the riser
   (:func:`wrap_seen`), and every tread shows but where the steps above it hide it (a tall wall
   hiding a tread gives the trick away: :func:`treads_seen`).  Of the two wraps, the one seeing
   most of the treads.  A straight flight (no turn), a spiral (no flight, or its wrap seen from
   straight above or past a tall wall) or a stepped grid (treads side by side) gives no view.

The view is exact (a difference of tread centroids) when the top and bottom treads have the
same shape, as modellers build them; it is then the view from which every step, the wrap
included, shows one riser.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from ..validate import as_faces, as_points
from .caps import unit_normals
from .clip import FRONT_NZ
from .junctions import _covering

#: A tread's normal is the up axis to ``1 - cos(angle)`` at most this.
TREAD_NORMAL_TOL = 1e-6
#: Fewest steps in a chain read as stairs.
MIN_STEPS = 6
#: Up-axis candidates tried (the most common face normals by area).
MAX_UP_AXES = 6
#: Flights turn by this angle at least (radians) and each turn the same way.
MIN_TURN = np.radians(45.0)
#: Runs of one flight point within this angle (radians) of each other.
FLIGHT_ANGLE = np.radians(10.0)
#: The treads are seen from above at an elevation (the view's angle over the horizontal plane)
#: between these (radians): not edge-on, not from straight above (a spiral's wrap).
MIN_ELEVATION = np.radians(10.0)
MAX_ELEVATION = np.radians(80.0)
#: Each step's move on screen is at least this share of its length in 3D.
MIN_STEP_SCREEN = 0.25
#: Share of the missing step's sample points that must see what a step shows there.
WRAP_SEEN = 0.9
#: Largest share of the model's area seen edge-on (as :data:`meschers_igl.obtain.view.MAX_EDGE_ON`).
MAX_EDGE_ON = 0.2


@dataclass(frozen=True)
class StairChain:
    """Treads of a staircase, lowest first.

    Attributes
    ----------
    up : (3,) float64
        The up axis (the treads' normal).
    treads : list of (k_i,) int64
        Each step's tread faces.
    centroids : (N, 3) float64
        Each tread's area-weighted centroid.
    levels : (N,) float64
        Each tread's height along ``up``.
    """

    up: np.ndarray
    treads: list
    centroids: np.ndarray
    levels: np.ndarray


def _plan(X: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(..., 2) coordinates of ``X`` in a basis of the plane normal to ``up``."""
    a = np.cross(up, np.eye(3)[int(np.argmin(np.abs(up)))])
    a /= np.linalg.norm(a)
    return np.stack([X @ a, X @ np.cross(up, a)], axis=-1)


def _up_axes(nu: np.ndarray, area: np.ndarray) -> np.ndarray:
    """(k, 3) the most common face normals by area (at most :data:`MAX_UP_AXES`)."""
    key = np.round(nu / 1e-3).astype(np.int64) + 1000  # components on a 1e-3 grid
    _, inv = np.unique((key[:, 0] * 2001 + key[:, 1]) * 2001 + key[:, 2], return_inverse=True)
    inv = inv.reshape(-1)
    w = np.bincount(inv, weights=area)
    S = np.stack([np.bincount(inv, weights=area * nu[:, c]) for c in range(3)], axis=1)
    order = np.argsort(-w, kind="stable")[:MAX_UP_AXES]
    S = S[order]
    L = np.linalg.norm(S, axis=1)
    return S[L > 0] / L[L > 0, None]


def _tread_patches(V, F, lab, nu, area, up, tol):
    """Treads facing ``up``, joined across edges (vertices welded by ``lab``) at one level:
    (faces per patch, level, area, centroid, boundary segments (s, 2, 3), their patch)."""
    tread = np.flatnonzero(nu @ up >= 1.0 - TREAD_NORMAL_TOL)
    if tread.size == 0:
        return None
    level = (V[F[tread]] @ up).mean(axis=1)
    W = lab[F[tread]]
    E = np.sort(np.stack([W, np.roll(W, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    f = np.repeat(np.arange(tread.size), 3)
    _, key = np.unique(E, axis=0, return_inverse=True)
    key = key.reshape(-1)
    o = np.argsort(key, kind="stable")
    twin = np.flatnonzero(key[o][1:] == key[o][:-1])  # an edge shared by two tread faces
    a, b = f[o][twin], f[o][twin + 1]
    ok = np.abs(level[a] - level[b]) <= tol
    A = sp.coo_matrix((np.ones(int(ok.sum())), (a[ok], b[ok])), shape=(tread.size,) * 2)
    n_p, plab = csgraph.connected_components(A, directed=False)
    w = area[tread]
    P_area = np.bincount(plab, weights=w, minlength=n_p)
    cen = V[F[tread]].mean(axis=1)
    C = np.stack([np.bincount(plab, weights=w * cen[:, c], minlength=n_p) for c in range(3)], 1)
    C /= np.maximum(P_area, 1e-300)[:, None]
    P_level = np.bincount(plab, weights=w * level, minlength=n_p) / np.maximum(P_area, 1e-300)
    # boundary edges of each patch: its faces' edges met once within the patch
    pk = plab[f] * (int(key.max()) + 1) + key
    _, first, cnt = np.unique(pk, return_index=True, return_counts=True)
    e = first[cnt == 1]
    fe, ce = e // 3, e % 3
    seg = np.stack([V[F[tread[fe], ce]], V[F[tread[fe], (ce + 1) % 3]]], axis=1)
    order = np.argsort(plab, kind="stable")
    faces = np.split(tread[order], np.cumsum(np.bincount(plab, minlength=n_p))[:-1])
    return faces, P_level, P_area, C, seg, plab[fe]


#: Most (point, segment) distances :func:`_touching` forms at once.
_TOUCH_CHUNK = 1 << 21


def _touching(seg2: np.ndarray, owner: np.ndarray, i, j, tol: float) -> np.ndarray:
    """(k,) bool: do patches ``i[k]`` and ``j[k]`` touch in plan -- a boundary vertex of one
    within ``tol`` of a boundary segment of the other -- for all pairs at once.

    Parameters
    ----------
    seg2 : (s, 2, 2) float64
        Plan boundary segments of every patch; ``owner`` (s,) their patch.
    """
    seg2 = seg2[np.argsort(owner, kind="stable")]
    cnt = np.bincount(owner)
    first = np.r_[0, np.cumsum(cnt)[:-1]]
    d = np.full(i.size, np.inf)
    for a, b in ((i, j), (j, i)):  # a's vertices on b's segments, then the other way
        n = cnt[a] * cnt[b]
        step = max(1, _TOUCH_CHUNK // max(int(n.max(initial=1)), 1))
        for lo in range(0, a.size, step):  # chunks of pairs
            k = np.arange(lo, min(lo + step, a.size))
            rep = np.repeat(k, n[k])
            local = np.arange(rep.size) - np.repeat(np.cumsum(n[k]) - n[k], n[k])
            P = seg2[first[a[rep]] + local // cnt[b[rep]], 0]
            S = seg2[first[b[rep]] + local % cnt[b[rep]]]
            e = S[:, 1] - S[:, 0]
            ee = np.maximum(np.einsum("ij,ij->i", e, e), 1e-300)
            t = np.clip(np.einsum("ij,ij->i", P - S[:, 0], e) / ee, 0.0, 1.0)
            dist = np.sqrt(((P - S[:, 0] - t[:, None] * e) ** 2).sum(axis=1))
            has = k[n[k] > 0]  # rep is sorted: one run per pair
            runs = np.r_[0, np.cumsum(n[has])[:-1]]
            d[has] = np.minimum(d[has], np.minimum.reduceat(dist, runs) if dist.size else [])
    return d <= tol


def stair_chain(V: Any, F: Any, tol: float | None = None) -> StairChain | None:
    """The longest chain of treads climbing one step at a time, over the candidate up axes.

    A tread is a planar patch of faces whose normal is the up axis ``n`` (to
    :data:`TREAD_NORMAL_TOL`); step ``j`` follows step ``i`` when it lies higher by at most its
    width (``sqrt`` of the smaller tread's area), the two touch in plan (a vertex of one within
    ``10 tol`` of an edge of the other) and neither lies over the other (their plan centroids
    apart by at least half the smaller width).

    Parameters
    ----------
    V : (#V, 3) array_like of float, F : (#F, 3) array_like of int
    tol : float, optional
        Absolute tolerance (default 1e-5 of the bounding-box diagonal).

    Returns
    -------
    StairChain or None
        None when no chain has :data:`MIN_STEPS` steps.
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    tol = 1e-5 * diag if tol is None else float(tol)
    pairs = cKDTree(V).query_pairs(0.5 * tol, output_type="ndarray")  # welded, as a soup may be
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(V.shape[0],) * 2)
    lab = csgraph.connected_components(A, directed=False)[1]
    nu = unit_normals(V, F)
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    best = None
    for up in _up_axes(nu, area):  # a few candidate up axes
        chain = _chain_for_axis(V, F, lab, nu, area, up, tol)
        if chain is not None and (best is None or len(chain.treads) > len(best.treads)):
            best = chain
    return best


def _chain_for_axis(V, F, lab, nu, area, up, tol) -> StairChain | None:
    """:func:`stair_chain` for one up axis (None under :data:`MIN_STEPS` steps)."""
    got = _tread_patches(V, F, lab, nu, area, up, tol)
    if got is None or len(got[0]) < MIN_STEPS:
        return None
    faces, level, parea, cen, seg, owner = got
    width = np.sqrt(parea)
    c2 = _plan(cen, up)
    seg2 = _plan(seg, up)
    radius = np.zeros(len(faces))
    np.maximum.at(radius, owner, np.linalg.norm(seg2[:, 0] - c2[owner], axis=1))
    # candidate pairs: plan centroids near enough for the patches to touch
    reach = 2.0 * float(radius.max()) + 10 * tol
    ij = cKDTree(c2).query_pairs(reach, output_type="ndarray").reshape(-1, 2)
    swap = level[ij[:, 0]] > level[ij[:, 1]]
    ij[swap] = ij[swap][:, ::-1]  # lower first
    i, j = ij[:, 0], ij[:, 1]
    dl = level[j] - level[i]
    dc = np.linalg.norm(c2[i] - c2[j], axis=1)
    wmin = np.minimum(width[i], width[j])
    may = (dl > tol) & (dl <= wmin) & (dc <= radius[i] + radius[j] + 10 * tol)
    may &= dc >= 0.5 * wmin
    i, j = i[may], j[may]
    touch = _touching(seg2, owner, i, j, 10 * tol)
    i, j = i[touch], j[touch]
    # the longest path up (the levels order the graph)
    order = np.argsort(level, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    length = np.ones(len(faces), dtype=np.int64)
    prev = np.full(len(faces), -1)
    by_start = [[] for _ in range(len(faces))]
    for a, b in zip(i.tolist(), j.tolist()):
        by_start[a].append(b)
    for a in order.tolist():  # in increasing level: a's length is final
        for b in by_start[a]:
            if length[a] + 1 > length[b]:
                length[b], prev[b] = length[a] + 1, a
    end = int(np.argmax(length))
    if length[end] < MIN_STEPS:
        return None
    path = [end]
    while prev[path[-1]] >= 0:
        path.append(int(prev[path[-1]]))
    path = path[::-1]
    return StairChain(up, [faces[k] for k in path], cen[path], level[path])


@dataclass(frozen=True)
class Flights:
    """The flights of a chain: ``runs`` (N - 1, 3) horizontal moves, ``rises`` (N - 1,), and
    ``start`` (f + 1,) the first run of each flight (``runs[start[k]:start[k + 1]]``)."""

    runs: np.ndarray
    rises: np.ndarray
    start: np.ndarray


def penrose_flights(chain: StairChain) -> Flights | None:
    """The flights of ``chain`` when they make an open ring, else None.

    A flight is a run of consecutive steps moving in one horizontal direction (within
    :data:`FLIGHT_ANGLE`).  A ring: three or four flights, each turning from the last by at
    least :data:`MIN_TURN` and all the same way, by less than a whole turn in all (a spiral
    turning at every step makes as many flights as steps, at least :data:`MIN_STEPS` - 1).
    """
    up = chain.up
    D = np.diff(chain.centroids, axis=0)
    rises = D @ up
    runs = D - np.outer(rises, up)
    L = np.linalg.norm(runs, axis=1)
    if np.any(L <= 1e-9 * max(float(L.max()), 1e-300)):
        return None
    u = runs / L[:, None]
    new = np.r_[True, np.einsum("ij,ij->i", u[1:], u[:-1]) < np.cos(FLIGHT_ANGLE)]
    start = np.r_[np.flatnonzero(new), u.shape[0]]
    n_f = start.size - 1
    if not 3 <= n_f <= 4:
        return None
    d = np.array([u[s:e].sum(axis=0) for s, e in zip(start[:-1], start[1:])])
    d /= np.linalg.norm(d, axis=1)[:, None]
    turn = np.arctan2(np.cross(d[:-1], d[1:]) @ up, np.einsum("ij,ij->i", d[:-1], d[1:]))
    if np.any(np.abs(turn) < MIN_TURN) or not (np.all(turn > 0) or np.all(turn < 0)):
        return None
    if abs(float(turn.sum())) >= 2.0 * np.pi - MIN_TURN:
        return None
    return Flights(runs, rises, start)


def wrap_views(chain: StairChain, flights: Flights) -> list:
    """The two wrap views: ``(v, after_top, s, h)`` with ``v`` along ``c_t + s + h n - c_0``
    (``v @ n > 0``), the missing step taken from the top flight (``after_top``) or the
    bottom one."""
    up, c = chain.up, chain.centroids
    out = []
    for after_top, k in ((True, -1), (False, 0)):
        s, h = flights.runs[k], float(flights.rises[k])
        w = c[-1] + s + h * up - c[0]
        if np.linalg.norm(w) > 0:
            v = w / np.linalg.norm(w)
            out.append((v if v @ up > 0 else -v, after_top, s, h))
    return out


def visible_faces(V: np.ndarray, F: np.ndarray, view: np.ndarray, P: np.ndarray) -> np.ndarray:
    """(k,) the face seen at each point's place on screen from ``view`` (-1: none).

    The face seen is the nearest to the camera (largest depth along ``view``) of the faces
    toward the viewer whose orthographic projection holds the point's (the covering pairs of
    ``junctions._covering``: barycentric coordinates at least -1e-9).
    """
    from ..operators import up_for_view, view_frame

    R = view_frame(view, up_for_view(view))
    C, Q = V @ R.T, P @ R.T
    T = C[F]
    N = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    front = np.flatnonzero(N[:, 2] > FRONT_NZ * np.maximum(np.linalg.norm(N, axis=1), 1e-300))
    out = np.full(Q.shape[0], -1)
    k, f, z = _covering(Q, T[front], 0.0)
    if k.size:
        o = np.lexsort((z, k))  # per point, the nearest last
        last = np.r_[k[o][1:] != k[o][:-1], True]
        out[k[o][last]] = front[f[o][last]]
    return out


#: Barycentric sample coordinates in each triangle (inner points, away from its edges).
_BARY = np.array(
    [[1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4], [2, 2, 1], [2, 1, 2], [1, 2, 2]], np.float64
)
_BARY /= _BARY.sum(axis=1, keepdims=True)


def _tread_samples(V, F, faces, centroid, shrink: float = 0.8) -> np.ndarray:
    """Points inside a tread: inner points of its faces drawn toward its centroid."""
    P = np.einsum("sk,fkj->fsj", _BARY, V[F[faces]]).reshape(-1, 3)
    return centroid + shrink * (P - centroid)


def _riser_samples(V, F, faces, s_dir, up, lo: float, hi: float, tol: float) -> np.ndarray:
    """Points on the riser standing on a tread's edge farthest along ``s_dir``, from height
    ``lo`` to ``hi`` above that edge's height (empty when the edge is not found)."""
    T = V[F[faces]]
    key = T @ s_dir
    far = key >= key.max() - tol
    P = T[far]  # corners on the edge
    if P.shape[0] < 2:
        return np.zeros((0, 3))
    across = np.cross(up, s_dir)
    a, b = P[np.argmin(P @ across)], P[np.argmax(P @ across)]
    t = np.array([0.2, 0.5, 0.8])
    u = lo + (hi - lo) * np.array([0.25, 0.5, 0.75])
    E = a + t[:, None] * (b - a)
    return (E[:, None] + u[None, :, None] * up).reshape(-1, 3)


def wrap_seen(V, F, chain: StairChain, v, after_top: bool, s, h: float, tol: float) -> float:
    """Share of the missing step's sample points that see what the step would show from ``v``.

    After the top (``after_top``): the missing tread is the top one moved by ``s + h n`` and
    must see the bottom tread; its riser stands on the top tread's edge along ``s``, from its
    level up by ``h``.  Before the bottom: the missing tread is the bottom one moved by
    ``-(s + h n)`` and must see the top tread; its riser stands on the bottom tread's edge
    along ``-s``, from ``h`` below up to it.  A riser point must see a face whose normal is the
    riser's (``-s``), checked only when the riser faces the viewer.
    """
    up = chain.up
    shat = s / np.linalg.norm(s)
    src, dst = (-1, 0) if after_top else (0, -1)
    move = (s + h * up) * (1.0 if after_top else -1.0)
    P = _tread_samples(V, F, chain.treads[src], chain.centroids[src]) + move
    seen = visible_faces(V, F, v, P)
    ok = np.isin(seen, chain.treads[dst])
    if v @ -shat > FRONT_NZ:
        if after_top:
            Q = _riser_samples(V, F, chain.treads[-1], shat, up, 0.0, h, tol)
        else:
            Q = _riser_samples(V, F, chain.treads[0], -shat, up, -h, 0.0, tol)
        f = visible_faces(V, F, v, Q)
        nu = unit_normals(V, F)[np.maximum(f, 0)]
        ok = np.r_[ok, (f >= 0) & (nu @ -shat >= 1.0 - TREAD_NORMAL_TOL)]
    return float(ok.mean())


#: Each tread must be seen, or hidden by the step above it, on at least this share of its
#: sample points.
MIN_TREAD_SEEN = 0.9
#: A tread is hidden by the steps above it where what hides it lies at most this many times
#: the chain's largest rise above the tread: the next riser, or at a turn the corner step and
#: the next flight's first step, two rises up.
RISER_HIDES = 2.0


def treads_seen(V, F, chain: StairChain, v) -> tuple[np.ndarray, np.ndarray]:
    """Per tread, the share of its sample points (drawn 0.9 toward its centroid) seen from
    ``v``, and the share seen or hidden only by a step above it (what hides the point lies at
    most :data:`RISER_HIDES` rises above the tread, where the ray to the camera meets it).

    In a picture of stairs each tread shows whole but for the strip the next step's riser
    hides; a tread hidden by a tall wall (a column far higher, a spiral's next turn) shows the
    stairs are not what the picture would make of them.
    """
    P = [_tread_samples(V, F, f, c, 0.9) for f, c in zip(chain.treads, chain.centroids)]
    own = np.repeat(np.arange(len(P)), [p.shape[0] for p in P])
    X = np.vstack(P)
    seen = visible_faces(V, F, v, X)
    face_step = np.full(F.shape[0], -1)
    for k, f in enumerate(chain.treads):  # the steps' faces
        face_step[f] = k
    ok = (seen >= 0) & (face_step[np.maximum(seen, 0)] == own)
    hid = np.flatnonzero(~ok & (seen >= 0))
    n = unit_normals(V, F)[seen[hid]]
    a = V[F[seen[hid], 0]]
    t = np.einsum("ij,ij->i", n, a - X[hid]) / np.maximum(n @ v, 1e-300)
    height = (X[hid] + t[:, None] * v) @ chain.up - chain.levels[own[hid]]
    riser = np.zeros_like(ok)
    riser[hid] = height <= RISER_HIDES * float(np.diff(chain.levels).max())
    m = np.bincount(own, minlength=len(P))
    return (
        np.bincount(own, weights=ok, minlength=len(P)) / m,
        np.bincount(own, weights=ok | riser, minlength=len(P)) / m,
    )


def _edge_on_share(V, F, v) -> float:
    """Share of the model's area whose faces contain ``v`` (seen edge-on, to 1e-3)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    area = np.linalg.norm(n, axis=1)
    on = np.abs(n @ v) < 1e-3 * np.maximum(area, 1e-300)
    return float(area[on].sum() / max(area.sum(), 1e-300))


def penrose_stairs_view(
    V: Any,
    F: Any,
    tol: float | None = None,
    start: Any = None,
    within: float = np.pi,
    chain: StairChain | None = None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """The view from which a staircase reads as Penrose stairs, or None (module docstring).

    Of the two wrap views (:func:`wrap_views`) of an open ring of flights
    (:func:`stair_chain`, :func:`penrose_flights`), those a person may take -- the treads seen
    from above at an elevation in ``[MIN_ELEVATION, MAX_ELEVATION]``, at most
    :data:`MAX_EDGE_ON` of the area edge-on, each step moving on screen by at least
    :data:`MIN_STEP_SCREEN` of its length, the missing step seen as a step (:func:`wrap_seen`
    at least :data:`WRAP_SEEN`), each tread seen but where the step above hides it on at least
    :data:`MIN_TREAD_SEEN` of it (:func:`treads_seen`) and, with ``start``, within ``within``
    of it -- the one seeing most of the treads: a person looks at stairs from where their
    treads show, and of the two wraps the wrong one hides treads behind the walls its gap
    leaves.

    Parameters
    ----------
    V : (#V, 3) array_like of float, F : (#F, 3) array_like of int
    tol : float, optional
        Absolute tolerance (default 1e-5 of the bounding-box diagonal).
    start : (3,) array_like, optional
        A unit view near the intended one.
    within : float, default: pi
        With ``start``: largest angle (radians) from it.
    chain : StairChain, optional
        :func:`stair_chain` of the model, when the caller has it.

    Returns
    -------
    (view, up) of (3,) float64, or None
        The unit view toward the camera (``v . n > 0`` for the up axis ``n``) and screen up,
        ``n`` projected onto the screen (a person sees stairs upright).
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    tol = 1e-5 * diag if tol is None else float(tol)
    chain = stair_chain(V, F, tol) if chain is None else chain
    flights = None if chain is None else penrose_flights(chain)
    if flights is None:
        return None
    steps = flights.runs + np.outer(flights.rises, chain.up)
    best = None
    for v, after_top, s, h in wrap_views(chain, flights):  # two views
        seen = _person_view(V, F, chain, steps, v, start, within)
        if seen is None or wrap_seen(V, F, chain, v, after_top, s, h, tol) < WRAP_SEEN:
            continue
        if best is None or seen.mean() > best[0] + 1e-9:
            best = (float(seen.mean()), v)
    if best is None:
        return None
    v = best[1]
    up = chain.up - (chain.up @ v) * v  # a person sees stairs upright
    return v, up / np.linalg.norm(up)


def _person_view(V, F, chain, steps, v, start, within) -> np.ndarray | None:
    """:func:`treads_seen` from ``v`` when a person may take it -- the treads from above within
    the elevations, inside ``start``'s cone, every step moving on screen, at most
    :data:`MAX_EDGE_ON` of the area edge-on, every tread seen -- else None."""
    elevation = float(np.arcsin(np.clip(v @ chain.up, -1.0, 1.0)))
    if not MIN_ELEVATION <= elevation <= MAX_ELEVATION:
        return None
    if start is not None and v @ start < np.cos(within):
        return None
    screen = np.linalg.norm(steps - np.outer(steps @ v, v), axis=1)
    if np.any(screen < MIN_STEP_SCREEN * np.linalg.norm(steps, axis=1)):
        return None
    if _edge_on_share(V, F, v) > MAX_EDGE_ON:
        return None
    seen, shown = treads_seen(V, F, chain, v)
    return seen if shown.min() >= MIN_TREAD_SEEN else None
