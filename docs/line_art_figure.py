"""``docs/images/line_art.png``: the six gallery figures as line art above their shaded renders.

python docs/line_art_figure.py

Each drawing is :func:`pyvista_views.draw`'s SVG (outlines thick, occlusion lines medium,
creases thin; visibility from the depth order) rasterized by cairosvg at the render's framing;
the impossibagel is Loop-subdivided twice, so its outline and contours are interpolated curves.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from meschers_igl import gallery
from meschers_igl.lines import line_drawing
from pyvista_views import render
from pyvista_views.camera import default_bounds
from pyvista_views.lineart import rasterize, to_svg

OUT = Path(__file__).resolve().parent / "images" / "line_art.png"
TILE = (300, 300)


def main() -> Path:
    columns = []
    for name in gallery.list_models():
        g = gallery.get_model(name)
        m, order = g.mescher, g.order
        if name == "impossibagel":
            m, order = m.subdivide(2, scheme="loop", order=order)
        lines = line_drawing(m, order)
        bounds = default_bounds(lines.box, TILE)
        art = rasterize(to_svg(lines, window_size=TILE, bounds=bounds), TILE)[..., :3]
        shaded = render(m, order, window_size=TILE, bounds=bounds, anti_aliasing=True)
        label = Image.new("RGB", (TILE[0], 26), "white")
        try:
            font = ImageFont.truetype("DejaVuSans.ttf", 15)
        except OSError:
            font = ImageFont.load_default()
        ImageDraw.Draw(label).text((8, 5), name.replace("_", " "), fill="black", font=font)
        columns.append(np.concatenate([np.asarray(label), art, shaded], axis=0))
    OUT.parent.mkdir(exist_ok=True)
    Image.fromarray(np.concatenate(columns, axis=1)).save(OUT)
    return OUT


if __name__ == "__main__":
    print(f"wrote {main()}")
