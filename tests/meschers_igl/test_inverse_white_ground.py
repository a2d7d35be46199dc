"""A face lit almost as light as a white ground is the figure's (flatten.figure_mask)."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse.flatten import figure_mask


@pytest.mark.render
@pytest.mark.parametrize(
    "light, level",
    [((-0.166, 0.778, 0.606), 252), ((0.529, -0.645, 0.551), 246), ((-0.823, -0.182, 0.539), 248)],
)
def test_a_face_nearly_as_light_as_a_white_ground_is_read(light, level):
    """The tribar on white under lights that shade one orientation 3-9 levels under white
    (within the 13 levels the ground's colour test allows): before, that face was ground,
    the picture read as two shades and refused or read 12% long; now its period within 5%."""
    import os

    pytest.importorskip("pyvista")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse import models
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture

    model = models.penrose_tribar()
    light = np.asarray(light) / np.linalg.norm(light)
    img, scale = zbuffer_picture(model, 128, light=light, ambient=0.2, background=(1, 1, 1))
    grey = np.round(img.mean(axis=-1) * 255.0)
    assert np.any(grey == level)  # the nearly white face is in the picture
    assert np.array_equal(figure_mask(img), grey < 255)
    m, _, _ = mescher_from_picture(img, light, 0.2, background=(1, 1, 1))
    assert figure_period(m) == pytest.approx(model.gap * scale, rel=0.05)


def test_a_ground_of_close_colours_on_the_border_is_all_ground():
    """A ground in two tones (a backdrop's fold) a few levels apart, both reaching the
    picture's border, is ground; a square as light as the lighter tone is not."""
    t = np.ones((64, 64, 3))
    t[32:] = 250 / 255.0
    t[20:44, 20:44] = 0.4
    t[26:38, 26:38] = 252 / 255.0  # a near-white face inside the figure
    fig = figure_mask(t)
    expected = np.zeros((64, 64), dtype=bool)
    expected[20:44, 20:44] = True
    assert np.array_equal(fig, expected)


def test_a_figure_over_the_whole_border_leaves_the_ground_to_colour():
    """No ground on the picture's border (a figure that fills it): the ground is every colour
    near the background's, as the colour test alone says."""
    t = np.full((32, 32, 3), 0.4)
    t[8:24, 8:24] = 1.0  # a white hole in a grey figure
    t[12:20, 12:20] = 252 / 255.0
    fig = figure_mask(t)
    assert not fig[8:24, 8:24].any() and fig[:8].all()
