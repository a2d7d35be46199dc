"""The shape, not its triangulation: the same tribar meshed four ways converts the same.

A capped U-shaped Penrose tribar (bars 2 wide, legs 12, 12 and 10 long, as a closed solid) is
built as a polycube on a grid of cells.  A modelling tool's grid puts vertices inside flat faces
and partway along straight edges; on a grid of 2-wide cells one of them lies, from the
isometric view, exactly where the outline of the near bar crosses the face behind, and the old
rule glued that grid line as a junction (period 8 sqrt 3 = 13.856 instead of the 10 sqrt 3 =
17.321 where the hidden bar end's corners pair up with the near bar end's).  The same shape
meshed coarsely, on 2-wide or 1-wide cells, with each quad split either way, must give one
period: the depth gap of the bar end's corner pairs.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from meschers_igl.errors import MescherWarning
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.bar_joints import HiddenStrip, _distinct_strips, corner_vertices
from meschers_igl.obtain.glue import flat_edges

VIEW = np.array([1.0, -1.0, 1.0]) / np.sqrt(3.0)
UP = (0.0, 1.0, 0.0)
GAP = 10.0 * np.sqrt(3.0)  # the z-bar's end cap behind the x-bar's end, (10, -10, 10) apart


def polycube(xs, ys, zs, filled, split=0):
    """Closed surface of the union of grid cells ``filled`` ((i, j, k) indices into the grid
    ``xs x ys x zs``): a quad between each filled cell and an empty neighbour, split along
    its diagonal 0-2 (``split=0``) or 1-3, outward."""
    grid = (np.asarray(xs, float), np.asarray(ys, float), np.asarray(zs, float))
    index: dict = {}
    quads = []
    for c in sorted(filled):  # test code: a few dozen cells
        for ax in range(3):
            for s in (-1, 1):
                nb = list(c)
                nb[ax] += s
                if tuple(nb) in filled:
                    continue
                a, b = [d for d in range(3) if d != ax]
                q = []
                for da, db in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    idx = [0, 0, 0]
                    idx[ax] = c[ax] + (s > 0)
                    idx[a], idx[b] = c[a] + da, c[b] + db
                    q.append(index.setdefault(tuple(idx), len(index)))
                quads.append((q, ax, s))
    V = np.zeros((len(index), 3))
    for (i, j, k), n in index.items():
        V[n] = grid[0][i], grid[1][j], grid[2][k]
    F = []
    for q, ax, s in quads:
        n = np.cross(V[q[1]] - V[q[0]], V[q[2]] - V[q[0]])
        if n[ax] * s < 0:
            q = q[::-1]
        F += (
            [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            if split == 0
            else [
                [q[0], q[1], q[3]],
                [q[1], q[2], q[3]],
            ]
        )
    return V, np.array(F)


def u_tribar_cells(step: float):
    """The U-tribar's x-bar (to x = 11), y-bar (to y = 11) and z-bar (down to z = -9) on
    cells ``step`` wide, or on the coarsest grid that holds it (``step=0``)."""
    if step == 0:
        xs, ys, zs = [-1, 1, 11], [-1, 1, 9, 11], [-9, -1, 1]
        filled = {(0, 0, 1), (1, 0, 1), (0, 1, 1), (0, 2, 1), (0, 2, 0)}
        return xs, ys, zs, filled
    xs = np.arange(-1.0, 11.0 + step / 2, step)
    zs = np.arange(-9.0, 1.0 + step / 2, step)
    ys = xs
    n, k1 = xs.size - 1, int(round(2 / step))  # cells per bar's width
    top = zs.size - 1 - k1  # first z cell of the bars' layer
    filled = set()
    for i in range(n):
        for a in range(k1):
            for b in range(k1):
                filled.add((i, a, top + b))  # x-bar
                filled.add((a, i, top + b))  # y-bar
    for k in range(zs.size - 1):
        for a in range(k1):
            for b in range(k1):
                filled.add((a, n - k1 + b, k))  # z-bar at the y-bar's far end
    return xs, ys, zs, filled


def _periods(V, F, view=VIEW, up=UP):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        m, _, report = model_to_mescher(V, F, view=view, up=up)
    p = np.abs(np.asarray(m.periods()))
    return p[p > 1e-6 * m.scale()], report


@pytest.mark.parametrize("split", [0, 1])
@pytest.mark.parametrize("step", [0, 2.0, 1.0])
def test_the_same_tribar_meshed_otherwise_has_the_same_period(step, split):
    V, F = polycube(*u_tribar_cells(step), split=split)
    p, report = _periods(V, F)
    assert p.size >= 1
    np.testing.assert_allclose(p, GAP, rtol=1e-9)
    assert [j.kind for j in report.junctions] == ["bar joint"]


def test_grid_vertices_jittered_keep_the_joint():
    """At 1e-6 of the size the model is the same to a person (its faces tilt by ~1e-5)."""
    V, F = polycube(*u_tribar_cells(2.0))
    rng = np.random.default_rng(0)
    for _ in range(3):
        Vj = V + rng.normal(scale=1e-6 * np.ptp(V, axis=0).max(), size=V.shape)
        p, _ = _periods(Vj, F)
        assert p.size >= 1
        np.testing.assert_allclose(p, GAP, rtol=1e-5)


def test_corners_of_a_subdivided_box_are_its_eight_corners():
    """A cube on a 3 x 3 x 3 grid: 8 corners; the 48 vertices inside its faces or partway along
    its edges are the grid's.  An open square sheet's outline vertices are all corners."""
    V, F = polycube(
        range(4),
        range(4),
        range(4),
        {(i, j, k) for i in range(3) for j in range(3) for k in range(3)},
    )
    c = corner_vertices(V, F)
    assert V.shape[0] == 56 and c.sum() == 8
    assert np.all(np.isin(V[c], [0.0, 3.0]).all(axis=1))
    # a flat sheet of 2 x 2 quads: the outline (8 vertices) but not the centre
    g = np.array([(i, j, 0.0) for j in range(3) for i in range(3)])
    q = [
        (i + 3 * j, i + 1 + 3 * j, i + 4 + 3 * j, i + 3 + 3 * j) for j in range(2) for i in range(2)
    ]
    Fs = np.array([t for a, b, cc, d in q for t in ((a, b, cc), (a, cc, d))])
    cs = corner_vertices(g, Fs)
    assert cs.sum() == 8 and not cs[4]


def test_flat_edges_are_the_triangulations():
    """The edge between two faces of one plane is flat; a bent one or a missing neighbour is
    not."""
    C = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [1, 1, 0.5]], float)
    F = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 2]])
    out = flat_edges(C, F, np.array([0, 0, 0]), np.array([1, 2, -1]), 1e-9)
    assert out.tolist() == [True, False, False]


def test_a_strip_reached_twice_is_added_once():
    """Two strips of one gap covering nearly the same region (a corner 0.01 apart, found along
    nearly parallel lines) are one; a strip elsewhere or of another gap is kept."""
    ring = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    faces = np.zeros(0, np.int64)
    a = HiddenStrip(ring, faces, 5.0)
    b = HiddenStrip(ring + [[0, 0], [0.01, 0], [0, 0], [0, 0]], faces, 5.0)
    c = HiddenStrip(ring + 3.0, faces, 5.0)
    d = HiddenStrip(ring, faces, 7.0)
    kept = _distinct_strips([a, b, c, d], 1e-6)
    assert [id(k) for k in kept] == [id(a), id(c), id(d)]
