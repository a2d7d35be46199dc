"""The ``meschers`` command line, in-process (``main(argv)``) and as a subprocess.

What each subcommand computes is checked against the library (periods, face counts, distances);
what a user error looks like is checked exactly: one line ``meschers: error: ...`` on stderr, a
non-zero status, no traceback.
"""

from __future__ import annotations

import json
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from meschers.cli import build_parser, main
from meschers_igl import load
from meschers_igl.gallery import get_model


def _paradox_dir() -> Path | None:
    """The ParadoxToolkit models: shipped in the package, else a copy under tests/data."""
    import importlib.resources

    for root in (
        Path(str(importlib.resources.files("meschers_igl"))) / "data" / "paradox",
        Path(__file__).parent / "data" / "paradox",
    ):
        if (root / "penrose_triangle.obj").is_file():
            return root
    return None


DATA = _paradox_dir()
SUBCOMMANDS = (
    "study",
    "info",
    "convert",
    "render",
    "draw",
    "geodesic",
    "smooth",
    "subdivide",
    "view",
    "studio",
)


def _gl() -> bool:
    try:
        from pyvista_views.headless import gl_available

        return bool(gl_available())
    except Exception:  # noqa: BLE001 - no pyvista/GL at all: skip the rendering tests
        return False


requires_gl = pytest.mark.skipif(not _gl(), reason="no offscreen OpenGL context")


NOTICE = "compiling kernels (first run only, about "


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err
    # on a machine whose kernel cache is empty the one notice of meschers.warmup may come first
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith(NOTICE)]
    assert len(lines) == 1, f"expected one error line, found {err!r}"
    assert lines[0].startswith("meschers: error: ") and "Traceback" not in err
    return lines[0]


# ------------------------------------------------------------------------------------------------
# help
# ------------------------------------------------------------------------------------------------
def test_help_lists_every_subcommand(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in (*SUBCOMMANDS, "inverse"):
        assert name in out


@pytest.mark.parametrize("command", SUBCOMMANDS)
def test_each_subcommand_has_help_with_an_example(command, capsys):
    assert main([command, "--help"]) == 0
    out = capsys.readouterr().out
    assert "example:" in out and f"meschers {command}" in out


def test_parser_covers_every_subcommand():
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    assert set(sub.choices) == {*SUBCOMMANDS, "inverse"}


# ------------------------------------------------------------------------------------------------
# info
# ------------------------------------------------------------------------------------------------
def test_info_gallery_model_json(capsys):
    assert main(["info", "penrose_triangle", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    g = get_model("penrose_triangle")
    m = g.mescher
    assert (info["vertices"], info["edges"], info["faces"]) == (m.n_vertices, m.n_edges, m.n_faces)
    assert info["genus"] == 1 and info["components"] == 1 and info["euler_characteristic"] == 0
    assert info["impossible"] is True
    assert max(np.abs(info["periods"])) == pytest.approx(g.expected_period, rel=1e-9)
    assert info["depth_arcs"] == g.order.n_arcs


def test_info_text_and_list(capsys):
    assert main(["info", "window"]) == 0
    out = capsys.readouterr().out
    # the Window's zeta integrates, its order cannot be realised (issue 18 item 7)
    assert "genus 4" in out and "impossible: yes (through its depth order" in out
    assert main(["info", "--list"]) == 0
    assert "penrose_triangle" in capsys.readouterr().out


# ------------------------------------------------------------------------------------------------
# user errors: one line, non-zero, no traceback
# ------------------------------------------------------------------------------------------------
def test_unknown_model(capsys):
    assert main(["info", "penrose_circle"]) == 2
    line = _one_error_line(capsys)
    assert "INPUT" in line and "penrose_triangle" in line and "'penrose_circle'" in line


def test_missing_file(tmp_path, capsys):
    assert main(["info", str(tmp_path / "absent.ply")]) == 2
    assert "absent.ply" in _one_error_line(capsys)


def test_corrupt_file(tmp_path, capsys):
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nend_header\n\x00\x01")
    assert main(["info", str(bad)]) == 2
    _one_error_line(capsys)
    bad_npz = tmp_path / "bad.npz"
    bad_npz.write_text("not a zip")
    assert main(["info", str(bad_npz)]) == 2
    _one_error_line(capsys)


def test_wrong_file_kind_suggests_convert(tmp_path, capsys):
    obj = tmp_path / "model.obj"
    obj.write_text("v 0 0 0\n")
    assert main(["info", str(obj)]) == 2
    assert "meschers convert" in _one_error_line(capsys)


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["render", "penrose_triangle"], "-o/--output"),
        (["render", "penrose_triangle", "-o", "x.png", "--light", "1,2"], "--light: expected 3"),
        (["render", "penrose_triangle", "-o", "x.png", "--shading", "glossy"], "glossy"),
        (["smooth", "penrose_triangle", "-o", "x.ply", "--t-xy", "-1"], ">= 0"),
        (["frobnicate"], "frobnicate"),
        ([], "required"),
    ],
)
def test_bad_options(argv, fragment, capsys):
    assert main(argv) == 2
    assert fragment in _one_error_line(capsys)


def test_bad_output_name(tmp_path, capsys):
    assert main(["subdivide", "penrose_triangle", "-o", str(tmp_path / "x.obj")]) == 2
    assert ".ply or .npz" in _one_error_line(capsys)


def test_bad_source_vertex(capsys):
    assert main(["geodesic", "penrose_triangle", "--source", "100000"]) == 2
    assert "source" in _one_error_line(capsys)


def test_view_without_display(monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    assert main(["view", "penrose_triangle"]) == 2
    assert "display" in _one_error_line(capsys)


def test_unknown_study_model(tmp_path, capsys):
    assert main(["study", "--quick", "--models", "nope", "--out", str(tmp_path / "s")]) == 2
    assert "models" in _one_error_line(capsys)


# ------------------------------------------------------------------------------------------------
# the processing subcommands do what the library does
# ------------------------------------------------------------------------------------------------
def test_subdivide_then_info(tmp_path, capsys):
    out = tmp_path / "fine.ply"
    assert main(["subdivide", "penrose_triangle", "-o", str(out), "--levels", "2"]) == 0
    m, order = load(out, return_order=True)
    g = get_model("penrose_triangle")
    assert m.n_faces == 16 * g.mescher.n_faces and order is not None
    # a loaded file picks its own generators (orientation may flip): compare the magnitudes
    np.testing.assert_allclose(
        np.sort(np.abs(m.periods())), np.sort(np.abs(g.mescher.periods())), atol=1e-12
    )
    capsys.readouterr()
    assert main(["info", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["faces"] == m.n_faces


def test_smooth_keeps_periods(tmp_path, capsys):
    out = tmp_path / "smooth.npz"
    assert (
        main(["smooth", "impossibagel", "-o", str(out), "--t-xy", "0.05", "--t-zeta", "0.05"]) == 0
    )
    m0 = get_model("impossibagel").mescher
    m = load(out, return_order=False)
    assert not np.allclose(m.xy, m0.xy)
    zeta0, zeta1 = np.asarray(m0.zeta), np.asarray(m.zeta)
    for e, s in m0.homology_generators():  # the same loops carry the same depth gain
        assert float(s @ zeta1[e]) == pytest.approx(float(s @ zeta0[e]), abs=1e-10)
    assert "largest period change" in capsys.readouterr().out


def test_geodesic_saves_distances(tmp_path, capsys):
    npy = tmp_path / "d.npy"
    assert (
        main(
            ["geodesic", "penrose_triangle", "--source", "3", "--target", "30", "--save", str(npy)]
        )
        == 0
    )
    d = np.load(npy)
    m = get_model("penrose_triangle").mescher
    np.testing.assert_allclose(d, m.geodesic_distance(3), atol=1e-12)
    assert d[3] == pytest.approx(0.0, abs=1e-12)
    assert "shortest path 3 -> 30" in capsys.readouterr().out


def test_geodesic_exact(tmp_path, capsys):
    """--method exact: the window-propagation distances, equal to MMP on a real 3D covering;
    the shortest path's length equals the exact distance at the target."""
    from meschers_igl.geodesic import geodesic_distance

    npy = tmp_path / "d.npy"
    args = ["geodesic", "penrose_triangle", "--source", "3", "--target", "30", "--method", "exact"]
    assert main([*args, "--save", str(npy)]) == 0
    d = np.load(npy)
    m = get_model("penrose_triangle").mescher
    cov = geodesic_distance(m, 3, "covering")
    assert np.abs(d - cov).max() < 1e-9
    out = capsys.readouterr().out
    length = float(out.split("shortest path 3 -> 30: length ")[1].split(",")[0])
    assert length == pytest.approx(d[30], rel=1e-5)  # printed to 6 digits


@pytest.mark.skipif(DATA is None, reason="ParadoxToolkit models not installed")
def test_convert_paradox_model(tmp_path, capsys):
    meta = json.loads((DATA / "penrose_triangle.json").read_text())
    view = ",".join(map(str, meta["camera"]["view_dir"]))
    up = ",".join(map(str, meta["camera"]["up"]))
    out = tmp_path / "penrose.ply"
    assert (
        main(["convert", str(DATA / "penrose_triangle.obj"), str(out), "--view", view, "--up", up])
        == 0
    )
    text = capsys.readouterr().out
    assert "wrote" in text and "periods" in text
    m, order = load(out, return_order=True)
    assert order is not None and order.n_arcs > 0
    gap = max(meta["verification"]["depth_gaps"])
    assert np.abs(m.periods()).max() == pytest.approx(gap, rel=1e-4)
    assert m.euler_characteristic() == meta["verification"]["glued_chi"]


def test_inverse_delegates_every_argument(monkeypatch):
    seen = []
    fake = types.ModuleType("meschers.inverse_cli")
    fake.inverse_main = lambda args: seen.append(list(args)) or 0
    monkeypatch.setitem(sys.modules, "meschers.inverse_cli", fake)
    argv = ["inverse", "t.png", "--light", "0,0,1", "--out", "fit", "--help"]
    assert main(argv) == 0
    assert seen == [argv[1:]]


@requires_gl
def test_render_png(tmp_path):
    from PIL import Image

    out = tmp_path / "r.png"
    assert (
        main(
            ["render", "penrose_triangle", "-o", str(out), "--size", "96,64", "--shading", "smooth"]
        )
        == 0
    )
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape == (64, 96, 3)
    covered = (img != 255).any(axis=2).mean()
    assert 0.1 < covered < 0.9  # an object on a white background


# ------------------------------------------------------------------------------------------------
# as a subprocess (what a user's shell runs)
# ------------------------------------------------------------------------------------------------
def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "meschers", *args],
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_subprocess_info_and_error():
    ok = _run("info", "penrose_triangle")
    assert ok.returncode == 0 and "impossible: yes" in ok.stdout
    bad = _run("info", "no_such_model")
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and bad.stderr.startswith("meschers: error: INPUT")
    assert "Traceback" not in bad.stderr


def test_importing_the_cli_does_not_import_pyvista():
    code = "import sys, meschers.cli; sys.exit(int(any(m in sys.modules for m in ('pyvista', 'pymeshlab', 'torch'))))"
    assert subprocess.run([sys.executable, "-c", code], timeout=60).returncode == 0


# ------------------------------------------------------------------------------------------------
# CLI manners: help texts, shipped models by name, exact model selection, size guards
# ------------------------------------------------------------------------------------------------
def test_every_option_has_a_help_text():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name, p in sub.choices.items():
        for action in p._actions:
            if action.dest in ("help",):
                continue
            assert action.help and action.help.strip(), (
                f"{name} {action.option_strings or action.dest}"
            )


def test_solid_models_are_listed_and_named_where_models_are(capsys):
    from meschers.inputs import list_solids

    solids = list_solids()
    assert solids
    assert main(["info", "--list"]) == 0
    out = capsys.readouterr().out
    assert all(f"solid:{n}" in out for n in solids)
    assert main(["info", "no_such_model"]) == 2
    assert "solid:NAME" in capsys.readouterr().err
    assert main(["study", "--help"]) == 0
    assert "solid:NAME" in " ".join(capsys.readouterr().out.split())


def test_size_guards_speak_of_pixels_and_of_the_option(capsys, tmp_path):
    assert (
        main(["render", "penrose_triangle", "-o", str(tmp_path / "x.png"), "--size", "100000"]) == 2
    )
    err = capsys.readouterr().err
    assert "1e+10 pixels" in err and "add --force" in err and "force=True" not in err
    assert not (tmp_path / "x.png").exists()
    # the library keeps speaking of the keyword
    from meschers_igl import MescherError
    from meschers_igl.validate import check_budget

    with pytest.raises(MescherError, match="pass force=True"):
        check_budget(1e12, what="x")


def test_a_render_of_one_colour_is_refused_and_not_written(capsys, tmp_path, monkeypatch):
    import pyvista_views

    monkeypatch.setattr(
        pyvista_views, "render", lambda *a, **k: np.full((40, 40, 3), 255, np.uint8)
    )
    out = tmp_path / "blank.png"
    assert main(["render", "penrose_triangle", "-o", str(out)]) == 2
    assert "one colour" in capsys.readouterr().err
    assert not out.exists()


def test_geodesic_refuses_a_bad_target_before_computing_the_field(capsys, monkeypatch):
    import meschers_igl.geodesic as geodesic

    def boom(*a, **k):
        raise AssertionError("the field was computed before the target was checked")

    monkeypatch.setattr(geodesic, "geodesic_solver", boom)
    assert main(["geodesic", "penrose_triangle", "--source", "0", "--target", "99999"]) == 2
    assert "--target: expected indices in [0," in capsys.readouterr().err


def test_negative_vector_options_parse_for_every_command(capsys, tmp_path):
    from meschers.cli import _join_negative_vectors

    assert _join_negative_vectors(["inverse", "p.png", "--light", "-0.5,0.35,1"]) == [
        "inverse",
        "p.png",
        "--light=-0.5,0.35,1",
    ]
    # the inverse command gets the joined form: whatever it says, not "expected one argument"
    main(["inverse", str(tmp_path / "missing.png"), "--light", "-0.5,0.35,1"])
    assert "expected one argument" not in capsys.readouterr().err


def test_info_shipped_model_by_name(capsys):
    pytest.importorskip("pymeshlab")
    assert main(["info", "paradox:penrose_triangle", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    from meschers_igl.paradox import paradox_model

    meta = paradox_model("penrose_triangle").meta
    assert info["euler_characteristic"] == meta["verification"]["glued_chi"]
    gap = max(meta["verification"]["depth_gaps"])
    assert max(np.abs(info["periods"])) == pytest.approx(gap, rel=1e-4)
    assert main(["info", "paradox:no_such_model"]) == 2
    assert "penrose_triangle" in _one_error_line(capsys)


def test_convert_shipped_model_in_an_empty_folder(tmp_path, monkeypatch, capsys):
    """The README's line: no file but the package's own is needed."""
    pytest.importorskip("pymeshlab")
    monkeypatch.chdir(tmp_path)
    assert main(["convert", "paradox:penrose_triangle", "penrose.ply"]) == 0
    m, order = load(tmp_path / "penrose.ply", return_order=True)
    assert order is not None and order.n_arcs > 0 and m.is_impossible()
    assert "wrote penrose.ply" in capsys.readouterr().out
    # a gallery model is written as it is
    assert main(["convert", "impossibagel", "bagel.npz"]) == 0
    assert load(tmp_path / "bagel.npz").n_faces == get_model("impossibagel").mescher.n_faces


def test_too_big_subdivision_is_refused_at_once(tmp_path, capsys):
    import time

    t0 = time.perf_counter()
    assert (
        main(["subdivide", "penrose_triangle", "-o", str(tmp_path / "x.ply"), "--levels", "30"])
        == 2
    )
    assert time.perf_counter() - t0 < 1.0
    line = _one_error_line(capsys)
    assert "--force" in line and "faces" in line
    assert not (tmp_path / "x.ply").exists()
    assert (
        main(["render", "penrose_triangle", "-o", str(tmp_path / "x.png"), "--subdivide", "30"])
        == 2
    )
    assert "--force" in _one_error_line(capsys)


def test_size_guard_refuses_before_the_depth_order_is_computed(tmp_path, monkeypatch, capsys):
    # The order is the costly part of loading a gallery model (numba kernels, overlaps): the
    # refusal must not wait for it, so that `meschers subdivide --levels 30` exits at once.
    from meschers_igl import gallery

    model = type(gallery.get_model("penrose_triangle"))

    def no_order(self):
        raise AssertionError("the depth order was computed before the size guard")

    monkeypatch.setattr(model, "order", property(no_order))
    out = tmp_path / "x.ply"
    assert main(["subdivide", "penrose_triangle", "-o", str(out), "--levels", "30"]) == 2
    assert "--force" in _one_error_line(capsys)
    assert (
        main(["render", "penrose_triangle", "-o", str(tmp_path / "x.png"), "--subdivide", "30"])
        == 2
    )
    assert "--force" in _one_error_line(capsys)


def test_force_bypasses_the_size_guard(tmp_path, monkeypatch):
    from meschers_igl import validate

    # pretend the machine has 1 MB: one level is then "too big" unless forced
    monkeypatch.setattr(validate, "available_memory", lambda: 2**20)
    out = tmp_path / "x.ply"
    assert main(["subdivide", "penrose_triangle", "-o", str(out), "--levels", "2"]) == 2
    assert main(["subdivide", "penrose_triangle", "-o", str(out), "--levels", "2", "--force"]) == 0
    assert load(out).n_faces == 16 * get_model("penrose_triangle").mescher.n_faces


def test_study_models_select_exactly_what_they_name(monkeypatch, tmp_path):
    from meschers import study

    seen = {}

    def fake(specs, keys, st, progress):
        seen["specs"] = specs
        return []

    monkeypatch.setattr(study, "_run_serial", fake)
    monkeypatch.setattr(study, "write_report", lambda *a, **k: None, raising=False)
    out = str(tmp_path / "s")
    argv = ["study", "--quick", "--jobs", "1", "--no-progress", "--models", "penrose_triangle"]
    assert main([*argv, "--out", out]) == 0
    assert [(s.kind, s.name) for s in seen["specs"]] == [("gallery", "penrose_triangle")]
    argv = ["study", "paradox:penrose_stair", "impossibagel", "--jobs", "1", "--no-progress"]
    assert main([*argv, "--out", out]) == 0
    assert [(s.kind, s.name) for s in seen["specs"]] == [
        ("artist", "penrose_stair"),
        ("gallery", "impossibagel"),
    ]


def test_smooth_saves_the_order_followed_to_the_moved_screen_positions(tmp_path):
    from meschers_igl.painter import backface_share

    out = tmp_path / "stairs.npz"
    assert main(["smooth", "penrose_stairs", "-o", str(out), "--t-xy", "0.2"]) == 0
    m, order = load(out, return_order=True)
    g = get_model("penrose_stairs")
    assert backface_share(m, order, size=256) <= 1e-3
    assert backface_share(m, g.order, size=256) > 1e-3  # the unsmoothed order would show them


@pytest.mark.parametrize("name", ["impossible_cube", "window"])
def test_info_says_a_figure_is_impossible_through_its_order(name, capsys):
    # zeta integrates (every period is round-off, printed as 0) but the depth order cannot be
    # realised by the bent embedding: `info` used to print "impossible: no" and 1.3e-15 periods
    assert main(["info", name]) == 0
    out = capsys.readouterr().out
    assert "impossible: yes (through its depth order" in out
    periods = out.split("periods: ")[1].splitlines()[0].split(", ")
    assert set(periods) == {"0"}


def test_info_says_a_figure_is_impossible_through_its_periods(capsys):
    assert main(["info", "penrose_triangle"]) == 0
    assert "impossible: yes (periods" in capsys.readouterr().out


def test_the_no_torch_message_is_plain_and_names_torch_first(capsys, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_torch(name, *args, **kwargs):
        if name == "torch" or name.startswith("torch."):
            raise ModuleNotFoundError("No module named 'torch'", name="torch")
        return real_import(name, *args, **kwargs)

    for mod in [m for m in sys.modules if m.startswith("meschers_igl.inverse.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setattr(builtins, "__import__", no_torch)
    assert main(["inverse", "target.png", "--light", "0,0,1", "--out", "fit"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("meschers: error: meschers_igl.inverse needs PyTorch")  # no quotes
    assert err.index("pip install torch==2.13.0") < err.index("meschers[inverse]")


def test_cli_smooth_refuses_a_collapsing_time_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "s.ply"
    assert main(["smooth", "penrose_triangle", "-o", str(out), "--t-xy", "1e300"]) == 2
    assert "every vertex moved to one point" in capsys.readouterr().err
    assert not out.exists()


def test_inverse_help_has_examples(capsys):
    assert main(["inverse", "--help"]) == 0
    out = capsys.readouterr().out
    assert "example:" in out and "meschers inverse picture.png --light -0.5,0.35,1" in out
