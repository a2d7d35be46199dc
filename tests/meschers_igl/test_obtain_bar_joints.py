"""The three-box Penrose triangle: three separate boxes (as modelling tools make them), one
bar's end hidden exactly behind another bar's end.  A person reads an L-joint there; the loop
of bars fails to close by the depth gap ``t`` between the coincident ends (the translation
along the view that takes the hidden end onto the near one), which is the period.  Ordinary
scenes with a bar hidden behind a column stay possible.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from builders import box_mesh, merge_meshes
from scipy.spatial.transform import Rotation

from meschers_igl.geometry2d import overlapping_pairs
from meschers_igl.obtain import model_to_mescher, see_model
from meschers_igl.obtain.bar_joints import coincident_gaps

ISO = np.array([1.0, 1.0, 1.0])
UP = np.array([0.0, 0.0, 1.0])


def three_boxes(legs=(10.0, 10.0, 10.0), w=1.0, joint="overlap", turn=0):
    """Three boxes along x, y and down z forming a tribar whose x-bar's start end lies
    ``legs`` (x, y, z) behind the column's top end.

    ``joint``: the real corners as boxes overlapping by half a width (``"overlap"``), sharing
    the whole corner block (``"full"``) or abutting (``"abut"``).  ``turn``: the axes cycled
    ``turn`` times (x -> y -> z), which puts the junction at another corner of the picture.
    Returns ``(V, F, T)`` with ``T`` the translation from the hidden end to the near end.
    """
    a, b, c = legs
    ext = {"overlap": 0.5 * w, "full": w, "abut": 0.0}[joint]
    boxes = [
        box_mesh([0, 0, 0], [a + ext, w, w]),
        box_mesh([a, 0 if joint != "abut" else w, 0], [a + w, b + ext, w]),
        box_mesh([a, b, 0 if joint != "abut" else w], [a + w, b + w, c + w]),
    ]
    if joint == "abut":  # abutting boxes: the y-bar starts past the x-bar, the column above
        boxes[1] = box_mesh([a, 0, 0], [a + w, b, w])
        boxes[2] = box_mesh([a, b, 0], [a + w, b + w, c + w])
        boxes[0] = box_mesh([0, 0, 0], [a, w, w])
    V, F = merge_meshes(boxes)
    T = np.array([a, b, c])
    P = np.roll(np.eye(3), turn, axis=0)
    return V @ P.T, F, P @ T


def _see(V, F, view, up, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return see_model(V, F, view, up, **kw)


def _convert(V, F, view, up):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=view, up=up)


def _check_impossible(V, F, view, up, gap):
    m, order, report = _convert(V, F, view, up)
    p = np.abs(np.asarray(m.periods()))
    assert m.is_impossible(order=order).kind == "zeta"
    assert np.all(np.isclose(p[p > 1e-6 * gap], gap, rtol=1e-6)), (p, gap)
    assert any(abs(j.depth_gap - gap) <= 1e-6 * gap for j in report.junctions)
    return m, order, report


@pytest.mark.parametrize("joint", ["overlap", "full", "abut"])
@pytest.mark.parametrize("turn", [0, 1, 2])
def test_hidden_end_joined_period_is_the_gap(joint, turn):
    """From the view along the legs, the x-bar's end hides exactly behind the column's top end:
    the mescher is impossible with one period, the gap ``|T|`` between the coincident ends
    (10 sqrt 3), whichever corner carries the junction and however the real corners are made."""
    V, F, T = three_boxes(joint=joint, turn=turn)
    gap = float(np.linalg.norm(T))
    assert gap == pytest.approx(10 * np.sqrt(3))
    _check_impossible(V, F, ISO, UP, gap)


@pytest.mark.parametrize(
    "legs, w, joint",
    [
        ((6.0, 6.0, 6.0), 1.5, "overlap"),
        ((8.0, 12.0, 16.0), 1.0, "full"),
        ((5, 7.5, 10), 2, "abut"),
    ],
)
def test_other_lengths_widths_and_views(legs, w, joint):
    """Other bar lengths and widths; legs of unequal lengths seen along their own direction
    (a non-isometric view): the period is the length of the legs' closing vector."""
    V, F, T = three_boxes(legs, w, joint)
    _check_impossible(V, F, T / np.linalg.norm(T), UP, float(np.linalg.norm(T)))


@pytest.mark.parametrize("seed", range(9))
def test_posed_rotated_scaled_translated(seed):
    """A rigid pose, a scale (1e-2 to 1e2) and an offset change nothing but the period's
    scale (each kind of real corner, the junction at each corner)."""
    rng = np.random.default_rng(seed)
    V, F, T = three_boxes(joint=["overlap", "full", "abut"][seed % 3], turn=seed // 3)
    Q = Rotation.random(random_state=seed).as_matrix()
    s = 10.0 ** rng.uniform(-2, 2)
    off = rng.normal(size=3) * 1e3 * s
    W = s * V @ Q.T + off
    _check_impossible(W, F, Q @ ISO, Q @ UP, s * float(np.linalg.norm(T)))


def test_strips_hidden_and_map_unchanged():
    """The strips added behind the near bar are hidden: the mescher's other faces tile the
    model's silhouette once (their area is the area of the union of the projected model
    triangles, from shapely: an independent oracle), and each strip face has an arc to every
    face in front that overlaps it on screen."""
    import shapely

    from meschers_igl.operators import view_frame

    V, F, T = three_boxes()
    vm = _see(V, F, ISO, UP)
    strip = vm.report.source_face < 0
    assert strip.any()
    t = vm.xy[vm.F[~strip]]
    a2 = (t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1]) - (t[:, 2, 0] - t[:, 0, 0]) * (
        t[:, 1, 1] - t[:, 0, 1]
    )
    C = V @ view_frame(ISO / np.sqrt(3), UP).T
    sil = shapely.union_all(shapely.polygons(C[F][:, :, :2])).area
    assert np.all(a2 > 0)
    assert 0.5 * a2.sum() == pytest.approx(sil, rel=1e-6)
    pairs, _ = overlapping_pairs(vm.xy[vm.F], 1e-9)
    arcs = {tuple(a) for a in np.asarray(vm.arcs).tolist()}
    for f in np.flatnonzero(strip).tolist():
        over = [int(b) for a, b in pairs.tolist() if a == f] + [
            int(a) for a, b in pairs.tolist() if b == f
        ]
        assert over and all((f, g) in arcs for g in over if not strip[g])


def test_coincident_gaps_oracle():
    """The gaps shared by two or more screen-coincident vertex pairs: on the isometric tribar,
    10 sqrt 3 (the end's two top corners); 11 sqrt 3 has one pair only."""
    from meschers_igl.operators import view_frame

    V, F, _ = three_boxes()
    C = V @ view_frame(ISO / np.sqrt(3), UP).T
    gaps = coincident_gaps(C, F, 1e-6)
    assert [round(g, 9) for g, _, _ in gaps] == [round(10 * np.sqrt(3), 9)]
    g, near, far = gaps[0]
    assert np.allclose(V[near] - V[far], 10.0)


def _possible(V, F, view=ISO, up=UP):
    m, order, report = _convert(V, F, view, up)
    assert not m.is_impossible(order=order), report.junctions
    assert np.allclose(np.asarray(m.periods()), 0.0)


def test_bar_passing_behind_a_column_stays_possible():
    """A bar that runs behind a column and comes out on the other side."""
    V, F = merge_meshes([box_mesh([0, 0, 0], [1, 1, 10]), box_mesh([-12, -6, 2], [2, -5, 3])])
    _possible(V, F)


def test_end_hidden_mid_column_stays_possible():
    """The tribar with the column raised: the x-bar's end hides behind the column's middle,
    its corners on no corner of the column."""
    a = 10.0
    V, F = merge_meshes(
        [
            box_mesh([0, 0, 0], [a + 0.5, 1, 1]),
            box_mesh([a, 0, 0], [a + 1, a + 0.5, 1]),
            box_mesh([a, a, 0], [a + 1, a + 1, a + 6]),
        ]
    )
    _possible(V, F)


def test_open_chain_going_down_stays_possible():
    """Three boxes as an ordinary open chain, the last bar going down."""
    a = 10.0
    V, F = merge_meshes(
        [
            box_mesh([0, 0, 0], [a + 0.5, 1, 1]),
            box_mesh([a, 0, 0], [a + 1, a + 0.5, 1]),
            box_mesh([a, a, -a], [a + 1, a + 1, 1]),
        ]
    )
    _possible(V, F)


def test_tribar_from_a_view_that_does_not_line_up_stays_possible():
    """The same three boxes from a view 10 degrees off: no end lies behind another."""
    V, F, _ = three_boxes()
    v = Rotation.from_rotvec(np.radians(10) * np.array([1.0, -1.0, 0]) / np.sqrt(2)).apply(ISO)
    _possible(V, F, v / np.linalg.norm(v))


@pytest.mark.slow
@pytest.mark.parametrize("joint, turn", [("overlap", 0), ("full", 1), ("abut", 2)])
def test_renders_like_the_z_buffer(joint, turn, tmp_path):
    """The mescher (strips behind the near bar by their arcs) renders like the model's
    z-buffer under two lights, with no back face in sight."""
    pytest.importorskip("pyvista")
    from meschers_igl.operators import view_frame
    from meschers_igl.painter import backface_share
    from pyvista_views import render
    from pyvista_views.compare import image_agreement
    from pyvista_views.headless import configure_headless

    configure_headless()
    V, F, T = three_boxes(joint=joint, turn=turn)
    m, order, report = _convert(V, F, ISO, UP)
    C = V @ view_frame(report.view, report.up).T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    bounds = (c[0] - h, c[0] + h, c[1] - h, c[1] + h)
    for light in [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4)]:
        kw = dict(lights=[light], window_size=(200, 200), bounds=bounds)
        agree = image_agreement(render(m, order=order, **kw), render((C, F), **kw))
        assert agree["iou"] >= 0.99 and agree["luminance_corr"] >= 0.99, agree
    assert backface_share(m, order, size=128, bounds=bounds) <= 1e-3


@pytest.mark.parametrize("joint, turn", [("overlap", 0), ("full", 1), ("abut", 2)])
def test_auto_view_finds_the_view_along_the_legs(joint, turn):
    """``view="auto"``: the best-supported direction of lined-up vertex pairs is the view along
    the legs, and the joint seen from it is a junction: that view, and the period ``|T|``."""
    V, F, T = three_boxes(joint=joint, turn=turn)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = model_to_mescher(V, F, view="auto")
    assert abs(report.view @ T) == pytest.approx(np.linalg.norm(T), rel=1e-9)
    p = np.abs(np.asarray(m.periods()))
    assert np.all(np.isclose(p[p > 1e-6], np.linalg.norm(T), rtol=1e-6)) and p.max() > 1


def test_pairs_spread_through_a_block_lattice_are_no_bar_end():
    """An L-shaped block of unit cells before a wall, seen along the lattice vector (-1, -2, 1):
    six vertex pairs coincide on screen with one gap (sqrt 6), spread over the solid, not the
    corners of one bar's end (they lie in no plane).  No joint is read there; the scene stays
    possible from that view (it came out impossible, period sqrt 6, when any equal gaps
    counted)."""
    from ordinary_scenes import SCENES

    from meschers_igl.obtain.bar_joints import _one_end
    from meschers_igl.operators import view_frame

    V, F = SCENES["l_block"]()
    for view in ((-1.0, -2.0, 1.0), (-0.5, -1.0, 0.5)):
        R = view_frame(np.asarray(view) / np.linalg.norm(view), (0.0, 0.0, 1.0))
        tol = 1e-5 * float(np.linalg.norm(np.ptp(V, axis=0)))
        assert coincident_gaps(V @ R.T, F, tol) == []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m, order, _ = model_to_mescher(V, F, view=view, up=(0.0, 0.0, 1.0))
        assert not m.is_impossible(order=order)
    # the rule itself: corners of one end (a square, tilted) against a square and a point off it
    sq = (
        np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
        @ Rotation.random(random_state=1).as_matrix().T
    )
    assert _one_end(sq, 1e-9) and _one_end(sq[:3] + 5.0, 0.0)
    assert not _one_end(
        np.vstack([sq, sq[0] + 1e-3 * np.cross(sq[1] - sq[0], sq[3] - sq[0])]), 1e-6
    )


def test_gaps_on_a_lattice_are_no_joints():
    """Three or more gaps that are integer multiples of one step are repeated blocks seen
    along their repeat; two gaps (a tribar whose corner blocks coincide too) or gaps off the
    lattice are not."""
    from meschers_igl.obtain.bar_joints import _lattice

    r2 = np.sqrt(2.0)
    assert _lattice(np.array([2, 3, 4]) * r2, 1e-6)
    assert _lattice(np.array([1, 2, 5]) * 0.7, 1e-6)
    assert not _lattice(np.array([np.sqrt(3.0), 10 * np.sqrt(3.0)]), 1e-6)
    assert not _lattice(np.array([1.0, 2.0, 3.5]), 1e-6)
    assert not _lattice(np.array([1.0, 2.0, 3.0 + 1e-3]), 1e-6)


def test_a_staircase_seen_along_its_repeat_has_no_bar_joint():
    """A square spiral staircase (a real object) seen from the side along the vector from one
    step to the next lines up a face of each step with a face of the steps behind it (gaps of
    2, 3 and 4 times that vector): possible, with no joint."""
    from test_obtain_auto_stairs import _pose, square_spiral

    from meschers_igl.obtain.view import find_view
    from meschers_igl.operators import view_frame

    V, F = square_spiral([("+y", 4), ("+x", 4), ("-y", 4), ("-x", 3)])
    V, _ = _pose(V, 3)
    v, up = find_view(V, F)
    tol = 1e-5 * float(np.linalg.norm(np.ptp(V, axis=0)))
    assert coincident_gaps(V @ view_frame(v, up).T, F, tol) == []
    m, order, report = _convert(V, F, v, up)
    assert not m.is_impossible(order=order), np.abs(m.periods()).max()
    assert not report.junctions
