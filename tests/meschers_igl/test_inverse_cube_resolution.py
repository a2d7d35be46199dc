"""The impossible cube's climb read at 128 and at 256 pixels: the reading must not depend on
the picture's size.

Both cubes (the development set's ``Impossible_Cube.3ds`` and the box model
:func:`meschers_igl.inverse.models.impossible_cube`) are z-buffered under the acceptance
benchmark's six lights; the start mescher's period must be within its 5% of the true depth gap.
At 128 x 128 all twelve are.  At 256 x 256 the file's cube is 16-18% short under five lights
(+8% under the sixth) and the box cube 39% short under lights 3 and 5: strict xfails, so a
rule that reads them turns them into failures and the markers must go.

What differs for the file (light 0): at 128 a hidden line runs from a junction on the upright
bar's dark side face (a vertex of its straightened edge: a pixel step under Douglas-Peucker,
whose short segment reads as an occlusion) to the notch where a front bar's face runs on into
a back bar's face of the same shade; at 256 that edge straightens to one line and the hidden
line is not found.  It is not all that is missing: added by hand at 256 (from the notch to the
upright bar, its end moved over 2 px) the start stays 16% short.  Starting lines from notches
(an outline edge going on straight through one shade) finds it at 128 only, and costs the box
stairs two passes at 128.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import meschers_igl  # noqa: F401  (before the benchmark, which tests/ on sys.path could shadow)

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "real_models"
NAME = "Impossible_Cube.3ds"


@pytest.fixture(scope="module")
def bench():
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        return pytest.importorskip("bench_inverse_real")
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))


@pytest.fixture(scope="module")
def file_cube(bench):
    pytest.importorskip("pyvista")
    if not (REAL / "views.json").is_file() or not (REAL / NAME).is_file():
        pytest.skip("development set absent")
    return bench.load_models(REAL, {NAME})[0][0]


@pytest.fixture(scope="module")
def box_cube():
    pytest.importorskip("pyvista")
    from meschers_igl.inverse.models import impossible_cube

    return impossible_cube()


def _climb_error(bench, model, k: int, res: int) -> float:
    """The start mescher's period over the true gap, less one, under the benchmark's light k."""
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture

    light = bench.hemisphere_lights(6, 0)[k]
    image, scale = zbuffer_picture(
        model, res, light=light, ambient=bench.AMBIENT, background=bench.GROUND
    )
    m0, _, _ = mescher_from_picture(image, light, bench.AMBIENT, background=bench.GROUND)
    return figure_period(m0) / (model.gap * scale) - 1.0


@pytest.mark.render
@pytest.mark.parametrize("k", range(6))
def test_file_cube_climbs_its_gap_at_128(bench, file_cube, k):
    err = _climb_error(bench, file_cube, k, 128)
    assert abs(err) < 0.05, err


@pytest.mark.render
@pytest.mark.xfail(strict=True, reason="16-18% short at 256 px")
@pytest.mark.parametrize("k", range(6))
def test_file_cube_climbs_its_gap_at_256(bench, file_cube, k):
    err = _climb_error(bench, file_cube, k, 256)
    assert abs(err) < 0.05, err


@pytest.mark.render
@pytest.mark.parametrize(
    ("k", "res"),
    [(k, 128) for k in range(6)]
    + [(k, 256) for k in (0, 1, 2, 4)]
    + [
        pytest.param(k, 256, marks=pytest.mark.xfail(strict=True, reason="39% short at 256 px"))
        for k in (3, 5)
    ],
)
def test_box_cube_climbs_its_gap(bench, box_cube, k, res):
    err = _climb_error(bench, box_cube, k, res)
    assert abs(err) < 0.05, err
