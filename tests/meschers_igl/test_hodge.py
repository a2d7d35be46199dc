"""Projection, Hodge decomposition, homology basis, periods, impossible tori."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, shapes


def _torus(n_u=24, n_v=10):
    V, F = shapes.torus(n_u, n_v)
    return Mescher.from_mesh(V @ shapes.random_rotation(11).T, F), V, F


def test_ordinary_torus_is_possible():
    m, _, _ = _torus()
    assert len(m.homology_generators()) == 2
    assert not m.is_impossible()
    assert np.abs(m.periods()).max() < 1e-12
    assert np.abs(m.hodge().omega).max() < 1e-10


def test_generator_loops_are_closed_and_counted(embedded_mesh):
    name, V, F = embedded_mesh
    m = Mescher.from_mesh(V, F)
    expected = {"torus": 2, "thin_torus": 2, "sphere": 0, "grid": 0, "annulus": 1, "bumpy_grid": 0}
    gens = m.homology_generators()
    assert len(gens) == expected[name]
    for e, s in gens:
        E = m.edges[e]
        tails = np.where(s > 0, E[:, 0], E[:, 1])
        heads = np.where(s > 0, E[:, 1], E[:, 0])
        assert np.array_equal(heads[:-1], tails[1:]) and heads[-1] == tails[0]
        # an exact form integrates to zero around any closed loop
        z = np.random.default_rng(0).standard_normal(m.n_vertices)
        assert abs(s @ (m.d01 @ z)[e]) < 1e-12


def test_climbing_torus_periods():
    """Depth climbing c per turn around the hole: periods are integer combos of (c, 0)."""
    c = 0.75
    m = shapes.impossible_torus(24, 10, climb=c)
    assert m.is_impossible()
    p = m.periods()
    # each period is an integer multiple of c, and together they generate c * Z
    k = p / c
    assert np.allclose(k, np.round(k), atol=1e-9)
    assert np.gcd.reduce(np.abs(np.round(k)).astype(int)) == 1
    # explicit construction without with_periods: depth = sin(v) + c * u / (2 pi) per face
    V, F = shapes.torus(24, 10)
    u = np.arctan2(V[:, 1], V[:, 0])
    # per-face corner depths with the angle unwrapped inside each face
    uf = np.unwrap(u[F], axis=1)
    Z = V[F][:, :, 2] + c * uf / (2 * np.pi)
    m2 = Mescher.from_corner_depths(F, V[:, :2], Z)
    assert m2.is_impossible()
    k2 = m2.periods() / c
    assert np.allclose(k2, np.round(k2), atol=1e-9) and np.abs(np.round(k2)).max() == 1


def test_hodge_decomposition_identities():
    m = shapes.impossible_torus(20, 8, climb=1.3)
    h = m.hodge()
    assert np.allclose(m.d01 @ h.z + h.omega, m.zeta, atol=1e-12)
    assert np.abs(m.d12 @ h.omega).max() < 1e-10  # closed
    assert np.abs(m.d01.T @ (m.star1 @ h.omega)).max() < 1e-10  # co-closed
    H = m.harmonic_basis()
    assert np.allclose(H @ m.periods(), h.omega, atol=1e-10)
    G = np.array(
        [np.bincount(e, weights=s, minlength=m.n_edges) for e, s in m.homology_generators()]
    )
    assert np.allclose(G @ H, np.eye(H.shape[1]), atol=1e-10)


def test_with_periods_sets_periods_and_keeps_exact_part():
    m, _, _ = _torus()
    m2 = m.with_periods([0.4, -1.1])
    assert np.allclose(m2.periods(), [0.4, -1.1], atol=1e-12)
    # the change is harmonic for the original metric: the exact part d01 z is untouched
    dz = m2.zeta - m.zeta
    assert np.abs(m.d12 @ dz).max() < 1e-12
    assert np.abs(m.d01.T @ (m.star1 @ dz)).max() < 1e-10
    assert np.allclose(m2.xy, m.xy)
    # (the Hodge split itself depends on the metric, which zeta changes, so z moves a little)
    m3 = m2.with_periods([0.0, 0.0])
    assert not m3.is_impossible()
    assert np.abs(m3.periods()).max() < 1e-12
    with pytest.raises(MescherError, match="values"):
        m.with_periods([1.0])


def test_projection_is_least_squares_and_idempotent(rng):
    m, V, F = _torus(12, 6)
    noise = rng.standard_normal(m.n_edges)
    noisy = m.zeta + 0.1 * noise
    with pytest.raises(MescherError, match="project=True"):
        Mescher(m.F, m.xy, m.edges, noisy)
    p = Mescher(m.F, m.xy, m.edges, noisy, project=True)
    assert np.abs(p.integrability_residual()).max() < 1e-12
    # idempotent
    pp = Mescher(p.F, p.xy, p.edges, p.zeta, project=True)
    assert np.allclose(pp.zeta, p.zeta, atol=1e-13)
    # least squares: the residual is orthogonal to every closed form (here: exact ones and
    # harmonic ones), i.e. it lies in the image of d12^T
    r = noisy - p.zeta
    z = rng.standard_normal(m.n_vertices)
    assert abs((m.d01 @ z) @ r) < 1e-9
    assert np.abs(m.harmonic_basis().T @ r).max() < 1e-9
    # and it is no farther than the true zeta from the noisy one
    assert np.linalg.norm(r) <= np.linalg.norm(noisy - m.zeta) + 1e-12


def test_projection_on_mesh_with_boundary(rng):
    V, F = shapes.grid(6, 6)
    m = Mescher.from_mesh(V, F)
    p = Mescher(m.F, m.xy, m.edges, rng.standard_normal(m.n_edges), project=True)
    assert np.abs(p.integrability_residual()).max() < 1e-12
    assert not p.is_impossible()  # a disc has no harmonic forms


def test_from_corner_depths_averages_conflicts():
    F = np.array([[0, 1, 2], [0, 2, 3]])
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    # both faces consistent except the shared edge 0->2: face 0 says +1, face 1 says +3
    Z = np.array([[0.0, 0.0, 1.0], [0.0, 3.0, 3.0]])
    m = Mescher.from_corner_depths(F, xy, Z)
    assert np.abs(m.integrability_residual()).max() < 1e-12
    edge = {tuple(e): i for i, e in enumerate(m.edges.tolist())}
    # averaged value 2 is then projected together with the face's other edges
    assert 1.0 < m.zeta[edge[(0, 2)]] < 3.0
