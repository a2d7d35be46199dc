"""Line art files: SVG structure, PDF/PNG output, and the rasterized SVG against two oracles.

* the painter's visible-face map (:func:`meschers_igl.painter.visible_faces`, no GPU): every
  line pixel of the map (:func:`meschers_igl.lines.visible_face_edges`) lies within 1.5 px of
  a drawn pixel of the SVG as cairosvg rasterizes it (recall) and every drawn pixel within
  1.5 px of one (precision), for the gallery, ParadoxToolkit and development-set models;
* on an ordinary mesh, VTK's z-buffer: the renderer's own face-id image of the 3D mesh
  (:func:`pyvista_views.gl.face_id_image`) gives the hidden-line drawing the SVG must equal.
"""

from __future__ import annotations

import json
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from pvv_helpers import requires_gl
from scipy import ndimage

from meschers_igl import DepthOrder, Mescher, MescherError, shapes
from meschers_igl.gallery import get_model, list_models
from meschers_igl.line_pixels import visible_face_edges
from meschers_igl.lines import KINDS, line_drawing
from meschers_igl.painter import visible_faces
from pyvista_views.camera import default_bounds
from pyvista_views.lineart import DEFAULT_WIDTHS, draw, overlay, rasterize, to_svg

cairosvg = pytest.importorskip("cairosvg")

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"
SVG = "{http://www.w3.org/2000/svg}"
SIZE = 512


def _squares():
    sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=float)
    V = np.concatenate([np.c_[sq, np.zeros(4)], np.c_[sq + 1.0, np.ones(4)]])
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    m = Mescher.from_mesh(V, F)
    return m, DepthOrder.from_embedding(m, V[F][:, :, 2])


def scores(ld, faces_map, m, bounds, tol=1.5):
    """(recall, precision) of the SVG rasterized at the map's size against its line pixels."""
    H, W = faces_map.shape
    gt = visible_face_edges(faces_map, m, bounds)
    img = rasterize(to_svg(ld, window_size=(W, H), bounds=bounds, widths=1.0), (W, H))
    drawn = img[..., 0] < 128
    d_drawn = ndimage.distance_transform_edt(~drawn)
    d_gt = ndimage.distance_transform_edt(~gt)
    return float(np.mean(d_drawn[gt] <= tol)), float(np.mean(d_gt[drawn] <= tol))


def painter_scores(m, order, size=SIZE, **kw):
    ld = line_drawing(m, order, **kw)
    bounds = default_bounds(ld.box, (size, size))
    return scores(ld, visible_faces(m, order, size=size, bounds=bounds), m, bounds)


# ----------------------------------------------------------------------------- the file
def test_svg_groups_paths_widths_and_coordinates(tmp_path):
    m, order = _squares()
    ld = line_drawing(m, order, hidden=True)
    svg = draw(m, order, tmp_path / "squares.svg", window_size=(400, 400), bounds=(0, 4, 0, 4))
    assert (tmp_path / "squares.svg").read_text() == svg
    root = ET.fromstring(svg)
    assert root.get("width") == "400" and root.get("viewBox") == "0 0 400 400"
    groups = {g.get("id"): g for g in root.iter(f"{SVG}g")}
    assert set(groups) == {"outline", "occlusion"}  # no crease here; hidden lines omitted
    for name, g in groups.items():
        assert float(g.get("stroke-width")) == pytest.approx(DEFAULT_WIDTHS[name], abs=0.01)
        n_lines = int(np.sum(ld.visible & (ld.kind == KINDS.index(name))))
        assert len(list(g.iter(f"{SVG}path"))) == n_lines
    # the figure's outline: one closed path through the 8 corners, screen (x, y) -> (100 x,
    # 400 - 100 y) pixels
    (d,) = [p.get("d") for p in groups["outline"].iter(f"{SVG}path")]
    assert d.startswith("M") and d.endswith("Z")
    pts = {tuple(float(v) for v in c.split()) for c in d[1:-1].replace("L", ",").split(",")}
    assert pts == {
        (0, 400),
        (200, 400),
        (200, 300),
        (300, 300),
        (300, 100),
        (100, 100),
        (100, 200),
        (0, 200),
    }
    dashed = ET.fromstring(draw(m, order, hidden="dashed", bounds=(0, 4, 0, 4)))
    hidden = [g for g in dashed.iter(f"{SVG}g") if g.get("id") == "hidden"]
    assert len(hidden) == 1 and hidden[0].get("stroke-dasharray")


def test_pdf_and_png_files(tmp_path):
    g = get_model("penrose_triangle")
    draw(g.mescher, g.order, tmp_path / "p.pdf", window_size=(300, 200))
    assert (tmp_path / "p.pdf").read_bytes()[:5] == b"%PDF-"
    draw(g.mescher, g.order, tmp_path / "p.png", window_size=(300, 200))
    from PIL import Image

    img = np.asarray(Image.open(tmp_path / "p.png").convert("RGB"))
    assert img.shape == (200, 300, 3)
    dark = img.min(axis=2) < 128
    assert 0.01 < dark.mean() < 0.2  # lines on white


def test_bad_arguments(tmp_path):
    m, order = _squares()
    with pytest.raises(MescherError, match="path"):
        draw(m, order, tmp_path / "x.jpg")
    with pytest.raises(MescherError, match="widths"):
        draw(m, order, widths={"shadow": 1.0})
    with pytest.raises(MescherError, match="hidden"):
        draw(m, order, hidden="dotted")
    with pytest.raises(MescherError, match="lines"):
        to_svg("not lines")


# ------------------------------------------------------------------ the painter's picture
@pytest.mark.parametrize("name", list_models())
def test_gallery_svg_matches_the_painter(name):
    g = get_model(name)
    recall, precision = painter_scores(g.mescher, g.order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


@pytest.mark.parametrize(
    "name", ["impossible_cube", "penrose_stair", "penrose_triangle_block", "impossible_arch"]
)
def test_paradox_svg_matches_the_painter(name):
    from meschers.inputs import load_mescher, resolve

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order = load_mescher(resolve(f"paradox:{name}", "model"))
    recall, precision = painter_scores(m, order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


@pytest.mark.slow
@pytest.mark.skipif(not REAL.is_dir(), reason="development set absent")
def test_development_models_svg_matches_the_painter():
    from meshlab_filters.convert import model_to_mescher

    views = json.loads((REAL / "views.json").read_text())
    done = 0
    for name, v in views.items():
        if name.startswith("_"):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m, order = model_to_mescher(REAL / name, view=v["view"], up=v["up"])[:2]
        recall, precision = painter_scores(m, order)
        assert recall >= 0.98 and precision >= 0.98, (name, recall, precision)
        done += 1
    assert done == 7


def test_loop_subdivided_svg_matches_the_painter():
    g = get_model("impossibagel")
    m, order = g.mescher.subdivide(2, scheme="loop", order=g.order)
    recall, precision = painter_scores(m, order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


# --------------------------------------------------------------------------- the z-buffer
@requires_gl
@pytest.mark.render
@pytest.mark.parametrize("tilt", [60.0, 75.0])
def test_ordinary_mesh_equals_its_z_buffer_hidden_line_drawing(tilt):
    from pyvista_views.render import render_scene

    V, F = shapes.torus(48, 20)
    # seen obliquely: the near side of the tube hides the hole's far rim, whose contour ends
    t, u = np.radians(tilt), np.radians(17.0)
    Rx = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    Rz = np.array([[np.cos(u), -np.sin(u), 0], [np.sin(u), np.cos(u), 0], [0, 0, 1]])
    V = V @ (Rx @ Rz).T
    m = Mescher.from_mesh(V, F)
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    ld = line_drawing(m, order, contours="mesh", crease_angle=25.0)
    bounds = default_bounds(ld.box, (SIZE, SIZE))
    with render_scene((V, F), window_size=(SIZE, SIZE), bounds=bounds) as scene:
        layer = scene.layers[0]
        zbuffer_faces = layer.face_map(scene.plotter, bounds)
    assert (zbuffer_faces >= 0).mean() > 0.2
    gt = visible_face_edges(zbuffer_faces, m, bounds, crease_angle=25.0)
    img = rasterize(to_svg(ld, window_size=(SIZE, SIZE), bounds=bounds, widths=1.0), (SIZE,) * 2)
    drawn = img[..., 0] < 128
    d_drawn = ndimage.distance_transform_edt(~drawn)
    d_gt = ndimage.distance_transform_edt(~gt)
    recall, precision = np.mean(d_drawn[gt] <= 1.5), np.mean(d_gt[drawn] <= 1.5)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


@requires_gl
@pytest.mark.render
def test_overlay_lines_sit_on_the_render_edges():
    g = get_model("penrose_triangle")
    size = (360, 300)
    plain = overlay(g.mescher, g.order, window_size=size, widths=0.001)  # lines invisible
    lined = overlay(g.mescher, g.order, window_size=size, color="#ff0000")
    assert plain.shape == lined.shape == (300, 360, 3)
    red = (lined[..., 0] > 200) & (lined[..., 1] < 80) & (lined[..., 2] < 80)
    figure = np.any(plain < 250, axis=2)
    edge = figure & ~ndimage.binary_erosion(figure)
    d = ndimage.distance_transform_edt(~red)
    assert np.mean(d[edge] <= 2.0) >= 0.98
    # the lines change the picture only next to them
    changed = np.any(np.abs(lined.astype(int) - plain.astype(int)) > 40, axis=2)
    assert np.mean(ndimage.distance_transform_edt(~red)[changed] <= 1.5) >= 0.99


def test_picture_without_cairosvg_draws_the_same_lines(monkeypatch):
    import pyvista_views.lineart as la

    g = get_model("penrose_triangle")
    lines = line_drawing(g.mescher, g.order)
    with_cairo = la.picture(lines, (240, 200)).min(axis=2) < 128

    def no_cairo(*args, **kwargs):
        raise ImportError("no cairosvg")

    monkeypatch.setattr(la, "rasterize", no_cairo)
    with_pil = la.picture(lines, (240, 200)).min(axis=2) < 128
    assert with_pil.shape == (200, 240) and with_pil.mean() > 0.01
    d = ndimage.distance_transform_edt(~with_cairo)
    assert np.mean(d[with_pil] <= 1.5) >= 0.98
    d = ndimage.distance_transform_edt(~with_pil)
    assert np.mean(d[with_cairo] <= 1.5) >= 0.98
