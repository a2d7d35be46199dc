"""Blocks lined up by chance: a period needs a loop around an opening or a ring of parts.

Scenes of a few boxes, some overlapping, some on a floor (as a modeller lays blocks out), seen
from the view ``view="auto"`` finds for them: two box edges coincide on screen with a depth gap
and gluing them there (a false edge, a hidden gap) would close a short loop through two or three
blocks with a period, around nothing the figure leaves open.  A person sees separate blocks; the
mescher is possible (or no view is found).  A Penrose ring of step columns that hides its own
courtyard from its view keeps its period: its loop runs through a ring of parts.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from test_obtain_hidden_riser import penrose_columns

from meschers_igl import MescherError
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.openings import RING_PARTS, period_around_opening, periods

UP = np.array([0.0, 0.0, 1.0])
FLOOR = (-2.0, 8.0, -2.0, 8.0, -0.3, 0.0)

#: (x0, x1, y0, y1, z0, z1) boxes, a turn about z (degrees) and the view auto found for them
SCENES = {
    "two_rows_on_a_floor": (
        [
            (4, 6, 3, 5, 2, 3),
            (3, 4, 3, 6, 2, 5),
            (2, 3, 4, 5, 3, 5),
            (1, 3, 0, 2, 1, 2),
            (2, 3, 1.5, 2.5, 0, 1),
            (0, 1, 0.5, 3.5, 1, 2),
            FLOOR,
        ],
        0.0,
        (-1.0, 1.0, 1.0),
    ),
    "crossed_slabs_turned": (
        [
            (0, 3, 1, 2, 0, 1),
            (0.5, 1.5, 1, 3, 0.5, 3.5),
            (2, 3, 0, 3, 0.5, 3.5),
            (0.5, 3.5, 2, 5, 0, 1),
        ],
        75.073833482625,
        (0.9794, 0.2017, 0.0),
    ),
    "notched_block_on_a_floor": (
        [(0, 1, 2, 5, 2, 5), (2, 5, 3, 5, 2, 5), (1, 3, 4, 5, 3, 4), (0, 2, 2, 3, 4, 5), FLOOR],
        0.0,
        (-1.0, -1.0, 1.0),
    ),
}


def _scene(name):
    spec, turn, view = SCENES[name]
    V, F = merge_meshes([box_mesh(b[0::2], b[1::2]) for b in spec])
    t = np.radians(turn)
    Rz = np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])
    v = np.asarray(view, float)
    return V @ Rz.T, F, v / np.linalg.norm(v)


def _convert(V, F, view, up=UP):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, up=up)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_blocks_lined_up_by_chance_stay_possible_from_their_view(name):
    """From the view that lines two edges up, the scene is possible in zeta and in its order,
    and no glued junction with a depth gap is reported."""
    V, F, view = _scene(name)
    m, order, report = _convert(V, F, view)
    assert not m.is_impossible(order=order)
    tol = 1e-6 * m.scale()
    assert not [
        j for j in report.junctions if j.depth_gap > tol and j.kind != "occluded continuation"
    ]


@pytest.mark.parametrize("name", sorted(SCENES))
def test_blocks_lined_up_by_chance_from_auto_are_possible_or_refused(name):
    V, F, _ = _scene(name)
    try:
        m, order, _ = _convert(V, F, "auto")
    except MescherError as err:
        assert str(err).startswith(("view:", "V:"))
        return
    assert not m.is_impossible(order=order)


@pytest.mark.parametrize("s", [4, 5, 6])
def test_a_ring_of_columns_hiding_its_courtyard_keeps_its_climb(s):
    """Seen along ``w`` the columns' far side covers the courtyard: no opening, but the loop
    runs through every column (at least :data:`RING_PARTS`), and the period is one turn's climb
    ``|w|`` (also for ``s = 6``, a ring none of the other tests builds)."""
    V, F, w = penrose_columns(s)
    m, order, _ = _convert(V, F, w / np.linalg.norm(w))
    p = np.abs(np.asarray(m.periods()))
    p = p[p > 1e-6 * m.scale()]
    assert m.is_impossible(order=order).kind == "zeta"
    np.testing.assert_allclose(p.min(), np.linalg.norm(w), rtol=1e-6)


def _covered_ring(n_parts):
    """A square frame climbing ``2 pi`` per turn (8 triangles, depth = angle) with a plate in
    front covering its opening, the frame's faces dealt round-robin into ``n_parts`` parts and
    the plate a part of its own: (F, xy, Z, part)."""
    r = np.array([[-2, -2], [2, -2], [2, 2], [-2, 2], [-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    F = np.array(
        [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
    )
    ang = np.mod(np.arctan2(r[:, 1], r[:, 0]), 2 * np.pi)[F]
    Z = np.where(ang - ang.min(axis=1, keepdims=True) > np.pi, ang - 2 * np.pi, ang)
    plate_xy = np.array([[-1.5, -1.5], [1.5, -1.5], [1.5, 1.5], [-1.5, 1.5]])
    plate = np.array([[8, 9, 10], [8, 10, 11]])
    part = np.r_[np.arange(8) * n_parts // 8, [n_parts, n_parts]]
    return (
        np.vstack([F, plate]),
        np.vstack([r, plate_xy]),
        np.vstack([Z, np.full((2, 3), 9.0)]),
        part,
    )


@pytest.mark.parametrize(
    "n_parts, kept", [(1, False), (2, False), (3, False), (4, True), (8, True)]
)
def test_a_loop_with_no_opening_counts_only_through_a_ring_of_parts(n_parts, kept):
    F, xy, Z, part = _covered_ring(n_parts)
    assert np.abs(periods(F, xy, Z)[1]).max() == pytest.approx(2 * np.pi)
    assert period_around_opening(F, xy, Z, 1e-9, 1e-6, part) is False  # the plate covers it
    assert period_around_opening(F, xy, Z, 1e-9, 1e-6, part, RING_PARTS) is kept
    flat = np.zeros_like(Z)  # no period: nothing to keep, whatever the parts
    assert period_around_opening(F, xy, flat, 1e-9, 1e-6, part, RING_PARTS) is None


def _city():
    """Nine towers of heights 1..4 on a 3 x 3 grid (spacing 2) standing on a ground slab."""
    towers = [
        box_mesh([2 * x, 2 * y, 0], [2 * x + 1, 2 * y + 1, 1 + (7 * x + 3 * y) % 4])
        for x in range(3)
        for y in range(3)
    ]
    return merge_meshes([*towers, box_mesh([-1, -1, -0.1], [6, 6, 0])])


def test_towers_standing_on_a_slab_are_not_broken_bars():
    """Seen from below along (0, -20, -21): a tower's top and another's foot, standing on the
    slab, are congruent caps lined up on screen 2.9 apart in depth, the foot hidden by the slab.
    A foot resting on the slab is no end of a broken bar: nothing is bridged, the city is
    possible (in zeta and in its order) from there and from ``view="auto"``."""
    V, F = _city()
    v = np.array([0.0, -20.0, -21.0]) / 29.0
    m, order, report = _convert(V, F, v)
    assert not [j for j in report.junctions if j.kind == "hidden gap"]
    assert not m.is_impossible(order=order)
    try:
        m, order, _ = _convert(V, F, "auto")
    except MescherError as err:
        assert str(err).startswith(("view:", "V:"))
        return
    assert not m.is_impossible(order=order)
