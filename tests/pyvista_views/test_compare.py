"""Figure 10 made quantitative: cut = ground truth for shading, mescher for intrinsic operations."""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import ramp_ring, requires_gl

from meschers_igl import Mescher, MescherError
from pyvista_views import compare
from pyvista_views.compare import COLUMNS, ROWS

pytestmark = [requires_gl, pytest.mark.render]


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


def test_numbers_cover_every_cell_and_the_figure_is_saved(result):
    from PIL import Image

    assert set(result.numbers) == set(ROWS)
    assert all(set(result.numbers[r]) == set(COLUMNS) for r in ROWS)
    assert all(np.isfinite(list(result.numbers[r].values())).all() for r in ROWS)
    with Image.open(result.path) as im:
        assert im.size[0] > 4 * 96 and im.size[1] > 3 * 96
    assert "mescher" in result.table()


def test_mescher_relights_like_the_cut_model_and_bent_does_not(result):
    n = result.numbers
    for column in ("render", "relit"):
        assert n["cut"][column] == 0.0
        assert n["mescher"][column] < 0.5  # same normals, same pixels
        assert n["bent"][column] > 5.0  # the harmonic part of the depth is gone
    for row in ROWS:  # the three rows are pixel aligned: same silhouette
        a = np.any(result.images[row]["render"] != 255, axis=-1)
        b = np.any(result.images["cut"]["render"] != 255, axis=-1)
        assert (a & b).sum() / (a | b).sum() > 0.98


def test_cut_seam_breaks_smoothing_and_geodesics(result):
    n = result.numbers
    assert n["mescher"]["smoothed"] == 0.0 and n["mescher"]["geodesic"] == 0.0
    assert n["cut"]["smoothed"] > 5.0  # the seam opens
    assert n["cut"]["geodesic"] > 0.1  # paths cannot cross the seam
    d = result.distances
    # heat-method distances are approximate, but detours around the seam are much longer
    assert d["cut"].max() > 1.3 * d["mescher"].max()
    assert np.median(d["cut"] - d["mescher"]) > -0.01 * d["mescher"].max()


def test_compare_refuses_objects_without_the_geometry_it_needs():
    with pytest.raises(MescherError, match="cut_embedding"):
        compare(object(), path=None)
