"""Antialiased and JPEG pictures made flat again before they are read (flatten_picture)."""

from __future__ import annotations

import io

import numpy as np
import pytest

from meschers_igl import MescherError
from meschers_igl.inverse.flatten import flatten_picture, is_antialiased, is_flat, noise_radius

GROUND = (140, 178, 230)


def _cube_corner(size: int, greys=(80, 150, 220), ss: int = 1) -> np.ndarray:
    """(size, size, 3) uint8: three rhombi of a box's corner in ``greys`` on a blue ground,
    drawn ``ss`` times larger and averaged over ``ss x ss`` blocks (``ss = 1``: flat)."""
    from PIL import Image, ImageDraw

    n = size * ss
    c = np.array([0.5, 0.52]) * n
    r = 0.36 * n
    corner = [c + r * np.array([np.cos(a), np.sin(a)]) for a in np.radians(np.arange(6) * 60 + 30)]
    im = Image.new("RGB", (n, n), GROUND)
    d = ImageDraw.Draw(im)
    for k, g in enumerate(greys):  # rhombus k: the centre and three consecutive corners
        pts = [
            tuple(c),
            tuple(corner[2 * k]),
            tuple(corner[2 * k + 1]),
            tuple(corner[2 * k + 2 - 6 * (k == 2)]),
        ]
        d.polygon(pts, fill=(g, g, g))
    a = np.asarray(im, dtype=np.float64)
    return a.reshape(size, ss, size, ss, 3).mean(axis=(1, 3)).round().astype(np.uint8)


def _jpeg(a: np.ndarray, quality: int) -> np.ndarray:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(a).save(buf, "JPEG", quality=quality)
    buf.seek(0)
    return np.asarray(Image.open(buf).convert("RGB"))


def _colours(a: np.ndarray) -> np.ndarray:
    return np.unique(np.round(a.reshape(-1, 3)).astype(int), axis=0)


@pytest.mark.parametrize("size", [128, 256, 512])
def test_a_flat_picture_is_flat_an_antialiased_or_jpeg_one_is_not(size):
    """At 256 and 512 px the blends are under half a percent of the pixels and repeat along
    the straight edges (shared by 16 pixels and more): they are told by being one pixel wide."""
    flat = _cube_corner(size)
    assert len(_colours(flat)) == 4 and is_flat(flat / 255.0)
    blended = _cube_corner(size, ss=4) / 255.0
    assert not is_flat(blended)
    if size == 512:  # the test can fail: the colour counts alone call it flat
        assert is_flat(blended, max_thin=1.0)
    assert not is_flat(_jpeg(flat, 90) / 255.0)


@pytest.mark.parametrize("quality", [75, 90, 95])
def test_antialiasing_is_told_from_jpeg_noise(quality):
    """Averaged samples blend only the edges; a JPEG is noisy inside its faces too, and so is
    a JPEG of an antialiased picture.  A flat picture is neither."""
    flat, blended = _cube_corner(128), _cube_corner(128, ss=4)
    assert is_antialiased(blended / 255.0) and not is_antialiased(flat / 255.0)
    assert not is_antialiased(_jpeg(flat, quality) / 255.0)
    assert not is_antialiased(_jpeg(blended, quality) / 255.0)


def test_an_antialiased_picture_is_made_flat():
    """Averaged over 4 x 4 samples, the edge pixels blend the faces they cross (a blend of the
    dark and the light face is near the middle one's grey).  Restored: the four colours
    exactly, and every pixel the colour of the face over most of it (all but a few along
    the edges, where the split is near half)."""
    truth = _cube_corner(128, ss=4)
    blended = truth / 255.0
    flat = flatten_picture(blended)
    expected = _colours(np.array([GROUND, (80,) * 3, (150,) * 3, (220,) * 3]))
    assert np.array_equal(_colours(flat * 255.0), expected)
    # the colour of most of each pixel: its nearest of the four colours, where that is clear
    cols = np.array([GROUND, (80,) * 3, (150,) * 3, (220,) * 3], dtype=float)
    wrong = np.abs(flat * 255.0 - _majority(128, cols)).max(axis=-1) > 0.5
    assert wrong.mean() < 0.01


def _majority(size: int, cols: np.ndarray) -> np.ndarray:
    """The colour covering most of each pixel of the 4 x 4 supersampled corner."""
    fine = _cube_corner(size * 4).reshape(size, 4, size, 4, 3).transpose(0, 2, 1, 3, 4)
    fine = fine.reshape(size, size, 16, 3).astype(float)
    k = np.abs(fine[..., None, :] - cols[None, None, None]).max(axis=-1).argmin(axis=-1)
    votes = np.stack([(k == i).sum(axis=-1) for i in range(len(cols))], axis=-1)
    return cols[votes.argmax(axis=-1)]


def test_faces_three_levels_apart_stay_two_faces():
    """Without noise the radius is one and a half levels: an antialiased picture of two faces
    three grey levels apart (two bar faces under an ordinary light) keeps both."""
    blended = _cube_corner(128, greys=(80, 150, 153), ss=4) / 255.0
    assert noise_radius(blended) == pytest.approx(1.5 / 255.0)
    cols = _colours(flatten_picture(blended) * 255.0)
    assert len(cols) == 4 and {150, 153} <= set(cols[:, 0].tolist())


def test_jpeg_noise_is_made_flat():
    """JPEG at quality 90 leaves a few levels of noise on the faces and rings along their
    edges; restored, the four colours come back within a level and nearly every pixel has the
    flat picture's colour."""
    truth = _cube_corner(128)
    noisy = _jpeg(truth, 90) / 255.0
    assert 3.0 / 255.0 < noise_radius(noisy) <= 8.0 / 255.0
    flat = flatten_picture(noisy) * 255.0
    cols = _colours(flat)
    assert len(cols) == 4
    assert np.abs(cols - _colours(truth)).max() <= 1.5
    assert np.mean(np.abs(flat - truth).max(axis=-1) > 2.0) < 0.02


def test_a_picture_with_no_flat_colour_is_refused():
    rng = np.random.default_rng(0)
    with pytest.raises(MescherError, match="flat colours"):
        flatten_picture(rng.random((64, 64, 3)))
    with pytest.raises(MescherError, match=r"\(H, W, 3\)"):
        flatten_picture(np.zeros((8, 8)))


@pytest.mark.render
def test_an_antialiased_picture_of_the_tribar_reads_its_period():
    """A picture larger than the 128 pixels ``meschers inverse`` reads at is averaged down to
    them (box filter): its edges blend like an antialiased render's.  Made flat, the tribar's
    period comes within 5% (read as it was, the blends are thin faces of a third shade along
    every edge: +129% under this light)."""
    import os

    pytest.importorskip("pyvista")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse import models
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture

    model = models.penrose_tribar()
    light = np.array([0.189, -0.198, 0.962])  # lit from below: one face of each bar dark
    ground = np.asarray(GROUND) / 255.0
    big, scale = zbuffer_picture(model, 512, light=light, ambient=0.2, background=ground)
    picture = big.reshape(128, 4, 128, 4, 3).mean(axis=(1, 3))
    assert not is_flat(picture)
    m, _, _ = mescher_from_picture(picture, light, 0.2, background=ground)
    assert m.is_impossible()
    assert figure_period(m) == pytest.approx(model.gap * scale, rel=0.05)


def test_the_figure_of_an_antialiased_picture_is_where_most_of_a_pixel_is():
    """A pixel a face only tints is ground, as a renderer sampling pixel centres sees it:
    the figure mask of the antialiased corner is its majority-coverage mask, while the plain
    colour test takes every tinted pixel (the silhouette half a pixel out all round)."""
    from meschers_igl.inverse.flatten import figure_mask
    from meschers_igl.inverse.targets import target_mask

    cols = np.array([GROUND, (80,) * 3, (150,) * 3, (220,) * 3], dtype=float)
    most = np.abs(_majority(128, cols) - np.asarray(GROUND)).max(axis=-1) > 0
    blended = _cube_corner(128, ss=4) / 255.0
    ground = np.asarray(GROUND) / 255.0
    fig, tinted = figure_mask(blended, ground), target_mask(blended, ground)
    assert np.mean(fig != most) < 0.002
    assert (tinted & ~most).sum() > 10 * max((fig & ~most).sum(), 1)
    flat = _cube_corner(128) / 255.0
    assert np.array_equal(figure_mask(flat, ground), target_mask(flat, ground))


@pytest.mark.render
def test_the_cli_reads_a_larger_picture_it_averages_down(tmp_path):
    """``meschers inverse`` box-averages a 512 px picture to the 128 px it fits: the start is
    read from the flat picture and the silhouette measured as the renderer samples it."""
    import json
    import os

    pytest.importorskip("pyvista")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from PIL import Image

    from meschers.inverse_cli import inverse_main, zbuffer_picture
    from meschers_igl.inverse import models

    model = models.penrose_tribar()
    light = (0.3, 0.5, 1.0)
    big, scale = zbuffer_picture(model, 512, light=light, ambient=0.2)
    path = tmp_path / "tribar.png"
    Image.fromarray((big * 255).round().astype(np.uint8)).save(path)
    out = tmp_path / "fit"
    args = [str(path), "--out", str(out), "--light", "0.3,0.5,1", "--iters", "20"]
    assert inverse_main(args + ["--no-progress"]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["silhouette_iou"] > 0.98 and metrics["psnr_db"] > 30.0
    assert metrics["figure_period"] == pytest.approx(model.gap * scale, rel=0.05)


def _bars(n: int = 128, greys=(150, 171, 180)) -> np.ndarray:
    """(n, n, 3) uint8: a lattice of bars (two faces each way, one across) in light greys near
    the ground's brightness, on the blue ground: a long outline of low contrast."""
    from PIL import Image, ImageDraw

    im = Image.new("RGB", (n, n), GROUND)
    d = ImageDraw.Draw(im)
    for x in range(16, n - 16, 24):
        d.rectangle([x, 16, x + 5, n - 17], fill=(greys[0],) * 3)
        d.rectangle([x + 6, 16, x + 9, n - 17], fill=(greys[1],) * 3)
    for y in range(16, n - 16, 24):
        d.rectangle([16, y, n - 17, y + 4], fill=(greys[2],) * 3)
    return np.asarray(im)


@pytest.mark.parametrize("quality, most", [(75, 0.08), (90, 0.03)])
def test_jpeg_colour_bled_along_the_outline_is_ground_or_face(quality, most):
    """JPEG keeps colour at half resolution: along a long outline the ground's hue bleeds two
    pixels into light grey bars, a band of bluish grey wide enough to be a colour of its own
    (before: five colours, 16% / 8% of the figure's pixels off; now 6% / 1.4%).  Not a face: four
    colours, the figure's mask within ``most`` of its pixels."""
    from meschers_igl.inverse.targets import target_mask

    a = _bars()
    f = flatten_picture(_jpeg(a, quality) / 255.0)
    assert len(_colours(f * 255.0)) == 4
    g = np.asarray(GROUND) / 255.0
    truth = target_mask(a / 255.0, g)
    assert np.count_nonzero(target_mask(f, g) != truth) < most * truth.sum()
