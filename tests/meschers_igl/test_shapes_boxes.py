"""Boxes and block grids: closed, outward, the volumes and the layout asked for."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import MescherError, shapes


def _volume(V, F):
    # divergence theorem: sum over faces of det(v0, v1, v2) / 6 (positive when outward)
    return np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6.0


def test_each_box_is_a_closed_outward_solid_of_its_volume():
    lo = np.array([[0.0, 0.0, 0.0], [5.0, -1.0, 2.0], [-3.0, 4.0, 0.5]])
    hi = lo + np.array([[1.0, 2.0, 3.0], [0.5, 0.5, 4.0], [2.0, 1.0, 1.0]])
    V, F = shapes.boxes(lo, hi)
    assert V.shape == (24, 3) and F.shape == (36, 3)
    for k in range(3):
        Fk = F[12 * k : 12 * (k + 1)]
        assert Fk.min() == 8 * k and Fk.max() == 8 * k + 7  # separate parts
        # closed and consistently oriented: every directed edge once, its reverse once
        he = np.concatenate([Fk[:, [0, 1]], Fk[:, [1, 2]], Fk[:, [2, 0]]])
        keys = set(map(tuple, he))
        assert len(keys) == 36 and all((b, a) in keys for a, b in keys)
        assert _volume(V, Fk) == pytest.approx(np.prod(hi[k] - lo[k]), rel=1e-12)
        assert np.allclose(V[8 * k : 8 * k + 8].min(0), lo[k])
        assert np.allclose(V[8 * k : 8 * k + 8].max(0), hi[k])


def test_block_grid_layout_heights_and_ground():
    n = 3
    heights = np.arange(n * n) + 1.0
    V, F = shapes.block_grid(n, heights=heights)
    assert F.shape == (12 * n * n, 3)
    vols = [_volume(V, F[12 * k : 12 * (k + 1)]) for k in range(n * n)]
    assert np.allclose(vols, 4.0 * heights)  # 2 x 2 footprints
    assert np.allclose(V[:, :2].min(0), 0.0) and np.allclose(V[:, :2].max(0), 3.0 * n - 1.0)
    Vg, Fg = shapes.block_grid(n, ground=10.0)
    assert Fg.shape[0] == F.shape[0] + 2 and Vg.shape[0] == V.shape[0] + 4
    c = 1.5 * n - 0.5
    assert np.allclose(Vg[-4:, :2].min(0), c - 10.0) and np.allclose(Vg[-4:, 2], 0.0)


def test_bad_boxes_are_refused():
    with pytest.raises(MescherError, match="lo, hi"):
        shapes.boxes([[0, 0, 0]], [[1, 0, 1]])
    with pytest.raises(MescherError, match="heights"):
        shapes.block_grid(2, heights=[1.0, 2.0])
