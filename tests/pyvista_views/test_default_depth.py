"""``render(m)`` without an order never shows a back face (pyvista_views.render.default_depth).

Face-index order draws the far side of an ordinary closed mesh over its near side; the default
must resolve overlaps (z-buffer for a possible mescher, an order from local depth otherwise).
The oracle is the GL face map of the drawn layer: the faces it shows must all be
counter-clockwise on screen (``n_z > 0``).
"""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from pvv_helpers import luminance, requires_gl

from meschers_igl import Mescher
from meschers_igl.gallery import get_model
from pyvista_views.render import default_depth, render_scene

pytestmark = requires_gl


def _back_face_share(scene) -> float:
    layer = scene.layers[-1]
    fm = layer.face_map(scene.plotter, scene.bounds)
    xy, F = layer.source
    faces = fm[fm >= 0]
    T = xy[F[faces]]
    area = (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1]) - (T[:, 1, 1] - T[:, 0, 1]) * (
        T[:, 2, 0] - T[:, 0, 0]
    )
    return float(np.mean(area <= 0))


def _torus():
    t = pv.ParametricTorus(ringradius=1.0, crosssectionradius=0.35, u_res=48, v_res=24)
    t = t.triangulate().clean()
    V = np.asarray(t.points, dtype=np.float64)
    R = pv.transformations.axis_angle_rotation((1, 0, 0), 60)[:3, :3]  # tilted: it overlaps
    return Mescher.from_mesh(V @ R.T, t.regular_faces.astype(np.int64))


@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_ordinary_torus_shows_no_back_face(shading):
    m = _torus()
    with render_scene(m, shading=shading, window_size=(300, 300)) as sc:
        sc.screenshot()
        assert sc.layers[-1].depth == "z-buffer"
        assert _back_face_share(sc) == 0.0
    # face-index order (what render did without an order) shows back faces: the test can fail
    with render_scene(m, order=np.arange(m.n_faces), window_size=(300, 300)) as sc:
        sc.screenshot()
        assert _back_face_share(sc) > 0.05


def test_sphere_is_lit_from_the_light():
    s = pv.Sphere(theta_resolution=32, phi_resolution=32)
    m = Mescher.from_mesh(np.asarray(s.points, float), s.regular_faces.astype(np.int64))
    with render_scene(m, lights=[(1, 1, 1)], shading="smooth", window_size=(200, 200)) as sc:
        img = sc.screenshot()
        assert _back_face_share(sc) == 0.0
    lum = luminance(img)
    # toward the light (upper right) brighter than away from it (lower left), inside the disc
    assert lum[40:80, 120:160].mean() > lum[120:160, 40:80].mean() + 40


def test_impossible_mescher_gets_an_order_from_local_depth():
    g = get_model("penrose_triangle")
    order, how = default_depth(g.mescher)
    assert how == "local depth"
    with render_scene(g.mescher, window_size=(300, 300)) as sc:
        sc.screenshot()
        assert sc.layers[-1].depth == "local depth"
        assert _back_face_share(sc) == 0.0


def test_smoothing_at_the_studys_times_shows_no_back_face():
    """The impossibagel smoothed (xy and depth) at the study's times 2e-4 and 1e-3 s^2, its
    order followed: back faces show at the crescent tip unless they are put behind the front
    faces they overlap (hide_back_faces); with it, none at 512 pixels (painter oracle)."""
    from meschers_igl.painter import backface_share
    from pyvista_views.render import hide_back_faces

    g = get_model("impossibagel")
    m, order = g.mescher.subdivide(1, order=g.order)
    s = float(np.linalg.norm(np.ptp(np.asarray(m.xy), axis=0)))
    shown_before = 0.0
    for factor in (2e-4, 1e-3):
        ms = m.smooth(t_xy=factor * s * s, t_zeta=factor * s * s)
        followed = order.follow(ms)
        shown_before += backface_share(ms, followed, size=512)
        assert backface_share(ms, hide_back_faces(ms, followed), size=512) == 0.0
    assert shown_before > 0.0  # the test can fail: following alone leaves a few
