"""Headless rendering set-up: EGL when there is no display, and the plotter every view starts from.

VTK first tries an X window and prints "bad X server connection" when there is none; asking for
``vtkEGLRenderWindow`` up front avoids that (FACTS.md).  The variable must be set before the first
render window exists, so it is set when this package is imported, only on Linux without a display,
and only if the user has not chosen a window class already.
"""

from __future__ import annotations

import functools
import os
import sys

import pyvista as pv

_EGL_VARIABLE = "VTK_DEFAULT_OPENGL_WINDOW"


def has_display() -> bool:
    """Whether an on-screen window can be opened (always true off Linux)."""
    if not sys.platform.startswith("linux"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def configure_headless() -> None:
    """Ask VTK for an EGL window on a Linux machine without a display (user's choice kept)."""
    if not has_display():
        os.environ.setdefault(_EGL_VARIABLE, "vtkEGLRenderWindow")


def is_offscreen(off_screen: bool | None = None) -> bool:
    """Whether views must render off screen: asked for, ``pyvista.OFF_SCREEN``, or no display."""
    if off_screen is not None:
        return bool(off_screen)
    return bool(pv.OFF_SCREEN) or not has_display()


def new_plotter(
    window_size: tuple[int, int] = (800, 800),
    off_screen: bool | None = None,
    background: object = "white",
    anti_aliasing: bool = False,
    **kwargs: object,
) -> pv.Plotter:
    """A plotter with no light kit and no headlight (lights are added by :mod:`.lights`).

    Anti-aliasing is off by default so that ``bounds`` maps to whole pixels exactly and
    silhouettes compare pixel for pixel; pass ``anti_aliasing=True`` for figures.
    """
    plotter = pv.Plotter(
        off_screen=is_offscreen(off_screen),
        window_size=list(window_size),
        lighting="none",
        **kwargs,
    )
    if anti_aliasing:
        plotter.enable_anti_aliasing("ssaa")
    else:
        plotter.disable_anti_aliasing()
    plotter.set_background(background)
    return plotter


@functools.lru_cache(maxsize=1)
def gl_available() -> bool:
    """Whether an (offscreen) OpenGL context can be made here; tried once per process."""
    configure_headless()
    try:
        plotter = pv.Plotter(off_screen=True, window_size=[8, 8], lighting="none")
        plotter.add_mesh(pv.Triangle())
        image = plotter.screenshot(return_img=True)
        plotter.close()
    except Exception:  # any VTK/GL failure means "no context", the only question asked here
        return False
    return image is not None and image.shape[:2] == (8, 8)
