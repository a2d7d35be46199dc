"""Steps with a hidden riser: a tread's front edge lies over the lower tread (the riser faces
away), and the visible surface joins the two treads by a riser band seen edge-on.

The models are step columns (separate boxes, as a modeller lays out blocks): a Penrose ring
whose last column lines up on screen with the first one turn higher, and ordinary stairs.
The band carries the real depth step, so it never creates a period by itself: the period of a
Penrose ring is its climb per turn (the offset along the view of the columns that line up),
and ordinary stairs stay possible.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from visible_models import convert_quietly

from meschers_igl.errors import MescherWarning
from meschers_igl.obtain import see_model
from meschers_igl.obtain.glue import STEP_BAND
from meschers_igl.operators import view_frame
from meschers_igl.shapes import boxes


def penrose_columns(s: int, base: float = -2.5):
    """A Penrose ring of step columns on the border of an ``(s+1) x (s+1)`` grid: flights up
    ``x = 0`` (``s`` steps), along ``y = s`` (``s + 1``), down ``x = s`` (``s - 1``) and one
    column at ``(s - 1, 1)``, each one rise ``r = (s - 2) / (3 s)`` above the one before.  The
    last column's top is ``3 s r = s - 2`` above the first, offset ``w = (s - 2, 1, s - 2)``
    from it: seen along ``w`` its -x top edge lies on the first column's +x top edge, and a
    turn climbs ``|w|`` along the view.  Returns (V, F, w)."""
    r = (s - 2) / (3 * s)
    cells = (
        [(0, j) for j in range(s)]
        + [(i, s) for i in range(s + 1)]
        + [(s, j) for j in range(s - 1, 0, -1)]
        + [(s - 1, 1)]
    )
    lo = np.array([[i, j, base] for i, j in cells], float)
    hi = np.array([[i + 1, j + 1, r * k] for k, (i, j) in enumerate(cells)], float)
    V, F = boxes(lo, hi)
    return V, F, np.array([s - 2.0, 1.0, s - 2.0])


def straight_flight(n: int = 5, rise: float = 0.25):
    """An ordinary straight flight of ``n`` step columns climbing along +y."""
    lo = np.array([[0.0, j, -1.0] for j in range(n)])
    hi = np.array([[1.0, j + 1.0, rise * (j + 1)] for j in range(n)])
    return boxes(lo, hi)


def stepped_grid(n: int = 3, rise: float = 0.3):
    """Touching unit columns on an ``n x n`` grid, column ``(i, j)`` of height ``1 + rise (i + j)``:
    steps climbing along x and y at once (a real object)."""
    ij = np.array([(i, j) for i in range(n) for j in range(n)], float)
    lo = np.c_[ij, np.zeros(n * n)]
    hi = np.c_[ij + 1.0, 1.0 + rise * ij.sum(axis=1)]
    return boxes(lo, hi)


def _n_bands(report) -> int:
    return int(np.count_nonzero(report.source_face < 0))


@pytest.mark.parametrize("s", [4, 5])
def test_penrose_columns_climb_per_turn(s):
    """Seen along ``w`` the ring is impossible and every period is a whole number of turns,
    the least one turn: |w| (the hidden risers of the flights climbing away join the treads;
    without them the tread loop is cut and only the depth order is impossible)."""
    V, F, w = penrose_columns(s)
    m, order, report, p = convert_quietly(V, F, w)
    climb = float(np.linalg.norm(w))
    assert m.is_impossible(order=order).kind == "zeta"
    assert p.size >= 1
    np.testing.assert_allclose(p.min(), climb, rtol=1e-6)
    np.testing.assert_allclose(p / climb, np.round(p / climb), atol=1e-6)
    assert _n_bands(report) > 0


def test_penrose_columns_any_pose():
    """The rule is the same in any pose: the ring rotated, seen along the rotated ``w``."""
    V, F, w = penrose_columns(4)
    rng = np.random.default_rng(7)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    m, order, report, p = convert_quietly(V @ Q.T, F, Q @ w, Q @ np.array([0.0, 0.0, 1.0]))
    assert m.is_impossible(order=order).kind == "zeta"
    np.testing.assert_allclose(p.min(), np.linalg.norm(w), rtol=1e-6)


@pytest.mark.parametrize("view", [(0.7, 0.45, 1.0), (1.1, 0.3, 0.8)])
@pytest.mark.parametrize("s", [3, 4, 5])
def test_penrose_columns_from_a_general_view_are_possible(s, view):
    """The ring is a real object (a spiral with a drop): from a view where nothing lines up,
    the riser bands join its treads and no period appears."""
    V, F, _ = penrose_columns(s)
    m, order, report, p = convert_quietly(V, F, view)
    assert _n_bands(report) > 0  # the rule was used
    assert p.size == 0
    assert not m.is_impossible(order=order)


@pytest.mark.parametrize("view", [(2.0, 1.0, 2.0), (1.0, 3.0, 2.0), (-1.0, 2.0, 3.0)])
def test_ordinary_stairs_stay_possible(view):
    """A straight flight with its risers facing away and its side wall in front of the lower
    treads (the wall's step edges cut them too): the bands add no period."""
    V, F = straight_flight()
    m, order, report, p = convert_quietly(V, F, view)
    if view[1] > 0:  # risers face -y: hidden from these views
        assert _n_bands(report) > 0
    assert p.size == 0
    assert not m.is_impossible(order=order)


@pytest.mark.parametrize("view", [(2.0, 1.0, 2.0), (1.0, 1.0, 1.0), (-1.0, -2.0, 3.0)])
def test_stepped_grid_stays_possible(view):
    V, F = stepped_grid()
    m, order, _, p = convert_quietly(V, F, view)
    assert p.size == 0
    assert not m.is_impossible(order=order)


def test_band_is_a_thin_riser_between_the_treads():
    """Each band triangle has its corners on two consecutive treads (world heights ``rise k``
    and ``rise (k + 1)``, read back from its screen position and depth), and the bands are
    thin: their screen area is at most the band width times the front edges they run along."""
    rise, n = 0.25, 3
    V, F = straight_flight(n=n, rise=rise)
    v, up = np.array([2.0, 1.0, 2.0]) / 3.0, np.array([0.0, 0.0, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        vm = see_model(V, F, v, up, snap=False)
    band = vm.report.source_face < 0
    assert band.any()
    R = view_frame(vm.report.view, vm.report.up)
    P = np.concatenate([vm.xy[vm.F[band]], vm.Z[band][..., None]], axis=2)  # camera frame
    height = (P @ R)[..., 2] / rise  # world z in rises
    np.testing.assert_allclose(height, np.round(height), atol=1e-6)
    k = np.round(height)
    np.testing.assert_array_equal(k.max(axis=1) - k.min(axis=1), 1.0)
    T = vm.xy[vm.F[band]]
    area = 0.5 * np.abs(
        (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1])
        - (T[:, 2, 0] - T[:, 0, 0]) * (T[:, 1, 1] - T[:, 0, 1])
    )
    diag = float(np.linalg.norm(np.ptp(V, axis=0)))
    # n - 1 hidden steps, each front edge of unit length (shorter on screen)
    assert 0.0 < area.sum() <= STEP_BAND * diag * (n - 1) * (1.0 + 1e-9)
