"""Shared fixtures: named suites of awkward meshes (geometry-central's closed/boundary meshes)."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import shapes


def _rotated(V, F, seed):
    return V @ shapes.random_rotation(seed).T, F


CLOSED = {
    "torus": lambda: _rotated(*shapes.torus(18, 9), 1),
    "sphere": lambda: _rotated(*shapes.icosphere(2), 2),
    "thin_torus": lambda: _rotated(*shapes.torus(30, 5, R=3.0, r=0.3), 3),
}
BOUNDARY = {
    "grid": lambda: _rotated(*shapes.grid(7, 9), 4),
    "annulus": lambda: _rotated(*shapes.annulus(20, 4), 5),
    "bumpy_grid": lambda: _bumpy_grid(6),
}


def _bumpy_grid(seed):
    V, F = shapes.grid(9, 8)
    rng = np.random.default_rng(seed)
    V = V + np.c_[0.02 * rng.standard_normal((len(V), 2)), 0.3 * rng.standard_normal(len(V))]
    return _rotated(V, F, seed)


ALL = {**CLOSED, **BOUNDARY}


def _with_unreferenced(V, F, at):
    """Insert a vertex no face uses at index ``at`` (later indices shift up by one)."""
    V = np.insert(V, at, V.mean(axis=0) + 10.0, axis=0)
    return V, np.where(F >= at, F + 1, F), at


#: Meshes a mescher must refuse (issue 13.3): (V, F, index of the unreferenced vertex).
UNREFERENCED = {
    "grid_extra_last": lambda: _with_unreferenced(*shapes.grid(5, 4), 20),
    "torus_extra_middle": lambda: _with_unreferenced(*shapes.torus(10, 5), 17),
    "annulus_extra_first": lambda: _with_unreferenced(*shapes.annulus(12, 3), 0),
}


@pytest.fixture(params=sorted(UNREFERENCED))
def unreferenced_mesh(request):
    """(name, V, F, k): an ordinary mesh with one vertex ``k`` that no face uses."""
    V, F, k = UNREFERENCED[request.param]()
    return request.param, V, F, k


@pytest.fixture(params=sorted(ALL))
def embedded_mesh(request):
    """(name, V, F) of an ordinary mesh in a random rotation."""
    V, F = ALL[request.param]()
    return request.param, V, F


@pytest.fixture
def rng():
    return np.random.default_rng(1234)


#: tests whose worker died under them (a native crash), each given one more run on a new worker
_CRASHED: list[str] = []


@pytest.hookimpl(optionalhook=True)
def pytest_handlecrashitem(crashitem, report, sched):
    """A test whose xdist worker died (a segfault in a native library) runs once more.

    A test that crashes again fails; one that passes on its second run is listed at the end of
    the run (``pytest_terminal_summary``), so a crash is never silent.  The crashes seen so far
    (rarely, not reproduced) happened inside the garbage collector, not in the running test's
    own code.
    """
    if _CRASHED.count(crashitem) >= 1:
        return
    _CRASHED.append(crashitem)
    sched.mark_test_pending(crashitem)
    report.outcome = "rerun"


def pytest_report_teststatus(report, config):
    if report.outcome == "rerun":
        return "rerun", "R", ("RERUN", {"yellow": True})
    return None


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if _CRASHED:
        terminalreporter.write_sep("=", "tests whose worker crashed, run again", yellow=True)
        for nodeid in _CRASHED:
            terminalreporter.write_line(f"CRASHED once, ran again: {nodeid}")


def pytest_sessionfinish(session, exitstatus):
    """Close render windows and collect PyMeshLab/VTK objects while the interpreter is whole.

    A worker once segfaulted in a garbage collection during pytest's terminal summary, after all
    tests had passed; tearing down GL contexts and MeshSets here, in a known order, avoids
    leaving them to interpreter shutdown.
    """
    import gc
    import sys

    if "pyvista" in sys.modules:
        sys.modules["pyvista"].close_all()
    gc.collect()
