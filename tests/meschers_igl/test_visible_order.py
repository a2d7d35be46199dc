"""Impossible through the depth order m.is_impossible(order=...)."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import DepthOrder, Mescher, MescherError
from meschers_igl.impossibility import order_realisable


def _two_flat_triangles(dz=0.0):
    """Two separate flat triangles overlapping on screen, the second at depth dz."""
    xy = np.array([[0, 0], [2, 0], [0, 2], [0.5, 0.5], [2.5, 0.5], [0.5, 2.5]], float)
    F = np.array([[0, 1, 2], [3, 4, 5]])
    Z = np.array([[0.0, 0, 0], [dz, dz, dz]])
    return Mescher.from_corner_depths(F, xy, Z)


def test_separate_parts_take_any_offsets():
    m = _two_flat_triangles()
    # one arc either way is realisable by moving one part: margin up to the LP's bound
    for arcs in ([[0, 1]], [[1, 0]]):
        r = m.is_impossible(order=DepthOrder(2, arcs))
        assert not r and r.kind is None and r.margin > 0
    # both ways at once is a cycle no offsets satisfy
    r = m.is_impossible(order=[[0, 1], [1, 0]])
    assert r and r.kind == "order" and "offsets" in str(r)


def test_one_part_has_no_freedom():
    # a folded pair of faces of one part: face 1 folds back over face 0 and lies in front of it
    # where they overlap (bent depth = true depth: zeta integrates); the overlap's centroid c is
    # hand-computed from the fold: face 1 is 1/3 in front there
    V = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0.5, 0.5, 1.0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])  # face 1 is clockwise on screen (folded)
    m = Mescher.from_mesh(V, F)
    assert not m.is_impossible()
    r = m.is_impossible(order=[[0, 1]])  # 0 behind 1: what the geometry says
    assert not r and r.kind is None
    r = m.is_impossible(order=[[1, 0]])  # the opposite: no offset can fix one part
    assert r and r.kind == "order" and "same part" in str(r)
    ok, margin, _ = order_realisable(m, [[1, 0]])
    # overlap = the screen triangle (0.5,0.5),(2,0),(0,2) minus nothing: centroid (5/6, 5/6);
    # face 1's depth there: barycentric in ((2,0),(0.5,0.5),(0,2)) with z (0, 1, 0) -> 1/3
    assert not ok and np.isclose(margin, -1.0 / 3.0, rtol=1e-12)


def test_touching_faces_need_not_part():
    # an occlusion contour: faces that only share an edge may carry an arc at equal depth
    xy = np.array([[0, 0], [2, 0], [0, 2], [2, 2]], float)
    m = Mescher.from_mesh(np.c_[xy, np.zeros(4)], np.array([[0, 1, 2], [1, 3, 2]]))
    assert m.is_impossible(order=[[0, 1]]).kind is None


def test_parts_in_contact_may_touch_both_ways():
    """Two separate squares meeting on screen along x = 1 at equal depth (a block resting
    against another, flush): arcs both ways across that contour are realised by contact, with
    no offset between the parts; overlapping faces still need a strict order."""
    xy = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [1, 0], [2, 0], [1, 1], [2, 1]], float)
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 5, 7], [4, 7, 6]])
    m = Mescher.from_corner_depths(F, xy, np.zeros((4, 3)))
    ok, margin, why = order_realisable(m, [[0, 2], [3, 1]])  # across x = 1, either way
    assert ok, why
    assert not m.is_impossible(order=[[0, 2], [3, 1]])
    # the same two arcs between squares that overlap by a strip: no placement
    m2 = Mescher.from_corner_depths(
        F, xy - np.array([[0, 0]] * 4 + [[0.5, 0]] * 4), np.zeros((4, 3))
    )
    ok, margin, _ = order_realisable(m2, [[0, 3], [3, 0]])
    assert not ok and margin <= 0.0


def test_faces_of_one_part_at_equal_depth_say_nothing():
    """One flat part folded over itself in its own plane: where its faces overlap they are at
    equal depth, so an arc either way between them is round-off's to decide, not a
    contradiction; folded out of the plane (1/3 behind) it is one."""
    V = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0.5, 0.5, 0.0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])  # face 1 folds back over face 0
    m = Mescher.from_mesh(V, F)
    for arcs in ([[0, 1]], [[1, 0]]):
        assert order_realisable(m, arcs)[0]
    V[3, 2] = 1.0
    assert not order_realisable(Mescher.from_mesh(V, F), [[1, 0]])[0]


def test_gallery_reutersvard_is_impossible_through_its_order_and_penrose_through_zeta():
    from meschers_igl.gallery import get_model

    g = get_model("reutersvard_triangle")
    assert not g.mescher.is_impossible()  # zeta integrates (separate cubes)
    r = g.mescher.is_impossible(order=g.order)
    assert r.kind == "order" and r.margin < 0
    g = get_model("penrose_triangle", bar_length=4.0, bar_width=1.0, resolution=2)
    r = g.mescher.is_impossible(order=g.order)
    assert r.kind == "zeta" and "6.928203" in str(r)


def test_bad_order():
    m = _two_flat_triangles()
    with pytest.raises(MescherError, match="order"):
        m.is_impossible(order=[[0, 5]])
