"""The paper's Figure 10, made quantitative: mescher vs cut vs bent representations.

Rows are the three representations of one impossible object, columns four operations:

=========  ====================================================================================
render     lit by ``lights``
relit      lit by ``relit_lights`` (the bent model's shading is wrong here: its normals lost the
           harmonic part of the depth)
smoothed   Laplacian smoothing of each representation with the same diffusion time
geodesic   heat-method distance from one vertex (the cut model's seam blocks paths; the bent
           model's metric is not the object's)
=========  ====================================================================================

Every representation goes through the same operators: the cut and bent models are real meshes,
turned into (embeddable) meschers with ``Mescher.from_mesh`` for smoothing and geodesics, so the
numbers measure the representation, not a different solver.  All cells share one camera
(the mescher's xy box), so they line up pixel for pixel.

Numbers per cell: for *render* and *relit*, **dL**, the mean absolute luminance difference to the
cut model's image, which is the ground truth for shading; for *smoothed*, the same difference to
the smoothed mescher's image; for *geodesic*, the mean absolute distance difference to the
mescher's distance, relative to its largest distance (cut vertices compared with the mescher
vertex they copy).  The mescher's own row is the reference where it is one (0 by definition).

This module owns the image measurements of the project: :func:`luminance` (Rec. 709, on the
scale 0 = black to 1 = white, the one scale of every dL printed in figures, tables and JSON),
:func:`image_difference` and :func:`image_agreement`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_index_array, as_positive

from .camera import default_bounds, xy_box
from .render import hide_back_faces
from .scene import MescherScene

__all__ = [
    "COLUMNS",
    "ROWS",
    "Comparison",
    "compare",
    "image_agreement",
    "image_difference",
    "luminance",
    "trim_rows",
]

ROWS = ("mescher", "cut", "bent")
COLUMNS = ("render", "relit", "smoothed", "geodesic")
_NEEDED = ("cut_embedding", "bent_embedding", "smooth", "geodesic_distance", "hodge")


@dataclass
class Comparison:
    """What :func:`compare` measured.

    Attributes
    ----------
    numbers : dict row -> dict column -> float
        Module docstring for the meaning of each column's number.
    images : dict row -> dict column -> (H, W, 3) uint8
    distances : dict row -> (#V_mescher,) float64
        Geodesic distances carried to the mescher's vertices (cut: the first copy of each).
    path : pathlib.Path or None
        The saved figure.
    meschers : dict row -> Mescher
        The mescher and its cut and bent embeddings as (embeddable) meschers, so a caller can
        measure more on them without rebuilding them.
    smoothed : dict row -> Mescher
        Each row's mescher smoothed with ``t_smooth``.
    solvers : dict row -> HeatGeodesicSolver
        The factored heat-method solver of each row's mescher (query more sources for free).
    vmap : (#V_cut,) int64
        Mescher vertex of each cut-model vertex.
    """

    numbers: dict[str, dict[str, float]]
    images: dict[str, dict[str, np.ndarray]] = field(repr=False)
    distances: dict[str, np.ndarray] = field(repr=False)
    path: Path | None = None
    meschers: dict[str, Any] = field(default_factory=dict, repr=False)
    smoothed: dict[str, Any] = field(default_factory=dict, repr=False)
    solvers: dict[str, Any] = field(default_factory=dict, repr=False)
    vmap: np.ndarray | None = field(default=None, repr=False)

    def figure(self):
        """The labelled 3 x 4 grid with each cell's number under it (a PIL image)."""
        return _figure(self)

    def table(self) -> str:
        """The numbers as a fixed-width text table."""
        lines = ["representation " + "".join(f"{c:>11s}" for c in COLUMNS)]
        for r in ROWS:
            lines.append(f"{r:<15s}" + "".join(f"{self.numbers[r][c]:11.4f}" for c in COLUMNS))
        return "\n".join(lines)


#: Rec. 709 luma weights of linear R, G, B.
LUMA = np.array([0.2126, 0.7152, 0.0722])


def luminance(image: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of an RGB uint8 image on the scale 0 (black) to 1 (white).

    Parameters
    ----------
    image : (..., 3) uint8

    Returns
    -------
    (...) float64
        ``L = (0.2126 R + 0.7152 G + 0.0722 B) / 255``.
    """
    return (np.asarray(image, dtype=np.float64) / 255.0) @ LUMA


def _covered(image: np.ndarray, background: Sequence[int]) -> np.ndarray:
    bg = np.asarray(background, dtype=np.asarray(image).dtype).reshape(
        (1,) * (image.ndim - 1) + (3,)
    )
    return np.any(image != bg, axis=-1)


def _check_pair(a: Any, b: Any) -> tuple[np.ndarray, np.ndarray]:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.ndim != 3 or a.shape[2] != 3:
        raise MescherError(
            f"a, b: expected two (H, W, 3) images of one shape, found {a.shape} and {b.shape}"
        )
    return a, b


def image_difference(
    a: np.ndarray, b: np.ndarray, background: Sequence[int] = (255, 255, 255)
) -> float:
    """dL: mean ``|L_a - L_b|`` (:func:`luminance`, 0-1) over the pixels covered in either image.

    Parameters
    ----------
    a, b : (H, W, 3) uint8
        Two renders with one camera and size.
    background : (3,) int
        Pixels of exactly this colour are empty.

    Returns
    -------
    float
        In [0, 1]; 0 when neither image covers a pixel.
    """
    a, b = _check_pair(a, b)
    covered = _covered(a, background) | _covered(b, background)
    if not covered.any():
        return 0.0
    return float(np.abs(luminance(a) - luminance(b))[covered].mean())


def image_agreement(
    a: np.ndarray, b: np.ndarray, background: Sequence[int] = (255, 255, 255)
) -> dict:
    """How well render ``a`` matches reference render ``b`` (same camera and size).

    Parameters
    ----------
    a, b : (H, W, 3) uint8
    background : (3,) int
        Pixels of exactly this colour are empty.

    Returns
    -------
    dict
        ``iou``: |mask_a & mask_b| / |mask_a | mask_b| of the covered pixels (1 when both are
        empty); ``luminance_mae``: dL over the pixels covered in both, mean |L_a - L_b| with L
        the :func:`luminance` in [0, 1]; ``luminance_corr``: Pearson correlation of L_a and
        L_b over those pixels (1 when either is constant there and they are equal, else 0).
    """
    a, b = _check_pair(a, b)
    ma, mb = _covered(a, background), _covered(b, background)
    union, both = int(np.count_nonzero(ma | mb)), ma & mb
    iou = 1.0 if union == 0 else float(np.count_nonzero(both)) / union
    if not both.any():
        return {"iou": iou, "luminance_mae": 0.0, "luminance_corr": 1.0 if union == 0 else 0.0}
    la, lb = luminance(a)[both], luminance(b)[both]
    mae = float(np.abs(la - lb).mean())
    sa, sb = la.std(), lb.std()
    if sa < 1e-12 or sb < 1e-12:  # a constant image: correlation undefined, equal means agreement
        corr = 1.0 if mae < 1e-12 else 0.0
    else:
        corr = float(np.mean((la - la.mean()) * (lb - lb.mean())) / (sa * sb))
    return {"iou": iou, "luminance_mae": mae, "luminance_corr": corr}


def _require(m: Any) -> None:
    missing = [name for name in _NEEDED if not hasattr(m, name)]
    if missing:
        raise MescherError(
            f"m: expected a Mescher with {', '.join(missing)} (meschers_igl geometry and "
            f"embedding modules), found {type(m).__name__} without them"
        )


def _default_time(m: Any) -> float:
    h = float(np.mean(m.edge_lengths()))
    return 2.0 * h * h


def compare(
    m: Any,
    order: object = None,
    path: str | Path | None = "compare.png",
    lights: object = ((1.0, 1.0, 1.0),),
    relit_lights: object = ((-1.0, 0.3, 0.6),),
    source: int = 0,
    t_smooth: float | None = None,
    cut_edges: object = None,
    shading: str = "smooth",
    window_size: tuple[int, int] = (256, 256),
    cmap: str = "viridis",
    isolines: int = 8,
    *,
    solver: Any = None,
    smoothed: Any = None,
) -> Comparison:
    """Render Figure 10 of the paper and measure it.

    Parameters
    ----------
    m : meschers_igl.Mescher
        Typically an impossible one (``m.is_impossible()``).
    order : None, DepthOrder or (#F,) array_like
        The mescher's depth order (the embeddings are z-buffered).
    path : str or Path or None
        Where to save the 3 x 4 figure (PNG); ``None``: do not save.
    lights, relit_lights
        Directional lights of the *render* and *relit* columns.
    source : int
        Source vertex of the geodesic distances (its cut copies are all sources).
    t_smooth : float, optional
        Diffusion time for smoothing xy and depth (default ``2 * mean edge length^2``).
    cut_edges : (k,) int, optional
        Passed to ``m.cut_embedding``.
    shading : {"flat", "smooth"}
    window_size : (int, int)
        Size of each cell.
    cmap, isolines
        Colour map and isoline count of the geodesic column.
    solver : HeatGeodesicSolver, optional
        A factored solver of ``m`` to reuse for the mescher's distance (default: one is built,
        standard method).
    smoothed : Mescher, optional
        ``m.smooth(t_xy=t_smooth, t_zeta=t_smooth)`` if the caller has it already.

    Returns
    -------
    Comparison
        ``numbers[row][column]``, the cell images, the distances and the saved path.
    """
    _require(m)
    from meschers_igl import HeatGeodesicSolver, Mescher

    source = int(as_index_array(source, "source", np.asarray(m.xy).shape[0])[0])
    t = _default_time(m) if t_smooth is None else as_positive(t_smooth, "t_smooth")
    V_cut, F_cut, vmap = m.cut_embedding(cut_edges)
    V_bent, F_bent = m.bent_embedding()
    vmap = np.asarray(vmap, dtype=np.int64)
    bounds = default_bounds(xy_box(np.asarray(m.xy)), window_size)

    # Smoothing and geodesics: one set of operators for all three rows.
    cut_m, bent_m = Mescher.from_mesh(V_cut, F_cut), Mescher.from_mesh(V_bent, F_bent)
    meschers = {"mescher": m, "cut": cut_m, "bent": bent_m}
    smoothed_rows = {
        "mescher": m.smooth(t_xy=t, t_zeta=t) if smoothed is None else smoothed,
        "cut": cut_m.smooth(t_xy=t, t_zeta=t),
        "bent": bent_m.smooth(t_xy=t, t_zeta=t),
    }
    if solver is not None and getattr(solver, "m", m) is not m:
        raise MescherError(
            "solver: expected a HeatGeodesicSolver built for m, found one for another mescher"
        )
    solvers = {
        "mescher": HeatGeodesicSolver(m) if solver is None else solver,
        "cut": HeatGeodesicSolver(cut_m),
        "bent": HeatGeodesicSolver(bent_m),
    }
    d_m = np.asarray(solvers["mescher"].distance(source))
    first_copy = np.full(np.asarray(m.xy).shape[0], -1, dtype=np.int64)
    first_copy[vmap[::-1]] = np.arange(vmap.size)[::-1]
    # The cut model is a real mesh: its source is one point (one copy of a seam vertex), and
    # each vertex is read at one copy, as a user of that model would see it.
    d_cut = np.asarray(solvers["cut"].distance(int(first_copy[source])))
    d_bent = np.asarray(solvers["bent"].distance(source))
    distances = {"mescher": d_m, "cut": d_cut[first_copy], "bent": d_bent}
    finite = np.isfinite(d_m)
    clim = (0.0, float(d_m[finite].max()) if finite.any() else 1.0)

    meshes = {
        "mescher": None,
        "cut": (V_cut, F_cut),
        "bent": (V_bent, F_bent),
    }
    geodesic_field = {"mescher": d_m, "cut": d_cut, "bent": d_bent}
    images, background = _panels(
        m,
        order,
        meshes,
        geodesic_field,
        smoothed_rows,
        dict(shading=shading, cmap=cmap, clim=clim, isolines=isolines),
        bounds,
        lights,
        relit_lights,
        window_size,
    )

    numbers = _numbers(images, distances, d_m, clim, background)

    result = Comparison(numbers, images, distances, None, meschers, smoothed_rows, solvers, vmap)
    if path is not None:
        result.path = _save_figure(result, Path(path))
    return result


def _panels(
    m, order, meshes, geodesic_field, smoothed_rows, look, bounds, lights, relit_lights, window_size
):
    """The figure's panels, ``images[row][column]``, and the background colour."""
    shading, cmap, clim, isolines = look["shading"], look["cmap"], look["clim"], look["isolines"]
    images: dict[str, dict[str, np.ndarray]] = {r: {} for r in ROWS}
    with MescherScene(window_size=window_size) as scene:
        for row in ROWS:
            for column in COLUMNS:
                scene.clear()
                kwargs: dict[str, Any] = {"shading": shading}
                if column == "geodesic":
                    kwargs.update(
                        scalars=geodesic_field[row], cmap=cmap, clim=clim, isolines=isolines
                    )
                if column == "smoothed":
                    s = smoothed_rows[row]
                    if row == "mescher":
                        # smoothing moved xy: overlaps appear and vanish, so the order follows
                        # (and back faces go behind where the surface turns edge-on)
                        follow = getattr(order, "follow", None)
                        moved = order if follow is None else hide_back_faces(s, follow(s))
                        scene.add(s, order=moved, **kwargs)
                    else:
                        scene.add_embedding(*s.bent_embedding(), **kwargs)
                elif row == "mescher":
                    scene.add(m, order=order, **kwargs)
                else:
                    scene.add_embedding(*meshes[row], **kwargs)
                scene.view(bounds)
                scene.relight(relit_lights if column == "relit" else lights)
                images[row][column] = scene.screenshot()
        background = np.asarray(scene.plotter.background_color.int_rgb, dtype=np.uint8)
    return images, background


def _numbers(images, distances, d_m, clim, background) -> dict[str, dict[str, float]]:
    """dL of each panel against the cut model's (render, relit) or the mescher's (smoothed), and
    the mean geodesic difference to the mescher's distances over the field's range."""
    finite = np.isfinite(d_m)
    numbers: dict[str, dict[str, float]] = {r: {} for r in ROWS}
    scale = clim[1] or 1.0
    for row in ROWS:
        for column in ("render", "relit"):
            numbers[row][column] = image_difference(
                images[row][column], images["cut"][column], background
            )
        numbers[row]["smoothed"] = image_difference(
            images[row]["smoothed"], images["mescher"]["smoothed"], background
        )
        d = distances[row]
        ok = finite & np.isfinite(d)
        numbers[row]["geodesic"] = float(np.abs(d[ok] - d_m[ok]).mean() / scale)
    return numbers


def _save_figure(result: Comparison, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    result.figure().save(path)
    return path


def _figure(result: Comparison):
    from PIL import Image, ImageDraw, ImageFont

    trimmed = trim_rows([[result.images[r][c] for c in COLUMNS] for r in ROWS])
    images = {r: dict(zip(COLUMNS, row)) for r, row in zip(ROWS, trimmed)}
    first = images[ROWS[0]][COLUMNS[0]]
    h, w = first.shape[:2]
    try:  # labels readable at page width (13 px)
        fnt = ImageFont.load_default(size=13)
    except TypeError:  # Pillow < 10.1
        fnt = ImageFont.load_default()
    left, top, caption, foot = 76, 22, 18, 38
    width = left + w * len(COLUMNS)
    canvas = Image.new("RGB", (width, top + (h + caption) * len(ROWS) + foot), "white")
    draw = ImageDraw.Draw(canvas)
    for j, column in enumerate(COLUMNS):
        draw.text((left + j * w + 4, 4), column, fill="black", font=fnt)
    draw.text(
        (4, top + (h + caption) * len(ROWS) + 3),
        "dL: mean |luminance difference| (0 black .. 1 white) to the cut model (render, relit)\n"
        "or to the smoothed mescher; rel. dist.: mean |d - d_mescher| / max d_mescher",
        fill="#444444",
        font=fnt,
    )
    for i, row in enumerate(ROWS):
        y = top + i * (h + caption)
        draw.text((4, y + h // 2), row, fill="black", font=fnt)
        for j, column in enumerate(COLUMNS):
            canvas.paste(Image.fromarray(images[row][column]), (left + j * w, y))
            unit = "rel. dist." if column == "geodesic" else "dL"
            value = result.numbers[row][column]
            draw.text((left + j * w + 4, y + h + 2), f"{unit} {value:.3f}", fill="black", font=fnt)
    return canvas


def trim_rows(
    cells: Sequence[Sequence[np.ndarray]], pad: int = 6, min_height: int = 0
) -> list[list[np.ndarray]]:
    """The panels with the image rows that are white in every panel cut away (the same rows
    from each, so the panels keep one size and one camera), ``pad`` pixels kept either side
    and at least ``min_height`` rows (room for a colour bar).

    A wide figure in a square panel leaves white bands above and below it; stacked in a grid
    they become empty bands across the figure.
    """
    arrays = [[np.asarray(c) for c in row] for row in cells]
    h = arrays[0][0].shape[0]
    used = np.zeros(h, dtype=bool)
    for row in arrays:
        for a in row:
            if a.shape[0] == h:
                used |= np.any(a < 250, axis=(1, 2))
    if not used.any():
        return arrays
    rows = np.flatnonzero(used)
    lo, hi = max(int(rows[0]) - pad, 0), min(int(rows[-1]) + pad + 1, h)
    short = min(min_height, h) - (hi - lo)
    if short > 0:  # widen around the middle, inside the image
        lo = max(lo - (short + 1) // 2, 0)
        hi = min(lo + max(hi - lo, min(min_height, h)), h)
        lo = hi - max(hi - lo, min(min_height, h))
    return [[a[lo:hi] if a.shape[0] == h else a for a in row] for row in arrays]
