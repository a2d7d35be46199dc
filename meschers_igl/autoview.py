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

from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from .errors import MescherError
from .topology import boundary_loops
from .validate import as_faces, as_points

__all__ = ["find_view", "up_for_view"]

#: Vertices taking part in the vote (all pairs among them are tried).
MAX_VOTERS = 1500
#: Pair directions within this angle (radians) vote for the same view.
VOTE_ANGLE = 2e-4
#: Distinct directions (by votes) judged before giving up.
MAX_DIRECTIONS = 200
#: Largest share of the model's area seen edge-on from an acceptable view.
MAX_EDGE_ON = 0.2


def up_for_view(view: Any) -> np.ndarray:
    """Screen up for ``view``: world +z projected onto the screen plane (+y if view is vertical)."""
    v = np.asarray(view, dtype=np.float64)
    v = v / np.linalg.norm(v)
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])):
        u = axis - (axis @ v) * v
        if np.linalg.norm(u) > 1e-6:
            return u / np.linalg.norm(u)
    raise MescherError(f"view: expected a finite direction, found {v.tolist()}")  # unreachable


def _voters(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Boundary vertices of a cut model, else every used vertex (sampled down to MAX_VOTERS)."""
    loops = boundary_loops(F)
    S = np.unique(np.concatenate(loops)) if loops else np.unique(F)
    if S.size > MAX_VOTERS:
        S = np.sort(rng.choice(S, MAX_VOTERS, replace=False))
    return S


def find_view(V: Any, F: Any, *, return_support: bool = False, max_views: int = 1):
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
    on_face = set()
    for a, b in ((0, 1), (1, 2), (2, 0)):
        e = np.sort(Fs[:, [a, b]], axis=1)
        e = e[(e >= 0).all(axis=1)]
        on_face.update((e[:, 0] * S.size + e[:, 1]).tolist())
    key = i * S.size + j
    ok &= ~np.isin(key, np.fromiter(on_face, dtype=np.int64, count=len(on_face)))
    D, L, i, j = D[ok], L[ok], i[ok], j[ok]
    U = D / L[:, None]
    U *= np.where(U @ np.array([1e-3, 1e-2, 1.0]) < 0, -1.0, 1.0)[:, None]  # one hemisphere
    tree = cKDTree(np.vstack([U, -U]))
    # votes: pairs whose directions agree within VOTE_ANGLE (either sign), longer pairs first
    counts = np.array([len(c) for c in tree.query_ball_point(U, VOTE_ANGLE)])
    if counts.size == 0 or counts.max() < 2:
        raise MescherError(
            "V: expected vertex pairs that line up along a common direction (a view in which "
            "parts of the model coincide on screen), found none; pass view= explicitly"
        )
    # candidates by votes; a view must not see much of the model edge-on (a view along an
    # axis of a box model lines up many pairs but shows its side faces as lines)
    T = V[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    area = np.linalg.norm(n, axis=1)
    nu = n / np.maximum(area, 1e-300)[:, None]
    order = np.lexsort((-L, -counts))
    found = []
    tried = np.zeros(U.shape[0], dtype=bool)  # pairs whose direction was already judged
    n_tried = 0
    for c in order.tolist():  # the best-supported distinct directions first, few tried
        if tried[c]:
            continue
        if counts[c] < 2 or n_tried >= MAX_DIRECTIONS or len(found) >= max_views:
            break
        n_tried += 1
        tried |= np.abs(U @ U[c]) >= np.cos(VOTE_ANGLE)
        edge_on = float(area[np.abs(nu @ U[c]) < 1e-3].sum() / area.sum())
        if edge_on <= MAX_EDGE_ON:
            found.append(c)
    if not found:
        raise MescherError(
            "V: expected vertex pairs that line up along a direction from which the model is "
            "not seen edge-on, found none; pass view= explicitly"
        )
    out = []
    for k in found:  # refine each candidate
        support = np.flatnonzero(np.abs(U @ U[k]) >= np.cos(VOTE_ANGLE))
        # the direction that makes the supporting pairs coincide best (weighted by length^2)
        M = D[support].T @ D[support]
        w, E = np.linalg.eigh(M)
        v = E[:, -1]
        if v[2] < 0 or (abs(v[2]) <= 1e-12 and v[1] < 0):
            v = -v
        out.append((v, up_for_view(v), np.stack([S[i[support]], S[j[support]]], axis=1)))
    if max_views == 1:
        v, up, pairs = out[0]
        return (v, up, pairs) if return_support else (v, up)
    return out
