"""factorize_spd: exact small cases, agreement of the backends, and clear errors."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp

from meschers_igl import MescherError
from meschers_igl.solvers import BACKENDS, factorize_spd


def _heat_matrix(n=12):
    V, F = igl.upsample(*_octahedron(), 2)
    V = V / np.linalg.norm(V, axis=1, keepdims=True)
    L, M = igl.cotmatrix(V, F), igl.massmatrix(V, F)
    return (M - 0.01 * L).tocsr()


def _octahedron():
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    F = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    )
    return V, F


@pytest.mark.parametrize("backend", BACKENDS)
def test_two_by_two_exact(backend):
    A = sp.csr_matrix([[2.0, 1.0], [1.0, 2.0]])
    solve = factorize_spd(A, backend=backend)
    np.testing.assert_allclose(solve(np.array([1.0, 1.0])), [1 / 3, 1 / 3], atol=1e-15)
    np.testing.assert_allclose(solve(np.eye(2)), np.linalg.inv(A.toarray()), atol=1e-15)


@pytest.mark.parametrize("backend", BACKENDS)
def test_residuals_one_and_many_right_hand_sides(backend):
    A = _heat_matrix()
    rng = np.random.default_rng(0)
    b, B = rng.random(A.shape[0]), rng.random((A.shape[0], 5))
    solve = factorize_spd(A, backend=backend)
    x, X = solve(b), solve(B)
    assert x.shape == b.shape and X.shape == B.shape
    assert np.linalg.norm(A @ x - b) < 1e-12 * np.linalg.norm(b)
    assert np.linalg.norm(A @ X - B) < 1e-12 * np.linalg.norm(B)
    np.testing.assert_allclose(X[:, 2], solve(B[:, 2]), atol=1e-14)  # block == one by one
    np.testing.assert_allclose(solve(np.asfortranarray(B)), X, atol=1e-14)


def test_backends_agree_and_auto_prefers_cholespy():
    A = _heat_matrix()
    b = np.random.default_rng(1).random(A.shape[0])
    xs = [factorize_spd(A, backend=bk)(b) for bk in BACKENDS]
    np.testing.assert_allclose(xs[0], xs[1], atol=1e-12)
    assert factorize_spd(A).backend == "cholespy"


def test_errors_name_the_argument():
    A = _heat_matrix()
    with pytest.raises(MescherError, match="A: expected a scipy.sparse"):
        factorize_spd(A.toarray())
    with pytest.raises(MescherError, match="square"):
        factorize_spd(sp.csr_matrix(np.ones((2, 3))))
    with pytest.raises(MescherError, match="backend"):
        factorize_spd(A, backend="pardiso")
    bad = A.copy()
    bad.data[0] = np.nan
    with pytest.raises(MescherError, match="finite"):
        factorize_spd(bad)
    with pytest.raises(MescherError, match="positive definite"):
        factorize_spd(-A, backend="cholespy")
    with pytest.raises(MescherError, match="nonsingular"):
        factorize_spd(sp.csr_matrix((3, 3)), backend="splu")
    with pytest.raises(MescherError, match="b: expected shape"):
        factorize_spd(A)(np.ones(3))
