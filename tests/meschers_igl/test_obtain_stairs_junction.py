"""Step junctions of Penrose stairs: the top tread's edge seen over a wall that rises to the
bottom tread, a person reading the strip of wall as one more riser.

The models are made here in two ways other than ``test_obtain_hidden_riser``'s square step
columns: a ring of four flights with different step counts on a ``W x H`` rectangle, as
separate blocks and as one closed solid (a height field with its walls split at every level,
so it is watertight).  Seen along ``w = (W - 2, b, r N)`` (``b < 1``) the top tread's -x edge
lies on the +x walls of the first columns, over the bottom column's one riser below its top: the
loop climbs ``N`` risers per turn and the period is the depth of that climb along the view,
``r N / v_z`` (the oracle is the construction, not the code).  With ``b = 1`` the columns'
vertical edges would line up too (a false edge of their own); ``b < 1`` keeps them apart, and
the old rules saw these rings as possible.  Ordinary objects stay possible: the same ring where its drop is in
sight, a box in front of a wall, a flight before a wall on a floor.
"""

from __future__ import annotations

import numpy as np
import pytest
from visible_models import convert_quietly

from meschers_igl.obtain.stairs import MAX_JUNCTION_RISE
from meschers_igl.shapes import boxes


def ring_cells(W: int, H: int):
    """Cells of a ring of flights on a ``W x H`` rectangle: up ``x = 0`` (``H`` steps), along
    ``y = H`` (``W + 1``), down ``x = W`` (``H - 1``) and the top cell ``(W - 1, 1)`` beside
    the last flight; cell ``k`` is ``k`` risers high."""
    return (
        [(0, j) for j in range(H)]
        + [(i, H) for i in range(W + 1)]
        + [(W, j) for j in range(H - 1, 0, -1)]
        + [(W - 1, 1)]
    )


def ring_blocks(W: int, H: int, r: float, base: float = -2.5):
    """The ring as separate blocks. Returns (V, F, N) with N the number of treads."""
    cells = ring_cells(W, H)
    lo = np.array([[i, j, base] for i, j in cells], float)
    hi = np.array([[i + 1, j + 1, r * k] for k, (i, j) in enumerate(cells)], float)
    V, F = boxes(lo, hi)
    return V, F, len(cells)


def heightfield_solid(height: dict, base: float):
    """One closed solid over unit cells ``(i, j) -> top height``: tops, bottoms and the walls
    between a cell and a lower neighbour (or none), each wall split at every level so that
    the surface is watertight.  Returns (V, F), outward oriented."""
    levels = np.unique(np.r_[base, list(height.values())])
    quads = []
    for (i, j), h in height.items():
        quads.append([(i, j, h), (i + 1, j, h), (i + 1, j + 1, h), (i, j + 1, h)])
        quads.append([(i, j, base), (i, j + 1, base), (i + 1, j + 1, base), (i + 1, j, base)])
        sides = {  # neighbour, the wall's two corners counter-clockwise seen from outside
            (i + 1, j): ((i + 1, j), (i + 1, j + 1)),
            (i - 1, j): ((i, j + 1), (i, j)),
            (i, j + 1): ((i + 1, j + 1), (i, j + 1)),
            (i, j - 1): ((i, j), (i + 1, j)),
        }
        for nb, (a, b) in sides.items():
            lo = height.get(nb, base)
            zs = levels[(levels >= lo) & (levels <= h)]
            for z0, z1 in zip(zs[:-1], zs[1:]):
                quads.append([(*a, z0), (*b, z0), (*b, z1), (*a, z1)])
    P = np.array(quads, float).reshape(-1, 3)
    V, inv = np.unique(np.round(P, 9), axis=0, return_inverse=True)
    Q = inv.reshape(-1, 4)
    F = np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])
    return V, F


def ring_solid(W: int, H: int, r: float, base: float = -2.5):
    cells = ring_cells(W, H)
    V, F = heightfield_solid({c: r * k for k, c in enumerate(cells)}, base)
    return V, F, len(cells)


RINGS = [(4, 3, 0.2), (5, 2, 0.15), (3, 4, 0.1)]


@pytest.mark.parametrize("make", [ring_blocks, ring_solid])
@pytest.mark.parametrize("b", [0.8, 0.6])
@pytest.mark.parametrize("W,H,r", RINGS)
def test_penrose_ring_period_is_the_climb_per_turn(make, W, H, r, b):
    """Seen along ``(W - 2, b, r N)`` the ring is impossible; its least period is the climb of
    ``N`` risers seen along the view, ``r N / v_z``, and every period a whole number of it."""
    V, F, N = make(W, H, r)
    w = np.array([W - 2.0, b, r * N])
    m, order, report, p = convert_quietly(V, F, w)
    climb = r * N / (w[2] / np.linalg.norm(w))
    np.testing.assert_allclose(climb, np.linalg.norm(w), rtol=1e-12)  # the construction
    assert m.is_impossible(order=order).kind == "zeta"
    np.testing.assert_allclose(p.min(), climb, rtol=1e-6)
    np.testing.assert_allclose(p / climb, np.round(p / climb), atol=1e-6)
    gaps = [j.depth_gap for j in report.junctions if j.kind == "false edge"]
    assert any(np.isclose(g, climb, rtol=1e-6) for g in gaps)


@pytest.mark.parametrize("make", [ring_blocks, ring_solid])
def test_penrose_ring_any_pose(make):
    """The rule is the same in any pose: the ring rotated, seen along the rotated view."""
    W, H, r = RINGS[0]
    V, F, N = make(W, H, r)
    w = np.array([W - 2.0, 0.7, r * N])
    Q, _ = np.linalg.qr(np.random.default_rng(3).normal(size=(3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    m, order, _, p = convert_quietly(V @ Q.T, F, Q @ w, Q @ np.array([0.0, 0.0, 1.0]))
    assert m.is_impossible(order=order).kind == "zeta"
    np.testing.assert_allclose(p.min(), np.linalg.norm(w), rtol=1e-6)


@pytest.mark.parametrize("make", [ring_blocks, ring_solid])
@pytest.mark.parametrize("k", [0.5, 1.5])
def test_junction_strip_of_a_few_risers(make, k):
    """Slightly off the exact view the strip of wall is ``1 + k`` risers tall, up to
    MAX_JUNCTION_RISE: still the last riser of the loop, whose period is the climb seen,
    ``r (N + k) / v_z``."""
    W, H, r = RINGS[0]
    assert 1.0 + k <= MAX_JUNCTION_RISE
    V, F, N = make(W, H, r)
    w = np.array([W - 2.0, 0.7, r * (N + k)])
    m, order, _, p = convert_quietly(V, F, w)
    assert m.is_impossible(order=order).kind == "zeta"
    np.testing.assert_allclose(p.min(), np.linalg.norm(w), rtol=1e-6)


@pytest.mark.parametrize("make", [ring_blocks, ring_solid])
@pytest.mark.parametrize(
    "view",
    [
        (-1.0, 0.45, 1.5),  # the drop (the top cell's -x face) in sight
        (2.0, 0.7, 0.2 * 14.5),  # the top's edge 4.5 risers down the wall: a wall
        (0.7, 0.45, 1.0),
        (1.1, 0.3, 0.8),
    ],
)
def test_ring_with_its_drop_in_sight_is_possible(make, view):
    """The ring is a real spiral with a drop: where the drop is seen, or the strip below the
    bottom tread is taller than MAX_JUNCTION_RISE risers, no step junction is glued."""
    V, F, _ = make(*RINGS[0])
    m, order, report, p = convert_quietly(V, F, view)
    assert p.size == 0
    assert not m.is_impossible(order=order)


def test_box_in_front_of_a_wall_is_possible():
    """A box whose top's back edge lies over a taller wall standing on the same floor: no
    chain of rising steps leads from the wall's top back to the box."""
    lo = np.array([[-1.0, -1.0, -0.2], [0.0, 0.0, 0.0], [-0.5, 2.0, 0.0]])
    hi = np.array([[3.0, 4.0, 0.0], [1.0, 1.0, 1.0], [2.5, 2.5, 2.0]])
    V, F = boxes(lo, hi)
    for view in [(0.3, -1.0, 0.8), (0.0, -1.0, 0.5), (-0.4, -1.0, 1.2)]:
        m, order, report, p = convert_quietly(V, F, view)
        assert p.size == 0
        assert not m.is_impossible(order=order)


def test_flight_before_a_wall_is_possible():
    """A straight flight climbing toward a lower wall behind it, on a floor: the top tread's
    back edge over the wall, whose top only the floor reaches (a step down from the flight)."""
    n, rise = 4, 0.3
    lo = [[-1.0, -1.0, -0.2]] + [[0.0, j, 0.0] for j in range(n)] + [[-0.5, n + 1.0, 0.0]]
    hi = [[3.0, n + 3.0, 0.0]] + [[1.0, j + 1.0, rise * (j + 1)] for j in range(n)]
    hi += [[1.5, n + 1.5, 0.5]]
    V, F = boxes(np.array(lo), np.array(hi))
    for view in [(0.3, -1.0, 1.0), (-0.3, -1.0, 1.1)]:
        m, order, report, p = convert_quietly(V, F, view)
        assert p.size == 0
        assert not m.is_impossible(order=order)
