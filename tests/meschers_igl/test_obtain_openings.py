"""Bar joints only around openings: a chain of bars joined end to end encloses a window.

Three boxes seen along their legs make the Penrose triangle: the joined loop winds once around
the triangle's opening, whatever stands behind it (a floor the boxes stand on is another part,
not the loop's).  Blocks packed together that line up two corner pairs from one view by accident
enclose nothing but their own faces: no bar joint is read there, from a given view or from
``view="auto"``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from test_obtain_bar_joints import three_boxes

from meschers_igl import MescherError
from meschers_igl.mescher import Mescher
from meschers_igl.obtain import PERIOD_RTOL, model_to_mescher
from meschers_igl.obtain.openings import (
    opening_points,
    period_around_opening,
    periods,
    winding_numbers,
)

UP = np.array([0.0, 0.0, 1.0])


def _convert(V, F, view, up=UP):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, up=up)


def _square_ring(outer=2.0, inner=1.0, centre=(0.0, 0.0)):
    """A square frame as 8 triangles: the outer square minus the inner one (xy, F)."""
    c = np.asarray(centre)
    o = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * outer + c
    i = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * inner + c
    xy = np.vstack([o, i])
    F = []
    for k in range(4):
        a, b = k, (k + 1) % 4
        F += [[a, b, 4 + b], [a, 4 + b, 4 + a]]
    return xy, np.asarray(F)


def test_winding_numbers_of_a_square_loop():
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    tail, head = np.arange(4), (np.arange(4) + 1) % 4
    pts = np.array([[0.5, 0.5], [2.0, 0.5], [0.5, -3.0]])
    assert winding_numbers(xy, tail, head, pts).tolist() == [1, 0, 0]
    assert winding_numbers(xy, head, tail, pts).tolist() == [-1, 0, 0]  # reversed
    twice = np.r_[tail, tail], np.r_[head, head]
    assert winding_numbers(xy, *twice, pts).tolist() == [2, 0, 0]
    perm = np.array([2, 0, 3, 1])  # the edges in any order
    assert winding_numbers(xy, tail[perm], head[perm], pts).tolist() == [1, 0, 0]


def test_opening_points_of_frames_and_plates():
    xy, F = _square_ring()
    pts = opening_points(xy, F, 1e-9)
    assert pts.shape == (1, 2) and np.all(np.abs(pts) < 1.0)  # inside the inner square
    plate = np.array([[0, 1, 2], [0, 2, 3]])
    assert opening_points(xy, plate, 1e-9).shape == (0, 2)  # the outer square, filled
    xy2, F2 = _square_ring(centre=(10.0, 0.0))
    both = opening_points(np.vstack([xy, xy2]), np.vstack([F, F2 + 8]), 1e-9)
    assert both.shape == (2, 2)


@pytest.mark.parametrize("floor", [False, True])
def test_three_box_tribar_winds_around_its_opening(floor):
    """The joined loop goes once around the triangle's opening: a floor the boxes stand on
    shows through it but is a part of its own (a backdrop), so the opening stays one."""
    V, F, T = three_boxes()
    gap = float(np.linalg.norm(T))
    if floor:
        lo, hi = V.min(axis=0), V.max(axis=0)
        Vf, Ff = box_mesh([lo[0] - 20, lo[1] - 20, lo[2] - 1], [hi[0] + 20, hi[1] + 20, lo[2]])
        V, F = np.vstack([V, Vf]), np.vstack([F, Ff + V.shape[0]])
    m, order, report = _convert(V, F, T / gap)
    p = np.abs(np.asarray(m.periods()))
    p = p[p > PERIOD_RTOL * m.scale()]
    assert p.size >= 1 and np.allclose(p, gap, rtol=1e-6)
    assert any(j.kind == "bar joint" for j in report.junctions)
    # on the mescher alone (no 3D parts) the floor, glued where the boxes stand on it, fills
    # the opening; the conversion knows the parts and takes the floor away as a backdrop
    seen = period_around_opening(
        m.F, m.xy, m.corner_depths(), 1e-9 * m.scale(), PERIOD_RTOL * m.scale()
    )
    assert seen == (not floor)


def _climbing_ring(climb=1.0):
    """The square frame whose depth climbs ``climb`` per radian of turn (the cut along the
    negative x axis): one loop, period ``2 pi climb``."""
    xy, F = _square_ring()
    ang = np.mod(np.arctan2(xy[:, 1], xy[:, 0]), 2 * np.pi)[F]
    ang = np.where(ang - ang.min(axis=1, keepdims=True) > np.pi, ang - 2 * np.pi, ang)
    return xy, F, climb * ang


def test_a_climbing_frame_has_its_period_around_the_opening():
    xy, F, Z = _climbing_ring()
    assert period_around_opening(F, xy, np.zeros_like(Z), 1e-9, 1e-6) is None  # no period
    # the loop's period, as the mescher measures it
    ring = Mescher.from_corner_depths(F, xy, Z)
    assert np.abs(ring.periods()).max() == pytest.approx(2 * np.pi)
    _, gained, _ = periods(F, xy, Z)
    assert np.allclose(np.abs(gained), np.abs(ring.periods()), atol=1e-12)
    assert period_around_opening(F, xy, Z, 1e-9, 1e-6)
    # a plate behind, wider than the frame: without the 3D parts it fills the opening; as a
    # part of its own whose box holds the frame (a backdrop), it is taken away
    plate_xy = np.array([[-3.0, -3.0], [3.0, -3.0], [3.0, 3.0], [-3.0, 3.0]])
    plate = np.array([[0, 1, 2], [0, 2, 3]]) + 8
    both = np.vstack([F, plate]), np.vstack([xy, plate_xy]), np.vstack([Z, np.full((2, 3), -9.0)])
    assert period_around_opening(*both, 1e-9, 1e-6) is False
    part = np.r_[np.zeros(F.shape[0], dtype=np.int64), np.ones(2, dtype=np.int64)]
    assert period_around_opening(*both, 1e-9, 1e-6, part)
    # a smaller block in front of the opening is no backdrop: the opening is covered
    block_xy = plate_xy / 2.5
    front = np.vstack([F, plate]), np.vstack([xy, block_xy]), np.vstack([Z, np.full((2, 3), 9.0)])
    assert period_around_opening(*front, 1e-9, 1e-6, part) is False
    # the period alone is not enough: below the tolerance it is round-off
    assert period_around_opening(F, xy, Z, 1e-9, 10.0) is None


# box scenes that line up two corner pairs from the view auto chose (and from which the
# two-pair rule glued a bar joint): their loops enclose only their own faces
PACKED = [
    [(2, 4, 1.5, 3.5, 1, 2), (0, 2, 0, 1, 2, 5), (0, 3, 0, 1, 4, 5)],
    [(3, 4, 0, 3, 4, 6), (0.5, 2.5, 0, 3, 1.5, 4.5), (3, 6, 3, 6, 0, 2)],
    [(2, 3, 0, 2, 2, 5), (0.5, 3.5, 2, 4, 0.5, 3.5), (0, 2, 1.5, 3.5, 1.5, 3.5)],
]


@pytest.mark.parametrize("boxes", PACKED)
def test_packed_blocks_from_auto_are_possible_or_refused(boxes):
    V, F = merge_meshes([box_mesh(b[::2], b[1::2]) for b in boxes])
    try:
        m, order, report = _convert(V, F, "auto", None)
    except MescherError:
        return  # "no view found" is a clear answer
    assert not m.is_impossible(order=order), (report.view, report.junctions)
    assert not any(j.kind == "bar joint" for j in report.junctions if j.depth_gap > 1e-6)
