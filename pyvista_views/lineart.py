"""Vector line art of meschers: SVG and PDF files, and the lines over a PyVista render.

:func:`meschers_igl.lines.line_drawing` computes the lines (outlines, occlusion lines with their
T-junctions, creases, occluding contours) and their visibility from the depth order; here they
become a drawing:

* :func:`to_svg` writes one ``<path>`` per joined polyline, grouped by kind (``<g id="outline">``
  ...), with round caps and joins and a stroke width per kind: thick outlines, medium occlusion
  lines, thin creases; hidden lines, on request, dashed and grey underneath.  The file uses
  nothing but paths and groups, so Inkscape, Illustrator and a journal's PDF pipeline read it
  as it is.
* :func:`draw` is the front door: a mescher (and order) to an SVG, PDF or PNG file, or to the
  SVG text.  PDF and PNG go through cairosvg (``pip install cairosvg``).
* :func:`overlay` draws the lines over :func:`pyvista_views.render`'s picture with the same
  framing (the same :func:`pyvista_views.camera.default_bounds`), so the lines sit on the
  shaded figure's edges.

The framing follows the renderer's: ``bounds = (xmin, xmax, ymin, ymax)`` in screen units is
exactly the picture's extent, with square pixels.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.lines import KINDS, LineDrawing, line_drawing
from meschers_igl.validate import as_choice, as_positive

from .camera import as_bounds, as_window_size, default_bounds

__all__ = ["DEFAULT_WIDTHS", "HIDDEN_MODES", "draw", "overlay", "picture", "rasterize", "to_svg"]

#: Stroke widths (pixels of the picture) per kind.
DEFAULT_WIDTHS = {"outline": 2.5, "occlusion": 1.8, "crease": 1.1, "hidden": 0.9}
HIDDEN_MODES = ("omit", "dashed")
#: Formats :func:`draw` writes, by file suffix.
FORMATS = (".svg", ".pdf", ".png")
_HIDDEN_COLOR = "#8c8c8c"


def _cairosvg():
    try:
        import cairosvg
    except ImportError as exc:  # optional: only PDF/PNG output and rasterizing need it
        raise ImportError(
            "PDF and PNG output of line drawings need cairosvg: pip install "
            '"meschers[lineart]" (or cairosvg; and the system\'s libcairo2)'
        ) from exc
    return cairosvg


def _frame(lines: LineDrawing, window_size: Any, bounds: Any) -> tuple[tuple[int, int], tuple]:
    window_size = as_window_size(window_size)
    b = default_bounds(lines.box, window_size) if bounds is None else as_bounds(bounds)
    return window_size, b


def _widths(widths: Any) -> dict[str, float]:
    out = dict(DEFAULT_WIDTHS)
    if widths is None:
        return out
    if isinstance(widths, (int, float)):  # one width for every kind
        w = as_positive(widths, "widths")
        return {k: w for k in out}
    if not isinstance(widths, dict):
        raise MescherError(
            f"widths: expected a number or a dict of kind -> width, found {type(widths).__name__}"
        )
    for k, v in widths.items():
        as_choice(k, "widths key", (*KINDS, "hidden"))
        out[k] = as_positive(v, f"widths[{k!r}]")
    return out


def to_svg(
    lines: LineDrawing,
    path: Any = None,
    *,
    window_size: tuple[int, int] = (800, 800),
    bounds: Any = None,
    widths: Any = None,
    color: str = "black",
    hidden: str = "omit",
    background: str | None = None,
) -> str:
    """The SVG text of a line drawing (also written to ``path`` if given).

    Parameters
    ----------
    lines : meschers_igl.lines.LineDrawing
    path : str or Path, optional
        An ``.svg`` file to write.
    window_size : (int, int), default: (800, 800)
        (width, height) of the picture in pixels (SVG user units).
    bounds : (xmin, xmax, ymin, ymax), optional
        Screen box shown, exactly; default: the mescher's box plus a 5% margin, widened to the
        window's aspect (as :func:`pyvista_views.render`).
    widths : float or dict, optional
        Stroke width in pixels per kind (``"outline"``, ``"occlusion"``, ``"crease"``,
        ``"hidden"``), or one number for all; default :data:`DEFAULT_WIDTHS`.
    color : str, default: "black"
    hidden : {"omit", "dashed"}, default: "omit"
        Hidden lines (present in ``lines`` when computed with ``hidden=True``) drawn dashed and
        grey below the visible ones, or left out.
    background : str, optional
        A background colour (a full-size rectangle); default transparent.

    Returns
    -------
    str
    """
    if not isinstance(lines, LineDrawing):
        raise MescherError(f"lines: expected a LineDrawing, found {type(lines).__name__}")
    hidden = as_choice(hidden, "hidden", HIDDEN_MODES)
    (W, H), (x0, x1, y0, y1) = _frame(lines, window_size, bounds)
    w = _widths(widths)
    sx, sy = W / (x1 - x0), H / (y1 - y0)
    P = np.empty_like(lines.points)
    P[:, 0] = (lines.points[:, 0] - x0) * sx
    P[:, 1] = (y1 - lines.points[:, 1]) * sy
    text = np.char.mod("%.2f", P)
    coords = np.char.add(np.char.add(text[:, 0], " "), text[:, 1])

    def paths(idx: np.ndarray) -> list[str]:
        out = []
        for i in idx.tolist():
            a, b = int(lines.offsets[i]), int(lines.offsets[i + 1])
            closed = bool(lines.closed[i]) and b - a > 2
            pts = coords[a : b - 1] if closed else coords[a:b]
            d = "M" + " L".join(pts.tolist()) + (" Z" if closed else "")
            out.append(f'    <path d="{d}"/>')
        return out

    head = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{W}" height="{H}" '
        f'viewBox="0 0 {W} {H}">',
        "  <title>line drawing</title>",
    ]
    if background is not None:
        head.append(f'  <rect width="{W}" height="{H}" fill="{background}"/>')
    body = []
    common = 'fill="none" stroke-linecap="round" stroke-linejoin="round"'
    if hidden == "dashed":
        idx = np.flatnonzero(~lines.visible)
        if idx.size:
            dash = f"{3 * w['hidden']:.2f} {2.5 * w['hidden']:.2f}"
            body += [
                f'  <g id="hidden" {common} stroke="{_HIDDEN_COLOR}" '
                f'stroke-width="{w["hidden"]:.2f}" stroke-dasharray="{dash}">',
                *paths(idx),
                "  </g>",
            ]
    for code in (2, 1, 0):  # creases under occlusion lines under outlines
        name = KINDS[code]
        idx = np.flatnonzero(lines.visible & (lines.kind == code))
        if idx.size:
            body += [
                f'  <g id="{name}" {common} stroke="{color}" stroke-width="{w[name]:.2f}">',
                *paths(idx),
                "  </g>",
            ]
    svg = "\n".join([*head, *body, "</svg>", ""])
    if path is not None:
        Path(path).write_text(svg, encoding="utf-8")
    return svg


def rasterize(svg: str, window_size: tuple[int, int], background: Any = "white") -> np.ndarray:
    """An SVG drawn to pixels by cairosvg: (H, W, 4) uint8 RGBA (``background=None``: alpha
    only where lines are)."""
    from PIL import Image

    W, H = as_window_size(window_size)
    png = _cairosvg().svg2png(
        bytestring=svg.encode("utf-8"),
        output_width=W,
        output_height=H,
        background_color=background,
    )
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGBA"))


def draw(
    m: Any,
    order: Any = None,
    path: Any = None,
    *,
    crease_angle: float = 30.0,
    contours: str = "auto",
    hidden: str = "omit",
    window_size: tuple[int, int] = (800, 800),
    bounds: Any = None,
    widths: Any = None,
    color: str = "black",
    background: str | None = None,
    lines: LineDrawing | None = None,
) -> str:
    """Line art of a mescher as SVG, written to ``path`` (``.svg``, ``.pdf`` or ``.png``).

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional
        The depth order the lines' visibility follows (default: face-index order).
    path : str or Path, optional
        Where to write; the suffix picks the format (PDF and PNG need cairosvg).
    crease_angle : float, default: 30
        Degrees (:func:`meschers_igl.lines.line_drawing`).
    contours : {"auto", "mesh", "interpolated"}
    hidden : {"omit", "dashed"}, default: "omit"
    window_size, bounds, widths, color, background
        As in :func:`to_svg` (a PDF page is ``window_size`` points; a PNG that many pixels,
        white unless ``background`` says otherwise).
    lines : LineDrawing, optional
        Lines already computed (the other line options are then ignored).

    Returns
    -------
    str
        The SVG text.
    """
    hidden = as_choice(hidden, "hidden", HIDDEN_MODES)
    suffix = None
    if path is not None:
        suffix = Path(path).suffix.lower()
        if suffix not in FORMATS:
            raise MescherError(
                f"path: expected a file name ending in {', '.join(FORMATS)}, found '{path}'"
            )
    if lines is None:
        lines = line_drawing(
            m, order, crease_angle=crease_angle, contours=contours, hidden=hidden == "dashed"
        )
    svg = to_svg(
        lines,
        window_size=window_size,
        bounds=bounds,
        widths=widths,
        color=color,
        hidden=hidden,
        background=background,
    )
    if suffix == ".svg":
        Path(path).write_text(svg, encoding="utf-8")
    elif suffix == ".pdf":
        _cairosvg().svg2pdf(bytestring=svg.encode("utf-8"), write_to=str(path))
    elif suffix == ".png":
        from PIL import Image

        img = rasterize(svg, as_window_size(window_size), background or "white")
        Image.fromarray(img).save(path)
    return svg


def overlay(
    m: Any,
    order: Any = None,
    image: np.ndarray | None = None,
    *,
    window_size: tuple[int, int] = (800, 800),
    bounds: Any = None,
    crease_angle: float = 30.0,
    contours: str = "auto",
    hidden: str = "omit",
    widths: Any = None,
    color: str = "black",
    lines: LineDrawing | None = None,
    **render_kwargs: Any,
) -> np.ndarray:
    """The line drawing over a shaded render with the same framing: (H, W, 3) uint8.

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional
    image : (H, W, 3) uint8, optional
        A picture already rendered with these ``bounds`` and ``window_size``; default
        :func:`pyvista_views.render` ``(m, order, bounds=..., window_size=..., **render_kwargs)``.
    window_size, bounds, crease_angle, contours, hidden, widths, color, lines
        As in :func:`draw`.
    **render_kwargs
        Passed to :func:`pyvista_views.render` (``lights``, ``shading``, ...).

    Returns
    -------
    (H, W, 3) uint8
    """
    window_size = as_window_size(window_size)
    if lines is None:
        lines = line_drawing(
            m,
            order,
            crease_angle=crease_angle,
            contours=contours,
            hidden=as_choice(hidden, "hidden", HIDDEN_MODES) == "dashed",
        )
    b = default_bounds(lines.box, window_size) if bounds is None else as_bounds(bounds)
    if image is None:
        from .render import render

        image = render(m, order, bounds=b, window_size=window_size, **render_kwargs)
    image = np.asarray(image)
    if image.shape[:2] != (window_size[1], window_size[0]):
        raise MescherError(
            f"image: expected shape ({window_size[1]}, {window_size[0]}, 3) for window_size "
            f"{window_size}, found {image.shape}"
        )
    svg = to_svg(
        lines, window_size=window_size, bounds=b, widths=widths, color=color, hidden=hidden
    )
    rgba = rasterize(svg, window_size, background=None).astype(np.float64)
    alpha = rgba[..., 3:4] / 255.0
    out = image[..., :3].astype(np.float64) * (1.0 - alpha) + rgba[..., :3] * alpha
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)


def picture(
    lines: LineDrawing,
    window_size: tuple[int, int] = (800, 800),
    *,
    bounds: Any = None,
    widths: Any = None,
    color: str = "black",
    hidden: str = "omit",
) -> np.ndarray:
    """The line drawing as pixels on white: (H, W, 3) uint8.

    The SVG of :func:`to_svg` rasterized by cairosvg; without cairosvg (or the system's
    cairo), the same polylines drawn by PIL at 4x and downsampled (round joins, no dashes).
    """
    window_size = as_window_size(window_size)
    try:
        svg = to_svg(
            lines,
            window_size=window_size,
            bounds=bounds,
            widths=widths,
            color=color,
            hidden=hidden,
        )
        return rasterize(svg, window_size)[..., :3]
    except (ImportError, OSError):
        pass
    from PIL import Image, ImageDraw

    (W, H), (x0, x1, y0, y1) = _frame(lines, window_size, bounds)
    w, k = _widths(widths), 4
    img = Image.new("RGB", (W * k, H * k), "white")
    pen = ImageDraw.Draw(img)
    P = np.c_[
        (lines.points[:, 0] - x0) * (W * k / (x1 - x0)),
        (y1 - lines.points[:, 1]) * (H * k / (y1 - y0)),
    ]
    for code in (2, 1, 0):
        width = max(1, round(w[KINDS[code]] * k))
        for i in np.flatnonzero(lines.visible & (lines.kind == code)).tolist():
            pts = [tuple(p) for p in P[lines.offsets[i] : lines.offsets[i + 1]].tolist()]
            pen.line(pts, fill=color, width=width, joint="curve")
    return np.asarray(img.resize((W, H), Image.LANCZOS))
