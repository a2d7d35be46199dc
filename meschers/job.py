"""One model's run of the study: its record, its figures, its renderer and its failed steps.

A :class:`ModelJob` is what a study step receives; :class:`ModelResult` is what comes back from a
job (in this process or from a Dask worker): plain data -- the numbers, the figures as PNG bytes,
the errors -- so that the report is written in one place from results computed anywhere.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .figures import png_bytes
from .settings import LIGHTS, StudySettings

__all__ = ["Figure", "ModelJob", "ModelResult", "Renderer", "Section"]


@dataclass
class Figure:
    """One PNG of the report (``data``: the PNG file's bytes)."""

    file: str
    title: str
    caption: str
    data: bytes = field(default=b"", repr=False)


@dataclass
class Section:
    """A model's part of the report."""

    name: str
    title: str
    description: str
    figures: list[Figure] = field(default_factory=list)


@dataclass
class ModelResult:
    """What one model's job produced.

    Attributes
    ----------
    group : {"models", "other_tools"}
        The part of the report (and of ``metrics.json``) it belongs to.
    key : str
        Its name in that part (unique within the study).
    record : dict
        Its numbers (``metrics.json``), ``errors`` and ``timings_s`` included.
    section : Section
        Its figures (with their PNG bytes).
    errors : list of str
        Failed steps (the other steps still ran).
    """

    group: str
    key: str
    record: dict
    section: Section
    errors: list[str] = field(default_factory=list)


class Renderer:
    """One head-on scene reused by every render of a job (a GL context is costly to make)."""

    def __init__(self, cell: int) -> None:
        from pyvista_views import MescherScene

        self.scene = MescherScene(window_size=(cell, cell))

    def shoot(self, items: Sequence[tuple], bounds, lights=LIGHTS[:1], env_map=None) -> np.ndarray:
        """Render ``items`` (("mescher", m, order, kw), ("mesh", V, F, kw), ("path", path, None,
        kw) or ("points", vertices, None, kw)) with one camera."""
        scene = self.scene
        scene.clear()
        for kind, a, b, kw in items:
            if kind == "mescher":
                scene.add(a, order=b, **kw)
            elif kind == "path":  # a polyline on the last mescher, drawn where it is visible
                scene.add_path(a, **kw)
            elif kind == "points":  # vertices of the last mescher, marked where visible
                scene.add_points(a, **kw)
            else:
                scene.add_embedding(a, b, **kw)
        scene.view(bounds)
        scene.relight(lights, env_map)
        return scene.screenshot()

    def relit(self, items, bounds, lights: Sequence, env_map=None) -> list[np.ndarray]:
        """One render per light (and one for ``env_map``), the geometry added once."""
        self.shoot(items, bounds)
        images = []
        for light in lights:
            self.scene.relight([light])
            images.append(self.scene.screenshot())
        if env_map is not None:
            self.scene.relight([], env_map)
            images.append(self.scene.screenshot())
        return images

    def close(self) -> None:
        self.scene.close()


class ModelJob:
    """The state of one model's steps: settings, renderer, record, figures, errors.

    Parameters
    ----------
    group, key : str
        Where the result goes (:class:`ModelResult`).
    section : Section
    settings : StudySettings
    progress : callable(str), optional
        Called with ``"model: step"`` before each step.
    """

    def __init__(
        self,
        group: str,
        key: str,
        section: Section,
        settings: StudySettings,
        progress: Callable[[str], None] | None = None,
    ) -> None:
        self.group, self.key, self.section, self.st = group, key, section, settings
        self.progress = progress or (lambda label: None)
        self.record: dict[str, Any] = {}
        self.errors: list[str] = []
        self._renderer: Renderer | None = None

    @property
    def renderer(self) -> Renderer:
        if self._renderer is None:
            self._renderer = Renderer(self.st.cell)
        return self._renderer

    def figure(self, image: Any, file: str, title: str, caption: str) -> None:
        """Add a figure (a PIL image or an (H, W, 3) array) to the section."""
        self.section.figures.append(Figure(file, title, caption, png_bytes(image)))

    def step(self, key: str, label: str, fn: Callable[..., Any], *args: Any) -> Any:
        """Run ``fn(*args)``, timing it; a failure is recorded and the job goes on (returns None)."""
        from .warmup import STEP_GROUPS, wait_compiled

        label = f"{self.section.name}: {label}"
        # on a first run: the kernel groups this step uses, compiled meanwhile in another process
        wait_compiled(STEP_GROUPS.get(key))
        self.progress(label)
        t0 = time.perf_counter()
        try:
            return fn(*args)
        except Exception as exc:  # noqa: BLE001 -- one broken step must not lose the report
            msg = f"{label}: {type(exc).__name__}: {exc}"
            self.errors.append(msg)
            self.record.setdefault("errors", []).append(msg)
            self.record.setdefault("tracebacks", []).append(traceback.format_exc(limit=6))
            return None
        finally:
            self.record.setdefault("timings_s", {})[key] = round(time.perf_counter() - t0, 3)

    def result(self) -> ModelResult:
        self.record["runtime_s"] = round(sum(self.record.get("timings_s", {}).values()), 3)
        return ModelResult(self.group, self.key, self.record, self.section, list(self.errors))

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
