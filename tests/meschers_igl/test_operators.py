"""Operators equal libigl's on embeddable meshes; DEC identities; hand-computed triangles."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp

from meschers_igl import Mescher, shapes

TOL = 1e-10


def _max(A):
    A = A.toarray() if sp.issparse(A) else np.asarray(A)
    return float(np.abs(A).max(initial=0.0))


def test_operators_equal_libigl(embedded_mesh):
    _, V, F = embedded_mesh
    m = Mescher.from_mesh(V, F)
    assert _max(m.cotmatrix() - igl.cotmatrix(V, F)) < TOL
    assert _max(m.massmatrix() - igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)) < TOL
    assert (
        _max(m.massmatrix("barycentric") - igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC))
        < TOL
    )
    assert _max(m.grad() - igl.grad(V, F)) < TOL
    assert _max(m.face_areas() - igl.doublearea(V, F) / 2) < TOL
    assert _max(m.face_normals() - igl.per_face_normals(V, F, np.array([0.0, 0, 1]))) < TOL
    E = m.edges
    assert _max(m.edge_lengths() - np.linalg.norm(V[E[:, 1]] - V[E[:, 0]], axis=1)) < TOL
    # vertex normals: area weighted
    vn = igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA)
    assert _max(m.vertex_normals() - vn) < 1e-8


def test_operators_invariant_to_view(embedded_mesh):
    """Intrinsic operators do not depend on the view; normals rotate with it."""
    _, V, F = embedded_mesh
    R = shapes.random_rotation(7)
    a = Mescher.from_mesh(V, F)
    b = Mescher.from_mesh(V @ R.T, F)
    assert _max(a.cotmatrix() - b.cotmatrix()) < TOL
    assert _max(a.massmatrix() - b.massmatrix()) < TOL


def test_dec_identities(embedded_mesh):
    _, V, F = embedded_mesh
    m = Mescher.from_mesh(V, F)
    assert _max(m.d12 @ m.d01) == 0.0
    L = m.cotmatrix()
    G = m.grad()
    A = sp.diags(np.tile(m.face_areas(), 3))
    assert _max(G.T @ A @ G + L) < TOL
    assert _max(m.d01.T @ m.star1 @ m.d01 + L) < TOL
    assert _max(m.star2.diagonal() * m.face_areas() - 1.0) < TOL
    # star0: barycentric areas == libigl's barycentric mass matrix
    Mb = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC)
    assert _max(m.star0.diagonal() - Mb.diagonal()) < TOL
    # laplacian0 as in DESIGN
    assert _max(m.laplacian0() - sp.diags(1 / Mb.diagonal()) @ (-L)) < TOL
    # exterior derivatives have entries in {-1, 0, 1}
    assert set(np.unique(m.d01.data)) <= {-1.0, 1.0}
    assert set(np.unique(m.d12.data)) <= {-1.0, 1.0}


def test_grad_of_linear_function_is_constant():
    V, F = shapes.grid(5, 5)
    V = V @ shapes.random_rotation(3).T
    m = Mescher.from_mesh(V, F)
    # camera frame is the world frame for view (0,0,1): grad of the x coordinate
    G = m.grad()
    for k, unit in enumerate(np.eye(3)):
        g = (G @ V[:, k]).reshape(3, -1).T  # (#F, 3)
        n = m.face_normals()
        tangential = unit - (n @ unit)[:, None] * n
        assert np.allclose(g, tangential, atol=1e-12)


def test_single_triangle_by_hand():
    # right triangle in screen with depths 0, 1, 0: corners (0,0,0), (1,0,1), (0,1,0)
    F = np.array([[0, 1, 2]])
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    m = Mescher(F, xy, np.array([[0, 1], [1, 2], [0, 2]]), np.array([1.0, -1.0, 0.0]))
    # lengths: |01| = sqrt2, |12| = sqrt(1+1+1)=sqrt3, |02| = 1
    assert np.allclose(np.sort(m.edge_lengths()), np.sort([np.sqrt(2), np.sqrt(3), 1.0]))
    # area = |(1,0,1) x (0,1,0)| / 2 = |(-1,0,1)|/2 = sqrt2/2
    assert np.isclose(m.face_areas()[0], np.sqrt(2) / 2)
    assert np.allclose(m.face_normals()[0], np.array([-1.0, 0.0, 1.0]) / np.sqrt(2))
    # corner angles: at 0 between (1,0,1) and (0,1,0): 90 deg -> cot 0; edge 1-2 weight 0
    # at 1: vectors (-1,0,-1), (-1,1,-1): cos = 2/(sqrt2*sqrt3) -> cot = 2/sqrt2 = sqrt2
    # at 2: vectors (0,-1,0), (1,-1,1): cos = 1/sqrt3 -> cot = 1/sqrt2
    w = m.star1.diagonal()
    edge = {tuple(e): i for i, e in enumerate(m.edges.tolist())}
    assert np.isclose(w[edge[(1, 2)]], 0.0, atol=1e-15)
    assert np.isclose(w[edge[(0, 2)]], np.sqrt(2) / 2)  # opposite corner 1
    assert np.isclose(w[edge[(0, 1)]], 1 / (2 * np.sqrt(2)))  # opposite corner 2
    assert np.allclose(m.corner_depths(), [[0.0, 1.0, 0.0]])
    assert np.allclose(m.star0.diagonal(), np.sqrt(2) / 6)


def test_degenerate_triangles_keep_operators_finite():
    # a needle and a zero-area (collinear in 3D) triangle, as artist models contain; both meshes
    # are valid meschers (manifold, oriented), so construction must succeed and mollify
    xy = np.array([[0, 0], [1, 0], [2, 0], [1, 1e-13], [1, 1]], dtype=float)
    F = np.array([[0, 1, 3], [1, 2, 3], [0, 3, 4], [3, 2, 4]])
    V = np.c_[xy, np.zeros(len(xy))]
    F2 = np.r_[F, [[0, 2, 1]]]  # exactly collinear zero-area face glued below the needles
    for FF in (F, F2):
        m = Mescher.from_mesh(V, FF)
        assert m.n_faces == FF.shape[0]
        assert m.mollification() > 0  # the needles and the flat face trigger it
        for A in (m.cotmatrix(), m.massmatrix(), m.grad(), m.star1, m.star2):
            assert np.isfinite(A.data).all()
        assert np.isfinite(m.face_normals()).all() and np.isfinite(m.vertex_normals()).all()
        assert (m.face_areas() > 0).all()  # mollified
        L = m.cotmatrix()
        assert np.allclose(L @ np.ones(m.n_vertices), 0, atol=1e-9)
        assert _max(L - L.T) < 1e-9 * _max(L)
        # the mollified metric is one metric: G^T A G = -L, and L matches libigl's intrinsic
        # cotmatrix on the mollified lengths
        A3 = sp.diags(np.tile(m.face_areas(), 3))
        assert _max(m.grad().T @ A3 @ m.grad() + L) < 1e-9 * _max(L)
        lm = m.face_edge_lengths(mollified=True)
        assert _max(L - igl.cotmatrix_intrinsic(lm, m.F)) < 1e-9 * _max(L)
        # mollification adds one eps to every length: the sliver triangles now satisfy the
        # triangle inequality with a margin of 1e-5 times the mean length
        l = m.face_edge_lengths()
        np.testing.assert_allclose(lm - l, m.mollification(), rtol=1e-9)
        slack = np.min(lm.sum(axis=1, keepdims=True) - 2 * lm, axis=1)
        assert slack.min() >= 1e-5 * l.mean() * (1 - 1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_seeded_random_meshes(seed):
    """Random displaced spheres: symmetric L, constants in its kernel, PSD energy."""
    V, F = shapes.icosphere(2)
    rng = np.random.default_rng(seed)
    V = V * (1 + 0.2 * rng.random((len(V), 1)))
    m = Mescher.from_mesh(V @ shapes.random_rotation(seed).T, F)
    L = m.cotmatrix()
    assert _max(L - L.T) < 1e-12
    assert np.abs(L @ np.ones(len(V))).max() < 1e-10
    u = rng.standard_normal(len(V))
    assert u @ (-L @ u) >= 0
    assert _max(m.cotmatrix() - igl.cotmatrix(V @ shapes.random_rotation(seed).T, F)) < TOL


def test_mollified_gradient_is_consistent_with_cotmatrix():
    """Needles trigger mollification; G, A and L then all come from the mollified metric."""
    xy = np.array([[0, 0], [1, 0], [2, 0], [1, 1e-13], [1, 1]], dtype=float)
    F = np.array([[0, 1, 3], [1, 2, 3], [0, 3, 4], [3, 2, 4]])
    m = Mescher.from_mesh(np.c_[xy, np.zeros(5)], F)
    assert m.mollification() > 0
    G, L = m.grad(), m.cotmatrix()
    A = sp.diags(np.tile(m.face_areas(), 3))
    assert _max(G.T @ A @ G + L) < 1e-12 * _max(L)
    assert np.isfinite(G.data).all()


def test_mollified_gradient_equals_plain_gradient_without_mollification(embedded_mesh):
    from meschers_igl import operators as ops

    _, V, F = embedded_mesh
    m = Mescher.from_mesh(V, F)
    assert m.mollification() == 0.0
    Gm = ops.grad_mollified(m.local_corners(), m.face_edge_lengths(), m.F, m.n_vertices)
    assert _max(Gm - m.grad()) < 1e-10
