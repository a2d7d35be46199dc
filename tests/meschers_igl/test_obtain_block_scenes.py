"""Ordinary scenes of separate blocks seen from standard views stay possible.

From the isometric and dimetric views a modelling tool offers, edges of separate blocks line up
on screen by accident: an arch's post's side behind the other post's, a short box's side along
a tall box's.  A false edge (a junction) needs its two model edges to pair corner to corner
when the far one is its block's outline; edges that merely overlap on screen, shifted along
their line, are an alignment, and the scene is possible.  A tribar's junction (corners that
pair) still glues.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from meschers_igl.errors import MescherError
from meschers_igl.obtain import model_to_mescher

#: Corners of the unit cube, index ``4 x + 2 y + z``, and its 12 outward triangles.
CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float64)
CUBE_F = np.array(
    [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1]]
    + [[2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
)


def blocks(bounds):
    """One unwelded mesh of axis-aligned boxes ``(x0, x1, y0, y1, z0, z1)``."""
    V = np.vstack(
        [np.array(b[0::2]) + CUBE * (np.array(b[1::2]) - np.array(b[0::2])) for b in bounds]
    )
    F = np.vstack([CUBE_F + 8 * k for k in range(len(bounds))])
    return V, F


SCENES = {
    "arch": [(0, 1, 0, 1, 0, 3), (3, 4, 0, 1, 0, 3), (0, 4, 0, 1, 3, 4)],
    "frame": [(0, 1, 0, 1, 0, 4), (3, 4, 0, 1, 0, 4), (0, 4, 0, 1, 0, 1), (0, 4, 0, 1, 3, 4)],
    "two_on_slab": [(0, 1, 0, 1, 0, 1), (2, 3, 0, 1, 0, 2), (-1, 4, -1, 2, -0.2, 0)],
    "city": [
        (2 * x, 2 * x + 1, 2 * y, 2 * y + 1, 0, 1 + (7 * x + 3 * y) % 4)
        for x in range(3)
        for y in range(3)
    ]
    + [(-1, 6, -1, 6, -0.1, 0)],
}

# (scene, view): each was impossible before (a false edge of two overlapping outlines)
CASES = [
    ("arch", (2, 1, 1)),
    ("frame", (2, 1, 1)),
    ("two_on_slab", (1, 1, 1)),
    ("two_on_slab", (1, -1, 1)),
    ("city", (1, -1, 1)),
]


@pytest.mark.parametrize(("name", "view"), CASES)
def test_blocks_lining_up_by_accident_stay_possible(name, view):
    V, F = blocks(SCENES[name])
    v = np.asarray(view, float) / np.linalg.norm(view)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, _, report = model_to_mescher(V, F, view=v, up=(0, 0, 1))
    gaps = [j.depth_gap for j in report.junctions if j.kind == "false edge"]
    p = np.abs(np.asarray(m.periods(), float))
    assert not m.is_impossible() and np.all(p <= 1e-9), (p, gaps)
    assert not gaps


def test_a_tribar_of_blocks_still_glues_its_junction():
    """The control: three blocks whose end edges pair corner to corner from ``T``."""
    a, b, c = 8.0, 12.0, 16.0
    V, F = blocks([(0, a, 0, 1, 0, 1), (a, a + 1, 0, b, 0, 1), (a, a + 1, b, b + 1, 0, c + 1)])
    T = np.array([a, b, c])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, _, _ = model_to_mescher(V, F, view=T / np.linalg.norm(T), up=(0, 0, 1))
    p = np.abs(np.asarray(m.periods(), float))
    np.testing.assert_allclose(p[p > 1e-6], np.linalg.norm(T), rtol=1e-6)


def _random_scene(rng):
    """1-6 boxes on a half-unit grid, sometimes a ground plate, sometimes turned about z."""
    bounds = []
    for _ in range(int(rng.integers(1, 7))):
        lo = rng.integers(0, 5, size=3) * (0.5 if rng.random() < 0.5 else 1.0)
        size = rng.integers(1, 4, size=3).astype(float)
        bounds.append(tuple(np.ravel(np.stack([lo, lo + size], axis=1))))
    if rng.random() < 0.3:
        bounds.append((-2, 8, -2, 8, -0.3, 0))
    V, F = blocks(bounds)
    if rng.random() < 0.3:
        a = np.radians(rng.uniform(0, 90))
        V = V @ np.array([[np.cos(a), np.sin(a), 0], [-np.sin(a), np.cos(a), 0], [0, 0, 1]])
    return V, F


def test_random_block_scenes_give_a_mescher_or_one_error():
    """120 random scenes of blocks, each from ``view="auto"`` or a random or isometric view: a
    mescher whose edge values close on every triangle, or a MescherError -- never another
    exception."""
    rng = np.random.default_rng(7)
    done = 0
    for _ in range(120):
        V, F = _random_scene(rng)
        r = rng.random()
        if r < 0.25:
            view = "auto"
        else:
            view = rng.normal(size=3)
            view = np.sign(view) / np.sqrt(3.0) if r < 0.6 else view / np.linalg.norm(view)
        up = (0, 0, 1) if isinstance(view, str) or abs(view[2]) < 0.99 else (0, 1, 0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m, _, _ = model_to_mescher(V, F, view=view, up=up)
            except MescherError:
                continue
        s = m.d12 @ np.asarray(m.zeta)  # zeta sums to zero round every triangle
        assert np.abs(s).max() <= 1e-9 * max(1.0, float(np.abs(m.zeta).max()))
        done += 1
    assert done >= 60
