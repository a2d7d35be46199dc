"""Figures of the README and of ``docs/concepts.rst`` (fixed camera; re-run after changing the
renderer or the gallery).  Runs from any working directory and needs only the installed package.

python docs/make_figures.py                  # every figure
python docs/make_figures.py gallery          # only the named ones (gallery, closed_solid,
                                             # hidden_gap_cube, reutersvard_relief,
                                             # exact_geodesic, concepts)

``gallery.png``: every gallery model under two lights, with its line drawing over the shading
(the lines say where each step and bar ends when two faces share a shade), and its depth
potential ``z`` (the exact part of its Hodge decomposition). ``closed_solid.png``: a closed U-shaped solid (an artist's
Penrose tribar, sphere topology) before and after :meth:`Mescher.from_model`.
``hidden_gap_cube.png`` and ``reutersvard_relief.png``: a real model seen obliquely, its
z-buffer from its view, and its mescher (a hidden gap glued; perceived right angles).
``exact_geodesic.png``: exact geodesic distance on the impossibagel against the heat method.
``concepts``: ``docs/_static/concepts/{mescher,periods,order}.png`` (the Sphinx build only reads
the PNGs, so it needs no OpenGL).  The 3D solids are the package's own
(``meschers_igl/data/solids``: an OBJ and its view per model).
"""

from __future__ import annotations

import importlib.resources
import json
import sys
from pathlib import Path

import igl
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from meschers_igl import Mescher, gallery
from meschers_igl.obtain import model_to_mescher
from meschers_igl.operators import view_frame
from pyvista_views import render
from pyvista_views.lineart import overlay

OUT = Path(__file__).resolve().parent / "images"
CONCEPTS = Path(__file__).resolve().parent / "_static" / "concepts"
LIGHTS = [(0.4, 0.6, 1.0), (-0.8, 0.3, 0.6)]
TILE = 320
GALLERY_WIDTHS = {"outline": 1.2, "occlusion": 1.0, "crease": 0.6}


def _solid(name: str) -> tuple[np.ndarray, np.ndarray, dict]:
    """``(V, F, meta)`` of one of the package's 3D solids (meta: view, up, depth_gap, ...)."""
    root = importlib.resources.files("meschers_igl") / "data" / "solids"
    with importlib.resources.as_file(root / f"{name}.obj") as path:
        V, F = igl.read_triangle_mesh(str(path))
    meta = json.loads((root / f"{name}.json").read_text())
    return np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64), meta


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
        # A treads-toward-the-viewer flight of the stairs shows its steps only as lines: treads
        # of one height and the next share a shade, as in Penrose's drawing.
        tiles = [
            overlay(m, order, window_size=(TILE, TILE), lights=[light], widths=GALLERY_WIDTHS)
            for light in LIGHTS
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
    V, F, meta = _solid("u_tribar")
    ISO_VIEW, ISO_UP, gap = meta["view"], meta["up"], float(meta["depth_gap"])
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
        render(
            before,
            order=DepthOrder.from_embedding(before, C[:, 2][F]),
            lights=lights,
            window_size=(S, S),
            bounds=bounds,
        ),
        render(m, order=order, lights=lights, window_size=(S, S), bounds=bounds),
    ]
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
    draw.text(
        (2 * S + 10, S + 35),
        f"(the depth gap {gap:.4f}); glued junction circled",
        fill="black",
        font=_font(),
    )
    path = OUT / "closed_solid.png"
    img.save(path)
    return path


def _model_panels(V, F, meta, side, m, order, captions: list[str], name: str, S: int = 360) -> Path:
    """Three panels with captions: the 3D model z-buffered from ``side`` (a real object), the
    model z-buffered from its view (``meta``'s), and the mescher ``m`` in ``order``."""
    ISO_VIEW, ISO_UP = meta["view"], meta["up"]
    lights = [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4)]
    R = view_frame(ISO_VIEW, ISO_UP)

    def framed(C):
        lo, hi = C[:, :2].min(0), C[:, :2].max(0)
        c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
        return {
            "bounds": (c[0] - h, c[0] + h, c[1] - h, c[1] + h),
            "lights": lights,
            "window_size": (S, S),
        }

    Co, C = V @ view_frame(side, R[1]).T, V @ R.T
    panels = [
        render((Co, F), **framed(Co)),
        render((C, F), **framed(C)),
        render(m, order=order, **framed(C)),
    ]
    img = Image.new("RGB", (3 * S, S + 40), "white")
    draw = ImageDraw.Draw(img)
    for k, (panel, text) in enumerate(zip(panels, captions)):
        img.paste(Image.fromarray(panel), (k * S, 0))
        draw.text((k * S + 10, S + 10), text, fill="black", font=_font())
    path = OUT / f"{name}.png"
    img.save(path)
    return path


def hidden_gap_cube_figure() -> Path:
    V, F, meta = _solid("hidden_gap_cube")
    gap = float(meta["depth_gap"])
    R = view_frame(meta["view"], meta["up"])
    t, u = np.radians(18.0), (R[0] + 0.6 * R[1]) / np.linalg.norm(R[0] + 0.6 * R[1])
    m, order, _ = model_to_mescher(V, F, view="auto")
    captions = [
        "the closed frame (oblique view)",
        "its z-buffer from its view",
        f"the mescher: period {np.abs(m.periods()).max():.4f} (gap {gap:.4f})",
    ]
    return _model_panels(
        V, F, meta, np.cos(t) * R[2] + np.sin(t) * u, m, order, captions, "hidden_gap_cube"
    )


def reutersvard_relief_figure() -> Path:
    V, F, meta = _solid("reutersvard_relief")
    R = view_frame(meta["view"], meta["up"])
    t = np.radians(70.0)
    m, order, _ = model_to_mescher(
        V, F, view=meta["view"], up=meta["up"], perceive=meta["perceive"]
    )
    captions = [
        "the relief, 70 degrees aside",
        "its z-buffer from its view",
        f"as perceived: period {np.abs(m.periods()).max():.4f}",
    ]
    return _model_panels(
        V, F, meta, np.cos(t) * R[2] + np.sin(t) * R[0], m, order, captions, "reutersvard_relief"
    )


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
    from meschers.figures import Colorbar, compose
    from pyvista_views.camera import default_bounds, xy_box

    size = (TILE + 40, TILE)
    bounds = default_bounds(xy_box(np.asarray(m.xy)), size)
    kw = {
        "order": order,
        "lights": [(0.4, 0.6, 1.0)],
        "window_size": size,
        "bounds": bounds,
        "shading": "smooth",
        "show_scalar_bar": False,
        "points": {"vertices": [source], "color": "white", "radius": 6},
    }
    cmap = "viridis"
    cells = [
        render(m, scalars=exact, clim=(0, top), cmap=cmap, isolines=12, **kw),
        render(m, scalars=heat, clim=(0, top), cmap=cmap, isolines=12, **kw),
    ]
    dist = compose(
        [cells],
        col_labels=["exact (window propagation)", f"heat method (auto = {heat_solver.method})"],
        colorbar=Colorbar(cmap, 0.0, top, "geodesic distance"),
    )
    diff = render(m, scalars=err, clim=(0, float(err.max())), cmap="magma", **kw)
    diff = compose(
        [[diff]],
        col_labels=[f"difference: mean {err.mean():.2%}, max {err.max():.2%}"],
        colorbar=Colorbar("magma", 0.0, float(err.max()), "|heat - exact| / max"),
    )
    dist, diff = np.asarray(dist.convert("RGB")), np.asarray(diff.convert("RGB"))
    h = max(dist.shape[0], diff.shape[0])
    pad = lambda a: np.pad(a, ((0, h - a.shape[0]), (0, 0), (0, 0)), constant_values=255)  # noqa: E731
    img = Image.fromarray(np.concatenate([pad(dist), pad(diff)], axis=1))
    path = OUT / "exact_geodesic.png"
    img.save(path)
    return path


def _mescher_concept(m, order) -> None:
    """Screen positions per vertex, relative depth per edge, and the picture they make."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    segs = m.xy[m.edges]
    lim = np.abs(m.zeta).max()
    lc = LineCollection(segs, array=m.zeta, cmap="coolwarm", clim=(-lim, lim), linewidths=2)
    axes[0].add_collection(lc)
    axes[0].plot(*m.xy.T, "k.", ms=3)
    axes[0].set_aspect("equal")
    axes[0].autoscale()
    fig.colorbar(lc, ax=axes[0], shrink=0.8, label="zeta[e] = depth(head) - depth(tail)")
    axes[0].set_title("what is stored: xy per vertex, zeta per edge")
    axes[1].imshow(render(m, order=order, lights=[(1, 1, 1)], window_size=(420, 420)))
    axes[1].set_title("what is seen: render(m, order)")
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(CONCEPTS / "mescher.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def _loop_vertices(m, loop_edges, signs):
    """Vertex sequence of a homology loop given as oriented edges."""
    e = m.edges[loop_edges]
    tails = np.where(signs > 0, e[:, 0], e[:, 1])
    heads = np.where(signs > 0, e[:, 1], e[:, 0])
    return np.append(tails, heads[-1])


def _periods_concept(m) -> None:
    """Integrating zeta once around the loop of the hole: back at the start, but higher."""
    (edges0, signs0), (edges1, signs1) = m.homology_generators()
    # the generator with the non-zero period
    k = int(np.argmax(np.abs(m.periods())))
    loop_edges, signs = [(edges0, signs0), (edges1, signs1)][k]
    verts = _loop_vertices(m, loop_edges, signs)
    depth = np.concatenate([[0.0], np.cumsum(signs * m.zeta[loop_edges])])
    lengths = np.linalg.norm(np.diff(m.xy[verts], axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(lengths)])

    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    axes[0].add_collection(LineCollection(m.xy[m.edges], colors="0.85", linewidths=0.6))
    pts = m.xy[verts]
    lc = LineCollection(
        np.stack([pts[:-1], pts[1:]], axis=1), array=depth[1:], cmap="viridis", linewidths=3.5
    )
    axes[0].add_collection(lc)
    axes[0].plot(*pts[0], "o", color="red", ms=8, label="start = end")
    axes[0].set_aspect("equal")
    axes[0].autoscale()
    axes[0].axis("off")
    axes[0].legend(loc="lower left")
    axes[0].set_title("a loop of the homology basis")
    axes[1].plot(s, depth, "-o", ms=3)
    axes[1].axhline(m.periods()[k], color="red", ls="--", lw=1)
    axes[1].set(
        xlabel="screen length along the loop",
        ylabel="zeta summed along the loop",
        title=f"depth climbs by the period {m.periods()[k]:.3f}",
    )
    fig.tight_layout()
    fig.savefig(CONCEPTS / "periods.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def _order_concept(gm) -> None:
    """The same mescher drawn in face-index order and in a linear extension of its depth order."""
    m, order = gm.mescher, gm.order
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
    axes[0].imshow(render(m, order=np.arange(m.n_faces), window_size=(400, 400)))
    axes[0].set_title("faces in index order")
    axes[1].imshow(render(m, order=order, window_size=(400, 400)))
    axes[1].set_title(f"order: {order.graph.number_of_edges()} arcs, back to front")
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(CONCEPTS / "order.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def concept_figures() -> Path:
    """The three figures of ``docs/concepts.rst`` (matplotlib around renders)."""
    import matplotlib

    matplotlib.use("Agg")
    CONCEPTS.mkdir(parents=True, exist_ok=True)
    pt = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=2)
    _mescher_concept(pt.mescher, pt.order)
    _periods_concept(pt.mescher)
    _order_concept(gallery.get_model("impossible_cube"))
    return CONCEPTS


FIGURES = {
    "gallery": gallery_figure,
    "closed_solid": closed_solid_figure,
    "hidden_gap_cube": hidden_gap_cube_figure,
    "reutersvard_relief": reutersvard_relief_figure,
    "exact_geodesic": exact_geodesic_figure,
    "concepts": concept_figures,
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
