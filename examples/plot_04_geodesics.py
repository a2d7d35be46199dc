"""
Geodesics, isolines and shortest paths
======================================

Heat diffusion and the heat method need only the intrinsic operators, which every mescher has
(paper Sec. 4.3): distances flow across the place where a cut model would have a seam.
:class:`~meschers_igl.HeatGeodesicSolver` factors once and answers many queries;
:meth:`~meschers_igl.Mescher.shortest_path` traces a polyline on the surface.
"""

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl import HeatGeodesicSolver, gallery
from pyvista_views import render

gm = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=8)
m, order = gm.mescher, gm.order
source = int(np.argmin(m.xy[:, 0]))  # the leftmost corner

solver = HeatGeodesicSolver(m, method="accurate")  # factor once (refined: <= 2 % error) ...
d = solver.distance([source])  # ... query many
target = int(np.argmax(d))
path = m.shortest_path(source, target)
print(f"farthest vertex {target}: heat distance {d[target]:.4f}, path length {path.length:.4f}")

# %%
# Heat diffusion of a spike at the source (backward Euler, paper Eq. 5) conserves mass.
u0 = np.zeros(m.n_vertices)
u0[source] = 1.0
u = m.heat_diffuse(u0, t=2.0)
mass = m.massmatrix().diagonal()
print("mass before / after diffusion:", mass @ u0, mass @ u)

# %%
# The distance as colour with isolines, and the shortest path (red) drawn over it with the
# same camera (``bounds``): the path's screen positions are ``path.xy``.
x0, y0 = m.xy.min(axis=0)
x1, y1 = m.xy.max(axis=0)
pad = 0.05 * max(x1 - x0, y1 - y0)
bounds = (x0 - pad, x1 + pad, y0 - pad, y1 + pad)
# explicit bounds: the picture is exactly that box, with no colour bar beside it
img = render(
    m, order=order, scalars=d, isolines=8, bounds=bounds, window_size=(500, 500), scalar_bar=False
)
heat = render(
    m,
    order=order,
    scalars=np.log10(np.maximum(u, 1e-6)),
    cmap="inferno",
    bounds=bounds,
    window_size=(500, 500),
    scalar_bar=False,
)

fig, axes = plt.subplots(1, 2, figsize=(11, 5.5))
extent = (bounds[0], bounds[1], bounds[2], bounds[3])
axes[0].imshow(heat, extent=extent)
axes[0].set_title(f"log10 of the heat from vertex {source}, t = 2")
axes[1].imshow(img, extent=extent)
axes[1].plot(*path.xy.T, color="red", lw=2.5)
axes[1].plot(*m.xy[[source, target]].T, "o", color="white", mec="k")
axes[1].set_title(f"heat-method distance, path of length {path.length:.2f}")
for ax in axes:
    ax.axis("off")
fig.tight_layout()
plt.show()
