"""Models far from the origin convert as at the origin, in their own frame.

A model exported from a scene sits where it stood in the scene, often hundreds of its sizes away
from the origin.  The conversion sees it from its bounding box's centre (positions far from the
origin lose digits in every plane and cross product) and moves the mescher's screen positions
and the junctions' back: the result is the model's, translated by the translation's projection.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from test_obtain_bar_joints import three_boxes
from visible_models import ISO_UP, ISO_VIEW, hidden_gap_cube, triangulate, u_tribar

from meschers_igl.obtain import model_to_mescher
from meschers_igl.operators import view_frame

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"
needs_real = pytest.mark.skipif(not REAL.is_dir(), reason="the development set is absent")
AWAY = np.array([1.0, -2.0, 3.0])


def _quiet(V, F, view, up):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, up=up)


def _periods(m):
    p = np.abs(np.asarray(m.periods(), dtype=float))
    return np.sort(p[p > 1e-6 * m.scale()])


def _models():
    V, P, _ = u_tribar()
    yield "u_tribar", np.asarray(V, float), np.asarray(triangulate(P))
    V, P, _ = hidden_gap_cube()
    yield "hidden_gap_cube", np.asarray(V, float), np.asarray(triangulate(P))
    V, F, _ = three_boxes()
    yield "three_boxes", V, F


@pytest.mark.parametrize(
    "name, V, F", list(_models()), ids=lambda x: x if isinstance(x, str) else ""
)
def test_a_model_moved_away_is_the_same_mescher_moved(name, V, F):
    """Moved ``1e4`` sizes away: the same faces, depths and periods; the screen positions and
    the junctions' positions moved by the translation's projection ``(R t)[:2]``."""
    m0, _, r0 = _quiet(V, F, ISO_VIEW, ISO_UP)
    t = AWAY * 1e4 * np.ptp(V, axis=0).max()
    m1, order, r1 = _quiet(V + t, F, ISO_VIEW, ISO_UP)
    shift = (view_frame(ISO_VIEW, ISO_UP) @ t)[:2]
    assert np.array_equal(m1.F, m0.F)
    np.testing.assert_allclose(m1.xy, m0.xy + shift, rtol=0, atol=1e-9 * np.abs(shift).max())
    np.testing.assert_allclose(_periods(m1), _periods(m0), rtol=1e-9)
    assert _periods(m0).size and m1.is_impossible(order=order)
    assert [j.kind for j in r1.junctions] == [j.kind for j in r0.junctions]
    for a, b in zip(r0.junctions, r1.junctions):
        np.testing.assert_allclose(b.position, a.position + shift, atol=1e-9 * np.abs(shift).max())
        assert b.depth_gap == pytest.approx(a.depth_gap, rel=1e-9)


def _real(name):
    from meshlab_filters.load import read_meshset

    ms = read_meshset(REAL / name)  # the mesh lives as long as its set
    mesh = ms.current_mesh()
    return np.asarray(mesh.vertex_matrix(), float), np.asarray(mesh.face_matrix(), np.int64)


@needs_real
@pytest.mark.parametrize("k", [1e2, 1e4])
@pytest.mark.parametrize(
    "name",
    ["PenroseTriangle.obj", "EscherCube.obj", "PenroseStairs2.obj", "Impossible_Cube.3ds"],
)
def test_real_models_far_away_keep_their_verdict_and_periods(name, k):
    """Each file moved ``k`` sizes away, from its view: impossible as at the origin, with the
    same smallest and largest period, to ten conversion tolerances."""
    views = json.loads((REAL / "views.json").read_text())
    view, up = np.asarray(views[name]["view"]), np.asarray(views[name]["up"])
    V, F = _real(name)
    m0, o0, _ = _quiet(V, F, view, up)
    m1, o1, _ = _quiet(V + AWAY * k * np.ptp(V, axis=0).max(), F, view, up)
    assert bool(m1.is_impossible(order=o1)) and bool(m0.is_impossible(order=o0))
    p0, p1 = _periods(m0), _periods(m1)  # how many loops carry them is the gluing's choice
    assert (p0.size == 0) == (p1.size == 0)  # the Escher cube: impossible by its order
    if p0.size:
        # the junctions are told to the conversion's tolerance (1e-5 of the diagonal)
        atol = 1e-4 * np.linalg.norm(np.ptp(V, axis=0))
        np.testing.assert_allclose([p1.min(), p1.max()], [p0.min(), p0.max()], atol=atol)
