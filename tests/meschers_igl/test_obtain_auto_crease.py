"""``view="auto"`` for two mitred tips meeting at a point (crease joints).

The cube frame with its corner at the origin cut away (``cut_corner_frame``: bars ``w`` wide,
the three bars there ending in double mitres pulled back by ``w``) lines up one pair of corners
per pair of tips: the tip corner ``b = (2w, 0, w)`` of the bar along x and ``c = (0, w, 0)`` of
the bar along y coincide on screen seen along ``c - b`` (``c`` in front, ``|c - b| = w sqrt 6``
apart), and so for every permutation of the axes (the frame's symmetries): six directions, the
permutations of ``(-2, 1, -1) / sqrt 6``.  No two pairs line up along one of them (on the
smaller frames one more pair, by accident), which the vote of vertex pairs needs; the view is
found from the crease joint the pair forms.  Box scenes meet square: they have no mitre, so no
crease joint and nothing changes for them.
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from scipy.spatial.transform import Rotation
from test_obtain_impossible_cube import cut_corner_frame
from test_obtain_real import _real, needs_real

from meschers_igl import MescherError
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.bar_joints import crease_pairs
from meschers_igl.obtain.clip import REL_TOL

pytest.importorskip("pymeshlab")  # the frames' mitred tips are united by MeshLab

SIZES = [(7, 1.0), (5, 1.0), (9, 2.0), (7, 0.5)]


def _tip_directions() -> np.ndarray:
    """(6, 3) the unit directions ``c - b`` over the permutations of the axes."""
    out = []
    for perm in itertools.permutations(range(3)):
        b, c = np.array([2.0, 0.0, 1.0])[list(perm)], np.array([0.0, 1.0, 0.0])[list(perm)]
        out.append(c - b)
    return np.array(out) / np.sqrt(6.0)


def _tol(V) -> float:
    """The converter's absolute tolerance for ``V``."""
    return REL_TOL * float(np.linalg.norm(np.ptp(V, axis=0)))


def _convert(V, F, view="auto", **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, **kw)


def _periods(m):
    p = np.abs(np.asarray(m.periods(), float))
    return p[p > 1e-6]


def _which_tip(view, dirs) -> int:
    """The index of the direction of ``dirs`` that ``view`` is (to round-off), else -1."""
    k = int(np.argmax(dirs @ view))
    return k if dirs[k] @ view >= 1.0 - 1e-12 else -1


@pytest.mark.parametrize(("n", "w"), SIZES)
def test_crease_pairs_nearest_are_the_tips(n, w):
    """The crease joints with the smallest gap are the tips' pairs: along exactly the six
    permutations of ``(-2, 1, -1) / sqrt 6``, each ``w sqrt 6`` apart, the near corner minus
    the far one ``gap * view``."""
    V, F = cut_corner_frame(n, w)
    tol = _tol(V)
    near, far, view, gap = crease_pairs(V, F, tol)
    assert gap.min() == pytest.approx(w * np.sqrt(6.0), rel=1e-12)
    assert np.allclose(V[near] - V[far], gap[:, None] * view, atol=1e-12 * n * w)
    tips = np.abs(gap - w * np.sqrt(6.0)) <= 10 * tol
    dirs = _tip_directions()
    got = {_which_tip(v, dirs) for v in view[tips]}
    assert got == set(range(6))


@pytest.mark.parametrize("seed", [0, 1])
def test_crease_pairs_move_with_the_model(seed):
    """A rigid motion and a scale ``s`` of the model turn the pairs' directions with it and
    scale their gaps by ``s`` (the test is local to the model, the view plays no part)."""
    rng = np.random.default_rng(seed)
    Q = Rotation.random(random_state=seed).as_matrix()
    s, t = float(rng.uniform(0.3, 3.0)), rng.normal(size=3) * 10
    V, F = cut_corner_frame(7, 1.0)
    _, _, view0, gap0 = crease_pairs(V, F, _tol(V))
    W = s * V @ Q.T + t
    _, _, view1, gap1 = crease_pairs(W, F, _tol(W))
    key0 = np.round(np.c_[view0 @ Q.T, gap0 * s] * 1e6)
    key1 = np.round(np.c_[view1, gap1] * 1e6)
    assert {tuple(r) for r in key0.tolist()} == {tuple(r) for r in key1.tolist()}


def test_square_faces_make_no_crease_pairs():
    """Faces meeting square or continuing each other are no mitre: the whole frame and scenes
    of axis-aligned boxes (turned as a whole) have no crease joint from any direction."""
    V, F = cut_corner_frame(7, 1.0, cut=False)
    assert crease_pairs(V, F, _tol(V))[0].size == 0
    rng = np.random.default_rng(7)
    for k in range(20):  # random scenes of boxes
        boxes = []
        for _ in range(int(rng.integers(2, 7))):
            lo = rng.integers(0, 5, size=3) * 0.5
            boxes.append(box_mesh(lo, lo + rng.integers(1, 4, size=3)))
        V, F = merge_meshes(boxes)
        V = V @ Rotation.random(random_state=k).as_matrix().T
        assert crease_pairs(V, F, _tol(V))[0].size == 0


@pytest.mark.parametrize(("n", "w"), SIZES)
def test_auto_finds_the_tips_and_their_gap(n, w):
    """``view="auto"`` sees the frame along one of the tips' directions, from above the
    horizon: the mescher is impossible, the tips are joined there (a bar joint of their gap),
    and every period is the gap ``w sqrt 6`` (to the conversion's tolerance)."""
    V, F = cut_corner_frame(n, w)
    m, order, report = _convert(V, F)
    assert _which_tip(report.view, _tip_directions()) >= 0, report.view
    assert report.view[2] >= 0
    gap = w * np.sqrt(6.0)
    assert any(
        j.kind == "bar joint" and j.depth_gap == pytest.approx(gap, rel=1e-9)
        for j in report.junctions
    )
    assert m.is_impossible(order=order)
    p = _periods(m)
    assert p.size and np.all(np.abs(p - gap) <= 0.1 * _tol(V)), p


@pytest.mark.parametrize("k", range(6))
def test_each_tips_view_glues_its_gap_exactly(k):
    """From each of the six tips' directions (given), the far tip's hidden strip ends on the
    far face's own corner, exactly the gap behind the near crease: every period is
    ``w sqrt 6`` to a tenth of the tolerance (the mirror views as well as the turned ones)."""
    V, F = cut_corner_frame(7, 1.0)
    d = _tip_directions()[k]
    m, order, report = _convert(V, F, d, up=(0.0, 0.0, 1.0))
    assert m.is_impossible(order=order)
    p = _periods(m)
    assert p.size and np.all(np.abs(p - np.sqrt(6.0)) <= 0.1 * _tol(V)), p


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_auto_posed_frames(seed):
    """Turned, scaled and moved, the frame is seen along a turned tips' direction, its periods
    the scaled gap."""
    rng = np.random.default_rng(seed)
    Q = Rotation.random(random_state=seed).as_matrix()
    s, t = float(rng.uniform(0.3, 3.0)), rng.normal(size=3) * 10
    V, F = cut_corner_frame(7, 1.0)
    W = s * V @ Q.T + t
    m, order, report = _convert(W, F)
    assert _which_tip(report.view, _tip_directions() @ Q.T) >= 0, report.view
    assert m.is_impossible(order=order)
    p = _periods(m)
    assert p.size and np.all(np.abs(p - s * np.sqrt(6.0)) <= 0.1 * _tol(W)), p


@pytest.mark.parametrize("k", [0, 3, 5])
def test_auto_from_a_start_takes_the_tips_near_it(k):
    """With ``view_start`` 4 degrees off one tips' direction (below the horizon or above),
    that direction is the view: the crease joints are searched within 10 degrees of it."""
    V, F = cut_corner_frame(7, 1.0)
    d = _tip_directions()[k]
    axis = np.cross(d, (0.3, 0.5, 0.8))
    start = Rotation.from_rotvec(np.radians(4.0) * axis / np.linalg.norm(axis)).apply(d)
    m, order, report = _convert(V, F, view_start=start)
    assert report.view @ d == pytest.approx(1.0, abs=1e-12)
    assert m.is_impossible(order=order)
    assert np.all(np.abs(_periods(m) - np.sqrt(6.0)) <= 0.1 * _tol(V))


#: Ordinary scenes of axis-aligned boxes (as a fuzz of block scenes drew them).
BOX_SCENES = [
    [(0, 2, 2, 3, 3, 6), (4, 7, 1, 4, 3, 5), (3, 5, 2, 3, 1, 4), (0, 1, 1.5, 4.5, 0.5, 2.5)],
    [(0, 1, 4, 6, 4, 7), (2, 5, 0, 1, 2, 3), (0, 1, 0, 1, 0, 1), (3, 6, 0, 3, 3, 5)],
    [(2, 3, 1.5, 2.5, 0, 2), (4, 7, 4, 6, 2, 3), (0, 1, 1, 2, 0, 2), (1, 3, 4, 7, 0, 2)],
]


@pytest.mark.parametrize("boxes", BOX_SCENES)
def test_auto_box_scenes_stay_possible_or_refused(boxes):
    """Boxes meeting square, from ``view="auto"``: possible, or refused (nothing lines up a
    junction); never joined at a crease."""
    V, F = merge_meshes([box_mesh(b[0::2], b[1::2]) for b in boxes])
    try:
        m, order, report = _convert(V, F)
    except MescherError:
        return
    assert not m.is_impossible(order=order), report.junctions


@needs_real
def test_real_impossible_cube_auto_is_the_tips_view():
    """``Impossible_Cube.3ds`` from ``view="auto"``: the direction of its one coincident pair
    of tips (0.02 degrees from the given view; a mirror-symmetric model, the mirror view
    ranked second by ``v_y``), its period the listed gap."""
    V, F, d = _real("Impossible_Cube.3ds")
    m, order, report = _convert(V, F)
    given = np.asarray(d["view"], float) / np.linalg.norm(d["view"])
    assert np.degrees(np.arccos(min(1.0, report.view @ given))) <= 0.05
    assert m.is_impossible(order=order)
    gaps = np.asarray(d["coincident_depth_gaps"], float)
    p = _periods(m)
    assert p.size and np.all(np.min(np.abs(p[:, None] - gaps[None]), axis=1) <= 1e-3 * gaps.max())
    assert any(j.kind == "bar joint" for j in report.junctions)
