"""Fixtures of the picture reader's tests: the acceptance benchmark's pictures and the project's
own line art."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import meschers_igl  # noqa: F401  (before the benchmark, which tests/ on sys.path could shadow)

ROOT = Path(__file__).resolve().parents[2]
#: the development set of real models (beside the repository; a clone reaches it through a link)
REAL = ROOT.parent / "shared" / "real_models"


@pytest.fixture(scope="session")
def bench():
    """``benchmarks/bench_inverse_real.py``: its lights, ground, ambient and model loading."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        return pytest.importorskip("bench_inverse_real")
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))


@pytest.fixture(scope="session")
def development_model(bench):
    """``load(name)``: a development-set model as the benchmark loads it (its view and true gap);
    skips without the development set."""

    def load(name: str):
        pytest.importorskip("pyvista")
        if not (REAL / "views.json").is_file() or not (REAL / name).is_file():
            pytest.skip("development set absent")
        return bench.load_models(REAL, {name})[0][0]

    return load


@pytest.fixture(scope="session")
def bench_start(bench):
    """``start(model, k, res=128)``: the start mescher read from the benchmark's picture of
    ``model`` under its light ``k`` (:func:`.picture.mescher_from_picture`), its info, and the
    model's true gap in screen units."""

    def start(model, k: int, res: int = 128):
        from meschers.inverse_cli import zbuffer_picture
        from meschers_igl.inverse.picture import mescher_from_picture

        light = bench.hemisphere_lights(6, 0)[k]
        image, scale = zbuffer_picture(
            model, res, light=light, ambient=bench.AMBIENT, background=bench.GROUND
        )
        m0, _, info = mescher_from_picture(image, light, bench.AMBIENT, background=bench.GROUND)
        return m0, info, model.gap * scale

    return start


@pytest.fixture
def line_art():
    """``draw(spec, path, size=512)``: the project's own line art of ``spec`` as an antialiased
    PNG (``meschers draw``), the true period of its mescher in picture units (the drawing spans
    its default screen box; NaN without one) and the mescher, its order and that box."""

    def draw(spec: str, path, size: int = 512):
        import numpy as np

        pytest.importorskip("cairosvg")
        from PIL import Image

        from meschers.cli import main
        from meschers.inputs import load_mescher, resolve
        from pyvista_views.lineart import default_bounds

        assert main(["draw", spec, "-o", str(path), "--size", str(size)]) == 0
        picture = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
        m, order = load_mescher(resolve(spec))
        xy = m.xy
        box = default_bounds(
            (xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max()), (size, size)
        )
        p = np.abs(m.periods())
        period = float(p.max()) * 2.0 / (box[1] - box[0]) if p.size else float("nan")
        return picture, period, (m, order, box)

    return draw
