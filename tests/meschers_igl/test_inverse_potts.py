"""JPEG's ragged edges smoothed by a Potts model (flatten._potts_smooth) that keeps the corners
of a staircase's steps: the teeth of a stair's outline are its steps.  And a flight's thin
risers, of the darkest shade, kept as a face: a thin colour is a blend only between two."""

from __future__ import annotations

import numpy as np
import pytest
from test_inverse_faces import _angles_deg
from test_inverse_flatten import GROUND, _jpeg
from test_inverse_other_lights import _camera_axes

from meschers_igl.inverse.flatten import POTTS_WEIGHT, _potts_smooth, flatten_picture


def _energy(labels: np.ndarray, dist: np.ndarray) -> float:
    """The Potts energy: squared colour distances plus the weight per unlike 4-neighbour pair."""
    data = np.take_along_axis(dist**2, labels[..., None], axis=-1).sum()
    cuts = (labels[1:] != labels[:-1]).sum() + (labels[:, 1:] != labels[:, :-1]).sum()
    return float(data + POTTS_WEIGHT * cuts)


def _two_labels(labels: np.ndarray, off: float) -> np.ndarray:
    """(H, W, 2) distances: 0 to a pixel's own label, ``off`` radii to the other."""
    d = np.full(labels.shape + (2,), off)
    np.put_along_axis(d, labels[..., None], 0.0, axis=-1)
    return d


def test_a_bump_goes_and_a_steps_corner_stays():
    """A staircase edge (label 1 below) with a bump of one pixel on a tread, every pixel's
    colour one radius from the other label's.  The bump (three unlike neighbours) costs
    ``2 * POTTS_WEIGHT`` more than it saves and goes; each step's corner pixel (two unlike
    neighbours, two like) stays, as does every other pixel."""
    L = np.zeros((12, 24), dtype=np.int64)
    for i in range(4):  # four treads of 6 px, each 2 px lower than the last
        L[2 + 2 * i :, 6 * i : 6 * i + 6] = 1
    truth = L.copy()
    L[3, 9] = 1  # a bump on the second tread
    out = _potts_smooth(L, _two_labels(L, 1.0))
    assert np.array_equal(out, truth)
    corners = [(2 + 2 * i, 6 * i + 5) for i in range(3)]
    assert all(out[r, c] == 1 and L[r, c + 1] == 0 and L[r - 1, c] == 0 for r, c in corners)


def test_a_colour_far_from_the_other_keeps_its_label():
    """A bump whose colour is more than ``sqrt(2 * POTTS_WEIGHT)`` radii from the other
    label's is a feature, not noise: it stays."""
    L = np.zeros((8, 8), dtype=np.int64)
    L[4:] = 1
    L[3, 4] = 1
    far = np.sqrt(2.0 * POTTS_WEIGHT) * 1.05
    assert _potts_smooth(L, _two_labels(L, far))[3, 4] == 1
    assert _potts_smooth(L, _two_labels(L, 0.95 * far / 1.05))[3, 4] == 0


@pytest.mark.parametrize("seed", range(4))
def test_the_result_is_a_local_minimum_of_the_energy(seed):
    """Random labels and distances (three labels, 10 x 12): the energy does not rise, and no
    single pixel's change lowers it (checked pixel by pixel, label by label)."""
    rng = np.random.default_rng(seed)
    dist = rng.uniform(0.0, 2.5, size=(10, 12, 3))
    L = rng.integers(0, 3, size=(10, 12))
    out = _potts_smooth(L, dist, sweeps=50)
    e = _energy(out, dist)
    assert e <= _energy(L, dist) + 1e-12
    for r in range(10):
        for c in range(12):
            for k in range(3):
                trial = out.copy()
                trial[r, c] = k
                assert _energy(trial, dist) >= e - 1e-9


def _stairs(rise: int, run: int, n: int = 128, steps: int = 18):
    """(n, n, 3) uint8: a flight's outline, ``steps`` treads ``run`` px long each ``rise`` px
    lower, in a dark grey over a light grey face, on the blue ground; its figure mask and
    each step's convex corner (a tread's last pixel before the drop)."""
    a = np.zeros((n, n, 3), np.uint8)
    a[:] = GROUND
    fig = np.zeros((n, n), dtype=bool)
    corners = []
    for i in range(steps):
        x0, y0 = 10 + run * i, 24 + rise * i
        fig[y0:90, x0 : x0 + run] = True
        corners.append((y0, x0 + run - 1))
    a[fig] = 70
    a[fig & (np.arange(n)[:, None] >= 70)] = 170
    return a, fig, corners[:-1]


@pytest.mark.parametrize(("rise", "run"), [(1, 3), (2, 5), (3, 4), (1, 6)])
@pytest.mark.parametrize("quality", [75, 90])
def test_a_jpeg_flights_outline_keeps_its_steps(rise, run, quality):
    """Made flat again, a JPEG picture of a flight keeps the corner pixel of every step (a
    3 x 3 majority kept 0-6 of 17 at rises of 2-3 px) and, at quality 90, all but a few of
    the figure's pixels (a majority: 36-38 off)."""
    from meschers_igl.inverse.targets import target_mask

    a, fig, corners = _stairs(rise, run)
    flat = flatten_picture(_jpeg(a, quality) / 255.0)
    mask = target_mask(flat, np.asarray(GROUND) / 255.0)
    assert sum(bool(mask[r, c]) for r, c in corners) >= len(corners) - 1
    if quality == 90:
        assert np.count_nonzero(mask != fig) < 0.003 * fig.sum()


def test_a_thin_darkest_face_is_a_face_not_a_blend():
    """A flight's risers seen nearly edge-on: strips one pixel high of the darkest shade
    between light treads.  One pixel wide, but between no two other colours: a face (it was
    taken for ringing, its pixels given to the ground and the light face)."""
    a = np.zeros((128, 128, 3), np.uint8)
    a[:] = GROUND
    a[24:104, 24:104] = 203
    a[26:104:4, 24:104] = 51  # twenty risers, 80 px long and 1 px high
    flat = flatten_picture(_jpeg(a, 90) / 255.0) * 255.0
    risers = np.zeros((128, 128), dtype=bool)
    risers[26:104:4, 24:104] = True
    assert np.mean(np.abs(flat[risers] - 51.0).max(axis=-1) < 6.0) > 0.95
    assert np.mean(np.abs(flat[~risers] - a[~risers]).max(axis=-1) < 6.0) > 0.99


def test_a_jpeg_of_the_box_stairs_keeps_its_risers(bench):
    """The box stairs under the seed-1 benchmark's light 3 as a JPEG: their risers, at the
    ambient shade and 1-2 px high, were taken for ringing and given to the ground, and the two
    shades left read a frame 37 degrees off.  Now the frame is within 2 degrees."""
    from meschers_igl.inverse.models import penrose_stairs
    from meschers_igl.inverse.picture import mescher_from_picture

    pytest.importorskip("pyvista")
    model = penrose_stairs()
    light = bench.hemisphere_lights(6, 1)[3]
    img = bench.published_picture(model, 128, light, "jpeg")[0]
    _, _, info = mescher_from_picture(img, light, bench.AMBIENT, background=bench.GROUND)
    assert _angles_deg(info["normals"], _camera_axes(bench, model)).max() < 2.0
    assert np.round(info["shades"].min() * 255) <= 53  # the risers' ambient shade
