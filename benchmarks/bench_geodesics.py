"""Heat-method geodesics: precompute and per-source time against libigl and potpourri3d.

Run: ``python benchmarks/bench_geodesics.py [--sizes 100000 1000000] [--queries 5]``.

On one ordinary torus per size (``_meshes.torus_with_faces``), the same run times

* ours: ``HeatGeodesicSolver(Mescher.from_mesh(V, F))`` (precompute: operators + two
  factorizations; the Mescher itself is built outside the timing) and ``.distance(s)``;
* libigl: ``igl.heat_geodesics_precompute(V, F, data)`` / ``igl.heat_geodesics_solve``;
* potpourri3d: ``MeshHeatMethodDistanceSolver(V, F)`` / ``.compute_distance(s)``;

and prints the ratios (ours / peer; < 1 is faster).  Targets: per query
<= 1.0x potpourri3d, precompute <= 1.5x libigl.  The machine is shared: run once or twice.

Ours is the default, ``method="auto"`` (``meschers_igl.geodesic.heat.choose_method``): above
``AUTO_REFINE_MAX_FACES`` (25k) faces, and on crumpled meshes, that is
``method="geometry_central"``, potpourri3d's own heat method (the printed max difference to
potpourri3d is round-off); at or below it, on meshes that are not crumpled, auto refines once
(about 4x the query time, and 0.53-0.89x potpourri3d's error).  The line ``ours`` says which
method ran.  numba's first use in a process (intrinsic Delaunay flips) is warmed up on a small
torus before the timings.
"""

from __future__ import annotations

import argparse
import gc
import sys
import time
from pathlib import Path

import igl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _meshes import torus_with_faces  # noqa: E402

from meschers_igl import Mescher  # noqa: E402
from meschers_igl.geodesic.heat import HeatGeodesicSolver  # noqa: E402


def _time(fn, repeat=1):
    ts = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), out


def bench(n_faces: int, n_queries: int) -> None:
    V, F = torus_with_faces(n_faces)
    srcs = np.random.default_rng(0).choice(V.shape[0], n_queries, replace=False)
    print(f"\n== torus, {F.shape[0]} faces, {V.shape[0]} vertices, {n_queries} queries ==")
    m = Mescher.from_mesh(V, F)
    HeatGeodesicSolver(Mescher.from_mesh(*torus_with_faces(2000))).distance(0)  # warm-up (numba)

    t_ours_pre, S = _time(lambda: HeatGeodesicSolver(m))
    t_ours_q, d_ours = _time(lambda: [S.distance(int(s)) for s in srcs])
    t_ours_q /= n_queries
    print(
        f"ours         precompute {t_ours_pre:7.2f} s   per query {t_ours_q * 1e3:7.1f} ms"
        f"   (method={S.method!r})"
    )
    S_method = S.method
    S = None
    gc.collect()

    data = igl.HeatGeodesicsData()
    t_igl_pre, _ = _time(lambda: igl.heat_geodesics_precompute(V, F, data))
    t_igl_q, d_igl = _time(lambda: [igl.heat_geodesics_solve(data, np.array([s])) for s in srcs])
    t_igl_q /= n_queries
    print(f"libigl       precompute {t_igl_pre:7.2f} s   per query {t_igl_q * 1e3:7.1f} ms")
    data = None
    gc.collect()
    err = max(np.abs(a - b).max() for a, b in zip(d_ours, d_igl))
    same = "same method, same t" if S_method == "standard" else f"ours is {S_method!r}"
    print(f"max |ours - libigl| = {err:.2e} ({same})")
    d_ours_0 = d_ours[0]

    try:
        import potpourri3d as pp3d
    except ImportError:
        pp3d = None
        print("potpourri3d not installed: pip install potpourri3d")
    if pp3d is not None:
        t_pp_pre, P = _time(lambda: pp3d.MeshHeatMethodDistanceSolver(V, F))
        t_pp_q, d_pp = _time(lambda: [P.compute_distance(int(s)) for s in srcs])
        t_pp_q /= n_queries
        print(f"potpourri3d  precompute {t_pp_pre:7.2f} s   per query {t_pp_q * 1e3:7.1f} ms")
        print(f"max |ours - potpourri3d| = {np.abs(d_ours_0 - d_pp[0]).max():.2e} (first source)")
        P = None
        gc.collect()
    print(f"ratio precompute ours/libigl      {t_ours_pre / t_igl_pre:5.2f}x  (target <= 1.5)")
    print(f"ratio per query  ours/libigl      {t_ours_q / t_igl_q:5.2f}x")
    if pp3d is not None:
        print(f"ratio precompute ours/potpourri3d {t_ours_pre / t_pp_pre:5.2f}x")
        print(f"ratio per query  ours/potpourri3d {t_ours_q / t_pp_q:5.2f}x  (target <= 1.0)")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100_000, 1_000_000])
    ap.add_argument("--queries", type=int, default=5)
    args = ap.parse_args(argv)
    for n in args.sizes:
        bench(n, args.queries)


if __name__ == "__main__":
    main()
