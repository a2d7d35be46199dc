"""Reading a picture: faces from lines, orientations from shades, the light from the creases."""

from __future__ import annotations

import itertools
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

from meschers_igl import MescherError
from meschers_igl.inverse import models as mdl
from meschers_igl.inverse import picture as pic

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"


def _frame(seed: int) -> np.ndarray:
    """Rows: three orthonormal normals, all facing the viewer (n_z > 0.15)."""
    rng = np.random.default_rng(seed)
    while True:
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        n = q.T * np.sign(q.T[:, 2:3])
        if n[:, 2].min() > 0.15 and np.linalg.det(n) != 0:
            return n


def _zbuffer(model, light, res=128, background=(1.0, 1.0, 1.0)):
    pytest.importorskip("pyvista")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from meschers.inverse_cli import zbuffer_picture

    return zbuffer_picture(model, res, light=light, ambient=0.2, background=background)


# ------------------------------------------------------------------------ segmentation


def test_three_means_is_the_best_of_all_partitions():
    # oracle: every assignment of 7 weighted values to 3 non-empty groups (3^7)
    rng = np.random.default_rng(3)
    for _ in range(5):
        v = np.sort(rng.uniform(0, 1, 7))
        w = rng.uniform(0.1, 3.0, 7)
        g = pic._three_means(v, w)

        def cost(lab, v=v, w=w):
            out = 0.0
            for k in range(3):
                sel = lab == k
                if sel.any():
                    out += (w[sel] * (v[sel] - np.average(v[sel], weights=w[sel])) ** 2).sum()
            return out

        best = min(
            cost(np.array(lab))
            for lab in itertools.product(range(3), repeat=7)
            if len(set(lab)) == 3
        )
        assert cost(g) == pytest.approx(best, rel=1e-12, abs=1e-15)
        assert np.all(np.diff(g) >= 0)  # contiguous groups in sorted order


def test_faces_three_grey_levels_apart_are_two_faces():
    # three touching panels: 0.50, 0.50 + 3/255 and 0.80 on white; a histogram peak finder
    # with a 5% window merges the first two
    img = np.ones((60, 60, 3))
    img[10:50, 5:20] = 0.50
    img[10:50, 20:35] = 0.50 + 3 / 255
    img[10:50, 35:55] = 0.80
    seg = pic.segment_picture(img)
    assert seg.labels[30, 10] != seg.labels[30, 25] != seg.labels[30, 45]
    assert len(np.unique(seg.labels[seg.mask])) == 3
    assert np.sort(seg.shades) == pytest.approx([0.50, 0.50 + 3 / 255, 0.80])
    # a small face of a fourth shade (a mitred end) joins the nearest orientation
    img[12:15, 40:43] = 0.95
    seg = pic.segment_picture(img)
    assert seg.labels[13, 41] == seg.labels[30, 45]


def test_no_figure_and_one_shade_for_two_orientations_are_refused():
    with pytest.raises(MescherError, match="expected a figure"):
        pic.segment_picture(np.ones((32, 32, 3)))
    img = np.ones((40, 40, 3))
    img[5:35, 5:20] = 0.2  # two orientations both turned away from the light: one shade
    img[5:35, 20:35] = 0.9
    with pytest.raises(MescherError, match="found 2 distinct shade"):
        pic.segment_picture(img)


# ----------------------------------------------------------------- frame and light


@pytest.mark.parametrize("seed", range(6))
def test_frames_from_creases_recover_the_frame_up_to_its_necker_mirror(seed):
    N = _frame(seed)
    rng = np.random.default_rng(seed + 100)
    d = N[:, :2] / np.linalg.norm(N[:, :2], axis=1, keepdims=True)
    d *= rng.choice([-1.0, 1.0], size=(3, 1))  # a line has no direction
    frames = pic.frames_from_creases(d)
    mirror = N * np.array([-1.0, -1.0, 1.0])
    for F_ in frames:  # each an orthonormal frame facing the viewer
        assert F_ @ F_.T == pytest.approx(np.eye(3), abs=1e-12)
        assert np.all(F_[:, 2] > 0)
    err = [min(np.abs(F_ - N).max(), np.abs(F_ - mirror).max()) for F_ in frames]
    assert max(err) < 1e-12
    assert np.abs(frames[0] - frames[1]).max() > 1e-3  # the two readings differ


def test_frames_from_creases_refuse_directions_no_frame_projects_to():
    d = np.array([[1.0, 0.0], [math.cos(0.3), math.sin(0.3)], [math.cos(0.5), math.sin(0.5)]])
    with pytest.raises(MescherError, match="right-angled"):
        pic.frames_from_creases(d)


@pytest.mark.parametrize("shadow", [False, True])
def test_estimate_light_inverts_the_lambertian_shades(shadow):
    N = _frame(7)
    rng = np.random.default_rng(1)
    for _ in range(20):
        lvec = rng.normal(size=3)
        lvec /= np.linalg.norm(lvec)
        s = N @ lvec
        if (np.sum(s <= 0.05) != (1 if shadow else 0)) or np.any((s > 0) & (s < 0.05)):
            continue
        shades = 0.2 + 0.8 * np.maximum(s, 0.0)
        assert pic.estimate_light(shades, N, 0.2) == pytest.approx(lvec, abs=1e-12)


def test_light_is_read_from_a_zbuffered_tribar():
    # light from above (l_y > 0): of the two Necker readings the one a person takes
    light = np.array([-0.5, 0.35, 1.0])
    image, _ = _zbuffer(mdl.penrose_tribar(), light)
    _, _, info = pic.mescher_from_picture(image, None, 0.2)
    cos = info["light"] @ (light / np.linalg.norm(light))
    assert math.degrees(math.acos(min(cos, 1.0))) < 2.0
    axes = mdl.penrose_tribar().axes_in_camera()
    err = np.degrees(np.arccos(np.clip(np.abs(info["normals"] @ axes.T).max(axis=1), -1, 1)))
    assert err.max() < 2.0


# ------------------------------------------------------------ pictures of real files


def _real(name):
    if not (REAL / "views.json").is_file():
        pytest.skip("the development set of real models is absent")
    from meshlab_filters.load import load_artist_model

    v = json.loads((REAL / "views.json").read_text())[name]
    V, F, _ = load_artist_model(REAL / name)
    view = np.asarray(v["view"], float) / np.linalg.norm(v["view"])
    up = np.asarray(v["up"], float)
    up = up - (up @ view) * view
    return mdl.BoxModel(name, V, np.asarray(F), view, up / np.linalg.norm(up), 0.0)


@pytest.mark.parametrize(
    "light",
    [(0.79, 0.31, 0.52), (0.19, -0.2, 0.96)],  # faces 9 levels apart; shades 121, 175, 197
)
def test_real_tribar_picture_is_read_with_the_models_face_directions(light):
    model = _real("PenroseTriangle.obj")
    light = np.asarray(light) / np.linalg.norm(light)
    ground = (0.55, 0.7, 0.9)
    image, _ = _zbuffer(model, light, background=ground)
    m, _, info = pic.mescher_from_picture(image, light, 0.2, background=ground)
    assert m.is_impossible()
    # the file's faces are its axes (a Blender box model)
    axes = model.camera_frame().T
    err = np.degrees(np.arccos(np.clip(np.abs(info["normals"] @ axes.T).max(axis=1), -1, 1)))
    assert err.max() < 2.0
    # read again without the light: the same light or its Necker mirror
    _, _, est = pic.mescher_from_picture(image, None, 0.2, background=ground)
    mirror = light * np.array([-1.0, -1.0, 1.0])
    best = max(est["light"] @ light, est["light"] @ mirror)
    assert math.degrees(math.acos(min(best, 1.0))) < 2.0


@pytest.mark.parametrize("res", [128, 256, 512])
def test_tribar_period_at_any_resolution(res):
    # an occlusion cut stops a pixel and a half short of the outline at every resolution (a
    # long straight constraint kept as one edge stopped it 16 pixels short at 256^2: period
    # 0.775 of the gap, the hole's step instead of the outline's)
    from meschers_igl.inverse.metrics import figure_period

    model = mdl.penrose_tribar()
    light = np.array([0.19, -0.2, 0.96])
    image, scale = _zbuffer(model, light, res)
    m, _, _ = pic.mescher_from_picture(image, light, 0.2)
    assert figure_period(m) == pytest.approx(model.gap * scale, rel=0.02)
