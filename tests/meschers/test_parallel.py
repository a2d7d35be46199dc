"""A study over a folder of one's own models, on two Dask workers: the serial run's results, and
a broken model reported in the page without stopping the others."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from meschers.report import embedded_images
from meschers.study import run_study
from meschers_igl import save
from meschers_igl.gallery import get_model
from meschers_igl.paradox import paradox_model
from pyvista_views.headless import gl_available

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not gl_available(), reason="no offscreen OpenGL context"),
]


def _strip(x):
    """metrics without what depends on the run (timings, tracebacks, where it ran)."""
    if isinstance(x, dict):
        return {
            k: _strip(v)
            for k, v in x.items()
            if k not in ("timings_s", "runtime_s", "tracebacks", "parallel")
        }
    if isinstance(x, list):
        return [_strip(v) for v in x]
    return x


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """A folder: a small saved mescher, an artist model with its sidecar view, a broken one."""
    folder = tmp_path_factory.mktemp("models")
    g = get_model("penrose_triangle", bar_length=4.0, bar_width=1.0, resolution=3)
    save(g.mescher, folder / "small_triangle.npz", order=g.order)
    pm = paradox_model("penrose_stair")
    shutil.copy(pm.obj, folder / "stair.obj")
    (folder / "stair.json").write_text(json.dumps({"view": list(pm.view), "up": list(pm.up)}))
    (folder / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")  # a face with no vertex 9
    (folder / "broken.json").write_text(json.dumps({"view": [0, 0, 1], "up": [0, 1, 0]}))
    return folder


@pytest.fixture(scope="module")
def runs(models, tmp_path_factory):
    out = tmp_path_factory.mktemp("runs")
    serial = run_study([str(models)], out=out / "serial", quick=True, progress=False)
    par = run_study([str(models)], out=out / "par", quick=True, progress=False, jobs=2)
    return serial, par


def test_parallel_study_equals_serial(runs):
    serial, par = runs
    # every model ran; the broken one is reported, and did not stop the others
    assert set(serial.metrics["models"]) == {"small_triangle"}
    assert set(serial.metrics["other_tools"]) == {"broken", "stair"}
    broken = serial.metrics["other_tools"]["broken"]
    assert broken["errors"] and "convert" in broken["errors"][0]
    assert not serial.metrics["models"]["small_triangle"].get("errors")
    assert not serial.metrics["other_tools"]["stair"].get("errors")
    assert serial.errors == par.errors and len(serial.errors) == 1
    # one BLAS/OpenMP thread per model in this process and in the workers alike: sums in the
    # same order, so the same numbers to the last digit
    assert serial.metrics["models"]["small_triangle"]["threads"] == 1
    assert par.metrics["models"]["small_triangle"]["threads"] == 1
    # the same numbers, and the same figures in the same order
    assert _strip(serial.metrics) == _strip(par.metrics)
    assert par.metrics["parallel"] == {"jobs": 2, "scheduler": None}
    titles = [[f.title for f in s.figures] for s in serial.sections]
    assert titles == [[f.title for f in s.figures] for s in par.sections]
    assert sum(map(len, titles)) == 9 + 2  # the mescher's nine figures, the stair's two
    html = par.index.read_text()
    assert "Step failed: broken: convert" in html and "Stair" in html


def test_parallel_figures_equal_serial_pixel_for_pixel(runs):
    """The serial run renders several models in one process, a worker one or two: no state
    may leak from one render to the next (it did once, through the face-id pass of isolines)."""
    from io import BytesIO

    from PIL import Image

    serial, par = runs
    a = embedded_images(serial.index)  # in page order, which is the models' order
    b = embedded_images(par.index)
    for x, y in zip(a, b, strict=True):
        ia = np.asarray(Image.open(BytesIO(x)).convert("RGB"), dtype=int)
        ib = np.asarray(Image.open(BytesIO(y)).convert("RGB"), dtype=int)
        assert ia.shape == ib.shape
        assert int((np.abs(ia - ib).max(axis=2) > 0).sum()) == 0


def test_a_task_that_raises_is_reported_and_the_others_finish():
    """map_models hands a raising task to on_error and keeps the order of the items."""
    import math

    from meschers.parallel import map_models

    done = []
    out = map_models(
        math.sqrt,
        [4.0, -1.0, 9.0],
        jobs=1,
        on_done=lambda i, r: done.append(i),
        on_error=lambda i, exc: f"failed: {type(exc).__name__}",
    )
    assert out == [2.0, "failed: ValueError", 3.0] and sorted(done) == [0, 1, 2]
    with pytest.raises(ValueError):
        map_models(math.sqrt, [-1.0], jobs=1)
