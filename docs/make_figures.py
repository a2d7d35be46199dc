"""Figures for the README (fixed camera; re-run after changing the renderer or the gallery).

python docs/make_figures.py                  # every figure
python docs/make_figures.py gallery          # only the named ones (gallery, closed_solid,
                                             # hidden_gap_cube, reutersvard_relief,
                                             # exact_geodesic)

``gallery.png``: every gallery model under two lights and its depth potential ``z`` (the exact
part of its Hodge decomposition). ``closed_solid.png``: a closed U-shaped solid (an artist's
Penrose tribar, sphere topology) before and after :meth:`Mescher.from_model`.
``hidden_gap_cube.png`` and ``reutersvard_relief.png``: a real model seen obliquely, its
z-buffer from its view, and its mescher (a hidden gap glued; perceived right angles).
``exact_geodesic.png``: exact geodesic distance on the impossibagel against the heat method.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from meschers_igl import Mescher, gallery
from meschers_igl.obtain import model_to_mescher
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


def _tests_builders():
    # the artist models are built the way the tests build them (not by the code under test)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "meschers_igl"))


def _model_panels(V, F, side, m, order, captions: list[str], name: str, S: int = 360) -> Path:
    """Three panels with captions: the 3D model z-buffered from ``side`` (a real object), the
    model z-buffered from its view (ISO), and the mescher ``m`` in ``order``."""
    from visible_models import ISO_UP, ISO_VIEW

    lights = [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4)]
    R = view_frame(ISO_VIEW, ISO_UP)

    def framed(C):
        lo, hi = C[:, :2].min(0), C[:, :2].max(0)
        c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
        return {"bounds": (c[0] - h, c[0] + h, c[1] - h, c[1] + h), "lights": lights,
                "window_size": (S, S)}  # fmt: skip

    Co, C = V @ view_frame(side, R[1]).T, V @ R.T
    panels = [render((Co, F), **framed(Co)), render((C, F), **framed(C)),
              render(m, order=order, **framed(C))]  # fmt: skip
    img = Image.new("RGB", (3 * S, S + 40), "white")
    draw = ImageDraw.Draw(img)
    for k, (panel, text) in enumerate(zip(panels, captions)):
        img.paste(Image.fromarray(panel), (k * S, 0))
        draw.text((k * S + 10, S + 10), text, fill="black", font=_font())
    path = OUT / f"{name}.png"
    img.save(path)
    return path


def hidden_gap_cube_figure() -> Path:
    _tests_builders()
    from visible_models import ISO_UP, ISO_VIEW, hidden_gap_cube, triangulate

    V, P, gap = hidden_gap_cube()
    F = triangulate(P)
    R = view_frame(ISO_VIEW, ISO_UP)
    t, u = np.radians(18.0), (R[0] + 0.6 * R[1]) / np.linalg.norm(R[0] + 0.6 * R[1])
    m, order, _ = model_to_mescher(V, F, view="auto")
    captions = ["the closed frame (oblique view)", "its z-buffer from its view",
                f"the mescher: period {np.abs(m.periods()).max():.4f} (gap {gap:.4f})"]  # fmt: skip
    return _model_panels(V, F, np.cos(t) * R[2] + np.sin(t) * u, m, order, captions,
                         "hidden_gap_cube")  # fmt: skip


def reutersvard_relief_figure() -> Path:
    _tests_builders()
    from relief_models import reutersvard_relief
    from visible_models import ISO_UP, ISO_VIEW, triangulate

    V, P, gap = reutersvard_relief()
    F = triangulate(P)
    R = view_frame(ISO_VIEW, ISO_UP)
    t = np.radians(70.0)
    m, order, _ = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP, perceive="manhattan")
    captions = ["the relief, 70 degrees aside", "its z-buffer from its view",
                f"as perceived: period {np.abs(m.periods()).max():.4f}"]  # fmt: skip
    return _model_panels(V, F, np.cos(t) * R[2] + np.sin(t) * R[0], m, order, captions,
                         "reutersvard_relief")  # fmt: skip


def exact_geodesic_figure() -> Path:
    """The impossibagel (a torus whose depth climbs around its hole), subdivided: exact distance
    from one vertex (window propagation on the intrinsic mesh), the heat method's default, and
    where they differ."""
    from meschers_igl.geodesic.exact import ExactGeodesicSolver
    from meschers_igl.geodesic.heat import HeatGeodesicSolver

    gm = gallery.get_model("impossibagel")
    m, order = gm.mescher.subdivide(1, order=gm.order)
    source = int(np.argmin(np.asarray(m.xy)[:, 0]))  # the leftmost vertex
    exact = ExactGeodesicSolver(m).distance(source)
    heat_solver = HeatGeodesicSolver(m)
    heat = heat_solver.distance(source)
    top = float(exact.max())
    err = np.abs(heat - exact) / top
    from meschers.figures import Colorbar, compose, overlay
    from pyvista_views.camera import default_bounds, xy_box

    size = (TILE + 40, TILE)
    bounds = default_bounds(xy_box(np.asarray(m.xy)), size)
    kw = {"order": order, "lights": [(0.4, 0.6, 1.0)], "window_size": size, "bounds": bounds,
          "shading": "smooth", "show_scalar_bar": False}  # fmt: skip
    dot = [(np.asarray(m.xy)[[source]], "white", 6)]
    cmap = "viridis"
    cells = [
        render(m, scalars=exact, clim=(0, top), cmap=cmap, isolines=12, **kw),
        render(m, scalars=heat, clim=(0, top), cmap=cmap, isolines=12, **kw),
    ]
    dist = compose([[overlay(c, bounds, points=dot) for c in cells]],
                   col_labels=["exact (window propagation)", f"heat method (auto = {heat_solver.method})"],
                   colorbar=Colorbar(cmap, 0.0, top, "geodesic distance"))  # fmt: skip
    diff = render(m, scalars=err, clim=(0, float(err.max())), cmap="magma", **kw)
    diff = compose([[overlay(diff, bounds, points=dot)]],
                   col_labels=[f"difference: mean {err.mean():.2%}, max {err.max():.2%}"],
                   colorbar=Colorbar("magma", 0.0, float(err.max()), "|heat - exact| / max"))  # fmt: skip
    dist, diff = np.asarray(dist.convert("RGB")), np.asarray(diff.convert("RGB"))
    h = max(dist.shape[0], diff.shape[0])
    pad = lambda a: np.pad(a, ((0, h - a.shape[0]), (0, 0), (0, 0)), constant_values=255)  # noqa: E731
    img = Image.fromarray(np.concatenate([pad(dist), pad(diff)], axis=1))
    path = OUT / "exact_geodesic.png"
    img.save(path)
    return path


FIGURES = {
    "gallery": gallery_figure,
    "closed_solid": closed_solid_figure,
    "hidden_gap_cube": hidden_gap_cube_figure,
    "reutersvard_relief": reutersvard_relief_figure,
    "exact_geodesic": exact_geodesic_figure,
}


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
