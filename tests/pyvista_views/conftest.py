"""Offscreen rendering fixtures: no display, a theme reset.

Image regression uses pytest-pyvista's ``verify_image_cache`` (``test_images.py``, references in
``image_cache/``).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import pyvista as pv

from pyvista_views.headless import configure_headless

configure_headless()
pv.OFF_SCREEN = True


def pytest_configure(config: pytest.Config) -> None:
    """pytest-pyvista's reference images live here (its ``--image_cache_dir`` unless given);
    the ``antialiased`` marker is declared."""
    config.addinivalue_line("markers", "antialiased: render with the default anti-aliasing")
    if getattr(config.option, "image_cache_dir", "absent") is None:
        config.option.image_cache_dir = str(Path(__file__).parent / "image_cache")


@pytest.fixture(autouse=True)
def _pixel_exact(request, monkeypatch):
    """Image measures compare silhouettes and shades pixel for pixel, so pictures are drawn
    without anti-aliasing unless a test is marked ``antialiased`` (the default a user gets)."""
    import pyvista_views.headless as headless

    if request.node.get_closest_marker("antialiased") is None:
        monkeypatch.setattr(headless, "DEFAULT_ANTI_ALIASING", False)
    yield


@pytest.fixture(autouse=True)
def _reset_theme():
    """Tests must not leak theme changes into each other."""
    pv.global_theme.restore_defaults()
    pv.OFF_SCREEN = True
    yield
    pv.global_theme.restore_defaults()
