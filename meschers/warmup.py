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
import pkgutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from typing import Any

from meschers_igl import compiled

__all__ = [
    "COMPILE_SECONDS",
    "announce_compilation",
    "cold_groups",
    "ensure_compiled",
    "warm_group",
]

RENDER_PACKAGE = "pyvista_views"

# CPU seconds to compile each group from an empty cache on one core of a 2-core machine
# (benchmarks/bench_study.py --fresh measures them); only for the estimate printed beforehand.
COMPILE_SECONDS = {"order": 14.0, "geodesic": 16.0, "render": 3.0}


_WARM = "from meschers.warmup import warm_group; warm_group({group!r})"


def _modules(group: str) -> tuple[str, ...]:
    if group != "render":
        return compiled.GROUPS[group]
    # every module of the rendering package (the kernels it compiles may live in any of them)
    import importlib

    pkg = importlib.import_module(RENDER_PACKAGE)
    return tuple(
        f"{RENDER_PACKAGE}.{m.name}" for m in pkgutil.iter_modules(pkg.__path__) if not m.ispkg
    )


def cold_groups(groups: Iterable[str] = (*compiled.GROUPS, "render")) -> list[str]:
    """The groups with at least one kernel that has no machine code cached for this CPU."""
    return [g for g in groups if compiled.cold_kernels(_modules(g))]


def warm_group(group: str) -> float:
    """Compile (or load) one group's kernels in this process; the seconds it took."""
    t = time.perf_counter()
    if group == "render":
        from pyvista_views.headless import configure_headless

        configure_headless()
        import numpy as np

        from meschers_igl import shapes
        from pyvista_views import render

        m = shapes.impossible_torus(12, 6, climb=1.0)
        total = np.arange(m.n_faces)  # a total order: the order kernels are the other group's
        for shading in ("flat", "smooth"):
            render(m, total, shading=shading, window_size=(32, 32))
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
    # fresh interpreters (not multiprocessing): they import nothing of the caller's script, which
    # may have no ``if __name__ == "__main__"`` guard, and hold no GL context or Dask thread;
    # the longest groups first, a new one started as soon as one ends
    pending = sorted(cold, key=lambda g: COMPILE_SECONDS.get(g, 10.0))
    running: list[tuple[str, subprocess.Popen, Any]] = []
    failed = []
    while pending or running:
        while pending and len(running) < n:
            g = pending.pop()
            log = tempfile.TemporaryFile(mode="w+")
            cmd = [sys.executable, "-c", _WARM.format(group=g)]
            running.append((g, subprocess.Popen(cmd, stdout=log, stderr=log, text=True), log))
        time.sleep(0.05)
        for item in [r for r in running if r[1].poll() is not None]:
            g, proc, log = item
            running.remove(item)
            if proc.returncode != 0:
                log.seek(0)
                failed.append(f"{g}: {(log.read().strip().splitlines() or ['?'])[-1]}")
            log.close()
    took = time.perf_counter() - t
    if say is not None:
        say(f"kernels compiled in {took:.0f} s (cached for every later run)")
        for line in failed:  # the work then compiles what it needs as it goes
            say(f"compiling kernels failed for {line}")
    return took


_announced: list[object] = []


def announce_compilation(say: Callable[[str], None], groups: Iterable[str]) -> None:
    """Say ``compiling kernels (first run only, about N s)`` when this process first compiles one
    of the project's kernels (a numba cache miss), once; nothing when everything is cached.

    For one command: its kernels compile as it reaches them, after its arguments were checked
    (a bad argument fails at once, in one line), and only the kernels it uses.

    Parameters
    ----------
    say : callable(str)
    groups : iterable of str
        The groups the command may use, for the estimate.
    """
    from numba.core import event

    groups = tuple(groups)

    class _Notice(event.Listener):
        def on_start(self, ev: Any) -> None:
            if self.done:
                return
            f = getattr(ev.data.get("dispatcher"), "py_func", None)
            if f is None or not f.__module__.startswith(("meschers_igl", "pyvista_views")):
                return
            self.done = True
            cold = cold_groups(groups) or [""]
            estimate = max(sum(COMPILE_SECONDS.get(g, 10.0) for g in cold), 1.0)
            say(f"compiling kernels (first run only, about {estimate:.0f} s)")

        def on_end(self, ev: Any) -> None:
            pass

    for old in _announced:  # one notice per process: the last caller's
        event.unregister("numba:compile", old)
    _announced.clear()
    listener = _Notice()
    listener.done = False
    event.register("numba:compile", listener)
    _announced.append(listener)
