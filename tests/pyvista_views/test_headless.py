"""Quiet headless use: no X warning from a plain ``import pyvista_views`` + render (issue 16.5)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from pvv_helpers import requires_gl

from pyvista_views import headless

RENDER = """
import numpy as np
import pyvista as pv
{imports}
s = pv.Sphere(theta_resolution=12, phi_resolution=12)
V, F = np.asarray(s.points), s.regular_faces
{draw}
print("window", {window})
print("figure", int((img != 255).any(axis=-1).sum()))
"""
OURS = RENDER.format(
    imports="import pyvista_views",
    draw="img = pyvista_views.render((V, F), window_size=(48, 48))",
    window="pv.Plotter(off_screen=True).ren_win.GetClassName()",
)
PLAIN = RENDER.format(
    imports="",
    draw=(
        "pl = pv.Plotter(off_screen=True, window_size=(48, 48)); pl.add_mesh(pv.Sphere())\n"
        "img = pl.screenshot(return_img=True)[..., :3]"
    ),
    window="pl.ren_win.GetClassName()",
)


def _run(code: str, display: str | None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("VTK_DEFAULT_OPENGL_WINDOW", "DISPLAY")}
    if display is not None:
        env["DISPLAY"] = display
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )


def _unused_display() -> str:
    """An X display name no server answers at (what a finished Xvfb leaves in $DISPLAY)."""
    for n in range(187, 260):
        if not os.path.exists(f"/tmp/.X11-unix/X{n}") and not headless._x_server_answers(f":{n}"):
            return f":{n}"
    pytest.skip("no unused X display number")


@requires_gl
@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X windows are Linux's")
@pytest.mark.parametrize("display", [None, "stale"])
def test_plain_import_and_render_print_no_x_warning(display):
    name = _unused_display() if display == "stale" else None
    if display is None:  # the yardstick: PyVista by itself warns here, so the check can fail
        plain = _run(PLAIN, name)
        if "bad X server connection" not in plain.stderr:
            pytest.skip("this VTK prints no X warning even by itself: nothing to silence")
    ours = _run(OURS, name)
    assert ours.returncode == 0, ours.stderr
    assert "bad X server" not in ours.stderr and "vtkXOpenGLRenderWindow" not in ours.stderr
    out = dict(line.split(" ", 1) for line in ours.stdout.splitlines())
    assert out["window"] in {w for w, _ in headless.HEADLESS_WINDOWS}
    assert int(out["figure"]) > 200  # a sphere drawn, not a blank image: 48 x 48 = 2304 pixels


def test_a_stale_display_is_no_display(monkeypatch):
    monkeypatch.setenv("DISPLAY", _unused_display())
    assert headless.has_display() is False or not sys.platform.startswith("linux")
    monkeypatch.delenv("DISPLAY")
    assert headless.has_display() is False or not sys.platform.startswith("linux")


def test_the_users_window_choice_is_kept(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.setenv("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    assert headless.configure_headless() == "vtkOSOpenGLRenderWindow"
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW")
    chosen = headless.configure_headless()
    assert chosen == headless.headless_window()
    assert os.environ.get("VTK_DEFAULT_OPENGL_WINDOW") == chosen
