"""
Smoothing (the Heart figure)
============================

Laplacian smoothing ``(M - t L) u = M u0`` of the screen positions ``xy``, of the exact part of
``zeta`` (``omega`` kept, paper Eq. 6), or of both. The harmonic part is in the kernel of the
Laplacian, so smoothing never changes the periods: the object stays impossible while its
shape relaxes.
"""

import matplotlib.pyplot as plt
import numpy as np

from meschers_igl import gallery
from pyvista_views import render

gm = gallery.get_model("penrose_triangle", bar_length=4.0, resolution=4)
m, order = gm.mescher, gm.order
s = np.ptp(m.xy, axis=0).max()  # size of the figure on screen
times = [0.0, 5e-3, 5e-2]
rows = {"smooth xy": (1, 0), "smooth zeta": (0, 1), "smooth both": (1, 1)}

x0, y0 = m.xy.min(axis=0) - 0.05 * s
bounds = (x0, x0 + 1.1 * s, y0, y0 + 1.1 * s)  # one camera for every panel
fig, axes = plt.subplots(3, 3, figsize=(10, 10))
for i, (name, (fx, fz)) in enumerate(rows.items()):
    for j, factor in enumerate(times):
        t = factor * s * s
        # smoothing xy moves the screen positions: the depth order follows them
        ms, order_s = m.smooth(t_xy=fx * t, t_zeta=fz * t, order=order)
        drift = np.abs(ms.periods() - m.periods()).max()
        axes[i, j].imshow(
            render(ms, order=order_s, shading="smooth", bounds=bounds, window_size=(300, 300))
        )
        axes[i, j].set_title(f"{name}, t = {factor:g} s^2\nperiod change {drift:.1e}", fontsize=9)
        axes[i, j].axis("off")
fig.tight_layout()
plt.show()
