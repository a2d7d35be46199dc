"""Figures of the study and the command line, composed with PIL from renders.

Pure image work: labelled grids of panels (:func:`compose`), colour bars, screen-space marks on a
render (:func:`overlay`, whose labels are placed so that they never overlap), numbers printed
with round-off shown as 0 (:func:`format_value`), and PNG bytes.  No rendering happens here; the
renders come from :class:`pyvista_views.MescherScene`.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = [
    "Colorbar",
    "compose",
    "format_value",
    "fit_text",
    "font",
    "format_values",
    "lines_over",
    "overlay",
    "png_bytes",
    "screen_to_pixel",
]

#: A value below this fraction of its scale is round-off and printed as 0.
ZERO_FRACTION = 1e-9
#: A colour-bar tick closer to 0 than this fraction of the bar's span is labelled 0 (a bar
#: cannot show a difference that small: the middle of (-0.593, 0.5929) is 0, not -3.21e-05).
TICK_ZERO_FRACTION = 1e-3


def round_off_scale(values: Sequence[float], size: float) -> float:
    """The scale periods are printed against: the largest ``|value|`` or the model's ``size``,
    whichever is larger (so periods that are all round-off print as 0, not as 1e-15)."""
    return max(max((abs(float(v)) for v in values), default=0.0), float(size))


def format_value(x: float, scale: float | None = None, digits: int = 4) -> str:
    """``x`` with ``digits`` significant digits, or ``"0"`` when ``|x| < 1e-9 * scale``.

    Parameters
    ----------
    x : float
    scale : float, optional
        The size the value is compared with (default ``|x|`` itself: only exact zeros are 0).
    digits : int

    Examples
    --------
    >>> format_value(1.78e-15, scale=6.93)
    '0'
    >>> format_value(6.928203, scale=6.93)
    '6.928'
    """
    x = float(x)
    s = abs(x) if scale is None else abs(float(scale))
    if x == 0 or (s > 0 and abs(x) < ZERO_FRACTION * s):
        return "0"
    return f"{x:.{digits}g}"


def format_values(values: Sequence[float], digits: int = 4, scale: float | None = None) -> str:
    """Comma-separated :func:`format_value` with one scale for all (default: the largest |value|),
    ``"none"`` for an empty sequence."""
    values = [float(v) for v in values]
    if not values:
        return "none"
    s = max(abs(v) for v in values) if scale is None else scale
    return ", ".join(format_value(v, s, digits) for v in values)


def font(size: int = 13):
    """PIL's default (scalable) font at ``size`` pixels."""
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1 has one bitmap size
        return ImageFont.load_default()


def screen_to_pixel(P: np.ndarray, bounds: Sequence[float], size: tuple[int, int]) -> np.ndarray:
    """Screen points to pixel coordinates of an image with exactly ``bounds`` as extent.

    Parameters
    ----------
    P : (k, 2) float
        Screen positions (x right, y up).
    bounds : (xmin, xmax, ymin, ymax)
    size : (width, height)

    Returns
    -------
    (k, 2) float
        ``(column, row)`` with row 0 at the top: ``c = (x - xmin) / (xmax - xmin) * W``,
        ``r = (ymax - y) / (ymax - ymin) * H`` (pixel centres at half-integers).
    """
    P = np.asarray(P, dtype=np.float64).reshape(-1, 2)
    xmin, xmax, ymin, ymax = (float(b) for b in bounds)
    w, h = size
    return np.column_stack(
        [(P[:, 0] - xmin) / (xmax - xmin) * w, (ymax - P[:, 1]) / (ymax - ymin) * h]
    )


class Colorbar:
    """A vertical colour bar: ``cmap`` from ``vmin`` (bottom) to ``vmax`` (top), with a title.

    Parameters
    ----------
    cmap : str
        A matplotlib colour map name (the one the panels were rendered with).
    vmin, vmax : float
    title : str
        What the colour means, e.g. ``"log10(u / max u)"``.
    ticks : int
        Labelled values, evenly spaced.
    """

    width = 100

    def __init__(self, cmap: str, vmin: float, vmax: float, title: str, ticks: int = 5):
        self.cmap, self.vmin, self.vmax, self.title, self.ticks = cmap, vmin, vmax, title, ticks

    def draw(self, height: int):
        """The bar as a PIL image ``(width, height)``."""
        from matplotlib import colormaps
        from PIL import Image, ImageDraw

        canvas = Image.new("RGB", (self.width, height), "white")
        draw, fnt = ImageDraw.Draw(canvas), font(11)
        top, bottom, x0, x1 = 30, height - 12, 6, 20
        n = max(bottom - top, 2)
        ramp = colormaps[self.cmap](np.linspace(1.0, 0.0, n))[:, :3]  # top = vmax
        strip = np.repeat((255 * ramp).astype(np.uint8)[:, None, :], x1 - x0, axis=1)
        canvas.paste(Image.fromarray(strip), (x0, top))
        draw.rectangle([x0 - 1, top - 1, x1, top + n], outline="black")
        for i, line in enumerate(_wrap(self.title, 15)[:2]):
            draw.text((2, 2 + 12 * i), line, fill="black", font=fnt)
        span = self.vmax - self.vmin
        for k in range(self.ticks):
            f = k / (self.ticks - 1)
            y = top + (1 - f) * (n - 1)
            value = self.vmin + f * span
            if abs(value) < TICK_ZERO_FRACTION * abs(span):  # 0 to the bar's resolution
                value = 0.0
            draw.line([(x1, y), (x1 + 3, y)], fill="black")
            label = format_value(value, scale=max(abs(self.vmin), abs(self.vmax)), digits=3)
            draw.text((x1 + 5, y - 6), label, fill="black", font=fnt)
        return canvas


def _wrap(text: str, width: int) -> list[str]:
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return lines + ([line] if line else [])


def compose(
    cells: Sequence[Sequence[np.ndarray]],
    col_labels: Sequence[str] | None = None,
    row_labels: Sequence[str] | None = None,
    notes: Sequence[Sequence[str]] | None = None,
    colorbar: Colorbar | None = None,
):
    """A labelled grid of equally sized renders (a PIL image).

    Parameters
    ----------
    cells : rows of (H, W, 3) uint8
    col_labels, row_labels : str per column / row, optional
    notes : rows of str, optional
        A short line printed under each cell (numbers).
    colorbar : Colorbar, optional
        Drawn right of the grid, as tall as the first row.
    """
    from PIL import Image, ImageDraw

    from pyvista_views.compare import trim_rows

    cells = trim_rows(cells, min_height=160 if colorbar is not None else 0)
    h, w = np.asarray(cells[0][0]).shape[:2]
    n_rows, n_cols = len(cells), max(len(r) for r in cells)
    left = 0
    if row_labels:  # as wide as the longest label (within 92..160 pixels)
        probe = ImageDraw.Draw(Image.new("RGB", (1, 1)))
        longest = max(probe.textlength(str(t), font=font()) for t in row_labels)
        left = int(min(max(92, longest + 10), 160))
    top = 20 if col_labels else 0
    below = 18 if notes else 0
    right = Colorbar.width if colorbar is not None else 0
    canvas = Image.new("RGB", (left + n_cols * w + right, top + n_rows * (h + below)), "white")
    draw, fnt = ImageDraw.Draw(canvas), font()
    for j, label in enumerate(col_labels or ()):
        draw.text(
            (left + j * w + 4, 3), fit_text(draw, str(label), fnt, w - 6), fill="black", font=fnt
        )
    for i, row in enumerate(cells):
        y = top + i * (h + below)
        if row_labels:
            text = fit_text(draw, str(row_labels[i]), fnt, left - 6)
            draw.text((4, y + h // 2 - 7), text, fill="black", font=fnt)
        for j, image in enumerate(row):
            canvas.paste(
                Image.fromarray(np.ascontiguousarray(image, dtype=np.uint8)), (left + j * w, y)
            )
            if notes and i < len(notes) and j < len(notes[i]) and notes[i][j]:
                text = fit_text(draw, notes[i][j], fnt, w - 6)
                draw.text((left + j * w + 4, y + h + 2), text, fill="black", font=fnt)
    if colorbar is not None:
        canvas.paste(colorbar.draw(h), (left + n_cols * w, top))
    return canvas


def fit_text(draw: Any, text: str, font: Any, width: int) -> str:
    """``text`` shortened with an ellipsis until it fits in ``width`` pixels (labels of
    neighbouring panels never run into each other)."""
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "...", font=font) > width:
        text = text[:-1]
    return text + "..."


def overlay(image: np.ndarray, bounds, segments=(), points=(), labels=()) -> np.ndarray:
    """Draw screen-space segments, dots and text on a render, ignoring what hides them (marks on
    a mescher's surface go through :meth:`pyvista_views.MescherScene.add_path` / ``add_points``
    instead, which draw them only where the surface is visible).

    Parameters
    ----------
    image : (H, W, 3) uint8
    bounds : (xmin, xmax, ymin, ymax)
        The render's exact extent in screen units.
    segments : iterable of (P (k, 2, 2), colour, width)
    points : iterable of (P (k, 2), colour, radius)
    labels : iterable of (p (2,), text, colour)
        Placed next to ``p`` by :func:`place_labels`, so they never overlap each other.

    Returns
    -------
    (H, W, 3) uint8
    """
    from PIL import Image, ImageDraw

    h, w = image.shape[:2]
    canvas = Image.fromarray(np.ascontiguousarray(image))
    draw, fnt = ImageDraw.Draw(canvas), font(12)
    for P, colour, width in segments:
        Q = screen_to_pixel(np.asarray(P).reshape(-1, 2), bounds, (w, h)).reshape(-1, 4)
        for q in Q:  # PIL draws one primitive per call; these are a few hundred segments
            draw.line([(q[0], q[1]), (q[2], q[3])], fill=colour, width=width)
    for P, colour, r in points:
        for c, rr in screen_to_pixel(P, bounds, (w, h)):
            draw.ellipse([c - r, rr - r, c + r, rr + r], fill=colour, outline="black")
    labels = list(labels)
    if labels:
        from pyvista_views.overlays import place_labels

        anchors = np.vstack([screen_to_pixel(p, bounds, (w, h)) for p, _, _ in labels])
        sizes = []
        for _, text, _ in labels:
            x0, y0, x1, y1 = draw.textbbox((0, 0), text, font=fnt, stroke_width=2)
            sizes.append((x1 - x0 + 2, y1 - y0 + 2))
        for (x, y), (_, text, colour) in zip(place_labels(anchors, sizes, (w, h)), labels):
            draw.text(
                (x + 1, y + 1), text, fill=colour, font=fnt, stroke_width=2, stroke_fill="white"
            )
    return np.asarray(canvas)


def lines_over(images: Sequence[np.ndarray], lines: Any, bounds, widths: Any = None) -> list:
    """A line drawing over renders of one framing: rasterized once, laid over each image.

    Parameters
    ----------
    images : sequence of (H, W, 3) uint8
        Renders with the exact extent ``bounds`` (all of one size).
    lines : meschers_igl.lines.LineDrawing
        Its visible lines are drawn (:func:`pyvista_views.lineart.to_svg`).
    bounds : (xmin, xmax, ymin, ymax)
    widths : float or dict, optional
        Stroke widths in pixels (:func:`pyvista_views.lineart.to_svg`).

    Returns
    -------
    list of (H, W, 3) uint8
        Each image under the lines, alpha-blended as :func:`pyvista_views.lineart.overlay` does.

    Raises
    ------
    MescherError
        Images of different sizes.
    ImportError
        Without cairosvg, which rasterizes the lines.
    """
    from meschers_igl.errors import MescherError
    from pyvista_views.lineart import rasterize, to_svg

    images = [np.asarray(im) for im in images]
    if not images:
        return []
    h, w = images[0].shape[:2]
    if any(im.shape[:2] != (h, w) for im in images):
        found = sorted({im.shape[:2] for im in images})
        raise MescherError(f"images: expected renders of one size, found sizes {found}")
    svg = to_svg(lines, window_size=(w, h), bounds=bounds, widths=widths)
    rgba = rasterize(svg, (w, h), background=None).astype(np.float64)
    alpha = rgba[..., 3:4] / 255.0
    ink = rgba[..., :3] * alpha
    return [
        np.clip(np.rint(im[..., :3] * (1.0 - alpha) + ink), 0, 255).astype(np.uint8)
        for im in images
    ]


def png_bytes(image: Any) -> bytes:
    """PNG file content of a PIL image or an (H, W, 3) uint8 array (fast zlib level: the study
    writes a few dozen figures and embeds them in its page)."""
    from PIL import Image

    if isinstance(image, np.ndarray):
        image = Image.fromarray(np.ascontiguousarray(image))
    buf = io.BytesIO()
    image.save(buf, format="PNG", compress_level=3)
    return buf.getvalue()


def geodesic_picture(
    m: Any,
    order: Any,
    d: np.ndarray,
    path: Any,
    ends: tuple[int, int] | None,
    size: tuple[int, int],
    isolines: int,
    draw_path: bool = True,
) -> np.ndarray:
    """The ``geodesic -o`` picture: the distance with isolines, the path and its two ends.

    Drawn on a midpoint-subdivided copy, as the study does: on a coarse model (the gallery's
    104-face triangle) smooth shading interpolates the vertex normals across whole bar faces and
    the flat faces came out blotched dark to light; subdivided, the blend stays in a narrow band
    at the creases.  The distances are interpolated linearly, so the isolines are those of the
    coarse field.  The path (on ``m``) is carried to the children of its faces
    (:func:`pyvista_views.overlays.refine_path`) and drawn, like the dots on its ``ends``
    (source, target), only where it lies on the visible surface
    (``render(..., paths=..., points=...)``); ``draw_path=False`` leaves out the path but keeps
    the dots (the picture the path is measured against).
    """
    from pyvista_views.camera import default_bounds, xy_box
    from pyvista_views.overlays import refine_path

    from .cli_args import headless_views
    from .settings import study_settings, subdivision_levels

    pvv = headless_views()
    bounds = default_bounds(xy_box(np.asarray(m.xy)), size)
    st = study_settings()  # the study's levels and face budget
    levels = subdivision_levels(m.n_faces, st.levels, st.max_faces)
    mv, order_v, dv, parent = m, order, d, np.arange(m.n_faces)
    if levels:
        if order is None:
            mv, S, parent = m.subdivide(levels, return_matrix=True, return_face_parent=True)
        else:
            mv, order_v, S, parent = m.subdivide(
                levels, order=order, return_matrix=True, return_face_parent=True
            )
        finite = np.isfinite(d)
        dv = S @ np.where(finite, d, 0.0)
        dv[(S @ (~finite).astype(float)) > 0] = np.inf  # a vertex next to an unreached one
    marks, dots = None, None
    if path is not None:
        xy, faces = refine_path(path.xy, path.faces, mv.xy, mv.F, parent)
        if draw_path:
            marks = {"path": (xy, faces), "color": "#ff2020", "width": 3}
    if ends is not None:  # vertex ids: original vertices keep their indices in the subdivision
        dots = [
            {"vertices": [ends[0]], "color": "white"},
            {"vertices": [ends[1]], "color": "#ff2020"},
        ]
    return pvv.render(
        mv,
        order=order_v,
        shading="smooth",
        scalars=dv,
        isolines=isolines,
        window_size=size,
        bounds=bounds,
        anti_aliasing=True,
        paths=marks,
        points=dots,
    )
