"""Figure 10 made quantitative: cut = ground truth for shading, mescher for intrinsic operations.

Also the project's image measurements (one owner: :mod:`pyvista_views.compare`): luminance on the
0-1 scale, dL and the agreement of two renders, on hand-made images.
"""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import ramp_ring, requires_gl

from meschers_igl import Mescher, MescherError
from pyvista_views import compare
from pyvista_views.compare import (
    COLUMNS,
    ROWS,
    image_agreement,
    image_difference,
    luminance,
)


# ------------------------------------------------------------------------------------------------
# image measurements on hand-made images
# ------------------------------------------------------------------------------------------------
def _image(mask: np.ndarray, grey: np.ndarray | float) -> np.ndarray:
    img = np.full(mask.shape + (3,), 255, dtype=np.uint8)
    img[mask] = np.broadcast_to(np.asarray(grey, dtype=np.uint8), mask.shape)[mask, None]
    return img


def test_luminance_scale_is_zero_to_one():
    img = np.array([[[0, 0, 0], [255, 255, 255], [255, 0, 0], [0, 255, 0], [0, 0, 255]]], np.uint8)
    np.testing.assert_allclose(luminance(img)[0], [0.0, 1.0, 0.2126, 0.7152, 0.0722], atol=1e-12)


def test_image_difference_hand_values():
    ma = np.zeros((4, 4), bool)
    ma[:2, :] = True  # 8 pixels of luminance 0.2
    mb = np.zeros((4, 4), bool)
    mb[1:3, :] = True  # 8 pixels of luminance 0.4, 4 shared
    a, b = _image(ma, 51), _image(mb, 102)
    # covered in either: 12 pixels; 4 shared differ by 0.2, 4 of a's differ from white by 0.8,
    # 4 of b's by 0.6
    assert image_difference(a, b) == pytest.approx((4 * 0.2 + 4 * 0.8 + 4 * 0.6) / 12)
    assert image_difference(a, a) == 0.0
    assert image_difference(_image(ma * False, 0), _image(ma * False, 0)) == 0.0


def test_image_agreement_hand_values():
    ma = np.zeros((4, 4), bool)
    ma[:2, :] = True  # 8 pixels
    mb = np.zeros((4, 4), bool)
    mb[1:3, :] = True  # 8 pixels, 4 shared
    a = _image(ma, 51)  # luminance 0.2
    b = _image(mb, 102)  # luminance 0.4
    g = image_agreement(a, b)
    assert g["iou"] == pytest.approx(4 / 12)
    assert g["luminance_mae"] == pytest.approx(0.2, abs=1e-12)
    assert g["luminance_corr"] == 0.0  # both constant on the overlap but different
    same = image_agreement(a, a)
    assert same == {"iou": 1.0, "luminance_mae": 0.0, "luminance_corr": 1.0}


def test_image_agreement_correlation_is_affine_invariant():
    rng = np.random.default_rng(0)
    mask = np.ones((6, 5), bool)
    grey = rng.integers(10, 120, size=(6, 5))
    g = image_agreement(_image(mask, grey), _image(mask, 2 * grey + 5))
    assert g["iou"] == 1.0
    assert g["luminance_corr"] == pytest.approx(1.0, abs=1e-6)  # uint8 rounding only


def test_image_measures_reject_mismatched_shapes():
    with pytest.raises(MescherError, match=r"a, b: expected .* found \(2, 2, 3\) and \(3, 3, 3\)"):
        image_agreement(np.zeros((2, 2, 3), np.uint8), np.zeros((3, 3, 3), np.uint8))
    with pytest.raises(MescherError, match=r"a, b: expected"):
        image_difference(np.zeros((2, 2), np.uint8), np.zeros((2, 2), np.uint8))


# ------------------------------------------------------------------------------------------------
# Figure 10
# ------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    F, xy, Z, _, _ = ramp_ring(48, 6, 0.6)
    m = Mescher.from_corner_depths(F, xy, Z)
    path = tmp_path_factory.mktemp("cmp") / "figure10.png"
    # a source on the cut model's seam: the far side of the seam is only reachable the long way
    # round (a source elsewhere may see the seam near its own cut locus, where it costs little)
    _, _, vmap = m.cut_embedding()
    source = int(np.flatnonzero(np.bincount(vmap) > 1)[0])
    return compare(
        m,
        path=path,
        window_size=(96, 96),
        lights=[(0, 1, 0.5)],
        relit_lights=[(-1, 0, 0.5)],
        source=source,
    )


@pytest.mark.render
@requires_gl
def test_numbers_cover_every_cell_and_the_figure_is_saved(result):
    from PIL import Image

    assert set(result.numbers) == set(ROWS)
    assert all(set(result.numbers[r]) == set(COLUMNS) for r in ROWS)
    assert all(np.isfinite(list(result.numbers[r].values())).all() for r in ROWS)
    with Image.open(result.path) as im:
        assert im.size[0] > 4 * 96 and im.size[1] > 3 * 96
    assert "mescher" in result.table()


@pytest.mark.render
@requires_gl
def test_mescher_relights_like_the_cut_model_and_bent_does_not(result):
    n = result.numbers
    for column in ("render", "relit"):
        assert n["cut"][column] == 0.0
        assert n["mescher"][column] < 0.5 / 255  # same normals, same pixels (dL on 0-1)
        assert n["bent"][column] > 5.0 / 255  # the harmonic part of the depth is gone
    for row in ROWS:  # the three rows are pixel aligned: same silhouette
        a = np.any(result.images[row]["render"] != 255, axis=-1)
        b = np.any(result.images["cut"]["render"] != 255, axis=-1)
        assert (a & b).sum() / (a | b).sum() > 0.98


@pytest.mark.render
@requires_gl
def test_cut_seam_breaks_smoothing_and_geodesics(result):
    n = result.numbers
    assert n["mescher"]["smoothed"] == 0.0 and n["mescher"]["geodesic"] == 0.0
    assert n["cut"]["smoothed"] > 5.0 / 255  # the seam opens
    assert n["cut"]["geodesic"] > 0.1  # paths cannot cross the seam
    d = result.distances
    # heat-method distances are approximate, but detours around the seam are much longer
    assert d["cut"].max() > 1.3 * d["mescher"].max()
    assert np.median(d["cut"] - d["mescher"]) > -0.01 * d["mescher"].max()


@pytest.mark.render
@requires_gl
def test_result_hands_back_what_it_computed(result):
    """The study reuses compare()'s meschers, smoothings and factored solvers."""
    cut_m, vmap = result.meschers["cut"], result.vmap
    assert vmap.shape == (cut_m.n_vertices,)
    # a factored solver answers a new query like a one-off solve on the same mescher
    d = result.solvers["cut"].distance(0)
    np.testing.assert_allclose(d, cut_m.geodesic_distance(0), atol=1e-10 * d.max())
    # the mescher's smoothed copy keeps its periods (and the cut model's seam has opened)
    np.testing.assert_allclose(
        np.abs(result.smoothed["mescher"].periods()).max(),
        np.abs(result.meschers["mescher"].periods()).max(),
        rtol=1e-9,
    )


def test_compare_refuses_objects_without_the_geometry_it_needs():
    with pytest.raises(MescherError, match="cut_embedding"):
        compare(object(), path=None)


@requires_gl
def test_smoothed_mescher_is_drawn_in_its_followed_order(monkeypatch):
    # Smoothing moves xy: the smoothed panel must not reuse the unsmoothed order (the stairs
    # showed back faces and see-through specks where smoothed bars slid over each other).
    from meschers_igl.gallery import get_model
    from meschers_igl.painter import backface_share
    from pyvista_views.scene import MescherScene

    g = get_model("penrose_stairs")
    m, order = g.mescher.subdivide(1, order=g.order)
    t = 5e-3 * float(np.linalg.norm(np.ptp(np.asarray(m.xy), axis=0))) ** 2
    smoothed = m.smooth(t_xy=t, t_zeta=t)
    drawn = []
    add = MescherScene.add

    def spy(self, mescher, *args, order=None, **kwargs):
        drawn.append((mescher, order))
        return add(self, mescher, *args, order=order, **kwargs)

    monkeypatch.setattr(MescherScene, "add", spy)
    compare(m, order, path=None, t_smooth=t, smoothed=smoothed, window_size=(64, 64))
    ((ms, o),) = [(ms, o) for ms, o in drawn if ms is smoothed]
    assert backface_share(ms, o, size=256) <= 1e-3
    assert backface_share(ms, order, size=256) > 1e-3  # the old order: back faces show
