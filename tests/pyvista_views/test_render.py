"""Rendering, offscreen: exact extents and shades, meschers vs real meshes, relighting, images."""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import back_to_front, iou, luminance, mask, ramp_ring, requires_gl, sphere

from meschers_igl import Mescher, MescherError
from pyvista_views import MescherScene, render

pytestmark = [requires_gl, pytest.mark.render]

LIGHTS = [(1, 1, 1), (-1, 0.3, 0.5), (0.2, -1, 0.3), (0, 0, 1)]
SIZE = (120, 120)


@pytest.fixture(scope="module")
def ball():
    V, F = sphere(24)
    return V, F, Mescher.from_mesh(V, F), back_to_front(V, F)


@pytest.fixture(scope="module")
def ring():
    F, xy, Z, V_cut, F_cut = ramp_ring()
    return Mescher.from_corner_depths(F, xy, Z), V_cut, F_cut


def square(x0, x1, y0, y1, tilt=(0.0, 0.0)):
    """Two triangles over [x0, x1] x [y0, y1] on the plane z = tilt . (x, y)."""
    V = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)
    V = np.c_[V, V @ np.asarray(tilt, float)]
    return V, np.array([[0, 1, 2], [0, 2, 3]])


# -- camera ------------------------------------------------------------------------------------


@pytest.mark.parametrize("window", [(100, 100), (80, 50)])
def test_bounds_are_exactly_the_image_extent(window):
    V, F = square(0.2, 0.5, 0.6, 0.9)
    img = render(Mescher.from_mesh(V, F), window_size=window, bounds=(0, 1, 0, 1))
    W, H = window
    assert img.shape == (H, W, 3) and img.dtype == np.uint8
    rows, cols = np.nonzero(mask(img))
    # pixel centres inside the square: columns 0.2 W .. 0.5 W, rows from the top (y up)
    assert (cols.min(), cols.max() + 1) == (round(0.2 * W), round(0.5 * W))
    assert (rows.min(), rows.max() + 1) == (round(0.1 * H), round(0.4 * H))


def test_default_bounds_frame_the_xy_box_with_square_pixels():
    V, F = square(-2, 2, 0, 1)
    img = render(Mescher.from_mesh(V, F), window_size=(100, 100))
    rows, cols = np.nonzero(mask(img))
    width, height = cols.max() - cols.min() + 1, rows.max() - rows.min() + 1
    assert 88 <= width <= 92  # 4 / (4 * 1.1) of the width, 5% margin each side
    assert abs(width / height - 4.0) < 0.2  # square pixels: the 4:1 box stays 4:1


def test_bounds_are_validated():
    V, F = square(0, 1, 0, 1)
    with pytest.raises(MescherError, match="bounds"):
        render(Mescher.from_mesh(V, F), bounds=(1, 0, 0, 1))
    with pytest.raises(MescherError, match="window_size"):
        render(Mescher.from_mesh(V, F), window_size=(0, 10))
    with pytest.raises(MescherError, match="window_size.*(width)"):
        render(Mescher.from_mesh(V, F), window_size=(12.5, 10))
    # refused before any GL work: 1e10 pixels do not fit in memory (meschers_igl check_budget)
    with pytest.raises(MescherError, match=r"window_size \(100000 x 100000 pixels\).*GB"):
        render(Mescher.from_mesh(V, F), window_size=(100_000, 100_000))


# -- shading -----------------------------------------------------------------------------------


@pytest.mark.parametrize("tilt", [(0.0, 0.0), (0.5, -0.25), (-1.0, 0.8)])
@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_matte_shade_is_exactly_ambient_plus_lambert(tilt, shading):
    """A plane z = a x + b y has normal (-a, -b, 1)/|.|; grey 0.85, ambient 0.2, diffuse 0.8."""
    V, F = square(0, 1, 0, 1, tilt)
    light = np.array([0.3, 0.4, 0.866])
    img = render(Mescher.from_mesh(V, F), lights=[light], shading=shading, window_size=(40, 40))
    n = np.array([-tilt[0], -tilt[1], 1.0])
    n /= np.linalg.norm(n)
    expected = 255 * 0.85 * (0.2 + 0.8 * max(n @ light / np.linalg.norm(light), 0))
    assert np.abs(img[mask(img)].astype(float) - expected).max() <= 1.0


def test_several_lights_add_up_and_no_light_leaves_ambient_only():
    V, F = square(0, 1, 0, 1)
    m = Mescher.from_mesh(V, F)
    kw = dict(window_size=(20, 20), normalize_lights=False)
    (one,) = {int(v) for v in render(m, lights=[(1, 0, 1)], **kw)[10, 10]}
    two = int(render(m, lights=[(1, 0, 1), (-1, 0, 1)], **kw)[10, 10, 0])
    none = int(render(m, lights=None, **kw)[10, 10, 0])
    c = np.sqrt(0.5)
    assert abs(one - 255 * 0.85 * (0.2 + 0.8 * c)) <= 1
    assert abs(two - min(255, 255 * 0.85 * (0.2 + 1.6 * c))) <= 1
    assert abs(none - 255 * 0.85 * 0.2) <= 1


def test_lights_never_wash_out_by_default():
    """Normalised (the default): the brightest visible normal of two lights (1,0,1), (-1,0,1)
    is n = (0,0,1) with irradiance 2c (c = cos 45); the diffuse factor becomes
    s = (1 - 0.2) / (0.8 * 2c), so that normal shows exactly the albedo 0.85, and one light
    of intensity 1 is left as it is."""
    V, F = square(0, 1, 0, 1)
    m = Mescher.from_mesh(V, F)
    c = np.sqrt(0.5)
    one = int(render(m, lights=[(1, 0, 1)], window_size=(20, 20))[10, 10, 0])
    assert abs(one - 255 * 0.85 * (0.2 + 0.8 * c)) <= 1  # unchanged
    two = int(render(m, lights=[(1, 0, 1), (-1, 0, 1)], window_size=(20, 20))[10, 10, 0])
    assert abs(two - 255 * 0.85) <= 1  # 0.85 * (0.2 + 0.8 * s * 2c) with s = 1 / (2c)
    # environment maps count too: studio + two lights stay below the albedo on a sphere
    ball = sphere(24)
    img = render(
        Mescher.from_mesh(*ball),
        order=back_to_front(*ball),
        lights=[(1, 1, 1), (-1, 0, 1)],
        env_map="studio",
        shading="smooth",
        window_size=(64, 64),
    )
    assert img[mask(img)].max() <= round(255 * 0.85) + 1
    # exposure brightens on purpose; the Reinhard tone map keeps the highlights unclipped
    bright = render(m, lights=[(1, 0, 1), (-1, 0, 1)], window_size=(20, 20), exposure=2.0)
    assert int(bright[10, 10, 0]) == 255
    toned = render(
        m, lights=[(1, 0, 1), (-1, 0, 1)], window_size=(20, 20), exposure=2.0, tone_map="reinhard"
    )
    assert 0.85 * 255 - 2 <= int(toned[10, 10, 0]) <= 0.85 * 255 + 1  # white point -> albedo
    with pytest.raises(MescherError, match="tone_map"):
        render(m, tone_map="filmic", window_size=(20, 20))


def test_point_lights_are_refused_before_rendering():
    import pyvista as pv

    V, F = square(0, 1, 0, 1)
    with pytest.raises(MescherError, match="Section 4.1"):
        render(Mescher.from_mesh(V, F), lights=[pv.Light(position=(0, 0, 3), positional=True)])


@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_mescher_of_a_mesh_renders_like_the_mesh_under_several_lights(ball, shading):
    """Same silhouette and shading as the z-buffered real mesh (issue 5: IoU >= .98, r >= .95)."""
    V, F, m, order = ball
    for light in LIGHTS:
        a = render(m, order=order, lights=[light], shading=shading, window_size=SIZE)
        b = render((V, F), lights=[light], shading=shading, window_size=SIZE)
        both = mask(a) & mask(b)
        assert iou(mask(a), mask(b)) >= 0.98
        assert np.corrcoef(luminance(a)[both], luminance(b)[both])[0, 1] >= 0.95


def test_in_face_index_order_the_sphere_shows_its_back(ball):
    """Drawn in face-index order the sphere shows its back; without an order ``render``
    resolves overlaps itself and matches the z-buffered mesh like the true order."""
    V, F, m, order = ball
    right = render((V, F), lights=[(1, 1, 1)], window_size=SIZE)
    wrong = render(m, order=np.arange(m.n_faces), lights=[(1, 1, 1)], window_size=SIZE)
    good = render(m, order=order, lights=[(1, 1, 1)], window_size=SIZE)
    default = render(m, lights=[(1, 1, 1)], window_size=SIZE)
    err = np.abs(luminance(wrong) - luminance(right)).mean()
    assert err > 10 * max(np.abs(luminance(good) - luminance(right)).mean(), 0.1)
    assert np.abs(luminance(default) - luminance(right)).mean() <= 0.1 * err


def test_painter_draws_later_faces_in_front_whatever_their_index():
    V0, F0 = square(0, 0.6, 0, 0.6)
    V1, F1 = square(0.4, 1, 0.4, 1)
    m = Mescher.from_mesh(np.r_[V0, V1], np.r_[F0, F1 + 4])
    colour = np.array([0.0, 0.0, 1.0, 1.0])  # faces 0, 1 low; 2, 3 high
    kw = dict(lights=None, scalars=colour, cmap="gray", ambient=1.0, window_size=(50, 50))
    kw["bounds"] = (0, 1, 0, 1)
    ahead = render(m, order=[0, 1, 2, 3], **kw)[20, 25]  # pixel (x=.5, y=.59) in the overlap
    behind = render(m, order=[2, 3, 0, 1], **kw)[20, 25]
    assert ahead.min() > 200 and behind.max() < 50


def test_smooth_and_flat_shading_differ_on_a_curved_surface(ball):
    *_, m, order = ball
    flat = render(m, order=order, shading="flat", window_size=SIZE)
    smooth = render(m, order=order, shading="smooth", window_size=SIZE)
    inside = mask(flat) & mask(smooth)
    diff = np.abs(luminance(flat) - luminance(smooth))[inside]
    assert iou(mask(flat), mask(smooth)) > 0.99 and diff.mean() > 1.0
    # smooth shading varies within a face: far more distinct grey levels than faces seen
    assert len(np.unique(luminance(smooth)[inside])) > 2 * len(np.unique(luminance(flat)[inside]))


def test_scalar_render_shows_a_monotone_colour_gradient(ball):
    V, F, m, order = ball
    kw = dict(order=order, scalars=V[:, 0], lights=None, ambient=1.0, diffuse=0.0, scalar_bar=False)
    gray = render(m, cmap="gray", window_size=SIZE, **kw)[SIZE[1] // 2]
    inside = mask(gray[None])[0]
    cols = np.nonzero(inside)[0]
    # x is linear in the column, the gray map linear in x: the row is a straight ramp 0..255
    fit = np.polyfit(cols, gray[inside, 0].astype(float), 1)
    assert np.abs(np.polyval(fit, cols) - gray[inside, 0]).max() < 4
    assert gray[inside, 0].min() < 10 and gray[inside, 0].max() > 245
    viridis = render(m, cmap="viridis", window_size=SIZE, **kw)[SIZE[1] // 2, inside].astype(int)
    # viridis runs from (68, 1, 84) purple on the left to (253, 231, 37) yellow on the right
    assert viridis[-1, 0] - viridis[0, 0] > 150 and viridis[0, 2] - viridis[-1, 2] > 30
    assert (np.diff(viridis[:, 1]) >= 0).all() and viridis[-1, 1] - viridis[0, 1] > 150


def test_isolines_are_drawn_on_visible_faces_only(ball):
    V, F, m, order = ball
    kw = dict(order=order, scalars=V[:, 1], lights=None, ambient=1.0, window_size=SIZE)
    plain, lined = render(m, **kw), render(m, isolines=5, isoline_color="red", **kw)
    red = (lined[..., 0] > 200) & (lined[..., 1] < 60) & (lined[..., 2] < 60)
    rows = np.unique(np.nonzero(red)[0])
    # five horizontal lines (y levels), each a thin band of rows
    bands = np.split(rows, np.nonzero(np.diff(rows) > 1)[0] + 1)
    assert len(bands) == 5 and all(len(b) <= 3 for b in bands)
    assert (np.abs(plain.astype(int) - lined).max(-1) > 0).mean() < 0.1
    with pytest.raises(MescherError, match="isolines"):
        render(m, isolines=3)  # no scalars


# -- relighting and the three representations ----------------------------------------------------


def test_relighting_reuses_geometry_and_is_reversible(ball):
    *_, m, order = ball
    with MescherScene(window_size=SIZE) as scene:
        layer = scene.add(m, order=order)
        scene.view()
        scene.relight([(1, 1, 1)])
        first = scene.screenshot()
        mesh, actor = layer.mesh, layer.actor
        scene.relight([(-1, -1, 0.5)])
        second = scene.screenshot()
        scene.relight([(1, 1, 1)])
        again = scene.screenshot()
        assert layer.mesh is mesh and layer.actor is actor and len(scene.layers) == 1
    assert np.abs(luminance(first) - luminance(second)).mean() > 5
    np.testing.assert_array_equal(first, again)
    np.testing.assert_array_equal(first, render(m, order=order, window_size=SIZE))


def test_cut_embedding_relights_like_the_mescher_and_bent_does_not(ring):
    """Figure 10, left columns: the cut model is the ground truth for shading."""
    m, V_cut, F_cut = ring
    bent = np.c_[m.xy, m.hodge().z]  # bent embedding: the exact part of zeta integrated
    for light in [(-1, 0, 0.5), (0, 1, 0.4), (1, -1, 1)]:
        a = render(m, lights=[light], window_size=SIZE)
        c = render((V_cut, F_cut), lights=[light], window_size=SIZE)
        b = render((bent, m.F), lights=[light], window_size=SIZE)
        both = mask(a) & mask(c) & mask(b)
        assert iou(mask(a), mask(c)) >= 0.98 and iou(mask(a), mask(b)) >= 0.98  # pixel aligned
        assert np.corrcoef(luminance(a)[both], luminance(c)[both])[0, 1] >= 0.95
        assert np.abs(luminance(a) - luminance(b))[both].mean() > 5.0


def test_representation_keyword_uses_the_meschers_own_embeddings(ring):
    m, *_ = ring
    kw = dict(lights=[(-1, 0, 0.5)], window_size=SIZE)
    images = {}
    for kind in ("bent", "cut"):
        V, F = getattr(m, f"{kind}_embedding")()[:2]
        images[kind] = render(m, representation=kind, **kw)
        # exactly the picture of that embedding drawn as a real mesh, same camera and bounds
        np.testing.assert_array_equal(images[kind], render((V, F), bounds=_bounds_of(m), **kw))
    # on an impossible ring the two embeddings differ (the cut has a step, the bent is tilted)
    assert iou(mask(images["bent"]), mask(images["cut"])) >= 0.98
    assert np.abs(luminance(images["bent"]) - luminance(images["cut"])).max() > 10


def _bounds_of(m):
    from pyvista_views.camera import default_bounds, xy_box

    return default_bounds(xy_box(m.xy), SIZE)


def test_env_map_shades_mescher_like_the_mesh_and_uniform_light_is_flat(ball):
    V, F, m, order = ball
    a = render(m, order=order, env_map="studio", lights=None, shading="smooth", window_size=SIZE)
    b = render((V, F), env_map="studio", lights=None, shading="smooth", window_size=SIZE)
    assert iou(mask(a), mask(b)) >= 0.98
    assert np.abs(a.astype(int) - b).max() <= 2
    assert luminance(a)[mask(a)].std() > 5  # the studio is not uniform
    flat = render(
        m, order=order, env_map="uniform", lights=None, ambient=0.0, diffuse=1.0, window_size=SIZE
    )
    assert np.abs(flat[mask(flat)].astype(int) - round(0.85 * 255)).max() <= 2


def test_env_map_relight_back_to_directional_lights(ball):
    *_, m, order = ball
    with MescherScene(window_size=SIZE) as scene:
        scene.add(m, order=order)
        scene.relight([(1, 1, 1)])
        first = scene.screenshot()
        scene.relight(None, env_map="sky")
        sky = scene.screenshot()
        scene.relight([(1, 1, 1)])
        again = scene.screenshot()
    assert np.abs(luminance(first) - luminance(sky)).mean() > 5
    np.testing.assert_array_equal(first, again)


# -- image regression: tests/pyvista_views/test_images.py (pytest-pyvista verify_image_cache) --


def test_real_depth_order_from_the_embedding_gives_the_meshs_picture(ball):
    from meschers_igl import DepthOrder

    V, F, m, _ = ball
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    a = render(m, order, lights=[(1, -1, 1)], window_size=SIZE)
    b = render((V, F), lights=[(1, -1, 1)], window_size=SIZE)
    both = mask(a) & mask(b)
    assert iou(mask(a), mask(b)) >= 0.98
    assert np.corrcoef(luminance(a)[both], luminance(b)[both])[0, 1] >= 0.95


@pytest.mark.antialiased
def test_edges_are_anti_aliased_by_default(ball):
    """By default the outline blends into the background: the default picture differs from
    the pixel-exact one (``anti_aliasing=False``) along the outline; inside, only face edges
    are softened (a small mean change)."""
    from scipy.ndimage import binary_dilation, binary_erosion

    V, F, m, order = ball
    smooth = render(m, order, lights=[(0, 0, 1)], window_size=SIZE)
    hard = render(m, order, lights=[(0, 0, 1)], window_size=SIZE, anti_aliasing=False)
    figure = mask(hard)
    outline = binary_dilation(figure, iterations=2) & ~binary_erosion(figure, iterations=2)
    changed = np.abs(luminance(smooth) - luminance(hard)) > 8
    assert changed.sum() > 0.5 * 4 * np.sqrt(figure.sum())  # about the outline's length
    assert changed[outline].mean() > 5 * changed[~outline].mean()
    assert np.abs(luminance(smooth) - luminance(hard))[~outline].mean() < 2


def test_a_misspelt_keyword_is_refused_with_a_suggestion():
    from meschers_igl import gallery

    m = gallery.get_model("penrose_triangle").mescher
    with pytest.raises(MescherError, match=r"lihgts: expected a keyword .*did you mean 'lights'"):
        render(m, lihgts=[(1.0, 1.0, 1.0)], window_size=(32, 32))
    with pytest.raises(MescherError, match=r"colour: expected a keyword .*did you mean 'color'"):
        render(m, colour="red", window_size=(32, 32))
