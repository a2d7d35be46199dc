"""
Hodge decomposition
===================

Every mescher's depths split into an exact part and a harmonic part,
``zeta = d01 @ z + omega`` (paper Sec. 3.2): ``z`` is a depth per vertex (the "bent" depth),
``omega`` is closed (``d12 @ omega = 0``) and co-closed, and carries all the periods. A mescher
is impossible exactly when ``omega`` is not zero.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection

from meschers_igl import gallery
from pyvista_views import render

gm = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=4)
m, order = gm.mescher, gm.order
h = m.hodge()

# %%
# The identities the decomposition satisfies, checked on this mescher.
print("|zeta - d01 z - omega|  =", np.abs(m.zeta - m.d01 @ h.z - h.omega).max())
print("|d12 omega| (closed)    =", np.abs(m.d12 @ h.omega).max())
print("|d01^T star1 omega|     =", np.abs(m.d01.T @ (m.star1 @ h.omega)).max(), "(co-closed)")
print(
    "periods of zeta, of omega:",
    np.round(m.periods(), 6),
    np.round(m.with_zeta(h.omega).periods(), 6),
)

# %%
# Left: the depth potential ``z`` as colour on the rendered mescher (the depth of the bent
# model). Right: ``|omega|`` per edge; it circulates around the triangle's hole.
img = render(
    m,
    order=order,
    scalars=h.z,
    cmap="viridis",
    isolines=10,
    window_size=(500, 500),
    scalar_bar_title="z",
)

fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
axes[0].imshow(img)
axes[0].set_title("exact part: potential z (colour, 10 isolines)")
segs = m.xy[m.edges]
lc = LineCollection(segs, array=np.abs(h.omega), cmap="magma_r", linewidths=2)
axes[1].add_collection(lc)
axes[1].set_aspect("equal")
axes[1].autoscale()
fig.colorbar(lc, ax=axes[1], shrink=0.7, label="|omega| per edge")
axes[1].set_title("harmonic part omega (carries the period)")
for ax in axes:
    ax.axis("off")
fig.tight_layout()
plt.show()
