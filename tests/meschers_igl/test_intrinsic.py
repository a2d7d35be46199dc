"""A triangle from its edge lengths (meschers_igl.intrinsic): hand-computed triangles, libigl.

Hand cases: the 3-4-5 right triangle (2A = 12; angles atan(3/4), atan(4/3), pi/2), the unit
right isosceles triangle (hat gradients (-1,-1), (1,0), (0,1)), the equilateral triangle, and a
needle whose area the textbook Heron formula gets wrong.
"""

from __future__ import annotations

import igl
import numpy as np
import pytest

from meschers_igl import MescherError, intrinsic

L345 = np.array([[3.0, 4.0, 5.0]])  # corner 2 is the right angle (opposite the hypotenuse)


def _random_lengths(n=500, seed=0):
    V = np.random.default_rng(seed).standard_normal((3 * n, 3))
    F = np.arange(3 * n).reshape(n, 3)
    return np.sqrt(igl.squared_edge_lengths(V, F)), V, F


def test_double_areas_by_hand_and_libigl():
    assert intrinsic.double_areas(L345)[0] == 12.0
    np.testing.assert_allclose(
        intrinsic.double_areas([[2.0, 2.0, 2.0]]), 2 * np.sqrt(3), rtol=1e-15
    )
    # a needle: sides 1, 1, c -> 2A = c sqrt(1 - c^2/4); plain Heron loses every digit here
    c = 1e-9
    dbl = intrinsic.double_areas([[1.0, 1.0, c]])[0]
    assert abs(dbl - c * np.sqrt(1 - c * c / 4)) < 1e-15 * c
    # a nearly flat cap: sides 1, 1, 2 - d with 2A = (2 - d) sqrt(1 - (1 - d/2)^2) ~ 2 sqrt(d)
    d = 2.0**-40  # 2 - d is exact in binary
    h = np.sqrt(d - d * d / 4)  # height over the long side, written without cancellation
    assert abs(intrinsic.double_areas([[1.0, 1.0, 2 - d]])[0] - (2 - d) * h) < 1e-12 * h
    # violating the triangle inequality: 0, as igl.doublearea(l, 0)
    assert intrinsic.double_areas([[1.0, 1.0, 3.0]])[0] == 0.0
    l, V, F = _random_lengths()
    np.testing.assert_allclose(intrinsic.double_areas(l), igl.doublearea(V, F), rtol=1e-12)


def test_cotangents_and_angles_by_hand():
    np.testing.assert_allclose(intrinsic.cotangents(L345)[0], [4 / 3, 3 / 4, 0.0], atol=1e-15)
    np.testing.assert_allclose(intrinsic.half_cotangents(L345)[0], [2 / 3, 3 / 8, 0.0], atol=1e-15)
    np.testing.assert_allclose(
        intrinsic.corner_angles(L345)[0],
        [np.arctan(3 / 4), np.arctan(4 / 3), np.pi / 2],
        rtol=1e-15,
    )
    np.testing.assert_allclose(intrinsic.corner_angles([[1.0, 1.0, 1.0]]), np.pi / 3, rtol=1e-15)
    l, V, F = _random_lengths()
    np.testing.assert_allclose(intrinsic.half_cotangents(l), igl.cotmatrix_entries(l), atol=1e-10)
    np.testing.assert_allclose(intrinsic.corner_angles(l), igl.internal_angles(V, F), atol=1e-12)
    np.testing.assert_allclose(intrinsic.corner_angles(l).sum(axis=1), np.pi, rtol=1e-14)
    # a needle's tiny angle keeps its relative accuracy (arccos would not)
    a = intrinsic.corner_angles([[1e-9, 1.0, 1.0]])[0, 0]
    assert abs(a - 1e-9) < 1e-22
    # zero-area faces carry no cotangent weight instead of inf
    assert np.all(intrinsic.half_cotangents([[1.0, 1.0, 2.0]]) == 0.0)


def test_layout_by_hand_and_lengths_kept():
    P = intrinsic.layout(L345)[0]
    np.testing.assert_allclose(P, [[0, 0], [5, 0], [3.2, 2.4]], atol=1e-15)
    l, _, _ = _random_lengths()
    P = intrinsic.layout(l)
    back = np.linalg.norm(P[:, [2, 0, 1]] - P[:, [1, 2, 0]], axis=2)  # opposite each corner
    np.testing.assert_allclose(back, l, rtol=1e-11)
    a, b = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    assert (cross > 0).all()  # counter-clockwise


def test_place_apex_by_hand():
    c = intrinsic.place_apex([0.0, 0.0], [5.0, 0.0], 4.0, 3.0)
    np.testing.assert_allclose(c, [3.2, 2.4], atol=1e-15)
    c = intrinsic.place_apex([0.0, 0.0], [5.0, 0.0], 4.0, 3.0, side=-1.0)
    np.testing.assert_allclose(c, [3.2, -2.4], atol=1e-15)
    # rotated and moved segment: the apex moves with it; vectorized over segments
    th = 0.7
    R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    pa, pb = np.array([[1.0, 2.0]] * 2), np.array([[1.0, 2.0]] * 2) + (R @ [5.0, 0.0])
    c = intrinsic.place_apex(pa, pb, [4.0, 4.0], [3.0, 3.0], [1.0, -1.0])
    np.testing.assert_allclose(c[0], [1.0, 2.0] + R @ [3.2, 2.4], atol=1e-14)
    np.testing.assert_allclose(c[1], [1.0, 2.0] + R @ [3.2, -2.4], atol=1e-14)


def test_hat_gradient_gram_by_hand():
    # p0 = (0,0), p1 = (1,0), p2 = (0,1): grad phi = (-1,-1), (1,0), (0,1)
    K, area = intrinsic.hat_gradient_gram([[np.sqrt(2), 1.0, 1.0]])
    np.testing.assert_allclose(K[0], [[2, -1, -1], [-1, 1, 0], [-1, 0, 1]], atol=1e-15)
    assert area[0] == pytest.approx(0.5, rel=1e-15)
    # A K is the face's block of -cotmatrix
    l, V, F = _random_lengths(50)
    K, area = intrinsic.hat_gradient_gram(l)
    L = igl.cotmatrix(V, F).toarray()
    blocks = -L[F[:, :, None], F[:, None, :]]
    np.testing.assert_allclose(area[:, None, None] * K, blocks, atol=1e-10)


def test_mollify_by_hand():
    lm, eps = intrinsic.mollify(L345)
    assert eps == 0.0 and lm is not None and np.array_equal(lm, L345)
    l = np.array([[1.0, 1.0, 2.0]])  # flat: slack 0
    lm, eps = intrinsic.mollify(l)
    assert eps == pytest.approx(1e-5 * 4 / 3, rel=1e-12)
    np.testing.assert_allclose(lm, l + eps)
    assert intrinsic.double_areas(lm)[0] > 0


def test_delaunay_check_and_flip_on_a_rhombus():
    # rhombus 0-1-2-3 with the long diagonal 0-2 as the shared edge: both angles opposite it are
    # 2 atan(2) = 126.9 degrees > 90, so edge 0-2 is not Delaunay; the flip makes 1-3 the edge
    V = np.array([[-2.0, 0, 0], [0, -1, 0], [2, 0, 0], [0, 1, 0]])
    F = np.array([[0, 1, 2], [0, 2, 3]])
    l = np.sqrt(igl.squared_edge_lengths(V, F))
    D = intrinsic.is_delaunay(l, F)
    assert not D[0, 1] and not D[1, 2]  # the shared edge, seen from each face
    assert D[0, 0] and D[0, 2] and D[1, 0] and D[1, 1]  # boundary edges
    lo, Fo, fe = intrinsic.intrinsic_delaunay(l, F)
    assert intrinsic.is_delaunay(lo, Fo).all()
    assert Fo.shape == (2, 3) and np.isclose(intrinsic.double_areas(lo).sum(), 8.0)
    shared = np.intersect1d(fe[0], fe[1])
    assert shared.size == 1  # one interior edge, of length |1 3| = 2
    f, c = np.nonzero(fe == shared[0])
    np.testing.assert_allclose(lo[f, c], 2.0)
    # a right angle on both sides (grid diagonal) counts as Delaunay despite round-off
    Vs = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    Fs = np.array([[0, 1, 2], [0, 2, 3]])
    assert intrinsic.is_delaunay(np.sqrt(igl.squared_edge_lengths(Vs, Fs)), Fs).all()


def test_midpoint_refine_one_triangle_by_hand():
    F = np.array([[0, 1, 2]])
    edges = np.array([[1, 2], [2, 0], [0, 1]])
    fe = np.array([[0, 1, 2]])
    lc, Fc, n = intrinsic.midpoint_refine(L345, F, edges, fe, 3)
    assert n == 6 and Fc.shape == (4, 3)
    np.testing.assert_allclose(np.sort(lc, axis=1), np.tile([1.5, 2.0, 2.5], (4, 1)))
    np.testing.assert_allclose(intrinsic.double_areas(lc), 3.0)
    # each child's lengths are those of a real layout: vertex 3 + e sits mid-edge e
    P = np.r_[intrinsic.layout(L345)[0], np.zeros((3, 2))]
    P[3:] = 0.5 * (P[edges[:, 0]] + P[edges[:, 1]])
    real = np.linalg.norm(P[Fc[:, [2, 0, 1]]] - P[Fc[:, [1, 2, 0]]], axis=2)
    np.testing.assert_allclose(lc, real, atol=1e-14)


def test_bad_lengths_raise():
    with pytest.raises(MescherError, match="l: expected"):
        intrinsic.double_areas(np.ones((3, 2)))


def test_apex_offsets_one_layout_for_arrays_and_kernels():
    """The apex over a segment keeps both distances (also on needles, where sqrt(la^2 - x^2)
    cancels), and the compiled scalar equals the vectorized form."""
    from meschers_igl.intrinsic import apex_kernel, apex_offsets

    rng = np.random.default_rng(0)
    a, b = rng.uniform(0.1, 1.0, 200), rng.uniform(0.1, 1.0, 200)
    base = np.abs(a - b) + rng.uniform(0.0, 1.0, 200) * (a + b - np.abs(a - b))
    base = np.r_[base, 1.0, 2.0]  # a needle (height 1e-6) and a degenerate flat triangle
    needle = np.hypot(0.5, 1e-6)
    a, b = np.r_[a, needle, 1.0], np.r_[b, needle, 1.0]
    x, y = apex_offsets(base, a, b)
    assert (y >= 0).all()
    np.testing.assert_allclose(np.hypot(x, y), a, rtol=1e-12)
    np.testing.assert_allclose(np.hypot(x - base, y), b, rtol=1e-12)
    assert y[-2] == pytest.approx(1e-6, rel=1e-3) and y[-1] == 0.0
    kernel = apex_kernel()
    for k in range(base.size):
        np.testing.assert_allclose(
            kernel(base[k], a[k], b[k]), (x[k], y[k]), rtol=1e-14, atol=1e-300
        )
