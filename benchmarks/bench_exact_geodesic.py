"""Exact geodesic distance (``method="exact"``) against the heat method, same mesh, same run.

Run: ``python benchmarks/bench_exact_geodesic.py [--faces 100000] [--queries 2]
[--check-faces 5000] [--meshes ...] [--covering]``.

First, on an ordinary torus of ``--check-faces`` faces, the max abs difference of the window
propagation against ``igl.exact_geodesic`` (and its time ratio to it).  Then, on meshes of about
``--faces`` faces, times

* exact: ``ExactGeodesicSolver(m)`` once (set-up) and ``.distance(s)`` per query
  (:mod:`meschers_igl.geodesic.exact`: window propagation on the intrinsic mesh, numba; the
  compile is excluded by a warm-up call on a small mesh); with ``--covering`` also
  ``method="covering"``, MMP (``igl.exact_geodesic``) on a covering (slow: minutes at 100k);
* heat: ``HeatGeodesicSolver(m)`` once (precompute) and ``.distance(s)`` (per query);

and prints the ratios exact / heat per query (the target: <= 10 at 100k faces) and exact / (heat precompute + one query), the one-off ``m.geodesic_distance(s)``.

The meshes: the gallery's impossible meschers, midpoint-subdivided to about ``--faces`` faces
(the meschers people make: flat faces meeting at creases and corners), and two smooth tori,
ordinary and impossible (climb 0.4 per turn), every vertex slightly curved.  Exact methods
differ by orders of magnitude between the two kinds, for a reason no implementation avoids: the
distance field is made of pieces (one per unfolded source) and every curved vertex starts a new
piece boundary behind it that runs on until it meets another; with thousands of slightly curved
vertices the pieces number ``O(n^1.5)`` (on the 20k-face torus 94% of the windows
propagated are the distance field's own pieces, sampled at 257 points per edge), while on a
piecewise-flat mesh they are ``O(n)`` (pieces of one unfolding are merged).  The machine is
shared: ratios, not seconds, matter.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _meshes import torus_with_faces  # noqa: E402

from meschers_igl import Mescher, shapes  # noqa: E402
from meschers_igl.gallery import get_model  # noqa: E402
from meschers_igl.geodesic import geodesic_distance  # noqa: E402
from meschers_igl.geodesic.exact import ExactGeodesicSolver  # noqa: E402
from meschers_igl.geodesic.heat import HeatGeodesicSolver  # noqa: E402

GALLERY = ("penrose_triangle", "penrose_stairs", "impossible_cube", "window", "impossibagel")
TARGET = 10.0


def _cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def impossible_torus(n_faces: int) -> Mescher:
    """A torus of about ``n_faces`` faces whose depth climbs 0.4 per turn (impossible)."""
    nv = max(3, int(round(np.sqrt(n_faces / 4))))
    nu = max(3, int(round(n_faces / (2 * nv))))
    V, F = shapes.torus(nu, nv)
    return Mescher.from_mesh(V, F).with_periods([0.4, 0.0])


def gallery_mescher(name: str, n_faces: int) -> Mescher:
    """A gallery mescher, midpoint-subdivided to the face count nearest ``n_faces``."""
    m = get_model(name).mescher
    levels = int(np.argmin([abs(m.n_faces * 4**k - n_faces) for k in range(8)]))
    return m.subdivide(levels) if levels else m


def check_against_libigl(n_faces: int) -> None:
    """Max abs difference to ``igl.exact_geodesic`` on an ordinary torus, and the time ratio."""
    import igl

    V, F = torus_with_faces(n_faces)
    m = Mescher.from_mesh(V, F)
    S = ExactGeodesicSolver(m)
    err, t_w, t_i = 0.0, 0.0, 0.0
    for s in np.random.default_rng(1).choice(m.n_vertices, 3, replace=False):
        t, d = _cpu(lambda s=s: S.distance(int(s)))
        t_w += t
        t, de = _cpu(lambda s=s: igl.exact_geodesic(V, F, VS=np.array([s]), VT=np.arange(len(V))))
        t_i += t
        err = max(err, float(np.abs(d - de).max()))
    print(f"== check: ordinary torus, {m.n_faces} faces, 3 sources")
    print(f"max |window - igl.exact_geodesic|       {err:.2e}")
    print(f"ratio igl.exact_geodesic / window       {t_i / t_w:9.1f}x")


def bench(name: str, m: Mescher, n_queries: int, covering: bool) -> tuple:
    """One row: faces, windows per face, heat and exact times per query and the ratios."""
    srcs = np.random.default_rng(0).choice(m.n_vertices, n_queries, replace=False)
    t_pre, S = _cpu(lambda: HeatGeodesicSolver(m))
    S.distance(int(srcs[0]))  # first call: lazily built parts
    t_q, _ = _cpu(lambda: [S.distance(int(s)) for s in srcs])
    t_q /= n_queries
    t_set, E = _cpu(lambda: ExactGeodesicSolver(m))
    t_ex, d = _cpu(lambda: [E.distance(int(s)) for s in srcs])
    t_ex /= n_queries
    h = S.distance(int(srcs[0]))
    pos = np.isfinite(d[0]) & (d[0] > 0)
    err = float(np.mean(np.abs(h - d[0])[pos] / d[0][pos]))
    row = (
        name,
        m.n_faces,
        E.n_windows / m.n_faces,
        t_q * 1e3,
        t_ex * 1e3,
        t_ex / t_q,
        (t_set + t_ex) / (t_pre + t_q),
        err,
    )
    print(
        f"{name:22s} {row[1]:7d} {row[2]:8.1f} {row[3]:9.1f} {row[4]:9.1f} {row[5]:8.1f}x "
        f"{row[6]:8.2f}x {err:9.4f}  {'yes' if row[5] <= TARGET else 'no'}",
        flush=True,
    )
    if covering:
        t_c, dc = _cpu(lambda: geodesic_distance(m, int(srcs[0]), "covering"))
        print(
            f"    covering (igl MMP) per query {t_c:8.3f} s: max |window - covering| "
            f"{np.abs(dc - d[0]).max():.2e}, ratio covering / window {t_c / t_ex:9.1f}x"
        )
    return row


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=100_000)
    ap.add_argument("--queries", type=int, default=2)
    ap.add_argument("--check-faces", type=int, default=5000)
    ap.add_argument(
        "--meshes",
        nargs="+",
        default=[*GALLERY, "torus", "impossible_torus"],
        help="gallery names, 'torus' and 'impossible_torus'",
    )
    ap.add_argument("--covering", action="store_true")
    args = ap.parse_args(argv)
    ExactGeodesicSolver(impossible_torus(200)).distance(0)  # warm-up: numba's compile/cache load
    check_against_libigl(args.check_faces)
    print(
        f"\n== about {args.faces} faces, {args.queries} queries each (CPU time); "
        f"target: exact query <= {TARGET:g}x a heat query"
    )
    print(
        f"{'mesh':22s} {'faces':>7s} {'win/face':>8s} {'heat ms':>9s} {'exact ms':>9s} "
        f"{'ratio':>9s} {'one-off':>9s} {'heat err':>9s}  <= {TARGET:g}"
    )
    for name in args.meshes:
        if name == "torus":
            V, F = torus_with_faces(args.faces)
            m = Mescher.from_mesh(V, F)
        elif name == "impossible_torus":
            m = impossible_torus(args.faces)
        else:
            m = gallery_mescher(name, args.faces)
        bench(name, m, args.queries, args.covering)
    print(
        "ratio: exact / heat per query; one-off: exact (set-up + query) / heat (precompute + "
        "query); heat err: the heat method's mean relative error against the exact distances"
    )


if __name__ == "__main__":
    main()
