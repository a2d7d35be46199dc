"""``meschers inverse``'s figure: every panel at least FIGURE_PIXELS wide, the renders drawn at
that size (not a small render enlarged), the target enlarged by whole pixels only, labelled."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("torch")

from meschers.inverse_cli import FIGURE_PIXELS, enlarge_nearest, figure_panels  # noqa: E402


def test_enlarge_nearest_repeats_each_pixel_as_a_block():
    rng = np.random.default_rng(0)
    image = rng.random((40, 40, 3))
    big, k = enlarge_nearest(image, 256)
    assert k == 7 and big.shape == (280, 280, 3)  # least whole factor: 6 * 40 = 240 < 256
    blocks = big.reshape(40, 7, 40, 7, 3)
    np.testing.assert_array_equal(blocks, np.broadcast_to(image[:, None, :, None], blocks.shape))
    same, k1 = enlarge_nearest(image, 40)
    assert k1 == 1 and same is image


def test_figure_panels_render_the_meschers_at_the_figure_size():
    from types import SimpleNamespace

    from meschers_igl.inverse import penrose_target, torus_for_target
    from meschers_igl.inverse.rasterizer import render_mescher

    lights = [(0.4, 0.25, 1.0)]
    target = penrose_target(32, lights=lights)
    m0, off0 = torus_for_target(target, np.ones(3), n_major=24, n_minor=8)
    shade = {"lights": lights, "light_colors": None, "ambient": 0.2}
    result = SimpleNamespace(mescher=m0, offsets=off0)  # the figure does not care what moved
    panels, titles = figure_panels(target, m0, off0, result, np.ones(3), shade, "torus")
    assert all(p.shape == (256, 256, 3) for p in panels) and FIGURE_PIXELS == 256
    assert titles[0] == "target (32 px, shown 8x, nearest)" and "256 px" in titles[2]
    np.testing.assert_array_equal(panels[0], enlarge_nearest(target, 256)[0])
    small = render_mescher(m0, off0, resolution=32, background=np.ones(3), sigma=1e-6, **shade)
    # a render at 256, not the 32-pixel one enlarged: not constant on the 8 x 8 blocks ...
    blocks = panels[2].reshape(32, 8, 32, 8, 3)
    assert (blocks.max(axis=(1, 3)) - blocks.min(axis=(1, 3))).max() > 0.1
    # ... and the same picture: averaged over the blocks, the 32-pixel render up to its edges
    mean = blocks.mean(axis=(1, 3))
    assert np.median(np.abs(mean - small)) < 1e-6
    assert np.mean(np.abs(mean - small).max(axis=-1) > 0.05) < 0.2
