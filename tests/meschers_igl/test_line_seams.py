"""Line drawings where the depth order flips between two neighbouring faces of one sheet."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import DepthOrder, Mescher
from meschers_igl.line_folds import order_seams
from meschers_igl.line_pixels import line_agreement
from meschers_igl.lines import KINDS, line_drawing


def _sheet_and_plate(arcs):
    """A flat sheet of two faces, f = 0 left and g = 1 right of the edge x = 0, 0 <= y <= 2,
    and a plate h = 2, the triangle (-0.5, 0.5), (0.5, 0.5), (-0.5, 1.5), over the edge for
    0.5 < y < 1; faces ordered by ``arcs`` alone."""
    V = np.array(
        [
            [0, 0, 0],
            [0, 2, 0],
            [-1, 1, 0],
            [1, 1, 0],
            [-0.5, 0.5, 1],
            [0.5, 0.5, 1],
            [-0.5, 1.5, 1],
        ],
        dtype=float,
    )
    F = np.array([[0, 1, 2], [0, 3, 1], [4, 5, 6]])
    m = Mescher.from_mesh(V, F)
    return m, DepthOrder.from_arrays(3, arcs)


def _on_seam(ld, visible=True):
    """Pieces of the drawing's segments on the line x = 0 strictly inside the sheet."""
    S = ld.segments(visible=visible)
    on = np.all(np.abs(S[:, :, 0]) <= 1e-12, axis=1)
    on &= np.all((S[:, :, 1] > 1e-12) & (S[:, :, 1] < 2 - 1e-12), axis=1)
    return np.sort(S[on, :, 1], axis=1)


@pytest.mark.parametrize("flip", [False, True])
def test_a_seam_of_the_order_is_drawn_where_a_face_between_lies_under_it(flip):
    # g behind h behind f: the painter shows f left of the edge and h right of it where h lies
    # under the edge (0.5 < y < 1), and f beside g (one sheet, no line) elsewhere; flipped,
    # f behind h behind g, h shows left of the edge and g right of it
    arcs = [[0, 2], [2, 1]] if flip else [[1, 2], [2, 0]]
    m, order = _sheet_and_plate(arcs)
    ld = line_drawing(m, order, hidden=True)
    assert _on_seam(ld).tolist() == [[0.5, 1.0]]  # exact T-junctions at h's edges
    assert _on_seam(ld, visible=False).size == 0  # a seam has no hidden part
    # the visible part of h (right of the edge: the triangle (0, 0.5), (0.5, 0.5), (0, 1);
    # flipped, the quadrilateral (-0.5, 0.5), (0, 0.5), (0, 1), (-0.5, 1.5) left of it) is
    # bounded by one closed occlusion line, the seam one of its sides; the rest of h is hidden
    seen, behind = 1.0 + np.sqrt(0.5), 0.5 + 1.0 + np.sqrt(0.5)
    if flip:
        seen, behind = behind + 0.5, seen - 0.5
    occ = (ld.kind == KINDS.index("occlusion")) & ld.visible
    assert occ.sum() == 1 and ld.closed[occ].all()
    assert ld.length("occlusion") == pytest.approx(seen, abs=1e-12)
    assert ld.length("outline") == pytest.approx(4 * np.sqrt(2.0), abs=1e-12)
    assert ld.length(visible=False) == pytest.approx(behind, abs=1e-12)
    assert line_agreement(line_drawing(m, order), m, order, size=128) == (1.0, 1.0)


@pytest.mark.parametrize("arcs", [[[1, 2], [0, 2]], [[2, 1], [2, 0]]])
def test_no_seam_without_a_face_drawn_between(arcs):
    # h over the whole sheet (the edge is hidden under it) or behind it (one sheet, no line):
    # nothing is drawn on the edge inside the sheet
    m, order = _sheet_and_plate(arcs)
    ld = line_drawing(m, order)
    assert _on_seam(ld).size == 0
    assert line_agreement(ld, m, order, size=128) == (1.0, 1.0)


def test_order_seams_rule():
    rank = np.array([0, 5, 2, 3, 9, 1])
    arcs = np.array([[0, 2], [0, 4], [3, 1], [5, 3]])  # (behind, in front)
    f = np.array([0, 1, 0, 3, 5])
    g = np.array([1, 3, 4, 0, 1])
    # edge (0, 1): face 2 over 0 (rank 2 in (0, 5)); (1, 3): nothing over 3; (0, 4): face 2
    # over 0 and before 4; (3, 0): face 2 over 0 but after 3 (rank 2 < 3: between 0 and 3);
    # (5, 1): face 3 over 5, rank 3 in (1, 5)
    assert order_seams(f, g, rank, arcs).tolist() == [True, False, True, True, True]
    # unsorted arcs give the same answer; no arcs, no seams
    assert order_seams(f, g, rank, arcs[::-1]).tolist() == [True, False, True, True, True]
    assert not order_seams(f, g, rank, np.zeros((0, 2), dtype=np.int64)).any()
    # strictly between: a face over the earlier one drawn after the later one makes no seam
    assert order_seams(np.array([0]), np.array([2]), rank, np.array([[0, 4]])).tolist() == [False]
