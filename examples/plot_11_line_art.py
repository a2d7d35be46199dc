"""
Line art of impossible figures
==============================

Impossible figures are known as drawings. A mescher has what a drawing needs: each triangle's
local shape (its normal, hence the dihedral angle of every edge, from zeta) and a depth order
that says which face is in front where. :func:`meschers_igl.lines.line_drawing` computes the
lines a person draws -- outlines against the paper, occlusion lines where one part passes in
front of another (stopping exactly where they go behind a face: T-junctions), creases, and the
occluding contours of smooth meschers -- and :func:`pyvista_views.draw` writes them as an SVG
or PDF with thick outlines and thin creases, one path per joined polyline.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import pyvista_views
from meschers_igl.gallery import get_model, list_models
from meschers_igl.lines import line_drawing
from pyvista_views.camera import default_bounds
from pyvista_views.lineart import overlay, rasterize, to_svg

SIZE = (360, 360)
out = Path(tempfile.mkdtemp())

# %%
# The six gallery figures: the shaded render and the line art of the same view. Every SVG is
# a file an illustrator can open (groups ``outline``, ``occlusion``, ``crease``).
fig, axes = plt.subplots(2, 6, figsize=(18, 6.4))
for k, name in enumerate(list_models()):
    g = get_model(name)
    m, order = g.mescher, g.order
    if name == "impossibagel":  # smooth: Loop-subdivided, interpolated contours
        m, order = m.subdivide(2, scheme="loop", order=order)
    lines = line_drawing(m, order)
    bounds = default_bounds(lines.box, SIZE)
    svg = to_svg(lines, out / f"{name}.svg", window_size=SIZE, bounds=bounds)
    shaded = pyvista_views.render(m, order, window_size=SIZE, bounds=bounds, anti_aliasing=True)
    axes[0, k].imshow(shaded)
    axes[1, k].imshow(rasterize(svg, SIZE))
    axes[0, k].set_title(name.replace("_", " "))
    n = np.bincount(lines.kind[lines.visible], minlength=3)
    axes[1, k].set_xlabel(f"{n[0]} outlines, {n[1]} occlusion lines, {n[2]} creases")
for ax in axes.ravel():
    ax.set_xticks([])
    ax.set_yticks([])
fig.tight_layout()

# %%
# Hidden lines on request, dashed and grey under the visible ones, and the lines over a render
# with the same framing (:func:`pyvista_views.lineart.overlay`).
g = get_model("impossible_cube")
hidden = line_drawing(g.mescher, g.order, hidden=True)
bounds = default_bounds(hidden.box, SIZE)
fig, axes = plt.subplots(1, 2, figsize=(8, 4.2))
svg = to_svg(hidden, window_size=SIZE, bounds=bounds, hidden="dashed")
axes[0].imshow(rasterize(svg, SIZE))
axes[0].set_title('hidden="dashed"')
axes[1].imshow(overlay(g.mescher, g.order, window_size=SIZE, lines=hidden, lights=[(1, 1, 1)]))
axes[1].set_title("overlay on the render")
for ax in axes:
    ax.set_axis_off()
fig.tight_layout()
print("SVG files in", out, sorted(p.name for p in out.glob("*.svg")))
