"""Loop subdivision keeps separate blocks overlapping on screen as they did: Reutersvard's cubes
stay cubes.

The measure is independent of the painter: each connected block's screen region is the union of
its projected triangles (shapely), and the overlap of two blocks is the area of the intersection
of their regions.  Loop with the crease rules (Hoppe et al. 1994) keeps every block a box, so
every pairwise overlap stays (up to round-off); plain Loop shrinks each block toward its centre
and the overlaps all but vanish (the test can fail).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import shapely
from scipy.sparse.csgraph import connected_components

from meschers_igl.gallery import get_model


def block_regions(m) -> list:
    """One shapely region per connected block of ``m``: the union of its screen triangles."""
    F, xy = np.asarray(m.F), np.asarray(m.xy)
    nv = xy.shape[0]
    a, b = F.reshape(-1), np.roll(F, -1, axis=1).reshape(-1)
    n, label = connected_components(
        sp.coo_matrix((np.ones(a.size), (a, b)), shape=(nv, nv)), directed=False
    )
    tris = shapely.polygons(xy[F])
    keep = shapely.area(tris) > 1e-12 * np.ptp(xy, axis=0).prod()  # edge-on faces cover nothing
    return [shapely.union_all(tris[keep & (label[F[:, 0]] == c)]) for c in range(n)]


def pairwise_overlaps(m) -> np.ndarray:
    """(n, n) areas of the screen intersection of every two blocks (0 on the diagonal)."""
    regions = block_regions(m)
    n = len(regions)
    out = np.zeros((n, n))
    for i in range(n):
        for j in range(i + 1, n):
            out[i, j] = out[j, i] = regions[i].intersection(regions[j]).area
    return out


@pytest.fixture(scope="module")
def reutersvard():
    g = get_model("reutersvard_triangle")
    return g.mescher, g.order, pairwise_overlaps(g.mescher)


@pytest.mark.parametrize("levels", [1, 2])
def test_loop_keeps_every_overlap_between_reutersvards_cubes(reutersvard, levels):
    m, order, before = reutersvard
    assert before.shape[0] == 9  # nine separate cubes
    pairs = before > 1e-9 * before.max()
    assert pairs.sum() >= 2 * 9  # each cube overlaps its neighbours on screen
    c, _ = m.subdivide(levels, "loop", order=order)
    after = pairwise_overlaps(c)
    assert after.shape == before.shape  # subdivision splits faces, never blocks
    ratio = after[pairs] / before[pairs]
    np.testing.assert_allclose(ratio, 1.0, atol=0.03)
    # no new overlap between cubes that did not overlap
    assert after[~pairs].max(initial=0.0) <= 1e-9 * before.max()


@pytest.mark.parametrize("levels", [1, 2])
def test_plain_loop_shrinks_the_cubes_apart(reutersvard, levels):
    """The measure sees the blobs: plain Loop (every edge smooth) loses most of each overlap."""
    m, order, before = reutersvard
    c, _ = m.subdivide(levels, "loop-smooth", order=order)
    after = pairwise_overlaps(c)
    pairs = before > 1e-9 * before.max()
    assert (after[pairs] / before[pairs]).max() < 0.5
