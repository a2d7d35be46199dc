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


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--size", type=int, default=1024)
    args = ap.parse_args(argv)
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
