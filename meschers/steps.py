"""The study's steps on one mescher, one small function each (paper Sections 3-4).

Every step takes the :class:`~meschers.job.ModelJob` (settings, renderer, record, figures) and
the :class:`Subject` (the processed mescher and what several steps share), records its numbers
under its own key and adds its figure.  What two steps need is computed once, in the
:class:`Subject`: one heat-method solver per (mescher, method), the exact distances, the
smoothed meschers per time.

================ ===================================================================================
subdivide        midpoint 1-to-4 subdivision with the depth order carried along; periods must not move
hodge            ``zeta = d01 z + omega`` (paper Eq. 3), the periods of ``omega`` drawn on the picture
render           flat and smooth shading under four directional lights and an environment map
loop_subdivision Loop subdivision with creases beside the input and plain Loop
heat             backward Euler heat diffusion from one vertex (paper Eq. 5) for three times ``t``
geodesic         heat-method distance against exact distances (window propagation), a shortest path
smoothing        Laplacian smoothing of xy, of the exact part of zeta and of both (paper Fig. 8)
relighting       the mescher and its bent embedding against the cut 3D model, light by light
comparison       mescher / cut / bent (paper Fig. 10, :func:`pyvista_views.compare.compare`)
================ ===================================================================================
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from meschers_igl.smoothing import follow_sheets
from pyvista_views.camera import default_bounds, xy_box
from pyvista_views.render import hide_back_faces

from .describe import describe, impossibility_kind
from .figures import (
    Colorbar,
    compose,
    format_value,
    format_values,
    lines_over,
    round_off_scale,
)
from .job import ModelJob
from .lineart_step import line_art
from .metrics import (
    distance_error,
    exact_distance,
    loop_periods,
    one_source_per_component,
    seam_gap,
)
from .settings import ENV_MAP, GEODESIC_CMAP, HEAT_CMAP, LIGHTS, subdivision_levels

__all__ = ["STEPS", "Subject", "run_mescher_steps", "subdivide", "subdivision_levels"]

#: Colours of the homology loops in the Hodge figure (grey: a loop with period 0).
PALETTE = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")
#: Heat is drawn as log10(u / max u) from this value (black) to 0: a point source's heat spans
#: many orders of magnitude, which a linear scale shows as a black figure with one bright dot.
HEAT_LOG_MIN = -6.0
#: The Heart figure smooths depth this many times longer than screen positions (see smoothing).
ZETA_TIME_FACTOR = 10.0
#: Smallest panel of the subdivision figure, in pixels (the study's quick cells are smaller).
FIGURE_MIN_PX = 256
#: Stroke widths (pixels) of the line drawing over the flat row: the gallery figure's, creases
#: a little wider so that they still show on the study's quick 192 px cells.
FLAT_LINE_WIDTHS = {"outline": 1.2, "occlusion": 1.0, "crease": 0.8}


@dataclass
class Subject:
    """The processed mescher of one model and what several steps share, computed once.

    Attributes
    ----------
    name : str
    m : Mescher
    order : DepthOrder or None
    reference : (Vcam (n, 3), F (k, 3)) or None
        The cut 3D model in camera coordinates, the ground truth for relighting.
    reference_note : str
        Where the reference comes from (said in the caption).
    exact : (#V,) float64, optional
        Exact distances from ``sources`` (set by :func:`geodesic`; ``inf`` where not measured).
    """

    name: str
    m: Any
    order: Any
    reference: tuple | None = None
    reference_note: str = "the gallery's cut 3D model"
    _solvers: dict = field(default_factory=dict, repr=False)
    _smoothed: dict = field(default_factory=dict, repr=False)
    exact: np.ndarray | None = field(default=None, repr=False)
    #: the input mescher and order, before the study's midpoint subdivision
    coarse: tuple | None = field(default=None, repr=False)
    _lines: Any = field(default=None, repr=False)

    def __post_init__(self) -> None:
        xy = np.asarray(self.m.xy)
        self.xy_box = xy_box(xy)
        self.scale = float(np.linalg.norm(np.ptp(xy, axis=0)))  # diagonal of the xy box
        self.h = float(np.mean(self.m.edge_lengths()))
        self.sources = one_source_per_component(self.m)
        self.source = int(self.sources[0])

    def bounds(self, cell: int) -> tuple[float, float, float, float]:
        """The camera of every panel: the xy box plus margin, square."""
        return default_bounds(self.xy_box, (cell, cell))

    def solver(self, method: str = "standard"):
        """The solver of ``m`` for ``method`` (:func:`meschers_igl.geodesic.geodesic_solver`)."""
        if method not in self._solvers:
            from meschers_igl.geodesic import geodesic_solver

            self._solvers[method] = geodesic_solver(self.m, method)
        return self._solvers[method]

    def lines(self):
        """The line drawing of the input mescher in its order, hidden parts included
        (:func:`meschers_igl.lines.line_drawing` with ``hidden=True``; its visible lines are
        the drawing without them): the render and line-art steps draw the one drawing."""
        if self._lines is None:
            from meschers_igl.lines import line_drawing

            m0, o0 = self.coarse if self.coarse is not None else (self.m, self.order)
            self._lines = line_drawing(m0, o0, hidden=True)
        return self._lines

    def smoothed(self, t: float):
        """``m`` with xy and the exact part of zeta smoothed for time ``t`` (one factorization
        of ``M - tL`` serves both, :meth:`Mescher.smooth`)."""
        if t not in self._smoothed:
            self._smoothed[t] = self.m.smooth(t_xy=t, t_zeta=t)
        return self._smoothed[t]


def _mescher(s: Subject, **kw: Any) -> tuple:
    return ("mescher", s.m, s.order, kw)


def subdivide(job: ModelJob, m0: Any, order0: Any) -> tuple:
    """Midpoint subdivision ``st.levels`` times (fewer if the faces would pass
    ``st.max_faces``), the order carried along; periods kept."""
    levels = subdivision_levels(m0.n_faces, job.st.levels, job.st.max_faces)
    if levels == 0:
        return m0, order0
    if order0 is None:
        m, order = m0.subdivide(levels, scheme="midpoint"), None
    else:
        m, order = m0.subdivide(levels, scheme="midpoint", order=order0)
    p0, p1 = np.asarray(m0.periods()), np.asarray(m.periods())
    job.record["subdivision"] = {
        "levels": levels,
        "faces": [int(m0.n_faces), int(m.n_faces)],
        "period_drift": float(np.abs(p1 - p0).max(initial=0.0)),
        "max_integrability_residual": float(np.abs(m.integrability_residual()).max()),
    }
    return m, order


def _loop_marks(s: Subject, periods: np.ndarray, all_loops: bool, prefix: bool) -> list:
    """The homology loops as closed geodesics on the surface (``shortest_loops``), as path items
    of :meth:`Renderer.shoot`: non-zero periods in colour, labelled with their period."""
    from meschers_igl.geodesic import shortest_loops

    # round-off is judged against the model's size: all-zero periods print as 0, not 1e-15
    scale = max(round_off_scale(periods, s.scale), 1e-300)
    items = []
    for k, loop in enumerate(shortest_loops(s.m)):
        nonzero = abs(periods[k]) > 1e-9 * max(s.scale, 1.0)
        if not (nonzero or all_loops):
            continue
        colour = PALETTE[k % len(PALETTE)] if nonzero else "#777777"
        text = format_value(periods[k], scale)
        # only loops that climb are labelled (ten "p=0" labels would bury the figure)
        label = (f"p{k}={text}" if prefix else text) if nonzero else None
        items.append(
            ("path", loop, None, {"color": colour, "width": 3 if nonzero else 2, "label": label})
        )
    return items


def hodge(job: ModelJob, s: Subject) -> None:
    """Hodge decomposition and periods (paper Eq. 3)."""
    st, m = job.st, s.m
    hd = m.hodge()
    exact, omega, zeta = m.d01 @ np.asarray(hd.z), np.asarray(hd.omega), np.asarray(m.zeta)
    periods = np.asarray(m.periods())
    job.record["hodge"] = {
        "zeta_norm": float(np.linalg.norm(zeta)),
        "exact_norm": float(np.linalg.norm(exact)),
        "harmonic_norm": float(np.linalg.norm(omega)),
        "reconstruction_error": float(np.abs(exact + omega - zeta).max()),
        "harmonic_closed": float(np.abs(m.d12 @ omega).max(initial=0.0)),
        "periods": periods.tolist(),
    }
    kind = impossibility_kind(m, s.order)
    job.record["hodge"]["impossible"] = kind is not None
    job.record["hodge"]["impossible_kind"] = kind
    bounds = s.bounds(st.cell)
    z = np.asarray(hd.z)
    zlim = (float(z.min()), float(z.max()) if z.max() > z.min() else float(z.min()) + 1.0)
    left = job.renderer.shoot(
        [
            _mescher(
                s, shading="smooth", scalars=z, cmap="coolwarm", clim=zlim, isolines=st.isolines
            )
        ],
        bounds,
    )
    loops = _loop_marks(s, periods, all_loops=True, prefix=True)
    right = job.renderer.shoot([_mescher(s, shading="flat"), *loops], bounds)
    fig = compose(
        [[left, right]],
        [f"exact part z ({st.isolines} isolines)", "homology loops and periods"],
        colorbar=Colorbar("coolwarm", *zlim, "z (depth, bent model)"),
    )
    job.figure(
        fig,
        f"{s.name}_hodge.png",
        "Hodge decomposition and periods",
        "Left: the potential z of the exact part d01 z of zeta (paper Eq. 3), i.e. the depth of the "
        f"bent embedding, with {st.isolines} isolines. Right: a closed geodesic in the class of each "
        "homology generator (tree-cotree), drawn where it lies on the visible surface (grey: period 0; "
        "coloured and labelled: the depth gained around it), and the depth gained around each, the periods of the harmonic part omega: "
        f"{format_values(periods, scale=round_off_scale(periods, s.scale))} (values "
        "below 1e-9 of the model's size are round-off, printed as 0). "
        f"{_impossible_because(kind)}",
    )


def _impossible_because(kind: str | None) -> str:
    """The caption's last sentence: what makes this object impossible, if anything."""
    if kind == "order":
        return (
            "Every period is 0, so zeta integrates; what makes the object impossible is its "
            "depth order, which its bent embedding cannot realise with one depth offset per "
            "connected component."
        )
    return "A non-zero period is what makes the object impossible."


def _flat_lines(s: Subject, images: list, bounds) -> tuple[list, str]:
    """The flat row under the figure's line drawing (outlines, occlusion lines, creases), as in
    the gallery figure: where a tread meets the next step's tread of the same shade (its riser
    faces away), only a line tells the steps apart.  The lines of the input mescher (the
    study's midpoint subdivision moves no point of the picture, and adds no line).  Without
    cairosvg the row stays plain and the returned note says so."""
    try:  # lines_over draws the visible lines only
        drawn = lines_over(images, s.lines(), bounds, widths=FLAT_LINE_WIDTHS)
    except ImportError:  # cairosvg is optional (meschers[lineart])
        return images, "cairosvg not installed: flat row without lines"
    return drawn, "line drawing over the flat row"


def render(job: ModelJob, s: Subject) -> None:
    """Flat shading with the line drawing over it, and smooth shading, under four lights and an
    environment map."""
    bounds = s.bounds(job.st.cell)
    rows = [
        job.renderer.relit([_mescher(s, shading=sh)], bounds, LIGHTS, ENV_MAP)
        for sh in ("flat", "smooth")
    ]
    rows[0], lines_note = _flat_lines(s, rows[0], bounds)
    cols = [f"light {i + 1} {tuple(round(c, 1) for c in L)}" for i, L in enumerate(LIGHTS)]
    fig = compose(rows, [*cols, f"env map '{ENV_MAP}'"], ["flat + lines", "smooth"])
    job.record["render"] = {
        "lights": [list(L) for L in LIGHTS],
        "env_map": ENV_MAP,
        "arcs_in_depth_order": int(s.order.n_arcs) if s.order is not None else 0,
        "flat_row": lines_note,
    }
    job.figure(
        fig,
        f"{s.name}_render.png",
        "Rendering and relighting",
        "The flattened mescher drawn back to front in a linear extension of its depth order (paper "
        "Sec. 4.1), shaded with normals derived from zeta: per face (top) and interpolated per vertex "
        "(bottom), under four directional lights and an environment map. Only directional and "
        "environment lighting is defined on a mescher (it has no absolute depth). Over the top "
        "row, the figure's line drawing (outlines, occlusion lines, creases), as in the gallery: "
        "where two surfaces of one orientation meet, such as the treads of neighbouring steps "
        "whose risers face away, shading alone cannot tell them apart.",
    )


def loop_subdivision(job: ModelJob, s: Subject) -> None:
    """Loop subdivision of the input mescher beside its flat faces (paper Sec. 4.2): with the
    crease rules (sharp edges kept) and, for comparison, plain Loop."""
    from meschers_igl.painter import backface_share

    m0, o0 = s.coarse if s.coarse is not None else (s.m, s.order)
    levels = subdivision_levels(m0.n_faces, 2, job.st.max_faces)
    if levels == 0:
        job.record["loop_subdivision"] = {"skipped": "over the face budget"}
        return
    cell = max(job.st.cell, FIGURE_MIN_PX)
    bounds = default_bounds(xy_box(np.asarray(m0.xy)), (cell, cell))
    p0 = np.asarray(m0.periods())
    rec: dict = {"levels": levels, "faces": [int(m0.n_faces), int(m0.n_faces * 4**levels)]}
    panels = [job.renderer.shoot([("mescher", m0, o0, {"shading": "flat"})], bounds)]
    notes = [f"{m0.n_faces} faces"]
    for scheme, shading in (("loop", "flat"), ("loop", "smooth"), ("loop-smooth", "smooth")):
        if o0 is None:
            ml, ol = m0.subdivide(levels, scheme=scheme), None
        else:
            ml, ol = m0.subdivide(levels, scheme=scheme, order=o0)
            ol = hide_back_faces(ml, ol)
        panels.append(job.renderer.shoot([("mescher", ml, ol, {"shading": shading})], bounds))
        back = float(backface_share(ml, ol, size=cell, bounds=bounds))
        drift = float(np.abs(np.asarray(ml.periods()) - p0).max(initial=0.0))
        rec[f"{scheme}_{shading}"] = {"backface_share": back, "period_drift": drift}
        notes.append(f"back faces {back:.1%}")
    job.record["loop_subdivision"] = rec
    cols = [
        "input (flat)",
        f"Loop x{levels}, creases (flat)",
        "creases (smooth)",
        "plain Loop (smooth)",
    ]
    fig = compose([panels], cols, notes=[notes])
    job.figure(
        fig,
        f"{s.name}_subdivision.png",
        "Loop subdivision with creases",
        f"The input mescher ({m0.n_faces} faces, flat) and {levels} level{'s' if levels > 1 else ''} of Loop subdivision of the "
        "surface a person sees (paper Sec. 4.2), the depth order carried along: with the crease rules of "
        "piecewise-smooth Loop subdivision (Hoppe et al. 1994; edges sharper than 30 degrees stay "
        "sharp, corners stay put), flat and smooth shading, and plain Loop, which rounds every edge. "
        "Under each panel: the share of the figure showing a back face. The periods are kept "
        f"(largest change {max(v['period_drift'] for k, v in rec.items() if isinstance(v, dict)):.1e}).",
    )


def heat(job: ModelJob, s: Subject) -> None:
    """Backward Euler heat diffusion from one vertex for three times (paper Eq. 5)."""
    st, m, scale = job.st, s.m, s.scale
    u0 = np.zeros(m.n_vertices)
    u0[s.source] = 1.0
    mass = m.massmatrix().diagonal()
    bounds = s.bounds(st.cell)
    images, notes, drift, spans = [], [], [], []
    for factor in st.heat_times:
        u = m.heat_diffuse(u0, factor * scale * scale)
        drift.append(abs(float(mass @ u) - float(mass @ u0)) / float(mass @ u0))
        # log scale per panel: each panel normalised to its maximum, then log10
        v = np.log10(np.maximum(u / u.max(), 10.0**HEAT_LOG_MIN))
        v[u <= 0] = np.inf  # parts the heat cannot reach (other components): "unreached"
        spans.append(float(u.min() / u.max()))
        kw = {"shading": "smooth", "scalars": v, "cmap": HEAT_CMAP, "clim": (HEAT_LOG_MIN, 0.0)}
        images.append(job.renderer.shoot([_mescher(s, **kw)], bounds))
        notes.append(f"t = {factor:g} s^2")
    job.record["heat"] = {
        "source": s.source,
        "t": [f * scale * scale for f in st.heat_times],
        "s": scale,
        "heat_conservation_error": max(drift),
        "min_over_max": spans,
    }
    bar = Colorbar(HEAT_CMAP, HEAT_LOG_MIN, 0.0, "log10(u/max u)")
    # only a model with a period has a loop that climbs; the others are impossible by their order
    across = ", across the impossible loop" if s.m.is_impossible() else ""
    job.figure(
        compose([images], notes, colorbar=bar),
        f"{s.name}_heat.png",
        "Heat diffusion",
        f"Backward Euler heat diffusion (M - tL) u = M u0 (paper Eq. 5) from vertex {s.source}, for "
        "three times t (s: diagonal of the xy box), each panel normalised to its maximum and drawn on a log "
        f"scale, log10(u / max u) from {HEAT_LOG_MIN:g} (dark blue) to 0 (yellow): the heat spreads over "
        f"the surface as perceived{across} (grey: parts it cannot reach). Total heat 1^T M u is kept to "
        f"{max(drift):.1e}.",
    )


def geodesic(job: ModelJob, s: Subject) -> None:
    """Heat-method distance against exact distances, and a shortest path."""
    st, m, sources, source = job.st, s.m, s.sources, s.source
    d = s.solver("standard").distance(sources)
    accurate = s.solver("accurate")
    d_acc = accurate.distance(sources)
    # the path: from the first source to the farthest vertex of its component
    d0 = accurate.distance(source) if sources.size > 1 else d_acc
    finite = np.isfinite(d0)
    target = int(np.flatnonzero(finite)[np.argmax(d0[finite])])
    # exact distances at every vertex (window propagation: the whole field in milliseconds)
    d_exact, how = exact_distance(m, sources)
    s.exact = d_exact
    rec: dict = {"sources": sources.tolist(), "exact": how}
    if d_exact is not None:
        rec["heat_error"] = distance_error(d, d_exact)
        rec["heat_accurate_error"] = distance_error(d_acc, d_exact)
    path = m.shortest_path(source, target, solver=accurate)  # the one accurate solver
    rec.update(target=target, path_length=float(path.length), path_points=int(path.n_points))
    if d_exact is not None and sources.size == 1:
        rec["path_length_over_exact"] = float(path.length / d_exact[target])
    job.record["geodesic"] = rec
    clim = (0.0, float(np.nanmax(np.where(np.isfinite(d_acc), d_acc, np.nan))))
    bounds = s.bounds(st.cell)
    kw = {
        "shading": "smooth",
        "scalars": d_acc,
        "cmap": GEODESIC_CMAP,
        "clim": clim,
        "isolines": st.isolines,
    }
    img = job.renderer.shoot(
        [
            _mescher(s, **kw),
            ("path", path, None, {"color": "#ff2020", "width": 3, "hidden": "dashed"}),
            ("points", sources, None, {"color": "white", "radius": 5}),
            ("points", [target], None, {"color": "#ff2020", "radius": 5}),
        ],
        bounds,
    )
    fig = compose([[img]], colorbar=Colorbar(GEODESIC_CMAP, *clim, "geodesic distance"))
    err = ""
    if d_exact is not None:
        err = (
            " Against exact distances at every vertex (window propagation on the intrinsic mesh, equal to "
            "igl.exact_geodesic on a real 3D covering to round-off): mean "
            f"error {rec['heat_error']['mean']:.2%} (standard) and {rec['heat_accurate_error']['mean']:.2%} "
            "(accurate preset) of the largest distance."
            + (
                f" The path is {rec['path_length_over_exact']:.4f} times the exact distance."
                if "path_length_over_exact" in rec
                else ""
            )
        )
    if not m.is_impossible():  # what the summary's footnote says for such a model
        from .report import NO_SEAM_NOTE

        err += f" The cut and bent models: {NO_SEAM_NOTE}."
    job.figure(
        fig,
        f"{s.name}_geodesic.png",
        "Geodesic distance and shortest path",
        f"Heat-method distance (Crane et al.; paper Sec. 4.3) from vertex {source} (white dot; one source "
        f"per connected component), accurate preset, with {st.isolines} isolines, and the shortest path "
        "(red) to the farthest vertex, traced down the distance's gradient and pulled taut; length "
        f"{path.length:.4g}. The path is solid where it lies on the visible surface and dashed where it "
        f"passes behind another sheet; the dots are drawn only where they are visible.{err}",
    )


def smoothing(job: ModelJob, s: Subject) -> None:
    """Smoothing of xy, of the exact part of zeta and of both (the paper's Heart figure).

    Depth is smoothed ``ZETA_TIME_FACTOR`` times longer than xy: at equal times the exact part
    of a box model's zeta barely moves (mean dL 0.002-0.025 against the unsmoothed panel), and
    the rows would look alike.  ``m.smooth(t, 10 t)`` gives the bottom row; the top and middle
    rows take its xy / its zeta (one backward Euler step acts on xy and on the exact part of
    zeta independently).  Under each panel: dL, the mean luminance change from the first
    column on the figure's pixels.
    """
    st, m = job.st, s.m
    p0 = np.asarray(m.periods())
    bounds = s.bounds(st.cell)
    rows: list[list[np.ndarray]] = [[], [], []]
    notes: list[list[str]] = [[], [], []]
    change_dl: dict = {"xy": [], "zeta": [], "both": []}
    drift = {"xy": 0.0, "zeta": 0.0, "both": 0.0}
    for factor in st.smooth_times:
        t = factor * s.scale * s.scale
        both = m.smooth(t_xy=t, t_zeta=ZETA_TIME_FACTOR * t)
        versions = {"xy": m.with_xy(both.xy), "zeta": m.with_zeta(both.zeta), "both": both}
        followed = None  # the rows "xy" and "both" share their screen positions, so their order
        for i, (row, ms) in enumerate(versions.items()):
            change = np.abs(loop_periods(m, ms.zeta) - p0).max(initial=0.0)
            drift[row] = max(drift[row], float(change))
            # moved xy: overlaps appear and vanish, so the order follows sheet by sheet (else
            # back faces, and specks where the smoothed bars slide over each other at a crossing)
            moved = row != "zeta" and factor > 0 and s.order is not None
            if moved and followed is None:
                followed = follow_sheets(s.order, ms)
            # where the surface turns edge-on, back faces go behind the front faces
            order = hide_back_faces(ms, followed) if moved else s.order
            img = job.renderer.shoot([("mescher", ms, order, {"shading": "smooth"})], bounds)
            rows[i].append(img)
            first = rows[i][0].astype(np.float64)
            figure = np.any(first < 255, axis=-1) | np.any(img < 255, axis=-1)
            dl = float(np.abs(img.astype(np.float64) - first).mean(axis=-1)[figure].mean() / 255)
            change_dl[row].append(dl)
            notes[i].append(f"dL {dl:.3f}")
    job.record["smoothing"] = {
        "t": [f * s.scale * s.scale for f in st.smooth_times],
        "t_zeta_factor": ZETA_TIME_FACTOR,
        "period_drift": drift,
        "luminance_change": change_dl,
    }
    cols = [f"t = {f:g} s^2" for f in st.smooth_times]
    fig = compose(
        rows, cols, ["smooth xy (t)", f"smooth zeta ({ZETA_TIME_FACTOR:g} t)", "smooth both"], notes
    )
    job.figure(
        fig,
        f"{s.name}_smoothing.png",
        "Smoothing (the paper's Heart figure)",
        "Laplacian smoothing (M - tL) u = M u0 of the screen positions xy for time t (top), of the exact "
        f"part z of zeta with omega kept for time {ZETA_TIME_FACTOR:g} t (middle; paper Eq. 6), and of "
        "both (bottom), for growing t (s: diagonal of the xy box; same camera in every panel). Under each "
        "panel, dL: the mean luminance change from the first column (0 = none, 1 = black to white). "
        "The harmonic part is in the kernel of the smoothing, so the periods do not move: largest "
        f"change {max(drift.values()):.1e}.",
    )


def relighting(job: ModelJob, s: Subject) -> None:
    """The mescher and its bent embedding relit like the cut 3D model, light by light."""
    from pyvista_views.compare import image_agreement

    if s.reference is None:
        job.record["relighting"] = {"skipped": "no cut 3D model to compare with"}
        return
    bounds = s.bounds(job.st.cell)
    Vcut, Fcut = s.reference
    r = job.renderer
    ref = r.relit([("mesh", Vcut, Fcut, {"shading": "flat"})], bounds, LIGHTS)
    mes = r.relit([_mescher(s, shading="flat")], bounds, LIGHTS)
    Vb, Fb = s.m.bent_embedding()
    bent = r.relit([("mesh", Vb, Fb, {"shading": "flat"})], bounds, LIGHTS)
    rec, notes = {}, []
    for key, imgs in (("mescher", mes), ("bent", bent)):
        agree = [image_agreement(a, b) for a, b in zip(imgs, ref)]
        rec[key] = {k: [g[k] for g in agree] for k in agree[0]}
        notes.append([f"IoU {g['iou']:.3f}  dL {g['luminance_mae']:.3f}" for g in agree])
    job.record["relighting"] = rec
    cols = [f"light {i + 1}" for i in range(len(LIGHTS))]
    fig = compose(
        [ref, mes, bent], cols, ["cut model", "mescher", "bent"], [[""] * len(LIGHTS), *notes]
    )
    worst_m, worst_b = max(rec["mescher"]["luminance_mae"]), max(rec["bent"]["luminance_mae"])
    if s.m.is_impossible():
        claim = (
            f"The mescher's normals are the cut model's (worst dL {worst_m:.3f}); the bent model's are "
            f"not (worst dL {worst_b:.3f}): bending cannot be relit (paper Fig. 10)."
        )
    else:
        claim = (
            f"This figure has no harmonic part (all periods 0), so its bent embedding is the mescher "
            f"itself and both relight like the cut model (worst dL {worst_m:.3f} and {worst_b:.3f}); "
            "it is impossible through its depth order only."
        )
    job.figure(
        fig,
        f"{s.name}_relight.png",
        "Relighting: mescher vs cut vs bent",
        f"{s.reference_note[0].upper()}{s.reference_note[1:]} (z-buffered, the reference), the mescher "
        "(painter's order) and the bent embedding (harmonic part dropped) under the four lights, flat "
        "shading. Under each panel: silhouette IoU and dL, the mean luminance difference to the cut model "
        f"on pixels covered by both (luminance from 0 = black to 1 = white). {claim}",
    )


def comparison(job: ModelJob, s: Subject) -> None:
    """Mescher / cut / bent (paper Fig. 10), reusing what the other steps computed."""
    from pyvista_views.compare import compare

    st, m = job.st, s.m
    if not m.is_impossible():
        # no harmonic part: the cut needs no seam and the bent model is the mescher itself
        job.record["comparison"] = {
            "skipped": "no harmonic part: cut and bent embeddings equal the mescher"
        }
        return
    t = st.compare_time * s.scale * s.scale
    t0 = time.perf_counter()
    cut = straight_cut_or_none(m, s.order)
    t_cut = time.perf_counter() - t0
    if cut is None:  # no straight cut alone on screen: the cut along mesh edges
        res = compare(
            m,
            s.order,
            path=None,
            source=s.source,
            t_smooth=t,
            window_size=(st.cell, st.cell),
            solver=s.solver("standard"),
            smoothed=s.smoothed(t),
        )
        seam = "cut along mesh edges where integration disagrees"
    else:
        # the mescher with the faces under the cut line split (same picture, same periods): its
        # cut model has a straight seam, as an artist cuts a bar; the first vertices are m's
        order = None if s.order is None else s.order.follow(cut.mescher, cut.face_parent)
        res = compare(
            cut.mescher,
            order,
            path=None,
            source=s.source,
            t_smooth=t,
            window_size=(st.cell, st.cell),
            cut_edges=cut.cut_edges,
        )
        seam = "cut along one straight screen line across a bar, where nothing else is drawn"
    n = m.n_vertices  # m's vertices come first in the split mescher
    rec: dict = {
        "t_smooth": t,
        "numbers": res.numbers,
        "seam": seam,
        "timings_s": {"seam_search": t_cut},
    }
    vmap = res.vmap
    if s.exact is not None:
        # the cut model at its best: every copy of the source is a source, and a mescher
        # vertex gets the distance of its nearest copy (compare() reads the first copy)
        d_cut = np.full(int(vmap.max()) + 1, np.inf)
        np.minimum.at(d_cut, vmap, res.solvers["cut"].distance(np.flatnonzero(vmap == s.source)))
        dist = {
            "mescher": res.distances["mescher"][:n],
            "cut": d_cut[:n],
            "bent": res.distances["bent"][:n],
        }
        rec["geodesic_error_vs_exact"] = {k: distance_error(v, s.exact) for k, v in dist.items()}
    rec["seam_gap_after_smoothing"] = {
        "cut": seam_gap(res.smoothed["cut"].xy, vmap) / s.scale,
        "mescher": 0.0,
        "bent": 0.0,
    }
    mm = m if cut is None else cut.mescher  # the mescher compare() ran on
    rec["max_period_after_smoothing"] = {
        "before": float(np.abs(mm.periods()).max(initial=0.0)),
        "mescher": float(np.abs(loop_periods(mm, res.smoothed["mescher"].zeta)).max(initial=0.0)),
        "bent": 0.0,  # its zeta is exact by construction: no period survives
    }
    job.record["comparison"] = rec
    ge = rec.get("geodesic_error_vs_exact")
    geo_txt = ""
    if ge:
        geo_txt = (
            " Geodesic error against exact distances (mean, fraction of the largest "
            f"distance): mescher {ge['mescher']['mean']:.2%}, cut {ge['cut']['mean']:.2%}, bent "
            f"{ge['bent']['mean']:.2%}: paths cannot cross the cut model's seam, and the bent model's "
            "metric is not the object's."
        )
    mp = rec["max_period_after_smoothing"]
    job.figure(
        res.figure(),
        f"{s.name}_compare.png",
        "Mescher vs cut vs bent (paper Fig. 10)",
        f"Rows: the mescher, its cut embedding ({seam}) and its bent embedding; "
        "columns: render, relit, smoothed with the same t (both xy and depth), heat-method geodesic distance "
        "from the same vertex. Numbers: dL, the mean luminance difference (0 = black to 1 = white) to the cut "
        "model (render, relit) or to the smoothed mescher (smoothed), and the mean distance difference to the "
        "mescher's relative to its largest (geodesic). Smoothing the cut model as an ordinary mesh opens a "
        f"crack at the seam of {rec['seam_gap_after_smoothing']['cut']:.2%} of the object's size; the mescher "
        f"has no seam and keeps its period ({format_value(mp['mescher'], mp['before'])} of "
        f"{format_value(mp['before'])}), the bent model has none to keep.{geo_txt}",
    )


def straight_cut_or_none(m: Any, order: Any = None) -> Any:
    """:func:`meschers_igl.embedding.straight_cut` of ``m`` (chosen so its cut model looks like
    ``m`` in ``order``), or None where no single straight cut alone on screen opens every
    period."""
    from meschers_igl import MescherError
    from meschers_igl.embedding import straight_cut

    try:
        return straight_cut(m, order)
    except MescherError:
        return None


#: The steps after subdivision, in order: (record key, progress label, function).
STEPS = (
    ("hodge", "Hodge decomposition", hodge),
    ("render", "render and relight", render),
    ("line_art", "line art", line_art),  # meschers/lineart_step.py
    ("loop_subdivision", "Loop subdivision", loop_subdivision),
    ("heat", "heat diffusion", heat),
    ("geodesic", "geodesic distance", geodesic),
    ("smoothing", "smoothing", smoothing),
    ("relighting", "relighting vs cut", relighting),
    ("comparison", "mescher / cut / bent", comparison),
)


def run_mescher_steps(
    job: ModelJob, name: str, m0: Any, order0: Any, reference: tuple | None, reference_note: str
) -> None:
    """Subdivide, then every step of :data:`STEPS` on the subdivided mescher."""
    job.record["input"] = describe(m0)
    m, order = job.step("subdivide", "subdivide", subdivide, job, m0, order0) or (m0, order0)
    s = Subject(name, m, order, reference, reference_note, coarse=(m0, order0))
    for key, label, fn in STEPS:
        job.step(key, label, fn, job, s)
