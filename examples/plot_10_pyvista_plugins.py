"""
The PyVista plugins
===================

Installing ``meschers`` registers PyVista entry points, so a plain ``import pyvista`` finds
them: a plotter component ``pl.mescher``, a ``mesh.mescher`` accessor that turns a cut model
into a mescher, a reader and writer for ``.mescher`` files, and the ``"meschers"`` theme
(orthographic, white, matte: the paper's look).
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pyvista as pv

from meschers_igl.paradox import paradox_model

# %%
# The accessor: read the shipped ParadoxToolkit model with PyVista and glue it.
pm = paradox_model("impossible_arch")
cut = pv.read(pm.obj)
m, order = cut.mescher.to_mescher(view=pm.view, up=pm.up)
print(
    cut.n_points,
    "points in the cut model ->",
    m.n_vertices,
    "mescher vertices; periods",
    np.round(m.periods(), 3),
)

# %%
# The plotter component draws the mescher (the same rendering path as
# :func:`pyvista_views.render`), adds the bent embedding as a real mesh in a second scene, and
# relights; ``pl.mescher.screenshot()`` renders first, as VTK needs after a relight.
pv.set_plot_theme("meschers")
shots = {}
pl = pv.Plotter(off_screen=True, window_size=(400, 400))
pl.mescher.add(m, order=order)
shots["pl.mescher.add(m, order)"] = pl.mescher.screenshot()
pl.mescher.relight((-1, 0.5, 0.6))
shots["pl.mescher.relight((-1, 0.5, 0.6))"] = pl.mescher.screenshot()
pl.close()
pl = pv.Plotter(off_screen=True, window_size=(400, 400))
pl.mescher.add_embedding(m, kind="bent")
shots['pl.mescher.add_embedding(m, kind="bent")'] = pl.mescher.screenshot()
pl.close()

# %%
# The ``.mescher`` writer and reader: a flattened, shaded PolyData that carries the mescher
# (``zeta`` and the order in its field data) and gives it back bit for bit.
out = Path(tempfile.mkdtemp(prefix="meschers_plugins_"))
poly = cut.mescher.to_polydata(view=pm.view, up=pm.up)
poly.save(out / "arch.mescher")
back = pv.read(out / "arch.mescher")
m2, order2 = back.mescher.to_mescher()
print("round trip bit-exact:", np.array_equal(m2.zeta, m.zeta), np.array_equal(m2.xy, m.xy))
pl = pv.Plotter(off_screen=True, window_size=(400, 400))
pl.add_mesh(back, color="lightgray")  # a plain PyVista mesh: cells back to front
pl.view_xy()
shots['pv.read("arch.mescher")'] = pl.screenshot()
pl.close()

fig, axes = plt.subplots(1, 4, figsize=(14, 3.8))
for ax, (title, img) in zip(axes, shots.items()):
    ax.imshow(img)
    ax.set_title(title, fontsize=9)
    ax.axis("off")
fig.tight_layout()
plt.show()
