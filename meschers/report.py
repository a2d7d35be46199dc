"""``index.html`` of the comparison study: one self-contained page, relative links to its PNGs.

The page has no script and no external resource (styles inline), so it opens from a folder, an
archive or a file server alike: a summary table of the numbers, then one section per model with
its figures and captions, then "Models from other tools", the errors if any, and the citation.
"""

from __future__ import annotations

import html
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["referenced_images", "write_report"]

_STYLE = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 2em auto;
       max-width: 1200px; padding: 0 1em; color: #222; line-height: 1.45; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f3f3f3; } td:first-child, th:first-child { text-align: left; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.92em; color: #444; max-width: 1000px; }
.cite { background: #f7f7f7; border-left: 4px solid #999; padding: 0.6em 1em; }
.err { color: #a00; } code { background: #f3f3f3; padding: 0 0.2em; }
"""


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def _num(x: Any, pct: bool = False, digits: int = 4) -> str:
    if x is None:
        return "&ndash;"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, float)):
        if isinstance(x, float) and not math.isfinite(x):
            return "&ndash;"
        if pct:
            return f"{100 * x:.2f}%"
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


def _gallery_table(models: dict) -> str:
    head = (
        "<tr><th>model</th><th>#V</th><th>#F</th><th>genus</th><th>impossible</th>"
        "<th>non-zero periods</th><th>period drift (subdiv. / smoothing)</th>"
        "<th>relight dL mescher</th><th>relight dL bent</th>"
        "<th>geodesic err. mescher</th><th>cut</th><th>bent</th>"
        "<th>seam crack (cut)</th><th>runtime s</th></tr>"
    )
    rows = []
    for name, r in models.items():
        drift = [_get(r, "subdivision", "period_drift")]
        sm = _get(r, "smoothing", "period_drift")
        drift.append(max(sm.values()) if isinstance(sm, dict) and sm else None)
        ge = _get(r, "comparison", "geodesic_error_vs_exact") or {}
        rows.append(
            _tr(
                (
                    _e(name),
                    _num(_get(r, "input", "vertices")),
                    _num(_get(r, "input", "faces")),
                    _num(_get(r, "input", "genus")),
                    _num(_get(r, "hodge", "impossible")),
                    _periods(_get(r, "hodge", "periods")),
                    " / ".join(_num(d, digits=2) for d in drift),
                    _num(_max(_get(r, "relighting", "mescher", "luminance_mae")), digits=3),
                    _num(_max(_get(r, "relighting", "bent", "luminance_mae")), digits=3),
                    _num(_get(ge, "mescher", "mean"), pct=True),
                    _num(_get(ge, "cut", "mean"), pct=True),
                    _num(_get(ge, "bent", "mean"), pct=True),
                    _num(_get(r, "comparison", "seam_gap_after_smoothing", "cut"), pct=True),
                    _num(r.get("runtime_s"), digits=3),
                )
            )
        )
    return f"<table>{head}{''.join(rows)}</table>"


def _tr(cells) -> str:
    """One table row of already formatted (escaped) cells."""
    return "<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>"


def _tools_table(tools: dict) -> str:
    head = (
        "<tr><th>figure</th><th>#V</th><th>#F</th><th>components</th><th>genus</th><th>&chi;</th>"
        "<th>expected &chi;</th><th>non-zero periods</th><th>tool's depth gaps</th>"
        "<th>min IoU vs cut</th><th>min luminance corr.</th><th>geodesic err.</th></tr>"
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


def _section(sec: Any, record: dict, level: str = "h2") -> str:
    parts = [
        f'<{level} id="{_e(sec.name)}">{_e(sec.title)}</{level}>',
        f"<p>{_e(sec.description)}</p>",
    ]
    for fig in sec.figures:
        if not fig.file:
            continue
        parts.append(
            f'<figure><img src="{_e(fig.file)}" alt="{_e(sec.title)}: {_e(fig.title)}" loading="lazy">'
            f"<figcaption><b>{_e(fig.title)}.</b> {_e(fig.caption)}</figcaption></figure>"
        )
    for err in record.get("errors", []):
        parts.append(f'<p class="err">Step failed: {_e(err)}</p>')
    return "\n".join(parts)


def write_report(
    out: str | Path, metrics: dict, sections: Sequence[Any], tool_sections: Sequence[Any] = ()
) -> Path:
    """Write ``out/index.html`` for a study.

    Parameters
    ----------
    out : folder holding the study's PNGs
    metrics : dict
        The study's ``metrics.json`` content (``models``, ``other_tools``, ``settings``, ...).
    sections, tool_sections : sequences of :class:`meschers.study.Section`
        Figures per gallery model and per model from other tools; only figures whose PNG exists
        in ``out`` are linked.

    Returns
    -------
    Path of ``index.html``.
    """
    out = Path(out)

    def present(secs: Sequence[Any]) -> list:
        for s in secs:
            s.figures = [f for f in s.figures if f.file and (out / f.file).is_file()]
        return list(secs)

    sections, tool_sections = present(sections), present(tool_sections)
    models, tools = metrics.get("models", {}), metrics.get("other_tools", {})
    st = metrics.get("settings", {})
    toc = " &middot; ".join(f'<a href="#{_e(s.name)}">{_e(s.title)}</a>' for s in sections)
    body = [
        "<h1>Meschers: a comparison study of impossible objects</h1>",
        "<p>Every operation of <i>Meschers: Geometry Processing of Impossible Objects</i> on the built-in "
        "gallery, with the mescher compared to the two earlier representations: the <b>cut</b> model "
        "(a real mesh with a seam where the depth jumps) and the <b>bent</b> model (the harmonic part "
        "of the depth dropped). Generated by <code>meschers study"
        + (" --quick" if st.get("quick") else "")
        + f"</code> in {_num(metrics.get('runtime_s'), digits=3)} s "
        f"({_num(st.get('cell'))}-pixel panels, {_num(st.get('levels'))} subdivision level(s)).</p>",
        f"<p>{toc}</p>",
        "<h2 id='summary'>Summary</h2>",
        "<p><b>dL</b>: worst mean luminance difference (0&ndash;1) to the cut model's z-buffered render over "
        "four lights. <b>Geodesic error</b>: mean |d &minus; d*| / max d*, heat method on each "
        "representation against exact distances d* on a real 3D covering of the mescher. <b>Seam "
        "crack</b>: widest screen gap between copies of one vertex after smoothing the cut model as a "
        "mesh, as a fraction of the object's size. <b>Period drift</b>: largest change of a period under "
        "subdivision / smoothing (zero up to round-off: both keep the harmonic part).</p>",
        _gallery_table(models),
    ]
    for sec in sections:
        body.append(_section(sec, models.get(sec.name, {})))
    if tool_sections:
        body.append("<h2 id='other-tools'>Models from other tools</h2>")
        body.append(
            "<p>Cut models of six classic figures made by the Blender add-on ParadoxToolkit "
            "(github.com/matgarate/Blender_ParadoxToolkit, GPL-3.0), glued into meschers from their view "
            "and up vectors alone (<code>meshlab_filters.cut_model_to_mescher</code>). The tori carry a "
            "period equal to the tool's depth gap; the stairs and block triangle are closed boxes, "
            "impossible through their depth order only.</p>"
        )
        body.append(_tools_table(tools))
        for sec in tool_sections:
            body.append(_section(sec, tools.get(sec.name, {}), level="h3"))
    elif metrics.get("other_tools_note"):
        body.append(f"<h2>Models from other tools</h2><p>{_e(metrics['other_tools_note'])}</p>")
    if metrics.get("errors"):
        items = "".join(f"<li>{_e(e)}</li>" for e in metrics["errors"])
        body.append(f"<h2>Errors</h2><ul class='err'>{items}</ul>")
    body.append(
        "<h2 id='citation'>Citation</h2>"
        f"<p class='cite'>{_e(metrics.get('citation', ''))} "
        f'<a href="{_e(metrics.get("doi", ""))}">{_e(metrics.get("doi", ""))}</a></p>'
        "<p>All numbers are in <a href='metrics.json'>metrics.json</a>.</p>"
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
    """The ``src`` of every ``<img>`` in an HTML file (for checking that they all exist)."""
    text = Path(index).read_text(encoding="utf-8")
    return [html.unescape(s) for s in re.findall(r"<img[^>]*\bsrc=\"([^\"]+)\"", text)]
