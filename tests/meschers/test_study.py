"""The comparison study: its measurements on hand-made cases, then one quick run end to end.

The end-to-end run (``run_study(quick=True)`` on the smallest gallery model plus one
ParadoxToolkit model) checks the paper's claims as numbers, not that files exist only:
the mescher relights exactly like the cut model and the bent model does not; the mescher's
geodesics beat the cut's and the bent's against exact covering distances; subdivision and
smoothing keep the periods; the ParadoxToolkit triangle's period is the tool's depth gap.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from meschers.describe import describe
from meschers.metrics import distance_error, loop_periods, one_source_per_component, seam_gap
from meschers.report import embedded_images, referenced_images
from meschers.study import run_study
from meschers_igl import Mescher, MescherError, shapes
from meschers_igl.gallery import get_model
from pyvista_views.headless import gl_available

requires_gl = pytest.mark.skipif(not gl_available(), reason="no offscreen OpenGL context")


# ------------------------------------------------------------------------------------------------
# measurements on hand-sized cases
# ------------------------------------------------------------------------------------------------
def test_distance_error_hand_values():
    d_exact = np.array([0.0, 1.0, 2.0, 4.0, np.inf])
    d = np.array([0.0, 1.5, 2.0, 3.0, 7.0])
    e = distance_error(d, d_exact)
    assert e["n"] == 4  # the unreachable vertex is left out
    assert e["mean"] == pytest.approx((0.5 + 1.0) / 4 / 4)
    assert e["max"] == pytest.approx(1.0 / 4)
    with pytest.raises(MescherError, match="d: expected shape"):
        distance_error(d[:3], d_exact)


def test_seam_gap_hand_values():
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.3], [1.0, 0.0], [5.0, 5.0]])
    vmap = np.array([0, 1, 0, 1, 2])  # vertex 0 copied with a 0.3 gap, vertex 1 coincident
    assert seam_gap(xy, vmap) == pytest.approx(0.3)
    assert seam_gap(xy[[0, 1, 4]], np.array([0, 1, 2])) == 0.0
    with pytest.raises(MescherError, match="vmap: expected shape"):
        seam_gap(xy, vmap[:3])


def test_one_source_per_component():
    V1, F1 = shapes.icosphere(1)
    V = np.vstack([V1, V1 + [5.0, 0, 0]])
    F = np.vstack([F1, F1 + len(V1)])
    m = Mescher.from_mesh(V, F)
    s = one_source_per_component(m)
    assert s.size == 2 and (s < len(V1)).sum() == 1
    d = m.geodesic_distance(s)
    assert np.isfinite(d).all() and np.allclose(d[s], 0.0)


def test_loop_periods_match_periods_and_survive_smoothing():
    g = get_model("penrose_triangle")
    m = g.mescher
    np.testing.assert_allclose(loop_periods(m, m.zeta), m.periods(), atol=1e-12)
    h = float(np.mean(m.edge_lengths()))
    ms = m.smooth(t_xy=h * h, t_zeta=4 * h * h)
    assert not np.allclose(ms.zeta, m.zeta)  # smoothing did something ...
    np.testing.assert_allclose(loop_periods(m, ms.zeta), m.periods(), atol=1e-10)  # ... not this
    assert np.abs(m.periods()).max() == pytest.approx(g.expected_period, rel=1e-9)


@pytest.mark.parametrize(
    ("mesh", "expected"),
    [
        ("torus", {"genus": 1, "euler_characteristic": 0, "components": 1, "boundary_loops": 0}),
        ("sphere", {"genus": 0, "euler_characteristic": 2, "components": 1, "boundary_loops": 0}),
        ("annulus", {"genus": 0, "euler_characteristic": 0, "components": 1, "boundary_loops": 2}),
    ],
)
def test_describe_topology(mesh, expected):
    V, F = {
        "torus": lambda: shapes.torus(12, 6),
        "sphere": lambda: shapes.icosphere(1),
        "annulus": lambda: shapes.annulus(12, 3),
    }[mesh]()
    info = describe(Mescher.from_mesh(V, F))
    assert {k: info[k] for k in expected} == expected
    assert info["impossible"] is False  # an ordinary mesh has no harmonic depth


# ------------------------------------------------------------------------------------------------
# one quick run, end to end
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def study(tmp_path_factory):
    if not gl_available():
        pytest.skip("no offscreen OpenGL context")
    out = tmp_path_factory.mktemp("study")
    return run_study(
        ["penrose_triangle", "paradox:penrose_triangle", "paradox:penrose_stair"],
        out=out,
        quick=True,
        progress=False,
    )


@requires_gl
def test_study_writes_report_and_metrics(study):
    out = study.out
    assert study.errors == []
    assert (out / "index.html").is_file() and (out / "metrics.json").is_file()
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["errors"] == [] and "10.1145/3731422" in metrics["citation"]
    # one file: every image is embedded, each is one of the PNGs written beside the page, and
    # every PNG is in the page
    refs = referenced_images(out / "index.html")
    assert refs and all(r.startswith("data:image/png;base64,") for r in refs)
    pngs = {p.name: p.read_bytes() for p in out.glob("*.png")}
    assert sorted(embedded_images(out / "index.html")) == sorted(pngs.values())
    kinds = {"hodge", "render", "heat", "geodesic", "smoothing", "relight", "compare"}
    assert {f"penrose_triangle_{k}.png" for k in kinds} <= set(pngs)
    assert {"tool_penrose_triangle_relight.png", "tool_penrose_triangle_periods.png"} <= set(pngs)
    html = (out / "index.html").read_text()
    assert (
        "<table>" in html
        and "Models from other tools" in html
        and "doi.org/10.1145/3731422" in html
    )
    assert 'src="' not in html.replace('src="data:', "")  # no link to another file
    ids = re.findall(r"\bid=[\"']([^\"']+)[\"']", html)
    assert len(ids) == len(set(ids)), "HTML ids repeat"
    # the gallery's and the tool's penrose_triangle are two sections with their own ids
    assert {"models-penrose_triangle", "other_tools-penrose_triangle"} <= set(ids)
    assert "{st." not in html and "{" not in re.sub(r"<style>.*?</style>", "", html, flags=re.S)


@requires_gl
def test_study_numbers_match_the_paper(study):
    r = study.metrics["models"]["penrose_triangle"]
    # subdivision, Hodge decomposition and smoothing keep the periods (sqrt(3) x bar length)
    assert r["subdivision"]["period_drift"] < 1e-9
    assert max(np.abs(r["hodge"]["periods"])) == pytest.approx(4 * np.sqrt(3), rel=1e-9)
    assert r["hodge"]["reconstruction_error"] < 1e-12 and r["hodge"]["harmonic_closed"] < 1e-12
    assert max(r["smoothing"]["period_drift"].values()) < 1e-9
    assert r["heat"]["heat_conservation_error"] < 1e-10
    # relighting: the mescher is the cut model pixel for pixel; the bent model's normals are wrong
    mes, bent = r["relighting"]["mescher"], r["relighting"]["bent"]
    assert min(mes["iou"]) > 0.99 and max(mes["luminance_mae"]) < 0.01  # dL on the 0-1 scale
    assert min(bent["luminance_mae"]) > 5 * max(max(mes["luminance_mae"]), 0.005)
    # the Fig. 10 numbers are on the same 0-1 dL scale as the relighting table
    numbers = r["comparison"]["numbers"]
    dl = [numbers[row][col] for row in numbers for col in ("render", "relit", "smoothed")]
    assert all(0.0 <= v <= 1.0 for v in dl) and numbers["cut"]["render"] == 0.0
    assert numbers["bent"]["render"] > 2 * numbers["mescher"]["render"]
    # geodesics against exact covering distances: the mescher beats both (the cut's seam blocks
    # paths, the bent model's metric is not the object's); which of those two is worse depends
    # on where the seam runs
    ge = r["comparison"]["geodesic_error_vs_exact"]
    assert ge["mescher"]["mean"] < 0.05
    # the mescher's mean error is the same with every release (2.06%); the cut's depends on the
    # seam, which the z-buffered comparison of candidate seams picks, and that depends on the VTK
    # release and the GL driver: 3.48% with VTK 9.7 here, 2.21% with VTK 9.4 (the oldest
    # pyproject.toml allows) on the same machine.  The bent model's is 9.07%.  So: better than
    # both, by a margin no release decides
    assert ge["mescher"]["mean"] < min(ge["bent"]["mean"], ge["cut"]["mean"])
    assert ge["cut"]["max"] > 2 * ge["mescher"]["max"]  # far worse across the seam
    assert r["geodesic"]["heat_accurate_error"]["mean"] < r["geodesic"]["heat_error"]["mean"]
    assert 0.99 < r["geodesic"]["path_length_over_exact"] < 1.1
    # smoothing opens the cut model's seam; the mescher keeps its period
    assert r["comparison"]["seam_gap_after_smoothing"]["cut"] > 0.005
    mp = r["comparison"]["max_period_after_smoothing"]
    assert mp["mescher"] == pytest.approx(mp["before"], rel=1e-9) and mp["bent"] == 0.0


@requires_gl
def test_study_models_from_other_tools(study):
    tools = study.metrics["other_tools"]
    assert set(tools) == {"penrose_triangle", "penrose_stair"}  # exactly what was named
    assert set(study.metrics["models"]) == {"penrose_triangle"}
    tri = tools["penrose_triangle"]
    gap = max(tri["expected"]["depth_gaps"])
    assert max(np.abs(tri["periods"])) == pytest.approx(gap, rel=1e-4)
    assert min(tri["relighting"]["iou"]) >= 0.98
    assert tools["penrose_stair"]["impossible"] is False  # boxes: impossible by the order only
    for r in tools.values():
        assert r["input"]["euler_characteristic"] == r["expected"]["glued_chi"]


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@requires_gl
@pytest.mark.skipif(_chromium() is None, reason="headless Chromium not installed")
def test_report_screenshot_in_headless_chromium(study, tmp_path):
    shot = tmp_path / "shot.png"
    cmd = [
        _chromium(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={tmp_path / 'profile'}",
        f"--screenshot={shot}",
        "--window-size=1200,900",
        (study.out / "index.html").resolve().as_uri(),
    ]
    subprocess.run(cmd, capture_output=True, timeout=120, check=False)
    assert shot.is_file(), "Chromium wrote no screenshot"
    from PIL import Image

    img = np.asarray(Image.open(shot).convert("L"), dtype=np.float64)
    assert img.shape == (900, 1200)
    dark = img < 128  # text, table rules, figures
    assert dark.mean() > 0.01 and img.std() > 10, "the screenshot of the report is blank"
    assert Path(shot).stat().st_size > 10_000


@requires_gl
def test_study_captions_and_heat_scale(study):
    sec = next(s for s in study.sections if s.name == "penrose_triangle")
    caps = {f.title: f.caption for f in sec.figures}
    assert "10 isolines" in caps["Geodesic distance and shortest path"]
    assert "log10(u / max u)" in caps["Heat diffusion"]
    # the heat panels show the heat: on the log scale most covered pixels are not black
    import io

    from PIL import Image

    heat = next(f for f in sec.figures if f.title == "Heat diffusion")
    img = np.asarray(Image.open(io.BytesIO(heat.data)).convert("L"), dtype=float)
    panel = img[20 : 20 + 192, : 3 * 192]
    covered = panel < 250
    assert (panel[covered] > 40).mean() > 0.5, "heat panels are nearly black"


def test_summary_prints_luminance_differences_to_their_resolution():
    """A dL of 3.7e-05 (under one 8-bit level) is printed 0.000, not 3.71e-05."""
    from meschers.report import _num

    assert _num(3.71e-05, fixed=3) == "0.000"
    assert _num(0.0658, fixed=3) == "0.066"
    assert _num(float("nan"), fixed=3) == "&ndash;"


def test_summary_geodesic_errors_of_a_model_without_seam():
    """No harmonic part: the summary gives the mescher's error its geodesic section measured, and
    says in words (with the footnote) why the cut and bent columns have no numbers of their own;
    a model with a comparison keeps its numbers."""
    from meschers.report import NO_SEAM_NOTE, _gallery_table

    no_seam = {
        "geodesic": {"heat_error": {"mean": 0.0123}},
        "comparison": {"skipped": "no harmonic part: cut and bent embeddings equal the mescher"},
    }
    seam = {
        "geodesic": {"heat_error": {"mean": 0.5}},  # not the comparison's: not shown
        "comparison": {
            "geodesic_error_vs_exact": {
                "mescher": {"mean": 0.01},
                "cut": {"mean": 0.02},
                "bent": {"mean": 0.03},
            },
            "seam_gap_after_smoothing": {"cut": 0.04},
        },
    }
    rows = _gallery_table({"cube": no_seam, "penrose": seam}).split("<tr>")[2:]
    cells = [re.findall(r"<td>(.*?)</td>", row) for row in rows]
    assert cells[0][9:13] == [
        "1.23%",
        "= mescher<sup>*</sup>",
        "= mescher<sup>*</sup>",
        "no seam<sup>*</sup>",
    ]
    assert cells[1][9:13] == ["1.00%", "2.00%", "3.00%", "4.00%"]
    html = _gallery_table({"cube": no_seam})
    assert "<sup>*</sup> no harmonic part" in html and NO_SEAM_NOTE.split(":")[0] in html
    assert "<sup>*</sup>" not in _gallery_table({"penrose": seam})  # no footnote without need


@requires_gl
def test_a_model_without_seam_says_so_in_its_section_and_summary(tmp_path):
    """The cube (impossible through its depth order only): no comparison is drawn; its geodesic
    section and the summary say why, and the summary gives the section's own error."""
    from meschers.report import NO_SEAM_NOTE

    res = run_study(["impossible_cube"], out=tmp_path, quick=True, progress=False)
    assert res.errors == []
    r = res.metrics["models"]["impossible_cube"]
    assert "skipped" in r["comparison"]
    sec = res.sections[0]
    caps = {f.title: f.caption for f in sec.figures}
    assert "Mescher vs cut vs bent (paper Fig. 10)" not in caps
    assert NO_SEAM_NOTE in caps["Geodesic distance and shortest path"]
    html = (tmp_path / "index.html").read_text()
    err = f"{100 * r['geodesic']['heat_error']['mean']:.2f}%"
    assert err in caps["Geodesic distance and shortest path"]
    row = re.search(r"<tr><td>impossible_cube</td>(.*?)</tr>", html).group(1)
    assert f"<td>{err}</td><td>= mescher<sup>*</sup></td>" in row
