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

    monkeypatch.setattr(
        warmup, "cold_groups", lambda groups: [g for g in ("order", "geodesic") if g in groups]
    )

    class Started:  # what start_compiling started: its groups, processes and groups left
        def __init__(self, cold, n, say, by_work=()):
            self.cold, self.n, self.left = list(cold), n, []

        def leave_to_work(self, groups):
            self.left += groups
            self.cold += groups

        def __eq__(self, other):
            return (self.cold, self.n) == other

    monkeypatch.setattr(warmup, "Compiling", Started)
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
    # a group left to the work takes no process of its own
    assert warmup.start_compiling(said.append, processes=2, by_work=["geodesic"]) == (
        ["order", "geodesic"],
        1,
    )


def test_groups_compiled_apart_start_before_a_group_left_to_the_work_is_checked(monkeypatch):
    """Checking the rendering group imports its package (PyVista, about a second of one core):
    the compiling processes are started before, so that core does not wait idle."""
    from meschers import warmup

    events = []

    def cold(groups):
        events.append(("check", list(groups)))
        return list(groups)

    class Started:
        def __init__(self, cold, n, say, by_work=()):
            events.append(("start", list(cold)))
            self.cold = list(cold)

        def leave_to_work(self, groups):
            events.append(("leave", list(groups)))
            self.cold += groups

    monkeypatch.setattr(warmup, "cold_groups", cold)
    monkeypatch.setattr(warmup, "Compiling", Started)
    said = []
    warmup.start_compiling(said.append, ["order", "render", "paths"], by_work=["render"])
    assert events == [
        ("check", ["order", "paths"]),
        ("start", ["order", "paths"]),
        ("check", ["render"]),
        ("leave", ["render"]),
    ]
    assert said[-1].endswith("order, paths, render")


def test_a_group_left_to_the_work_is_compiled_once_by_its_first_claimer(tmp_path, monkeypatch):
    """Of the processes that need a group left to the work, the first compiles it and the
    others wait for it; a claimer that died releases the others (they compile it themselves)."""
    import threading
    import time

    from meschers import warmup

    calls = []

    def fake(group):
        calls.append(group)
        time.sleep(0.4)
        return 0.4

    monkeypatch.setattr(warmup, "warm_group", fake)
    monkeypatch.setenv("MESCHERS_COMPILING", str(tmp_path))
    (tmp_path / "owner").write_text(str(os.getpid()))
    for name in ("render.wait", "render.bywork", "order.wait", "order.done"):
        (tmp_path / name).write_text("")
    finished = []

    def need():
        warmup.wait_compiled(["order", "render"])
        finished.append((time.perf_counter(), (tmp_path / "render.done").exists()))

    threads = [threading.Thread(target=need) for _ in range(3)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert calls == ["render"]  # one compile for three processes
    assert len(finished) == 3 and all(done for _, done in finished)
    assert all(t - t0 >= 0.35 for t, _ in finished)  # the others waited for it
    # a later process finds it done: no wait, no compile
    t = time.perf_counter()
    warmup.wait_compiled(["render"])
    assert time.perf_counter() - t < 0.2 and calls == ["render"]

    # the claimer is gone before it finished: the others stop waiting
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    (tmp_path / "render.done").unlink()
    (tmp_path / "render.claim").write_text(dead.stdout.strip())
    t = time.perf_counter()
    warmup.wait_compiled(["render"])
    assert time.perf_counter() - t < 0.5 and calls == ["render"]

    # a warm-up that fails leaves the step to compile what it uses, and releases the others
    def broken(group):
        calls.append(group)
        raise ImportError("no rendering here")

    monkeypatch.setattr(warmup, "warm_group", broken)
    (tmp_path / "render.claim").unlink()
    warmup.wait_compiled(["render"])
    assert calls == ["render", "render"] and (tmp_path / "render.done").exists()


def test_a_compilation_marks_groups_left_to_the_work_only_when_it_closes(monkeypatch):
    """The compiling processes never mark a group left to the work as done (its claimer does),
    and closing the compilation does, so nobody waits for a group nobody claimed."""
    from meschers import warmup

    monkeypatch.setattr(warmup, "_share", lambda cold, processes: [])
    monkeypatch.delenv("MESCHERS_COMPILING", raising=False)
    c = warmup.Compiling(["order", "render"], 1, None, by_work=["render"])
    folder = c.folder
    c._thread.join()
    names = sorted(os.listdir(folder))
    assert "render.bywork" in names and "render.done" not in names and "order.done" in names
    c.close()
    assert not os.path.exists(folder)
    assert warmup.BY_WORK == ("render",)


def test_a_process_waiting_for_a_group_compiles_the_unclaimed_ones_meanwhile(tmp_path, monkeypatch):
    """Workers that fill the cores compile the groups themselves: one waiting for a group
    another is compiling takes the unclaimed groups, the longest first, instead of idling; it
    never takes a group claimed or done, and stops once its own group is done."""
    import threading
    import time

    from meschers import warmup

    calls = []

    def fake(group):
        calls.append(group)
        time.sleep(0.05)
        return 0.05

    monkeypatch.setattr(warmup, "warm_group", fake)
    monkeypatch.setenv("MESCHERS_COMPILING", str(tmp_path))
    (tmp_path / "owner").write_text(str(os.getpid()))
    claimer = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        for g in ("order", "paths", "geodesic", "render", "heap"):
            (tmp_path / f"{g}.wait").write_text("")
            (tmp_path / f"{g}.bywork").write_text("")
        (tmp_path / "order.claim").write_text(str(claimer.pid))  # being compiled elsewhere
        (tmp_path / "heap.claim").write_text(str(claimer.pid))
        (tmp_path / "render.done").write_text("")  # compiled already
        waiter = threading.Thread(target=warmup.wait_compiled, args=(["order"],))
        waiter.start()
        time.sleep(0.6)
        assert waiter.is_alive()  # its own group is not done yet
        secs = warmup.COMPILE_SECONDS
        assert secs["geodesic"] > secs["paths"]
        assert calls == ["geodesic", "paths"]  # the longest first, each once
        assert (tmp_path / "geodesic.done").exists() and (tmp_path / "paths.done").exists()
        assert not (tmp_path / "heap.done").exists()  # claimed by another: left to it
        (tmp_path / "order.done").write_text("")
        waiter.join(5.0)
        assert not waiter.is_alive() and calls == ["geodesic", "paths"]
    finally:
        claimer.kill()
        claimer.wait()


def test_a_local_parallel_study_leaves_every_group_to_workers_that_fill_the_cores(
    tmp_path, monkeypatch
):
    """No compiling process beside workers that take every core (each would first pay an
    interpreter and the imports the workers do anyway); a serial study keeps them on the cores
    left."""
    from meschers import study, warmup

    seen = []

    def fake_start(say, beside=0, by_work=()):
        seen.append((beside, tuple(by_work)))
        raise KeyboardInterrupt  # stop the study here: only the decision is tested

    monkeypatch.setattr(warmup, "start_compiling", fake_start)
    monkeypatch.setattr(warmup, "available_cores", lambda: 2)
    for jobs in (2, 1):
        with pytest.raises(KeyboardInterrupt):
            study.run_study(models=["penrose_triangle"], out=tmp_path, jobs=jobs)
    assert seen == [(2, warmup.ALL_GROUPS), (1, warmup.BY_WORK)]


def test_the_cycle_collector_is_paused_while_a_group_compiles_and_restored_after(monkeypatch):
    """Compiling makes many short-lived cycles and each full collection walks every object of
    the process: the collector is off during a group's warm-up, and its state is restored after,
    also when the warm-up fails."""
    import gc

    from meschers import warmup

    seen = []

    def fake(group):
        seen.append(gc.isenabled())
        if group == "broken":
            raise RuntimeError("a failing warm-up")

    monkeypatch.setattr(warmup, "_warm", fake)
    assert gc.isenabled()
    warmup.warm_group("order")
    assert seen == [False] and gc.isenabled()
    with pytest.raises(RuntimeError):
        warmup.warm_group("broken")
    assert seen == [False, False] and gc.isenabled()
    gc.disable()
    try:
        warmup.warm_group("order")
        assert not gc.isenabled()  # a caller that had it off keeps it off
    finally:
        gc.enable()
