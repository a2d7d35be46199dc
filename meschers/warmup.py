"""Compiling the numba kernels once per machine, up front, in parallel, and saying so.

A fresh installation has no compiled kernels: the first call of each compiles it (tens of
seconds in all) and numba caches the machine code for every later process.  Left alone, a
parallel study would compile in every worker at once and a serial one inside its first model,
silently.  :func:`ensure_compiled` runs before the work starts: when kernels are missing from
the cache it prints ``compiling kernels (first run only, about N s)`` and compiles the groups
in parallel processes (one core each), so the workers only load the cache.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

from meschers_igl import compiled

__all__ = ["COMPILE_SECONDS", "cold_groups", "ensure_compiled", "warm_group"]

RENDER_MODULES = ("pyvista_views.polydata",)

# CPU seconds to compile each group from an empty cache on one core of a 2-core machine
# (benchmarks/bench_study.py --fresh measures them); only for the estimate printed beforehand.
COMPILE_SECONDS = {"order": 14.0, "geodesic": 16.0, "render": 3.0}


def _modules(group: str) -> tuple[str, ...]:
    return RENDER_MODULES if group == "render" else compiled.GROUPS[group]


def cold_groups(groups: Iterable[str] = (*compiled.GROUPS, "render")) -> list[str]:
    """The groups with at least one kernel that has no machine code cached for this CPU."""
    return [g for g in groups if compiled.cold_kernels(_modules(g))]


def warm_group(group: str) -> float:
    """Compile (or load) one group's kernels in this process; the seconds it took."""
    t = time.perf_counter()
    if group == "render":
        from pyvista_views.headless import configure_headless

        configure_headless()
        from meschers_igl import shapes
        from pyvista_views import render

        m = shapes.impossible_torus(12, 6, climb=1.0)
        for shading in ("flat", "smooth"):
            render(m, shading=shading, window_size=(32, 32))
    else:
        compiled.warm(group)
    return time.perf_counter() - t


def ensure_compiled(
    say: Callable[[str], None] | None = print,
    groups: Iterable[str] = (*compiled.GROUPS, "render"),
    processes: int | None = None,
) -> float:
    """Compile the missing kernel groups before the work starts, in parallel processes.

    Parameters
    ----------
    say : callable(str), optional
        Where the one-line notice goes (``None``: silent).
    groups : iterable of str
        The groups the coming work uses.
    processes : int, optional
        At most this many compiling processes (default: the cores available).

    Returns
    -------
    float
        Wall seconds spent compiling (0 when everything was cached).
    """
    cold = cold_groups(groups)
    if not cold:
        return 0.0
    ncpu = processes or len(os.sched_getaffinity(0))
    n = max(1, min(len(cold), ncpu))
    estimate = max(sum(COMPILE_SECONDS.get(g, 10.0) for g in cold) / n, 1.0)
    if say is not None:
        say(f"compiling kernels (first run only, about {estimate:.0f} s): {', '.join(cold)}")
    t = time.perf_counter()
    if n == 1:
        for g in cold:
            warm_group(g)
    else:
        # spawned, not forked: the parent may already hold a GL context or Dask threads
        with ProcessPoolExecutor(n, mp_context=get_context("spawn")) as pool:
            list(pool.map(warm_group, sorted(cold, key=lambda g: -COMPILE_SECONDS.get(g, 10.0))))
    took = time.perf_counter() - t
    if say is not None:
        say(f"kernels compiled in {took:.0f} s (cached for every later run)")
    return took
