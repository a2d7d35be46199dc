"""Directions of vertex pairs and their votes: which agree within an angle, either sign.

:func:`~meschers_igl.obtain.view.find_view` votes with the unit directions of vertex pairs: a
view from which parts of a model coincide on screen is a direction many pairs share.  A vote
holds up to a million directions (``MAX_VOTERS`` squared over two), so agreement is found
through a k-d tree of the directions and their opposites, never by scanning all of them for
each candidate.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["near_directions", "unique_rows", "votes"]


def unique_rows(X: np.ndarray):
    """Exactly equal rows of ``X`` (n, 3): (distinct rows, (n,) row -> distinct, counts)."""
    o = np.lexsort(X.T[::-1])
    new = np.r_[True, np.any(X[o[1:]] != X[o[:-1]], axis=1)][: X.shape[0]]
    inv = np.empty(X.shape[0], dtype=np.int64)
    inv[o] = np.cumsum(new) - 1
    return X[o[new]], inv, np.bincount(inv)


def votes(U: np.ndarray, angle: float):
    """How many of the unit directions ``U`` and ``-U`` lie within ``angle`` (chord length) of
    each ``U[k]``, itself included.

    Directions that repeat exactly (a model on a lattice: many vertex pairs along one
    direction) are counted once with their multiplicity, so the cost grows with the pairs of
    *distinct* directions that agree, not with the square of a cluster's size.

    Returns
    -------
    counts : (#U,) int64
    W : (k, 3) float64
        The distinct directions of ``U``.
    inv : (#U,) int64
        ``U[i] == W[inv[i]]``.
    tree : scipy.spatial.cKDTree
        Of ``W`` and ``-W`` (rows ``k`` on: ``-W[r - k]``), for :func:`near_directions`.
    """
    W, inv, mult = unique_rows(U)
    k = W.shape[0]
    tree = cKDTree(np.vstack([W, -W]))
    pq = tree.query_pairs(angle, output_type="ndarray")
    m2 = np.r_[mult, mult].astype(np.float64)
    near = np.bincount(pq[:, 0], weights=m2[pq[:, 1]], minlength=2 * k)
    near += np.bincount(pq[:, 1], weights=m2[pq[:, 0]], minlength=2 * k)
    return (mult + np.rint(near[:k]).astype(np.int64))[inv], W, inv, tree


def near_directions(W: np.ndarray, tree, u: np.ndarray, angle: float) -> np.ndarray:
    """Sorted indices of the distinct unit directions ``W`` with ``abs(W @ u) >= cos(angle)``.

    The same set as scanning every row, found through ``tree`` (of ``W`` and ``-W``, as
    :func:`votes` builds it) within the angle's chord, slightly widened, then tested exactly:
    a vote holds up to a million directions and a candidate needs only its few neighbours.
    """
    k = W.shape[0]
    r = 2.0 * np.sin(0.5 * angle) * (1.0 + 1e-6) + 1e-12
    idx = np.unique(np.asarray(tree.query_ball_point(u, r), dtype=np.int64) % max(k, 1))
    return idx[np.abs(W[idx] @ u) >= np.cos(angle)]
