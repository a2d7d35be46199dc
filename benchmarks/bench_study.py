"""``meschers study`` on the whole gallery: wall time against the 45 s target on 2 cores.

Runs the main job (``meschers study``: the six gallery models and the six shipped ParadoxToolkit
models, default settings) as a user runs it, in a fresh interpreter, with ``--jobs 2`` (two Dask
worker processes) and with ``--jobs 1`` (one model after another in one process), ``--repeat``
times each, and prints per run:

* the wall time of ``--jobs 2`` against the target (45 s on 2 cores),
* the ratio serial / ``--jobs 2`` measured in the same run (the yardstick: the same work on one
  core),
* the CPU time (user + system, the study and every worker process) of both, which does not
  depend on what else the machine is doing (a shared machine's wall times do),
* the load average before the run, so a slow wall time on a busy machine can be told apart.

With ``--fresh`` it measures instead what a new installation pays: the study twice in a row
with the default ``--jobs``, the first from an empty numba cache (every kernel compiled, as after
``pip install``) and empty user caches (``XDG_CACHE_HOME``: Mesa's shader cache, Matplotlib's
font list, as on a new machine), the second from the caches the first wrote, and prints first /
second against the 1.3x target.

Usage::

    python benchmarks/bench_study.py            # two rounds, default settings
    python benchmarks/bench_study.py --quick    # the --quick study instead
    python benchmarks/bench_study.py --fresh    # first run (empty kernel cache) / second run
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

TARGET_S = 45.0
FRESH_TARGET = 1.3  # first run / second run


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_study(
    jobs: int | None,
    quick: bool,
    out: str,
    numba_cache: str | None = None,
    user_cache: str | None = None,
) -> tuple[float, float]:
    """(wall s, cpu s) of one ``meschers study`` in a fresh interpreter (workers included)."""
    cmd = [sys.executable, "-m", "meschers", "study", "--out", out, "--no-progress"]
    cmd += (["--jobs", str(jobs)] if jobs else []) + (["--quick"] if quick else [])
    env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW="vtkEGLRenderWindow")
    if numba_cache:
        env["NUMBA_CACHE_DIR"] = numba_cache
    if user_cache:
        env["XDG_CACHE_HOME"] = user_cache
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if proc.returncode != 0:
        print(proc.stdout[-2000:], proc.stderr[-4000:], sep="\n", file=sys.stderr)
        raise SystemExit(f"meschers study --jobs {jobs} failed with status {proc.returncode}")
    return wall, cpu


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=2, help="rounds of (--jobs 2, --jobs 1)")
    ap.add_argument("--quick", action="store_true", help="time 'meschers study --quick'")
    ap.add_argument("--no-serial", action="store_true", help="skip the --jobs 1 yardstick")
    ap.add_argument(
        "--fresh",
        action="store_true",
        help="first run from an empty kernel cache / second run (default --jobs)",
    )
    args = ap.parse_args(argv)
    what = "meschers study" + (" --quick" if args.quick else "")
    if args.fresh:
        return fresh(what, args.quick, args.repeat)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(
        f"{what}: gallery + ParadoxToolkit models, {cores} cores visible; target {TARGET_S:.0f} s "
        "wall with --jobs 2 on 2 cores"
    )
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.repeat):
            load = os.getloadavg()[0]
            wall2, cpu2 = run_study(2, args.quick, os.path.join(tmp, f"p{r}"))
            line = (
                f"run {r + 1}: --jobs 2 {wall2:6.1f} s wall "
                f"({'<=' if wall2 <= TARGET_S else '>'} {TARGET_S:.0f} s target, "
                f"{wall2 / TARGET_S:.2f}x), cpu {cpu2:6.1f} s"
            )
            ok &= wall2 <= TARGET_S
            if not args.no_serial:
                wall1, cpu1 = run_study(1, args.quick, os.path.join(tmp, f"s{r}"))
                line += (
                    f" | --jobs 1 {wall1:6.1f} s wall, cpu {cpu1:6.1f} s"
                    f" | serial / --jobs 2 = {wall1 / wall2:.2f}"
                )
            print(line + f" | load average before {load:.1f}", flush=True)
    return 0 if ok else 1


def fresh(what: str, quick: bool, repeat: int) -> int:
    """First run from an empty numba cache, then the second; their ratio against the target."""
    print(
        f"{what} as after a fresh install: first run (empty kernel cache) / second run, "
        f"default --jobs; target <= {FRESH_TARGET}x"
    )
    ok = True
    for r in range(repeat):
        with tempfile.TemporaryDirectory() as tmp:
            cache, user = os.path.join(tmp, "numba"), os.path.join(tmp, "cache")
            load = os.getloadavg()[0]
            w1, c1 = run_study(None, quick, os.path.join(tmp, "first"), cache, user)
            w2, c2 = run_study(None, quick, os.path.join(tmp, "second"), cache, user)
            ratio = w1 / w2
            ok &= ratio <= FRESH_TARGET
            print(
                f"round {r + 1}: first {w1:6.1f} s wall (cpu {c1:6.1f} s), second {w2:6.1f} s "
                f"wall (cpu {c2:6.1f} s): first / second = {ratio:.2f} "
                f"({'<=' if ratio <= FRESH_TARGET else '>'} {FRESH_TARGET}) | load average "
                f"before {load:.1f}",
                flush=True,
            )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
