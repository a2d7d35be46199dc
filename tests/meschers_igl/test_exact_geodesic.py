"""Exact geodesic distance by window propagation (meschers_igl.exact_geodesic), issue 13 item 5.

Oracles: Euclidean distance on flat sheets (also around a reflex corner of an L-shaped sheet,
where the geodesic bends at the corner), ``igl.exact_geodesic`` (Kirsanov's MMP) on ordinary
meshes, and MMP on a real 3D covering (``algorithm="covering"``) on impossible meschers.
"""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra
from test_heat import obtuse_sheet, ordinary_torus, sliver_box

from meschers_igl import Mescher, MescherError, shapes
from meschers_igl.exact_geodesic import ExactGeodesicSolver, exact_geodesic
from meschers_igl.gallery import get_model
from meschers_igl.paths import exact_geodesic_distance, geodesic_distance

TOL = 1e-9


def _igl(V, F, s):
    return igl.exact_geodesic(
        np.ascontiguousarray(V, dtype=np.float64),
        np.ascontiguousarray(F, dtype=np.int64),
        VS=np.atleast_1d(s).astype(np.int64),
        VT=np.arange(len(V), dtype=np.int64),
    )


def _grid(n, jitter=0.0, seed=0):
    """A triangulated square [0, 1]^2 (n x n vertices), interior vertices jittered, z = 0."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    xy = np.c_[i.ravel(), j.ravel()] / (n - 1.0)
    inner = (i.ravel() % (n - 1) != 0) & (j.ravel() % (n - 1) != 0)
    xy[inner] += jitter / (n - 1) * np.random.default_rng(seed).uniform(-1, 1, (inner.sum(), 2))
    a = (i[:-1, :-1] * n + j[:-1, :-1]).ravel()
    F = np.r_[np.c_[a, a + n, a + n + 1], np.c_[a, a + n + 1, a + 1]]
    return np.c_[xy, np.zeros(len(xy))], F.astype(np.int64)


def _l_shape(n=17):
    """[0, 2]^2 without the open square (1, 2)^2: a reflex corner at (1, 1)."""
    V, F = _grid(n)
    V = 2.0 * V
    c = V[F].mean(axis=1)
    F = F[~((c[:, 0] > 1) & (c[:, 1] > 1))]
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(used.size)
    return V[used], remap[F]


def _check(V, F, sources):
    m = Mescher.from_mesh(V @ shapes.random_rotation(3).T, F, view=(0.3, -0.2, 1.0))
    d = exact_geodesic(m, sources)
    de = _igl(V, F, sources)
    err = np.abs(d - de).max()
    assert err < TOL, err
    return d


# ----------------------------------------------------------------------------------------------
# ordinary meshes: analytic values and libigl
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("jitter", [0.0, 0.2])
def test_flat_sheet_is_euclidean(jitter):
    """A convex flat sheet: the exact distance is the straight-line distance (every vertex of the
    regular grid has angle exactly 2 pi: geodesics run through vertices and along edges)."""
    V, F = _grid(21, jitter)
    assert (igl.doublearea(V[:, :2], F) > 0).all()  # no fold: a planar convex domain
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    assert (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0).all()
    for s in (0, 220, 137):
        d = _check(V, F, s)
        np.testing.assert_allclose(d, np.linalg.norm(V - V[s], axis=1), rtol=0, atol=TOL)


def test_reflex_corner_bends_geodesics():
    """An L-shaped sheet: targets hidden from the source are reached around the corner (1, 1)."""
    V, F = _l_shape()
    s = int(np.argmin(np.linalg.norm(V[:, :2] - [1.875, 0.25], axis=1)))
    d = _check(V, F, s)
    c = np.array([1.0, 1.0, 0.0])
    # the straight segment is blocked when it passes through the removed square
    t = np.linspace(0, 1, 401)[:, None, None]
    pts = V[s] + t * (V - V[s])[None]
    blocked = ((pts[..., 0] > 1 + 1e-12) & (pts[..., 1] > 1 + 1e-12)).any(axis=0)
    expect = np.where(
        blocked,
        np.linalg.norm(c - V[s]) + np.linalg.norm(V - c, axis=1),
        np.linalg.norm(V - V[s], axis=1),
    )
    assert blocked.sum() > 20
    np.testing.assert_allclose(d, expect, rtol=0, atol=TOL)
    # a distance along edges (Dijkstra) would be far off there: the test can tell
    a, b = igl.edges(F).T
    G = sp.csr_matrix((np.linalg.norm(V[a] - V[b], axis=1), (a, b)), shape=(len(V), len(V)))
    dj = dijkstra(G, directed=False, indices=s)
    assert np.abs(dj - expect)[blocked].max() > 0.05


@pytest.mark.parametrize(
    "mesh",
    ["icosphere", "torus", "obtuse_sheet", "sliver_box", "bumpy_l_shape"],
)
def test_equals_libigl(mesh):
    if mesh == "icosphere":
        V, F = shapes.icosphere(3)
    elif mesh == "torus":
        V, F = ordinary_torus(40, 14)
    elif mesh == "obtuse_sheet":
        V, F = obtuse_sheet(24, 24)  # angles near 150 degrees, a boundary
    elif mesh == "sliver_box":
        V, F = sliver_box()  # 0.003-degree slivers
        a = np.degrees(igl.internal_angles(V, F)).min()
        assert a < 0.004
    else:
        V, F = _l_shape(21)
        V = V.copy()
        V[:, 2] = 0.3 * np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1])  # saddles and a reflex corner
    for s in (0, len(V) // 2, [1, len(V) - 1]):
        _check(V, F, s)


def test_zero_area_face():
    """A face whose apex lies on its opposite edge (area 0; libigl's MMP runs out of memory on
    it): the distances are finite, a metric, and those of a 1e-9 lift of the apex to 1e-8."""
    V, F = _grid(9)
    V[:, 2] = 0.2 * np.sin(3 * V[:, 0])
    a, b, c = F[30]
    V[c] = 0.5 * (V[a] + V[b])
    assert igl.doublearea(V, F).min() < 1e-15
    m = Mescher.from_mesh(V, F)
    V2 = V.copy()
    V2[c, 2] += 1e-9
    for s in (0, 40):
        d = exact_geodesic(m, s)
        assert np.isfinite(d).all()
        e0, e1 = m.edges.T
        assert np.all(np.abs(d[e0] - d[e1]) <= m.edge_lengths() * (1 + 1e-12) + 1e-15)
        assert np.abs(d - _igl(V2, F, s)).max() < 1e-8


def test_multiple_sources_are_the_nearest():
    V, F = ordinary_torus(32, 12)
    m = Mescher.from_mesh(V, F)
    S = ExactGeodesicSolver(m)
    srcs = [4, 101, 250]
    d = S.distance(srcs)
    np.testing.assert_allclose(d, np.min([S.distance(s) for s in srcs], axis=0), atol=0)
    assert np.abs(d - _igl(V, F, srcs)).max() < TOL
    assert (d[srcs] == 0).all()


def test_lengths_only_and_components():
    """From faces and edge lengths alone; a component without a source stays at inf."""
    V, F = ordinary_torus(16, 8)
    n = len(V)
    V2, F2 = np.r_[V, V + [10, 0, 0]], np.r_[F, F + n]
    d = ExactGeodesicSolver(F=F2, l=igl.edge_lengths(V2, F2)).distance(5)
    assert np.isinf(d[n:]).all()
    assert np.abs(d[:n] - _igl(V, F, 5)).max() < TOL
    m = Mescher.from_mesh(V2, F2)
    np.testing.assert_array_equal(exact_geodesic_distance(m, 5), d)


# ----------------------------------------------------------------------------------------------
# impossible meschers: the covering (MMP on a real 3D surface) as oracle
# ----------------------------------------------------------------------------------------------
def test_impossible_torus_equals_covering():
    V, F = shapes.torus(40, 16)
    m = Mescher.from_mesh(V, F).with_periods([0.4, 0.0])
    assert np.abs(m.periods()).max() > 0.3
    for s in (0, 333, [5, 400]):
        d = geodesic_distance(m, s, method="exact")
        dc = exact_geodesic_distance(m, s, algorithm="covering")
        assert np.abs(d - dc).max() < TOL
    # a metric: |d(a) - d(b)| <= |ab| on every edge
    a, b = m.edges.T
    assert np.all(np.abs(d[a] - d[b]) <= m.edge_lengths() * (1 + 1e-12))


def test_penrose_triangle_equals_covering():
    m = get_model("penrose_triangle").mescher
    assert np.abs(m.periods()).max() > 1.0
    for s in (0, 7, m.n_vertices - 1):
        d = exact_geodesic_distance(m, s)
        assert np.abs(d - exact_geodesic_distance(m, s, algorithm="covering")).max() < TOL


def test_bad_input():
    V, F = ordinary_torus(8, 4)
    m = Mescher.from_mesh(V, F)
    with pytest.raises(MescherError, match="sources"):
        exact_geodesic(m, len(V))
    with pytest.raises(MescherError, match="algorithm"):
        exact_geodesic_distance(m, 0, algorithm="mmp")
    with pytest.raises(MescherError, match="F, l"):
        ExactGeodesicSolver(F=F, l=np.ones((len(F), 2)))
    with pytest.raises(MescherError, match="m"):
        ExactGeodesicSolver()
