"""Store depth-order arcs, overlap pairs and centroids that ``test_order.py`` compares against.

Runs from any working directory: ``python tests/meschers_igl/data/make_order_reference.py``.
"""

import hashlib
import sys
from pathlib import Path

import igl
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from test_order import _paradox, camera, folded_strip, torus  # noqa: E402

from meschers_igl import DepthOrder, Mescher, shapes  # noqa: E402
from meschers_igl.geometry2d import overlapping_pairs  # noqa: E402

out = {}
view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
V, F = torus()
m = Mescher.from_mesh(V, F, view=view, up=up)
Zc = camera(V, view, up)[F][:, :, 2]
o = DepthOrder.from_embedding(m, Zc)
out["torus_embedding"] = o.arcs
out["torus_local"] = DepthOrder.from_local_depth(m).arcs
p, c = overlapping_pairs(m.xy[m.F], centroids=True)
out["torus_pairs"], out["torus_centroids"] = p, c
front = np.flatnonzero(m.xy[m.F][:, :, 0].mean(1) > 0.1)
back = np.setdiff1d(np.arange(m.n_faces), front)
out["torus_put_in_front"] = o.copy().put_in_front(front, back).arcs
for name in [
    "penrose_triangle",
    "penrose_triangle_block",
    "impossible_cube",
    "penrose_stair",
    "impossible_arch",
    "reutersvard_rectangle",
]:
    mp, Zp = _paradox(name)
    out[name + "_embedding"] = DepthOrder.from_embedding(mp, Zp).arcs
    out[name + "_local"] = DepthOrder.from_local_depth(mp).arcs
    p, c = overlapping_pairs(mp.xy[mp.F], centroids=True)
    out[name + "_pairs"], out[name + "_centroids"] = p, c
Vs, Fs = folded_strip()
ms = Mescher.from_mesh(Vs, Fs, view=(0.15, 0.1, 1.0))
out["strip_local"] = DepthOrder.from_local_depth(ms).arcs
out["strip_paths"] = DepthOrder.from_local_depth(ms, _force_paths=True).arcs
V1, F1 = torus(16, 8)
m1 = Mescher.from_mesh(V1, F1, view=view, up=up)
o1 = DepthOrder.from_embedding(m1, camera(V1, view, up)[F1][:, :, 2])
V2, F2 = igl.upsample(V1, F1)
m2 = Mescher.from_mesh(V2, F2, view=view, up=up)
out["refine"] = o1.refine(np.repeat(np.arange(F1.shape[0]), 4), m2).arcs
# random soup: sizes over two decades, slivers, shared corners
rng = np.random.default_rng(7)
n = 800
c0 = rng.uniform(0, 10, (n, 1, 2))
T = c0 + rng.normal(size=(n, 3, 2)) * np.exp(rng.uniform(-3, 0.5, (n, 1, 1)))
T[::7, 2] = T[::7, 0] + 1e-3 * (T[::7, 1] - T[::7, 0])  # slivers
T[1::11, 0] = T[0:-1:11, 1][: T[1::11].shape[0]]  # shared corners
out["soup_T"] = T
p, c = overlapping_pairs(T, centroids=True)
out["soup_pairs"], out["soup_centroids"] = p, c
np.savez_compressed(HERE / "order_reference.npz", **out)
# a larger torus: hashes only
Vb, Fb = shapes.torus(200, 60, 1.0, 0.4)
mb = Mescher.from_mesh(Vb, Fb, view=view, up=up)
ob = DepthOrder.from_embedding(mb, camera(Vb, view, up)[Fb][:, :, 2])
lb = DepthOrder.from_local_depth(mb)
print({k: v.shape for k, v in out.items()})
print("big", mb.n_faces, ob.n_arcs, hashlib.sha256(ob.arcs.tobytes()).hexdigest(), lb == ob)
