"""The scene sets its camera only when something it depends on changed (a relit frame costs no
bounds pass over every point), and still undoes any other camera change before a screenshot."""

from __future__ import annotations

import numpy as np
from pvv_helpers import requires_gl, sphere

from meschers_igl import Mescher
from pyvista_views import scene as scene_mod
from pyvista_views.scene import MescherScene


@requires_gl
def test_relit_frames_do_not_reset_the_camera_but_user_moves_are_undone(monkeypatch):
    calls = []
    real = scene_mod.set_view
    monkeypatch.setattr(scene_mod, "set_view", lambda p, b: (calls.append(b), real(p, b)))
    V, F = sphere()
    m = Mescher.from_mesh(V, F)
    with MescherScene(window_size=(96, 96)) as sc:
        sc.add(m)
        first = sc.screenshot()
        n = len(calls)
        for light in ((1.0, 0.0, 1.0), (-1.0, 0.5, 1.0)):
            sc.relight(light)
            sc.screenshot()
        assert len(calls) == n  # relighting changed no bounds, window, actor or camera
        sc.relight((0.0, 0.0, 1.0))  # back to the default light direction
        sc.relight()
        # a user (or another tool) turns the camera: the next screenshot puts it back
        sc.plotter.renderer.GetActiveCamera().Azimuth(40.0)
        again = sc.screenshot()
        assert len(calls) == n + 1
        assert np.array_equal(again, first)
        # a new layer (new geometry, maybe a new z range) sets the camera again
        sc.add(Mescher.from_mesh(V + [0.2, 0.0, 0.0], F))
        assert len(calls) > n + 1
