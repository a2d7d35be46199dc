"""The study's line-art step: each model's line drawing beside its shaded render.

The drawing is :func:`meschers_igl.lines.line_drawing` of the input mescher in its depth order
(outlines, occlusion lines with their T-junctions, creases), drawn as
:func:`pyvista_views.draw` writes it; the record holds the counts of lines by kind and the
drawing's recall and precision against the painter's picture
(:func:`meschers_igl.lines.line_agreement`, 1.5 pixels at 512).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pyvista_views.camera import default_bounds, xy_box

from .figures import compose

__all__ = ["line_art"]


def line_art(job: Any, s: Any) -> None:
    """Shaded render, line art and the lines over the render, of the input mescher."""
    from meschers_igl.line_pixels import line_agreement
    from meschers_igl.lines import KINDS
    from pyvista_views.lineart import picture

    m0, o0 = s.coarse if s.coarse is not None else (s.m, s.order)
    cell = int(job.st.cell)
    bounds = default_bounds(xy_box(np.asarray(m0.xy)), (cell, cell))
    lines = s.lines()
    shaded = job.renderer.shoot([("mescher", m0, o0, {"shading": "flat"})], bounds)
    art = picture(lines, (cell, cell), bounds=bounds)
    dashed = picture(lines, (cell, cell), bounds=bounds, hidden="dashed")
    ink = art.min(axis=2, keepdims=True).astype(np.float64) / 255.0
    over = np.clip(shaded * ink, 0, 255).astype(np.uint8)
    recall, precision = line_agreement(lines, m0, o0)
    counts = {name: int((lines.visible & (lines.kind == k)).sum()) for k, name in enumerate(KINDS)}
    job.record["line_art"] = {
        "polylines": counts,
        "hidden_polylines": int((~lines.visible).sum()),
        "recall": recall,
        "precision": precision,
    }
    notes = [
        f"{m0.n_faces} faces",
        ", ".join(f"{v} {k}" for k, v in counts.items()),
        f"recall {recall:.3f}, precision {precision:.3f}",
        f"{int((~lines.visible).sum())} hidden",
    ]
    fig = compose(
        [[shaded, art, over, dashed]],
        ["shaded", "line art", "lines over the render", "hidden lines dashed"],
        notes=[notes],
    )
    job.figure(
        fig,
        f"{s.name}_line_art.png",
        "Line art",
        "The drawing a person makes of the figure, from the mescher and its depth order: outlines "
        "against the paper (thick), occlusion lines where one part passes in front of another, "
        "ending exactly where they pass behind a face, and creases where zeta's dihedral angle "
        "exceeds 30 degrees (thin); `meschers draw` writes it as SVG or PDF. Recall and precision: "
        "the line pixels of the painter's picture within 1.5 px of a drawn line, and the drawn "
        "pixels within 1.5 px of one (512 px).",
    )
