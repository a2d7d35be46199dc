"""Construction + cotmatrix + massmatrix + grad of a mescher vs libigl on the same mesh.

Prints the median time of each side (interleaved runs, same process) and the ratio
``mescher / libigl``.  Target (issue 2): ratio <= 1.5 at ~1M faces; peak memory linear in size.

    python benchmarks/bench_operators.py [--faces 1000000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import gc
import resource
import statistics
import sys
import time
from pathlib import Path

import igl

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _meshes import torus_with_faces  # noqa: E402

from meschers_igl import Mescher  # noqa: E402


def run_mescher(V, F):
    m = Mescher.from_mesh(V, F)
    return m.cotmatrix(), m.massmatrix(), m.grad()


def run_libigl(V, F):
    return igl.cotmatrix(V, F), igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI), igl.grad(V, F)


def timed(fn, *args) -> float:
    gc.collect()
    t = time.perf_counter()
    fn(*args)
    return time.perf_counter() - t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--faces", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args(argv)
    V, F = torus_with_faces(a.faces)
    print(f"mesh: {len(V)} vertices, {len(F)} faces")
    ours, peer = [], []
    for _ in range(a.repeats):  # interleaved: both sides see the same machine load
        peer.append(timed(run_libigl, V, F))
        ours.append(timed(run_mescher, V, F))
    mo, mp = statistics.median(ours), statistics.median(peer)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"libigl cotmatrix+massmatrix+grad:           median {mp:.3f} s  {peer}")
    print(f"Mescher.from_mesh+cotmatrix+massmatrix+grad: median {mo:.3f} s  {ours}")
    print(f"ratio mescher / libigl = {mo / mp:.2f}  (target <= 1.5)")
    print(f"peak RSS {rss:.0f} MiB ({rss * 1024 * 1024 / len(F):.0f} bytes per face)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
