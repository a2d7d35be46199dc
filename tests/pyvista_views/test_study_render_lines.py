"""The study's render figure shows every step of the stairs, as the gallery figure does: the flat
row carries the line drawing, so the treads of neighbouring steps (same shade, risers facing
away) are told apart by a line.

Measured as in ``test_gallery_lines.py``: on the study's own panels, the pixels where the visible
surface passes from one tread to a parallel one a few risers away (the CPU painter's
visible-face map of the input figure) must be dark.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_gallery_lines import dark_share, step_edge_pixels

from meschers_igl.gallery import get_model
from meschers_igl.painter import visible_faces

pytest.importorskip("cairosvg")


def _render_rows(monkeypatch, g):
    """The panels of the study's render step (flat row, smooth row) on ``g``, as composed."""
    import meschers.steps as steps
    from meschers.job import ModelJob, Section
    from meschers.settings import study_settings

    job = ModelJob("models", "stairs", Section("stairs", "stairs", ""), study_settings(True))
    m, order = steps.subdivide(job, g.mescher, g.order)
    s = steps.Subject("stairs", m, order, coarse=(g.mescher, g.order))
    seen = []

    def keep(rows, *args, **kw):
        seen.append([[np.asarray(p) for p in row] for row in rows])
        return np.zeros((4, 4, 3), np.uint8)

    monkeypatch.setattr(steps, "compose", keep)
    steps.render(job, s)
    job.renderer.close()
    return seen[0], s.bounds(job.st.cell), job


def test_every_step_of_the_study_stairs_is_drawn(monkeypatch):
    g = get_model("penrose_stairs")
    (flat, smooth), bounds, job = _render_rows(monkeypatch, g)
    cell = job.st.cell
    assert flat[0].shape[:2] == (cell, cell)
    face_map = visible_faces(g.mescher, g.order, size=cell, bounds=bounds)
    steps = step_edge_pixels(g, face_map)
    assert steps.sum() > 50  # the treads of neighbouring steps meet along many pixels
    # under the first light the shading alone hides most steps (the smooth row is plain)
    assert dark_share(smooth[0], steps) < 0.3
    shares = [dark_share(panel, steps) for panel in flat]
    assert min(shares) > 0.95, shares
    assert job.record["render"]["flat_row"] == "line drawing over the flat row"


def test_lines_over_refuses_renders_of_different_sizes():
    from meschers.figures import lines_over
    from meschers_igl.errors import MescherError
    from meschers_igl.lines import line_drawing

    g = get_model("penrose_stairs")
    lines = line_drawing(g.mescher, g.order)
    b = (-1.0, 1.0, -1.0, 1.0)
    with pytest.raises(MescherError, match="images: expected renders of one size"):
        lines_over([np.zeros((8, 8, 3), np.uint8), np.zeros((8, 9, 3), np.uint8)], lines, b)
    blank = np.full((16, 16, 3), 255, np.uint8)
    # lines outside the frame leave the image as it was
    far = (100.0, 101.0, 100.0, 101.0)
    np.testing.assert_array_equal(lines_over([blank], lines, far)[0], blank)


def test_render_and_line_art_draw_one_drawing_whose_visible_part_is_the_plain_one(monkeypatch):
    """The render step's lines and the line-art step come from one ``line_drawing`` call (the
    hidden parts included), and its visible lines are exactly the drawing without them."""
    import meschers.lineart_step as lineart_step
    import meschers_igl.lines as lines_mod

    g = get_model("penrose_stairs")
    calls = []
    real = lines_mod.line_drawing

    def counted(*args, **kw):
        calls.append(kw.get("hidden", False))
        return real(*args, **kw)

    monkeypatch.setattr(lines_mod, "line_drawing", counted)
    (flat, _), _, job = _render_rows(monkeypatch, g)
    assert calls == [True]
    import meschers.steps as steps
    from meschers.job import ModelJob, Section

    job = ModelJob("models", "stairs", Section("stairs", "stairs", ""), job.st)
    s = steps.Subject("stairs", g.mescher, g.order)
    lineart_step.line_art(job, s)
    steps._flat_lines(s, [np.zeros((8, 8, 3), np.uint8)], (-1.0, 1.0, -1.0, 1.0))
    job.renderer.close()
    assert calls == [True, True]  # one more subject, one more drawing; both steps share it
    plain, full = real(g.mescher, g.order), s.lines()
    got, want = full.polylines(visible=True), plain.polylines()
    assert len(got) == len(want) > 0 and not full.visible.all()
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)
