"""``index.html`` of the comparison study: one self-contained file.

The figures are embedded as ``data:image/png;base64`` URIs and the styles are inline; the page
has no script and no external resource, so the one file opens anywhere (mail it, archive it).
The PNGs are also written beside it for reuse.  Content: a summary table per part of the report
(:data:`meschers.study.GROUPS`), one section per model with its figures and captions, the errors
if any, and the citation.  Every HTML id is unique: ``<part>-<model>``.

**dL**, everywhere in the study (figures, tables, ``metrics.json``): the mean absolute difference
of Rec. 709 luminance between two renders, luminance on the scale 0 = black to 1 = white
(:func:`pyvista_views.compare.luminance`).
"""

from __future__ import annotations

import base64
import html
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = [
    "DL_NOTE",
    "NO_SEAM_NOTE",
    "TABLES",
    "embedded_images",
    "referenced_images",
    "write_report",
]

#: The one explanation of dL, used by the page (the figures' captions say the same).
DL_NOTE = (
    "<b>dL</b>: mean absolute difference of luminance between two renders with one camera, "
    "luminance from 0 (black) to 1 (white) (Rec. 709; <code>pyvista_views.compare.luminance</code>)"
)

#: Why a model without a harmonic part has no mescher / cut / bent comparison (the summary's
#: footnote and its geodesic section's caption say the same).
NO_SEAM_NOTE = (
    "no harmonic part (not impossible, or impossible through its depth order only): its cut "
    "model needs no seam and its bent model is the mescher itself, so both have the mescher's "
    "geodesic error and no seam to crack; the study draws no mescher / cut / bent comparison "
    "for it"
)

_STYLE = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 2em auto;
       max-width: 1200px; padding: 0 1em; color: #222; line-height: 1.45; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.85em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.45em; text-align: right; }
th { background: #f3f3f3; } td:first-child, th:first-child { text-align: left; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.92em; color: #444; max-width: 1000px; }
.cite { background: #f7f7f7; border-left: 4px solid #999; padding: 0.6em 1em; }
.err { color: #a00; } code { background: #f3f3f3; padding: 0 0.2em; }
"""


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def _num(x: Any, pct: bool = False, digits: int = 4, fixed: int | None = None) -> str:
    """A table cell: ``digits`` significant digits, or ``fixed`` decimals (for measures whose
    resolution is known: a luminance dL of 3.7e-05 is 0 at 8 bits per channel)."""
    if x is None:
        return "&ndash;"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, float)):
        if isinstance(x, float) and not math.isfinite(x):
            return "&ndash;"
        if pct:
            return f"{100 * x:.2f}%"
        if fixed is not None:
            return f"{x:.{fixed}f}"
        return f"{x:.{digits}g}" if isinstance(x, float) else str(x)
    return _e(x)


def _get(d: dict, *keys: Any) -> Any:
    for k in keys:
        if isinstance(d, dict) and k in d:
            d = d[k]
        elif isinstance(d, list) and isinstance(k, int) and -len(d) <= k < len(d):
            d = d[k]
        else:
            return None
    return d


def _max(values: Any) -> Any:
    return max(values) if isinstance(values, list) and values else None


def _periods(values: Any, tol: float = 1e-9) -> str:
    if not isinstance(values, list):
        return "&ndash;"
    nz = [v for v in values if abs(v) > tol * max(1.0, max(abs(u) for u in values))]
    return ", ".join(f"{v:.4g}" for v in nz) if nz else "0"


def _drift(x: Any, scale: float) -> str:
    """A period change: 0 when below 1e-9 of the periods' scale (round-off)."""
    if not isinstance(x, (int, float)) or not math.isfinite(x):
        return "&ndash;"
    return "0" if abs(x) < 1e-9 * scale else f"{x:.2g}"


def _gallery_table(models: dict) -> str:
    head = (
        "<tr><th>model</th><th>#V</th><th>#F</th><th>genus</th><th>impossible</th>"
        "<th>non-zero periods</th><th>period drift (subdiv. / smoothing)</th>"
        "<th>relight dL mescher</th><th>relight dL bent</th>"
        "<th>geodesic err. mescher</th><th>cut</th><th>bent</th>"
        "<th>seam crack (cut)</th><th>runtime s</th></tr>"
    )
    rows = []
    no_seam = False
    for name, r in models.items():
        drift = [_get(r, "subdivision", "period_drift")]
        sm = _get(r, "smoothing", "period_drift")
        drift.append(max(sm.values()) if isinstance(sm, dict) and sm else None)
        periods = _get(r, "hodge", "periods") or _get(r, "input", "periods") or []
        scale = max([abs(p) for p in periods] + [1.0])
        ge = _get(r, "comparison", "geodesic_error_vs_exact") or {}
        mescher_err = _get(ge, "mescher", "mean")
        same = _get(r, "comparison", "skipped") is not None  # no seam: cut = bent = mescher
        if same:
            mescher_err = _get(r, "geodesic", "heat_error", "mean")  # its geodesic section's
            no_seam = True
        rows.append(
            _tr(
                (
                    _e(name),
                    _num(_get(r, "input", "vertices")),
                    _num(_get(r, "input", "faces")),
                    _num(_get(r, "input", "genus")),
                    _impossible_cell(r),
                    _periods(_get(r, "hodge", "periods")),
                    " / ".join(_drift(d, scale) for d in drift),
                    _num(_max(_get(r, "relighting", "mescher", "luminance_mae")), fixed=3),
                    _num(_max(_get(r, "relighting", "bent", "luminance_mae")), fixed=3),
                    _num(mescher_err, pct=True),
                    *(
                        (_SAME, _SAME, _NO_SEAM)
                        if same
                        else (
                            _num(_get(ge, "cut", "mean"), pct=True),
                            _num(_get(ge, "bent", "mean"), pct=True),
                            _num(
                                _get(r, "comparison", "seam_gap_after_smoothing", "cut"), pct=True
                            ),
                        )
                    ),
                    _num(r.get("runtime_s"), digits=3),
                )
            )
        )
    note = f"<p><sup>*</sup> {_e(NO_SEAM_NOTE)}.</p>" if no_seam else ""
    return f"<table>{head}{''.join(rows)}</table>{note}"


_SAME = "= mescher<sup>*</sup>"
_NO_SEAM = "no seam<sup>*</sup>"


def _impossible_cell(r: dict) -> str:
    """ "yes (zeta)" / "yes (order)" / "no": impossible through its periods or its order."""
    if not _get(r, "hodge", "impossible"):
        return "no" if _get(r, "hodge", "impossible") is False else "&ndash;"
    kind = _get(r, "hodge", "impossible_kind")
    return f"yes ({_e(kind)})" if kind else "yes"


def _tr(cells) -> str:
    """One table row of already formatted (escaped) cells."""
    return "<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>"


def _tools_table(tools: dict, gaps: str = "tool's depth gaps", reference: str = "cut") -> str:
    head = (
        "<tr><th>figure</th><th>#V</th><th>#F</th><th>components</th><th>genus</th><th>&chi;</th>"
        f"<th>expected &chi;</th><th>non-zero periods</th><th>{gaps}</th>"
        f"<th>min IoU vs {reference}</th><th>min luminance corr.</th><th>geodesic err.</th></tr>"
    )
    rows = []
    for name, r in tools.items():
        gaps = _get(r, "expected", "depth_gaps")
        rows.append(
            _tr(
                (
                    _e(name),
                    _num(_get(r, "input", "vertices")),
                    _num(_get(r, "input", "faces")),
                    _num(_get(r, "input", "components")),
                    _num(_get(r, "input", "genus")),
                    _num(_get(r, "input", "euler_characteristic")),
                    _num(_get(r, "expected", "glued_chi")),
                    _periods(r.get("periods")),
                    _e(", ".join(f"{g:.4g}" for g in gaps))
                    if isinstance(gaps, list)
                    else "&ndash;",
                    _num(min(_get(r, "relighting", "iou") or [math.nan]), digits=4),
                    _num(min(_get(r, "relighting", "luminance_corr") or [math.nan]), digits=4),
                    _num(_get(r, "geodesic", "heat_accurate_error", "mean"), pct=True),
                )
            )
        )
    return f"<table>{head}{''.join(rows)}</table>"


def _anchor(group: str, name: str) -> str:
    """A unique HTML id: the report part and the model (ids are unique within a part)."""
    return re.sub(r"[^A-Za-z0-9_-]", "-", f"{group}-{name}")


def _data_uri(data: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _section(result: Any, level: str = "h2") -> str:
    sec, record = result.section, result.record
    parts = [
        f'<{level} id="{_e(_anchor(result.group, sec.name))}">{_e(sec.title)}</{level}>',
        f"<p>{_e(sec.description)}</p>",
    ]
    for fig in sec.figures:
        if not fig.data:
            continue
        parts.append(
            f'<figure><img src="{_data_uri(fig.data)}" alt="{_e(sec.title)}: {_e(fig.title)}" '
            f'title="{_e(fig.file)}"><figcaption><b>{_e(fig.title)}.</b> {_e(fig.caption)}'
            "</figcaption></figure>"
        )
    for err in record.get("errors", []):
        parts.append(f'<p class="err">Step failed: {_e(err)}</p>')
    return "\n".join(parts)


#: Summary table of each report part (:data:`meschers.study.GROUPS`): key -> function(records).
TABLES = {
    "models": _gallery_table,
    "other_tools": _tools_table,
    "artist_models": lambda records: _tools_table(records, "model's depth gaps", "3D model"),
}


def write_report(
    out: str | Path, metrics: dict, results: Sequence[Any], groups: Sequence[Any]
) -> Path:
    """Write ``out/index.html`` for a study.

    Parameters
    ----------
    out : folder of the study
    metrics : dict
        The study's ``metrics.json`` content (``settings``, ``runtime_s``, a dict of records
        per part, ...).
    results : sequence of :class:`meschers.job.ModelResult`
        Figures (with their PNG bytes) and records per model, in report order.
    groups : sequence of :class:`meschers.study.Group`
        The parts of the report, in order; a part without results is left out.

    Returns
    -------
    Path of ``index.html``.
    """
    out = Path(out)
    st = metrics.get("settings", {})
    by_group = {g.key: [r for r in results if r.group == g.key] for g in groups}
    toc = "<br>".join(
        f"<b>{_e(g.title)}</b>: "
        + " &middot; ".join(
            f'<a href="#{_e(_anchor(r.group, r.section.name))}">{_e(r.section.title)}</a>'
            for r in by_group[g.key]
        )
        for g in groups
        if by_group[g.key]
    )
    body = [
        "<h1>Meschers: a comparison study of impossible objects</h1>",
        "<p>Every operation of <i>Meschers: Geometry Processing of Impossible Objects</i> on each "
        "model, with the mescher compared to the two earlier representations: the <b>cut</b> model "
        "(a real mesh with a seam where the depth jumps) and the <b>bent</b> model (the harmonic part "
        "of the depth dropped). Generated by <code>meschers study"
        + (" --quick" if st.get("quick") else "")
        + f"</code> in {_num(metrics.get('runtime_s'), digits=3)} s "
        f"({_num(st.get('cell'))}-pixel panels, up to {_num(st.get('levels'))} midpoint subdivision "
        f"level(s) while a model stays under {_num(st.get('max_faces'))} faces). "
        "This page is one file: its figures are embedded.</p>",
        f"<p>{toc}</p>",
        "<h2 id='summary'>Summary</h2>",
        f"<p>{DL_NOTE}. <b>relight dL</b>: the worst, over four lights, of the dL to the cut "
        "model's z-buffered render on the pixels both cover. <b>Geodesic error</b>: mean |d &minus; d*| / "
        "max d*, heat method on each representation against exact distances d* of the mescher "
        "(window propagation on its intrinsic mesh; equal to igl.exact_geodesic on a real 3D "
        "covering, tested). <b>Seam crack</b>: widest screen gap between copies of one vertex after "
        "smoothing the cut model as a mesh, as a fraction of the object's size. <b>Period drift</b>: "
        "largest change of a period under subdivision / smoothing (zero up to round-off: both keep the "
        "harmonic part). Values below 1e-9 of their scale are round-off and printed as 0.</p>",
    ]
    for g in groups:
        results_g = by_group[g.key]
        if not results_g:
            continue
        level = "h2" if g.key == "models" else "h3"
        if g.key != "models":
            body.append(f"<h2 id='{_e(g.key)}'>{_e(g.title)}</h2>")
            if g.intro:
                body.append(f"<p>{g.intro}</p>")
        table = TABLES.get(g.key)
        if table is not None:
            body.append(table({r.section.name: r.record for r in results_g}))
        for r in results_g:
            body.append(_section(r, level=level))
    if metrics.get("errors"):
        items = "".join(f"<li>{_e(e)}</li>" for e in metrics["errors"])
        body.append(f"<h2 id='errors'>Errors</h2><ul class='err'>{items}</ul>")
    body.append(
        "<h2 id='citation'>Citation</h2>"
        f"<p class='cite'>{_e(metrics.get('citation', ''))} "
        f'<a href="{_e(metrics.get("doi", ""))}">{_e(metrics.get("doi", ""))}</a></p>'
        "<p>All numbers are in <code>metrics.json</code> beside this page.</p>"
    )
    page = (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<title>Meschers study</title><style>{_STYLE}</style></head><body>\n"
        + "\n".join(body)
        + "\n</body></html>\n"
    )
    path = out / "index.html"
    path.write_text(page, encoding="utf-8")
    return path


def referenced_images(index: str | Path) -> list[str]:
    """The ``src`` of every ``<img>`` in an HTML file (``data:`` URIs in a study's page)."""
    text = Path(index).read_text(encoding="utf-8")
    return [html.unescape(s) for s in re.findall(r"<img[^>]*\bsrc=\"([^\"]+)\"", text)]


def embedded_images(index: str | Path) -> list[bytes]:
    """The PNG bytes of every image embedded as a ``data:image/png;base64`` URI."""
    prefix = "data:image/png;base64,"
    return [
        base64.b64decode(s[len(prefix) :]) for s in referenced_images(index) if s.startswith(prefix)
    ]
