"""``view="auto"`` on reliefs: physically realisable tricks carved to be seen from the front.

A relief reads as an impossible figure only to a person assuming right angles
(``perceive="manhattan"``); no vertex pairs line up from its front (it is a real torus), so the
junction search finds no view.  The rule: a relief is seen from the front along its thin axis,
toward its carved side.  Checked on the relief of ``relief_models`` (sheared, compressed cubes;
the perceived climb ``sqrt(3) k a`` computed from the cube path, not from the model) put in a
general pose, and on models with no illusion that must stay possible.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from relief_models import flat_backed_relief, reutersvard_relief
from visible_models import AXES, ISO_VIEW, convex_block, soup, triangulate, weld_blocks

from meschers_igl import MescherError, MescherWarning
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.view import RELIEF_RATIO, relief_fronts
from meschers_igl.shapes import boxes, random_rotation


def _pose(V, seed):
    """A rigid motion of ``V`` (rows) and the rotation."""
    R = random_rotation(seed)
    return V @ R.T + np.array([3.0, -7.0, 11.0]), R


def _periods(m, size):
    p = np.abs(np.asarray(m.periods()))
    return np.unique(np.round(p[p > 1e-5 * size], 9))


@pytest.mark.parametrize("seed", [1, 3])
def test_auto_manhattan_takes_the_carved_front_of_a_flat_backed_relief(seed):
    # before: the vote lined up bar ends along another direction and read nothing (seed 3:
    # view (0.886, -0.433, -0.164), no period)
    V, F, gap = flat_backed_relief(4, 1.0, 0.3)
    Vp, R = _pose(V, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        m, order, report = model_to_mescher(Vp, F, view="auto", perceive="manhattan")
    # the flat back faces away: the view is the figure's own, not its mirror
    assert np.allclose(report.view, R @ ISO_VIEW, atol=1e-9)
    p = _periods(m, gap)
    assert p.size == 1 and abs(p[0] - gap) <= 1e-6 * gap
    assert m.is_impossible(order=order).kind == "zeta"


def test_auto_manhattan_reads_a_two_sided_relief_as_a_soup():
    # carved on both sides (a sheared torus of cubes): either side reads the same climb
    k = 5
    V, P, gap = reutersvard_relief(k, 1.0, 0.4)
    Vp, R = _pose(V, 7)
    assert gap == pytest.approx(np.sqrt(3.0) * k)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        m, _, report = model_to_mescher(
            *soup(Vp, triangulate(P)), view="auto", perceive="manhattan"
        )
    assert abs(report.view @ (R @ ISO_VIEW)) == pytest.approx(1.0, abs=1e-9)
    p = _periods(m, gap)
    assert p.size == 1 and abs(p[0] - gap) <= 1e-5 * gap  # float32 soup


def test_auto_without_perceive_suggests_it_instead_of_refusing():
    # before: "view: expected a view from which junctions line up, found none"
    V, P, gap = reutersvard_relief(4, 1.0, 0.3)
    Vp, R = _pose(V, 2)
    with pytest.warns(MescherWarning, match="perceive='manhattan'"):
        m, order, report = model_to_mescher(Vp, triangulate(P), view="auto")
    assert not m.is_impossible(order=order)  # possible as carved: a real torus
    assert abs(report.view @ (R @ ISO_VIEW)) == pytest.approx(1.0, abs=1e-9)
    assert any("perceive='manhattan'" in w for w in report.warnings)


def test_relief_fronts_of_a_plate_with_blocks_on_one_side():
    # a plate and blocks on its +z face, as separate boxes, in a general pose: the front is
    # the plate's normal toward the blocks (the oracle: the rotation's third column)
    lo = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.5], [2.0, 1.0, 0.5]])
    hi = np.array([[4.0, 3.0, 0.5], [1.5, 2.0, 0.8], [3.0, 2.0, 1.2]])
    V, F = boxes(lo, hi)
    for seed in range(4):
        Vp, R = _pose(V, seed)
        fronts = relief_fronts(Vp, F)
        assert len(fronts) == 2
        assert np.allclose(fronts[0], R[:, 2], atol=1e-12)
        assert np.allclose(fronts[1], -R[:, 2], atol=1e-12)
        # mirrored through the plate (blocks below it): the other side
        Vm = V * np.array([1.0, 1.0, -1.0])
        fm = relief_fronts(_pose(Vm, seed)[0], F[:, ::-1])
        assert np.allclose(fm[0], -R[:, 2], atol=1e-12)


def test_relief_fronts_only_for_thin_models():
    # a box of depth t and 1 x 2 across is a relief exactly when t <= RELIEF_RATIO * 1
    for t, thin in ((0.99 * RELIEF_RATIO, True), (1.01 * RELIEF_RATIO, False)):
        V, F = boxes(np.zeros((1, 3)), np.array([[2.0, 1.0, t]]))
        assert bool(relief_fronts(V, F)) is thin
    # a flat sheet (no hull): its normal, the convention's side first (v_z >= 0)
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float) @ random_rotation(5).T
    fr = relief_fronts(V, np.array([[0, 1, 2], [0, 2, 3]]))
    n = random_rotation(5)[:, 2]
    assert np.allclose(fr[0], n if n[2] >= 0 else -n, atol=1e-12)


def _open_chain(lam=0.3):
    """A possible figure: an L of unit cubes (4 along x, then 3 along y), compressed in depth
    along the isometric view (a relief).  (A chain climbing in z too nearly closes on screen:
    its end cube meets the first one edge to edge from this view, the real object's trick.)"""
    steps = [AXES[0]] * 3 + [AXES[1]] * 3
    c = [np.zeros(3)]
    for d in steps:
        c.append(c[-1] + d)
    blocks = []
    for ctr in c:
        hs = np.array([np.r_[e * sg, -(ctr @ (e * sg)) - 0.5] for e in AXES for sg in (1, -1)])
        Vb, Pb = convex_block(hs, ctr)
        Vb = Vb - (1.0 - lam) * (Vb @ ISO_VIEW)[:, None] * ISO_VIEW[None, :]
        blocks.append((Vb, Pb))
    V, polys = weld_blocks(blocks)
    return V, triangulate(polys)


@pytest.mark.parametrize("perceive", [None, "manhattan"])
def test_reliefs_with_no_illusion_stay_possible(perceive):
    V, F = _open_chain()
    plate = boxes(
        np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.5], [2.0, 1.0, 0.5]]),
        np.array([[4.0, 3.0, 0.5], [1.5, 2.0, 0.8], [3.0, 2.0, 1.2]]),
    )
    for Vm, Fm in ((V, F), plate):
        assert relief_fronts(Vm, Fm)  # thin: the relief rule applies
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MescherWarning)
            try:
                m, order, _ = model_to_mescher(Vm, Fm, view="auto", perceive=perceive)
            except MescherError:
                continue  # no view (nothing lines up, nothing reads as a box drawing)
        assert not m.is_impossible(order=order)


REAL = os.environ.get("MESCHERS_REAL_MODELS", "/work/shared/real_models")


@pytest.mark.skipif(
    not os.path.isfile(os.path.join(REAL, "ImpossibleTriangle.obj")), reason="no real models"
)
def test_real_relief_from_auto_reads_as_from_its_given_view():
    from meshlab_filters import model_to_mescher as from_file

    path = os.path.join(REAL, "ImpossibleTriangle.obj")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        mg, _, _ = from_file(path, view=(0, 0, 1), up=(0, 1, 0), perceive="manhattan")
        ma, _, ra = from_file(path, view="auto", perceive="manhattan")
    assert np.allclose(ra.view, [0.0, 0.0, 1.0], atol=1e-12)
    pg, pa = _periods(mg, 100.0), _periods(ma, 100.0)
    assert pa.size >= 1 and np.allclose(pa, pg, rtol=1e-9)
