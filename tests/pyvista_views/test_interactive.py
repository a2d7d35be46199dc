"""Interactive view: offscreen it returns the render; its widget actions change the right state."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from pvv_helpers import back_to_front, requires_gl, sphere

from meschers_igl import Mescher, MescherError
from pyvista_views import MescherViewer, plot, render
from pyvista_views.interactive import angles_from_light, light_from_angles

pytestmark = [requires_gl, pytest.mark.render]
SIZE = (80, 80)


@pytest.fixture(scope="module")
def ball():
    V, F = sphere(16)
    return V, F, Mescher.from_mesh(V, F), back_to_front(V, F)


def squares():
    V = np.array([[0, 0], [0.6, 0], [0.6, 0.6], [0, 0.6]], float)
    V = np.r_[V, V + 0.4]
    V = np.c_[V, np.zeros(8)]
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    return Mescher.from_mesh(V, F)


def test_light_angles_round_trip_and_match_the_camera_frame():
    np.testing.assert_allclose(light_from_angles(0, 0), [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(light_from_angles(90, 0), [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(light_from_angles(33, 90), [0, 0, 1], atol=1e-12)
    d = light_from_angles(-120.0, 25.0)
    np.testing.assert_allclose(angles_from_light(d), (-120.0, 25.0))


def test_offscreen_plot_returns_the_render_instead_of_blocking(ball):
    V, F, m, order = ball
    image = plot(m, order, lights=[(1, 1, 1)], window_size=SIZE)
    np.testing.assert_array_equal(image, render(m, order, lights=[(1, 1, 1)], window_size=SIZE))


def test_light_slider_relights_like_a_fresh_render(ball):
    V, F, m, order = ball
    viewer = MescherViewer(m, order, window_size=SIZE, off_screen=True)
    layer = viewer.scene.layers[0]
    viewer.set_light_angles(azimuth=200, elevation=30)
    assert viewer.scene.layers[0] is layer  # relit, not rebuilt
    expected = render(m, order, lights=[light_from_angles(200, 30)], window_size=SIZE)
    np.testing.assert_array_equal(viewer.screenshot(), expected)
    viewer.scene.close()


def test_scalar_toggle_and_shading_toggle(ball):
    V, F, m, order = ball
    viewer = MescherViewer(
        m, order, scalars={"x": V[:, 0], "y": V[:, 1]}, window_size=SIZE, off_screen=True
    )
    assert viewer.scalar_names == [None, "x", "y"] and viewer.current_scalars == "x"
    viewer.cycle_scalars()
    np.testing.assert_array_equal(
        viewer.screenshot(), render(m, order, scalars={"y": V[:, 1]}, window_size=SIZE)
    )
    viewer.cycle_scalars()
    assert viewer.current_scalars is None
    np.testing.assert_array_equal(viewer.screenshot(), render(m, order, window_size=SIZE))
    viewer.toggle_shading()
    np.testing.assert_array_equal(
        viewer.screenshot(), render(m, order, shading="smooth", window_size=SIZE)
    )
    with pytest.raises(MescherError, match="name"):
        viewer.show_scalars("z")
    viewer.scene.close()


def test_picking_two_groups_puts_the_first_in_front_of_the_second():
    m = squares()
    kw = dict(
        lights=None,
        scalars=np.array([0.0, 0, 1, 1]),
        cmap="gray",
        ambient=1.0,
        diffuse=0.0,
        bounds=(0, 1, 0, 1),
        window_size=(50, 50),
        off_screen=True,
    )
    viewer = MescherViewer(m, order=[2, 3, 0, 1], **kw)
    assert viewer.screenshot()[20, 25].max() < 50  # dark square (faces 0, 1) in front
    picked_front = pv.Triangle()
    picked_front.cell_data["face_id"] = np.array([2])
    picked_back = pv.Triangle()
    picked_back.cell_data["face_id"] = np.array([0])
    viewer.on_pick(picked_front)
    viewer.on_pick(picked_back)
    viewer.put_in_front([3], [1])
    np.testing.assert_array_equal(np.sort(viewer._draw), np.arange(4))
    rank = np.argsort(viewer._draw)
    assert rank[2] > rank[0] and rank[3] > rank[1]
    assert viewer.screenshot()[20, 25].min() > 200  # the light square now in front
    viewer.scene.close()


def test_widgets_attach_to_an_interactive_plotter(ball):
    V, F, m, order = ball
    viewer = MescherViewer(m, order, window_size=SIZE, off_screen=False)
    if viewer.scene.plotter.iren is None:
        pytest.skip("no interactor available here")
    viewer._add_widgets()  # sliders, keys, picking and the pan/zoom-only style all attach
    assert len(viewer.scene.plotter.widgets.slider_widgets) == 2
    viewer.set_light_angles(azimuth=0, elevation=10)
    np.testing.assert_allclose(viewer.scene.lights[0].direction, light_from_angles(0, 10))
    viewer.scene.close()
