"""
Make a mescher and read its periods
===================================

A mescher stores a screen position ``xy`` per vertex and a *relative depth* ``zeta`` per edge
(``zeta[e] = depth(head) - depth(tail)``). The depths sum to zero around every triangle, so each
triangle has a 3D shape, but not necessarily around longer loops: the depth gained once around
a loop of a homology basis is a **period**. A mescher with a non-zero period is impossible.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection

from meschers_igl import Mescher, gallery, shapes

# %%
# An ordinary torus seen head-on is a mescher whose depths integrate around every loop:
# both periods (around the tube and around the hole) are zero.
V, F = shapes.torus(48, 16)
torus = Mescher.from_mesh(V, F, view=(0, 0, 1), up=(0, 1, 0))
print(torus.n_vertices, "vertices,", torus.n_edges, "edges,", torus.n_faces, "faces")
print(
    "possible torus: periods", np.round(torus.periods(), 12), "impossible:", torus.is_impossible()
)

# %%
# ``with_periods`` keeps the surface and sets the harmonic part of ``zeta``: the same torus now
# climbs 1.0 every time one goes around its hole and still ends where it started.
climbing = torus.with_periods([0.0, 1.0])
print(
    "climbing torus: periods",
    np.round(climbing.periods(), 12),
    "impossible:",
    climbing.is_impossible(),
)

# %%
# The Penrose triangle of the gallery is glued from a *cut* 3D model; its period is the depth
# gap of the cut, sqrt(3) times the bar length.
gm = gallery.get_model("penrose_triangle", bar_length=4.0)
penrose = gm.mescher
print("Penrose triangle: periods", np.round(penrose.periods(), 6), "=", np.sqrt(3) * 4.0)
print("locally integrable: max |d12 zeta| =", np.abs(penrose.integrability_residual()).max())

# %%
# The loops the periods are measured on (a tree-cotree homology basis), drawn on the screen
# positions: the depth integrated along each coloured loop is printed in the legend.


def draw(ax, m, title):
    segs = m.xy[m.edges]
    ax.add_collection(LineCollection(segs, colors="0.8", linewidths=0.5))
    for (loop_edges, _signs), period, color in zip(
        m.homology_generators(), m.periods(), ["tab:red", "tab:blue", "tab:green", "tab:orange"]
    ):
        ax.add_collection(
            LineCollection(
                segs[loop_edges], colors=color, linewidths=2.5, label=f"period {period:+.3f}"
            )
        )
    ax.set_title(title)
    ax.set_aspect("equal")
    ax.autoscale()
    ax.axis("off")
    ax.legend(loc="lower center", fontsize=8, bbox_to_anchor=(0.5, -0.15))


fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
draw(axes[0], torus, "torus: possible")
draw(axes[1], climbing, "torus.with_periods([0, 1])")
draw(axes[2], penrose, "Penrose triangle")
fig.tight_layout()
plt.show()
