"""``meschers inverse``: the application's command line for inverse rendering."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

pytest.importorskip("torch")
pytest.importorskip("largesteps")

from meschers_igl import MescherError, load  # noqa: E402


def test_cli_torus_end_to_end(tmp_path):
    from meschers.inverse_cli import inverse_main

    out = tmp_path / "fit"
    rc = inverse_main(
        [
            "penrose",
            "--light",
            "0.4,0.25,1",
            "--out",
            str(out),
            "--iters",
            "6",
            "--resolution",
            "32",
            "--init",
            "torus",
            "--torus",
            "24,8",
            "--every",
            "3",
            "--no-progress",
        ]
    )
    assert rc == 0
    for name in (
        "mescher.ply",
        "render.png",
        "init.png",
        "loss.png",
        "before_after.png",
        "metrics.json",
        "renders/step_00003.png",
        "renders/step_00006.png",
    ):
        assert (out / name).stat().st_size > 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["max_abs_d12_zeta"] < 1e-10 and len(metrics["periods"]) == 2
    assert [s for s, _ in metrics["psnr_curve"]] == [3, 6]
    m = load(out / "mescher.ply", return_order=False)
    assert m.n_faces == 2 * 24 * 8


@pytest.mark.render
def test_cli_holds_the_faces_to_their_shade_regions(tmp_path, monkeypatch):
    """From a picture the fit gets each face's region normal and the penalty that holds it
    (what the acceptance benchmark measures), not the bare image loss."""
    from meschers.inverse_cli import inverse_main
    from meschers_igl.inverse import optimize
    from meschers_igl.inverse.turn import PICTURE_TURN

    seen = {}

    class Stop(Exception):
        pass

    def fake_fit(target, init, offsets, **kw):
        seen.update(kw, init=init)
        raise Stop

    monkeypatch.setattr(optimize, "fit_mescher", fake_fit)
    with pytest.raises(Stop):
        inverse_main(["tribar", "--out", str(tmp_path / "t"), "--iters", "2", "--no-progress"])
    n = np.asarray(seen["face_normals"])
    assert n.shape == (seen["init"].n_faces, 3)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0) and np.all(n[:, 2] > 0)
    # one normal per shade region (a tribar shows three orientations), not each face's own;
    # the start's faces mostly lie in their regions' planes already (the lift's least squares)
    assert 3 <= len(np.unique(np.round(n, 9), axis=0)) <= 6
    agree = np.einsum("ij,ij->i", n, seen["init"].face_normals())
    assert np.median(agree) > np.cos(np.radians(1.0))
    assert tuple(seen["options"].turn) == PICTURE_TURN


def test_cli_from_a_zbuffered_tribar(tmp_path):
    from meschers.inverse_cli import inverse_main

    out = tmp_path / "tribar"
    rc = inverse_main(
        ["tribar", "--out", str(out), "--iters", "20", "--every", "10", "--no-progress"]
    )
    assert rc == 0
    metrics = json.loads((out / "metrics.json").read_text())
    # started from the picture: already close, impossible, with the model's depth gap
    assert metrics["init"] == "picture" and metrics["impossible"]
    assert metrics["psnr_init_db"] > 29.0 and metrics["silhouette_iou"] > 0.97
    assert abs(metrics["figure_period"] - metrics["true_gap"]) < 0.15 * metrics["true_gap"]
    assert metrics["exposure"] == 1.0  # a white figure
    m, order = load(out / "mescher.ply", return_order=True)
    assert m.n_faces == metrics["faces"]
    assert np.isfinite(metrics["cpu_seconds"])


def test_cli_rejects_bad_light_and_huge_resolution(tmp_path):
    from meschers.inverse_cli import inverse_main

    with pytest.raises(MescherError, match="--light"):
        inverse_main(["penrose", "--light", "0,1", "--out", str(tmp_path)])
    with pytest.raises(MescherError, match="--resolution"):
        inverse_main(["penrose", "--out", str(tmp_path), "--resolution", "2000000"])
    with pytest.raises(MescherError, match="--init picture"):
        inverse_main(
            [
                "penrose",
                "--light",
                "0,0,1",
                "--light",
                "1,0,1",
                "--out",
                str(tmp_path),
                "--iters",
                "1",
            ]
        )


def test_meschers_cli_hands_over_to_inverse_main(tmp_path):
    from meschers.cli import main

    out = tmp_path / "fit"
    argv = [
        "inverse",
        "penrose",
        "--out",
        str(out),
        "--iters",
        "2",
        "--resolution",
        "16",
        "--init",
        "torus",
        "--torus",
        "12,6",
        "--no-progress",
    ]
    assert main(argv) == 0
    assert (out / "mescher.ply").exists()


@pytest.mark.render
def test_cli_light_with_negative_components_and_light_in_metrics(tmp_path):
    from meschers.cli import main

    out = tmp_path / "given"
    argv = [
        "inverse",
        "tribar",
        "--light",
        "-0.5,0.35,1",
        "--out",
        str(out),
        "--iters",
        "4",
        "--every",
        "2",
        "--resolution",
        "96",
        "--no-progress",
    ]
    assert main(argv) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    given = np.array([-0.5, 0.35, 1.0]) / np.linalg.norm([-0.5, 0.35, 1.0])
    assert np.asarray(metrics["light"][0]) == pytest.approx(given, abs=1e-12)
    assert metrics["light_estimated"] is False
    assert abs(metrics["figure_period"] - metrics["true_gap"]) < 0.15 * metrics["true_gap"]
    # no --light: read from the picture (the same light, or its Necker mirror (-x, -y, z))
    out = tmp_path / "estimated"
    argv = [
        "inverse",
        "tribar",
        "--out",
        str(out),
        "--iters",
        "2",
        "--every",
        "2",
        "--resolution",
        "96",
        "--no-progress",
    ]
    assert main(argv) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["light_estimated"] is True
    true = np.array([0.6, -0.1, 1.0]) / np.linalg.norm([0.6, -0.1, 1.0])
    est = np.asarray(metrics["light"][0])
    cos = max(est @ true, est @ (true * [-1.0, -1.0, 1.0]))
    assert math.degrees(math.acos(min(cos, 1.0))) < 2.0


def test_cli_picture_without_a_figure_is_refused(tmp_path):
    from PIL import Image

    from meschers.inverse_cli import inverse_main

    blank = tmp_path / "blank.png"
    Image.fromarray(np.full((64, 64, 3), 255, np.uint8)).save(blank)
    with pytest.raises(MescherError, match="expected a figure"):
        inverse_main([str(blank), "--out", str(tmp_path / "o"), "--no-progress"])


@pytest.mark.render
def test_zbuffer_ground_is_read_in_zero_to_one_integers_included():
    """``(1, 1, 1)`` is white, as ``(1.0, 1.0, 1.0)`` (PyVista alone would read integers as
    0-255 and paint the ground black); a colour outside [0, 1] is refused by name."""
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse.models import penrose_tribar

    model = penrose_tribar()
    ints, _ = zbuffer_picture(model, 32, background=(1, 1, 1))
    floats, _ = zbuffer_picture(model, 32, background=(1.0, 1.0, 1.0))
    np.testing.assert_array_equal(ints, floats)
    np.testing.assert_array_equal(ints[0, 0], [1.0, 1.0, 1.0])
    with pytest.raises(MescherError, match="background"):
        zbuffer_picture(model, 32, background=(255, 255, 255))


def _corner_picture(n: int = 64) -> np.ndarray:
    """(n, n) uint8: a box's corner, three rhombi of greys 60, 140, 220, on white."""
    from PIL import Image, ImageDraw

    im = Image.new("L", (n, n), 255)
    d = ImageDraw.Draw(im)
    c = np.array([0.5, 0.5]) * n
    r = 0.4 * n
    pts = [c + r * np.array([np.cos(a), np.sin(a)]) for a in np.radians(np.arange(6) * 60 + 30)]
    for k, g in enumerate((60, 140, 220)):
        q = [tuple(c), tuple(pts[2 * k]), tuple(pts[2 * k + 1]), tuple(pts[(2 * k + 2) % 6])]
        d.polygon(q, fill=g)
    return np.asarray(im)


def test_pictures_are_read_as_seen_whatever_their_mode(tmp_path):
    """Grey, RGB, 16-bit grey (which ``convert("RGB")`` clips to white), and transparent
    grounds, whatever colour the transparent pixels store, read as the same picture: the
    figure laid over white, as on a page."""
    from PIL import Image

    from meschers.inverse_cli import _load_target

    g = _corner_picture()
    ground = g == 255
    files = {
        "grey": Image.fromarray(g),
        "rgb": Image.fromarray(np.repeat(g[..., None], 3, axis=2)),
        "grey16": Image.fromarray(g.astype(np.uint16) * 257),
    }
    for stored in (0, 255):  # transparent pixels storing black, or white
        rgb = np.repeat(np.where(ground, stored, g)[..., None], 3, axis=2).astype(np.uint8)
        alpha = np.where(ground, 0, 255).astype(np.uint8)
        files[f"rgba{stored}"] = Image.fromarray(np.dstack([rgb, alpha]), "RGBA")
        files[f"la{stored}"] = Image.fromarray(np.dstack([rgb[..., 0], alpha]), "LA")
    expected = np.repeat(g[..., None], 3, axis=2) / 255.0
    for name, im in files.items():
        path = tmp_path / f"{name}.png"
        im.save(path)
        got = _load_target(str(path), 64)
        np.testing.assert_allclose(got, expected, atol=1e-12, err_msg=name)
    # half-transparent pixels blend with white; averaging down keeps 8-bit levels
    rgba = np.dstack([np.zeros((64, 64, 3), np.uint8), np.full((64, 64), 128, np.uint8)])
    Image.fromarray(rgba, "RGBA").save(tmp_path / "half.png")
    np.testing.assert_allclose(_load_target(str(tmp_path / "half.png"), 64), 127 / 255.0)
    small = _load_target(str(tmp_path / "rgb.png"), 32)
    assert small.shape == (32, 32, 3)
    np.testing.assert_allclose(small * 255.0, np.round(small * 255.0), atol=1e-9)


def test_an_oblong_picture_is_centred_in_a_square_of_its_ground(tmp_path):
    """A picture wider (or taller) than high is the square of its longer side with the picture
    in the middle: the margins take the ground's colour, the figure keeps its pixels; and
    ``meschers inverse`` fits it there."""
    from PIL import Image

    from meschers.inverse_cli import _load_target, inverse_main

    g = _corner_picture()  # 64 x 64, white ground
    cream = np.array([242, 236, 219], dtype=np.uint8)
    rgb = np.where((g == 255)[..., None], cream, np.repeat(g[..., None], 3, axis=2))
    wide = np.concatenate(
        [np.broadcast_to(cream, (64, 16, 3)), rgb, np.broadcast_to(cream, (64, 48, 3))], 1
    )
    Image.fromarray(np.ascontiguousarray(wide)).save(tmp_path / "wide.png")
    Image.fromarray(np.ascontiguousarray(wide.transpose(1, 0, 2))).save(tmp_path / "tall.png")
    for name in ("wide", "tall"):
        got = _load_target(str(tmp_path / f"{name}.png"), 0)
        assert got.shape == (128, 128, 3)
        sq = got if name == "wide" else got.transpose(1, 0, 2)
        # the picture sits in rows 32..95, the margins above and below are the ground
        np.testing.assert_allclose(sq[32:96], wide / 255.0, atol=1e-12)
        np.testing.assert_allclose(
            sq[:32], np.broadcast_to(cream / 255.0, (32, 128, 3)), atol=1e-12
        )
        np.testing.assert_allclose(
            sq[96:], np.broadcast_to(cream / 255.0, (32, 128, 3)), atol=1e-12
        )
    out = tmp_path / "fit"
    args = ["wide.png", "--out", str(out), "--iters", "2", "--resolution", "64", "--no-progress"]
    assert inverse_main([str(tmp_path / args[0]), *args[1:]]) == 0
    assert json.loads((out / "metrics.json").read_text())["silhouette_iou"] > 0.95
