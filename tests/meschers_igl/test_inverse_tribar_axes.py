"""The face directions a picture shows (the inverse benchmark's axis oracle) and a sheared tribar.

A tribar made a real torus by shearing (the development model PenroseTriangle2) shows three face
directions at right angles, as any tribar; its sheared faces, which hold much of its area, are
seen edge-on.  The directions a person reads are those of the faces seen, weighted by the area
they cover on screen.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from meschers_igl.errors import MescherError
from meschers_igl.inverse.metrics import picture_axes
from meschers_igl.inverse.models import BoxModel, boxes_mesh

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"
ISO = np.array([1.0, -1.0, 1.0]) / math.sqrt(3.0)


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def _same_directions(a: np.ndarray, b: np.ndarray, deg: float) -> bool:
    """Rows of ``a`` and ``b`` pair up (either sign) within ``deg`` degrees."""
    cos = np.abs(_unit_rows(a) @ _unit_rows(b).T)
    return bool(
        np.all(cos.max(axis=1) >= math.cos(math.radians(deg)))
        and len(set(np.argmax(cos, axis=1).tolist())) == len(a)
    )


def _unit_rows(a):
    a = np.asarray(a, dtype=np.float64)
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def _plate_seen_edge_on():
    """A 10 x 10 x 0.01 plate whose big faces have the normal (1, 1, 0)/sqrt 2, normal to ISO."""
    V, F = boxes_mesh([[[0.0, 0.0, 0.0], [10.0, 0.01, 10.0]]])
    # rotate the box's y axis onto (1, 1, 0)/sqrt 2 about z; its x axis goes to (1, -1, 0)/sqrt 2
    c = s = math.sqrt(0.5)
    Rz = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    return V @ Rz.T + np.array([3.0, 0.0, 0.0]), F


def test_picture_axes_ignore_faces_seen_edge_on():
    Vc, Fc = boxes_mesh([[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]])
    Vp, Fp = _plate_seen_edge_on()
    n = np.cross(Vp[Fp[:, 1]] - Vp[Fp[:, 0]], Vp[Fp[:, 2]] - Vp[Fp[:, 0]])
    big = np.linalg.norm(n, axis=1) > 1.0  # the plate's 10 x 10 faces
    assert big.sum() == 4
    np.testing.assert_allclose(n[big] @ ISO, 0.0, atol=1e-12)
    V = np.vstack([Vc, Vp])
    F = np.vstack([Fc, Fp + len(Vc)])
    # the plate's big faces hold 200 of the 206.4 units of area, and cover nothing on screen
    axes = picture_axes(V, F, ISO)
    assert _same_directions(axes, np.eye(3), 1e-9)
    # the plate's big faces change nothing; its sides (0.4 of area, along z and (1, -1, 0))
    # only add to z, which then leads
    assert _same_directions(picture_axes(Vc, Fc, ISO), axes, 1e-9)
    assert abs(axes[0, 2]) == pytest.approx(1.0)


def test_picture_axes_turn_with_the_model_and_ignore_orientation():
    rng = np.random.default_rng(3)
    V, F = boxes_mesh([[[0, 0, 0], [4, 1, 1]], [[3, 0, 1], [4, 1, 4]], [[0, 1, 0], [1, 3, 1]]])
    view = _unit([0.3, -0.8, 0.5])
    axes = picture_axes(V, F, view)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    turned = picture_axes(V @ Q.T, F, Q @ view)
    assert _same_directions(turned, axes @ Q.T, 1e-6)
    # inward faces (the triangles reversed) and the view from behind: the same directions
    assert _same_directions(picture_axes(V, F[:, ::-1], -view), axes, 1e-9)
    # the most seen direction first: the y faces cover 0.8 of each unit of area on screen
    assert abs(axes[0] @ [0.0, 1.0, 0.0]) == pytest.approx(1.0)


def test_picture_axes_refuse_bad_input():
    V, F = boxes_mesh([[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]])
    with pytest.raises(MescherError, match="view"):
        picture_axes(V, F, [0.0, 0.0, 0.0])
    with pytest.raises(MescherError, match="V: expected"):
        picture_axes(V[:, :2], F, ISO)
    with pytest.raises(MescherError, match="F: expected"):
        picture_axes(V, F.astype(float), ISO)
    # a flat square seen edge-on shows nothing
    flat = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    with pytest.raises(MescherError, match="edge-on"):
        picture_axes(flat, np.array([[0, 1, 2], [0, 2, 3]]), [1.0, 0.0, 0.0])


def _visible_faces(model: BoxModel, res: int, extent: float = 0.8) -> np.ndarray:
    """(res, res) the model's face nearest the viewer at each pixel centre, -1 off the figure.

    Framed as :func:`meschers.inverse_cli.zbuffer_picture` frames it (row 0 at the top), by
    barycentric coordinates and the largest depth: a z-buffer that is not the code under test.
    """
    C = model.V @ model.camera_frame().T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    P = (C - np.r_[0.5 * (lo + hi), 0.0]) * (2.0 * extent / float((hi - lo).max()))
    g = (np.arange(res) + 0.5) / res * 2.0 - 1.0
    X, Y = np.meshgrid(g, -g)
    q = np.stack([X.ravel(), Y.ravel()], axis=1)
    depth = np.full(len(q), -np.inf)
    face = np.full(len(q), -1)
    for f, (a, b, c) in enumerate(model.F):
        M = np.array([P[b, :2] - P[a, :2], P[c, :2] - P[a, :2]]).T
        if abs(np.linalg.det(M)) < 1e-14:  # seen edge-on
            continue
        u, v = np.linalg.solve(M, (q - P[a, :2]).T)
        z = P[a, 2] + u * (P[b, 2] - P[a, 2]) + v * (P[c, 2] - P[a, 2])
        nearer = (u >= 0) & (v >= 0) & (u + v <= 1) & (z > depth)
        depth[nearer], face[nearer] = z[nearer], f
    return face.reshape(res, res)


def _real_model(name: str) -> BoxModel:
    if not (REAL / "views.json").is_file():
        pytest.skip("the development set of real models is absent")
    import json

    pytest.importorskip("pymeshlab")
    from meshlab_filters.load import load_artist_model

    v = json.loads((REAL / "views.json").read_text())[name]
    V, F, _ = load_artist_model(REAL / name)
    view = _unit(v["view"])
    up = np.asarray(v["up"], float)
    up = _unit(up - (up @ view) * view)
    return BoxModel(name, V, np.asarray(F), view, up, math.nan)


def test_sheared_tribar_axes_are_the_three_directions_its_picture_shows():
    m = _real_model("PenroseTriangle2.obj")
    R = m.camera_frame()
    axes = picture_axes(m.V, m.F, m.view) @ R.T
    # the three directions a person reads are at right angles, as the tribar's
    cos = np.abs(axes @ axes.T)[np.triu_indices(3, 1)]
    assert np.all(cos < math.cos(math.radians(89.9)))
    vis = _visible_faces(m, 128)
    V, F = m.V @ R.T, np.asarray(m.F)
    n = _unit_rows(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]))
    seen = n[vis[vis >= 0]]
    near = np.abs(seen @ axes.T).max(axis=1) >= math.cos(math.radians(10.0))
    # the model's own picture: all but its one sheared face seen nearly edge-on (n_z = 0.09,
    # 4% of the figure) lies on these directions; on the most-area directions it was 65%
    assert near.mean() >= 0.95
    assert np.all(np.abs(seen[~near, 2]) < 0.1)


@pytest.mark.parametrize("light", [(0.19, -0.2, 0.96), (0.74, 0.54, 0.4), (-0.9, -0.44, 0.03)])
def test_sheared_tribar_region_normals_are_the_picture_axes(light):
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse.picture import mescher_from_picture

    m = _real_model("PenroseTriangle2.obj")
    light = _unit(light)
    ground = (0.55, 0.7, 0.9)
    image, _ = zbuffer_picture(m, 128, light=light, ambient=0.2, background=ground)
    _, region, info = mescher_from_picture(image, light, 0.2, background=ground)
    axes = picture_axes(m.V, m.F, m.view) @ m.camera_frame().T
    # the frame is read from region boundaries traced on 128 pixels (bars about 25 pixels
    # wide, creases 40-80 long: a pixel off over 40 is 1.4 degrees) and turned about the light
    # in steps of 0.25 degrees; 0.1 to 1.5 degrees were measured over six lights
    assert _same_directions(info["normals"], axes, 3.0)
    assert np.bincount(region, minlength=3).min() > 0


def test_outer_ground_leaves_the_holes_out():
    from meschers_igl.inverse.faces import _outer_ground

    mask = np.zeros((9, 9), dtype=bool)
    mask[1:8, 1:8] = True
    mask[3:6, 3:6] = False  # a hole
    outer = _outer_ground(mask)
    assert not outer[3:6, 3:6].any() and not outer[mask].any()
    assert outer.sum() == 81 - 49
    # a band across the image leaves two grounds, both on the border; with a ring, a
    # background pixel in a corner is the ground and the one the ring encloses a hole
    band = np.zeros((6, 6), dtype=bool)
    band[2:4, :] = True
    assert np.array_equal(_outer_ground(band), ~band)
    ring = np.ones((5, 5), dtype=bool)
    ring[2, 2] = False
    ring[0, 0] = False
    out = _outer_ground(ring)
    assert out[0, 0] and not out[2, 2]


def test_relief_shared_shade_split_reads_a_hole_outline_as_a_line_inside():
    """The Reutersvärd relief lit so that two face directions are turned away (one shade).

    Each pixel of the dark shade is put on one of its two faces by the lines at the ends of
    its chord; a chord that runs out onto the central hole has often crossed unseen edges
    between dark faces where the bars turn around the hole.  Against the faces the model's
    own z-buffer shows there (an independent picture), the split puts 329 of the figure's
    5501 pixels on the wrong face when a hole's outline counts as the outline (the whole
    face in the nook under the top cube among them) and 278 when it counts as a line inside;
    about 150 of those are one-pixel steps along the unseen creases, which no line shows.
    """
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture
    from meschers_igl.inverse.picture import segment_picture

    m = _real_model("ImpossibleTriangle.obj")
    light = _unit((-0.897, -0.442, 0.029))
    ground = (0.55, 0.7, 0.9)
    image, _ = zbuffer_picture(m, 128, light=light, ambient=0.2, background=ground)
    seg = segment_picture(image, ground, light=light, ambient=0.2)
    assert seg.normals is not None  # two shades: the lines split the shared one
    vis = _visible_faces(m, 128)
    np.testing.assert_array_equal(vis >= 0, seg.labels >= 0)
    V, F = m.V @ m.camera_frame().T, np.asarray(m.F)
    n = _unit_rows(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]))
    n *= np.sign(n[:, 2:3] + 1e-300)  # toward the viewer
    truth = np.argmax(n[vis[vis >= 0]] @ seg.normals.T, axis=1)
    wrong = int(np.sum(truth != seg.labels[vis >= 0]))
    assert wrong < 295, wrong  # 278 measured (329 with every outline first)
