"""Development models under lights the acceptance benchmark's seed does not draw (its seed 1).

Two readings went wrong there and were mended as rules, not for these files:

- ``Impossible_Cube.3ds`` under two lights turning two of its face directions away: 50 pixels
  of faces seen nearly edge-on, a few levels over the ambient shade, joined the shared group
  and lifted its mean shade, so the frame was asked to light both dark directions at a
  grazing angle (``n . l`` = 0.003) and turned 25 degrees: PSNR 23 dB, 0% of the pixels near
  the model's axes, period +287%.  Shades are now the median of their pixels and a shade
  within two levels of the ambient one is turned away (:data:`.faces.AMBIENT_LEVELS`).
- ``PenroseTriangle2.obj`` under a light from the right: two face directions 16 levels apart
  and a sheared end (4% of the figure) of a fourth shade; by variance the two were one
  orientation and the end another, a frame 8 degrees off with 39% of the pixels near the axes
  after the fit.  The next grouping's frame fits the lines (``picture.RETRY_MISFIT``).
"""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.render


def _camera_axes(bench, model) -> np.ndarray:
    """(3, 3) the model's face directions in the camera frame, facing the viewer."""
    ax = bench.model_axes(model)
    C = np.stack([np.cross(model.up, model.view), model.up, model.view])
    N = ax @ C.T
    return N * np.sign(N[:, 2:3])


def _start(bench, model, k: int):
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture

    light = bench.hemisphere_lights(6, 1)[k]
    image, scale = zbuffer_picture(
        model, 128, light=light, ambient=bench.AMBIENT, background=bench.GROUND
    )
    m0, _, info = mescher_from_picture(image, light, bench.AMBIENT, background=bench.GROUND)
    return figure_period(m0), model.gap * scale, info


def _angles_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    c = np.abs(a @ b.T).max(axis=1)
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


@pytest.mark.parametrize("k", [1, 2])
def test_file_cube_with_two_directions_turned_away(bench, development_model, k):
    model = development_model("Impossible_Cube.3ds")
    period, gap, info = _start(bench, model, k)
    assert info["normals"] is not None and info["unseen_turn"]
    assert _angles_deg(info["normals"], _camera_axes(bench, model)).max() < 2.0
    assert period == pytest.approx(gap, rel=0.05)


def test_sheared_tribar_with_two_close_shades(bench, development_model):
    model = development_model("PenroseTriangle2.obj")
    _, _, info = _start(bench, model, 3)
    assert info["misfit"] < 0.025
    assert _angles_deg(info["normals"], _camera_axes(bench, model)).max() < 2.0
