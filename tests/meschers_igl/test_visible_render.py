"""Models seen from their view render like their z-buffered 3D model.

The oracle is PyVista's z-buffer of the real 3D model in camera coordinates
(``pyvista_views.render((V_camera, F))``: same camera, same lights); the mescher is drawn by
``pyvista_views.render`` in its depth order.  No back face may be visible
(``meschers_igl.painter.backface_share``, a painter's algorithm without GL).
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from visible_models import (
    ISO_UP,
    ISO_VIEW,
    block_stairs,
    hidden_gap_cube,
    hidden_gap_frame,
    soup,
    triangulate,
    u_tribar,
)

from meschers_igl.obtain import model_to_mescher
from meschers_igl.operators import view_frame

pv = pytest.importorskip("pyvista")
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

MODELS = {
    "u_tribar": u_tribar,
    "block_stairs": block_stairs,
    "hidden_gap_frame": hidden_gap_frame,
    "hidden_gap_cube": hidden_gap_cube,
}
LIGHTS = [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4)]
SIZE = 240


def _images(name, hidden="auto", stl=False):
    from pyvista_views import render
    from pyvista_views.headless import configure_headless

    configure_headless()
    pv.OFF_SCREEN = True
    V, P, gap = MODELS[name]()
    F = triangulate(P)
    Vm, Fm = soup(V, F) if stl else (V, F)
    m, order, report = model_to_mescher(Vm, Fm, view=ISO_VIEW, up=ISO_UP, hidden=hidden)
    C = V @ view_frame(ISO_VIEW, ISO_UP).T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    bounds = (c[0] - h, c[0] + h, c[1] - h, c[1] + h)
    kw = dict(lights=LIGHTS, window_size=(SIZE, SIZE), bounds=bounds)
    zbuf = render((C, F), **kw)
    img = render(m, order=order, **kw)
    return m, order, zbuf, img, bounds


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, hidden, stl",
    [(n, "auto", False) for n in sorted(MODELS)]
    + [(n, False, False) for n in sorted(MODELS)]
    + [("hidden_gap_cube", "auto", True)],
)
def test_renders_like_the_z_buffered_model(name, hidden, stl, tmp_path):
    """The closed surface (hidden side kept, its order from the model's depths) and the visible
    surface both render like the model's z-buffer, without a back face in sight."""
    from meschers_igl.painter import backface_share
    from pyvista_views.compare import image_agreement

    m, order, zbuf, img, bounds = _images(name, hidden, stl)
    agree = image_agreement(img, zbuf)
    if os.environ.get("MESCHERS_KEEP_RENDERS"):
        from PIL import Image

        Image.fromarray(np.hstack([zbuf, img])).save(
            f"{os.environ['MESCHERS_KEEP_RENDERS']}/{name}_{hidden}_{'stl' if stl else 'obj'}.png"
        )
    assert agree["iou"] >= 0.98, agree
    assert agree["luminance_corr"] >= 0.98, agree
    assert backface_share(m, order, size=128, bounds=bounds) <= 1e-3
