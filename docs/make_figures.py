"""Figures for the README (fixed camera; re-run after changing the renderer or the gallery).

python docs/make_figures.py                  # every figure
python docs/make_figures.py gallery          # only the named ones (gallery, closed_solid)

``gallery.png``: every gallery model under two lights and its depth potential ``z`` (the exact
part of its Hodge decomposition). ``closed_solid.png``: a closed U-shaped solid (an artist's
Penrose tribar, sphere topology) before and after :meth:`Mescher.from_model`.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from meschers_igl import Mescher, gallery
from meschers_igl.models import model_to_mescher
from meschers_igl.operators import view_frame
from pyvista_views import render

OUT = Path(__file__).resolve().parent / "images"
LIGHTS = [(0.4, 0.6, 1.0), (-0.8, 0.3, 0.6)]
TILE = 320


def _font(size: int = 15):
    try:
        return ImageFont.truetype("DejaVuSans.ttf", size)
    except OSError:
        return ImageFont.load_default()


def gallery_figure() -> Path:
    rows = []
    for name in gallery.list_models():
        gm = gallery.get_model(name)
        m, order = gm.mescher, gm.order
        tiles = [
            render(m, order=order, lights=[light], window_size=(TILE, TILE)) for light in LIGHTS
        ]
        tiles.append(
            render(
                m,
                order=order,
                scalars=m.hodge().z,
                scalar_bar_title="depth z",
                window_size=(TILE + 120, TILE),
            )
        )
        row = Image.fromarray(np.concatenate(tiles, axis=1))
        label = Image.new("RGB", (row.width, 24), "white")
        ImageDraw.Draw(label).text((8, 4), name.replace("_", " "), fill="black", font=_font())
        rows.append(np.concatenate([np.asarray(label), np.asarray(row)], axis=0))
    path = OUT / "gallery.png"
    Image.fromarray(np.concatenate(rows, axis=0)).save(path)
    return path


def closed_solid_figure() -> Path:
    # the U-solid is built the way the tests build artist models (half-spaces, quads)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "meschers_igl"))
    from visible_models import ISO_UP, ISO_VIEW, triangulate, u_tribar

    V, P, gap = u_tribar()
    F = triangulate(P)
    R = view_frame(ISO_VIEW, ISO_UP)
    C = V @ R.T
    lo, hi = C[:, :2].min(0), C[:, :2].max(0)
    ctr, h = 0.5 * (lo + hi), 0.56 * float((hi - lo).max())
    bounds = (ctr[0] - h, ctr[0] + h, ctr[1] - h, ctr[1] + h)
    S, lights = 360, [(0.45, 0.75, 1.0)]
    side = Mescher.from_mesh(V, F, view=(1.0, -0.35, 0.45), up=(0, 0, 1))  # the 3D solid, oblique
    before = Mescher.from_mesh(V, F, view=ISO_VIEW, up=ISO_UP)
    m, order, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)
    from meschers_igl import DepthOrder

    side_order = DepthOrder.from_embedding(
        side, (V @ view_frame((1.0, -0.35, 0.45), (0, 0, 1))[2])[F]
    )
    panels = [
        render(side, order=side_order, lights=lights, window_size=(S, S)),
        render(before, order=DepthOrder.from_embedding(before, C[:, 2][F]), lights=lights,
               window_size=(S, S), bounds=bounds),
        render(m, order=order, lights=lights, window_size=(S, S), bounds=bounds),
    ]  # fmt: skip
    img = Image.new("RGB", (3 * S, S + 70), "white")
    for k, p in enumerate(panels):
        img.paste(Image.fromarray(p), (k * S, 0))
    draw = ImageDraw.Draw(img)
    j = report.junctions[0]
    x = (j.position[0] - bounds[0]) / (bounds[1] - bounds[0]) * S + 2 * S
    y = (bounds[3] - j.position[1]) / (bounds[3] - bounds[2]) * S
    draw.ellipse([x - 16, y - 16, x + 16, y + 16], outline=(220, 30, 30), width=3)
    captions = [
        "a closed U-shaped solid (oblique view)",
        f"from (1,1,1), from_mesh: {before.periods().size} periods",
        f"from_model: period {abs(m.periods()).max():.4f}",
    ]
    for k, text in enumerate(captions):
        draw.text((k * S + 10, S + 10), text, fill="black", font=_font())
    draw.text((2 * S + 10, S + 35), f"(the depth gap {gap:.4f}); glued junction circled",
              fill="black", font=_font())  # fmt: skip
    path = OUT / "closed_solid.png"
    img.save(path)
    return path


FIGURES = {"gallery": gallery_figure, "closed_solid": closed_solid_figure}


def main(names: list[str] | None = None) -> None:
    """Make the named figures (default: all of :data:`FIGURES`)."""
    names = list(FIGURES) if not names else names
    unknown = sorted(set(names) - set(FIGURES))
    if unknown:
        raise SystemExit(f"figures: expected some of {', '.join(FIGURES)}, found {unknown}")
    OUT.mkdir(exist_ok=True)
    for name in names:
        print(f"wrote {FIGURES[name]()}")


if __name__ == "__main__":
    main(sys.argv[1:])
