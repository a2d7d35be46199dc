"""Headless rendering set-up: a display-free GL window when there is no display, and the
plotter every view starts from.

On Linux, VTK's default window tries X first and prints ``vtkXOpenGLRenderWindow ... bad X server
connection`` when no X server answers, before falling back.  Asking for a display-free
window up front avoids the warning: ``vtkEGLRenderWindow`` (EGL: a GPU, or Mesa's llvmpipe) when
``libEGL`` can be loaded, else ``vtkOSOpenGLRenderWindow`` (OSMesa, software).  The choice goes in
``VTK_DEFAULT_OPENGL_WINDOW``, which VTK reads whenever it makes a render window, so
:func:`configure_headless` runs when this package is imported; it never overrides a value the
user set, and it does nothing where an X server answers.  "No display" means that no X server
answers at ``$DISPLAY`` (unset, or a stale ``:99`` left by a finished Xvfb), tried once per value
with Xlib's ``XOpenDisplay``, which fails quietly.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import os
import sys

import pyvista as pv

from meschers_igl.errors import MescherError

#: The environment variable VTK reads to choose its OpenGL window class.
WINDOW_VARIABLE = "VTK_DEFAULT_OPENGL_WINDOW"
#: Display-free window classes in order of preference, with the library each one needs.
HEADLESS_WINDOWS = (("vtkEGLRenderWindow", "EGL"), ("vtkOSOpenGLRenderWindow", "OSMesa"))


@functools.lru_cache(maxsize=8)
def _x_server_answers(display: str) -> bool:
    """Whether an X server accepts a connection at ``display`` (Xlib's ``XOpenDisplay``)."""
    name = ctypes.util.find_library("X11")
    if not display or name is None:
        return False
    try:
        x11 = ctypes.CDLL(name)
    except OSError:
        return False
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    handle = x11.XOpenDisplay(display.encode())
    if not handle:
        return False
    x11.XCloseDisplay(handle)
    return True


def has_display() -> bool:
    """Whether an on-screen window can be opened: always off Linux; on Linux, whether an X server
    answers at ``$DISPLAY`` (VTK's on-screen windows there are X windows)."""
    if not sys.platform.startswith("linux"):
        return True
    return _x_server_answers(os.environ.get("DISPLAY", ""))


@functools.lru_cache(maxsize=1)
def headless_window() -> str | None:
    """The display-free VTK window class this machine can load (:data:`HEADLESS_WINDOWS`), or
    ``None`` when it has neither libEGL nor libOSMesa (VTK then keeps its own fallback)."""
    for window, library in HEADLESS_WINDOWS:
        if ctypes.util.find_library(library) is not None:
            return window
    return None


def configure_headless() -> str | None:
    """Choose a display-free VTK window on a Linux machine without a display.

    Sets ``VTK_DEFAULT_OPENGL_WINDOW`` to :func:`headless_window` unless the user set it or an X
    server answers.

    Returns
    -------
    str or None
        The window class VTK will use by default (the user's, ours, or ``None``: VTK's own choice).
    """
    if WINDOW_VARIABLE not in os.environ and not has_display():
        window = headless_window()
        if window is not None:
            os.environ[WINDOW_VARIABLE] = window
    return os.environ.get(WINDOW_VARIABLE)


def in_notebook() -> bool:
    """Whether this is a Jupyter kernel, where a view is a widget (trame renders it off screen
    on the server and streams it) rather than a window or a screenshot."""
    import scooby

    return bool(scooby.in_ipykernel())


def is_offscreen(off_screen: bool | None = None) -> bool:
    """Whether views must render off screen: asked for, ``pyvista.OFF_SCREEN``, or no display."""
    if off_screen is not None:
        return bool(off_screen)
    return bool(pv.OFF_SCREEN) or not has_display()


def new_plotter(
    window_size: tuple[int, int] = (800, 800),
    off_screen: bool | None = None,
    background: object = "white",
    anti_aliasing: bool | str = False,
    **kwargs: object,
) -> pv.Plotter:
    """A plotter with no light kit and no headlight (lights are added by :mod:`.lights`).

    ``anti_aliasing``: ``False`` (off: ``bounds`` maps to whole pixels exactly and
    silhouettes compare pixel for pixel), ``"fxaa"`` (VTK's FXAA post-pass: edges smoothed
    cheaply), ``"ssaa"`` or ``True`` (supersampling: the best edges, several times the pixels)
    or ``"msaa"``.
    """
    plotter = pv.Plotter(
        off_screen=is_offscreen(off_screen),
        window_size=list(window_size),
        lighting="none",
        **kwargs,
    )
    mode = as_anti_aliasing(anti_aliasing)
    if mode is None:
        plotter.disable_anti_aliasing()
    elif mode == "fxaa":
        # VTK's FXAA pass directly: PyVista swaps it for SSAA on EGL builds, several times
        # the cost, though the pass draws right there (checked against SSAA by the tests)
        plotter.disable_anti_aliasing()
        plotter.renderer.SetUseFXAA(True)
    else:
        plotter.enable_anti_aliasing(mode)
    plotter.set_background(background)
    return plotter


AA_MODES = ("fxaa", "ssaa", "msaa")
#: Anti-aliasing of :func:`~pyvista_views.render` and :class:`~pyvista_views.MescherScene`
#: unless told otherwise: FXAA, a post-pass that smooths edges for about a tenth of a second
#: at 1024^2 on a software rasterizer (SSAA costs 2-2.5x a frame there).
DEFAULT_ANTI_ALIASING: bool | str = "fxaa"


def as_anti_aliasing(anti_aliasing: object) -> str | None:
    """``None`` (off) or one of :data:`AA_MODES`; ``True`` means ``"ssaa"``."""
    if anti_aliasing is None or anti_aliasing is False:
        return None
    if anti_aliasing is True:
        return "ssaa"
    if isinstance(anti_aliasing, str) and anti_aliasing in AA_MODES:
        return anti_aliasing
    raise MescherError(
        f"anti_aliasing: expected False, True or one of {AA_MODES}, found {anti_aliasing!r}"
    )


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
