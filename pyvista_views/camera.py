"""The head-on camera every picture uses: screen boxes, image bounds and the orthographic view.

The camera frame of docs/conventions.rst (x right, y up, z toward the viewer) is the scene frame: the camera
looks down -z with y up and is orthographic, so ``bounds = (xmin, xmax, ymin, ymax)`` in screen
units is exactly the image's extent.  Pixel (row r, column c) of a ``(width, height)`` window
covers ``x in xmin + [c, c+1] * (xmax-xmin)/width`` and ``y in ymax - [r+1, r] * (ymax-ymin)/height``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_count, as_float_array, check_budget

#: Share of the content's size added on every side by :func:`default_bounds`.
DEFAULT_MARGIN = 0.05
#: Peak bytes per window pixel: RGBA colour and 24-bit depth buffers on the GPU or in Mesa's
#: software framebuffer, the RGB(A) screenshot copy and its float conversions in numpy.
BYTES_PER_PIXEL = 48.0


def as_window_size(window_size: object, force: bool = False) -> tuple[int, int]:
    """Validate a render window size ``(width, height)``; refuse one that does not fit in memory.

    Parameters
    ----------
    window_size : (int, int)
        Positive integers.
    force : bool, default: False
        Skip the memory estimate (:func:`meschers_igl.validate.check_budget`).

    Returns
    -------
    (int, int)
    """
    if isinstance(window_size, (str, bytes)) or np.ndim(window_size) != 1 or len(window_size) != 2:
        raise MescherError(
            f"window_size: expected (width, height) positive integers, found {window_size!r}"
        )
    w = as_count(window_size[0], "window_size[0] (width)", minimum=1)
    h = as_count(window_size[1], "window_size[1] (height)", minimum=1)
    check_budget(
        float(w) * float(h),
        BYTES_PER_PIXEL,
        f"window_size ({w} x {h} pixels)",
        force=force,
        unit="pixels",
    )
    return (w, h)


def xy_box(xy: Any) -> tuple[float, float, float, float]:
    """Screen box ``(xmin, xmax, ymin, ymax)`` of points.

    Parameters
    ----------
    xy : (n, >=2) array_like
        Screen positions (extra columns, e.g. z, are ignored).

    Returns
    -------
    (float, float, float, float)
    """
    xy = np.asarray(xy, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[0] == 0 or xy.shape[1] < 2:
        raise MescherError(f"xy: expected (n >= 1, 2) screen positions, found shape {xy.shape}")
    return (
        float(xy[:, 0].min()),
        float(xy[:, 0].max()),
        float(xy[:, 1].min()),
        float(xy[:, 1].max()),
    )


def default_bounds(
    box: Sequence[float],
    window_size: Sequence[int],
    margin: float = DEFAULT_MARGIN,
    reserve: float = 0.0,
) -> tuple[float, float, float, float]:
    """``box`` (xmin, xmax, ymin, ymax) grown by ``margin`` of its size, then widened in x or y to
    the window's aspect ratio so that pixels are square.

    Parameters
    ----------
    box : (4,) float
        Content's screen box (:func:`xy_box`).
    window_size : (int, int)
        (width, height) in pixels.
    margin : float
        Fraction of the box's width (height) added on the left and right (top and bottom).
    reserve : float, default: 0
        Share of the window's width kept free on the right (for a colour bar): the box is
        framed in the left ``1 - reserve`` of the window.

    Returns
    -------
    (xmin, xmax, ymin, ymax) with ``(xmax - xmin) / (ymax - ymin) == width / height``.
    """
    xmin, xmax, ymin, ymax = (float(b) for b in box)
    w, h = xmax - xmin, ymax - ymin
    size = max(w, h) or 1.0
    w, h = max(w, 1e-9 * size), max(h, 1e-9 * size)  # a segment or a point still gets a frame
    cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
    w, h = w * (1 + 2 * margin), h * (1 + 2 * margin)
    reserve = float(reserve)
    if not 0.0 <= reserve < 1.0:
        raise MescherError(f"reserve: expected a share of the width in [0, 1), found {reserve}")
    aspect = (1.0 - reserve) * window_size[0] / window_size[1]
    if w / h < aspect:
        w = h * aspect
    else:
        h = w / aspect
    left, right = cx - w / 2, cx + w / 2
    return (left, right + w * reserve / (1.0 - reserve), cy - h / 2, cy + h / 2)


def as_bounds(bounds: object) -> tuple[float, float, float, float]:
    """Validate ``(xmin, xmax, ymin, ymax)`` with ``xmin < xmax`` and ``ymin < ymax``."""
    b = as_float_array(bounds, "bounds", (4,))
    if not (b[0] < b[1] and b[2] < b[3]):
        raise MescherError(
            f"bounds: expected (xmin, xmax, ymin, ymax) with xmin < xmax and ymin < ymax, "
            f"found {tuple(b.tolist())}"
        )
    return tuple(float(v) for v in b)


def set_view(plotter: Any, bounds: Sequence[float]) -> None:
    """Orthographic camera down -z, y up, whose image is exactly ``bounds`` (xmin, xmax, ymin,
    ymax): the vertical extent is ``2 * parallel_scale`` and an explicit aspect ratio fixes the
    horizontal one (pixels are square only when the window has the same aspect as ``bounds``).
    The clipping range hugs the scene's z range so the painter's steps stay resolvable in the
    depth buffer."""
    xmin, xmax, ymin, ymax = as_bounds(bounds)
    # one bounds pass over every prop (each access of plotter.bounds is one, about 7 ms at 1M
    # points), and the camera flagged as set before it is read, so that PyVista does not
    # reset it (another pass) only for us to overwrite it
    scene_bounds = plotter.bounds
    zmin, zmax = scene_bounds[4], scene_bounds[5]
    if not np.isfinite([zmin, zmax]).all() or zmax < zmin:  # empty scene
        zmin, zmax = 0.0, 0.0
    size = max(xmax - xmin, ymax - ymin)
    pad = 0.01 * (zmax - zmin) + 1e-6 * size
    distance = size + pad
    plotter.camera_set = True
    camera = plotter.camera
    # vtkCamera's own setters: PyVista's properties reset the clipping range after each one
    # (a bounds pass each), which the last line sets anyway
    camera.SetParallelProjection(True)
    cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
    camera.SetFocalPoint(cx, cy, zmin)
    camera.SetPosition(cx, cy, zmax + distance)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetParallelScale(0.5 * (ymax - ymin))
    camera.SetExplicitAspectRatio((xmax - xmin) / (ymax - ymin))
    camera.SetUseExplicitAspectRatio(True)
    camera.SetClippingRange(distance - pad, distance + (zmax - zmin) + pad)
