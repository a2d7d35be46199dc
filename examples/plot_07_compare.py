"""
Mescher, cut model and bent model
=================================

Before meschers, impossible objects were processed as a *cut* 3D model (real geometry with a
seam where the illusion is) or a *bent* one (the depth potential ``z`` of the Hodge
decomposition, the period dropped). :func:`pyvista_views.compare` renders the paper's Figure 10
for all three and measures it: only the mescher relights like the cut model, smooths without
opening the seam and measures distances across it.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl import gallery
from pyvista_views import compare

gm = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=4)
m, order = gm.mescher, gm.order
out = Path(tempfile.mkdtemp(prefix="meschers_compare_"))
result = compare(m, order=order, path=out / "compare.png", window_size=(220, 220))
print(result.table())

# %%
# The rows are the three representations, the columns render / relit / smoothed / geodesic
# distance (the numbers above are described in :mod:`pyvista_views.compare`).
fig = plt.figure(figsize=(11, 9))
plt.imshow(plt.imread(result.path))
plt.axis("off")
plt.tight_layout()
plt.show()

# %%
# The cut embedding is a real 3D mesh: integrating ``zeta`` on the mescher cut open, the jump
# across the seam equals the period.
Vc, Fc, vmap = m.cut_embedding()
Vb, Fb = m.bent_embedding()
print("cut model:", len(Vc), "vertices for the mescher's", m.n_vertices, "; bent model:", len(Vb))
print("period", np.round(m.periods(), 6))
