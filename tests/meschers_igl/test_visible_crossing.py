"""The impossible cube's trick, built here: a real cube frame (one welded solid) whose nearer
bar is broken *in line* exactly where a farther bar crosses it on screen.  The farther bar
shows through the gap, so a viewer completes the broken bar behind it -- which contradicts
the frame's depths: impossible through the depth order, with no period.

Controls: the same frame cut square (an end face is seen: the bar visibly stops), with a
wider gap (background shows beside the crossing bar), seen from another view, a broken bar in front of a wall, and a crossing bar that is a separate
part (its depth is free: the completed reading is realisable) all stay possible.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from visible_models import (
    AXES,
    box_block,
    convex_block,
    separate_blocks,
    triangulate,
    weld_blocks,
)

from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.junctions import CROSSING_SLACK


def _frame_bars(L):
    C = [np.array(c, float) * L for c in np.ndindex(2, 2, 2)]
    return [
        (a, b) for i, a in enumerate(C) for b in C[i + 1 :] if np.isclose(np.linalg.norm(a - b), L)
    ]


def _box_along(P0, P1, d, t):
    h = t / 2
    side = h * (1 - np.abs(d))
    return box_block(np.minimum(P0, P1) - side, np.maximum(P0, P1) + side)


def _slanted_piece(A, d, t, start, n, X):
    """A square bar on the axis through A along d, from ``start`` (square end) to the plane
    through X with normal n (n . d > 0), as a convex block."""
    o = [k for k in range(3) if abs(d[k]) < 0.5]
    hs = [np.r_[s * AXES[k], -s * (A @ AXES[k]) - t / 2] for k in o for s in (1.0, -1.0)]
    hs += [np.r_[-d, d @ start], np.r_[n, -(n @ X)]]
    return convex_block(np.asarray(hs), 0.5 * (start + X))


def _frame(view, L=6.0, t=1.0, widen=0.0, broken=True, square=False):
    """Corner cubes and 12 bars over {0, L}^3, welded; the nearer of two bars whose axes cross
    on screen (within 0.3 to 0.7 of each, more than 2 t apart in depth) is cut in line where its
    axis crosses the farther bar's band (widened by ``widen`` on each side), by planes holding
    the view (the ends are seen edge-on, as the impossible cube is built; ``square``: cut
    square, so that an end face is seen); with
    ``broken=False`` the frame stays whole.

    Returns (V, F, R, crossing) with R the view frame (rows right, up, view); ``crossing`` is
    False when no two bars cross so (the unbroken frame is returned)."""
    v = np.asarray(view, float) / np.linalg.norm(view)
    up = AXES[2] - v[2] * v
    up /= np.linalg.norm(up)
    R = np.stack([np.cross(up, v), up, v])
    bars = _frame_bars(L)
    best = None
    for i, (A, B) in enumerate(bars):
        for P, Q in bars:
            a, b, p, q = (R[:2] @ x for x in (A, B, P, Q))
            M = np.stack([b - a, p - q], 1)
            if abs(np.linalg.det(M)) < 1e-6:
                continue
            s, u = np.linalg.solve(M, p - a)
            near = v @ (A + s * (B - A)) > v @ (P + u * (Q - P)) + 2 * t
            if best is None and broken and 0.3 < s < 0.7 and 0.3 < u < 0.7 and near:
                best = (i, P, Q)
    blocks = [
        box_block(c - t / 2, c + t / 2)
        for c in (np.array(c, float) * L for c in np.ndindex(2, 2, 2))
    ]
    h = t / 2
    for k, (P, Q) in enumerate(bars):
        if best is None or k != best[0]:
            d = (Q - P) / L
            blocks.append(_box_along(P + h * d, Q - h * d, d, t))
    if best is not None:
        i, P, Q = best
        A, B = bars[i]
        d, e = (B - A) / L, (Q - P) / L
        # the far bar's band on screen: its cross-section's offsets across its screen direction
        e2 = R[:2] @ e
        nrm = np.array([-e2[1], e2[0]]) / np.linalg.norm(e2)
        o = [k for k in range(3) if abs(e[k]) < 0.5]
        off = [(R[:2] @ (x * AXES[o[0]] + y * AXES[o[1]])) @ nrm for x in (-h, h) for y in (-h, h)]
        base = (R[:2] @ (A - P)) @ nrm
        xs = sorted((c - base) / ((R[:2] @ d) @ nrm) for c in (min(off) - widen, max(off) + widen))
        # cut by planes holding the view and the far bar's direction: each end is seen edge-on
        # and its screen trace is an edge of the far bar's band
        n = np.cross(v, e)
        n *= np.sign(n @ d) / np.linalg.norm(n)
        if square:
            n = d
        blocks.append(_slanted_piece(A, d, t, A + h * d, n, A + xs[0] * d))
        blocks.append(_slanted_piece(A, -d, t, B - h * d, -n, A + xs[1] * d))
    V, polys = weld_blocks(blocks)
    return V, np.asarray(triangulate(polys), np.int64), R, best is not None


def _convert(V, F, view, up):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = model_to_mescher(V, F, view=view, up=up)
    return m, order, report


VIEWS = [(1, 2, 3), (2, 3, 1.5), (3, 1, 2), (1, 3, 2), (2, -1, 3)]


@pytest.mark.parametrize("view", VIEWS)
def test_crossing_frame_is_impossible_by_order(view):
    V, F, R, crossed = _frame(view)
    assert crossed
    m, order, report = _convert(V, F, R[2], R[1])
    assert report.route == "closed", str(report)
    assert [j.kind for j in report.junctions] == ["crossing"], str(report)
    imp = m.is_impossible(order=order)
    assert imp.kind == "order", (view, str(imp))
    # in line: the completed bar gains no depth around any loop
    assert np.abs(m.periods()).max(initial=0.0) <= 1e-9 * m.scale()
    # the tube (bridge faces) lies behind faces it is in front of in 3D
    assert np.count_nonzero(report.source_face < 0) == 8  # a square tube: 4 quads


@pytest.mark.parametrize("view", VIEWS[:2])
def test_crossing_controls_stay_possible(view):
    V, F, R, _ = _frame(view)
    V0, F0, R0, crossed = _frame(view, broken=False)  # the whole frame
    assert not crossed
    m, order, report = _convert(V0, F0, R0[2], R0[1])
    assert all(j.depth_gap == 0.0 or j.kind == "occluded continuation" for j in report.junctions)
    assert not any(j.kind == "crossing" for j in report.junctions)
    assert not m.is_impossible(order=order)
    # square ends: an end face is seen, the bar visibly stops
    Vs, Fs, Rs, _ = _frame(view, square=True)
    m, order, report = _convert(Vs, Fs, Rs[2], Rs[1])
    assert not any(j.kind == "crossing" for j in report.junctions)
    assert not m.is_impossible(order=order)
    # a wider gap shows background beside the crossing bar
    Vw, Fw, Rw, _ = _frame(view, widen=0.5)
    m, order, report = _convert(Vw, Fw, Rw[2], Rw[1])
    assert not any(j.kind == "crossing" for j in report.junctions)
    assert not m.is_impossible(order=order)
    # the same broken frame from a view 8 degrees away: a broken bar, nothing lines up
    v = R[2] + np.radians(8.0) * R[0]
    v /= np.linalg.norm(v)
    m, order, report = _convert(V, F, v, R[1])
    assert not any(j.kind == "crossing" for j in report.junctions)
    assert not m.is_impossible(order=order)


def test_crossing_slack_is_a_share_of_the_gap():
    assert 0.0 < CROSSING_SLACK < 0.5


def test_broken_bar_before_a_wall_and_a_separate_crossing_bar_are_possible():
    """A wall covers far beyond the gap (not a bar crossing it); a crossing bar that is a part
    of its own can be moved in depth, so the completed reading is realisable."""
    wall = [
        box_block([0, 0, 0], [2.5, 1, 1]),
        box_block([3.5, 0, 0], [6, 1, 1]),
        box_block([-2, 4, -3], [8, 5, 4]),
    ]
    for view in [(0.3, -1, 0.4), (0, -1, 0.2)]:
        v = np.asarray(view, float) / np.linalg.norm(view)
        up = AXES[2] - v[2] * v
        V, polys = separate_blocks(wall)
        m, order, report = _convert(V, np.asarray(triangulate(polys)), v, up / np.linalg.norm(up))
        assert not report.junctions or all(j.kind != "crossing" for j in report.junctions)
        assert not m.is_impossible(order=order)
    cross = wall[:2] + [box_block([2.5, 4, -3], [3.5, 5, 4])]
    V, polys = separate_blocks(cross)
    m, order, report = _convert(V, np.asarray(triangulate(polys)), (0, -1.0, 0), (0, 0, 1.0))
    assert [j.kind for j in report.junctions] == ["crossing"]
    assert not m.is_impossible(order=order)
