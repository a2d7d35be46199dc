"""The study's steps on an artist's cut model seen from its view ("Models from other tools").

A cut model made by another tool (the ParadoxToolkit files shipped in
``meschers_igl/data/paradox``, or any mesh with a sidecar JSON view) is cleaned with PyMeshLab and
glued into a mescher from its view and up vectors alone; then the mescher is relit against the
tool's own model and its periods are compared with the tool's depth gaps.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pyvista_views.camera import default_bounds, xy_box

from .describe import describe
from .figures import compose, format_values, round_off_scale
from .inputs import ModelSpec, load_artist, load_solid
from .job import ModelJob
from .metrics import distance_error, exact_distance, one_source_per_component
from .settings import ENV_MAP, GEODESIC_CMAP, LIGHTS

__all__ = [
    "convert",
    "convert_solid",
    "periods_and_geodesic",
    "relight",
    "run_solid_steps",
    "run_tool_steps",
]


def convert(job: ModelJob, spec: ModelSpec) -> tuple:
    """Load, clean and glue the cut model; record its topology and the tool's own checks."""
    m, order, Vcam, F, report = load_artist(spec)
    verification = spec.meta.get("verification", {}) if isinstance(spec.meta, dict) else {}
    job.record["input"] = describe(m)
    job.record["cleanup"] = report.as_dict()
    job.record["expected"] = {
        "depth_gaps": verification.get("depth_gaps"),
        "glued_chi": verification.get("glued_chi"),
    }
    return m, order, Vcam, F


def convert_solid(job: ModelJob, spec: ModelSpec) -> tuple:
    """See the 3D model from its view (``Mescher.from_model``); record the conversion report."""
    m, order, Vcam, F, report = load_solid(spec)
    job.record["input"] = describe(m)
    job.record["conversion"] = {
        "junctions": [
            {"position": [float(v) for v in j.position], "depth_gap": float(j.depth_gap)}
            for j in report.junctions
        ],
        "report": str(report),
    }
    gap = spec.meta.get("depth_gap") if isinstance(spec.meta, dict) else None
    verdict = m.is_impossible(order=order)
    job.record["impossible_kind"] = verdict.kind
    job.record["expected"] = {"depth_gaps": None if gap is None else [float(gap)]}
    return m, order, Vcam, F


def run_solid_steps(job: ModelJob, spec: ModelSpec) -> None:
    """Convert (model seen from its view), relight against its z-buffer, periods and geodesic."""
    got = job.step("convert", "convert", convert_solid, job, spec)
    if got is None:
        return
    m, order, Vcam, F = got
    job.step("relight", "relight", relight, job, spec.name, m, order, Vcam, F, "the model")
    job.step(
        "periods_geodesic",
        "periods and geodesic",
        periods_and_geodesic,
        job,
        spec.name,
        m,
        order,
        "the model's depth gaps",
    )


def relight(
    job: ModelJob,
    name: str,
    m: Any,
    order: Any,
    Vcam: np.ndarray,
    F: np.ndarray,
    reference: str = "tool's cut",
) -> None:
    """The glued mescher and the tool's cut model under the four lights (and the env map)."""
    from pyvista_views.compare import image_agreement

    bounds = default_bounds(xy_box(np.asarray(m.xy)), (job.st.cell, job.st.cell))
    r = job.renderer
    mes = r.relit([("mescher", m, order, {"shading": "flat"})], bounds, LIGHTS, ENV_MAP)
    ref = r.relit([("mesh", Vcam, F, {"shading": "flat"})], bounds, LIGHTS)
    agree = [image_agreement(a, b) for a, b in zip(mes, ref)]
    job.record["relighting"] = {k: [g[k] for g in agree] for k in agree[0]}
    notes = [
        [f"IoU {g['iou']:.3f}  corr {g['luminance_corr']:.3f}" for g in agree] + [""],
        [""] * len(ref),
    ]
    cols = [f"light {i + 1}" for i in range(len(LIGHTS))] + [f"env map '{ENV_MAP}'"]
    fig = compose([mes, ref], cols, ["mescher", reference], notes)
    top = (
        "the mescher glued from the tool's cut model (only its view and up vectors given)"
        if reference == "tool's cut"
        else "the mescher of what the viewer sees (Mescher.from_model, from the model's view)"
    )
    bottom = "the cut model" if reference == "tool's cut" else "the 3D model"
    job.figure(
        fig,
        f"tool_{name}_relight.png",
        "Render and relight",
        f"Top: {top}, drawn in its depth order under four lights and an environment map. Bottom: "
        f"{bottom} itself, z-buffered with the same camera. Numbers: silhouette IoU and the correlation of "
        "the two luminances (0 = black to 1 = white) on pixels covered by both; a model read with "
        "perceived right angles shades as perceived, not as built.",
    )


def periods_and_geodesic(
    job: ModelJob, name: str, m: Any, order: Any, gaps_of: str = "the tool's depth gaps"
) -> None:
    """Periods against the expected depth gaps (``gaps_of`` names them in the caption); heat
    distance after one subdivision."""
    st = job.st
    periods = np.asarray(m.periods())
    job.record["periods"] = periods.tolist()
    job.record["impossible"] = bool(m.is_impossible())
    ms, order1 = m.subdivide(1, order=order)
    source = one_source_per_component(ms)
    d = ms.geodesic_distance(source, method="accurate")
    d_exact, how = exact_distance(ms, source)
    rec = {"sources": source.tolist(), "subdivision_levels": 1, "exact": how}
    if d_exact is not None:
        rec["heat_accurate_error"] = distance_error(d, d_exact)
    job.record["geodesic"] = rec
    bounds = default_bounds(xy_box(np.asarray(m.xy)), (st.cell, st.cell))
    kw = {"shading": "smooth", "scalars": d, "cmap": GEODESIC_CMAP, "isolines": st.isolines}
    dots = ("points", source, None, {"color": "white", "radius": 5})
    img = job.renderer.shoot([("mescher", ms, order1, kw), dots], bounds)
    from meschers_igl.geodesic import shortest_loops

    # closed geodesics around the loops with a period, drawn where they are visible
    loops = [
        ("path", loop, None, {"color": "#d62728", "width": 3, "label": format_values([periods[k]])})
        for k, loop in enumerate(shortest_loops(m))
        if abs(periods[k]) > 1e-9 * m.scale()
    ]
    flat = job.renderer.shoot([("mescher", m, order, {"shading": "flat"}), *loops], bounds)
    fig = compose([[flat, img]], ["non-zero periods", "geodesic distance"])
    gaps = job.record.get("expected", {}).get("depth_gaps")
    gaps_txt = format_values(gaps) if isinstance(gaps, list) else "not given"
    err = (
        f" Mean error against exact distances: {rec['heat_accurate_error']['mean']:.2%}."
        if "heat_accurate_error" in rec
        else ""
    )
    job.figure(
        fig,
        f"tool_{name}_periods.png",
        "Periods and geodesic distance",
        f"Left: homology loops with a non-zero period ({gaps_of}: {gaps_txt}); periods found "
        f"{format_values(periods, scale=round_off_scale(periods, m.scale()))}. Right: heat-method distance (accurate preset) from the white dots (one "
        f"per connected component) after one midpoint subdivision, with {st.isolines} isolines.{err}",
    )


def run_tool_steps(job: ModelJob, spec: ModelSpec) -> None:
    """Convert, relight, periods and geodesic; a failed conversion skips the rest."""
    got = job.step("convert", "convert", convert, job, spec)
    if got is None:
        return
    m, order, Vcam, F = got
    job.step("relight", "relight", relight, job, spec.name, m, order, Vcam, F)
    job.step(
        "periods_geodesic", "periods and geodesic", periods_and_geodesic, job, spec.name, m, order
    )
