"""The painter's-algorithm oracle: hand-sized pictures with known answers."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from meschers_igl import DepthOrder, MescherError
from meschers_igl.painter import backface_share, pixel_grid, visible_faces


def _soup(*tris):
    xy = np.concatenate([np.asarray(t, dtype=float) for t in tris])
    F = np.arange(len(xy)).reshape(-1, 3)
    return SimpleNamespace(F=F, xy=xy)


BOX = (0.0, 4.0, 0.0, 4.0)  # 4x4 pixels of unit size: centres at 0.5, 1.5, 2.5, 3.5


def test_pixel_grid_centres_and_rows_top_down():
    c, b, shape = pixel_grid(np.zeros((1, 2)), size=4, bounds=BOX)
    assert shape == (4, 4) and b == BOX
    assert c[0, 0].tolist() == [0.5, 3.5] and c[3, 3].tolist() == [3.5, 0.5]


def test_square_pixel_count_and_background():
    # the lower-left triangle of the 4x4 box covers centres with x + y <= 4: 10 of 16
    m = _soup([(0, 0), (4, 0), (0, 4)])
    faces = visible_faces(m, size=4, bounds=BOX)
    assert (faces == 0).sum() == 10 and (faces == -1).sum() == 6
    xs, ys = pixel_grid(m.xy, 4, BOX)[0].reshape(-1, 2).T
    assert np.array_equal((faces.ravel() == 0), xs + ys <= 4)


def test_order_decides_which_face_is_seen():
    big = [(0, 0), (4, 0), (4, 4)]  # counter-clockwise
    small = [(2, 0.2), (3.9, 0.2), (3.9, 2)]
    m = _soup(big, small)
    front_small = visible_faces(m, DepthOrder(2, [(0, 1)]), size=4, bounds=BOX)
    front_big = visible_faces(m, DepthOrder(2, [(1, 0)]), size=4, bounds=BOX)
    assert (front_small == 1).sum() > 0 and (front_big == 1).sum() == 0
    assert ((front_small >= 0) == (front_big >= 0)).all()


def test_backface_share_counts_clockwise_faces():
    ccw = [(0, 0), (4, 0), (0, 4)]  # 10 pixels
    cw = [(4, 4), (4, 0.1), (0.1, 4)]  # clockwise: centres with x + y > 4.1 -> 6 pixels
    m = _soup(ccw, cw)
    assert backface_share(m, DepthOrder(2, [(1, 0)]), size=4, bounds=BOX) == pytest.approx(6 / 16)
    # the clockwise face hidden behind a covering front face shows nothing
    cover = [(-1, -1), (9, -1), (-1, 9)]
    m2 = _soup(cw, cover)
    assert backface_share(m2, DepthOrder(2, [(0, 1)]), size=4, bounds=BOX) == 0.0


def test_barycentric_reproduces_the_pixel_centres():
    rng = np.random.default_rng(0)
    m = _soup(*(rng.uniform(0, 4, (3, 2)) for _ in range(6)))
    faces, bary = visible_faces(m, size=16, bounds=BOX, return_barycentric=True)
    hit = faces >= 0
    centres = pixel_grid(m.xy, 16, BOX)[0][hit]
    rebuilt = np.einsum("pk,pkd->pd", bary[hit], m.xy[m.F[faces[hit]]])
    assert np.allclose(rebuilt, centres, atol=1e-12)
    assert np.all(bary[hit] >= -1e-12) and np.isnan(bary[~hit]).all()


def test_degenerate_faces_cover_nothing_and_bad_input_is_named():
    m = _soup([(0, 0), (2, 2), (4, 4)])
    assert (visible_faces(m, size=4, bounds=BOX) == -1).all()
    with pytest.raises(MescherError, match="bounds"):
        visible_faces(m, size=4, bounds=(1, 0, 0, 1))
    with pytest.raises(MescherError, match="size"):
        visible_faces(m, size=0)
    with pytest.raises(MescherError, match="order"):
        visible_faces(m, DepthOrder(3), size=4, bounds=BOX)
