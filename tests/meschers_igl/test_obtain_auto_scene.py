"""``view="auto"`` in a scene: a capped tribar standing beside a grid of blocks.

The blocks line up along many directions by accident (a grid of cubes from a diagonal), and
the vertex pairs along one of them outnumber the pairs along the tribar's junction.  The
tribar's two caps lie in one plane with their offset ``T`` in it: from the view ``T / |T|``
they coincide on screen, each edge-on -- the junction a person sees -- however many pairs of
other parts line up elsewhere.  The view is ``T / |T|`` to round-off, the period the built gap.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from visible_models import AXES, ring, triangulate, weld_blocks

from meschers_igl import MescherError
from meschers_igl.obtain import PERIOD_RTOL, model_to_mescher
from meschers_igl.obtain.view import find_view
from meschers_igl.shapes import block_grid


def capped_tribar(lengths=(4.0, 4.0, 4.0)):
    """A tribar of x, y and z bars of the given lengths, opened in the x bar and capped there by
    one plane holding the view ``sum of the bars`` (not isometric unless the lengths agree).
    Returns (V, F, view, gap)."""
    x, y, z = AXES
    view = np.asarray(lengths, float) / np.linalg.norm(lengths)
    blocks, gap = ring([(x, lengths[0]), (y, lengths[1]), (z, lengths[2])], 1.0, view=view)
    V, P = weld_blocks(blocks)
    return V, triangulate(P), view, gap


def in_a_scene(V, F, n, offset=(12.0, -4.0, -1.0)):
    """``(V, F)`` beside an ``n x n`` grid of separate 2 x 2 x 1 blocks."""
    Vg, Fg = block_grid(n)
    return np.vstack([V, Vg + np.asarray(offset)]), np.vstack([F, Fg + V.shape[0]])


def _auto(V, F, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view="auto", **kw)


@pytest.mark.parametrize("lengths", [(4.0, 4.0, 4.0), (6.0, 3.0, 5.0)])
@pytest.mark.parametrize("n", [3, 5])
def test_the_tribar_junction_wins_over_the_blocks_lined_up_by_accident(lengths, n):
    V, F, view, gap = capped_tribar(lengths)
    V, F = in_a_scene(V, F, n)
    v, _ = find_view(V, F)  # the vote: the blocks' accidental direction, not the junction
    assert np.linalg.norm(np.cross(v, view)) > 0.1
    m, order, report = _auto(V, F)
    assert np.linalg.norm(np.cross(report.view, view)) <= 1e-12
    p = np.abs(np.asarray(m.periods()))
    p = p[p > PERIOD_RTOL * m.scale()]
    assert p.size >= 1 and np.allclose(p, gap, rtol=1e-9)
    assert m.is_impossible(order=order).kind == "zeta"


def test_an_approximate_start_finds_the_same_view_and_the_blocks_alone_stay_possible():
    V0, F0, view, gap = capped_tribar((6.0, 3.0, 5.0))
    V, F = in_a_scene(V0, F0, 4)
    start = view + np.array([0.04, -0.03, 0.02])  # a few degrees off
    _, _, report = _auto(V, F, view_start=start / np.linalg.norm(start))
    assert np.linalg.norm(np.cross(report.view, view)) <= 1e-12
    # 10 degrees is the reach of a start: from 30 degrees off, no view
    far = np.cross(view, (0.0, 0.0, 1.0))
    far = np.cos(np.radians(30)) * view + np.sin(np.radians(30)) * far / np.linalg.norm(far)
    with pytest.raises(MescherError, match="within 10 degrees"):
        _auto(V, F, view_start=far)
    # the grid alone: nothing impossible to find
    Vg, Fg = block_grid(4)
    try:
        m, order, _ = _auto(Vg, Fg)
    except MescherError as err:
        assert str(err).startswith("view: expected a view from which junctions line up")
    else:
        assert not m.is_impossible(order=order)


def _backdrop(V, F, size=40.0, gap=6.0):
    """``(V, F)`` in front of a large thin box behind it, seen face-on from the tribar's view
    side (a wall or a floor an artist puts behind a figure), much larger in area than it."""
    from visible_models import box_block

    lo = V.min(axis=0) - gap - np.array([size, size, 1.0])
    Vb, Pb = box_block(lo, lo + np.array([2 * size, 2 * size, 1.0]))
    Fb = triangulate(Pb)
    return np.vstack([V, Vb]), np.vstack([F, Fb + V.shape[0]])


@pytest.mark.parametrize("lengths", [(4.0, 4.0, 4.0), (6.0, 3.0, 5.0)])
def test_a_backdrop_does_not_hide_that_the_figure_is_seen_edge_on(lengths):
    """The share seen edge-on weighs each part by the vertex pairs it lines up: from an axis
    of the bars the tribar (which lines the pairs up) shows its sides as lines, however much
    face-on area a backdrop adds to the scene."""
    from meschers_igl.obtain.view import MAX_EDGE_ON, _FaceAreas

    V, F, view, gap = capped_tribar(lengths)
    Vs, Fs = _backdrop(V, F)
    faces, alone = _FaceAreas.of(Vs, Fs), _FaceAreas.of(V, F)
    z = np.array([[0.0, 0.0, 1.0]])  # an axis of the bars, face-on to the backdrop
    whole = float(faces.area[np.abs(faces.nu @ z[0]) < 1e-3].sum() / faces.area.sum())
    assert faces.edge_on(z)[0] == pytest.approx(whole, rel=1e-12)  # default: area-weighted
    assert whole < MAX_EDGE_ON  # the whole scene's share would let the axis view pass
    ends = np.arange(V.shape[0])  # pairs lined up by the tribar's vertices only
    assert faces.edge_on(z, ends)[0] == pytest.approx(alone.edge_on(z)[0], rel=1e-12)
    assert faces.edge_on(z, ends)[0] > MAX_EDGE_ON
    # pairs in both parts: each part's share weighed by its count of pair ends
    back = np.arange(V.shape[0], Vs.shape[0])
    mixed = faces.edge_on(z, np.r_[ends, back[:4]])[0]
    own_back = float(
        faces.area[(faces.part == faces.part[-1]) & (np.abs(faces.nu @ z[0]) < 1e-3)].sum()
        / faces.area[faces.part == faces.part[-1]].sum()
    )
    n = ends.size
    assert mixed == pytest.approx((n * alone.edge_on(z)[0] + 4 * own_back) / (n + 4))
    m, order, report = _auto(Vs, Fs)
    assert np.linalg.norm(np.cross(report.view, view)) <= 1e-9
    p = np.abs(np.asarray(m.periods()))
    p = p[p > PERIOD_RTOL * m.scale()]
    assert p.size >= 1 and np.allclose(p, gap, rtol=1e-9)
