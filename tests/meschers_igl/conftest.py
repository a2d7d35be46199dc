"""Fixtures of the picture reader's tests that read the acceptance benchmark's pictures."""

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
