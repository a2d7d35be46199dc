"""Line drawing cost against the first rendered frame of the same mescher.

A line drawing (``meschers_igl.lines.line_drawing``: sources, exact visibility against the
depth order, kinds, joined polylines, plus the SVG text of ``pyvista_views.draw.to_svg``) is
timed against ``pyvista_views.render`` of the same mescher and order at 1024^2 (scene, plotter,
lights, first screenshot), in one process.  Models, at about 100k faces:

- the impossibagel, Loop-subdivided three times (131k faces; smooth: interpolated contours);
- the Penrose stairs, midpoint-subdivided three times (90k faces; creases and occlusions
  along mesh edges, every bar edge made of many mesh edges).

The one-off costs both share (the order's linear extension, the mescher's cached normals) are
paid before timing.  The machine is shared and its load moves by 2x within a minute, so each
repetition times the drawing and the render back to back (which one goes first alternates);
the ratio printed is the median of the paired ratios over ``--repeat`` (5) repetitions.
Target: <= 2x.  ``python benchmarks/bench_draw.py [--repeat N] [--size S]``.

``--table`` prints instead the recall/precision table of the drawings against the painter's
picture (the SVG rasterized by cairosvg at 512 px against the line pixels of the painter's
visible-face map, 1.5 px): the gallery (as is, and Loop-subdivided once and twice), the
ParadoxToolkit models and the development set (``../shared/real_models``) where present.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import pyvista_views
from meschers_igl.gallery import get_model
from meschers_igl.lines import line_drawing
from pyvista_views.lineart import to_svg


def models():
    g = get_model("impossibagel")
    m, o = g.mescher.subdivide(3, scheme="loop", order=g.order)
    yield "impossibagel, Loop x3", m, o
    g = get_model("penrose_stairs")
    m, o = g.mescher.subdivide(3, scheme="midpoint", order=g.order)
    yield "penrose_stairs, midpoint x3", m, o


def _scores(m, o, size=512):
    """(recall, precision) of the rasterized SVG against the painter's line pixels."""
    from scipy import ndimage

    from meschers_igl.line_pixels import visible_face_edges
    from meschers_igl.painter import visible_faces
    from pyvista_views.camera import default_bounds
    from pyvista_views.lineart import rasterize

    ld = line_drawing(m, o)
    bounds = default_bounds(ld.box, (size, size))
    gt = visible_face_edges(visible_faces(m, o, size=size, bounds=bounds), m, bounds)
    img = rasterize(to_svg(ld, window_size=(size, size), bounds=bounds, widths=1.0), (size, size))
    drawn = img[..., 0] < 128
    recall = float(np.mean(ndimage.distance_transform_edt(~drawn)[gt] <= 1.5))
    precision = float(np.mean(ndimage.distance_transform_edt(~gt)[drawn] <= 1.5))
    return recall, precision


def _table_models():
    import json
    from pathlib import Path

    from meschers.inputs import load_mescher, resolve
    from meschers_igl.gallery import list_models

    for name in list_models():
        g = get_model(name)
        yield "gallery", name, g.mescher, g.order
        for k in (1, 2) if name == "impossibagel" else (1,):
            m, o = g.mescher.subdivide(k, scheme="loop", order=g.order)
            yield f"gallery, Loop x{k}", name, m, o
    from meschers_igl.paradox import list_paradox_models

    for name in list_paradox_models():
        m, o = load_mescher(resolve(f"paradox:{name}", "model"))
        yield "ParadoxToolkit", name, m, o
    real = Path(__file__).resolve().parents[2] / "shared" / "real_models"
    if (real / "views.json").is_file():
        from meshlab_filters.convert import model_to_mescher

        for name, v in json.loads((real / "views.json").read_text()).items():
            if not name.startswith("_"):
                m, o = model_to_mescher(real / name, view=v["view"], up=v["up"])[:2]
                yield "development set", name, m, o


def table() -> None:
    """Print the recall/precision table (see the module notes)."""
    worst = 1.0
    print(f"{'set':22s} {'model':34s} {'faces':>7s} {'recall':>7s} {'precision':>9s}")
    for group, name, m, o in _table_models():
        r, p = _scores(m, o)
        worst = min(worst, r, p)
        print(f"{group:22s} {name:34s} {m.n_faces:7d} {r:7.4f} {p:9.4f}")
    print(f"lowest of all: {worst:.4f} (target >= 0.98)")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--table", action="store_true", help="recall/precision table instead")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.table:
        table()
        return
    size = (args.size, args.size)
    warnings.simplefilter("ignore")
    for label, m, o in models():
        m.face_normals(), m.vertex_normals(), o.linear_extension(warn=False)
        line_drawing(m, o)  # compiled joining walk, first call
        pyvista_views.render(m, o, window_size=(64, 64))  # GL context, first call

        def draw(m=m, o=o):
            t = time.perf_counter()
            ld = line_drawing(m, o)
            to_svg(ld, window_size=size)
            return time.perf_counter() - t, ld

        def render(m=m, o=o):
            t = time.perf_counter()
            pyvista_views.render(m, o, window_size=size)
            return time.perf_counter() - t

        ratios, td, tr = [], [], []
        for rep in range(args.repeat):
            if rep % 2:
                r = render()
                d, ld = draw()
            else:
                d, ld = draw()
                r = render()
            ratios.append(d / r)
            td.append(d)
            tr.append(r)
        print(
            f"{label}: {m.n_faces} faces, {ld.n_lines} polylines ({len(ld.points)} points): "
            f"draw {np.median(td):.3f} s, first frame {np.median(tr):.3f} s, "
            f"ratio {np.median(ratios):.2f}x (target <= 2x)"
        )


if __name__ == "__main__":
    main()
