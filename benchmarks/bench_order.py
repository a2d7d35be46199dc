"""Depth-order benchmark: DepthOrder at ~1M faces against honest peers measured in the same run.

Scene: an ordinary torus seen obliquely (its front and back halves overlap on screen), made a
mescher with ``Mescher.from_mesh``; ``Zc`` is the true camera depth of each face's corners.

Peers (the same work done another way, timed here):

* overlap detection -- brute force: the same vectorized separating-axis test over *all* pairs of
  a screen window of ``--subset`` faces, against our grid broad phase + narrow phase on the same
  window (all pairs of 1M faces, 5e11, cannot be timed);
* sorting -- networkx: building the ``DiGraph`` of the order and ``nx.topological_sort``,
  against ``DepthOrder.linear_extension`` (Kahn's algorithm on CSR);
* refinement -- ``from_embedding`` from scratch on the subdivided mescher, against ``refine``.

Run:  python benchmarks/bench_order.py [--faces 1000000] [--subset 3000] [--no-networkx]
"""

from __future__ import annotations

import argparse
import time

import igl
import networkx as nx
import numpy as np

from meschers_igl import DepthOrder, Mescher, shapes
from meschers_igl.geometry2d import (
    default_tol,
    overlapping_pairs,
    triangle_heights,
    triangles_overlap,
)
from meschers_igl.operators import view_frame

VIEW, UP = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)


def torus(n_faces: int, R: float = 1.0, r: float = 0.4):
    nv = max(int(np.sqrt(n_faces / 2 / 2.5)), 3)  # tube resolution; 2.5 x more around the ring
    nu = max(int(n_faces / 2 / nv), 3)
    return shapes.torus(nu, nv, R, r)


def timed(fn, *args, **kw):
    t = time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - t


def brute_force_pairs(T: np.ndarray, tol: float, block: int = 1 << 20) -> np.ndarray:
    """All pairs, the same narrow phase: the peer for the broad phase."""
    n = T.shape[0]
    ok = triangle_heights(T) > tol
    ii, jj = np.triu_indices(n, 1)
    out = []
    for s in range(0, ii.size, block):
        i, j = ii[s : s + block], jj[s : s + block]
        keep = ok[i] & ok[j]
        i, j = i[keep], j[keep]
        hit = triangles_overlap(T[i], T[j], tol)
        out.append(np.stack((i[hit], j[hit]), 1))
    return np.concatenate(out)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=1_000_000)
    ap.add_argument("--subset", type=int, default=3000)
    ap.add_argument("--no-networkx", action="store_true", help="skip the (slow) networkx peer")
    args = ap.parse_args(argv)

    V, F = torus(args.faces)
    m, t_mesh = timed(Mescher.from_mesh, V, F, view=VIEW, up=UP)
    Zc = (V @ view_frame(VIEW, UP).T)[F][:, :, 2]
    print(f"scene: oblique torus, {m.n_faces:,} faces (Mescher.from_mesh {t_mesh:.2f} s)")

    order, t_emb = timed(DepthOrder.from_embedding, m, Zc)
    print(f"DepthOrder.from_embedding: {t_emb:.2f} s, {order.n_arcs:,} arcs")

    # -- overlap detection vs brute force on a screen window of `subset` faces
    T = m.xy[m.F]
    tol = default_tol(T)
    c = T.mean(1)
    centre = c[np.argmin(np.linalg.norm(c - np.median(c, 0), axis=1))]
    sub = np.argsort(np.linalg.norm(c - centre, axis=1))[: args.subset]
    Ts = T[sub]
    (ours, _), t_ours = timed(overlapping_pairs, Ts, tol)
    brute, t_brute = timed(brute_force_pairs, Ts, tol)
    assert np.array_equal(ours, brute), "broad phase missed or added pairs"
    print(
        f"overlap pairs on a {args.subset}-face window ({ours.shape[0]} overlaps): grid "
        f"{t_ours * 1e3:.1f} ms vs brute force {t_brute * 1e3:.0f} ms -> "
        f"{t_brute / t_ours:.0f}x faster (same pairs)"
    )

    # -- sorting vs networkx
    perm, t_kahn = timed(order.linear_extension)
    pos = np.empty_like(perm)
    pos[perm] = np.arange(perm.size)
    assert np.all(pos[order.arcs[:, 0]] < pos[order.arcs[:, 1]])
    print(f"linear_extension (Kahn on CSR): {t_kahn:.2f} s")
    if not args.no_networkx:

        def nx_sort():
            G = nx.DiGraph()
            G.add_nodes_from(range(order.n_faces))
            G.add_edges_from(order.arcs.tolist())
            return list(nx.topological_sort(G))

        _, t_nx = timed(nx_sort)
        print(f"networkx DiGraph + topological_sort: {t_nx:.2f} s -> {t_nx / t_kahn:.0f}x slower")

    # -- local depth (globally integrable here: one spanning forest)
    local, t_loc = timed(DepthOrder.from_local_depth, m)
    print(f"DepthOrder.from_local_depth: {t_loc:.2f} s, equal to from_embedding: {local == order}")

    # -- refine one level coarser -> this level, vs from_embedding from scratch
    Vc, Fc = torus(args.faces // 4)
    mc = Mescher.from_mesh(Vc, Fc, view=VIEW, up=UP)
    oc = DepthOrder.from_embedding(mc, (Vc @ view_frame(VIEW, UP).T)[Fc][:, :, 2])
    V2, F2 = igl.upsample(Vc, Fc)
    m2 = Mescher.from_mesh(V2, F2, view=VIEW, up=UP)
    parent = np.repeat(np.arange(Fc.shape[0]), 4)
    r, t_ref = timed(oc.refine, parent, m2)
    scratch, t_scr = timed(
        DepthOrder.from_embedding, m2, (V2 @ view_frame(VIEW, UP).T)[F2][:, :, 2]
    )
    print(
        f"refine {mc.n_faces:,} -> {m2.n_faces:,} faces: {t_ref:.2f} s vs from_embedding from "
        f"scratch {t_scr:.2f} s -> {t_scr / t_ref:.1f}x; same order: {r == scratch}"
    )


if __name__ == "__main__":
    main()
