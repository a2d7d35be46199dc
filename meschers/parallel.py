"""Running the study's models in parallel with Dask (``meschers study --jobs N`` / ``--scheduler``).

Each model is one task, :func:`meschers.study.study_model`, which returns plain data (numbers,
PNG bytes, errors); the client writes the files and the report.  So the workers need no shared
folder, a remote cluster works like a local one, and the result is the one a serial run gives.
Dask is imported here only, lazily, with an install hint.
"""

from __future__ import annotations

import logging
import os
import uuid
from collections.abc import Callable, Sequence
from typing import Any

from meschers_igl.errors import MescherError

__all__ = ["dask_client", "map_models"]


def _import_distributed():
    try:
        import distributed
    except ModuleNotFoundError as exc:  # pragma: no cover - dask is a dependency
        raise MescherError(
            "jobs: expected Dask's distributed scheduler for a parallel study, found it missing "
            "(pip install 'dask[distributed]'), or run with --jobs 1"
        ) from exc
    return distributed


def _fast_exit_plugin():
    """A worker plugin that ends the worker process at once when the cluster closes.

    A worker that has rendered (an EGL context) takes seconds to exit normally, and the nanny
    kills it after 4 s: on a 45 s study that is a tenth of the time.  Only for the local cluster
    this module starts (never on someone else's scheduler).
    """
    distributed = _import_distributed()

    class FastExit(distributed.WorkerPlugin):
        name = "meschers-fast-exit"

        def teardown(self, worker: Any) -> None:  # noqa: ARG002 -- Dask's signature
            os._exit(0)

    return FastExit()


class dask_client:
    """A Dask client: on ``scheduler`` (an address like ``tcp://host:8786``) or on a new local
    cluster of ``jobs`` single-threaded worker processes (closed on exit)."""

    def __init__(self, jobs: int = 2, scheduler: str | None = None) -> None:
        self.jobs, self.scheduler = jobs, scheduler
        self.client: Any = None
        self._cluster: Any = None

    def __enter__(self) -> Any:
        distributed = _import_distributed()
        if self.scheduler:
            try:
                self.client = distributed.Client(self.scheduler, timeout=20)
            except (OSError, TimeoutError) as exc:
                raise MescherError(
                    f"scheduler: expected a reachable Dask scheduler, found none at "
                    f"{self.scheduler!r} ({exc})"
                ) from None
            return self.client
        # one thread per worker: the steps hold the GIL in numpy/VTK and each worker renders
        # with its own GL context; Dask's HTTP server on a free port (a fixed one may be taken)
        self._cluster = distributed.LocalCluster(
            n_workers=self.jobs,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )
        self.client = distributed.Client(self._cluster)
        self.client.register_plugin(_fast_exit_plugin())
        return self.client

    def __exit__(self, *exc: object) -> None:
        # the local workers exit at once (_fast_exit_plugin): the comms to them close under
        # Dask's feet, which it logs with tracebacks; nothing is lost, so say nothing
        quiet = [logging.getLogger(n) for n in ("distributed", "tornado")] if self._cluster else []
        levels = [lg.level for lg in quiet]
        for lg in quiet:
            lg.setLevel(logging.CRITICAL)
        try:
            if self.client is not None:
                self.client.close()
            if self._cluster is not None:
                self._cluster.close()
        finally:
            for lg, level in zip(quiet, levels):
                lg.setLevel(level)


def map_models(
    fn: Callable[..., Any],
    items: Sequence[Any],
    *,
    args: tuple = (),
    jobs: int = 2,
    scheduler: str | None = None,
    priority: Sequence[float] | None = None,
    on_done: Callable[[int, Any], None] | None = None,
    on_error: Callable[[int, BaseException], Any] | None = None,
) -> list[Any]:
    """``[fn(item, *args) for item in items]`` on a Dask cluster, in the order of ``items``.

    Parameters
    ----------
    fn : callable
        Importable by the workers (a module-level function).
    items : sequence
        Picklable.
    jobs : int
        Workers of the local cluster (ignored with ``scheduler``).
    scheduler : str, optional
        Address of an existing Dask scheduler.
    priority : sequence of float, optional
        Larger first (the longest models first balance the workers best).
    on_done : callable(index, result), optional
        Called as each task finishes (progress).
    on_error : callable(index, exception) -> result, optional
        The result to use for a task that raised (default: re-raise); a failed task never stops
        the others.

    Returns
    -------
    list
        One result per item.
    """
    distributed = _import_distributed()
    results: list[Any] = [None] * len(items)
    with dask_client(jobs, scheduler) as client:
        futures, token = {}, uuid.uuid4().hex[:8]
        for i, item in enumerate(items):
            prio = 0 if priority is None else int(priority[i])
            fut = client.submit(
                fn,
                item,
                *args,
                key=f"meschers-study-{token}-{i}",
                pure=False,
                priority=prio,
                retries=0,
            )
            futures[fut] = i
        for fut in distributed.as_completed(list(futures)):
            i = futures[fut]
            try:
                results[i] = fut.result()
            except Exception as exc:  # noqa: BLE001 -- a failed model is reported, not fatal
                if on_error is None:
                    raise
                results[i] = on_error(i, exc)
            if on_done is not None:
                on_done(i, results[i])
    return results
