"""
An artist model through PyMeshLab
=================================

Real cut models come from other tools as quads in float32 with seams placed by someone else.
The package ships six made by the Blender add-on ParadoxToolkit (GPL-3.0 data, see
``meschers_igl/data/paradox/LICENSE-NOTE.md``). :func:`meshlab_filters.load_artist_model` reads
any format PyMeshLab reads and cleans it; :func:`meshlab_filters.cut_model_to_mescher` glues the
cut along the view direction into a mescher and its depth order.
"""

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl.paradox import list_paradox_models, paradox_model
from meshlab_filters import cut_model_to_mescher, load_artist_model
from pyvista_views import render

print(list_paradox_models(variants=False))
pm = paradox_model("penrose_triangle")
print("file:", pm.obj.name, "camera view", np.round(pm.view, 3), "up", np.round(pm.up, 3))

V, F, report = load_artist_model(pm.obj)
print(report)

# %%
# Gluing needs only the camera: boundary loops that coincide on screen are paired by one common
# translation along the view direction. The period equals the tool's depth gap (17.32).
m, order = cut_model_to_mescher(pm.obj, view=pm.view, up=pm.up)
print(m.n_vertices, "vertices,", m.n_faces, "faces; periods", np.round(m.periods(), 4))
print("depth gaps the tool recorded:", pm.meta["verification"]["depth_gaps"][:2])

# %%
# The mescher rendered with its depth order, and its exact part ``z`` as colour.
fig, axes = plt.subplots(1, 2, figsize=(10, 5.6))
axes[0].imshow(render(m, order=order, lights=[(1, 1, 1)], window_size=(420, 420)))
axes[0].set_title("ParadoxToolkit penrose_triangle as a mescher")
axes[1].imshow(
    render(m, order=order, scalars=m.hodge().z, window_size=(420, 420), scalar_bar_title="z")
)
axes[1].set_title("its depth potential z")
for ax in axes:
    ax.axis("off")
fig.tight_layout()
plt.show()
