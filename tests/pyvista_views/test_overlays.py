"""Paths, loops and points are drawn only on the visible surface (pyvista_views.overlays).

The oracle is the CPU painter (:func:`meschers_igl.painter.visible_faces`), not the GL face map
the renderer clips with: a sample of a polyline is visible when the painter shows its face, or
a face sharing a corner with it, within one pixel; an overlay pixel is on a hidden layer when it
is farther than half a line width (plus 1 px) from every visible sample.  Drawing every piece (``hidden="dashed"``, the picture without
clipping) must fail the same measure: the test can fail.
"""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import requires_gl
from scipy.spatial import cKDTree

from meschers_igl.gallery import get_model
from meschers_igl.painter import visible_faces
from pyvista_views import render
from pyvista_views.camera import default_bounds, xy_box
from pyvista_views.overlays import clip_polyline, place_labels

pytestmark = requires_gl

SIZE = 320
WIDTH = 3.0


@pytest.fixture(scope="module", params=["penrose_triangle", "impossible_cube", "impossibagel"])
def figure(request):
    from meschers_igl.geodesic import shortest_loops

    g = get_model(request.param)
    m, order = g.mescher.subdivide(1, order=g.order)
    d = m.geodesic_distance(0)
    target = int(np.flatnonzero(np.isfinite(d))[np.nanargmax(np.where(np.isfinite(d), d, -1))])
    paths = [m.shortest_path(0, target), *shortest_loops(m)]
    bounds = default_bounds(xy_box(m.xy), (SIZE, SIZE))
    painter = visible_faces(m, order, size=SIZE, bounds=bounds)
    return request.param, m, order, paths, bounds, painter


def _samples(path, bounds, step_px=0.25):
    """Points along the path every ``step_px`` pixels (pixel coordinates) and their faces."""
    xy, faces = np.asarray(path.xy), np.asarray(path.faces)
    px = (bounds[1] - bounds[0]) / SIZE
    out, fs = [], []
    for k in range(xy.shape[0] - 1):
        n = max(int(np.ceil(np.linalg.norm(xy[k + 1] - xy[k]) / (step_px * px))), 1)
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        out.append(xy[k] + t * (xy[k + 1] - xy[k]))
        fs.append(np.full(n + 1, faces[k]))
    P = np.vstack(out)
    col = (P[:, 0] - bounds[0]) / px
    row = (bounds[3] - P[:, 1]) / px
    return np.column_stack([row, col]), np.concatenate(fs)


def _shares_corner(F, f, g):
    return (F[f][:, :, None] == F[g][:, None, :]).any(axis=(1, 2))


def overlay_pixels_on_hidden_layers(m, paths, painter, bounds, image, plain, levels=0):
    """Overlay pixels not explained by a piece of a path on the face the painter shows there
    (an overlay pixel: one differing from ``plain`` by more than ``levels`` in some channel)."""
    F = np.asarray(m.F)
    diff = np.abs(image.astype(np.int16) - plain.astype(np.int16)).max(axis=-1)
    drawn = diff > levels
    rows, cols = np.nonzero(drawn)
    if rows.size == 0:
        return 0, 0
    S, fs = zip(*(_samples(p, bounds) for p in paths))
    S, fs = np.vstack(S), np.concatenate(fs)
    # a sample is on the visible surface when the painter shows its face's one-ring near it
    r = np.clip(np.floor(S[:, 0]).astype(int), 0, SIZE - 1)
    c = np.clip(np.floor(S[:, 1]).astype(int), 0, SIZE - 1)
    seen = np.zeros(S.shape[0], dtype=bool)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            g = painter[np.clip(r + dr, 0, SIZE - 1), np.clip(c + dc, 0, SIZE - 1)]
            ok = g >= 0
            seen[ok] |= _shares_corner(F, fs[ok], g[ok])
    if not seen.any():
        return rows.size, rows.size
    centres = np.column_stack([rows + 0.5, cols + 0.5])
    # farther than half a line width (+1 px of anti-aliasing) from every visible sample
    dist, _ = cKDTree(S[seen]).query(centres)
    bad = int((dist > WIDTH / 2 + 1.0).sum())
    return bad, rows.size


def test_overlay_pixels_on_hidden_layers_are_zero(figure):
    name, m, order, paths, bounds, painter = figure
    kw = dict(window_size=(SIZE, SIZE), bounds=bounds, lights=[(0, 0, 1)])
    plain = render(m, order, **kw)
    marks = [{"path": p, "color": "red", "width": WIDTH} for p in paths]
    image = render(m, order, paths=marks, **kw)
    bad, total = overlay_pixels_on_hidden_layers(m, paths, painter, bounds, image, plain)
    assert total > 200, name  # the paths are drawn where they are visible
    assert bad == 0, f"{name}: {bad} of {total} overlay pixels on hidden layers"
    # drawing the hidden pieces too (dashed) puts pixels on hidden layers: the measure can fail
    dashed = [{**mk, "hidden": "dashed"} for mk in marks]
    broken = render(m, order, paths=dashed, **kw)
    bad_b, _ = overlay_pixels_on_hidden_layers(m, paths, painter, bounds, broken, plain)
    assert bad_b > 20, f"{name}: hidden pieces should be measurable, found {bad_b}"


def test_clip_polyline_keeps_the_visible_share_of_each_path(figure):
    """With the painter's face map: every path has visible pieces, and every figure hides a
    part of some path (the clipping has something to do)."""
    name, m, order, paths, bounds, painter = figure
    F = np.asarray(m.F)
    hidden_somewhere = False
    for p in paths:
        p0, p1, vis, _ = clip_polyline(np.asarray(p.xy), np.asarray(p.faces), F, painter, bounds)
        hidden_somewhere |= bool((~vis).any())
        assert vis.any(), name
    assert hidden_somewhere, name


def test_point_discs_never_cover_the_background():
    g = get_model("penrose_triangle")
    m, order = g.mescher, g.order
    bounds = default_bounds(xy_box(m.xy), (SIZE, SIZE))
    painter = visible_faces(m, order, size=SIZE, bounds=bounds)
    xy = np.asarray(m.xy)
    # outline corners: the extreme vertices of the figure (a disc there is half off the figure)
    corners = np.unique([np.argmin(xy[:, 0]), np.argmax(xy[:, 0]), np.argmin(xy[:, 1])])
    kw = dict(window_size=(SIZE, SIZE), bounds=bounds, lights=[(0, 0, 1)])
    plain = render(m, order, **kw)
    image = render(m, order, points={"vertices": corners, "color": "red", "radius": 8}, **kw)
    drawn = np.any(image != plain, axis=-1)
    assert drawn.sum() > 3 * 50  # three discs, each at least a quarter visible
    off = drawn & (painter < 0)
    assert off.sum() <= 0.02 * drawn.sum(), off.sum()  # anti-aliased rim pixels at most


def test_place_labels_never_overlap_and_stay_inside():
    rng = np.random.default_rng(1)
    anchors = rng.uniform(0, 200, size=(12, 2))
    anchors[:6] = [100, 100]  # six labels on one spot
    sizes = [(40, 14)] * 12
    corners = place_labels(anchors, sizes, (200, 200))
    boxes = np.column_stack([corners, corners + np.array([40.0, 14.0])])
    assert (boxes[:, 0] >= 0).all() and (boxes[:, 2] <= 200).all()
    assert (boxes[:, 1] >= 0).all() and (boxes[:, 3] <= 200).all()
    for i in range(12):
        for j in range(i):
            w = min(boxes[i, 2], boxes[j, 2]) - max(boxes[i, 0], boxes[j, 0])
            h = min(boxes[i, 3], boxes[j, 3]) - max(boxes[i, 1], boxes[j, 1])
            assert w <= 0 or h <= 0, (i, j)


def test_refine_path_puts_every_piece_in_a_child_of_its_face():
    """Midpoint children tile their parent: each piece of the carried path lies in its child
    (barycentric coordinates of its midpoint >= 0), that child's parent holds the original
    segment, and the pieces add up to the original polyline."""
    from pyvista_views.overlays import refine_path

    m = get_model("penrose_triangle").mescher
    p = m.shortest_path(0, 30)
    xy0, f0 = np.asarray(p.xy), np.asarray(p.faces)
    for levels in (1, 2):
        mv, parent = m.subdivide(levels, return_face_parent=True)
        xy, faces = refine_path(xy0, f0, mv.xy, mv.F, parent)
        assert xy.shape[0] > xy0.shape[0]  # the path crosses children
        T = np.asarray(mv.xy)[np.asarray(mv.F)[faces[:-1]]]
        mid = 0.5 * (xy[:-1] + xy[1:])
        e1, e2, r = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0], mid - T[:, 0]
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        b1 = (r[:, 0] * e2[:, 1] - r[:, 1] * e2[:, 0]) / det
        b2 = (e1[:, 0] * r[:, 1] - e1[:, 1] * r[:, 0]) / det
        assert min(b1.min(), b2.min(), (1 - b1 - b2).min()) >= -1e-9
        # each piece lies in a child of the face holding its part of the original polyline
        arc0 = np.cumsum(np.linalg.norm(np.diff(xy0, axis=0), axis=1))
        step = np.linalg.norm(np.diff(xy, axis=0), axis=1)
        seg = np.searchsorted(arc0, np.cumsum(step) - 0.5 * step)
        np.testing.assert_array_equal(parent[faces[:-1]], f0[seg])
        np.testing.assert_allclose(step.sum(), arc0[-1], rtol=1e-12)


def test_geodesic_cli_draws_its_path_only_on_visible_layers(tmp_path):
    """``meschers geodesic -o``: the path's pixels in the written PNG all lie near a piece of
    the path on the face the CPU painter shows (the coarse painter: midpoint children stay
    inside their parents and keep their parents' order, so the visible coarse face is the
    parent of the visible child).  The path 0 -> 35 on the triangle runs 172 px on the visible
    surface and 71 px on hidden sheets (painter, 320 px): drawn on top, as a plain screen
    polyline, 100+ of its pixels lie on hidden layers."""
    from PIL import Image

    from meschers.cli import main
    from meschers.figures import geodesic_picture

    g = get_model("penrose_triangle")
    m, order = g.mescher, g.order
    out = tmp_path / "geo.png"
    size = f"{SIZE},{SIZE}"
    args = ["geodesic", "penrose_triangle", "--source", "0", "--target", "35"]
    assert main([*args, "-o", str(out), "--size", size]) == 0
    image = np.array(Image.open(out).convert("RGB"))
    path = m.shortest_path(0, 35)
    d = m.geodesic_distance(0)
    plain = geodesic_picture(m, order, d, path, (0, 35), (SIZE, SIZE), 12, draw_path=False)
    bounds = default_bounds(xy_box(m.xy), (SIZE, SIZE))
    painter = visible_faces(m, order, size=SIZE, bounds=bounds)
    # the end dots are measured by test_point_discs_never_cover_the_background: left out
    ends = np.asarray(path.xy)[[0, -1]]
    rows, cols = np.mgrid[0:SIZE, 0:SIZE]
    px = (bounds[1] - bounds[0]) / SIZE
    for x, y in ends:
        near = np.hypot(cols + 0.5 - (x - bounds[0]) / px, rows + 0.5 - (bounds[3] - y) / px) < 8
        image[near] = plain[near]
    # the CLI supersamples: its filter leaves +-1-level tails just past the line's half width
    bad, total = overlay_pixels_on_hidden_layers(m, [path], painter, bounds, image, plain, 2)
    assert total > 300  # the visible part is drawn (172 px long, 3 px wide)
    assert bad == 0, f"{bad} of {total} path pixels on hidden layers"
