"""Make the figures of ``docs/concepts.rst`` (committed under ``docs/_static/concepts/``).

Run from anywhere: ``python docs/concept_figures.py``. The Sphinx build only reads the PNGs, so
it needs no OpenGL; the gallery examples are rendered at build time instead.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

from meschers_igl import gallery  # noqa: E402
from pyvista_views import render  # noqa: E402

OUT = Path(__file__).resolve().parent / "_static" / "concepts"


def mescher_figure(m, order) -> None:
    """Screen positions per vertex, relative depth per edge, and the picture they make."""
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
    fig.savefig(OUT / "mescher.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def loop_vertices(m, loop_edges, signs):
    """Vertex sequence of a homology loop given as oriented edges."""
    e = m.edges[loop_edges]
    tails = np.where(signs > 0, e[:, 0], e[:, 1])
    heads = np.where(signs > 0, e[:, 1], e[:, 0])
    return np.append(tails, heads[-1])


def periods_figure(m) -> None:
    """Integrating zeta once around the loop of the hole: back at the start, but higher."""
    (edges0, signs0), (edges1, signs1) = m.homology_generators()
    # the generator with the non-zero period
    k = int(np.argmax(np.abs(m.periods())))
    loop_edges, signs = [(edges0, signs0), (edges1, signs1)][k]
    verts = loop_vertices(m, loop_edges, signs)
    depth = np.concatenate([[0.0], np.cumsum(signs * m.zeta[loop_edges])])
    lengths = np.linalg.norm(np.diff(m.xy[verts], axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(lengths)])

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
    fig.savefig(OUT / "periods.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def order_figure(gm) -> None:
    """The same mescher drawn in face-index order and in a linear extension of its depth order."""
    m, order = gm.mescher, gm.order
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
    axes[0].imshow(render(m, order=None, window_size=(400, 400)))
    axes[0].set_title("order=None: faces in index order")
    axes[1].imshow(render(m, order=order, window_size=(400, 400)))
    axes[1].set_title(f"order: {order.graph.number_of_edges()} arcs, back to front")
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(OUT / "order.png", dpi=80, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    pt = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=2)
    mescher_figure(pt.mescher, pt.order)
    periods_figure(pt.mescher)
    order_figure(gallery.get_model("impossible_cube"))
    for p in sorted(OUT.glob("*.png")):
        print(p)


if __name__ == "__main__":
    main()
