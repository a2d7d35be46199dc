"""A face's thin tip crossing a pixel corner between two faces' tips (a 2 x 2 checkerboard of
labels whose four pixels are tips) is made whole before the pieces are lifted
(regions._tips_through_corners); two regions' corners meeting are left apart."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse.regions import _tips_through_corners, region_polygons


def _own(L: np.ndarray) -> np.ndarray:
    """4-neighbours of each pixel's own label."""
    P = np.pad(L, 1, constant_values=-99)
    return sum(
        (P[1 + dy : P.shape[0] - 1 + dy, 1 + dx : P.shape[1] - 1 + dx] == L)
        for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))
    )


def _four_tip_blocks(L: np.ndarray) -> int:
    t = _own(L) <= 1
    a, b, c, d = L[:-1, :-1], L[:-1, 1:], L[1:, :-1], L[1:, 1:]
    four = (a == d) & (b == c) & (a != b) & t[:-1, :-1] & t[:-1, 1:] & t[1:, :-1] & t[1:, 1:]
    return int(np.count_nonzero(four))


# A dark wedge (0) narrowing down between two light faces (1), as the antialiased box cube
# shows it: its tip crosses a pixel corner at rows 1-2, columns 2-3, and the light faces'
# tips cross it the other way, onto the dark face below.
WEDGE = np.array(
    [
        [1, 1, 0, 0, 0, 1, 1],
        [1, 1, 1, 0, 1, 1, 1],
        [1, 1, 0, 1, 1, 1, 1],
        [0, 0, 0, 0, 0, 0, 0],
    ]
)


def test_a_wedges_tip_through_a_corner_is_made_whole():
    """The block at rows 1-2, columns 2-3 has four tips: its top right pixel takes the main
    diagonal's label (the light), and nothing else changes."""
    assert _four_tip_blocks(WEDGE) == 1
    out = _tips_through_corners(WEDGE)
    assert _four_tip_blocks(out) == 0
    assert np.argwhere(out != WEDGE).tolist() == [[1, 3]] and out[1, 3] == 1


def test_two_regions_corners_meeting_are_left_apart():
    """Two squares of one label touching at a corner across two of another (each block pixel
    with two neighbours of its own label): four faces, and the point keeps them apart."""
    L = np.zeros((16, 16), dtype=np.int64)
    L[:8, :8] = 1
    L[8:, 8:] = 1
    assert np.array_equal(_tips_through_corners(L), L)
    assert len(region_polygons(L, corners=True)[0]) == 4


def test_every_block_is_made_whole_when_asked():
    """``every=True``: the squares' corners are joined along the main diagonal (one pixel
    changes: the top right of the block), and no checkerboard is left."""
    L = np.zeros((16, 16), dtype=np.int64)
    L[:8, :8] = 1
    L[8:, 8:] = 1
    out = _tips_through_corners(L, every=True)
    assert np.argwhere(out != L).tolist() == [[7, 8]] and out[7, 8] == 1
    a, b, c, d = out[:-1, :-1], out[:-1, 1:], out[1:, :-1], out[1:, 1:]
    assert not np.any((a == d) & (b == c) & (a != b))


def test_the_light_faces_become_one_piece_through_the_corner():
    """The wedge on the ground, as polygons: as the pixels are, two light and two dark
    pieces meet at the corner; made whole, the light faces are one piece through it and
    the dark ones stay two."""
    L = np.pad(WEDGE, ((0, 3), (0, 0)), constant_values=-1)  # square, ground below
    raw, raw_region, _ = region_polygons(L)
    whole, region, _ = region_polygons(L, corners=True)
    assert sorted(raw_region.tolist()) == [0, 0, 1, 1]
    assert sorted(region.tolist()) == [0, 0, 1]
    light = [p for p, k in zip(whole, region) if k == 1][0]
    assert light.area > sum(p.area for p, k in zip(raw, raw_region) if k == 1)  # and the pixel


@pytest.mark.parametrize("seed", range(5))
def test_no_four_tip_block_is_left_and_few_pixels_change(seed):
    """Random labels (three, and the background): no four-tip block is left, and no more
    pixels change than there were such blocks at first, or made by a change."""
    rng = np.random.default_rng(seed)
    L = rng.integers(-1, 3, size=(24, 24))
    n = _four_tip_blocks(L)
    assert n > 0
    out = _tips_through_corners(L, passes=64)
    assert _four_tip_blocks(out) == 0
    assert 0 < np.count_nonzero(out != L) <= 4 * n


@pytest.mark.render
@pytest.mark.parametrize("k", [0, 1, 3])
def test_the_antialiased_box_cube_climbs_its_gap(bench, k):
    """The box cube averaged down from 4x (a renderer's antialiasing): under these lights a
    bar's dark tip crosses a pixel corner between two faces of one light shade, and the
    start's climb was gone (period -99%); now within 5%."""
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.models import impossible_cube
    from meschers_igl.inverse.picture import mescher_from_picture

    pytest.importorskip("pyvista")
    model = impossible_cube()
    light = bench.hemisphere_lights(6, 0)[k]
    img, scale = bench.published_picture(model, 128, light, "antialiased")
    m, _, _ = mescher_from_picture(img, light, bench.AMBIENT, background=bench.GROUND)
    assert figure_period(m) == pytest.approx(model.gap * scale, rel=0.05)
