"""
Render and relight
==================

:func:`pyvista_views.render` draws a mescher head-on with an orthographic camera: the triangles
are flattened, shaded with normals derived from ``zeta`` and drawn back to front in a linear
extension of the depth order (the painter's algorithm, paper Sec. 4.1). Only directional lights
and environment maps are allowed: a mescher has no absolute 3D positions for a point light.
"""

import matplotlib.pyplot as plt

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
    "no depth order": {"lights": [(1, 1, 1)], "order": None},
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
# pass behind now cover the ones in front. The order is a DAG over faces
# (``order.graph``, a :class:`networkx.DiGraph`); ``order.linear_extension()`` is the
# back-to-front sequence the renderer uses.
print(order.graph.number_of_nodes(), "faces,", order.graph.number_of_edges(), "arcs")
