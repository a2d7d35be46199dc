"""A hidden gap is a *bar* broken behind an occluder: two pieces in line, each longer than
it is wide, which a viewer completes into one bar (good continuation).  Blocks as long as they
are wide -- a level laid out as a grid of cubes -- line up behind one another from many views
without being one object: they stay separate, and the scene stays possible.
"""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from visible_models import ISO_VIEW, hidden_gap_frame, triangulate

from meschers_igl import MescherError
from meschers_igl.obtain import model_to_mescher, weld
from meschers_igl.obtain.junctions import bar_end_pairs, parts_and_front, pieces_are_bars
from meschers_igl.operators import view_frame


def cube_grid(nx=3, ny=2, pitch=3.0):
    """Unit cubes on a ``pitch`` grid in the ground plane, as a level designer lays them out."""
    cubes = [
        box_mesh([pitch * i, pitch * j, 0.0], [pitch * i + 1, pitch * j + 1, 1.0])
        for i in range(nx)
        for j in range(ny)
    ]
    return merge_meshes(cubes)


#: From (3, 2, 0) the cube at (0, 0) lines up on screen with the cube at (3, 2), one pitch
#: deeper, the space between them hidden behind the cube at (3, 0).
LINED_UP = np.array([3.0, 2.0, 0.0]) / np.sqrt(13.0)


def _quiet(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(*args, **kwargs)


def test_cubes_lined_up_behind_a_cube_stay_separate():
    """Seen from a view that lines two cubes up behind a third, no bridge joins them (false
    edges between silhouettes that coincide may be glued: separate blocks make no loop) and the
    grid stays possible; ``view="auto"`` finds no view to take from it."""
    V, F = cube_grid()
    m, order, report = _quiet(V, F, view=LINED_UP, up=(0.0, 0.0, 1.0))
    assert not [j for j in report.junctions if j.kind == "hidden gap"]
    assert not m.is_impossible(order=order)
    assert np.all(np.asarray(m.periods()) == 0.0)
    try:
        m, order, _ = _quiet(V, F, view="auto")
    except MescherError as err:
        assert str(err).startswith("view: expected a view from which junctions line up")
    else:
        assert not m.is_impossible(order=order)


@pytest.mark.parametrize("length", [0.5, 1.0, 1.3, 3.0])
def test_pieces_are_bars_when_longer_than_their_caps_are_wide(length):
    """Two boxes ``1 x 1`` in cross-section, ``length`` long along x, in line 2 apart: bars
    when ``length`` exceeds the cap's diagonal sqrt(2) (its widest extent)."""
    V, F = merge_meshes(
        [
            box_mesh([0.0, 0.0, 0.0], [length, 1.0, 1.0]),
            box_mesh([length + 2, 0, 0], [2 * length + 2, 1, 1]),
        ]
    )
    V, F, _ = weld(V, F, 1e-9)
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    part = parts_and_front(V, F, TT, view_frame(ISO_VIEW, (0.0, 0.0, 1.0)))[0]
    facing = [be for be in bar_end_pairs(V, F, 1e-9, TT) if be.d is not None and be.d[0] > 0.5]
    facing = [be for be in facing if np.isclose(np.linalg.norm(be.T), 2.0)]
    assert len(facing) == 1
    assert pieces_are_bars(V, F, part, facing[0]) == (length > np.sqrt(2.0))


def test_the_hidden_gap_frame_pieces_are_bars():
    """The broken bar of the hidden-gap frame (one welded frame) still counts as a bar, and its
    period is the built gap from its view."""
    V, P, gap = hidden_gap_frame()
    m, _, report = _quiet(V, triangulate(P), view=ISO_VIEW, up=(-1.0, -1.0, 2.0))
    assert [j.kind for j in report.junctions].count("hidden gap") == 1
    p = np.abs(np.asarray(m.periods()))
    assert np.isclose(p.max(), gap, rtol=1e-9)


def test_cubes_either_side_of_a_crossing_bar_are_no_broken_bar():
    """Two bars in line either side of a bar lying behind their gap (seen along -y) are read
    as one bar completed behind it (a crossing); two cubes there are two cubes."""
    from visible_models import box_block, separate_blocks

    behind = box_block([2.5, 4, -3], [3.5, 5, 4])
    for lo0, hi1, kinds in ((0.0, 6.0, ["crossing"]), (1.5, 4.5, [])):
        blocks = [box_block([lo0, 0, 0], [2.5, 1, 1]), box_block([3.5, 0, 0], [hi1, 1, 1]), behind]
        V, polys = separate_blocks(blocks)
        _, _, report = _quiet(V, np.asarray(triangulate(polys)), view=(0, -1.0, 0), up=(0, 0, 1.0))
        assert [j.kind for j in report.junctions if j.kind == "crossing"] == kinds
