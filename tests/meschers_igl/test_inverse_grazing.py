"""Normals from shades where one face is at the ambient shade and the lit two are near grazing.

``|R^T l| = 1`` gives the dark face's ``n . l`` as ``-sqrt(1 - s_i^2 - s_j^2)``; where the
lit shades' squares sum to nearly 1, a grey level's rounding moves that root by tenths, and
the frame by degrees.  The creases then have to choose among the roots the rounded shades
allow.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from meschers_igl.inverse import shading as sh


def _frame_and_light(seed: int, dark_dot: float):
    """A random frame facing the viewer and a unit light with ``n_2 . l = dark_dot``."""
    rng = np.random.default_rng(seed)
    while True:
        N = Rotation.random(random_state=rng).as_matrix()
        N = N * np.sign(N[:, 2:3])
        if np.linalg.det(N) < 0:
            N[[0, 1]] = N[[1, 0]]
        if N[:, 2].min() > 0.3:
            break
    a = rng.uniform(0.2, 1.2)
    lit = math.sqrt(1.0 - dark_dot**2)
    s = np.array([lit * math.cos(a), lit * math.sin(a), dark_dot])
    light = N.T @ s
    if light[2] <= 0.05:  # the light must face the viewer (upper hemisphere)
        return None
    return N, light


def _angle_deg(A, B) -> float:
    return float(np.degrees(np.arccos(np.clip(np.abs((A * B).sum(axis=1)), -1, 1))).max())


@pytest.mark.parametrize("seed", range(8))
def test_creases_choose_the_dark_root_the_rounded_shades_allow(seed):
    got = None
    for k in range(40):  # a frame whose light faces the viewer
        got = _frame_and_light(100 * seed + k, dark_dot=-0.03)
        if got is not None:
            break
    N, light = got
    amb = 0.2
    shades = amb + (1 - amb) * np.maximum(N @ light, 0.0)
    shades = np.round(shades * 255.0) / 255.0  # an 8-bit picture's grey levels
    # boundaries exactly along the three creases (screen projections of n_i x n_j)
    pairs = np.array([[0, 1], [1, 2], [0, 2]])
    dirs = np.cross(N[pairs[:, 0]], N[pairs[:, 1]])[:, :2]
    new, _ = sh.normals_from_shading(shades, light, amb, dirs, pairs, n_angles=7200)
    old, _ = sh.normals_from_shading(shades, light, amb, dirs, pairs, n_angles=7200, level=0.0)
    err_new, err_old = _angle_deg(new, N), _angle_deg(old, N)
    # the root alone is off by degrees; the roots the rounding allows hold the true one, and
    # the creases (exact here) find it to the search's steps (17 roots, 0.05 degree turns)
    assert err_new < 0.75, (err_new, err_old)
    assert err_new < err_old
    # the lit shades are still met to the rounding (a grey level of slack)
    s = (N @ light)[:2]
    assert np.abs((new @ light)[:2] - s).max() < 1.5 / 255 / (1 - amb) + 1e-9


def test_a_well_conditioned_dark_face_keeps_its_root():
    """Far from grazing the root is fixed to under the spread: one candidate, the root."""
    s = np.array([0.6, 0.5, -0.0])
    c = sh._dark_candidates(s, 1.0 / 255.0 / 0.8)
    assert len(c) == 1
    np.testing.assert_allclose(np.linalg.norm(c[0]), 1.0)
    np.testing.assert_allclose(c[0][2], -math.sqrt(1 - 0.36 - 0.25))
    # near grazing the candidates span the band, each a unit vector with the dark entry <= 0
    g = sh._dark_candidates(np.array([0.6, 0.8, 0.0]), 1.0 / 255.0 / 0.8)
    assert len(g) >= 17
    r = np.array([-v[2] for v in g])
    np.testing.assert_allclose([np.linalg.norm(v) for v in g], 1.0)
    assert r.min() >= 0 and r.max() > math.sin(math.radians(3.0))
    # the lit pair keeps its ratio
    np.testing.assert_allclose([v[0] / v[1] for v in g], 0.75)
