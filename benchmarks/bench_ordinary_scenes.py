"""Ordinary scenes seen from many views: how often the converter calls a real object impossible.

For each scene of ``tests/meschers_igl/ordinary_scenes.py`` (a box on a floor before a wall,
two boxes side by side, a table, an L-shaped block, ordinary stairs as one solid and as
blocks) and each of its 90 views with zero and equal components (exact alignments of edges at
different depths), converts the scene (``meschers_igl.obtain.model_to_mescher``, up +z) and
counts the views from which it comes out impossible, with the largest period; errors are
counted apart.

    python benchmarks/bench_ordinary_scenes.py [--scene NAME] [--verbose]
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "2")
import meschers_igl  # noqa: E402,F401 -- before tests/ joins the path (its meschers_igl/ folder)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "meschers_igl"))

import numpy as np  # noqa: E402
from ordinary_scenes import SCENES, axis_views  # noqa: E402


def sweep(name: str, verbose: bool = False):
    """(views impossible, views refused, views, largest period) of scene ``name``."""
    from meschers_igl import MescherError
    from meschers_igl.obtain import model_to_mescher

    V, F = SCENES[name]()
    n_imp = n_err = 0
    top = 0.0
    views = axis_views()
    for v in views:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                m, order, _ = model_to_mescher(V, F, view=np.asarray(v), up=(0.0, 0.0, 1.0))
        except MescherError as err:
            n_err += 1
            if verbose:
                print(f"  {v}: refused: {str(err)[:90]}")
            continue
        kind = m.is_impossible(order=order).kind
        if kind is not None:
            n_imp += 1
            p = float(np.abs(np.asarray(m.periods())).max(initial=0.0))
            top = max(top, p)
            if verbose:
                print(f"  {v}: impossible ({kind}), largest period {p:.4g}")
    return n_imp, n_err, len(views), top


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=None, choices=sorted(SCENES))
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args(argv)
    names = [a.scene] if a.scene else list(SCENES)
    print(f"{'scene':16s} impossible refused views  largest period")
    for name in names:
        n_imp, n_err, n, top = sweep(name, a.verbose)
        print(f"{name:16s} {n_imp:10d} {n_err:7d} {n:5d}  {top:.4g}")


if __name__ == "__main__":
    main()
