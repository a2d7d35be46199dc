"""
Render and relight
==================

:func:`pyvista_views.render` draws a mescher head-on with an orthographic camera: the triangles
are flattened, shaded with normals derived from ``zeta`` and drawn back to front in a linear
extension of the depth order (the painter's algorithm, paper Sec. 4.1). Only directional lights
and environment maps are allowed: a mescher has no absolute 3D positions for a point light.
"""

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl import gallery
from pyvista_views import render

gm = gallery.get_model("impossible_cube")
m, order = gm.mescher, gm.order
print(gm.description)
print("depth-order cycles:", order.cycles())
# no period (its zeta integrates): the cube is impossible through its depth order, the back bar
# drawn over the front top bar where no depth offset could put it
print("impossible through:", m.is_impossible(order=order).kind)

# %%
# Four directional lights (the direction *toward* the light, camera frame: x right, y up, z
# toward the viewer), an environment map, and smooth shading.
settings = {
    "light (1, 1, 1)": {"lights": [(1, 1, 1)]},
    "light (-1, 0.3, 0.6)": {"lights": [(-1, 0.3, 0.6)]},
    "light (0, -1, 0.4)": {"lights": [(0, -1, 0.4)]},
    "two lights, smooth": {"lights": [(1, 1, 1), (-1, 0, 1)], "shading": "smooth"},
    'env_map="studio"': {"lights": [], "env_map": "studio"},
    "face-index order": {"lights": [(1, 1, 1)], "order": np.arange(m.n_faces)},
}
fig, axes = plt.subplots(2, 3, figsize=(12, 8))
for ax, (title, kw) in zip(axes.flat, settings.items()):
    kw = {"order": order, **kw}
    ax.imshow(render(m, window_size=(360, 360), **kw))
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
plt.show()

# %%
# The last panel draws the faces in index order instead of the depth order: bars that should
# pass behind now cover the ones in front.  (``order=None`` never does this: ``render`` then
# builds an order from the mescher's relative depths, or uses the z-buffer for a possible one.) The order is a DAG over faces
# (``order.graph``, a :class:`networkx.DiGraph`); ``order.linear_extension()`` is the
# back-to-front sequence the renderer uses.
print(order.graph.number_of_nodes(), "faces,", order.graph.number_of_edges(), "arcs")

# %%
# Marks on the visible surface: a shortest path, the closed geodesics around the figure's loops
# and two dots are drawn only where the surface they lie on is the one the viewer sees (hidden
# pieces left out, or dashed with ``hidden="dashed"``); dots are clipped to the outline and
# labels placed without overlap.
from meschers_igl.geodesic import shortest_loops  # noqa: E402

pt = gallery.get_model("penrose_triangle")
mp, op = pt.mescher.subdivide(1, order=pt.order)
path = mp.shortest_path(0, 200)
marks = [{"path": path, "color": "red", "label": "path"}]
marks += [
    {"path": loop, "hidden": "dashed", "label": f"loop {k}"}
    for k, loop in enumerate(shortest_loops(mp))
]
img = render(
    mp,
    order=op,
    paths=marks,
    points={"vertices": [0, 200], "labels": ["s", "t"]},
    window_size=(480, 480),
)
plt.figure(figsize=(6, 6))
plt.imshow(img)
plt.axis("off")
plt.show()
