"""The view from which a model's impossible junctions line up (``view="auto"``).

An impossible figure is built so that, from one orthographic view, parts far apart in depth
coincide on screen: the two sides of a cut, the end of a bar and the start of another.  Their
vertices then pair up along one direction -- the view.  So the view is the direction shared by
the most vertex-pair differences ``V[i] - V[j]`` (a vote over pair directions, like a Hough
transform on the sphere), refined to round-off as the direction that makes the supporting pairs
coincide best: the top eigenvector of ``sum d d^T`` over their differences ``d`` (minimising
``sum |d - (d . v) v|^2``, the squared screen distances).

The sign is not visible in the pairing (``v`` and ``-v`` line up the same pairs): we follow the
convention of modelling tools (Blender, ParadoxToolkit), a camera above the horizon with world
``+z`` up, so ``v_z >= 0`` and screen up is world ``z`` projected onto the screen.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import igl
import numpy as np

from ..errors import MescherError
from ..operators import up_for_view, view_frame
from ..topology import boundary_loops
from ..validate import as_faces, as_points
from .clip import FRONT_NZ, REL_TOL
from .directions import near_directions, votes
from .junctions import (
    BarEnds,
    bar_end_pairs,
    bridges_blocked,
    junction_at,
    may_be_junctions,
    pairs_may_be_bars,
    parts_and_front,
    pieces_are_bars,
)
from .view_rank import MAX_RANKED_DIRECTIONS, crease_views, ranked_views
from .view_stairs import MIN_ELEVATION, penrose_stairs_view, stair_chain

#: Vertices taking part in the vote (all pairs among them are tried).
MAX_VOTERS = 1500
#: Pair directions within this angle (radians) vote for the same view.
VOTE_ANGLE = 2e-4
#: Distinct directions (by votes) judged before giving up.
MAX_DIRECTIONS = 200
#: Largest share of the area (each part weighed by the vertex pairs it lines up) seen edge-on
#: from an acceptable view.
MAX_EDGE_ON = 0.2
#: A better-supported view seeing more of the model edge-on than :data:`MAX_EDGE_ON`, but
#: less than this share, is tried when no other view shows a junction (a tribar sheared or
#: bevelled so that faces contain its view shows a fifth to a quarter of its area edge-on; a
#: cube seen along a face diagonal shows 1/3, along an axis 2/3).
EDGE_ON_FALLBACK = 0.3
#: At most this many such better-supported views are judged.
MAX_EDGE_ON_VIEWS = 3
#: Largest share of the whole model's area seen edge-on from a candidate of the vote, however
#: the pairs lie: a table (or a floor) seen exactly level lines up its legs' corners along the
#: level diagonals and shows 80% of its area as lines; nobody takes that view.
MAX_EDGE_ON_WHOLE = 0.5


def _voters(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Boundary vertices of a cut model, else every used vertex (sampled down to MAX_VOTERS)."""
    loops = boundary_loops(F)
    S = np.unique(np.concatenate(loops)) if loops else np.unique(F)
    if S.size > MAX_VOTERS:
        S = np.sort(rng.choice(S, MAX_VOTERS, replace=False))
    return S


def find_view(
    V: Any,
    F: Any,
    *,
    return_support: bool = False,
    max_views: int = 1,
    max_edge_on: float = MAX_EDGE_ON,
):
    """The orthographic view in which most vertex pairs coincide on screen.

    Parameters
    ----------
    V : (#V, 3) array_like of float
    F : (#F, 3) array_like of int
    return_support : bool, default: False
        Also return the supporting vertex pairs.
    max_views : int, default: 1
        With more than one: a list of up to ``max_views`` candidates ``(view, up, pairs)``,
        distinct directions in decreasing support (for a caller that judges each).
    max_edge_on : float, default: :data:`MAX_EDGE_ON`
        Largest share of the area a candidate may see edge-on, each part weighed by the
        vertex pairs it lines up (a view along an axis of a box model lines up many pairs but
        shows its side faces as lines).

    Returns
    -------
    view : (3,) float64
        Unit direction from the model toward the camera (``view[2] >= 0``).
    up : (3,) float64
        Screen up (:func:`up_for_view`).
    pairs : (k, 2) int64
        Only with ``return_support``: the vertex pairs that coincide from ``view``.

    Raises
    ------
    MescherError
        When no two vertex pairs share a direction (nothing lines up from any view).
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    out = _pick(_vote(V, F), V, F, max_views, max_edge_on)
    if max_views == 1:
        v, up, pairs = out[0]
        return (v, up, pairs) if return_support else (v, up)
    return out


def _vote(V: np.ndarray, F: np.ndarray) -> tuple:
    """The vote of :func:`find_view`: (voters S, pair differences D, lengths L, unit directions
    U, pair ends i, j into S, votes per pair, distinct directions W, pair -> W); computed once
    per model (the edge-on fallback picks from the same vote)."""
    S = _voters(V, F, np.random.default_rng(0))
    i, j = np.triu_indices(S.size, k=1)
    D = V[S[j]] - V[S[i]]
    L = np.linalg.norm(D, axis=1)
    scale = float(np.ptp(V[S], axis=0).max()) if S.size else 0.0
    ok = L > 1e-6 * max(scale, 1e-300)
    # pairs on a common face are the model's own edges and diagonals, not junctions
    pos = np.full(V.shape[0], -1)
    pos[S] = np.arange(S.size)
    Fs = pos[F]
    e = np.sort(Fs[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    e = e[(e >= 0).all(axis=1)]
    key = i * S.size + j
    ok &= ~np.isin(key, np.unique(e[:, 0] * S.size + e[:, 1]))
    D, L, i, j = D[ok], L[ok], i[ok], j[ok]
    U = D / L[:, None]
    U *= np.where(U @ np.array([1e-3, 1e-2, 1.0]) < 0, -1.0, 1.0)[:, None]  # one hemisphere
    # votes: pairs whose directions agree within VOTE_ANGLE (either sign), longer pairs first
    counts, W, inv, tree = votes(U, VOTE_ANGLE)
    if counts.size == 0 or counts.max() < 2:
        raise MescherError(
            "V: expected vertex pairs that line up along a common direction (a view in which "
            "parts of the model coincide on screen), found none; pass view= explicitly"
        )
    return S, D, L, U, i, j, counts, W, inv, tree


@dataclass(frozen=True)
class _FaceAreas:
    """Unit normals ``nu`` (#F, 3) and areas ``area`` (#F,) of a model's faces, the connected
    part of each face ``part`` (#F,) and of each vertex ``vpart`` (#V,), for :meth:`edge_on`."""

    nu: np.ndarray
    area: np.ndarray
    part: np.ndarray
    vpart: np.ndarray

    @classmethod
    def of(cls, V: np.ndarray, F: np.ndarray) -> _FaceAreas:
        T = V[F]
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        area = np.linalg.norm(n, axis=1)
        part = np.asarray(igl.facet_components(F)[1], dtype=np.int64)
        vpart = np.zeros(V.shape[0], dtype=np.int64)
        vpart[F.reshape(-1)] = np.repeat(part, 3)
        return cls(n / np.maximum(area, 1e-300)[:, None], area, part, vpart)

    def edge_on(self, W: np.ndarray, verts: np.ndarray | None = None) -> np.ndarray:
        """(k,) for each unit direction ``W[i]``: the share of the area seen edge-on from it.

        Each part's own share, averaged with weights: the parts' areas by default (the share
        of the whole model), or with ``verts`` (vertex ids, the ends of the vertex pairs that
        line up along ``W``) the number of those in each part -- the parts that make the
        view.  So a backdrop or a floor seen face-on, whose area dwarfs the figure, does not
        hide that the figure lining up the pairs is seen edge-on, and a small block whose
        caps contain the view (a junction's mitre) weighs by its share of the pairs.
        """
        side = self.area[:, None] * (np.abs(self.nu @ np.reshape(W, (-1, 3)).T) < 1e-3)
        if verts is None:  # every part by its area: the whole model's share
            return side.sum(axis=0) / max(float(self.area.sum()), 1e-300)
        n = int(self.part.max(initial=-1)) + 1
        edge = np.zeros((n, side.shape[1]))
        np.add.at(edge, self.part, side)
        total = np.bincount(self.part, weights=self.area, minlength=n)
        w = np.bincount(self.vpart[np.asarray(verts).reshape(-1)], minlength=n).astype(float)
        share = edge / np.maximum(total, 1e-300)[:, None]
        return (w @ share) / max(float(w.sum()), 1.0)


def _pick(vote: tuple, V, F, max_views: int, max_edge_on: float) -> list:
    """Up to ``max_views`` refined ``(view, up, pairs)`` from ``vote``, best supported first,
    each seeing at most ``max_edge_on`` of the model edge-on (:func:`find_view`)."""
    S, D, L, U, i, j, counts, W, inv, tree = vote
    # candidates by votes; a view must not see much of the model edge-on (a view along an
    # axis of a box model lines up many pairs but shows its side faces as lines)
    faces = _FaceAreas.of(V, F)
    by_dir = np.argsort(inv, kind="stable")  # pairs grouped by their distinct direction
    first = np.searchsorted(inv[by_dir], np.arange(W.shape[0] + 1))
    order = np.lexsort((-L, -counts))
    found = []
    tried = np.zeros(W.shape[0], dtype=bool)  # directions already judged
    n_tried = 0
    for c in order.tolist():  # the best-supported distinct directions first, few tried
        if tried[inv[c]]:
            continue
        if counts[c] < 2 or n_tried >= MAX_DIRECTIONS or len(found) >= max_views:
            break
        n_tried += 1
        tried[near_directions(W, tree, U[c], VOTE_ANGLE)] = True
        along = by_dir[first[inv[c]] : first[inv[c] + 1]]  # the pairs of this direction
        if (
            faces.edge_on(U[c][None], np.r_[S[i[along]], S[j[along]]])[0] <= max_edge_on
            and faces.edge_on(U[c][None])[0] <= MAX_EDGE_ON_WHOLE
        ):
            found.append(c)
    if not found:
        raise MescherError(
            "V: expected vertex pairs that line up along a direction from which the model is "
            "not seen edge-on, found none; pass view= explicitly"
        )
    out = []
    for k in found:  # refine each candidate
        near = near_directions(W, tree, U[k], VOTE_ANGLE)  # the pairs along those: by_dir
        support = np.sort(np.concatenate([by_dir[first[w] : first[w + 1]] for w in near]))
        # the direction that makes the supporting pairs coincide best (weighted by length^2)
        M = D[support].T @ D[support]
        w, E = np.linalg.eigh(M)
        v = E[:, -1]
        if v[2] < 0 or (abs(v[2]) <= 1e-12 and v[1] < 0):
            v = -v
        out.append((v, up_for_view(v), np.stack([S[i[support]], S[j[support]]], axis=1)))
    return out


#: A model is a relief when its least width is at most this share of its smaller extent across.
RELIEF_RATIO = 0.5


def relief_fronts(V: Any, F: Any) -> list[np.ndarray]:
    """The views a person takes of a relief: along its thin axis, the carved side first.

    A relief (a bas-relief, a physically realisable trick carved in layers) is made to be seen
    from the front, along the direction in which it is thinnest: the least width of the model
    over the normals of its convex hull's facets (exact for a slab with a flat back or a face
    on the hull; the principal axis of least spread for a flat sheet).  The carved side is the
    one whose facing faces lie less on its outer plane (by area): a relief's layers, not its
    flat back; on a tie (carved on both sides) the side with ``v_z >= 0`` first.

    Parameters
    ----------
    V : (#V, 3) array_like of float, F : (#F, 3) array_like of int

    Returns
    -------
    list of (3,) float64
        ``[front, -front]``, or ``[]`` when the model is not thin: its least width over
        :data:`RELIEF_RATIO` times its smaller extent across that axis.
    """
    from scipy.spatial import ConvexHull, QhullError

    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    P = V[np.unique(F)]
    X = P - P.mean(axis=0)
    normals = np.linalg.svd(X, full_matrices=False)[2][-1:]  # the axis of least spread
    try:
        normals = np.vstack([normals, ConvexHull(P).equations[:, :3]])
    except QhullError:
        pass  # flat or degenerate: the axis of least spread is the normal
    width = np.ptp(P @ normals.T, axis=0)
    n = normals[int(np.argmin(width))]
    n = n / np.linalg.norm(n)
    Y = X - np.outer(X @ n, n)  # the model flattened onto its plane
    across = np.ptp(Y @ np.linalg.svd(Y, full_matrices=False)[2][:2].T, axis=0).min()
    if not across > 0 or width.min() > RELIEF_RATIO * across:
        return []
    T = V[F]
    N = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    area = np.linalg.norm(N, axis=1)
    c, h = (N @ n) / np.maximum(area, 1e-300), T @ n  # (#F,), (#F, 3)
    flat = []
    for s, end in ((1.0, h.max()), (-1.0, h.min())):  # each side's faces, on its outer plane?
        w = area * (s * c > 1e-6)
        on = np.all(np.abs(h - end) <= 1e-6 * across, axis=1)
        flat.append(float(w @ on / w.sum()) if w.sum() > 0 else 1.0)
    if n[2] < 0 or (abs(n[2]) <= 1e-12 and n[1] < 0):
        n, flat = -n, flat[::-1]  # the convention first on a tie
    if flat[0] > flat[1] + 1e-9:
        n = -n  # the other side is carved, this one flat
    return [n + 0.0, -n + 0.0]  # no negative zeros


# ------------------------------------------------------------------------------ automatic view
#: A hidden gap is looked for on circles passing within this angle of a start view.
START_ANGLE = np.radians(10.0)


#: At most this many pairs of bar ends (the nearest first) are searched for a hidden gap.
MAX_AUTO_BARS = 16


def _camera(V, F, R):
    """Camera-frame vertices and the faces toward the viewer (as :func:`parts_and_front`,
    without the parts, which do not depend on the view)."""
    C = V @ R.T
    N = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    return C, N[:, 2] > FRONT_NZ * np.maximum(np.linalg.norm(N, axis=1), 1e-300)


def _occluder_centred_view(V, F, TT, part, be: BarEnds, tol, v0, iters: int = 50):
    """The view on the circle where ``be``'s pieces line up that centres the part hiding the
    gap (seen from ``v0``) on the gap: ``v`` along ``c_occ - p`` with ``c_occ`` the occluding
    part's (area-weighted) centroid and ``p`` the gap's middle on the first piece's line."""
    from ..geometry2d import barycentric

    w = np.cross(be.d, be.T)
    w /= np.linalg.norm(w)
    R = view_frame(v0, up_for_view(v0))
    C, front = _camera(V, F, R)
    found = junction_at(V, F, C, R, be, tol, front, part, True)
    if found is None or found[0] == "false edge":
        return None
    ell = found[2]
    c0 = V[be.first.loop].mean(axis=0)
    mid = (c0 + 0.5 * ell * be.d) @ R.T
    T = C[F[front]]
    B = barycentric(np.repeat(mid[None, :2], T.shape[0], 0), T[:, :, :2])
    inside = np.flatnonzero(np.all(B >= -1e-9, axis=1))
    z = (B[inside] * T[inside, :, 2]).sum(axis=1)
    occ = part[np.flatnonzero(front)[inside[np.argmax(z)]]]
    Fo = F[part == occ]
    Tw = V[Fo]
    area = 0.5 * np.linalg.norm(np.cross(Tw[:, 1] - Tw[:, 0], Tw[:, 2] - Tw[:, 0]), axis=1)
    c_occ = (area[:, None] * Tw.mean(axis=1)).sum(axis=0) / area.sum()
    v = v0 / np.linalg.norm(v0)
    for _ in range(iters):  # converges in a few steps (the gap's middle moves little)
        M = np.stack([be.d, v], axis=1)
        (ell, _), *_ = np.linalg.lstsq(M, be.T, rcond=None)
        u = c_occ - (c0 + 0.5 * ell * be.d)
        u -= (u @ w) * w
        u /= np.linalg.norm(u)
        if np.linalg.norm(u - v) < 1e-15:
            break
        v = u
    R = view_frame(v, up_for_view(v))
    C, front = _camera(V, F, R)
    found = junction_at(V, F, C, R, be, tol, front, part, True)
    return None if found is None or found[0] != "hidden gap" else v


@dataclass(frozen=True)
class _PairArrays:
    """The bar-end pairs' view-independent quantities as arrays (one row per pair).

    Attributes
    ----------
    T : (k, 3) float64
        Translation from the first cap to the second.
    D : (k, 3) float64
        The bar's direction at the first cap (zeros where the pair has none).
    n1 : (k, 3) float64
        The first cap's normal.
    bars : (k,) bool
        A bridge may join them: a bar direction pointing out of the first cap and both pieces
        longer along it than their caps are wide (:func:`pieces_are_bars`).
    """

    T: np.ndarray
    D: np.ndarray
    n1: np.ndarray
    bars: np.ndarray


def _pair_arrays(V, F, part, pairs: list) -> _PairArrays:
    """:class:`_PairArrays` of ``pairs``; ``bars`` as :func:`pieces_are_bars` decides it, for
    all pairs at once (:func:`pairs_may_be_bars` without slack)."""
    k = len(pairs)
    T = np.array([be.T for be in pairs], np.float64).reshape(k, 3)
    n1 = np.array([be.first.normal for be in pairs], np.float64).reshape(k, 3)
    D = np.zeros((k, 3))
    has_d = np.fromiter((be.d is not None for be in pairs), bool, k)
    D[has_d] = np.array([pairs[i].d for i in np.flatnonzero(has_d).tolist()]).reshape(-1, 3)
    return _PairArrays(T, D, n1, pairs_may_be_bars(V, F, part, pairs, slack=0.0))


def _junction_seen(V, F, part, pairs, arr: _PairArrays, R, tol) -> bool:
    """Is a junction of the bar ends ``pairs`` seen from view ``R`` (:func:`junction_at`)?

    Caps coinciding on screen that contain the view and gain depth are a false edge, decided
    for all pairs at once; a bridge (hidden gap, crossing) is judged pair by pair only where
    it may hold: two bars (:func:`may_be_junctions`), their bridge through empty space (one
    winding-number call)."""
    v = R[2]
    gap = arr.T @ v
    line = (np.linalg.norm(arr.T - gap[:, None] * v, axis=1) <= tol) & (np.abs(gap) > tol)
    if np.any(line & (np.abs(arr.n1 @ v) <= 1e-6) & (gap >= 0)):
        return True
    sub = [pairs[i] for i in np.flatnonzero(~line & arr.bars).tolist()]
    sub = [be for be, m in zip(sub, may_be_junctions(sub, R, tol, True).tolist()) if m]
    blocked = bridges_blocked(V, F, R, sub)
    sub = [be for be, bl in zip(sub, blocked.tolist()) if not bl]
    if not sub:
        return False
    C, front = _camera(V, F, R)
    return any(junction_at(V, F, C, R, be, tol, front, part, True, False) for be in sub)


def find_model_view(
    V: Any,
    F: Any,
    tol: float | None = None,
    start: Any = None,
    judge: Any = None,
    within: float = START_ANGLE,
    joint_judge: Any = None,
):
    """``view="auto"`` for any model: the view from which its junctions line up.

    0. Penrose stairs (:func:`~meschers_igl.obtain.view_stairs.penrose_stairs_view`): an open
       ring of flights is seen from above, from where its bottom step sits on screen where the
       step after its top would be (their junction is usually hidden behind a wall, which the
       searches below miss); screen up is then the stairs' up axis projected.  On any other
       staircase (a chain of treads, :func:`~meschers_igl.obtain.view_stairs.stair_chain`),
       without ``start``, a view below ``MIN_ELEVATION`` over its treads is refused (seen from
       the side, columns line up by accident).
    1. Coincidences (:func:`meschers_igl.autoview.find_view`, a vote over vertex pairs that
       line up, refined to round-off): taken when a false edge (two caps coinciding on
       screen) or a hidden gap is seen from it -- cut files and capped solids.
       Else caps in one plane with their offset ``T`` in it: the view ``T / |T|``
       (:func:`_cap_views`; a capped tribar among blocks lining up more pairs by accident).
    2. Hidden gaps: the two pieces of a broken bar (:func:`bar_end_pairs`, bar direction
       ``d``, pieces ``T`` apart) line up on screen exactly for the views ``v`` in the plane
       of ``d`` and ``T``: one circle of views.  Along it, the view is the one that centres the
       part hiding the gap on the gap (``v`` along the line from the gap's middle to the
       occluder's centroid, iterated with the gap's middle): where an artist puts the crossing
       bar.  The circle is searched from ``start`` (circles within 10 degrees of it) or, from
       the model alone, in 2-degree steps for a view where the gap is hidden (the
       :data:`MAX_AUTO_BARS` pairs of bar ends nearest each other).  A cut model (open loops)
       takes the vote's view, as :func:`~meschers_igl.autoview.find_view` gives it, when its
       loops glue from it (slits that pair with nothing are no seam).
    3. Crossings (:func:`_crossing_view`): a bar broken in line, completed behind a crossing
       bar, from the middle of the arc of views seeing its ends edge-on.
    4. Edge-on views: a direction better supported than the vote's view but refused for
       seeing over :data:`MAX_EDGE_ON` of the model edge-on (under :data:`EDGE_ON_FALLBACK`:
       a sheared or bevelled figure shows faces containing its view) is taken when a junction
       is seen from it, as in 1.
    5. Crease joints (with ``joint_judge``): two mitred tips meeting at a point (a cube frame
       with its corner cut away) line up one pair of corners, which the vote cannot tell
       from accidents; a pair is a candidate when the corners' creases run along each other
       from it with a mitre behind (:func:`~meschers_igl.obtain.bar_joints.crease_pairs`),
       its direction taken when ``joint_judge`` sees them joined there
       (:func:`~meschers_igl.obtain.view_rank.crease_views`: the nearest tips first).
    6. Ties: the vote's other directions, ranked by the junction a person sees -- corners
       flush on screen and far apart through the model
       (:func:`~meschers_igl.obtain.view_rank.ranked_views`; box corners line up as many pairs
       along lattice directions) -- the first few judged from both sides, as in 1.

    Parameters
    ----------
    V : (#V, 3) array_like of float, F : (#F, 3) array_like of int
        The model (cleaned: welded, oriented outward -- :func:`see_model` passes it so).
    tol : float, optional
        Absolute tolerance (default 1e-5 of the bounding-box diagonal).
    start : (3,) array_like, optional
        A view near the intended one (e.g. off by a few degrees).
    within : float, default: :data:`START_ANGLE`
        With ``start``: how far (radians) from it the view may be.
    judge : callable, optional
        ``judge(view, up) -> bool``: is a junction seen from the vote's view (besides paired
        caps)?  :func:`meschers_igl.obtain.see_model` passes one that glues the visible surface
        and asks for a loop that gains depth.
    joint_judge : callable, optional
        ``joint_judge(view, up, gap) -> bool``: are two corners ``gap`` apart in depth joined
        from ``view`` (a bar joint closing a loop that gains depth)?  Without it, step 5 is
        skipped.

    Returns
    -------
    view, up : (3,) float64
        Unit view (toward the camera) and screen up (world +z projected; for stairs, their
        up axis projected).

    Raises
    ------
    MescherError
        When no view lines up a junction (near ``start``, when given).
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    tol = REL_TOL * diag if tol is None else float(tol)
    start = _unit_start(start)
    chain = stair_chain(V, F, tol)
    stairs = penrose_stairs_view(
        V, F, tol, start, within if start is not None else np.pi, chain=chain
    )
    if stairs is not None:  # an open ring of flights whose top and bottom steps line up
        return stairs
    v, up = _junction_view(V, F, tol, start, judge, within, joint_judge)
    if start is None and chain is not None and v @ chain.up < np.sin(MIN_ELEVATION):
        el = np.degrees(np.arcsin(np.clip(v @ chain.up, -1.0, 1.0)))
        raise MescherError(  # seen from the side, columns of stairs line up by accident
            f"view: expected a view from which junctions line up and the stairs' treads are "
            f"seen from above, found {np.round(v, 4).tolist()} at {el:.3g} degrees; pass view="
        )
    return v, up


def _junction_view(V, F, tol, start, judge, within, joint_judge=None):
    """Steps 1-6 of :func:`find_model_view`: (view, up) from which a junction lines up."""
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    pairs = bar_end_pairs(V, F, tol, TT)
    R0 = view_frame((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))
    part = parts_and_front(V, F, TT, R0)[0]

    arr = _pair_arrays(V, F, part, pairs)

    def seen(v):
        return _junction_seen(V, F, part, pairs, arr, view_frame(v, up_for_view(v)), tol)

    err = vote = None
    try:
        vote = _vote(V, F)
        v, up, _ = _pick(vote, V, F, 1, MAX_EDGE_ON)[0]
    except MescherError as e:
        v, err = None, e
    # a cut model's junctions: its open loops, when they glue from the vote's view (not slits)
    if v is not None and bool(boundary_loops(F)) and _loops_glue(V, F, v, up):
        if start is None or v @ start >= np.cos(within):
            return v, up
    near = v is not None and (start is None or v @ start >= np.cos(within))
    # the best-supported direction, when a junction is seen from it (caps that pair up, or a
    # false edge on the visible surface closing a loop that gains depth); a weaker direction
    # lines up pairs by accident (a staircase seen from below, a frame along its diagonal)
    if near and (seen(v) or (judge is not None and judge(v, up))):
        return v, up
    # caps in one plane: from the view along their offset they coincide (a false edge), however
    # many pairs of other parts line up by accident along another direction (a scene)
    for vc in _cap_views(V, F, arr, tol, start, within):
        if seen(vc):
            return vc, up_for_view(vc)
    # hidden gaps: the bar ends nearest each other first, a bounded number of them
    off = arr.bars & (np.linalg.norm(np.cross(arr.D, arr.T), axis=1) > tol)  # off the bar's line
    k = np.flatnonzero(off)
    k = k[np.argsort(np.linalg.norm(arr.T[k], axis=1), kind="stable")][:MAX_AUTO_BARS]
    vb = _hidden_gap_view(V, F, TT, part, [pairs[i] for i in k.tolist()], tol, start, within)
    if vb is not None:
        return vb, up_for_view(vb)
    vc = _crossing_view(V, F, TT, part, pairs, tol, start, within)
    if vc is not None:
        return vc, up_for_view(vc)
    for ve, upe, _ in _edge_on_views(vote, V, F, v):  # better supported, refused as edge-on
        if start is not None and ve @ start < np.cos(within):
            continue
        if seen(ve) or (judge is not None and judge(ve, upe)):
            return ve, upe
    if joint_judge is not None:  # one pair of mitred tips meeting: a crease joint
        for vc, gap in crease_views(V, F, tol, start, within, VOTE_ANGLE):
            upc = up_for_view(vc)
            if joint_judge(vc, upc, gap):
                return vc, upc
    try:  # directions tied in the vote, ranked: a flush junction far through the model
        cands = _pick(vote, V, F, MAX_RANKED_DIRECTIONS, MAX_EDGE_ON) if vote else []
    except MescherError:
        cands = []
    for vr, upr in ranked_views(V, F, cands, v, tol, start, within, np.cos(VOTE_ANGLE)):
        if seen(vr) or (judge is not None and judge(vr, upr)):
            return vr, upr
    if start is not None:
        raise MescherError(
            f"view: expected a view within {np.degrees(within):.3g} degrees of "
            f"{np.round(start, 6).tolist()} from which junctions line up, found none"
        )
    if err is not None:
        raise err
    raise MescherError(
        f"view: expected a view from which junctions line up, found none (tried the view "
        f"{np.round(v, 4).tolist()} lining up the most vertex pairs, and {int(off.sum())} pair(s) of "
        "bar ends for a hidden gap); pass view= or view_start="
    )


def _cap_views(V, F, arr: _PairArrays, tol, start, within) -> list:
    """The views along the offsets ``T`` of caps lying in one plane (``n . T = 0``: from
    ``T`` they coincide on screen, each seen edge-on -- a capped tribar's false edge), best
    first: along the most such pairs, then nearest ``start``; those seeing over
    :data:`MAX_EDGE_ON` of the model edge-on, or farther than ``within`` from ``start``, left
    out.  Each is ``T / |T|`` exactly, the sign as :func:`find_view`'s (``v_z >= 0``)."""
    L = np.linalg.norm(arr.T, axis=1)
    U = arr.T[L > tol] / L[L > tol, None]
    U = U[np.abs(np.einsum("ij,ij->i", arr.n1[L > tol], U)) <= 1e-6]
    flip = (U[:, 2] < 0) | ((np.abs(U[:, 2]) <= 1e-12) & (U[:, 1] < 0))
    U = np.where(flip[:, None], -U, U)
    if U.shape[0] == 0:
        return []
    _, first, counts = np.unique(np.round(U / 1e-9), axis=0, return_index=True, return_counts=True)
    W = U[first]
    ok = _FaceAreas.of(V, F).edge_on(W) <= MAX_EDGE_ON
    near = np.zeros(W.shape[0]) if start is None else W @ start
    if start is not None:
        ok &= near >= np.cos(within)
    order = np.lexsort((-near, -counts))
    return [W[i] for i in order[ok[order]].tolist()]


def _unit_start(start):
    """``start`` as a unit direction (None stays None); a zero vector is refused."""
    if start is None:
        return None
    start = as_points(np.reshape(start, (1, 3)), "start", 3)[0]
    if np.linalg.norm(start) == 0:
        raise MescherError("start: expected a non-zero direction, found (0, 0, 0)")
    return start / np.linalg.norm(start)


def _loops_glue(V, F, v, up) -> bool:
    """Do the model's boundary loops pair up and glue from view ``v`` (a cut model's seam)?"""
    from ..cutmesh import glue_cut_mesh

    try:
        return bool(glue_cut_mesh(V, F, view=v, up=up)["pairings"])
    except MescherError:
        return False


#: Views on a crossing's circle are judged this far apart (radians); the ends of the arc of
#: views from which the crossing holds are then bisected to round-off.
CROSSING_STEP = np.radians(3.0)


def _crossing_view(V, F, TT, part, pairs, tol, start, within=START_ANGLE):
    """The view from which a bar broken *in line* is completed behind a crossing bar (the
    impossible cube's trick, :func:`junction_at`'s "crossing"), or None.

    The ends are seen edge-on -- the views on the great circle perpendicular to the end
    faces' normal -- and the crossing holds over an arc of that circle, as the crossing bar
    moves across the gap on screen; the view is the arc's middle, where the crossing bar is
    centred on the gap (where an artist puts it).  With ``start``, the crossing view nearest
    it within ``within``; else the one whose arc is longest (the most robust reading).
    """
    withd = [be for be in pairs if be.d is not None]
    D = np.array([be.d for be in withd]).reshape(-1, 3)
    T = np.array([be.T for be in withd]).reshape(-1, 3)
    inline = np.linalg.norm(np.cross(D, T), axis=1) <= tol
    near_first = np.argsort(np.linalg.norm(T, axis=1), kind="stable")
    cand, seen_pairs = [], set()
    for k in near_first[inline[near_first]][: 8 * MAX_AUTO_BARS].tolist():  # nearest first
        be = withd[k]
        key = frozenset((id(be.first), id(be.second)))
        if key in seen_pairs:
            continue  # each unordered pair once
        seen_pairs.add(key)
        if pieces_are_bars(V, F, part, be):  # blocks as long as wide: no bar to complete
            cand.append(be)
    best = None
    for be in cand[:MAX_AUTO_BARS]:  # the in-line bar ends nearest each other
        n = be.first.normal
        a = np.cross(n, np.eye(3)[int(np.argmin(np.abs(n)))])
        a /= np.linalg.norm(a)
        b = np.cross(n, a)

        def view(th, a=a, b=b):
            return np.cos(th) * a + np.sin(th) * b

        blocked = bool(bridges_blocked(V, F, view_frame(a, up_for_view(a)), [be])[0])
        if blocked:
            continue  # the pieces' axis runs through a solid, from every view

        def crossing(th, be=be):
            v = view(th)
            R = view_frame(v, up_for_view(v))
            C, front = _camera(V, F, R)
            found = junction_at(V, F, C, R, be, tol, front, part, True, False)
            return found is not None and found[0] == "crossing"

        steps = np.arange(0.0, 2.0 * np.pi, CROSSING_STEP)
        hit = _crossing_may_hold(
            V, F, be, np.cos(steps)[:, None] * a + np.sin(steps)[:, None] * b, n
        )
        hit[hit] = [crossing(th) for th in steps[hit].tolist()]  # the few views it may hold from
        if not hit.any() or hit.all():
            continue
        k0 = int(np.flatnonzero(~hit)[0])  # runs of hits, from a miss on (circular)
        order = (k0 + np.arange(steps.size)) % steps.size
        h = hit[order]
        starts = np.flatnonzero(h & ~np.r_[False, h[:-1]])
        ends = np.flatnonzero(h & ~np.r_[h[1:], False])
        for s0, e0 in zip(starts.tolist(), ends.tolist()):  # the arcs of views
            lo = _bisect(crossing, steps[order[s0]] - CROSSING_STEP, steps[order[s0]])
            hi = _bisect(crossing, steps[order[e0]] + CROSSING_STEP, steps[order[e0]])
            v = view(0.5 * (lo + hi if hi >= lo else lo + hi + 2.0 * np.pi))
            if start is not None and v @ start < np.cos(within):
                continue
            score = -float(v @ start) if start is not None else -float((hi - lo) % (2 * np.pi))
            if best is None or score < best[0]:
                best = (score, v)
    return None if best is None else best[1]


def _bisect(ok, out: float, inside: float, iters: int = 30) -> float:
    """The boundary between an angle ``out`` where ``ok`` fails and ``inside`` where it holds."""
    for _ in range(iters):  # to round-off of the angle
        mid = 0.5 * (out + inside)
        if ok(mid):
            inside = mid
        else:
            out = mid
    return inside


def _edge_on_views(vote, V, F, v) -> list:
    """The directions supported by more vertex pairs than the vote's view ``v`` (all, when
    ``v`` is None) that :func:`find_view` refused for seeing over :data:`MAX_EDGE_ON` of the
    model edge-on, but under :data:`EDGE_ON_FALLBACK`: at most :data:`MAX_EDGE_ON_VIEWS`
    ``(view, up, pairs)``, the best supported first."""
    try:
        views = _pick(vote, V, F, MAX_EDGE_ON_VIEWS, EDGE_ON_FALLBACK) if vote else []
    except MescherError:
        return []
    out = []
    for w in views:  # a few, in decreasing support
        if v is not None and abs(w[0] @ v) >= np.cos(VOTE_ANGLE):
            break  # the vote's own view (already judged) and the weaker ones after it
        out.append(w)
    return out


def _hidden_gap_view(V, F, TT, part, cand, tol, start, within=START_ANGLE):
    """The view hiding a bar's gap, searched on each candidate's circle of views (from
    ``start`` when given, else in 2-degree steps), nearest ``start``; None when none."""
    best = None
    for be in cand:  # a few candidate bar ends
        w = np.cross(be.d, be.T)
        w /= np.linalg.norm(w)
        e1 = be.d
        e2 = np.cross(w, e1)
        if start is not None:
            if abs(start @ w) > np.sin(within):
                continue
            th0 = np.arctan2(start @ e2, start @ e1)
            n = int(np.ceil(np.degrees(within)))
            k = np.repeat(np.arange(1.0, n + 1.0), 2) * np.tile([-1.0, 1.0], n)
            steps = th0 + np.radians(np.r_[0.0, k])  # the start first, then 1 degree apart
        else:
            steps = np.radians(np.arange(0.0, 360.0, 2.0))
        # T = l d + g v(theta) in the circle's frame: keep the views with l > 0 and g != 0
        t1, t2 = be.T @ e1, be.T @ e2
        sn = np.sin(steps)
        g = t2 / np.where(np.abs(sn) > 1e-9, sn, np.nan)
        steps = steps[(t1 - g * np.cos(steps) > tol) & (np.abs(g) > tol)]
        g = t2 / np.sin(steps)
        views = np.cos(steps)[:, None] * e1 + np.sin(steps)[:, None] * e2
        vb = None
        for s in range(0, steps.size, _HIDE_BLOCK):  # blocks of views, until one hides the gap
            b = slice(s, s + _HIDE_BLOCK)
            may = _gap_may_hide(
                V, F, part, be, tol, views[b], w, g[b], t1 - g[b] * np.cos(steps[b])
            )
            for v0 in views[b][may]:  # the few views the gap may hide behind
                vb = _occluder_centred_view(V, F, TT, part, be, tol, v0)
                if vb is not None:
                    break
            if vb is not None:
                break
        if vb is None or (start is not None and vb @ start < np.cos(within)):
            continue
        score = 0.0 if start is None else -float(vb @ start)
        if best is None or score < best[0]:
            best = (score, vb)
    return None if best is None else best[1]


#: Views on a hidden gap's circle judged together by :func:`_gap_may_hide`.
_HIDE_BLOCK = 16
#: Most (view, sample point, face) triples :func:`_gap_may_hide` forms at once.
_HIDE_CHUNK = 1 << 21


def _gap_may_hide(V, F, part, be: BarEnds, tol, views, w, g, ell) -> np.ndarray:
    """(n,) bool: may the bridge of ``be`` be hidden from each of ``views`` (n, 3), all on the
    circle of views normal to ``w``, with ``T = ell d + g v``?

    False only where :func:`junction_at` surely finds no hidden gap, judged for all views at
    once: the bridge's axis runs through a solid (one winding-number call), or one of its
    sample points is not covered by a face toward the viewer nearer than both pieces (the
    test of ``_tube_hidden``, with a looser inside test: a superset).
    """
    d, P0 = be.d, V[be.first.loop]
    c0 = P0.mean(axis=0)
    along = (np.array([0.25, 0.5, 0.75])[None, :, None] * ell[:, None, None]) * d  # (n, 3, 3)
    axis = c0 + along
    wn = igl.winding_number(V, F, axis.reshape(-1, 3)).reshape(-1, 3)
    out = ~np.any(np.abs(wn) > 0.5, axis=1)
    S = (0.9 * P0 + 0.1 * c0)[None, None] + along[:, :, None]  # (n, 3, #loop, 3)
    S = np.concatenate([S.reshape(views.shape[0], -1, 3), axis], axis=1)  # (n, m, 3)
    own = np.isin(part, part[[be.first.faces[0], be.second.faces[0]]])
    slack = np.where(own, float(np.ptp(P0, axis=0).max()), 0.0)
    k = np.flatnonzero(out)
    sz, zmax, _ = _sample_cover(V, F, views[k], w, S[k], slack)
    out[k] = np.all(zmax > np.maximum(sz, sz + g[k, None]), axis=1)
    return out


def _crossing_may_hold(V, F, be: BarEnds, views, n) -> np.ndarray:
    """(k,) bool: may :func:`junction_at` find ``be`` a crossing from each of ``views`` (all
    normal to ``n``)?  False only where a sample point of the bridge is not covered by any face
    toward the viewer farther than it by the end's screen width (the first test of
    :func:`crossing_behind`, the pieces' own faces included: a superset)."""
    P0 = V[be.first.loop]
    c0 = P0.mean(axis=0)
    ell = float(np.linalg.norm(be.T))  # the pieces are in line: T = ell d
    s = np.array([0.25, 0.5, 0.75])[:, None, None]
    S = np.vstack(
        [(0.9 * P0 + 0.1 * c0 + s * ell * be.d).reshape(-1, 3), c0 + s[:, 0] * ell * be.d]
    )
    S = np.broadcast_to(S, (views.shape[0],) + S.shape)
    u = np.cross(views, n)
    # the screen width in any frame is at least the larger extent along two axes over sqrt 2
    width = np.maximum(np.ptp(P0 @ n), np.ptp(P0 @ u.T, axis=0)) / np.sqrt(2.0)
    sz, _, zmin = _sample_cover(V, F, views, n, S, np.zeros(F.shape[0]))
    return np.all(zmin < sz - width[:, None] + 1e-9 * (1.0 + np.abs(sz)), axis=1)


#: Views on a hidden gap's circle judged together by :func:`_gap_may_hide`.
_HIDE_BLOCK = 16
#: Most (view, sample point, face) triples :func:`_sample_cover` forms at once.
_COVER_CHUNK = 1 << 21


def _sample_cover(V, F, views, w, S, slack):
    """Depths of the faces covering sample points on screen, for views all normal to ``w``.

    Parameters
    ----------
    views : (n, 3) unit views, each normal to ``w`` (the screen is spanned by ``w`` and
        ``v x w``).
    S : (n, m, 3) sample points per view.
    slack : (#F,) subtracted from each face's depth for ``zmax``.

    Returns
    -------
    sz : (n, m) the samples' depths along their view.
    zmax, zmin : (n, m) the largest ``depth - slack`` (-inf where none) and the smallest depth
        (+inf where none) of the faces toward the viewer covering the sample on screen.
    """
    nv, m = S.shape[:2]
    sz = np.einsum("kmj,kj->km", S, views)
    zmax, zmin = np.full((nv, m), -np.inf), np.full((nv, m), np.inf)
    Tw = V[F]
    N = np.cross(Tw[:, 1] - Tw[:, 0], Tw[:, 2] - Tw[:, 0])
    nN = np.linalg.norm(N, axis=1)
    X = Tw @ w  # screen x along w, the same for every view
    x1, x2 = X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]
    u = np.cross(views, w)  # screen y
    step = max(1, _COVER_CHUNK // max(m * F.shape[0], 1))
    for c in range(0, nv, step):  # chunks of views
        k = slice(c, c + step)
        Y, Z = np.moveaxis(Tw @ u[k].T, 2, 0), np.moveaxis(Tw @ views[k].T, 2, 0)  # (nk, #F, 3)
        front = (N @ views[k].T).T > FRONT_NZ * nN - 1e-12 * nN  # (nk, #F)
        sx, sy = S[k] @ w, np.einsum("kmj,kj->km", S[k], u[k])
        y1, y2 = (Y[:, :, 1] - Y[:, :, 0])[:, None], (Y[:, :, 2] - Y[:, :, 0])[:, None]
        den = x1 * y2 - y1 * x2  # (nk, 1, #F)
        px, py = sx[:, :, None] - X[:, 0], sy[:, :, None] - Y[:, None, :, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            b1 = (px * y2 - py * x2) / den
            b2 = (x1 * py - y1 * px) / den
        b0 = 1.0 - b1 - b2
        inside = (b0 >= -1e-6) & (b1 >= -1e-6) & (b2 >= -1e-6) & front[:, None, :]
        zf = b0 * Z[:, None, :, 0] + b1 * Z[:, None, :, 1] + b2 * Z[:, None, :, 2]
        zmax[k] = np.where(inside, zf - slack, -np.inf).max(axis=2)
        zmin[k] = np.where(inside, zf, np.inf).min(axis=2)
    return sz, zmax, zmin
