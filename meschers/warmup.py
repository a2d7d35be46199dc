"""Compiling the numba kernels once per machine, in parallel, beside the work, and saying so.

A fresh installation has no compiled kernels: the first call of each compiles it (tens of
seconds in all) and numba caches the machine code for every later process.  Left alone, a
parallel study would compile in every worker at once and a serial one inside its first model,
silently.  :func:`start_compiling` runs before the work starts: when kernels are missing from
the cache it prints ``compiling kernels (first run only, about N s)`` and compiles the groups
in fresh processes (one core each), the groups a model needs first first.  The work does not
wait for all of them: workers start meanwhile and each model waits (:func:`wait_compiled`) only
for the groups its next steps use, which then load from the cache; so every kernel is compiled
once, by one process, while the other cores start the workers and the first models.
:func:`ensure_compiled` is the same, waiting for everything.

A group can instead be left to the work (``by_work``, a study's :data:`BY_WORK`): the first
process whose step needs it claims it and compiles it there; a process waiting for a group
another one compiles claims and compiles the longest group nobody has claimed meanwhile.  That
suits the rendering kernels, whose own process would first import the rendering stack that
every worker imports anyway, and every group when the workers take all the cores (a study's
default): a compiling process would only add an interpreter and the workers' imports.

Python's cycle collector is paused while a group compiles (:func:`warm_group`): numba's
compiler makes hundreds of thousands of short-lived cyclic objects, and each full collection
walks every object of the process.  Only there, in a process compiling on purpose: a command's
own compilations (:func:`announce_compilation`) leave the collector alone, since a long-lived
process (a notebook, a test run) would have it toggled around every later compilation.
"""

from __future__ import annotations

import gc
import os
import pkgutil
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Any

from meschers_igl import compiled

__all__ = [
    "ALL_GROUPS",
    "BY_WORK",
    "COMPILE_SECONDS",
    "FIRST_NEEDED",
    "STEP_GROUPS",
    "Compiling",
    "announce_compilation",
    "available_cores",
    "cold_groups",
    "ensure_compiled",
    "start_compiling",
    "wait_compiled",
    "warm_group",
]

RENDER_PACKAGE = "pyvista_views"

# CPU seconds to compile each group from an empty cache on one core of a 2-core machine, one
# group after another in one quiet process (the process's own start, about 1.3 s, counted in the
# first, so in each process's share); only for the estimate printed beforehand and for dealing
# groups to processes.
COMPILE_SECONDS = {"order": 8.6, "render": 1.8, "paths": 2.3, "geodesic": 6.4}


#: The groups a study leaves to its work: the first worker to draw compiles the rendering
#: kernels (about 2.5 CPU s beside the other processes) and the others wait for it.  A process of
#: their own would first import PyVista and VTK (about 3.5 CPU s), which the workers import
#: anyway; and each worker compiling them itself would pay them once per worker.
BY_WORK: tuple[str, ...] = ("render",)

#: Every kernel group, the rendering one included.
ALL_GROUPS: tuple[str, ...] = (*compiled.GROUPS, "render")

#: The groups a model's first steps use (building and ordering it, drawing it, its homology
#: loops), in order.
FIRST_NEEDED = ("order", "render", "paths")

#: The kernel groups each step of a study uses (the study's step keys), so that on a first run
#: a step waits only for those; a step not named waits for every group.  Waiting is only
#: scheduling: a kernel a step reaches before its group is ready is compiled by the step itself.
STEP_GROUPS: dict[str, tuple[str, ...]] = {
    "build": ("order",),
    "convert": ("order",),
    "subdivide": ("order",),
    "hodge": ("order", "render", "paths"),
    "render": ("order", "render"),
    "line_art": ("order",),
    "loop_subdivision": ("order", "render"),
    "heat": ("order", "render", "paths"),
    "geodesic": ("order", "render", "paths", "geodesic"),
    "smoothing": ("order", "render"),
    "relighting": ("order", "render"),
    "relight": ("order", "render"),
}

_WARM = "from meschers.warmup import warm_groups; warm_groups({groups!r}, {folder!r})"
_ENV = "MESCHERS_COMPILING"


def _modules(group: str) -> tuple[str, ...]:
    if group != "render":
        return compiled.GROUPS[group]
    # every module of the rendering package (the kernels it compiles may live in any of them)
    import importlib

    pkg = importlib.import_module(RENDER_PACKAGE)
    return tuple(
        f"{RENDER_PACKAGE}.{m.name}" for m in pkgutil.iter_modules(pkg.__path__) if not m.ispkg
    )


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return int(os.cpu_count() or 1)


def cold_groups(groups: Iterable[str] = ALL_GROUPS) -> list[str]:
    """The groups with at least one kernel that has no machine code cached for this CPU."""
    return [g for g in groups if compiled.cold_kernels(_modules(g))]


def warm_groups(groups: Iterable[str], folder: str | None = None) -> None:
    """Compile (or load) the kernels of ``groups`` in this process, one group after another,
    writing ``GROUP.done`` into ``folder`` (if given) as each is ready."""
    for g in groups:
        warm_group(g)
        if folder is not None and os.path.isdir(folder):
            with open(os.path.join(folder, f"{g}.done"), "w"):
                pass


@contextmanager
def _no_cycle_collection() -> Iterator[None]:
    """The cycle collector paused: numba's compiler makes hundreds of thousands of short-lived
    objects in reference cycles, and each full collection meanwhile walks every object of the
    process (a study worker's imports: ~230k), about 15% of the compile time.  The garbage is
    collected at the first collection after (one pass; ~150 MB more at the peak)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def warm_group(group: str) -> float:
    """Compile (or load) one group's kernels in this process; the seconds it took."""
    t = time.perf_counter()
    with _no_cycle_collection():
        _warm(group)
    return time.perf_counter() - t


def _warm(group: str) -> None:
    if group == "render":
        # the rendering package's kernels through the functions that call them, with a
        # mescher's types; no picture: a render window's set-up would cost more than they do
        import numpy as np

        from pyvista_views.normals import corner_groups
        from pyvista_views.polydata import provoking_cells

        m = compiled.tiny_mescher()
        up = np.tile([0.0, 0.0, 1.0], (m.n_faces, 1))
        corner_groups(m.F, up, np.ones(m.n_faces), 30.0)
        provoking_cells(m.F, m.n_vertices)
    else:
        compiled.warm(group)


class Compiling:
    """Kernel groups compiling in fresh interpreters, started by :func:`start_compiling`; the
    work that needs a group waits for it (:func:`wait_compiled`).

    Each interpreter compiles its groups one after another, the groups a model needs first
    first.  Few interpreters: each pays the interpreter's start, the imports and numba's own
    first-compilation set-up (several CPU seconds) before it compiles anything, and each takes
    a core from the work.

    While it runs, the environment variable ``MESCHERS_COMPILING`` names a folder of markers
    (``GROUP.wait`` for each group it compiles, ``GROUP.done`` once that group is compiled or
    its process ended, ``owner`` this process's id), so worker processes started meanwhile
    (they inherit the environment) wait for the groups they need instead of compiling them a
    second time.
    """

    def __init__(
        self,
        cold: list[str],
        processes: int,
        say: Callable[[str], None] | None,
        by_work: Iterable[str] = (),
    ):
        self.cold, self.say, self.failed = list(cold), say, []
        left = set(by_work)
        self.by_work = [g for g in self.cold if g in left]
        self.t0, self.started = time.perf_counter(), time.time()
        self.took = 0.0
        self.folder = tempfile.mkdtemp(prefix="meschers-compiling-")
        with open(os.path.join(self.folder, "owner"), "w") as f:
            f.write(str(os.getpid()))
        for g in cold:  # the groups to wait for; the others are cached already
            with open(os.path.join(self.folder, f"{g}.wait"), "w"):
                pass
        for g in self.by_work:  # compiled by the first process of the work that needs it
            with open(os.path.join(self.folder, f"{g}.bywork"), "w"):
                pass
        self._previous = os.environ.get(_ENV)
        os.environ[_ENV] = self.folder
        apart = [g for g in cold if g not in self.by_work]
        self._thread = threading.Thread(
            target=self._run,
            args=(_share(apart, processes) if apart else [],),
            name="meschers-compile",
            daemon=True,
        )
        self._thread.start()

    def leave_to_work(self, groups: Iterable[str]) -> None:
        """Leave ``groups`` (cold, not compiled by this compilation's processes) to the work:
        the first process that needs one claims and compiles it (:func:`wait_compiled`)."""
        for g in groups:
            if g in self.cold:
                continue
            for suffix in ("wait", "bywork"):
                with open(os.path.join(self.folder, f"{g}.{suffix}"), "w"):
                    pass
            self.by_work.append(g)  # first: the compiling thread marks cold groups not in it
            self.cold.append(g)

    def _run(self, shares: list[list[str]]) -> None:
        try:
            self._compile(shares)
        finally:  # whatever happened, nobody waits any longer (the work compiles what is missing)
            for g in self.cold:
                if g not in self.by_work:  # those are marked by the process that claimed them
                    self._mark(g)
            self.took = time.perf_counter() - self.t0

    def _mark(self, group: str) -> None:
        with open(os.path.join(self.folder, f"{group}.done"), "w"):
            pass

    def _compile(self, shares: list[list[str]]) -> None:
        running = []
        for groups in shares:
            log = tempfile.TemporaryFile(mode="w+")
            cmd = [sys.executable, "-c", _WARM.format(groups=groups, folder=self.folder)]
            proc = subprocess.Popen(cmd, stdout=log, stderr=log, text=True)
            running.append((groups, proc, log))
        for groups, proc, log in running:
            proc.wait()
            if proc.returncode != 0:
                log.seek(0)
                last = (log.read().strip().splitlines() or ["?"])[-1]
                self.failed.append(f"{', '.join(groups)}: {last}")
            log.close()
            for g in groups:
                self._mark(g)

    def wait(self, groups: Iterable[str] | None = None) -> None:
        """Wait until ``groups`` (default: all) are compiled (their processes ended)."""
        if groups is None:
            self._thread.join()
        else:
            _wait_markers(self.folder, groups, os.getpid())

    def close(self) -> float:
        """Wait for every group, report, remove the markers; the wall seconds compiling took."""
        self._thread.join()
        # the groups the work compiled: until the last of them was marked done by its claimer
        marked = [os.path.join(self.folder, f"{g}.done") for g in self.by_work]
        ends = [os.path.getmtime(m) for m in marked if os.path.exists(m)]
        self.took = max([self.took, *(end - self.started for end in ends)])
        for g in self.by_work:  # the work is over: nobody may wait for a group it never claimed
            self._mark(g)
        if os.environ.get(_ENV) == self.folder:
            if self._previous is None:
                del os.environ[_ENV]
            else:
                os.environ[_ENV] = self._previous
        shutil.rmtree(self.folder, ignore_errors=True)
        if self.say is not None:
            self.say(f"kernels compiled in {self.took:.0f} s (cached for every later run)")
            for line in self.failed:  # the work then compiled what it needed as it went
                self.say(f"compiling kernels failed for {line}")
        return self.took

    def __enter__(self) -> Compiling:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _seconds(group: str) -> float:
    return COMPILE_SECONDS.get(group, 10.0)


def _share(cold: list[str], processes: int) -> list[list[str]]:
    """The cold groups dealt to at most ``processes`` interpreters, each list in the order the
    work needs them: the groups a model needs first lead; each group goes to the least loaded
    interpreter (estimated seconds)."""
    ordered = [g for g in FIRST_NEEDED if g in cold]
    ordered += sorted((g for g in cold if g not in ordered), key=_seconds, reverse=True)
    shares: list[list[str]] = [[] for _ in range(max(1, min(processes, len(ordered))))]
    for g in ordered:
        min(shares, key=lambda share: sum(map(_seconds, share))).append(g)
    return [share for share in shares if share]


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process of that id: alive
        return True
    return True


def _claim(folder: str, group: str) -> int | None:
    """Claim a group left to the work: ``None`` when this process got it, else the claimer's id
    (0 while the claimer is still writing it)."""
    path = os.path.join(folder, f"{group}.claim")
    try:
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        try:
            with open(path) as f:
                return int(f.read() or 0)
        except (OSError, ValueError):
            return 0
    with os.fdopen(fd, "w") as f:
        f.write(str(os.getpid()))
    return None


def _compile_claimed(folder: str, group: str) -> None:
    """Compile ``group``, claimed by this process, and mark it done whatever happens."""
    try:
        warm_group(group)
    except Exception:  # noqa: BLE001 -- a warm-up only: the step compiles what it uses
        pass
    finally:
        with open(os.path.join(folder, f"{group}.done"), "w"):
            pass


def _steal(folder: str) -> bool:
    """Claim and compile a group left to the work that nobody has claimed yet, the longest
    first (so that the waits at the end are short); False when there is none.

    A process waiting for a group another one is compiling takes one of the others meanwhile
    instead of leaving its core idle.
    """
    try:
        names = os.listdir(folder)
    except OSError:
        return False
    left = {n.rsplit(".", 1)[0] for n in names if n.endswith(".bywork")}
    free = [g for g in left if f"{g}.claim" not in names and f"{g}.done" not in names]
    for g in sorted(free, key=_seconds, reverse=True):
        if _claim(folder, g) is None:
            _compile_claimed(folder, g)
            return True
    return False


def _wait_markers(folder: str, groups: Iterable[str], owner: int, timeout: float = 900.0) -> None:
    end = time.monotonic() + timeout
    for g in groups:
        if not os.path.exists(os.path.join(folder, f"{g}.wait")):
            continue  # not compiling: cached already
        done = os.path.join(folder, f"{g}.done")
        if os.path.exists(os.path.join(folder, f"{g}.bywork")) and not os.path.exists(done):
            claimer = _claim(folder, g)
            if claimer is None:  # this process compiles it; the others wait
                _compile_claimed(folder, g)
                continue
        else:
            claimer = 0
        while not os.path.exists(done) and os.path.isdir(folder):
            if not _alive(owner) or (claimer and not _alive(claimer)) or time.monotonic() > end:
                return  # nobody will finish it: the work compiles what it needs itself
            if not _steal(folder):
                time.sleep(0.02)


def start_compiling(
    say: Callable[[str], None] | None = print,
    groups: Iterable[str] = ALL_GROUPS,
    processes: int | None = None,
    beside: int = 0,
    by_work: Iterable[str] = (),
) -> Compiling | None:
    """Start compiling the missing kernel groups in processes of their own; do not wait.

    Says ``compiling kernels (first run only, about N s)`` when some are missing.  The work can
    start meanwhile: it calls :func:`wait_compiled` (here or in a worker process started after
    this call) before it needs a group, so each kernel is compiled once, by one process, while
    the other cores start the workers and the first models.

    Parameters
    ----------
    say : callable(str), optional
        Where the notices go (``None``: silent).
    groups : iterable of str
        The groups the coming work uses.
    processes : int, optional
        At most this many compiling processes (default: the cores available; the groups are
        dealt to them, so a 2-core machine compiles what a model needs first in one process
        and the rest in the other while the workers start).
    beside : int, default: 0
        Busy processes of the work that run meanwhile (a study's workers): they share the cores
        with the compiling processes, so the wall time said beforehand is longer by the share
        of the cores they take.
    by_work : iterable of str, default: ()
        Groups the work compiles itself, once: the first process whose step needs one (in
        :func:`wait_compiled`) claims and compiles it, the others wait for it.

    Returns
    -------
    Compiling or None
        ``None`` when everything was cached; else the running compilation (``close()`` it, or
        use it as a context manager, when the work is done).
    """
    groups, left = list(groups), set(by_work)
    # the groups compiled apart are checked and started first: checking a group left to the
    # work may import its package (the rendering one: PyVista and VTK, about 1 s of one core,
    # while the other would wait)
    apart = cold_groups([g for g in groups if g not in left])
    cores = available_cores()
    shares = _share(apart, processes or cores) if apart else []
    running = Compiling(apart, len(shares), say) if apart else None
    by_work = cold_groups([g for g in groups if g in left])
    if not by_work and running is None:
        return None
    if running is None:
        running = Compiling([], 0, say)
    running.leave_to_work(by_work)
    # one core's seconds for the longest share, stretched when more processes than cores run
    crowd = max(1.0, (len(shares) + max(int(beside), 0)) / cores)
    longest = max((sum(map(_seconds, share)) for share in shares), default=0.0)
    # the groups left to the work are shared by its busy processes (each waiting one takes the
    # longest group nobody has claimed), the largest group at least
    left = [_seconds(g) for g in by_work]
    sharing = max(1, min(int(beside), cores))
    by_hand = max(max(left, default=0.0), sum(left) / sharing)
    estimate = max(max(longest, by_hand) * crowd, 1.0)
    if say is not None:
        said = ", ".join(running.cold)
        say(f"compiling kernels (first run only, about {estimate:.0f} s): {said}")
    return running


def wait_compiled(groups: Iterable[str] | None = None) -> None:
    """Wait until the kernel groups ``groups`` (default: all) that :func:`start_compiling` is
    compiling, in this process or the one that started this worker, are compiled.

    Returns at once when nothing is compiling.  Stops waiting (and lets the work compile what
    it needs) if the process that started the compilation is gone.
    """
    folder = os.environ.get(_ENV)
    if not folder or not os.path.isdir(folder):
        return
    try:
        with open(os.path.join(folder, "owner")) as f:
            owner = int(f.read())
    except (OSError, ValueError):
        return
    _wait_markers(folder, ALL_GROUPS if groups is None else groups, owner)


def ensure_compiled(
    say: Callable[[str], None] | None = print,
    groups: Iterable[str] = ALL_GROUPS,
    processes: int | None = None,
) -> float:
    """Compile the missing kernel groups before the work starts: :func:`start_compiling`
    (same parameters), then wait for every group.

    Returns
    -------
    float
        Wall seconds spent compiling (0 when everything was cached).
    """
    running = start_compiling(say, groups, processes)
    return 0.0 if running is None else running.close()


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
