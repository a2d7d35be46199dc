"""
Subdivision
===========

``m.subdivide(levels, scheme="midpoint")`` splits every triangle into four: new screen positions
at the edge midpoints, each edge's ``zeta`` halved (paper Sec. 4.2). ``scheme="loop"`` runs Loop
subdivision on a covering of the mescher, so the surface gets smooth while the periods stay
exactly the same; edges sharper than 30 degrees keep their crease (the rules of piecewise-smooth
Loop subdivision, Hoppe et al. 1994), so boxes stay boxes.  ``scheme="loop-smooth"`` rounds
every edge (libigl's Loop).
"""

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl import gallery
from pyvista_views import render

gm = gallery.get_model("impossibagel")
m, order = gm.mescher, gm.order
print("coarse:", m.n_faces, "faces, periods", np.round(m.periods(), 6))

# %%
# With ``order=`` the depth order is carried to the children and returned too.
meshes = {"coarse": (m, order)}
for scheme in ("midpoint", "loop"):
    fine, fine_order = m.subdivide(2, scheme=scheme, order=order)
    meshes[f"{scheme}, 2 levels"] = (fine, fine_order)
    print(f"{scheme:8s}: {fine.n_faces} faces, periods {np.round(fine.periods(), 6)}")

# %%
# Top: the triangles on screen (zoomed in on the right of the ring). Bottom: rendered with smooth shading under one light.
fig, axes = plt.subplots(2, 3, figsize=(12, 8))
for j, (name, (mm, oo)) in enumerate(meshes.items()):
    axes[0, j].triplot(*mm.xy.T, mm.F, lw=0.3, color="k")
    axes[0, j].set_aspect("equal")
    axes[0, j].set(xlim=(1.2, 2.4), ylim=(-0.6, 0.6))
    axes[0, j].set_title(f"{name}: {mm.n_faces} faces")
    axes[1, j].imshow(
        render(mm, order=oo, shading="smooth", lights=[(1, 1, 1)], window_size=(360, 360))
    )
    for ax in axes[:, j]:
        ax.axis("off")
fig.tight_layout()
plt.show()

# %%
# Creases: Reutersvärd's cubes stay cubes under ``"loop"``; ``"loop-smooth"`` melts them into
# blobs that no longer overlap as the figure needs.
rv = gallery.get_model("reutersvard_triangle")
fig, axes = plt.subplots(1, 3, figsize=(12, 4))
for ax, (title, scheme) in zip(
    axes, [("input", None), ("loop", "loop"), ("loop-smooth", "loop-smooth")]
):
    mm, oo = (
        (rv.mescher, rv.order)
        if scheme is None
        else rv.mescher.subdivide(2, scheme, order=rv.order)
    )
    ax.imshow(render(mm, order=oo, shading="smooth", lights=[(1, 1, 1)], window_size=(360, 360)))
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
plt.show()
