"""Models seen from their view render like their z-buffered 3D model (issue 18 item 6).

The oracle is PyVista's z-buffer of the real 3D model in camera coordinates
(``pyvista_views.render((V_camera, F))``: same camera, same lights); the mescher is drawn by
``pyvista_views.render`` in its depth order.  No back face may be visible
(``meschers_igl.painter.backface_share``, a painter's algorithm without GL).
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from visible_models import ISO_UP, ISO_VIEW, block_stairs, hidden_gap_frame, triangulate, u_tribar

from meschers_igl.models import model_to_mescher
from meschers_igl.operators import view_frame

pv = pytest.importorskip("pyvista")
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

MODELS = {"u_tribar": u_tribar, "block_stairs": block_stairs, "hidden_gap_frame": hidden_gap_frame}
LIGHTS = [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4)]
SIZE = 240


def _images(name):
    from pyvista_views import render
    from pyvista_views.headless import configure_headless

    configure_headless()
    pv.OFF_SCREEN = True
    V, P, gap = MODELS[name]()
    F = triangulate(P)
    m, order, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)
    C = V @ view_frame(ISO_VIEW, ISO_UP).T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    bounds = (c[0] - h, c[0] + h, c[1] - h, c[1] + h)
    kw = dict(lights=LIGHTS, window_size=(SIZE, SIZE), bounds=bounds)
    zbuf = render((C, F), **kw)
    img = render(m, order=order, **kw)
    return m, order, zbuf, img, bounds


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(MODELS))
def test_renders_like_the_z_buffered_model(name, tmp_path):
    from meschers_igl.painter import backface_share

    m, order, zbuf, img, bounds = _images(name)
    fig_z = np.any(zbuf < 250, axis=2)  # white background
    fig_m = np.any(img < 250, axis=2)
    iou = np.count_nonzero(fig_z & fig_m) / np.count_nonzero(fig_z | fig_m)
    both = fig_z & fig_m
    lum = lambda a: a[..., :3].astype(float) @ [0.2126, 0.7152, 0.0722]  # noqa: E731
    corr = np.corrcoef(lum(zbuf)[both], lum(img)[both])[0, 1]
    if os.environ.get("MESCHERS_KEEP_RENDERS"):
        from PIL import Image

        Image.fromarray(np.hstack([zbuf, img])).save(
            f"{os.environ['MESCHERS_KEEP_RENDERS']}/{name}.png"
        )
    assert iou >= 0.98, iou
    assert corr >= 0.98, corr
    assert backface_share(m, order, size=128, bounds=bounds) == 0.0
