"""Accidental alignments of ordinary scenes are no junctions; tribar junctions still are.

Seen along views with zero or equal components, an ordinary scene lines up edges at different
depths on screen: a box's top edge on the foot of the wall behind it, a table's front edge on
the far edge of the floor under it, a block's top edge on a grid line of a lower top, two
legs' sides.  The general false-edge rule glued those as junctions (the scene came out
impossible, period = the depth gap).  A far edge that is its object's outline and is seen
elsewhere against its backdrop, or a crease whose hidden face the near face cannot continue
and whose ends do not pair up with the near edge's on screen, or a face seen edge-on joining
the two surfaces, is no junction.  Model edges that pair up corner to corner on screen (two
vertex pairs coinciding, as at a tribar's junction) stay glued.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from ordinary_scenes import SCENES, axis_views
from visible_models import ISO_UP, ISO_VIEW, convert_quietly, triangulate, u_tribar

from meschers_igl.errors import MescherWarning
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.alignment import far_edge_kinds, outline_seen
from meschers_igl.operators import view_frame

#: (scene, view, an edge of one block, an edge at another depth on the same screen line)
BOX_TOP, WALL_FOOT = ((0, 1, 1), (1, 1, 1)), ((-0.5, 2, 0), (2.5, 2, 0))
TABLE_FRONT, FLOOR_BACK = ((0, 0, 1), (2, 0, 1)), ((-1, 2, 0), (3, 2, 0))
COLUMN_TOP = ((1, 0, 2), (1, 2, 2))
ALIGNED = [
    ("floor_box_wall", (0.0, -1.0, 1.0), BOX_TOP, WALL_FOOT),
    ("floor_box_wall", (-1.0, -1.0, 1.0), BOX_TOP, WALL_FOOT),
    ("floor_box_wall", (0.5, -0.5, 0.5), BOX_TOP, WALL_FOOT),
    ("table", (-1.0, -2.0, 1.0), TABLE_FRONT, FLOOR_BACK),
    ("table", (0.0, -1.0, 0.5), TABLE_FRONT, FLOOR_BACK),
    ("table", (-1.0, -0.5, 0.5), ((0.2, 0, 0), (0.2, 0, 1)), ((1.8, 0.8, 0), (1.8, 0.8, 1))),
    ("l_block", (-1.0, -1.0, 1.0), COLUMN_TOP, ((2, 0, 1), (2, 2, 1))),
    ("l_block", (0.0, -1.0, 2.0), COLUMN_TOP, ((1, 0, 1), (1, 2, 1))),
]


def _convert(V, F, view):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        return model_to_mescher(V, F, view=np.asarray(view, float), up=(0.0, 0.0, 1.0))


@pytest.mark.parametrize("name, view, a, b", ALIGNED)
def test_ordinary_scenes_seen_along_an_alignment_are_possible(name, view, a, b):
    """Each view lines up two edges at different depths exactly (checked here on its own: the
    four ends on one screen line, the edges apart in depth); the scene comes out possible."""
    R = view_frame(np.asarray(view, float), np.array([0.0, 0.0, 1.0]))
    A, B = np.asarray(a, float) @ R.T, np.asarray(b, float) @ R.T
    u = A[1, :2] - A[0, :2]
    w = np.r_[A[:, :2], B[:, :2]] - A[0, :2]
    assert np.allclose(u[0] * w[:, 1] - u[1] * w[:, 0], 0.0, atol=1e-12)  # one screen line
    # at the same screen point the two edges lie at depths apart by more than half a unit
    s = ((A[0, :2] - B[0, :2]) @ (B[1, :2] - B[0, :2])) / np.sum((B[1, :2] - B[0, :2]) ** 2)
    assert abs(A[0, 2] - (B[0, 2] + s * (B[1, 2] - B[0, 2]))) > 0.5
    V, F = SCENES[name]()
    m, order, report = _convert(V, F, view)
    assert not m.is_impossible(order=order), (name, view, np.abs(m.periods()).max())
    assert not any(j.kind in ("false edge", "bar joint") for j in report.junctions)


def test_a_box_before_a_wall_is_possible_from_every_axis_view():
    """90 views with zero and equal components (14 impossible on the old rule)."""
    V, F = SCENES["floor_box_wall"]()
    for view in axis_views():
        m, order, _ = _convert(V, F, view)
        assert not m.is_impossible(order=order), view


@pytest.mark.parametrize("name", ["two_boxes", "stairs", "stair_blocks"])
def test_other_ordinary_scenes_stay_possible_along_their_alignments(name):
    V, F = SCENES[name]()
    for view in axis_views()[::3]:
        m, order, _ = _convert(V, F, view)
        assert not m.is_impossible(order=order), view


@pytest.mark.parametrize("name", sorted(SCENES))
def test_ordinary_scenes_from_auto_are_possible_or_refused(name):
    """``view="auto"`` on an ordinary scene: one MescherError (no view) or a possible mescher,
    never a level view lining up a table's legs, from which 80% of the scene is seen edge-on
    (:data:`~meschers_igl.obtain.view.MAX_EDGE_ON_WHOLE`)."""
    from meschers_igl.errors import MescherError
    from meschers_igl.obtain.view import MAX_EDGE_ON_WHOLE, _FaceAreas

    V, F = SCENES[name]()[:2]
    V, F = np.asarray(V, float), np.asarray(F)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MescherWarning)
            m, order, report = model_to_mescher(V, F, view="auto")
    except MescherError as err:
        assert "view" in str(err)
        return
    assert not m.is_impossible(order=order)
    assert _FaceAreas.of(V, F).edge_on(report.view[None])[0] <= MAX_EDGE_ON_WHOLE


def test_the_capped_tribar_keeps_its_junction():
    V, P, gap = u_tribar()
    _, _, report, p = convert_quietly(V, triangulate(P), ISO_VIEW, ISO_UP)
    assert p.size and np.allclose(p, gap, rtol=1e-6)
    assert any(j.kind == "false edge" for j in report.junctions)


REAL = Path(os.environ.get("MESCHERS_REAL_MODELS", "/work/shared/real_models"))


@pytest.mark.skipif(not (REAL / "views.json").is_file(), reason="no real models")
@pytest.mark.parametrize(
    "name, period", [("PenroseTriangle.obj", 17.321), ("PenroseTriangle2.obj", 69.282)]
)
def test_real_tribars_keep_their_junction_from_their_view(name, period):
    """PenroseTriangle2's far edge runs on past the junction as a crease of its bar (a stub
    of 5% of its length), the near face continuing that crease's hidden face: a junction.
    PenroseTriangle's is the z-bar's end hidden exactly behind the x-bar's end (its corners
    paired, 10 sqrt 3 apart), not the grid line of a face that the x-bar's outline runs along
    (8 sqrt 3: the triangulation's, see ``test_obtain_triangulation``)."""
    import json

    from meshlab_filters.load import read_meshset

    d = json.loads((REAL / "views.json").read_text())[name]
    ms = read_meshset(REAL / name)
    V, F = ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix()
    _, _, _, p = convert_quietly(V, F, d["view"], d["up"])
    assert p.size and np.allclose(p, period, rtol=1e-4)


def _square(z_below):
    """A unit square (two triangles, depth 0) above the edge (0,0)-(1,0); below it, a strip
    at depth ``z_below`` (None: nothing, the background)."""
    xy = [[0, 0], [1, 0], [1, 1], [0, 1]]
    Fa = [[0, 1, 2], [0, 2, 3]]
    Z = [[0, 0, 0], [0, 0, 0]]
    if z_below is not None:
        xy += [[0, -1], [1, -1]]
        Fa += [[4, 5, 1], [4, 1, 0]]
        Z += [[z_below] * 3, [z_below] * 3]
    return np.array(xy, float), np.array(Fa), np.array(Z, float)


@pytest.mark.parametrize("z_below, seen", [(None, True), (-1.0, True), (0.0, True), (1.0, False)])
def test_an_outline_is_seen_against_its_backdrop_only(z_below, seen):
    """The edge (0,0,0)-(1,0,0) with its face above: seen as an outline when below it lies
    the background, a farther surface or one touching it; not when something nearer lies
    there (a near object in front of it); nor when the face beside it is not at its depth."""
    xy, Fa, Z = _square(z_below)
    A, B = np.array([0.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])
    assert outline_seen(xy, Fa, Z, A, B, 1.0, 1e-6) is seen
    assert outline_seen(xy, Fa, Z, A + [0, 0, 0.5], B + [0, 0, 0.5], 1.0, 1e-6) is False


def _block_on_a_crease(slide):
    """A box [0, 2]^3 and a second box moved 1.5 along (1, 1, 1) and ``slide`` along z: from
    (1, 1, 1) its silhouette edge x = y = 3.5 lies on the first box's crease x = y = 2, whose
    other face (+y) the second box hides.  At ``slide = 0`` both ends of the two edges pair up
    on screen; slid along the edge, the crease runs on past one end of the near edge."""
    near = np.array([1.5, 3.5, 1.5 + slide])
    return merge_meshes([box_mesh([0, 0, 0], [2, 2, 2]), box_mesh(near, near + 2.0)])


@pytest.mark.parametrize("slide, glued", [(0.0, True), (0.5, False), (-0.5, False), (1.0, False)])
def test_a_crease_is_a_junction_only_where_the_corners_pair_up(slide, glued):
    """The near face (+x) is not parallel to the crease's hidden face (+y): it cannot take its
    place.  With both vertex pairs coinciding the picture shows one edge with matching corners
    and the false edge (depth gap 1.5 sqrt 3) stays; slid along the edge (the same screen line,
    the crease running on below or above the near box: T-junctions), the near box lies in
    front of the crease and nothing is glued.  Two blocks make no loop: possible either way."""
    V, F = _block_on_a_crease(slide)
    R = view_frame(ISO_VIEW, np.array([0.0, 0.0, 1.0]))
    a, b = np.array([[3.5, 3.5, 1.5 + slide], [2.0, 2.0, 0.0]]) @ R.T
    assert np.allclose(a[:2], b[:2] + [0.0, slide * np.sqrt(2.0 / 3.0)], atol=1e-12)
    m, order, report = _convert(V, F, ISO_VIEW)
    fe = [j for j in report.junctions if j.kind == "false edge"]
    assert bool(fe) is glued
    if glued:
        assert len(fe) == 1 and np.isclose(fe[0].depth_gap, 1.5 * np.sqrt(3.0), rtol=1e-12)
    assert not m.is_impossible(order=order)


@pytest.mark.parametrize("tol", [1e-6, 1e-3])
@pytest.mark.parametrize("lift, flat", [(0.2, True), (5.0, False)])
def test_a_far_face_goes_on_flat_to_the_model_tolerance(tol, lift, flat):
    """The far face (0,0,0), (1,0,0), (0,1,0) and its neighbour across the edge (1,0,0)-(0,1,0)
    whose far corner is lifted ``lift`` tolerances: its normal turns by ``lift tol sqrt 2``.
    Within ``tol / L`` (L = sqrt 2, the far face's longest edge) the surface goes on flat (an
    outline of nothing, no crease), whatever the model's scale; beyond it the edge is a crease
    whose hidden face the near face (normal +x) cannot continue."""
    h = lift * tol
    C = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, h], [0, 0, 1]], float)
    F = np.array([[0, 1, 2], [1, 3, 2], [0, 2, 4]])
    one = np.array([0])
    outline, crease = far_edge_kinds(C, F, one + 2, one, one + 1, np.zeros(1, bool), tol)
    assert outline[0] is np.bool_(flat) and crease[0] is np.bool_(not flat)
