"""The automatic view's searches judge many views and pairs at once: each vectorised test is
checked against the pair-by-pair, view-by-view rule it stands for (an independent oracle).

* the pairs that may be bridged (:func:`pieces_are_bars` for all pairs at once) are exactly
  those the per-pair rule accepts;
* the views a hidden gap may hide behind, and those a crossing may hold from, are supersets
  of the views :func:`junction_at` finds the junction from (a prefilter never drops one).
"""

from __future__ import annotations

import igl
import numpy as np
import pytest
from visible_models import block_stairs, hidden_gap_cube, hidden_gap_frame, triangulate

from meschers_igl.obtain.junctions import (
    bar_end_pairs,
    junction_at,
    parts_and_front,
    pieces_are_bars,
)
from meschers_igl.obtain.view import (
    _camera,
    _crossing_may_hold,
    _gap_may_hide,
    _pair_arrays,
    up_for_view,
)
from meschers_igl.operators import view_frame
from meschers_igl.shapes import block_grid, boxes


def _prepared(V, F):
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    part = parts_and_front(V, F, TT, view_frame((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)))[0]
    tol = 1e-5 * float(np.linalg.norm(np.ptp(V, axis=0)))
    return TT, part, tol


def _weld(V, F):
    from meschers_igl.obtain import weld

    V, F, _ = weld(V, F, 1e-9)
    return V, F


def _bars_and_blocks():
    """Bars in line 1 apart and offset (long boxes) beside cubes (blocks as long as wide)."""
    lo = np.array([[0, 0, 0], [4, 0, 0], [0, 3, 0], [5, 3, 1], [0, 6, 0], [2, 6, 0]], float)
    hi = lo + np.array([[3, 1, 1], [3, 1, 1], [3, 1, 1], [3, 1, 1], [1, 1, 1], [1, 1, 1]], float)
    return _weld(*boxes(lo, hi))


MODELS = {
    "frame": lambda: _weld(hidden_gap_frame()[0], triangulate(hidden_gap_frame()[1])),
    "cube": lambda: _weld(hidden_gap_cube()[0], triangulate(hidden_gap_cube()[1])),
    "stairs": lambda: _weld(block_stairs()[0], triangulate(block_stairs()[1])),
    "grid": lambda: _weld(*block_grid(3)),
    "bars_and_blocks": _bars_and_blocks,
}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_pairs_that_may_be_bridged_are_the_per_pair_rule(name):
    V, F = MODELS[name]()
    TT, part, tol = _prepared(V, F)
    pairs = bar_end_pairs(V, F, tol, TT)
    arr = _pair_arrays(V, F, part, pairs)
    ref = [
        be.d is not None and be.first.normal @ be.d > 0 and pieces_are_bars(V, F, part, be)
        for be in pairs
    ]
    assert arr.bars.tolist() == ref
    assert np.array_equal(arr.T, np.array([be.T for be in pairs]).reshape(-1, 3))
    if name == "bars_and_blocks":  # both kinds are there: the test can tell them apart
        assert 0 < int(arr.bars.sum()) < len(pairs)


def _circle(be):
    w = np.cross(be.d, be.T)
    w /= np.linalg.norm(w)
    return w, be.d, np.cross(w, be.d)


@pytest.mark.parametrize("name", ["frame", "cube", "bars_and_blocks"])
def test_views_a_gap_may_hide_behind_hold_every_hidden_gap(name):
    """On each offset pair's circle of views (1 degree apart), every view from which
    :func:`junction_at` finds a hidden gap is kept by the vectorised prefilter, and the
    prefilter drops some views (it is not the trivial superset)."""
    V, F = MODELS[name]()
    TT, part, tol = _prepared(V, F)
    arr_pairs = bar_end_pairs(V, F, tol, TT)
    arr = _pair_arrays(V, F, part, arr_pairs)
    n_hit = n_dropped = 0
    for be, bar in zip(arr_pairs, arr.bars.tolist()):
        if not bar or np.linalg.norm(np.cross(be.d, be.T)) <= tol:
            continue
        w, e1, e2 = _circle(be)
        th = np.radians(np.arange(0.5, 360.0, 1.0))
        t1, t2 = be.T @ e1, be.T @ e2
        g = t2 / np.sin(th)
        ell = t1 - g * np.cos(th)
        keep = (ell > tol) & (np.abs(g) > tol)
        th, g, ell = th[keep], g[keep], ell[keep]
        views = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
        may = _gap_may_hide(V, F, part, be, tol, views, w, g, ell)
        for v, m in zip(views, may.tolist()):
            R = view_frame(v, up_for_view(v))
            C, front = _camera(V, F, R)
            found = junction_at(V, F, C, R, be, tol, front, part, True)
            hidden = found is not None and found[0] == "hidden gap"
            assert m or not hidden, (name, v)
            n_hit += hidden
            n_dropped += not m
    if name != "bars_and_blocks":
        assert n_hit > 0 and n_dropped > 0


@pytest.mark.parametrize("k", [0, 1])
def test_views_a_crossing_may_hold_from_hold_every_crossing(k):
    """On the circle of views seeing an impossible cube's in-line ends edge-on (1 degree
    apart; the frames of the crossing tests), every view from which :func:`junction_at` finds
    the crossing is kept, and some views are dropped."""
    from test_visible_crossing import VIEWS, _frame

    V, F = _weld(*_frame(VIEWS[k])[:2])
    TT, part, tol = _prepared(V, F)
    pairs = bar_end_pairs(V, F, tol, TT)
    arr = _pair_arrays(V, F, part, pairs)
    inline = arr.bars & (np.linalg.norm(np.cross(arr.D, arr.T), axis=1) <= tol)
    assert inline.any()
    n_hit = n_dropped = 0
    for k in np.flatnonzero(inline).tolist():
        be = pairs[k]
        n = be.first.normal
        a = np.cross(n, np.eye(3)[int(np.argmin(np.abs(n)))])
        a /= np.linalg.norm(a)
        b = np.cross(n, a)
        th = np.radians(np.arange(0.0, 360.0, 1.0))
        views = np.cos(th)[:, None] * a + np.sin(th)[:, None] * b
        may = _crossing_may_hold(V, F, be, views, n)
        for v, m in zip(views, may.tolist()):
            R = view_frame(v, up_for_view(v))
            C, front = _camera(V, F, R)
            found = junction_at(V, F, C, R, be, tol, front, part, True, False)
            crossing = found is not None and found[0] == "crossing"
            assert m or not crossing, v
            n_hit += crossing
            n_dropped += not m
    assert n_hit > 0 and n_dropped > 0
