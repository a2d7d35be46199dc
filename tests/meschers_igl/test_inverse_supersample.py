"""An antialiased picture is compared with a render that averages samples over each pixel
(``InverseOptions.supersample``), as its renderer made it."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError
from meschers_igl.inverse.optimize import InverseOptions, fit_mescher


def _square(res: int):
    """A square facing the viewer whose left edge is a quarter pixel into a pixel column and
    whose top edge three quarters into a pixel row; the others on pixel boundaries."""
    px = 2.0 / res
    x0, x1, y0, y1 = -0.5 + 0.25 * px, 0.5, -0.5, 0.5 - 0.75 * px
    V = np.array([[x0, y0, 0], [x1, y0, 0], [x1, y1, 0], [x0, y1, 0]], float)
    return Mescher.from_mesh(V, np.array([[0, 1, 2], [0, 2, 3]])), (x1 - x0) * (y1 - y0)


def _render(m, res: int, k: int):
    opt = InverseOptions(iters=0, supersample=k, final_sigma=1e-7)
    black = np.zeros((res, res, 3))
    return fit_mescher(black, m, None, lights=[(0, 0, 1)], background=(0, 0, 0), options=opt)


def test_supersampled_coverage_is_each_pixels_share_of_the_face():
    """4 x 4 samples per pixel: the column the left edge cuts a quarter into is 3/4 covered,
    the row the top edge leaves a quarter of is 1/4, their corner 3/16; the covered area is
    the square's, exactly (its edges fall between samples).  One sample: 0 or 1."""
    res = 16
    m, area = _square(res)
    px = 2.0 / res
    one, four = _render(m, res, 1), _render(m, res, 4)
    assert set(np.unique(one.alpha)) == {0.0, 1.0}
    a = four.alpha
    col, row = 4, 4  # the pixel column holding x0, the pixel row holding y1 (row 0 on top)
    np.testing.assert_allclose(a[row + 1 : 12, col], 0.75, atol=1e-9)
    np.testing.assert_allclose(a[row, col + 1 : 12], 0.25, atol=1e-9)
    assert a[row, col] == pytest.approx(0.75 * 0.25, abs=1e-9)
    assert a.sum() * px * px == pytest.approx(area, abs=1e-9)
    # white face (light head-on, full diffuse) on black: the image is the coverage
    np.testing.assert_allclose(four.image[..., 0], a, atol=1e-9)


@pytest.mark.parametrize("k", [0, 9, 2.5, True])
def test_a_supersample_that_is_not_a_small_count_is_refused(k):
    m, _ = _square(8)
    with pytest.raises(MescherError, match="supersample"):
        _render(m, 8, k)


@pytest.mark.render
def test_an_antialiased_picture_is_fitted_and_measured_against_an_antialiased_render():
    """The tribar rendered at 512 px and averaged to 128 (a renderer's supersampling): the
    reading says it is antialiased, ``fit_options`` then averages 4 x 4 samples per pixel,
    and the fit's render is nearer the picture than one sampled at pixel centres.  A flat
    picture and a JPEG (a picture sampled at pixel centres, then compressed) are fitted with
    one sample per pixel."""
    import os

    pytest.importorskip("pyvista")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from dataclasses import replace

    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse import models
    from meschers_igl.inverse.metrics import image_psnr
    from meschers_igl.inverse.picture import fit_options, mescher_from_picture

    model = models.penrose_tribar()
    light = np.array([0.3, 0.5, 1.0]) / np.linalg.norm([0.3, 0.5, 1.0])
    ground = (0.55, 0.7, 0.9)
    big, _ = zbuffer_picture(model, 512, light=light, ambient=0.2, background=ground)
    picture = big.reshape(128, 4, 128, 4, 3).mean(axis=(1, 3))
    m0, region, info = mescher_from_picture(picture, light, 0.2, background=ground)
    assert info["flattened"] and info["antialiased"]
    opt = fit_options(iters=60, info=info)
    assert opt.supersample == 4
    psnr = {}
    for k in (1, 4):
        r = fit_mescher(
            picture,
            m0,
            None,
            lights=[light],
            ambient=0.2,
            background=ground,
            options=replace(opt, supersample=k),
            face_normals=info["normals"][region],
        )
        psnr[k] = image_psnr(r.image, picture)
    assert psnr[4] > 30.0
    assert psnr[4] > psnr[1] + 3.0  # measured 39.1 and 33.7 dB
    flat = zbuffer_picture(model, 128, light=light, ambient=0.2, background=ground)[0]
    info = mescher_from_picture(flat, light, 0.2, background=ground)[2]
    assert not info["flattened"] and fit_options(iters=60, info=info).supersample == 1
    info = mescher_from_picture(_jpeg(flat, 90), light, 0.2, background=ground)[2]
    assert info["flattened"] and not info["antialiased"]
    assert fit_options(iters=60, info=info).supersample == 1


def _jpeg(a: np.ndarray, quality: int) -> np.ndarray:
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray((a * 255.0).round().astype(np.uint8)).save(buf, "JPEG", quality=quality)
    buf.seek(0)
    return np.asarray(Image.open(buf).convert("RGB"), dtype=np.float64) / 255.0
