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

Usage::

    python benchmarks/bench_study.py            # two rounds, default settings
    python benchmarks/bench_study.py --quick    # the --quick study instead
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


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_study(jobs: int, quick: bool, out: str) -> tuple[float, float]:
    """(wall s, cpu s) of one ``meschers study`` in a fresh interpreter (workers included)."""
    cmd = [sys.executable, "-m", "meschers", "study", "--jobs", str(jobs), "--out", out,
           "--no-progress"] + (["--quick"] if quick else [])  # fmt: skip
    env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW="vtkEGLRenderWindow")
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
    args = ap.parse_args(argv)
    what = "meschers study" + (" --quick" if args.quick else "")
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"{what}: gallery + ParadoxToolkit models, {cores} cores visible; target {TARGET_S:.0f} s "
          "wall with --jobs 2 on 2 cores")  # fmt: skip
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.repeat):
            load = os.getloadavg()[0]
            wall2, cpu2 = run_study(2, args.quick, os.path.join(tmp, f"p{r}"))
            line = (f"run {r + 1}: --jobs 2 {wall2:6.1f} s wall "
                    f"({'<=' if wall2 <= TARGET_S else '>'} {TARGET_S:.0f} s target, "
                    f"{wall2 / TARGET_S:.2f}x), cpu {cpu2:6.1f} s")  # fmt: skip
            ok &= wall2 <= TARGET_S
            if not args.no_serial:
                wall1, cpu1 = run_study(1, args.quick, os.path.join(tmp, f"s{r}"))
                line += (f" | --jobs 1 {wall1:6.1f} s wall, cpu {cpu1:6.1f} s"
                         f" | serial / --jobs 2 = {wall1 / wall2:.2f}")  # fmt: skip
            print(line + f" | load average before {load:.1f}", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
