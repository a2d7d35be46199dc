"""Offscreen rendering fixtures: no display, a GL skip marker, a theme reset, image regression.

Image regression follows PyVista's ``verify_image_cache`` idea with per-test tolerances: each test
names its own ``mean`` (mean absolute difference, 0-255) and ``frac`` (fraction of pixels off by
more than 16) limits.  Set ``MESCHERS_REGENERATE_BASELINES=1`` to rewrite the PNGs under
``baseline/`` from the current code (then inspect them before committing).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv

from pyvista_views.headless import configure_headless

configure_headless()
pv.OFF_SCREEN = True

BASELINE = Path(__file__).parent / "baseline"


@pytest.fixture(autouse=True)
def _reset_theme():
    """Tests must not leak theme changes into each other."""
    pv.global_theme.restore_defaults()
    pv.OFF_SCREEN = True
    yield
    pv.global_theme.restore_defaults()


@pytest.fixture
def image_regression():
    """``check(name, image, mean=..., frac=...)`` against ``baseline/<name>.png``."""
    from PIL import Image

    def check(name: str, image: np.ndarray, mean: float, frac: float) -> None:
        path = BASELINE / f"{name}.png"
        if os.environ.get("MESCHERS_REGENERATE_BASELINES") == "1" or not path.exists():
            if not os.environ.get("MESCHERS_REGENERATE_BASELINES") and not path.exists():
                pytest.fail(f"missing baseline {path.name}; set MESCHERS_REGENERATE_BASELINES=1")
            path.parent.mkdir(exist_ok=True)
            Image.fromarray(image).save(path)
            return
        ref = np.asarray(Image.open(path).convert("RGB"))
        assert ref.shape == image.shape, f"{name}: shape {image.shape} != baseline {ref.shape}"
        diff = np.abs(ref.astype(np.int16) - image.astype(np.int16)).max(axis=-1)
        assert diff.mean() <= mean, f"{name}: mean abs difference {diff.mean():.3f} > {mean}"
        off = float((diff > 16).mean())
        assert off <= frac, f"{name}: {off:.4f} of pixels differ by > 16 (limit {frac})"

    return check
