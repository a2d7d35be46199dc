"""The study's figure helpers: numbers printed honestly, labels that never overlap, colour bars."""

from __future__ import annotations

import numpy as np
import pytest

from meschers.figures import (
    Colorbar,
    compose,
    format_value,
    format_values,
    overlay,
    png_bytes,
    screen_to_pixel,
)
from pyvista_views.overlays import place_labels


def test_round_off_prints_as_zero():
    # the impossible cube's periods: round-off next to a real period
    assert format_value(1.78e-15, scale=15.92) == "0"
    assert format_value(-3e-9, scale=1.0) == "-3e-09"  # above 1e-9 of the scale: a value
    assert format_value(0.0) == "0" and format_value(6.928203) == "6.928"
    assert format_values([15.92, -1.78e-15, 0.0, -15.92]) == "15.92, 0, 0, -15.92"
    assert format_values([]) == "none"


def _boxes(corners, sizes):
    return [(x, y, x + w, y + h) for (x, y), (w, h) in zip(corners, sizes)]


def test_labels_on_one_spot_do_not_overlap():
    anchors = np.full((6, 2), 100.0)  # six loops whose midpoints coincide
    sizes = [(40, 12)] * 6
    boxes = _boxes(place_labels(anchors, sizes, (300, 300)), sizes)
    for i, a in enumerate(boxes):
        assert 0 <= a[0] and a[2] <= 300 and 0 <= a[1] and a[3] <= 300  # inside the image
        for b in boxes[:i]:
            overlap = min(a[2], b[2]) - max(a[0], b[0]), min(a[3], b[3]) - max(a[1], b[1])
            assert overlap[0] <= 0 or overlap[1] <= 0, f"{a} overlaps {b}"


def test_overlay_draws_every_label_apart():
    img = np.full((120, 120, 3), 255, np.uint8)
    bounds = (0.0, 1.0, 0.0, 1.0)
    labels = [((0.5, 0.5), f"p{k}=0", "#d62728") for k in range(4)]
    out = overlay(img, bounds, labels=labels)
    red = (out[..., 0] > 150) & (out[..., 1] < 100)
    # four separate text blobs: columns/rows with red ink split into separated groups
    from scipy import ndimage

    _, n = ndimage.label(ndimage.binary_dilation(red, iterations=1))
    assert n >= 4


def test_screen_to_pixel_maps_bounds_to_image_corners():
    bounds = (-1.0, 3.0, 0.0, 2.0)
    P = np.array([[-1.0, 2.0], [3.0, 0.0], [1.0, 1.0]])
    np.testing.assert_allclose(
        screen_to_pixel(P, bounds, (200, 100)), [[0, 0], [200, 100], [100, 50]]
    )


def test_compose_layout_and_colorbar():
    cells = [[np.zeros((10, 12, 3), np.uint8)] * 3] * 2
    img = compose(cells, ["a", "b", "c"], ["r1", "r2"], [["x"] * 3] * 2)
    assert img.size == (92 + 3 * 12, 20 + 2 * (10 + 18))
    assert compose(cells).size == (36, 20)
    bar = Colorbar("viridis", 0.0, 2.0, "distance")
    tall = [[np.zeros((120, 100, 3), np.uint8)]]
    img = np.asarray(compose(tall, colorbar=bar))
    assert img.shape == (120, 100 + Colorbar.width, 3)
    strip = img[30:108, 100 + 12]  # the colour strip, top (vmax) to bottom (vmin)
    from matplotlib import colormaps

    top, bottom = (255 * np.asarray(colormaps["viridis"]([1.0, 0.0]))[:, :3]).astype(int)
    assert np.abs(strip[1].astype(int) - top).max() <= 8
    assert np.abs(strip[-1].astype(int) - bottom).max() <= 8


def test_png_bytes_round_trip():
    from io import BytesIO

    from PIL import Image

    a = np.random.default_rng(0).integers(0, 255, (7, 9, 3), dtype=np.uint8)
    b = np.asarray(Image.open(BytesIO(png_bytes(a))).convert("RGB"))
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("n", [1, 2, 9])
def test_long_labels_are_shortened_to_their_panel(n):
    from PIL import Image, ImageDraw

    from meschers.figures import fit_text, font

    draw = ImageDraw.Draw(Image.new("RGB", (10, 10)))
    text = fit_text(draw, "light 1 (1.0, 1.0, 1.0) " * n, font(), 120)
    assert draw.textlength(text, font=font()) <= 120


def test_heat_panels_are_at_most_5_percent_black():
    """The study's heat panel (log scale, its colour map, shading floor): at most 5% of the
    figure black (max channel < 40); with inferno (black end) the same panel is mostly black."""
    pytest.importorskip("pyvista")
    from pyvista_views import render
    from pyvista_views.headless import gl_available

    if not gl_available():
        pytest.skip("no offscreen OpenGL context")
    from meschers.settings import HEAT_CMAP
    from meschers.steps import HEAT_LOG_MIN
    from meschers_igl.gallery import get_model

    g = get_model("penrose_triangle")
    m, order = g.mescher.subdivide(1, order=g.order)
    s = float(np.linalg.norm(np.ptp(np.asarray(m.xy), axis=0)))
    u0 = np.zeros(m.n_vertices)
    u0[0] = 1.0
    u = m.heat_diffuse(u0, 1e-3 * s * s)
    v = np.log10(np.maximum(u / u.max(), 10.0**HEAT_LOG_MIN))
    kw = dict(
        shading="smooth",
        scalars=v,
        clim=(HEAT_LOG_MIN, 0.0),
        window_size=(192, 192),
        scalar_bar=False,
    )

    def black_share(img):
        figure = np.any(img != 255, axis=-1)
        return float((img.max(axis=-1) < 40)[figure].mean())

    assert black_share(render(m, order, cmap=HEAT_CMAP, **kw)) <= 0.05
    assert black_share(render(m, order, cmap="inferno", **kw)) > 0.2


def test_compose_leaves_no_empty_band_between_rows():
    """A wide figure in square panels: the white rows common to every panel are cut (6 px
    kept either side), the same rows from each panel."""
    from pyvista_views.compare import trim_rows

    a = np.full((200, 120, 3), 255, np.uint8)
    a[80:120, 10:110] = 90  # a wide figure in the middle
    b = a.copy()
    b[70:75, 50:60] = 0  # reaches 10 rows higher
    ((ta, tb),) = trim_rows([[a, b]])
    assert ta.shape == tb.shape == (120 - 70 + 12, 120, 3)
    np.testing.assert_array_equal(ta, a[64:126])
    assert trim_rows([[a]], min_height=160)[0][0].shape[0] == 160
    fig = np.asarray(compose([[a, b], [a, b]], row_labels=["one", "a much longer label"]))
    white_run = 0
    longest = 0
    for row in (fig < 250).any(axis=(1, 2)):
        white_run = 0 if row else white_run + 1
        longest = max(longest, white_run)
    assert longest <= 2 * 6 + 18  # the padding of two panels and a notes line at most


def test_colour_bar_middle_of_a_nearly_symmetric_range_is_labelled_0():
    """(-0.593, 0.5929): the middle tick is -5e-05, 1/20000 of the span: a 0, not '-5e-05'."""
    from PIL import ImageDraw

    labels = []
    original = ImageDraw.ImageDraw.text

    def spy(self, xy, text, *a, **k):
        labels.append(text)
        return original(self, xy, text, *a, **k)

    ImageDraw.ImageDraw.text = spy
    try:
        Colorbar("coolwarm", -0.593, 0.5929, "z").draw(200)
    finally:
        ImageDraw.ImageDraw.text = original
    assert "0" in labels and not any("e-05" in t for t in labels)
