"""Bridges of hidden gaps never run along a visible edge.

A scene of boxes on a floor before a wall, seen along a view with a zero component, has edges
that coincide on screen exactly (the box's foot on the floor, its top on the wall's foot).  A
bridge strip across such a box whose side is the box's visible foot edge would give that edge a
third face: the conversion then failed with "expected a manifold mesh" for some scalings of the
same view and not others (round-off decided).  The view's length must not matter.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from meschers_igl.errors import MescherWarning
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.amodal import _on_visible_edges
from meschers_igl.shapes import boxes

FLOOR_BOX_WALL = (
    np.array([[-1.0, -1.0, -0.2], [0.0, 0.0, 0.0], [-0.5, 2.0, 0.0]]),
    np.array([[3.0, 4.0, 0.0], [1.0, 1.0, 1.0], [2.5, 2.5, 2.0]]),
)


def _convert(V, F, view):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        return model_to_mescher(V, F, view=np.asarray(view, float), up=(0.0, 0.0, 1.0))


@pytest.mark.parametrize("view", [(0.0, -1.0, 0.5), (0.0, -2.0, 1.0), (0.5, -1.0, 0.5)])
def test_a_view_and_its_multiples_give_the_same_mescher(view):
    V, F = boxes(*FLOOR_BOX_WALL)
    got = [_convert(V, F, s * np.asarray(view)) for s in (1.0, 1.0 / np.linalg.norm(view), 3.0)]
    m0, _, r0 = got[0]
    for m, _, r in got[1:]:
        assert m.n_faces == m0.n_faces and m.n_vertices == m0.n_vertices
        np.testing.assert_allclose(np.sort(np.abs(m.periods())), np.sort(np.abs(m0.periods())))
        assert sorted(j.kind for j in r.junctions) == sorted(j.kind for j in r0.junctions)


def test_every_view_of_the_scene_converts():
    """Views with zero and equal components (exact coincidences on screen): a mescher each."""
    V, F = boxes(*FLOOR_BOX_WALL)
    for a in (-1.0, 0.0, 0.5):
        for b in (-2.0, -1.0, -0.5):
            for c in (0.5, 1.0):
                m, order, _ = _convert(V, F, (a, b, c))
                assert m.n_faces > 0 and order.n_faces == m.n_faces


def test_a_strip_side_on_a_visible_edge_is_refused():
    """Chains A = (0, 1) and B = (2, 3) bound the strip 1-0-3-2 (a unit square); its side
    0-3, or its diagonal 1-3, is an edge of one visible map and of neither in the other."""
    poly = [1, 0, 3, 2]
    tri = [(0, 1, 2), (0, 2, 3)]  # 1-0-3 and 1-3-2: the diagonal 1-3 and the sides 0-3, 2-1
    free = np.array([[0, 1, 5], [3, 2, 6], [7, 8, 9]])  # the chains' own edges and others
    assert not _on_visible_edges(poly, tri, [0, 1], [2, 3], free)
    assert _on_visible_edges(poly, tri, [0, 1], [2, 3], np.array([[0, 3, 5], [7, 8, 9]]))
    assert _on_visible_edges(poly, tri, [0, 1], [2, 3], np.array([[3, 1, 9]]))
