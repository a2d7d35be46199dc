"""Turning a mescher: identities of the Poisson re-projection (meschers_igl.rotation)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from meschers_igl import DepthOrder, Mescher, MescherError, shapes
from meschers_igl.gallery import get_model
from meschers_igl.operators import view_frame
from meschers_igl.rotation import rotate, rotation_matrix

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"


def _turned_about_centroid(m: Mescher, P: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Camera-frame points ``P`` turned by ``R`` about their star0-weighted centroid."""
    w = m.star0.diagonal()
    c = (w @ P) / w.sum()
    return (P - c) @ R.T + c


def _check_equals_turned_mesh(V: np.ndarray, F: np.ndarray, degrees: float, axis) -> None:
    m = Mescher.from_mesh(V, F)
    R = rotation_matrix(degrees, axis)
    turn = rotate(m, degrees, axis)
    ref = Mescher.from_mesh(V @ R.T, F)  # the 3D mesh turned, seen head-on
    np.testing.assert_array_equal(ref.edges, turn.mescher.edges)
    scale = m.scale()
    np.testing.assert_allclose(turn.mescher.zeta, ref.zeta, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(
        turn.mescher.xy, _turned_about_centroid(m, V, R)[:, :2], rtol=0, atol=1e-10 * scale
    )
    assert turn.residual < 1e-10
    np.testing.assert_allclose(turn.mescher.face_normals(), m.face_normals() @ R.T, atol=1e-9)


def test_rotation_matrix_identity_and_axes():
    np.testing.assert_array_equal(rotation_matrix(0.0, "x"), np.eye(3))
    np.testing.assert_array_equal(rotation_matrix(0, (1.0, 2.0, 3.0)), np.eye(3))
    R = rotation_matrix(90.0, "y")  # right-handed about y: +x goes to -z, +z to +x
    np.testing.assert_allclose(R @ [1, 0, 0], [0, 0, -1], atol=1e-15)
    np.testing.assert_allclose(R @ [0, 0, 1], [1, 0, 0], atol=1e-15)
    R = rotation_matrix(90.0, "x")  # the top comes toward the viewer
    np.testing.assert_allclose(R @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    R = rotation_matrix(37.0, (1.0, -2.0, 0.5))
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.isclose(np.linalg.det(R), 1.0)
    axis = np.array([1.0, -2.0, 0.5])
    np.testing.assert_allclose(R @ axis, axis, atol=1e-14)
    assert np.isclose(np.trace(R), 1 + 2 * np.cos(np.deg2rad(37.0)))


@pytest.mark.parametrize(
    "degrees, axis, words",
    [
        ("a", "x", "degrees: expected a number"),
        (float("nan"), "x", "degrees: expected a finite number"),
        (5.0, "w", "axis: expected 'x', 'y', 'z'"),
        (5.0, (0.0, 0.0, 0.0), "axis: expected a non-zero direction"),
        (5.0, (1.0, 0.0), "axis"),
    ],
)
def test_bad_arguments(degrees, axis, words):
    m = shapes.impossible_torus(12, 6, climb=1.0)
    with pytest.raises(MescherError, match=words):
        m.rotated(degrees, axis)


def test_bad_depth_offsets():
    m = shapes.impossible_torus(12, 6, climb=1.0)
    with pytest.raises(MescherError, match="depth_offsets"):
        rotate(m, 5.0, "y", depth_offsets=[0.0, 1.0])


@pytest.mark.parametrize("name", ["penrose_triangle", "impossibagel", "impossible_cube"])
def test_zero_degrees_is_the_identity(name):
    gm = get_model(name)
    m = gm.mescher
    m0, order0 = m.rotated(0.0, "x", order=gm.order)
    scale = m.scale()
    np.testing.assert_allclose(m0.xy, m.xy, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(m0.zeta, m.zeta, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(m0.periods(), m.periods(), rtol=0, atol=1e-12 * scale)
    # the order carried at 0 degrees is the order on the faces that overlap
    assert set(order0.graph.edges) == set(gm.order.follow(m).graph.edges)


@pytest.mark.parametrize("axis", ["x", "y", (0.3, -1.0, 0.4)])
@pytest.mark.parametrize("degrees", [3.0, 17.0, -40.0])
def test_possible_mescher_equals_turned_mesh(degrees, axis):
    V, F = shapes.torus(32, 12)
    V = V @ shapes.random_rotation(7).T
    _check_equals_turned_mesh(V, F, degrees, axis)


def test_possible_mescher_with_boundary_equals_turned_mesh():
    V, F = shapes.grid(9, 8)
    rng = np.random.default_rng(3)
    V = V + np.c_[0.02 * rng.standard_normal((len(V), 2)), 0.3 * rng.standard_normal(len(V))]
    _check_equals_turned_mesh(V, F, 11.0, "y")


def test_parts_at_given_depths_equal_turned_mesh():
    """Two tori apart in depth: the offsets of their centroids place them after the turn."""
    V1, F1 = shapes.torus(20, 8)
    V2 = V1 + [3.0, 0.5, -2.0]
    V, F = np.vstack([V1, V2]), np.vstack([F1, F1 + len(V1)])
    m = Mescher.from_mesh(V, F)
    w = m.star0.diagonal()
    labels = m.exact_part_solver().labels
    offsets = np.bincount(labels, weights=w * V[:, 2]) / np.bincount(labels, weights=w)
    R = rotation_matrix(14.0, "y")
    turn = rotate(m, 14.0, "y", depth_offsets=offsets)
    np.testing.assert_allclose(
        turn.mescher.xy, _turned_about_centroid(m, V, R)[:, :2], rtol=0, atol=1e-10
    )
    # without the offsets both parts turn about one depth: they land 2 sin(14 deg) closer in x
    apart = rotate(m, 14.0, "y").mescher.xy - turn.mescher.xy
    assert np.isclose(np.ptp(apart[:, 0]), 2.0 * np.sin(np.deg2rad(14.0)), rtol=1e-9)
    assert np.ptp(apart[:, 1]) < 1e-12


@pytest.mark.parametrize("axis", ["x", "y"])
@pytest.mark.parametrize("degrees", [1.0, 8.0, 20.0])
def test_impossible_mescher_loses_only_the_harmonic_screen_part(degrees, axis):
    m = shapes.impossible_torus(40, 14, climb=1.0)
    h = m.hodge()
    turn = rotate(m, degrees, axis)
    R = turn.matrix
    # the dropped screen 1-forms are R[:2, 2] * omega: harmonic (closed and co-closed)
    np.testing.assert_allclose(turn.lost, np.outer(h.omega, R[:2, 2]), rtol=0, atol=1e-11)
    assert np.abs(m.d12 @ turn.lost).max() < 1e-12
    s1 = m.star1.diagonal()
    assert np.abs(m.d01.T @ (s1[:, None] * turn.lost)).max() < 1e-11
    # periods keep their meaning (same loops): the depth component of the turned jump
    np.testing.assert_allclose(turn.mescher.periods(), R[2, 2] * m.periods(), atol=1e-12)
    assert turn.mescher.is_impossible()
    # the residual is the harmonic share of the turned screen forms
    E = m.edges
    e3 = np.c_[m.xy[E[:, 1]] - m.xy[E[:, 0]], m.zeta] @ R.T
    w = np.abs(s1)
    expect = np.sqrt(np.sum(w * h.omega**2)) * np.linalg.norm(R[:2, 2])
    expect /= np.sqrt(np.sum(w[:, None] * e3[:, :2] ** 2))
    assert np.isclose(turn.residual, expect, rtol=1e-9)
    assert 0 < turn.residual < np.sin(np.deg2rad(abs(degrees))) + 1e-12


def test_each_triangle_is_turned_up_to_what_was_lost():
    """The turned mescher's edge vectors are R e minus the lost screen part, per edge."""
    m = get_model("penrose_stairs").mescher
    turn = rotate(m, 6.0, "x")
    t = turn.mescher
    E = m.edges
    e_old = np.c_[m.xy[E[:, 1]] - m.xy[E[:, 0]], m.zeta]
    e_new = np.c_[t.xy[E[:, 1]] - t.xy[E[:, 0]], t.zeta]
    expect = e_old @ turn.matrix.T - np.c_[turn.lost, np.zeros(len(E))]
    np.testing.assert_allclose(e_new, expect, rtol=0, atol=1e-11 * m.scale())


def test_view_axis_turn_is_rigid_on_screen():
    m = shapes.impossible_torus(24, 8, climb=1.5)
    turn = rotate(m, 33.0, "z")
    assert turn.residual == 0.0
    np.testing.assert_allclose(turn.mescher.zeta, m.zeta, atol=1e-14)
    np.testing.assert_allclose(turn.mescher.edge_lengths(), m.edge_lengths(), rtol=1e-12)
    np.testing.assert_allclose(turn.mescher.periods(), m.periods(), atol=1e-14)


def test_turns_compose_for_possible_meschers_only():
    V, F = shapes.torus(24, 10)
    m = Mescher.from_mesh(V @ shapes.random_rotation(2).T, F)
    a = m.rotated(7.0, "y").rotated(5.0, "y")
    b = m.rotated(12.0, "y")
    np.testing.assert_allclose(a.xy, b.xy, atol=1e-10)
    np.testing.assert_allclose(a.zeta, b.zeta, atol=1e-10)
    mi = shapes.impossible_torus(24, 10, climb=1.0)
    a = mi.rotated(10.0, "y").rotated(-10.0, "y")  # turning back does not restore what was lost
    assert np.abs(a.periods() - mi.periods()).max() > 1e-3


def test_order_follows_the_turn():
    gm = get_model("penrose_triangle")
    m, order = gm.mescher.rotated(10.0, "y", order=gm.order)
    assert isinstance(order, DepthOrder)
    assert order.graph.number_of_nodes() == m.n_faces
    assert set(order.graph.edges) == set(gm.order.follow(m).graph.edges)


@pytest.mark.skipif(not REAL.is_dir(), reason="real models folder absent")
@pytest.mark.parametrize("name", ["PenroseTriangle2.obj", "EscherCube.obj"])
def test_real_model_seen_from_its_view_turns_like_the_mesh(name):
    from meshlab_filters import load_artist_model

    views = json.loads((REAL / "views.json").read_text())
    V, F, _ = load_artist_model(REAL / name)
    C = V @ view_frame(views[name]["view"], views[name]["up"]).T  # camera frame
    _check_equals_turned_mesh(C, F, 9.0, "x")


def test_turned_depths_are_closed_and_projection_is_a_no_op(monkeypatch):
    """c = R20 d01 x + R21 d01 y + R22 zeta is closed: projecting it changes nothing."""
    import meschers_igl.rotation as rotation

    m = get_model("penrose_stairs").mescher
    plain = rotate(m, 12.0, "x").mescher
    assert np.abs(plain.integrability_residual()).max() < 1e-12 * m.scale()
    monkeypatch.setattr(rotation, "ROUND_OFF_RTOL", -1.0)  # always project
    projected = rotate(m, 12.0, "x").mescher
    np.testing.assert_allclose(projected.zeta, plain.zeta, rtol=0, atol=1e-12 * m.scale())
