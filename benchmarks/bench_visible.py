"""Speed of converting a closed 3D model seen from its view (the bar: <= 10 s at 100k faces).

The model is the gallery's Penrose tribar cut model at high resolution, capped at its two open
ends (a closed U-shaped solid whose ends line up on screen).  Prints the conversion time
(``meschers_igl.obtain.model_to_mescher``) of both paths -- the closed surface (caps paired,
opened and glued crosswise, order from the model's depths) and the visible surface
(hidden-surface removal, visible map, gluing) -- and, as a yardstick measured in the same
run on the same mesh, ``igl.cotmatrix``.

A scene of many parts: ``--grid n`` separate 2 x 2 x 1 boxes, 1 apart (a city block), on a
ground quad 20 times the block's size, seen from (1, 2, 3); it must come out possible (no
period) and fast (the steps comparing parts with parts grow about linearly with the parts).

A large ordinary mesh beside a small figure: an ``--torus U V`` torus (500 x 100: 100k faces,
tens of thousands of planar facets with opposite facets) beside the hidden-gap tribar frame,
from the frame's view; the frame's gap must still be found (its period, L sqrt 3) within the
bar of 10 s.

    python benchmarks/bench_visible.py [--resolution 128] [--repeat 3] [--grid 10]
        [--torus 500 100]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "2")
os.environ.setdefault("OMP_NUM_THREADS", "2")

import igl  # noqa: E402
import numpy as np  # noqa: E402

from meschers_igl import shapes  # noqa: E402
from meschers_igl.errors import MescherWarning  # noqa: E402
from meschers_igl.gallery import get_model  # noqa: E402
from meschers_igl.obtain import model_to_mescher  # noqa: E402
from meschers_igl.topology import boundary_loops  # noqa: E402


def capped_tribar(resolution: int):
    g = get_model("penrose_triangle", resolution=resolution)
    V, F = g.V, g.F
    caps = []
    for loop in boundary_loops(F):  # fan each open end from its centre (a closed solid)
        c = V.shape[0]
        V = np.vstack([V, V[loop].mean(axis=0)])
        caps.append(np.stack([np.full(loop.size, c), np.roll(loop, -1), loop], axis=1))
    return V, np.vstack([F, *caps]), g.view, g.up, g.expected_period


def block_grid(n: int, ground: float = 20.0):
    """``n x n`` separate boxes on a ground quad ``ground`` times the grid's size."""
    return shapes.block_grid(n, ground=ground * 3.0 * n)


def bench_grid(n: int, repeat: int) -> float:
    V, F = block_grid(n)
    model_to_mescher(*block_grid(2), view=(1, 2, 3))  # warm-up
    t, (m, order, report) = best(lambda: model_to_mescher(V, F, view=(1, 2, 3)), repeat)
    p = float(np.abs(m.periods()).max(initial=0.0))
    print(
        f"block grid {n}x{n} on a ground plane: {F.shape[0]} faces, {n * n + 1} parts -> "
        f"{t:7.3f} s, route {report.route}, {m.n_faces} faces, largest period {p:.3g}"
    )
    return t


def hidden_gap_frame():
    """The suite's hidden-gap tribar frame (``tests/meschers_igl/visible_models.py``: a tribar
    whose x bar is broken behind a box, pieces ``L sqrt 3`` apart in depth): (V, F, gap)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "meschers_igl"))
    from visible_models import hidden_gap_frame as frame
    from visible_models import triangulate

    V, P, gap = frame()
    return V, triangulate(P), gap


def bench_torus_beside_frame(n_u: int, n_v: int, repeat: int) -> float:
    Vf, Ff, gap = hidden_gap_frame()
    Vt, Ft = shapes.torus(n_u, n_v, R=4.0, r=1.0)
    V = np.vstack([Vf, Vt + [30.0, -20.0, 0.0]])
    F = np.vstack([Ff, Ft + Vf.shape[0]])
    view, up = np.ones(3) / np.sqrt(3.0), np.array([-1.0, -1.0, 2.0]) / np.sqrt(6.0)
    model_to_mescher(Vf, Ff, view=view, up=up)  # warm-up
    t, (m, order, report) = best(lambda: model_to_mescher(V, F, view=view, up=up), repeat)
    p = [j.depth_gap for j in report.junctions]
    print(
        f"torus {n_u}x{n_v} beside a hidden-gap frame: {F.shape[0]} faces -> {t:7.3f} s "
        f"(bar 10 s: {'OK' if t <= 10.0 else 'TOO SLOW'}), route {report.route}, junctions "
        f"{[j.kind for j in report.junctions]}, gap {max(p, default=0.0):.6f} (built {gap:.6f})"
    )
    return t


def best(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=int, default=128)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--grid", type=int, nargs="*", default=[6, 10])
    ap.add_argument("--torus", type=int, nargs=2, default=[500, 100], metavar=("U", "V"))
    a = ap.parse_args(argv)
    warnings.simplefilter("ignore", MescherWarning)  # "the result is possible": expected
    for n in a.grid:
        bench_grid(n, a.repeat)
    worst = bench_torus_beside_frame(*a.torus, a.repeat)
    V, F, view, up, gap = capped_tribar(a.resolution)
    t_cot, _ = best(lambda: igl.cotmatrix(V, F), a.repeat)
    print(f"closed capped tribar: {F.shape[0]} faces, {V.shape[0]} vertices")
    print(f"  igl.cotmatrix    : {t_cot:8.3f} s  (yardstick, same mesh)")
    for hidden, what in (("auto", "closed surface (hidden side kept)"), (False, "visible surface")):
        model_to_mescher(V, F, view=view, up=up, hidden=hidden)  # warm-up (JIT, imports)
        t_conv, (m, order, report) = best(
            lambda h=hidden: model_to_mescher(V, F, view=view, up=up, hidden=h), a.repeat
        )
        worst = max(worst, t_conv)
        p = np.abs(m.periods())
        print(f"  model_to_mescher, {what}:")
        print(
            f"    {t_conv:8.3f} s = {t_conv / t_cot:6.1f} x cotmatrix -> {m.n_faces} faces, "
            f"period {p.max():.6f} (built with {gap:.6f}), {order.n_arcs} arcs"
        )
    print(
        f"bar (both 100k-face models): <= 10 s on 2 cores -> "
        f"{'OK' if worst <= 10.0 else 'TOO SLOW'}"
    )


if __name__ == "__main__":
    main()
