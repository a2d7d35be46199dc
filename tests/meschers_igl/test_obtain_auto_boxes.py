"""``view="auto"`` on a Penrose triangle of three separate boxes, from arrays and from a file.

The corners of separate boxes line up along lattice directions (a box's corner with another's,
seen nearly along an axis) more often than the bars' ends line up at the junction, so the
best-supported direction of the vote shows no junction; the search goes on to the caps that
coincide from the junction's view.  From a file, PyMeshLab's clean-up splits the edges where
abutting boxes touch instead of removing faces (which opened the solids: the search then saw
a cut model's boundary and no view).  Boxes that touch (a block lying on a plate) stay possible.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from test_obtain_bar_joints import three_boxes
from visible_models import write_obj

from meschers_igl import MescherError
from meschers_igl.obtain import model_to_mescher
from meschers_igl.shapes import boxes

ISO = np.ones(3) / np.sqrt(3.0)


def _auto(V_F_or_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if isinstance(V_F_or_path, tuple):
            return model_to_mescher(*V_F_or_path, view="auto")
        from meshlab_filters import model_to_mescher as from_file

        return from_file(V_F_or_path, view="auto")


def _check(m, order, report, view, gap):
    v = np.asarray(report.view, dtype=np.float64)
    assert abs(abs(v @ view) - 1.0) <= 1e-9, (v, view)
    p = np.abs(np.asarray(m.periods()))
    assert m.is_impossible(order=order).kind == "zeta"
    assert np.all(np.isclose(p[p > 1e-6 * gap], gap, rtol=1e-6)), (p, gap)


def test_the_vote_lines_up_box_corners_more_often_than_the_junction():
    """The premise: the best-supported direction is not the junction's view."""
    from meschers_igl.obtain.view import find_view

    V, F, _ = three_boxes(joint="abut")
    v, _ = find_view(V, F)
    assert abs(v @ ISO) < 0.99


@pytest.mark.parametrize("joint", ["overlap", "full", "abut"])
@pytest.mark.parametrize("turn", [0, 2])
def test_auto_view_of_three_boxes_is_the_junction_view(joint, turn):
    """Arrays: the view along the legs (isometric), the period the gap |T| = 10 sqrt 3."""
    V, F, T = three_boxes(joint=joint, turn=turn)
    _check(*_auto((V, F)), ISO, float(np.linalg.norm(T)))


@pytest.mark.parametrize("seed", range(3))
def test_auto_view_of_posed_boxes(seed):
    """A rigid pose and a scale: the view turns with the model, the period scales."""
    rng = np.random.default_rng(seed)
    V, F, T = three_boxes(joint=["overlap", "full", "abut"][seed])
    Q = Rotation.random(random_state=seed + 10).as_matrix()
    s = 10.0 ** rng.uniform(-1, 1)
    W = s * V @ Q.T + rng.normal(size=3) * 10 * s
    _check(*_auto((W, F)), Q @ ISO, s * float(np.linalg.norm(T)))


@pytest.mark.parametrize("joint", ["overlap", "abut"])
def test_auto_view_of_three_boxes_from_a_file_keeps_every_face(tmp_path, joint):
    """From an OBJ of three separate boxes (8 corners and 12 triangles each, as a modelling
    tool writes them): the same view and period, and the clean-up removes no face where the
    boxes touch (abutting: their corners coincide and weld)."""
    V, F, T = three_boxes(joint=joint)
    m, order, report = _auto(write_obj(tmp_path / "tribar.obj", V, F.tolist()))
    _check(m, order, report, ISO, float(np.linalg.norm(T)))
    assert report.cleanup.non_manifold_faces_removed == 0
    assert report.cleanup.faces_out == F.shape[0]


def test_blocks_lying_on_a_plate_stay_possible():
    """Two blocks on a plate touch it: pairs lining up between them are where they meet."""
    V, F = boxes(
        np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.5], [2.0, 1.0, 0.5]]),
        np.array([[4.0, 3.0, 0.5], [1.5, 2.0, 0.8], [3.0, 2.0, 1.2]]),
    )
    try:
        m, order, _ = _auto((V, F))
    except MescherError:
        return  # no view: nothing lines up as a junction
    assert not m.is_impossible(order=order)


def test_a_bar_joint_is_reported_as_such():
    """The junction of three boxes is a bar joint (a hidden end continued behind the near bar),
    reported with the gap |T|; no false edge is glued."""
    V, F, T = three_boxes()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, _, report = model_to_mescher(V, F, view=ISO, up=(0.0, 0.0, 1.0))
    kinds = [j.kind for j in report.junctions]
    assert kinds == ["bar joint"], kinds
    assert report.junctions[0].depth_gap == pytest.approx(np.linalg.norm(T), rel=1e-9)
    assert "bar joint at screen" in str(report)
