"""Isolines lie on the levels of the surface the viewer sees (issue 17, 8b).

The oracle is independent of OpenGL: :func:`meschers_igl.painter.visible_faces` point-samples
the painter's algorithm over the depth order at each pixel centre and gives the visible face
and the barycentric coordinates there, so the field's value on the *visible* surface at every
pixel is known exactly.  An isoline pixel (one that changes when isolines are drawn) must lie
within a line's half-width of a contour level of that visible value.
"""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import requires_gl

from meschers_igl.gallery import get_model
from pyvista_views import render
from pyvista_views.camera import default_bounds, xy_box
from pyvista_views.isolines import levels_of

pytestmark = [requires_gl, pytest.mark.render]
SIZE = 240


@pytest.fixture(scope="module")
def penrose_distance():
    g = get_model("penrose_triangle")
    m, order = g.mescher.subdivide(levels=2, order=g.order)
    source = int(np.argmin(m.xy[:, 1]))
    return m, order, m.geodesic_distance([source])


def visible_distance_px(m, order, u, levels, bounds):
    """(H, W) distance in pixels from each pixel centre to the nearest level of the visible
    surface's field (first order: |u - L| / |grad u| per pixel); inf on the background."""
    painter = pytest.importorskip("meschers_igl.painter")
    faces, bary = painter.visible_faces(m, order, size=SIZE, bounds=bounds, return_barycentric=True)
    F, xy = np.asarray(m.F), np.asarray(m.xy)
    seen = faces >= 0
    f = faces[seen]
    value = np.einsum("ij,ij->i", bary[seen], u[F[f]])
    P, U = xy[F[f]], u[F[f]]
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    du1, du2 = U[:, 1] - U[:, 0], U[:, 2] - U[:, 0]
    gx = (du1 * e2[:, 1] - du2 * e1[:, 1]) / det
    gy = (du2 * e1[:, 0] - du1 * e2[:, 0]) / det
    pixel = (bounds[1] - bounds[0]) / SIZE
    slope = np.hypot(gx, gy) * pixel  # value change per pixel
    gap = np.abs(value[:, None] - levels[None, :]).min(axis=1)
    out = np.full(faces.shape, np.inf)
    out[seen] = gap / np.maximum(slope, 1e-300)
    return out


def test_isoline_pixels_lie_on_the_visible_surfaces_levels(penrose_distance):
    m, order, d = penrose_distance
    bounds = default_bounds(xy_box(m.xy), (SIZE, SIZE))
    kw = dict(order=order, scalars=d, shading="smooth", window_size=(SIZE, SIZE), bounds=bounds)
    kw.update(scalar_bar=False, lights=[(1, 1, 1)])
    plain = render(m, **kw)
    lined = render(m, isolines=10, isoline_color="red", **kw)
    line = np.abs(plain.astype(int) - lined).max(axis=-1) > 24
    assert line.sum() > 5 * SIZE  # ten levels across the figure: many line pixels
    levels = levels_of(10, (d.min(), d.max()))
    dist = visible_distance_px(m, order, d, levels, bounds)
    # a 2-pixel line covers pixel centres up to ~1.5 px from its level; 2 px with rounding
    on_level = dist[line] <= 2.0
    assert on_level.mean() >= 0.98, f"{1 - on_level.mean():.1%} of isoline pixels off the levels"
    # and every level of the visible surface is drawn: pixels right on a level are lined
    # (away from the silhouette, where a line may be clipped by the pixel grid)
    exact = dist <= 0.3
    assert line[exact].mean() >= 0.9
