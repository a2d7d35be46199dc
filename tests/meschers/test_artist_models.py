"""The study's section "Models as artists make them" (issue 18): shipped closed solids seen from
their view come out impossible with their depth gap as period and render like their z-buffer."""

from __future__ import annotations

import json

import numpy as np
import pytest

from meschers.inputs import expand_models, list_solids
from meschers.study import default_models, run_study
from pyvista_views.headless import gl_available

requires_gl = pytest.mark.skipif(not gl_available(), reason="no offscreen OpenGL context")


def test_shipped_solids_are_named_and_in_the_default_study():
    assert list_solids() == [
        "block_stairs",
        "hidden_gap_cube",
        "hidden_gap_frame",
        "reutersvard_relief",
        "sheared_tribar_torus",
        "u_tribar",
    ]
    specs = expand_models(["solid:u_tribar"])
    assert [s.kind for s in specs] == ["solid"]
    assert {s.name for s in default_models() if s.kind == "solid"} == set(list_solids())


@requires_gl
@pytest.mark.slow
def test_study_section_for_closed_solids(tmp_path):
    res = run_study(
        ["solid:u_tribar", "solid:block_stairs"], out=tmp_path, quick=True, progress=False, jobs=1
    )
    assert res.errors == []
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    for name, r in metrics["artist_models"].items():
        gap = r["expected"]["depth_gaps"][0]
        assert np.abs(r["periods"]).max() == pytest.approx(gap, rel=1e-6), name
        assert r["impossible_kind"] == "zeta"
        assert (
            min(r["relighting"]["iou"]) >= 0.98 and min(r["relighting"]["luminance_corr"]) >= 0.98
        )
    page = (tmp_path / "index.html").read_text()
    assert "Models as artists make them" in page and "u_tribar" in page.replace(" ", "_").lower()
    # the section speaks of the 3D model, not of another tool's cut model
    assert "model's depth gaps" in page and "IoU vs 3D model" in page
    assert "tool's" not in page and "vs cut" not in page


def test_cli_info_sees_a_solid_from_its_view(capsys):
    from meschers.cli import main

    assert main(["info", "solid:u_tribar"]) == 0
    out = capsys.readouterr().out
    assert "impossible: yes" in out and "6.928" in out
