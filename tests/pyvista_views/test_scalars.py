"""Scalar fields people can read: a shading floor, and +inf drawn as "unreached"."""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import luminance, requires_gl

from meschers_igl import MescherError
from meschers_igl.gallery import get_model
from pyvista_views import render
from pyvista_views.layers import SCALAR_AMBIENT
from pyvista_views.polydata import as_scalars

pytestmark = requires_gl


def test_a_constant_field_keeps_its_colour_within_the_shading_floor():
    """Every face of a one-colour field is drawn between the floor and the full colour (with
    the plain material's ambient 0.2 the faces turned away from the light go nearly black)."""
    g = get_model("penrose_triangle")
    m, order = g.mescher, g.order
    kw = dict(window_size=(200, 200), lights=[(1, 1, 1)], scalar_bar=False)
    v = np.full(m.n_vertices, 0.5)
    img = render(m, order, scalars=v, cmap="gray", clim=(0.0, 1.0), **kw)
    lum = luminance(img)
    figure = np.any(img != 255, axis=-1)
    full = 0.5 * 255  # gray at the middle of its range (sRGB as drawn: measured, not gamma)
    assert lum[figure].min() >= SCALAR_AMBIENT * 0.95 * lum[figure].max()
    assert lum[figure].max() <= full * 1.05 + 2
    dark = render(m, order, scalars=v, cmap="gray", clim=(0.0, 1.0), ambient=0.2, diffuse=0.8, **kw)
    assert luminance(dark)[figure].min() < 0.5 * lum[figure].min()


def test_inf_is_drawn_unreached_and_nan_refused():
    g = get_model("reutersvard_triangle")
    m, order = g.mescher, g.order
    d = m.geodesic_distance(0)
    assert np.isinf(d).any()
    img = render(m, order, scalars=d, window_size=(200, 200), lights=[(1, 1, 1)])
    figure = np.any(img != 255, axis=-1)
    grey = figure & (np.ptp(img.astype(int), axis=-1) <= 3) & (img[..., 0] > 100)
    # the unreached cubes (8 of 9) are grey, most of the figure
    assert grey.sum() > 0.5 * figure.sum()
    with pytest.raises(MescherError, match="non-finite"):
        as_scalars(np.where(np.isinf(d), np.nan, d), m.n_vertices, m.n_faces)
