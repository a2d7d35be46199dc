"""What a drawing shows that its shaded reading cannot: the orientation a face takes from its
neighbours where its own edges allow two, and the lines between parallel faces (a stair's
tread over the one below).  Checked against the painter's picture of the mescher the project's
line art was drawn from: its faces' normals and its occlusion lines."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import MescherError
from meschers_igl.inverse import drawing as drw

pytestmark = pytest.mark.render


def _to_picture(P: np.ndarray, box) -> np.ndarray:
    """Screen points of the mescher -> the drawing's screen square ``[-1, 1]^2``."""
    x0, x1, y0, y1 = box
    return np.stack(
        [(P[:, 0] - x0) / (x1 - x0) * 2.0 - 1.0, (P[:, 1] - y0) / (y1 - y0) * 2.0 - 1.0], axis=1
    )


def _samples(segments, step: float) -> np.ndarray:
    """Points every ``step`` (or closer) along each (2, 2) segment."""
    out = []
    for a, b in segments:
        n = max(int(np.ceil(np.linalg.norm(b - a) / step)), 1)
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        out.append(a + t * (b - a))
    return np.concatenate(out) if out else np.zeros((0, 2))


def _distance(P: np.ndarray, segments) -> np.ndarray:
    """Distance of each point to the nearest of the segments."""
    S = np.asarray(segments, dtype=np.float64)  # (K, 2, 2)
    a, d = S[:, 0], S[:, 1] - S[:, 0]
    t = np.einsum("pkj,kj->pk", P[:, None] - a[None], d) / np.maximum((d * d).sum(1), 1e-300)
    q = a[None] + np.clip(t, 0.0, 1.0)[..., None] * d[None]
    return np.linalg.norm(P[:, None] - q, axis=2).min(axis=1)


@pytest.mark.parametrize(
    "spec",
    [
        "penrose_stairs",
        "penrose_triangle",
        "paradox:reutersvard_rectangle__iso_exact",
        "paradox:impossible_arch__iso_exact",
        "paradox:reutersvard_rectangle__axo_x60_z30",
        "paradox:impossible_cube__construction_frame",
        "paradox:impossible_cube__rot_blender290",
    ],
)
def test_faces_take_the_orientation_of_the_meschers_faces(tmp_path, line_art, spec):
    """Nearly every pixel of the reading has the normal of the mescher's face seen there.  The
    wall under the Penrose stairs' back flight shows the treads' edges in front of it along
    both of its other directions; its creases with the treads make it a wall (read by its own
    edges alone, 11% of the figure was a tread).  The impossible cubes' back bars pass behind
    the posts: the posts' edges are not theirs (with them, 10-13% of the cubes and 9% of the
    axonometric Reutersvärd rectangle took another orientation)."""
    from meschers_igl.painter import visible_faces

    picture, _, (m, order, box) = line_art(spec, tmp_path / "d.png")
    r = drw.shade_drawing(picture)
    seen = visible_faces(m, order, size=picture.shape[0], bounds=box)
    n = m.face_normals() * np.sign(m.face_normals()[:, 2:3])
    on = (r.faces >= 0) & (seen >= 0)
    read = r.normals[r.orientation[r.faces[on]]]
    cos = np.clip((read * n[seen[on]]).sum(axis=1), -1.0, 1.0)
    assert np.mean(np.degrees(np.arccos(cos)) < 5.0) >= 0.98


def test_steps_are_the_occlusion_lines_between_parallel_faces(tmp_path, line_art):
    """The Penrose stairs' line art: the lines the reading finds between two faces of one
    orientation lie on the mescher's occlusion lines, and they cover the stretches of those
    where the faces on the two sides are parallel (a tread over the next)."""
    from meschers_igl.lines import KINDS, line_drawing
    from meschers_igl.painter import visible_faces

    picture, _, (m, order, box) = line_art("penrose_stairs", tmp_path / "d.png")
    N = picture.shape[0]
    px = 2.0 / N
    r = drw.shade_drawing(picture)
    assert r.steps
    ld = line_drawing(m, order)
    occl = [
        _to_picture(ld.points[ld.offsets[i] : ld.offsets[i + 1]], box)
        for i in range(ld.n_lines)
        if KINDS[ld.kind[i]] == "occlusion" and ld.visible[i]
    ]
    true = [np.stack([c[k], c[k + 1]]) for c in occl for k in range(len(c) - 1)]
    # precision: every step lies along a drawn occlusion line of the mescher (within the
    # straightening's 0.75 pixel, a pixel's quantization and half a line's width)
    assert np.all(_distance(_samples(r.steps, 0.5 * px), true) < 2.0 * px)
    # recall: where the faces three pixels to either side of an occlusion line are parallel
    seen = visible_faces(m, order, size=N, bounds=box)
    nrm = m.face_normals()

    def face(Q):  # the mescher's face seen at picture points Q (-1: none)
        j = np.clip(np.floor((Q[:, 0] + 1.0) / px).astype(np.int64), 0, N - 1)
        i = np.clip(np.floor((1.0 - Q[:, 1]) / px).astype(np.int64), 0, N - 1)
        return seen[i, j]

    pts, across = [], []
    for a, b in true:
        q = _samples([(a, b)], 0.5 * px)
        u = (b - a) / np.linalg.norm(b - a)
        pts.append(q)
        across.append(np.repeat([[-u[1], u[0]]], len(q), axis=0))
    P, w = np.concatenate(pts), 3.0 * px * np.concatenate(across)
    f, g = face(P + w), face(P - w)
    both = (f >= 0) & (g >= 0) & (f != g)
    parallel = both.copy()
    parallel[both] = np.abs((nrm[f[both]] * nrm[g[both]]).sum(axis=1)) > np.cos(np.radians(1.0))
    assert parallel.sum() > 100  # the stairs' treads, one over the next
    # (93% measured: the rest lie within three pixels of a line's end, where a side is off it)
    assert np.mean(_distance(P[parallel], r.steps) < 2.0 * px) >= 0.85


def test_known_steps_are_cut_and_read_the_climb(tmp_path, line_art):
    """``mescher_from_picture(steps=...)`` cuts the mesh along each step it is given: the
    middle of every step lies on the mesh's boundary.  Reading the Penrose stairs' line art
    with its steps climbs much closer to the mescher's period than with the steps guessed from
    the shaded reading's jogs (at 128 pixels: -17% against -23%)."""
    from meschers.inverse_cli import _resize_flat
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture
    from meschers_igl.topology import boundary_edge_mask

    picture, period, _ = line_art("penrose_stairs", tmp_path / "d.png")
    r = drw.shade_drawing(picture)
    target = _resize_flat(r.picture, 128)
    m, _, info = mescher_from_picture(target, r.light, 0.2, steps=r.steps)
    assert len(info["hidden_lines"]) == len(r.steps)
    E = np.asarray(m.edges)
    rim = E[boundary_edge_mask(np.asarray(m.face_edges), m.n_edges)]
    ends = [m.xy[rim[:, 0]], m.xy[rim[:, 1]]]
    mids = np.array([0.5 * (a + b) for a, b in r.steps])
    assert np.all(_distance(mids, np.stack(ends, axis=1)) < 1e-3 * 2.0 / 128)  # on an edge
    guessed, _, _ = mescher_from_picture(target, r.light, 0.2)
    assert abs(figure_period(m) / period - 1) < abs(figure_period(guessed) / period - 1) - 0.03


@pytest.mark.xfail(strict=True, reason="the walls under the flights step out of sight (-17%)")
def test_the_stairs_line_art_reads_its_period(tmp_path, line_art):
    """Exactly isometric, the wall under a flight is one region of the drawing though its
    pieces under successive treads are parallel planes one in front of the next; only the
    jogs of its lower edge show it.  With the walls read as one plane the climb is 17% short
    at 128 pixels (17% at 256)."""
    from meschers.inverse_cli import _resize_flat
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.picture import mescher_from_picture

    picture, period, _ = line_art("penrose_stairs", tmp_path / "d.png")
    r = drw.shade_drawing(picture)
    m, _, _ = mescher_from_picture(_resize_flat(r.picture, 128), r.light, 0.2, steps=r.steps)
    assert figure_period(m) == pytest.approx(period, rel=0.05)


def test_steps_must_be_segments():
    from meschers_igl.inverse.picture import mescher_from_picture

    picture = np.ones((32, 32, 3))
    for bad in ([[0.0, 0.0, 1.0]], [[[0.1, 0.1], [0.1, 0.1]]], [[[0.0, np.nan], [0.5, 0.5]]]):
        with pytest.raises(MescherError, match="steps"):
            mescher_from_picture(picture, (0.3, 0.4, 1.0), 0.2, steps=bad)
