"""Kernels compiled once, up front, with a notice; the warm-up covers the types real work uses."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

# Runs in a fresh process with an empty numba cache folder of its own, so it sees what a new
# installation sees whatever this machine compiled before.
SCRIPT = textwrap.dedent(
    """
    import io, contextlib
    from numba.core import event
    from meschers_igl import compiled
    from meschers.warmup import ensure_compiled, cold_groups

    before = compiled.cold_kernels(compiled.GROUPS["order"])
    said = []
    ensure_compiled(said.append, groups=["order"], processes=1)
    after = compiled.cold_kernels(compiled.GROUPS["order"])
    again = []
    ensure_compiled(again.append, groups=["order"], processes=1)

    # real work after the warm-up compiles nothing new: the warm-up used the same signatures
    from meschers_igl import DepthOrder, gallery
    with event.install_recorder("numba:compile") as rec:
        gm = gallery.get_model("penrose_triangle")
        o = DepthOrder.from_local_depth(gm.mescher)
        o.linear_extension()
        gm.mescher.subdivide(1, order=gm.order)
    compiles = sorted({getattr(ev.data.get("dispatcher"), "__name__", "?")
                       for _, ev in rec.buffer if ev.is_start})
    print("BEFORE", len(before))
    print("SAID", said)
    print("AFTER", after)
    print("AGAIN", again)
    print("COMPILES", compiles)
    """
)


@pytest.mark.slow
def test_kernels_compile_once_with_a_notice_and_cover_real_work(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = dict(line.split(" ", 1) for line in proc.stdout.splitlines() if " " in line)
    assert int(out["BEFORE"]) >= 8  # an empty cache: the order kernels are all missing
    said = eval(out["SAID"])  # noqa: S307 -- our own repr of a list of str
    assert len(said) == 2 and said[0].startswith("compiling kernels (first run only, about ")
    assert said[1].startswith("kernels compiled in ")
    assert out["AFTER"] == "[]" and out["AGAIN"] == "[]"  # cached, and silent the second time
    assert out["COMPILES"] == "[]", (
        f"real work compiled kernels the warm-up missed: {out['COMPILES']}"
    )


def test_cold_kernels_skips_inlined_helpers_and_names_module_functions():
    from meschers_igl import compiled

    names = {
        f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        for d in compiled.kernels(compiled.GROUPS["order"])
    }
    assert "meschers_igl.overlap.grid_overlaps" in names
    cold = compiled.cold_kernels(compiled.GROUPS["order"])
    assert set(cold) <= names
    modules = [m for g in compiled.GROUPS.values() for m in g]
    inlined = {
        f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        for d in compiled.kernels(modules)
        if d.targetoptions.get("inline", "never") != "never"
    }
    assert inlined and not inlined & set(compiled.cold_kernels(modules))


def test_warm_refuses_an_unknown_group():
    from meschers_igl import MescherError, compiled

    with pytest.raises(MescherError, match="group: expected one of"):
        compiled.warm("everything")


@pytest.mark.slow
def test_a_command_announces_compilation_once_and_only_when_it_compiles(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    cmd = [sys.executable, "-m", "meschers", "subdivide", "penrose_triangle", "-o"]

    def run(out: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [*cmd, str(tmp_path / out)], env=env, capture_output=True, text=True, timeout=600
        )

    first, second = run("a.ply"), run("b.ply")
    assert first.returncode == 0 and second.returncode == 0, first.stderr + second.stderr
    notices = [ln for ln in first.stderr.splitlines() if ln.startswith("compiling kernels")]
    assert len(notices) == 1 and "(first run only, about " in notices[0]
    assert "compiling kernels" not in second.stderr  # cached: nothing compiles, nothing said
    # a bad argument fails before any kernel is reached: one line, no notice
    bad = subprocess.run(
        [sys.executable, "-m", "meschers", "render", "penrose_triangle", "-o", "x.jpg"],
        env={**env, "NUMBA_CACHE_DIR": str(tmp_path / "empty")},
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert bad.returncode == 2 and bad.stderr.strip().splitlines() == [
        ln for ln in bad.stderr.strip().splitlines() if ln.startswith("meschers: error: -o")
    ]


def test_wait_compiled_waits_for_the_groups_named_and_never_for_a_dead_owner(tmp_path, monkeypatch):
    import threading
    import time

    from meschers.warmup import wait_compiled

    monkeypatch.delenv("MESCHERS_COMPILING", raising=False)
    t = time.perf_counter()
    wait_compiled(["order"])  # nothing compiling: at once
    assert time.perf_counter() - t < 0.5
    monkeypatch.setenv("MESCHERS_COMPILING", str(tmp_path))
    (tmp_path / "owner").write_text(str(os.getpid()))
    for g in ("render", "order", "geodesic"):  # compiling these three
        (tmp_path / f"{g}.wait").write_text("")
    (tmp_path / "render.done").write_text("")
    t = time.perf_counter()
    wait_compiled(["render"])  # done already
    assert time.perf_counter() - t < 0.5
    t = time.perf_counter()
    wait_compiled(["render", "another"])  # a group not compiling (cached): no wait for it
    assert time.perf_counter() - t < 0.5
    timer = threading.Timer(0.6, (tmp_path / "order.done").write_text, args=("",))
    timer.start()
    t = time.perf_counter()
    wait_compiled(["render", "order"])
    assert time.perf_counter() - t >= 0.5 and (tmp_path / "order.done").exists()
    # the process that compiles is gone: stop waiting (the work compiles what it needs)
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    (tmp_path / "owner").write_text(dead.stdout.strip())
    t = time.perf_counter()
    wait_compiled(["geodesic"])
    assert time.perf_counter() - t < 0.5


def test_groups_are_dealt_to_few_processes_first_needed_first():
    from meschers.warmup import FIRST_NEEDED, _share

    cold = ["geodesic", "render", "order", "paths"]
    one = _share(cold, 1)
    assert len(one) == 1 and sorted(one[0]) == sorted(cold)
    assert one[0][: len(FIRST_NEEDED)] == list(FIRST_NEEDED)  # what a model needs first, first
    # two: each group to the least loaded process (estimated seconds), in the order needed
    two = _share(cold, 2)
    assert two == [["order"], ["render", "paths", "geodesic"]]
    assert _share(["geodesic"], 8) == [["geodesic"]]  # never more processes than groups


def test_one_process_marks_each_group_done_as_it_finishes(tmp_path, monkeypatch):
    """A process compiling several groups says each is ready before the next starts, so the
    work waiting for the first does not wait for the last."""
    from meschers import warmup

    seen = []

    def fake(group):
        seen.append((group, sorted(p.name for p in tmp_path.glob("*.done"))))
        return 0.0

    monkeypatch.setattr(warmup, "warm_group", fake)
    warmup.warm_groups(["order", "render", "geodesic"], str(tmp_path))
    assert seen == [
        ("order", []),
        ("render", ["order.done"]),
        ("geodesic", ["order.done", "render.done"]),
    ]
    assert sorted(p.name for p in tmp_path.glob("*.done")) == [
        "geodesic.done",
        "order.done",
        "render.done",
    ]


@pytest.mark.slow
def test_the_render_warm_up_leaves_no_render_kernel_cold(tmp_path):
    """Every cached kernel of the rendering package is compiled by the render group's warm-up;
    one left out would make every later run start a compiling process and say "first run only"
    again."""
    script = (
        "from meschers.warmup import cold_groups, warm_groups\n"
        "print('BEFORE', cold_groups(['render']))\n"
        "warm_groups(['render'])\n"
        "print('AFTER', cold_groups(['render']))\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    env.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    proc = subprocess.run(
        [sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = dict(line.split(" ", 1) for line in proc.stdout.splitlines() if " " in line)
    assert out["BEFORE"] == "['render']"  # an empty cache
    assert out["AFTER"] == "[]"


def test_the_estimate_counts_the_work_sharing_the_cores(monkeypatch):
    """The seconds said beforehand are one core's for the longest share, stretched by the
    processes beyond the cores (compiling ones and the work's), never shortened."""
    from meschers import warmup

    monkeypatch.setattr(warmup, "cold_groups", lambda groups: ["order", "geodesic"])
    monkeypatch.setattr(warmup, "Compiling", lambda cold, n, say: (cold, n))
    monkeypatch.setattr(warmup.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    secs = warmup.COMPILE_SECONDS
    said = []
    assert warmup.start_compiling(said.append, processes=2) == (["order", "geodesic"], 2)
    alone = max(secs["order"], secs["geodesic"])  # one group per process, two cores
    assert said[-1].startswith(f"compiling kernels (first run only, about {alone:.0f} s)")
    warmup.start_compiling(said.append, processes=2, beside=2)  # two workers beside: 4 on 2
    assert said[-1].startswith(f"compiling kernels (first run only, about {2 * alone:.0f} s)")
    warmup.start_compiling(said.append, processes=1, beside=1)  # one process, one worker
    both = secs["order"] + secs["geodesic"]
    assert said[-1].startswith(f"compiling kernels (first run only, about {both:.0f} s)")


def test_a_study_compiles_apart_without_importing_the_rendering_stack():
    """The processes a study starts to compile kernels import neither PyVista nor VTK (an import
    that costs more than the rendering kernels take to compile, and that the workers pay anyway);
    the rendering group is the only one left to the workers."""
    from meschers.warmup import APART
    from meschers_igl import compiled

    code = (
        "import sys\n"
        "from meschers.warmup import APART, warm_groups\n"
        "warm_groups(APART)\n"
        "print(sorted(m for m in ('pyvista', 'vtk', 'vtkmodules', 'pyvista_views') "
        "if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]"
    assert set(APART) == set(compiled.GROUPS)  # every group but "render"
