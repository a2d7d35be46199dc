"""Clean-up of what people make: faces repeated in place, points a tolerance apart.

A part duplicated where it was made keeps one copy; a sheet whose
two sides are two faces facing each other leaves nothing, and says so.

Welding makes a copy left in place share its original's vertices, so each of its faces repeats
one of the original's with the same orientation; blocks touching face to face instead meet in
faces of opposite orientation, both of which go.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from visible_models import ISO_UP, ISO_VIEW

from meschers_igl import MescherError
from meschers_igl.obtain import drop_contact_faces, drop_repeated_faces, model_to_mescher
from meschers_igl.obtain.clip import split_t_junctions
from meschers_igl.obtain.glue import interior_edges


def test_repeats_in_any_rotation_keep_one_and_opposites_are_left():
    F = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [3, 4, 5], [2, 1, 0]])
    kept, n = drop_repeated_faces(F)
    assert n == 3  # two rotations of [0, 1, 2] and one of [0, 2, 1]
    assert kept.tolist() == [[0, 1, 2], [0, 2, 1], [3, 4, 5]]
    # the opposite pair left is a contact: both go there, the lone face stays
    assert drop_contact_faces(kept)[0].tolist() == [[3, 4, 5]]
    assert drop_repeated_faces(np.zeros((0, 3), dtype=np.int64))[1] == 0


def _convert(V, F, view=ISO_VIEW, up=ISO_UP):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, up=up)


@pytest.mark.parametrize("copies", [2, 3])
def test_a_part_duplicated_in_place_converts_as_the_part(copies):
    """An L of two boxes, and the same with every vertex and face repeated ``copies`` times:
    the same visible surface (faces, screen positions, depths) and a repair that says so."""
    V, F = merge_meshes([box_mesh([0, 0, 0], [3, 1, 1]), box_mesh([0, 1, 0], [1, 3, 1])])
    one, _, _ = _convert(V, F)
    n = V.shape[0]
    Vd = np.vstack([V] * copies)
    Fd = np.vstack([F + k * n for k in range(copies)])
    many, order, report = _convert(Vd, Fd)
    assert many.F.shape == one.F.shape
    assert np.isclose(many.scale(), one.scale(), rtol=1e-12)
    np.testing.assert_allclose(
        np.sort(many.xy, axis=0), np.sort(one.xy, axis=0), atol=1e-12 * one.scale()
    )
    assert not many.is_impossible(order=order)
    assert any("repeated face" in r for r in report.repairs)


def test_a_sheet_of_two_facing_sides_is_refused_clearly():
    """A square as two triangles, and the same two triangles turned over on the same corners:
    every face lies on another facing it, nothing is left to see."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    with pytest.raises(MescherError, match=r"^F: expected faces left after clean-up"):
        _convert(V, np.vstack([F, F[:, ::-1]]), view=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0))
    # the same sheet duplicated in place (same side twice) is a square
    m, _, _ = _convert(V, np.vstack([F, F]), view=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0))
    assert m.F.shape[0] == 2


def _area(xy, F):
    e1, e2 = xy[F[:, 1]] - xy[F[:, 0]], xy[F[:, 2]] - xy[F[:, 0]]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def test_a_t_junction_is_split_at_the_vertex_on_the_edge():
    """Triangle (0,0), (4,0), (0,4) and a second face whose corner (2,0) lies on the first's
    bottom edge: the first becomes a fan of two through (2,0), the area unchanged."""
    xy = np.array([[0, 0], [4, 0], [0, 4], [2, 0], [2, -1], [3, -1]], float)
    F = np.array([[0, 1, 2], [3, 4, 5]])
    Ft, src = split_t_junctions(xy, F, np.array([7, 8]), 1e-9)
    assert Ft.shape[0] == 3 and sorted(src.tolist()) == [7, 7, 8]
    assert np.all(_area(xy, Ft) > 0)
    assert np.isclose(_area(xy, Ft[src == 7]).sum(), 8.0, rtol=1e-12)


def test_points_a_tolerance_apart_do_not_split_each_other_back_and_forth():
    """Five points of a clipped torus seen from its view (in units of the tolerance): three lie
    1.05 to 1.46 tol apart, each within tol of the edge the other two span.  Within tol of an
    edge's end, along it, a point is at that corner: nothing is split, the two faces keep their
    areas (splitting there made overlapping fans that never settled)."""
    xy = np.array(
        [[-158.933, 30.502], [43.108, -8.493], [41.773, -8.047], [31.578, -4.637], [42.474, -9.325]]
    )
    F = np.array([[0, 1, 2], [3, 2, 4]])
    Ft, _ = split_t_junctions(xy, F, np.zeros(2, dtype=np.int64), 1.0)
    np.testing.assert_allclose(np.abs(_area(xy, Ft)).sum(), np.abs(_area(xy, F)).sum(), rtol=1e-12)


def test_half_edges_pair_once_and_only_against_each_other():
    """An edge (0, 1) of k faces: the r-th half-edge one way pairs with the r-th the other way,
    each at most once; two faces on one side of it (overlapping) do not pair."""
    cases = {
        "two opposite": ([[0, 1, 2], [1, 0, 3]], 1),
        "two one way": ([[0, 1, 2], [0, 1, 3]], 0),
        "three": ([[0, 1, 2], [1, 0, 3], [0, 1, 4]], 1),
        "two and two": ([[0, 1, 2], [0, 1, 4], [1, 0, 3], [1, 0, 5]], 2),
    }
    for name, (F, pairs) in cases.items():
        F = np.asarray(F)
        h1, h2, he = interior_edges(F, 6)
        on = (np.sort(he[h1], axis=1) == [0, 1]).all(axis=1)
        assert on.sum() == pairs, name
        assert np.all(he[h1, 0] == he[h2, 1]) and np.all(he[h1, 1] == he[h2, 0]), name
        both = np.concatenate([h1, h2])
        assert np.unique(both).size == both.size, name  # each half-edge at most once


def test_a_scene_of_tori_an_icosahedron_and_a_cylinder_converts():
    """Primitives merged as a scene (two tori, an icosahedron, a tilted cylinder), seen from a
    view where clipping leaves three faces along one screen edge: a possible mescher (the
    gluing once made that edge non-manifold and the conversion was refused)."""
    import pyvista as pv

    parts = [
        pv.ParametricTorus(ringradius=1, crosssectionradius=0.3).translate((-2.618, 2.278, -1.003)),
        pv.ParametricTorus(ringradius=1, crosssectionradius=0.3).translate((2.841, 2.062, -1.63)),
        pv.Icosahedron(center=(-1.908, -2.586, 2.566)),
        pv.Cylinder(
            center=(-1.891, 2.045, -2.4),
            direction=(0.06723839, 0.92483598, -0.17351975),
            radius=0.4713807413583951,
            height=1.515828296730119,
            resolution=15,
        ),
    ]
    m = pv.merge([p.extract_surface(algorithm=None).triangulate() for p in parts])
    V = np.asarray(m.points, float)
    F = np.asarray(m.faces).reshape(-1, 4)[:, 1:]
    view = np.array([1.42079579, -1.35987168, -1.32479679])
    mm, order, _ = _convert(V, F, view / np.linalg.norm(view), (0.0, 0.0, 1.0))
    assert not mm.is_impossible(order=order)
