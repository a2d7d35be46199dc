"""The comparison study behind ``meschers study``: every operation of the paper on every model.

For each model of the built-in gallery (:mod:`meschers_igl.gallery`) the study runs, with a fixed
head-on camera (paper Sections 3-4):

========== =====================================================================================
subdivide  midpoint 1-to-4 subdivision with the depth order carried along; periods must not move
hodge      ``zeta = d01 z + omega`` (paper Eq. 3), the periods of ``omega`` around the homology
           generators, drawn on the picture
render     flat and smooth shading under four directional lights and an environment map
heat       backward Euler heat diffusion from one vertex (paper Eq. 5) for three times ``t``
geodesic   heat-method distance (Crane et al.), its error against the exact distance on a real
           3D covering of the mescher (:mod:`meschers_igl.covering`), a shortest path drawn on it
smoothing  Laplacian smoothing of xy, of the exact part of zeta and of both, for a row of times
           ``t`` (the paper's Heart figure, Fig. 8); the periods must not move
compare    mescher / cut / bent (paper Fig. 10): relighting error against the cut model,
           geodesic error against the covering's exact distances, the crack smoothing opens at
           the cut model's seam
========== =====================================================================================

and, when the ParadoxToolkit models ship with the package (``meschers_igl/data/paradox``), a
section "Models from other tools" with their render, relighting, periods and geodesic distance.

Every figure is a PNG composed with PIL from renders of :class:`~pyvista_views.MescherScene`;
the numbers go to ``metrics.json`` and :mod:`meschers.report` writes ``index.html``.
"""

from __future__ import annotations

import importlib.resources
import json
import math
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from pyvista_views.render import MescherScene, _xy_box, default_bounds

__all__ = [
    "CITATION",
    "StudySettings",
    "StudyResult",
    "distance_error",
    "image_agreement",
    "paradox_models",
    "run_study",
    "screen_to_pixel",
    "seam_gap",
    "study_settings",
]

CITATION = (
    "Ana Dodik, Isabella Yu, Kartik Chandra, Jonathan Ragan-Kelley, Joshua Tenenbaum, "
    "Vincent Sitzmann, Justin Solomon. Meschers: Geometry Processing of Impossible Objects. "
    "ACM Transactions on Graphics 44(4), 2025. DOI 10.1145/3731422."
)
DOI_URL = "https://doi.org/10.1145/3731422"

#: Four directional lights (directions *toward* the light, camera frame) as in the paper's Fig. 5.
LIGHTS: tuple[tuple[float, float, float], ...] = (
    (1.0, 1.0, 1.0),
    (-1.0, 1.0, 0.6),
    (0.3, -1.0, 0.8),
    (-0.6, -0.4, 1.0),
)
ENV_MAP = "studio"
_GEODESIC_CMAP = "viridis"
_HEAT_CMAP = "inferno"


# ------------------------------------------------------------------------------------------------
# settings
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class StudySettings:
    """Resolutions of one study run.

    Attributes
    ----------
    quick : bool
    cell : int
        Width and height in pixels of one rendered panel.
    levels : int
        Midpoint subdivision levels applied to each gallery model before processing.
    heat_times : tuple of float
        Heat diffusion times in units of ``h^2`` (``h`` the mean edge length after subdivision).
    smooth_times : tuple of float
        Smoothing times in units of ``s^2``, ``s`` the diagonal of the model's xy box.
    compare_time : float
        Smoothing time of the mescher / cut / bent comparison, in units of ``s^2``.
    isolines : int
        Isolines drawn on distance fields.
    """

    quick: bool
    cell: int
    levels: int
    heat_times: tuple[float, ...] = (2.0, 10.0, 50.0)
    smooth_times: tuple[float, ...] = (0.0, 2e-4, 1e-3, 5e-3)
    compare_time: float = 1e-3
    isolines: int = 10


def study_settings(quick: bool = False) -> StudySettings:
    """``--quick``: 192-pixel panels and one subdivision level; default: 320 pixels, two levels."""
    if quick:
        return StudySettings(quick=True, cell=192, levels=1)
    return StudySettings(quick=False, cell=320, levels=2)


# ------------------------------------------------------------------------------------------------
# measurements (pure numpy; tested on hand-made images and fields)
# ------------------------------------------------------------------------------------------------
def _luminance(image: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of an (H, W, 3) uint8 image, in [0, 1]."""
    return (np.asarray(image, dtype=np.float64) / 255.0) @ np.array([0.2126, 0.7152, 0.0722])


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
        empty); ``luminance_mae``: mean |L_a - L_b| over the pixels covered in both, L in [0, 1];
        ``luminance_corr``: Pearson correlation of L_a and L_b over those pixels (1 when either
        is constant there and they are equal, else 0).
    """
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.ndim != 3 or a.shape[2] != 3:
        raise MescherError(
            f"a, b: expected two (H, W, 3) images of one shape, found {a.shape} and {b.shape}"
        )
    bg = np.asarray(background, dtype=a.dtype).reshape(1, 1, 3)
    ma, mb = np.any(a != bg, axis=2), np.any(b != bg, axis=2)
    union, both = int(np.count_nonzero(ma | mb)), ma & mb
    iou = 1.0 if union == 0 else float(np.count_nonzero(both)) / union
    if not both.any():
        return {"iou": iou, "luminance_mae": 0.0, "luminance_corr": 1.0 if union == 0 else 0.0}
    la, lb = _luminance(a)[both], _luminance(b)[both]
    mae = float(np.abs(la - lb).mean())
    sa, sb = la.std(), lb.std()
    if sa < 1e-12 or sb < 1e-12:  # a constant image: correlation undefined, equal means agreement
        corr = 1.0 if mae < 1e-12 else 0.0
    else:
        corr = float(np.mean((la - la.mean()) * (lb - lb.mean())) / (sa * sb))
    return {"iou": iou, "luminance_mae": mae, "luminance_corr": corr}


def distance_error(d: np.ndarray, d_exact: np.ndarray) -> dict:
    """Error of a distance field against an exact one, over vertices where both are finite.

    Returns
    -------
    dict
        ``mean``: mean |d - d*| / max d*; ``max``: max |d - d*| / max d*; ``n``: vertices used.
        (Relative to the largest exact distance so that vertices next to the source, where
        ``d*`` is near zero, do not dominate.)
    """
    d, de = np.asarray(d, dtype=np.float64), np.asarray(d_exact, dtype=np.float64)
    if d.shape != de.shape:
        raise MescherError(f"d: expected shape {de.shape} like d_exact, found {d.shape}")
    ok = np.isfinite(d) & np.isfinite(de)
    scale = float(de[ok].max()) if ok.any() else 0.0
    if scale <= 0:
        return {"mean": math.nan, "max": math.nan, "n": int(ok.sum())}
    err = np.abs(d[ok] - de[ok]) / scale
    return {"mean": float(err.mean()), "max": float(err.max()), "n": int(ok.sum())}


def seam_gap(xy: np.ndarray, vmap: np.ndarray) -> float:
    """Largest screen distance between two copies of one vertex in a cut model.

    A cut model duplicates the vertices on its seam (``vmap[i]`` is the mescher vertex of cut
    vertex ``i``).  Copies coincide on screen until an operation moves them differently:
    smoothing the cut model as a mesh opens a crack of this width along the seam.

    Parameters
    ----------
    xy : (#Vc, 2) float
    vmap : (#Vc,) int

    Returns
    -------
    float
        ``max_i |xy_i - xy_first(vmap_i)|`` (0 when nothing is duplicated); twice this bounds
        the distance between any two copies.
    """
    xy = np.asarray(xy, dtype=np.float64)
    vmap = np.asarray(vmap, dtype=np.int64)
    if xy.ndim != 2 or vmap.shape != (xy.shape[0],):
        raise MescherError(
            f"vmap: expected shape ({xy.shape[0]},) matching xy {xy.shape}, found {vmap.shape}"
        )
    _, first, inverse = np.unique(vmap, return_index=True, return_inverse=True)
    return float(np.linalg.norm(xy - xy[first[inverse]], axis=1).max(initial=0.0))


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


def _topology(m: Any) -> dict:
    from .cli import describe

    return describe(m)


# ------------------------------------------------------------------------------------------------
# figures (PIL)
# ------------------------------------------------------------------------------------------------
def _font(size: int = 13):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1 has one bitmap size
        return ImageFont.load_default()


def compose(
    cells: Sequence[Sequence[np.ndarray]],
    col_labels: Sequence[str] | None = None,
    row_labels: Sequence[str] | None = None,
    notes: Sequence[Sequence[str]] | None = None,
):
    """A labelled grid of equally sized renders (a PIL image).

    Parameters
    ----------
    cells : rows of (H, W, 3) uint8
    col_labels, row_labels : str per column / row, optional
    notes : rows of str, optional
        A short line printed under each cell (numbers).
    """
    from PIL import Image, ImageDraw

    h, w = np.asarray(cells[0][0]).shape[:2]
    n_rows, n_cols = len(cells), max(len(r) for r in cells)
    left = 92 if row_labels else 0
    top = 20 if col_labels else 0
    below = 18 if notes else 0
    canvas = Image.new("RGB", (left + n_cols * w, top + n_rows * (h + below)), "white")
    draw, font = ImageDraw.Draw(canvas), _font()
    for j, label in enumerate(col_labels or ()):
        draw.text((left + j * w + 4, 3), str(label), fill="black", font=font)
    for i, row in enumerate(cells):
        y = top + i * (h + below)
        if row_labels:
            draw.text((4, y + h // 2 - 7), str(row_labels[i]), fill="black", font=font)
        for j, image in enumerate(row):
            canvas.paste(
                Image.fromarray(np.ascontiguousarray(image, dtype=np.uint8)), (left + j * w, y)
            )
            if notes and i < len(notes) and j < len(notes[i]) and notes[i][j]:
                draw.text((left + j * w + 4, y + h + 2), notes[i][j], fill="black", font=font)
    return canvas


def _overlay(image: np.ndarray, bounds, segments=(), points=(), labels=()) -> np.ndarray:
    """Draw screen-space segments, dots and text on a render (occlusion ignored).

    ``segments``: (P (k, 2, 2), colour, width); ``points``: (P (k, 2), colour, radius);
    ``labels``: (p (2,), text, colour).
    """
    from PIL import Image, ImageDraw

    h, w = image.shape[:2]
    canvas = Image.fromarray(np.ascontiguousarray(image))
    draw, font = ImageDraw.Draw(canvas), _font(12)
    for P, colour, width in segments:
        Q = screen_to_pixel(np.asarray(P).reshape(-1, 2), bounds, (w, h)).reshape(-1, 4)
        for q in Q:  # PIL draws one primitive per call; these are a few hundred segments
            draw.line([(q[0], q[1]), (q[2], q[3])], fill=colour, width=width)
    for P, colour, r in points:
        for c, rr in screen_to_pixel(P, bounds, (w, h)):
            draw.ellipse([c - r, rr - r, c + r, rr + r], fill=colour, outline="black")
    for p, text, colour in labels:
        c, rr = screen_to_pixel(p, bounds, (w, h))[0]
        draw.text(
            (c + 4, rr - 6), text, fill=colour, font=font, stroke_width=2, stroke_fill="white"
        )
    return np.asarray(canvas)


# ------------------------------------------------------------------------------------------------
# the run
# ------------------------------------------------------------------------------------------------
@dataclass
class Figure:
    """One PNG of the report."""

    file: str
    title: str
    caption: str


@dataclass
class Section:
    """A model's part of the report."""

    name: str
    title: str
    description: str
    figures: list[Figure] = field(default_factory=list)


@dataclass
class StudyResult:
    """What :func:`run_study` wrote.

    Attributes
    ----------
    out : Path
        The folder with the PNGs, ``metrics.json`` and ``index.html``.
    metrics : dict
        The content of ``metrics.json``.
    sections : list of Section
    errors : list of str
        Steps that failed (the study carries on; each is also in ``metrics["errors"]``).
    """

    out: Path
    metrics: dict
    sections: list[Section]
    errors: list[str]

    @property
    def index(self) -> Path:
        return self.out / "index.html"


class _Run:
    """State of one study: output folder, scene, progress bar, errors."""

    def __init__(self, out: Path, st: StudySettings, progress: Callable[[str], None]):
        self.out, self.st, self.progress = out, st, progress
        self.errors: list[str] = []
        self.scene = MescherScene(window_size=(st.cell, st.cell))

    def shoot(self, items: Sequence[tuple], bounds, lights=LIGHTS[:1], env_map=None) -> np.ndarray:
        """Render ``items`` (("mescher", m, order, kw) or ("mesh", V, F, kw)) with one camera."""
        scene = self.scene
        scene.clear()
        for kind, a, b, kw in items:
            if kind == "mescher":
                scene.add(a, order=b, **kw)
            else:
                scene.add_embedding(a, b, **kw)
        scene.view(bounds)
        scene.relight(lights, env_map)
        return scene.screenshot()

    def relit(self, items, bounds, lights: Sequence, env_map=None) -> list[np.ndarray]:
        """One render per light (and one for ``env_map``), the geometry added once."""
        self.shoot(items, bounds)
        images = []
        for light in lights:
            self.scene.relight([light])
            images.append(self.scene.screenshot())
        if env_map is not None:
            self.scene.relight([], env_map)
            images.append(self.scene.screenshot())
        return images

    def save(self, image, name: str) -> str:
        from PIL import Image

        if isinstance(image, np.ndarray):
            image = Image.fromarray(np.ascontiguousarray(image))
        image.save(self.out / name)
        return name

    def step(self, record: dict, key: str, label: str, fn: Callable[[], Any]) -> Any:
        """Run one step, timing it; a failure is recorded and the study goes on."""
        self.progress(label)
        t0 = time.perf_counter()
        try:
            return fn()
        except Exception as exc:  # noqa: BLE001 -- one broken step must not lose the report
            msg = f"{label}: {type(exc).__name__}: {exc}"
            self.errors.append(msg)
            record.setdefault("errors", []).append(msg)
            record.setdefault("tracebacks", []).append(traceback.format_exc(limit=6))
            return None
        finally:
            record.setdefault("timings_s", {})[key] = round(time.perf_counter() - t0, 3)

    def close(self) -> None:
        self.scene.close()


def _bounds(xy: np.ndarray, cell: int) -> tuple[float, float, float, float]:
    return default_bounds(_xy_box(np.asarray(xy)), (cell, cell))


def _fmt(values: Sequence[float]) -> str:
    return ", ".join(f"{v:.4g}" for v in values) if len(values) else "none"


def _sources(m: Any) -> np.ndarray:
    """One source per connected component (nearest its top-left corner), so that a distance
    field covers models made of separate pieces (Reutersvard's cubes, the stair boxes)."""
    from meschers_igl.topology import connected_components

    xy = np.asarray(m.xy)
    _, label = connected_components(np.asarray(m.F), int(m.n_vertices))
    label = np.asarray(label)
    used = np.zeros(label.size, dtype=bool)
    used[np.asarray(m.F).ravel()] = True
    corner = np.array([xy[:, 0].min(), xy[:, 1].max()])
    dist = np.where(used, np.linalg.norm(xy - corner, axis=1), np.inf)
    # per component, the vertex of least distance: sort by (label, distance), keep the firsts
    idx = np.lexsort((dist, label))
    first = idx[np.r_[True, label[idx][1:] != label[idx][:-1]]]
    return np.sort(first[np.isfinite(dist[first])]).astype(np.int64)


def loop_periods(m: Any, zeta: np.ndarray) -> np.ndarray:
    """Depth gained by the 1-form ``zeta`` around each of ``m``'s homology generators.

    Lets the periods of a processed mescher with the same edges (smoothed: same topology) be
    compared loop by loop with ``m.periods()``, whatever generators it would pick itself.
    """
    zeta = np.asarray(zeta, dtype=np.float64)
    return np.array([float(np.dot(s, zeta[e])) for e, s in m.homology_generators()])


def _exact_distance(m: Any, source: int) -> tuple[np.ndarray | None, str]:
    """Exact distances on the covering (``igl.exact_geodesic``), or why there are none."""
    from meschers_igl.covering import covering_distance

    try:
        return covering_distance(m, source), "covering (igl.exact_geodesic)"
    except MescherError as exc:  # e.g. two independent periods: no 1D stack of sheets
        return None, f"no covering: {exc}"


def _steps_model(
    run: _Run, name: str, m0: Any, order0: Any, cut: tuple, record: dict, sec: Section
) -> None:
    """All steps on one gallery model (``cut`` = (V, F) of its cut model, camera frame)."""
    from meschers_igl.heat import HeatGeodesicSolver

    st, out_name = run.st, name
    Vcut, Fcut = cut
    record["input"] = _topology(m0)

    # -- subdivision ----------------------------------------------------------------------------
    def subdivide():
        if st.levels == 0:
            return m0, order0
        m, order = m0.subdivide(st.levels, scheme="midpoint", order=order0)
        p0, p1 = np.asarray(m0.periods()), np.asarray(m.periods())
        record["subdivision"] = {
            "levels": st.levels,
            "faces": [int(m0.n_faces), int(m.n_faces)],
            "period_drift": float(np.abs(p1 - p0).max(initial=0.0)),
            "max_integrability_residual": float(np.abs(m.integrability_residual()).max()),
        }
        return m, order

    m, order = run.step(record, "subdivide", f"{name}: subdivide", subdivide) or (m0, order0)
    bounds = _bounds(m.xy, st.cell)
    scale = float(np.linalg.norm(np.ptp(np.asarray(m.xy), axis=0)))
    h = float(np.mean(m.edge_lengths()))
    sources = _sources(m)
    source = int(sources[0])
    base = {"shading": "smooth"}

    # -- Hodge decomposition and periods --------------------------------------------------------
    def hodge():
        hd = m.hodge()
        exact = m.d01 @ np.asarray(hd.z)
        omega = np.asarray(hd.omega)
        zeta = np.asarray(m.zeta)
        periods = np.asarray(m.periods())
        record["hodge"] = {
            "zeta_norm": float(np.linalg.norm(zeta)),
            "exact_norm": float(np.linalg.norm(exact)),
            "harmonic_norm": float(np.linalg.norm(omega)),
            "reconstruction_error": float(np.abs(exact + omega - zeta).max()),
            "harmonic_closed": float(np.abs(m.d12 @ omega).max(initial=0.0)),
            "periods": periods.tolist(),
            "impossible": bool(m.is_impossible()),
        }
        left = run.shoot(
            [
                (
                    "mescher",
                    m,
                    order,
                    dict(base, scalars=np.asarray(hd.z), cmap="coolwarm", isolines=st.isolines),
                )
            ],
            bounds,
        )
        right = run.shoot([("mescher", m, order, {"shading": "flat"})], bounds)
        segs, labels = [], []
        xy, edges = np.asarray(m.xy), np.asarray(m.edges)
        palette = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]
        for k, (eids, _signs) in enumerate(m.homology_generators()):
            colour = (
                palette[k % len(palette)] if abs(periods[k]) > 1e-9 * max(scale, 1) else "#777777"
            )
            segs.append((xy[edges[eids]], colour, 3))
            mid = xy[edges[eids[len(eids) // 2]]].mean(axis=0)
            labels.append((mid, f"p{k}={periods[k]:.3g}", colour))
        right = _overlay(right, bounds, segments=segs, labels=labels)
        fig = compose([[left, right]], ["exact part z (isolines)", "homology loops and periods"])
        sec.figures.append(Figure(run.save(fig, f"{out_name}_hodge.png"), "Hodge decomposition and periods",
            "Left: the potential z of the exact part d01 z of zeta (paper Eq. 3), i.e. the depth of the "
            "bent embedding, with isolines. Right: the homology generators (tree-cotree) and the depth "
            f"gained around each, the periods of the harmonic part omega: {_fmt(periods)}. A non-zero "
            "period is what makes the object impossible."))  # fmt: skip

    run.step(record, "hodge", f"{name}: Hodge decomposition", hodge)

    # -- rendering and relighting ---------------------------------------------------------------
    def render():
        rows = []
        for shading in ("flat", "smooth"):
            rows.append(
                run.relit([("mescher", m, order, {"shading": shading})], bounds, LIGHTS, ENV_MAP)
            )
        cols = [f"light {i + 1} {tuple(round(c, 1) for c in L)}" for i, L in enumerate(LIGHTS)] + [
            f"env map '{ENV_MAP}'"
        ]
        fig = compose(rows, cols, ["flat", "smooth"])
        record["render"] = {
            "lights": [list(L) for L in LIGHTS],
            "env_map": ENV_MAP,
            "arcs_in_depth_order": int(order.n_arcs) if order is not None else 0,
        }
        sec.figures.append(Figure(run.save(fig, f"{out_name}_render.png"), "Rendering and relighting",
            "The flattened mescher drawn back to front in a linear extension of its depth order (paper "
            "Sec. 4.1), shaded with normals derived from zeta: per face (top) and interpolated per vertex "
            "(bottom), under four directional lights and an environment map. Only directional and "
            "environment lighting is defined on a mescher (it has no absolute depth)."))  # fmt: skip

    run.step(record, "render", f"{name}: render and relight", render)

    # -- heat diffusion -------------------------------------------------------------------------
    def heat():
        u0 = np.zeros(m.n_vertices)
        u0[source] = 1.0
        Mdiag = m.massmatrix().diagonal()
        images, notes, drift = [], [], []
        for factor in st.heat_times:
            u = m.heat_diffuse(u0, factor * h * h)
            drift.append(abs(float(Mdiag @ u) - float(Mdiag @ u0)) / float(Mdiag @ u0))
            images.append(
                run.shoot(
                    [
                        (
                            "mescher",
                            m,
                            order,
                            dict(base, scalars=u / u.max(), cmap=_HEAT_CMAP, clim=(0, 1)),
                        )
                    ],
                    bounds,
                )
            )
            notes.append(f"t = {factor:g} h^2")
        record["heat"] = {
            "source": source,
            "t": [f * h * h for f in st.heat_times],
            "h": h,
            "heat_conservation_error": max(drift),
        }
        sec.figures.append(Figure(run.save(compose([images], notes), f"{out_name}_heat.png"), "Heat diffusion",
            f"Backward Euler heat diffusion (M - tL) u = M u0 (paper Eq. 5) from vertex {source}, for three "
            "times t (h: mean edge length), each normalised to its maximum. The heat spreads over the "
            "surface as perceived, across the impossible loop. Total heat 1^T M u is kept to "
            f"{max(drift):.1e}."))  # fmt: skip

    run.step(record, "heat", f"{name}: heat diffusion", heat)

    # -- geodesic distance and a shortest path --------------------------------------------------
    geo: dict = {}

    def geodesic():
        d_exact, how = _exact_distance(m, sources)
        geo["exact"] = d_exact
        rec: dict = {"sources": sources.tolist(), "exact": how}
        d = HeatGeodesicSolver(m).distance(sources)
        d_acc = HeatGeodesicSolver(m, method="accurate").distance(sources)
        # the path: from the first source to the farthest vertex of its component
        d0 = d_exact if d_exact is not None else d_acc
        d0 = HeatGeodesicSolver(m, method="accurate").distance(source) if sources.size > 1 else d0
        finite = np.isfinite(d0)
        target = int(np.flatnonzero(finite)[np.argmax(d0[finite])])
        if d_exact is not None:
            rec["heat_error"] = distance_error(d, d_exact)
            rec["heat_accurate_error"] = distance_error(d_acc, d_exact)
        path = m.shortest_path(source, target)
        rec.update(target=target, path_length=float(path.length), path_points=int(path.n_points))
        if d_exact is not None and sources.size == 1:
            rec["path_length_over_exact"] = float(path.length / d_exact[target])
        record["geodesic"] = rec
        P = np.asarray(path.xy)
        clim = (0.0, float(np.nanmax(np.where(np.isfinite(d_acc), d_acc, np.nan))))
        img = run.shoot(
            [
                (
                    "mescher",
                    m,
                    order,
                    dict(base, scalars=d_acc, cmap=_GEODESIC_CMAP, clim=clim, isolines=st.isolines),
                )
            ],
            bounds,
        )
        img = _overlay(img, bounds, segments=[(np.stack([P[:-1], P[1:]], axis=1), "#ff2020", 3)],
                       points=[(np.asarray(m.xy)[sources], "white", 5), (P[[-1]], "#ff2020", 5)])  # fmt: skip
        err = ""
        if d_exact is not None:
            err = (f" Against exact distances on a 3-sheet covering of the mescher (igl.exact_geodesic): mean error "
                   f"{rec['heat_error']['mean']:.2%} (standard) and {rec['heat_accurate_error']['mean']:.2%} "
                   f"(accurate preset) of the largest distance."
                   + (f" The path is {rec['path_length_over_exact']:.4f} times the exact distance."
                      if "path_length_over_exact" in rec else ""))  # fmt: skip
        sec.figures.append(Figure(run.save(img, f"{out_name}_geodesic.png"), "Geodesic distance and shortest path",
            f"Heat-method distance (Crane et al.; paper Sec. 4.3) from vertex {source} (white dot; one source "
            "per connected component), accurate preset, with {st.isolines} isolines, and the shortest path (red) to the farthest vertex, traced "
            f"down the distance's gradient and pulled taut; length {path.length:.4g}. The path is drawn on top "
            f"of the picture (occlusion ignored).{err}"))  # fmt: skip

    run.step(record, "geodesic", f"{name}: geodesic distance", geodesic)

    # -- smoothing (the Heart figure) -----------------------------------------------------------
    def smoothing():
        rows, drift = [], {}
        p0 = np.asarray(m.periods())
        for row, (fx, fz) in {"xy": (1, 0), "zeta": (0, 1), "both": (1, 1)}.items():
            cells, worst = [], 0.0
            for factor in st.smooth_times:
                t = factor * scale * scale
                ms = m.smooth(t_xy=fx * t, t_zeta=fz * t)
                drift_t = np.abs(loop_periods(m, ms.zeta) - p0).max(initial=0.0)
                worst = max(worst, float(drift_t))
                cells.append(run.shoot([("mescher", ms, order, base)], bounds))
            rows.append(cells)
            drift[row] = worst
        record["smoothing"] = {
            "t": [f * scale * scale for f in st.smooth_times],
            "period_drift": drift,
        }
        cols = [f"t = {f:g} s^2" for f in st.smooth_times]
        sec.figures.append(Figure(run.save(compose(rows, cols, ["smooth xy", "smooth zeta", "smooth both"]), f"{out_name}_smoothing.png"),
            "Smoothing (the paper's Heart figure)",
            "Laplacian smoothing (M - tL) u = M u0 of the screen positions xy (top), of the exact part z of "
            "zeta with omega kept (middle; paper Eq. 6), and of both (bottom), for growing t (s: diagonal of "
            "the xy box; same camera in every panel). The harmonic part is in the kernel of the smoothing, so "
            f"the periods do not move: largest change {max(drift.values()):.1e}."))  # fmt: skip

    run.step(record, "smoothing", f"{name}: smoothing", smoothing)

    # -- relighting against the cut model -------------------------------------------------------
    def relighting():
        ref = run.relit([("mesh", Vcut, Fcut, {"shading": "flat"})], bounds, LIGHTS)
        mes = run.relit([("mescher", m, order, {"shading": "flat"})], bounds, LIGHTS)
        Vb, Fb = m.bent_embedding()
        bent = run.relit([("mesh", Vb, Fb, {"shading": "flat"})], bounds, LIGHTS)
        rec = {}
        notes = []
        for key, imgs in (("mescher", mes), ("bent", bent)):
            agree = [image_agreement(a, b) for a, b in zip(imgs, ref)]
            rec[key] = {k: [g[k] for g in agree] for k in agree[0]}
            notes.append([f"IoU {g['iou']:.3f}  dL {g['luminance_mae']:.3f}" for g in agree])
        record["relighting"] = rec
        cols = [f"light {i + 1}" for i in range(len(LIGHTS))]
        fig = compose(
            [ref, mes, bent], cols, ["cut model", "mescher", "bent"], [[""] * len(LIGHTS), *notes]
        )
        worst_m = max(rec["mescher"]["luminance_mae"])
        worst_b = max(rec["bent"]["luminance_mae"])
        sec.figures.append(Figure(run.save(fig, f"{out_name}_relight.png"), "Relighting: mescher vs cut vs bent",
            "The gallery's cut 3D model (z-buffered, the reference), the mescher (painter's order) and the bent "
            "embedding (harmonic part dropped) under the four lights, flat shading. Under each panel: silhouette "
            "IoU and mean luminance difference (0-1) to the cut model on pixels covered by both. The mescher's "
            f"normals are the cut model's (worst dL {worst_m:.3f}); the bent model's are not (worst dL "
            f"{worst_b:.3f}): bending cannot be relit (paper Fig. 10)."))  # fmt: skip

    run.step(record, "relighting", f"{name}: relighting vs cut", relighting)

    # -- mescher / cut / bent: smoothing and geodesics ------------------------------------------
    def comparison():
        from meschers_igl import Mescher
        from pyvista_views.compare import compare

        if not m.is_impossible():
            # no harmonic part: the cut needs no seam and the bent model is the mescher itself
            record["comparison"] = {
                "skipped": "no harmonic part: cut and bent embeddings equal the mescher"
            }
            return
        t = st.compare_time * scale * scale
        res = compare(
            m,
            order,
            path=run.out / f"{out_name}_compare.png",
            source=source,
            t_smooth=t,
            window_size=(st.cell, st.cell),
        )
        rec: dict = {"t_smooth": t, "numbers": res.numbers}
        d_exact = geo.get("exact")
        Vc, Fc, vmap = m.cut_embedding()
        cut_m = Mescher.from_mesh(Vc, Fc)
        if d_exact is not None:
            # the cut model at its best: every copy of the source is a source, and a mescher
            # vertex gets the distance of its nearest copy (compare() reads the first copy)
            d_cut = np.full(m.n_vertices, np.inf)
            np.minimum.at(d_cut, vmap, cut_m.geodesic_distance(np.flatnonzero(vmap == source)))
            dist = {
                "mescher": res.distances["mescher"],
                "cut": d_cut,
                "bent": res.distances["bent"],
            }
            rec["geodesic_error_vs_exact"] = {
                k: distance_error(v, d_exact) for k, v in dist.items()
            }
        cut_s = cut_m.smooth(t_xy=t, t_zeta=t)
        rec["seam_gap_after_smoothing"] = {
            "cut": seam_gap(cut_s.xy, vmap) / scale,
            "mescher": 0.0,
            "bent": 0.0,
        }
        p0 = np.asarray(m.periods())
        ms = m.smooth(t_xy=t, t_zeta=t)
        rec["max_period_after_smoothing"] = {
            "before": float(np.abs(p0).max(initial=0.0)),
            "mescher": float(np.abs(loop_periods(m, ms.zeta)).max(initial=0.0)),
            "bent": 0.0,  # its zeta is exact by construction: no period survives
        }
        record["comparison"] = rec
        ge = rec.get("geodesic_error_vs_exact")
        geo_txt = ""
        if ge:
            geo_txt = (" Geodesic error against the covering's exact distances (mean, fraction of the largest "
                       f"distance): mescher {ge['mescher']['mean']:.2%}, cut {ge['cut']['mean']:.2%}, bent "
                       f"{ge['bent']['mean']:.2%}: paths cannot cross the cut model's seam, and the bent model's "
                       "metric is not the object's.")  # fmt: skip
        sec.figures.append(Figure(res.path.name if res.path else "", "Mescher vs cut vs bent (paper Fig. 10)",
            "Rows: the mescher, its cut embedding (cut along the homology generators) and its bent embedding; "
            "columns: render, relit, smoothed with the same t (both xy and depth), heat-method geodesic distance "
            "from the same vertex. Smoothing the cut model as an ordinary mesh opens a crack at the seam of "
            f"{rec['seam_gap_after_smoothing']['cut']:.2%} of the object's size; the mescher has no seam and keeps "
            f"its period ({rec['max_period_after_smoothing']['mescher']:.4g} of "
            f"{rec['max_period_after_smoothing']['before']:.4g}), the bent model has none to keep.{geo_txt}"))  # fmt: skip

    run.step(record, "comparison", f"{name}: mescher / cut / bent", comparison)


# ------------------------------------------------------------------------------------------------
# models from other tools
# ------------------------------------------------------------------------------------------------
def paradox_models() -> list[tuple[str, Path, dict]]:
    """The ParadoxToolkit cut models shipped in ``meschers_igl/data/paradox`` (name, OBJ, JSON).

    Empty when the data is not installed (the section is then left out of the report).
    """
    try:
        root = importlib.resources.files("meschers_igl") / "data" / "paradox"
        root = Path(str(root))
    except (ModuleNotFoundError, TypeError):  # pragma: no cover - a zipped install
        return []
    if not root.is_dir():
        return []
    found = []
    for obj in sorted(root.glob("*.obj")):
        meta = obj.with_suffix(".json")
        if meta.is_file():
            found.append((obj.stem, obj, json.loads(meta.read_text())))
    return found


def _steps_paradox(run: _Run, name: str, obj: Path, meta: dict, record: dict, sec: Section) -> None:
    from meschers_igl.operators import view_frame

    st = run.st
    view, up = meta["camera"]["view_dir"], meta["camera"]["up"]

    def convert():
        from meshlab_filters import cut_model_to_mescher, load_artist_model

        V, F, report = load_artist_model(obj)
        m, order = cut_model_to_mescher((V, F), view=view, up=up)
        gaps = meta.get("verification", {}).get("depth_gaps")
        record["input"] = _topology(m)
        record["cleanup"] = report.as_dict()
        record["expected"] = {
            "depth_gaps": gaps,
            "glued_chi": meta.get("verification", {}).get("glued_chi"),
        }
        return m, order, V @ view_frame(view, up).T, F

    got = run.step(record, "convert", f"{name}: convert", convert)
    if got is None:
        return
    m, order, Vc, F = got
    bounds = _bounds(m.xy, st.cell)

    def relight():
        mes = run.relit([("mescher", m, order, {"shading": "flat"})], bounds, LIGHTS, ENV_MAP)
        ref = run.relit([("mesh", Vc, F, {"shading": "flat"})], bounds, LIGHTS)
        agree = [image_agreement(a, b) for a, b in zip(mes, ref)]
        record["relighting"] = {k: [g[k] for g in agree] for k in agree[0]}
        notes = [
            [f"IoU {g['iou']:.3f}  corr {g['luminance_corr']:.3f}" for g in agree] + [""],
            [""] * len(ref),
        ]
        cols = [f"light {i + 1}" for i in range(len(LIGHTS))] + [f"env map '{ENV_MAP}'"]
        fig = compose([mes, ref], cols, ["mescher", "tool's cut"], notes)
        sec.figures.append(Figure(run.save(fig, f"paradox_{name}_relight.png"), "Render and relight",
            "Top: the mescher glued from the tool's cut model (only its view and up vectors given), drawn in "
            "its depth order under four lights and an environment map. Bottom: the cut model itself, z-buffered "
            "with the same camera. Numbers: silhouette IoU and luminance correlation of the two."))  # fmt: skip

    def periods_and_geodesic():
        periods = np.asarray(m.periods())
        record["periods"] = periods.tolist()
        record["impossible"] = bool(m.is_impossible())
        ms, order1 = m.subdivide(1, order=order)
        source = _sources(ms)
        d = ms.geodesic_distance(source, method="accurate")
        d_exact, how = _exact_distance(ms, source)
        rec = {"sources": source.tolist(), "subdivision_levels": 1, "exact": how}
        if d_exact is not None:
            rec["heat_accurate_error"] = distance_error(d, d_exact)
        record["geodesic"] = rec
        img = run.shoot(
            [
                (
                    "mescher",
                    ms,
                    order1,
                    {
                        "shading": "smooth",
                        "scalars": d,
                        "cmap": _GEODESIC_CMAP,
                        "isolines": st.isolines,
                    },
                )
            ],
            bounds,
        )
        img = _overlay(img, bounds, points=[(np.asarray(ms.xy)[source], "white", 5)])
        flat = run.shoot([("mescher", m, order, {"shading": "flat"})], bounds)
        xy, edges = np.asarray(m.xy), np.asarray(m.edges)
        segs, labels = [], []
        for k, (eids, _s) in enumerate(m.homology_generators()):
            if abs(periods[k]) > 1e-9 * m.scale():
                segs.append((xy[edges[eids]], "#d62728", 3))
                labels.append(
                    (xy[edges[eids[len(eids) // 2]]].mean(axis=0), f"{periods[k]:.4g}", "#d62728")
                )
        flat = _overlay(flat, bounds, segments=segs, labels=labels)
        fig = compose([[flat, img]], ["non-zero periods", "geodesic distance"])
        gaps = record.get("expected", {}).get("depth_gaps")
        err = (
            f" Mean error against exact covering distances: {rec['heat_accurate_error']['mean']:.2%}."
            if "heat_accurate_error" in rec
            else ""
        )
        sec.figures.append(Figure(run.save(fig, f"paradox_{name}_periods.png"), "Periods and geodesic distance",
            f"Left: homology loops with a non-zero period (the tool's depth gaps: {gaps}); periods found "
            f"{_fmt(periods)}. Right: heat-method distance (accurate preset) from the white dots (one per "
            f"connected component) after one midpoint subdivision.{err}"))  # fmt: skip

    run.step(record, "relight", f"{name}: relight", relight)
    run.step(record, "periods_geodesic", f"{name}: periods and geodesic", periods_and_geodesic)


# ------------------------------------------------------------------------------------------------
# entry point
# ------------------------------------------------------------------------------------------------
def run_study(
    models: Sequence[str] | None = None,
    out: str | Path = "meschers_study",
    quick: bool = False,
    progress: bool = True,
    other_tools: bool = True,
) -> StudyResult:
    """Run the comparison study and write its report.

    Parameters
    ----------
    models : sequence of str, optional
        Gallery model names (:func:`meschers_igl.gallery.list_models`); default: all.
    out : str or Path
        Output folder (created); receives the PNGs, ``metrics.json`` and ``index.html``.
    quick : bool
        Small panels and one subdivision level (:func:`study_settings`).
    progress : bool
        Show a rich progress bar with the model and step.
    other_tools : bool
        Add the "Models from other tools" section when the ParadoxToolkit data is installed.

    Returns
    -------
    StudyResult

    Raises
    ------
    MescherError
        Unknown model name, or ``out`` exists and is not a folder.
    """
    from meschers_igl.gallery import get_model, list_models
    from meschers_igl.operators import view_frame

    from .report import write_report

    names = list(list_models() if models is None else models)
    unknown = [n for n in names if n not in list_models()]
    if unknown or not names:
        raise MescherError(
            f"models: expected names from {', '.join(list_models())}, found {', '.join(unknown) or 'none'}"
        )
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise MescherError(f"out: expected a folder, found a file at '{out}'")
    out.mkdir(parents=True, exist_ok=True)
    st = study_settings(quick)
    tools = paradox_models() if other_tools else []
    t_start = time.perf_counter()
    metrics: dict[str, Any] = {
        "citation": CITATION,
        "doi": DOI_URL,
        "settings": asdict(st),
        "lights": [list(L) for L in LIGHTS],
        "env_map": ENV_MAP,
        "models": {},
        "other_tools": {},
    }
    sections: list[Section] = []
    tool_sections: list[Section] = []

    total = len(names) * 9 + len(tools) * 3
    with _progress(progress, total) as advance:
        run = _Run(out, st, advance)
        try:
            for name in names:
                g = get_model(name)
                record: dict = {"description": g.description, "expected_period": g.expected_period}
                sec = Section(name, name.replace("_", " ").title(), g.description)
                built = run.step(
                    record, "build", f"{name}: build", lambda g=g: (g.mescher, g.order)
                )
                if built is not None:
                    Vcam = g.V @ view_frame(g.view, g.up).T
                    _steps_model(run, name, built[0], built[1], (Vcam, g.F), record, sec)
                record["runtime_s"] = round(sum(record["timings_s"].values()), 3)
                metrics["models"][name] = record
                sections.append(sec)
            for name, obj, meta in tools:
                record = {"source": meta.get("source", {}).get("repo", ""), "file": obj.name}
                sec = Section(
                    name, name.replace("_", " ").title(), f"ParadoxToolkit cut model '{obj.name}'."
                )
                _steps_paradox(run, name, obj, meta, record, sec)
                record["runtime_s"] = round(sum(record.get("timings_s", {}).values()), 3)
                metrics["other_tools"][name] = record
                tool_sections.append(sec)
            if other_tools and not tools:
                metrics["other_tools_note"] = (
                    "ParadoxToolkit data not installed (meschers_igl/data/paradox)"
                )
        finally:
            run.close()
    metrics["errors"] = run.errors
    metrics["runtime_s"] = round(time.perf_counter() - t_start, 2)
    (out / "metrics.json").write_text(json.dumps(_jsonable(metrics), indent=2, allow_nan=True))
    write_report(out, metrics, sections, tool_sections)
    return StudyResult(out, metrics, sections + tool_sections, run.errors)


def _jsonable(x: Any) -> Any:
    """numpy scalars and arrays to plain Python, NaN/inf kept as JSON's NaN/Infinity."""
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, np.generic):
        return x.item()
    return x


class _progress:
    """A rich progress bar showing ``model: step`` (a no-op when disabled)."""

    def __init__(self, enabled: bool, total: int):
        self.enabled, self.total, self._bar = enabled, total, None

    def __enter__(self) -> Callable[[str], None]:
        if not self.enabled:
            return lambda label: None
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

        self._bar = Progress(
            TextColumn("[bold]meschers study[/]"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total}"),
            TimeElapsedColumn(),
            TextColumn("{task.description}"),
            transient=False,
        )
        self._bar.start()
        task = self._bar.add_task("starting", total=self.total)
        first = [True]

        def advance(label: str) -> None:
            # the bar counts finished steps: advance on every label after the first
            self._bar.update(task, description=label, advance=0 if first[0] else 1)
            first[0] = False

        return advance

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.update(self._bar.task_ids[0], completed=self.total)
            self._bar.stop()
