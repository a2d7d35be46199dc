"""``meschers draw``: the file is the library's drawing; options reach it; user errors are one
line."""

from __future__ import annotations

import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from meschers.cli import build_parser, main
from meschers_igl.gallery import get_model
from meschers_igl.lines import line_drawing

pytest.importorskip("cairosvg")
SVG = "{http://www.w3.org/2000/svg}"


def _paths(svg_text: str) -> dict[str, int]:
    root = ET.fromstring(svg_text)
    return {g.get("id"): len(list(g.iter(f"{SVG}path"))) for g in root.iter(f"{SVG}g")}


def test_draw_is_registered():
    parser = build_parser()
    args = parser.parse_args(["draw", "penrose_triangle", "-o", "x.svg", "--crease-angle", "95"])
    assert args.crease_angle == 95.0 and args.hidden == "omit"


def test_draw_svg_equals_the_library(tmp_path, capsys):
    out = tmp_path / "p.svg"
    assert main(["draw", "penrose_triangle", "-o", str(out), "--size", "300,200"]) == 0
    g = get_model("penrose_triangle")
    ld = line_drawing(g.mescher, g.order)
    counts = _paths(out.read_text())
    for k, name in enumerate(("outline", "occlusion", "crease")):
        assert counts.get(name, 0) == int((ld.visible & (ld.kind == k)).sum())
    assert "wrote" in capsys.readouterr().out
    root = ET.fromstring(out.read_text())
    assert (root.get("width"), root.get("height")) == ("300", "200")


def test_draw_options_reach_the_drawing(tmp_path):
    out = tmp_path / "c.svg"
    assert main(["draw", "impossible_cube", "-o", str(out), "--hidden", "dashed"]) == 0
    assert _paths(out.read_text()).get("hidden", 0) > 0
    # no edge of a box is sharper than 90 degrees: no creases above 95
    assert main(["draw", "impossible_cube", "-o", str(out), "--crease-angle", "95"]) == 0
    assert "crease" not in _paths(out.read_text())


def test_draw_pdf_and_subdivided(tmp_path):
    out = tmp_path / "b.pdf"
    assert main(["draw", "impossibagel", "-o", str(out), "--subdivide", "1"]) == 0
    assert out.read_bytes()[:5] == b"%PDF-"


def test_draw_overlay_png(tmp_path):
    from PIL import Image

    out = tmp_path / "o.png"
    assert main(["draw", "penrose_triangle", "-o", str(out), "--overlay", "--size", "120"]) == 0
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape == (120, 120, 3)
    grey = (np.ptp(img.astype(int), axis=2) < 10) & (img[..., 0] > 40) & (img[..., 0] < 230)
    assert grey.mean() > 0.1 and (img.max(axis=2) < 40).mean() > 0.005  # shading and lines


@pytest.mark.parametrize(
    "argv, words",
    [
        (["draw", "penrose_triangle", "-o", "x.jpg"], "-o: expected a file name ending in"),
        (["draw", "penrose_triangle", "-o", "x.svg", "--overlay"], ".png"),
        (["draw", "no_such_model", "-o", "x.svg"], "no_such_model"),
        (["draw", "penrose_triangle", "-o", "x.svg", "--crease-angle", "-3"], "expected a number"),
    ],
)
def test_draw_user_errors(tmp_path, capsys, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("meschers: error: ") and words in err[0]


def test_draw_subprocess(tmp_path):
    out = tmp_path / "s.svg"
    r = subprocess.run(
        [sys.executable, "-m", "meschers", "draw", "window", "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    assert out.read_text().startswith("<?xml") and "Traceback" not in r.stderr
