"""The comparison study behind ``meschers study``: every operation of the paper on every model.

Orchestration only: which models (:mod:`meschers.inputs`), one job per model
(:func:`study_model`: the steps of :mod:`meschers.steps` on a mescher, those of
:mod:`meschers.tool_steps` on an artist's cut model), run here or in parallel on Dask
(:mod:`meschers.parallel`), then one report (:mod:`meschers.report`) and ``metrics.json``.
Settings live in :mod:`meschers.settings`, measurements in :mod:`meschers.metrics` and
:mod:`pyvista_views.compare`, figures in :mod:`meschers.figures`.

By default the study runs the built-in gallery (:mod:`meschers_igl.gallery`) and, as "Models
from other tools", the ParadoxToolkit cut models shipped in ``meschers_igl/data/paradox``
(:mod:`meschers_igl.paradox`).  Given ``models``, it runs exactly those.
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError

from .inputs import ModelSpec, expand_models
from .job import Figure, ModelJob, ModelResult, Section
from .settings import CITATION, DOI_URL, ENV_MAP, LIGHTS, StudySettings, study_settings

__all__ = [
    "GROUPS",
    "RUNNERS",
    "Figure",
    "Section",
    "StudyResult",
    "default_models",
    "run_study",
    "study_model",
]


@dataclass(frozen=True)
class Group:
    """A part of the report: its key in ``metrics.json``, its heading and its introduction."""

    key: str
    title: str
    intro: str


#: The report's parts, in order.  Extension point: a section "Models as artists make
#: them" (models seen from a view with ``Mescher.from_model``) is one more entry here, e.g.
#: ``Group("artist_models", "Models as artists make them", "...")``, plus a runner in
#: :data:`RUNNERS` for its kind of :class:`~meschers.inputs.ModelSpec` and, for its table, a
#: function in :data:`meschers.report.TABLES` under the same key.
GROUPS: tuple[Group, ...] = (
    Group("models", "Gallery", ""),
    Group(
        "other_tools",
        "Models from other tools",
        "Cut models made by other tools (the six classic figures of the Blender add-on "
        "ParadoxToolkit, github.com/matgarate/Blender_ParadoxToolkit, GPL-3.0, or any mesh with a "
        "sidecar JSON view), glued into meschers from their view and up vectors alone "
        "(<code>meshlab_filters.cut_model_to_mescher</code>). The tori carry a period equal to the "
        "tool's depth gap; the stairs and block triangle are closed boxes, impossible through their "
        "depth order only.",
    ),
    Group(
        "artist_models",
        "Models as artists make them",
        "Real models of impossible figures as people publish them: closed solids and separate "
        "blocks, not cut models (built from half-spaces and saved as OBJ quads, shipped in "
        "<code>meschers_igl/data/solids</code>). Each is seen from its view by "
        "<code>Mescher.from_model</code> (<code>meshlab_filters.model_to_mescher</code>): hidden "
        "surfaces removed by polygon clipping, false edges glued crosswise so their depth gap "
        "becomes a period, occlusions ordered, a gap hidden behind a crossing bar bridged; the "
        "sheared torus is read with perceived right angles (<code>perceive='manhattan'</code>). "
        "The reference row is the model itself, z-buffered.",
    ),
)


def _run_gallery(job: ModelJob, spec: ModelSpec) -> None:
    from meschers_igl.cutmesh import camera_coordinates
    from meschers_igl.gallery import get_model

    from .steps import run_mescher_steps

    g = get_model(spec.name)
    job.record.update(description=g.description, expected_period=g.expected_period)
    built = job.step("build", "build", lambda: (g.mescher, g.order))
    if built is not None:
        reference = (camera_coordinates(g.V, g.view, g.up), g.F)
        run_mescher_steps(job, job.key, built[0], built[1], reference, "the gallery's cut 3D model")


def _run_saved(job: ModelJob, spec: ModelSpec) -> None:
    from meschers_igl import io

    from .steps import run_mescher_steps

    job.record.update(description=job.section.description, file=spec.path)
    got = job.step("build", "load", lambda: io.load(spec.path, return_order=True))
    if got is not None:
        m, order = got
        V, F, _ = m.cut_embedding()
        note = "the mescher's own cut embedding (integrated on the mesh cut open; no artist model given)"
        run_mescher_steps(job, job.key, m, order, (V, F), note)


def _run_artist(job: ModelJob, spec: ModelSpec) -> None:
    from .tool_steps import run_tool_steps

    repo = spec.meta.get("source", {}).get("repo", "") if isinstance(spec.meta, dict) else ""
    job.record.update(source=repo, file=Path(spec.path).name)
    run_tool_steps(job, spec)


#: How a job runs each kind of model: kind -> (group key, runner, steps shown by progress).
def _run_solid(job: ModelJob, spec: ModelSpec) -> None:
    from .tool_steps import run_solid_steps

    job.record.update(file=Path(spec.path).name)
    run_solid_steps(job, spec)


RUNNERS: dict[str, tuple[str, Callable[[ModelJob, ModelSpec], None], int]] = {
    "gallery": ("models", _run_gallery, 9),
    "mescher": ("models", _run_saved, 9),
    "artist": ("other_tools", _run_artist, 3),
    "solid": ("artist_models", _run_solid, 3),
}


def _description(spec: ModelSpec) -> str:
    if spec.kind == "gallery":
        from meschers_igl.gallery import get_model

        return get_model(spec.name).description
    if spec.kind == "mescher":
        return f"Saved mescher '{Path(spec.path).name}'."
    repo = spec.meta.get("source", {}).get("repo", "") if isinstance(spec.meta, dict) else ""
    if spec.kind == "solid" and isinstance(spec.meta, dict) and spec.meta.get("description"):
        return str(spec.meta["description"])
    if "ParadoxToolkit" in repo:
        return f"ParadoxToolkit cut model '{Path(spec.path).name}'."
    return f"Cut model '{Path(spec.path).name}' seen from its sidecar view."


#: BLAS/OpenMP threads per model (serial and parallel alike; models run in parallel instead).
STUDY_THREADS = 1


def study_model(
    spec: ModelSpec,
    key: str,
    settings: StudySettings,
    progress: Callable[[str], None] | None = None,
) -> ModelResult:
    """One model's job: every step on it, its failures recorded (never raised).

    Runs in this process or on a Dask worker (everything it takes and returns is picklable).

    Parameters
    ----------
    spec : ModelSpec
    key : str
        Its unique name in the study (section id and figure file names).
    settings : StudySettings
    progress : callable(str), optional

    Returns
    -------
    ModelResult
    """
    from threadpoolctl import threadpool_limits

    from pyvista_views.headless import configure_headless

    configure_headless()  # a fresh worker process has no pyvista settings yet
    # kernels still compiling on a first run (meschers.warmup.start_compiling): each step waits
    # for the groups it uses (ModelJob.step)
    # the same BLAS/OpenMP threads in this process and in every worker: sums are then done in
    # the same order and a parallel study gives the serial one's numbers to the last digit
    with threadpool_limits(limits=STUDY_THREADS):
        return _study_model(spec, key, settings, progress)


def _study_model(spec, key, settings, progress) -> ModelResult:
    import pyvista

    pyvista.OFF_SCREEN = True
    group, runner, _ = RUNNERS[spec.kind]
    section = Section(key, key.replace("_", " ").title(), _description(spec))
    job = ModelJob(group, key, section, settings, progress)
    try:
        job.record["threads"] = _threads()
        runner(job, spec)
    except Exception as exc:  # noqa: BLE001 -- the runner's own steps record theirs; this is the rest
        msg = f"{key}: {type(exc).__name__}: {exc}"
        job.errors.append(msg)
        job.record.setdefault("errors", []).append(msg)
    finally:
        job.close()
    return job.result()


def _threads() -> int:
    """The most threads any BLAS/OpenMP pool of this process may use now."""
    from threadpoolctl import threadpool_info

    return max((int(p["num_threads"]) for p in threadpool_info()), default=1)


def failed_result(spec: ModelSpec, key: str, exc: BaseException) -> ModelResult:
    """The result of a job that could not run at all (e.g. its worker died)."""
    group = RUNNERS[spec.kind][0]
    msg = f"{key}: job failed: {type(exc).__name__}: {exc}"
    section = Section(key, key.replace("_", " ").title(), _description(spec))
    return ModelResult(group, key, {"errors": [msg]}, section, [msg])


def default_models(other_tools: bool = True) -> list[ModelSpec]:
    """The gallery, then (with ``other_tools``) the shipped ParadoxToolkit and solid models."""
    from meschers_igl.gallery import list_models
    from meschers_igl.paradox import list_paradox_models

    from .inputs import list_solids

    names = list(list_models())
    if other_tools:
        names += [f"paradox:{n}" for n in list_paradox_models(variants=False)]
        names += [f"solid:{n}" for n in list_solids()]
    return expand_models(names)


def _keys(specs: Sequence[ModelSpec]) -> list[str]:
    """Unique names per report part (a second 'x' becomes 'x_2')."""
    seen: dict[tuple[str, str], int] = {}
    keys = []
    for spec in specs:
        k = (RUNNERS[spec.kind][0], spec.name)
        seen[k] = seen.get(k, 0) + 1
        keys.append(spec.name if seen[k] == 1 else f"{spec.name}_{seen[k]}")
    return keys


def _cost(spec: ModelSpec, settings: StudySettings) -> float:
    """A rough cost estimate, to start the longest models first (faces after subdivision)."""
    if spec.kind == "gallery":
        from meschers_igl.gallery import get_model

        return float(len(get_model(spec.name).F)) * 4.0**settings.levels
    size = Path(spec.path).stat().st_size if spec.path and Path(spec.path).is_file() else 0
    return size / (50.0 if spec.kind == "artist" else 20.0)


@dataclass
class StudyResult:
    """What :func:`run_study` wrote.

    Attributes
    ----------
    out : Path
        The folder with ``index.html`` (one file, figures embedded), the PNGs and ``metrics.json``.
    metrics : dict
        The content of ``metrics.json``.
    sections : list of Section
    errors : list of str
        Steps that failed (the study carries on; each is also in ``metrics["errors"]``).
    """

    out: Path
    metrics: dict
    sections: list[Section]
    errors: list[str]

    @property
    def index(self) -> Path:
        return self.out / "index.html"


def run_study(
    models: Sequence[str] | None = None,
    out: str | Path = "meschers_study",
    quick: bool = False,
    progress: bool = True,
    other_tools: bool = True,
    jobs: int = 1,
    scheduler: str | None = None,
) -> StudyResult:
    """Run the comparison study and write its report.

    Parameters
    ----------
    models : sequence of str, optional
        What to run, exactly (:mod:`meschers.inputs`): gallery names, ``paradox:NAME``, saved
        ``.ply``/``.npz`` meschers, meshes with a sidecar JSON view, folders, glob patterns.
        Default: the gallery and (with ``other_tools``) the shipped ParadoxToolkit models.
    out : str or Path
        Output folder (created); receives ``index.html``, the PNGs and ``metrics.json``.
    quick : bool
        Small panels and one subdivision level (:func:`~meschers.settings.study_settings`).
    progress : bool
        Show progress: a bar over every step (serial) or a line per finished model (parallel).
    other_tools : bool
        With ``models=None``: add the "Models from other tools" section.
    jobs : int
        1: run here, one model after another; more: that many Dask worker processes on a local
        cluster, one model per task.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:8786``); ``jobs`` is then ignored.

    Returns
    -------
    StudyResult

    Raises
    ------
    MescherError
        A model spec that names nothing, ``out`` a file, ``jobs`` < 1, an unreachable scheduler.
    """
    from meschers_igl.validate import as_count

    from .report import write_report
    from .warmup import ALL_GROUPS, BY_WORK, available_cores, start_compiling

    jobs = as_count(jobs, "jobs", minimum=1)
    specs = default_models(other_tools) if models is None else expand_models(list(models))
    if not specs:
        raise MescherError("models: expected at least one model, found none")
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise MescherError(f"out: expected a folder, found a file at '{out}'")
    out.mkdir(parents=True, exist_ok=True)
    st = study_settings(quick)
    keys = _keys(specs)
    t_start = time.perf_counter()
    # missing kernels compiled once: a model waits for the groups it needs (study_model), so no
    # kernel is compiled twice.  Local workers that fill every core compile the groups
    # themselves (the first to need one, or to wait, claims it): a process of its own would
    # first pay an interpreter and the imports every worker has done anyway.  Otherwise the
    # groups compile in processes of their own on the cores left, the rendering kernels
    # (BY_WORK) by the first worker to draw.
    fill = not scheduler and jobs > 1 and jobs >= available_cores()
    compiling = start_compiling(
        lambda line: print(line, file=sys.stderr),
        beside=0 if scheduler else jobs,
        by_work=ALL_GROUPS if fill else BY_WORK,
    )
    try:
        if scheduler or jobs > 1:
            results = _run_parallel(specs, keys, st, jobs, scheduler, progress)
        else:
            results = _run_serial(specs, keys, st, progress)
    finally:
        if compiling is not None:
            compiling.close()
    metrics: dict[str, Any] = {
        "citation": CITATION,
        "doi": DOI_URL,
        "settings": asdict(st),
        "lights": [list(L) for L in LIGHTS],
        "env_map": ENV_MAP,
        "models": {},
        "other_tools": {},
        "artist_models": {},
    }
    errors: list[str] = []
    for res in results:
        metrics.setdefault(res.group, {})[res.key] = res.record
        errors += res.errors
        for fig in res.section.figures:
            (out / fig.file).write_bytes(fig.data)
    metrics["errors"] = errors
    metrics["runtime_s"] = round(time.perf_counter() - t_start, 2)
    metrics["parallel"] = (
        {"jobs": jobs, "scheduler": scheduler} if (scheduler or jobs > 1) else None
    )
    (out / "metrics.json").write_text(json.dumps(_jsonable(metrics), indent=2, allow_nan=True))
    write_report(out, metrics, results, GROUPS)
    return StudyResult(out, metrics, [r.section for r in results], errors)


def _run_serial(specs, keys, st, progress: bool) -> list[ModelResult]:
    total = sum(RUNNERS[s.kind][2] for s in specs)
    with _progress(progress, total, "steps") as advance:
        return [study_model(spec, key, st, advance) for spec, key in zip(specs, keys)]


def _run_parallel(specs, keys, st, jobs, scheduler, progress: bool) -> list[ModelResult]:
    from .parallel import map_models

    with _progress(progress, len(specs), "models") as advance:
        advance("starting Dask workers")

        def done(i: int, res: ModelResult) -> None:
            fails = f", {len(res.errors)} failed step(s)" if res.errors else ""
            advance(f"{keys[i]} done in {res.record.get('runtime_s', 0):.1f} s{fails}")

        return map_models(
            _study_pair,
            list(zip(specs, keys)),
            args=(st,),
            jobs=jobs,
            scheduler=scheduler,
            priority=[_cost(s, st) for s in specs],
            on_done=done,
            on_error=lambda i, exc: failed_result(specs[i], keys[i], exc),
        )


def _study_pair(pair: tuple[ModelSpec, str], st: StudySettings) -> ModelResult:
    """:func:`study_model` for one (spec, key) item of :func:`~meschers.parallel.map_models`."""
    return study_model(pair[0], pair[1], st)


def _jsonable(x: Any) -> Any:
    """numpy scalars and arrays to plain Python, NaN/inf kept as JSON's NaN/Infinity."""
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, np.generic):
        return x.item()
    return x


class _progress:
    """A rich progress bar counting steps or models (a no-op when disabled)."""

    def __init__(self, enabled: bool, total: int, unit: str):
        self.enabled, self.total, self.unit, self._bar = enabled, total, unit, None

    def __enter__(self) -> Callable[[str], None]:
        if not self.enabled:
            return lambda label: None
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

        self._bar = Progress(
            TextColumn("[bold]meschers study[/]"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total} " + self.unit),
            TimeElapsedColumn(),
            TextColumn("{task.description}"),
            transient=False,
        )
        self._bar.start()
        task = self._bar.add_task("starting", total=self.total)
        first = [True]
        counts_done = self.unit == "models"

        def advance(label: str) -> None:
            if counts_done:  # a label per finished model (after the first, 'starting')
                self._bar.update(task, description=label, advance=0 if first[0] else 1)
                if not first[0]:
                    self._bar.console.print(f"  {label}")
            else:  # a label per starting step: the previous one is done
                self._bar.update(task, description=label, advance=0 if first[0] else 1)
            first[0] = False

        return advance

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.update(self._bar.task_ids[0], completed=self.total)
            self._bar.stop()
