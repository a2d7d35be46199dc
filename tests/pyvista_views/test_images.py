"""Image regression with pytest-pyvista's ``verify_image_cache`` (issue 17, 8c).

Each test draws one figure through :func:`pyvista_views.render.render_scene` and shows its
plotter; pytest-pyvista compares the frame with ``image_cache/<test name>.png`` (reference
images committed after a person looked at them) using PyVista's image error, with a per-test
tolerance set on the fixture.  Regenerate with ``pytest tests/pyvista_views/test_images.py
--reset_image_cache`` and *look at every image* before committing.
"""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import back_to_front, ramp_ring, requires_gl, sphere

from meschers_igl import Mescher
from meschers_igl.gallery import get_model
from pyvista_views.render import render_scene

# The plugin is in the test extra; without it (a bare environment) these tests skip.  Note that
# pytest-pyvista 0.3.3 fails at exit under ``-p no:cacheprovider`` (it needs config.cache).
pytest.importorskip("pytest_pyvista")
pytestmark = [requires_gl, pytest.mark.render]
SIZE = (160, 160)


def check(verify_image_cache, error: float, m, **kw) -> None:
    """Show ``render_scene(m, **kw)``'s plotter under ``verify_image_cache`` with ``error``."""
    verify_image_cache.error_value = error
    verify_image_cache.warning_value = 0.5 * error
    scene = render_scene(m, window_size=SIZE, **kw)
    scene.plotter.show()  # off screen: renders, then the fixture's close callback compares


@pytest.fixture(scope="module")
def ball():
    V, F = sphere(24)
    return V, F, Mescher.from_mesh(V, F), back_to_front(V, F)


@pytest.fixture(scope="module")
def penrose():
    g = get_model("penrose_triangle")
    return g.mescher, g.order


def test_sphere_smooth_scalars_isolines(ball, verify_image_cache):
    V, F, m, order = ball
    kw = dict(order=order, shading="smooth", scalars={"height": V[:, 1]}, isolines=4)
    check(verify_image_cache, 40.0, m, lights=[(1, 1, 1)], **kw)  # light moved 6 deg: 89


def test_ring_flat(verify_image_cache):
    F, xy, Z, *_ = ramp_ring()
    m = Mescher.from_corner_depths(F, xy, Z)
    check(verify_image_cache, 30.0, m, lights=[(-1, 0, 0.5)])  # light tilted by 0.2: 82


def test_ring_studio(verify_image_cache):
    F, xy, Z, *_ = ramp_ring()
    m = Mescher.from_corner_depths(F, xy, Z)
    check(verify_image_cache, 60.0, m, env_map="studio", lights=None, shading="smooth")  # sky: 731


def test_penrose_two_lights_and_studio(penrose, verify_image_cache):
    """The README's ``meschers render ... --light 1,1,1 --light -1,0,1 --env studio``."""
    m, order = penrose
    kw = dict(order=order, lights=[(1, 1, 1), (-1, 0, 1)], env_map="studio", shading="smooth")
    check(verify_image_cache, 100.0, m, **kw)  # without the order: 655, unnormalised: 3442


def test_penrose_geodesic_isolines_colour_bar(penrose, verify_image_cache):
    m, order = penrose
    m2, order2 = m.subdivide(levels=2, order=order)
    d = m2.geodesic_distance([int(np.argmin(m2.xy[:, 1]))])
    kw = dict(order=order2, shading="smooth", scalars={"geodesic distance": d}, isolines=8)
    check(verify_image_cache, 150.0, m2, **kw)  # 7 isolines: 504, no colour bar: 4258


def test_penrose_paths_and_loops_on_the_visible_surface(penrose, verify_image_cache):
    """A shortest path (red), the closed geodesics around the loops and two dots, drawn only
    where visible.  Drawing the hidden pieces dashed gives an image error of 68 (a light
    moved 6 degrees: 127)."""
    from meschers_igl.geodesic import shortest_loops

    m, order = penrose
    m, order = m.subdivide(1, order=order)
    d = m.geodesic_distance(0)
    target = int(np.nanargmax(np.where(np.isfinite(d), d, -1)))
    paths = [{"path": m.shortest_path(0, target), "color": "red"}]
    paths += [{"path": loop} for loop in shortest_loops(m)]
    check(verify_image_cache, 30.0, m, order=order, paths=paths, points=[0, target])


def test_reutersvard_loop_subdivision_keeps_the_cubes(verify_image_cache):
    """Loop x2 with creases, smooth shading: nine cubes.  Plain Loop's blobs: error 1622
    (a light moved 6 degrees: 112)."""
    g = get_model("reutersvard_triangle")
    m, order = g.mescher.subdivide(2, "loop", order=g.order)
    check(verify_image_cache, 60.0, m, order=order, shading="smooth")
