"""Figures for the README (fixed camera; re-run after changing the renderer).

python docs/make_figures.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from meschers_igl import gallery
from pyvista_views import render

OUT = Path(__file__).resolve().parent / "images"
LIGHTS = [(1, 1, 1), (-1, 0.5, 1), (0.3, -1, 0.8), (0, 0, 1)]


def main() -> None:
    OUT.mkdir(exist_ok=True)
    tiles = []
    for name in ["penrose_triangle", "penrose_stairs", "impossible_cube", "impossibagel"]:
        gm = gallery.get_model(name)
        m, order = gm.mescher, gm.order
        row = [
            render(m, order=order, lights=[light], window_size=(240, 240)) for light in LIGHTS[:2]
        ]
        row.append(render(m, order=order, scalars=m.hodge().z, window_size=(240, 240)))
        tiles.append(np.concatenate(row, axis=1))
    Image.fromarray(np.concatenate(tiles, axis=0)).save(OUT / "gallery.png")
    print(f"wrote {OUT / 'gallery.png'}")


if __name__ == "__main__":
    main()
