"""Exact geodesic distance by window propagation (meschers_igl.geodesic.exact).

Oracles: Euclidean distance on flat sheets (also around a reflex corner of an L-shaped sheet,
where the geodesic bends at the corner), ``igl.exact_geodesic`` (Kirsanov's MMP) on ordinary
meshes, and MMP on a real 3D covering (``algorithm="covering"``) on impossible meschers.
"""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp
from builders import obtuse_sheet, ordinary_torus, sliver_box
from scipy.sparse.csgraph import dijkstra

from meschers_igl import Mescher, MescherError, shapes
from meschers_igl.gallery import get_model
from meschers_igl.geodesic import geodesic_distance
from meschers_igl.geodesic.exact import ExactGeodesicSolver

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
    d = geodesic_distance(m, sources, "exact")
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
        d = geodesic_distance(m, s, "exact")
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
    np.testing.assert_array_equal(geodesic_distance(m, 5, "exact"), d)


# ----------------------------------------------------------------------------------------------
# impossible meschers: the covering (MMP on a real 3D surface) as oracle
# ----------------------------------------------------------------------------------------------
def test_impossible_torus_equals_covering():
    V, F = shapes.torus(40, 16)
    m = Mescher.from_mesh(V, F).with_periods([0.4, 0.0])
    assert np.abs(m.periods()).max() > 0.3
    for s in (0, 333, [5, 400]):
        d = geodesic_distance(m, s, method="exact")
        dc = geodesic_distance(m, s, "covering")
        assert np.abs(d - dc).max() < TOL
    # a metric: |d(a) - d(b)| <= |ab| on every edge
    a, b = m.edges.T
    assert np.all(np.abs(d[a] - d[b]) <= m.edge_lengths() * (1 + 1e-12))


def test_penrose_triangle_equals_covering():
    m = get_model("penrose_triangle").mescher
    assert np.abs(m.periods()).max() > 1.0
    for s in (0, 7, m.n_vertices - 1):
        d = geodesic_distance(m, s, "exact")
        assert np.abs(d - geodesic_distance(m, s, "covering")).max() < TOL


def test_subdivided_impossible_cube_equals_covering_with_linear_windows():
    """A gallery mescher, midpoint-subdivided (flat faces, creases, corners): exact against MMP
    on a real 3D covering, and the pieces of one unfolded source are merged, so the windows
    stay O(#F) (before the merge: 10-40 per face on such meshes, growing like sqrt(#F))."""
    m = get_model("impossible_cube").mescher.subdivide(1)
    S = ExactGeodesicSolver(m)
    for s in (3, m.n_vertices // 2):
        d = S.distance(s)
        assert S.n_windows < 4 * m.n_faces, S.n_windows / m.n_faces
        dc = geodesic_distance(m, s, "covering")
        assert np.abs(d - dc).max() < TOL


@pytest.mark.parametrize("n", [41, 81])
def test_flat_sheet_needs_a_few_windows_per_face(n):
    """On a flat square (one unfolding: the distance field is a single piece) the windows per
    face stay bounded as the mesh is refined; straight-boundary vertices (pseudo-sources, of
    total angle pi) cast no shadow and emit nothing."""
    V, F = _grid(n, 0.2)
    m = Mescher.from_mesh(V, F)
    S = ExactGeodesicSolver(m)
    s = (n // 3) * n + n // 4
    d = S.distance(s)
    np.testing.assert_allclose(d, np.linalg.norm(V - V[s], axis=1), rtol=0, atol=TOL)
    assert S.n_windows < 2.5 * m.n_faces, S.n_windows / m.n_faces


def test_a_saddle_emits_only_into_its_shadow():
    """A cone of total angle 3 pi at the apex of a flat fan (a saddle): a shortest path through
    it turns by >= pi on both sides, so it lights only the wedge of width 3 pi - 2 pi = pi
    opposite the source (4 of the 12 sectors); elsewhere the distance is the straight one in the
    unfolded fan.  The rim's vertices (boundary, angle 3 pi / 4 < pi) cast no shadow at all."""
    # sectors of 3 pi / k around vertex 0, rings at radius 1 and 2; k = 10 puts the shadow's
    # edges (at pi and 2 pi from the source's direction) inside sectors 3 and 6, a tenth of a
    # sector from their edges, so which sectors it lights does not hang on rounding
    k = 10
    F = []
    # intrinsic fan: vertex 0 at the centre, vertex 1 + i at radius 1, 1 + k + i at radius 2
    n_in = 1 + 2 * k
    for i in range(k):
        j = (i + 1) % k
        F.append([0, 1 + i, 1 + j])
        F.append([1 + i, 1 + k + i, 1 + k + j])
        F.append([1 + i, 1 + k + j, 1 + j])
    F = np.array(F)
    th = 3 * np.pi / k

    # planar positions of each face's corners in its own unfolding (sector i spans [i th, j th])
    def pos(v, i):
        if v == 0:
            return np.zeros(2)
        r = 1.0 if v <= k else 2.0
        idx = (v - 1) % k
        a = i * th if idx == i else (i + 1) * th
        return r * np.array([np.cos(a), np.sin(a)])

    lens = []
    for f, (a, b, c) in enumerate(F):
        i = f // 3
        P = [pos(a, i), pos(b, i), pos(c, i)]
        lens.append(
            [np.linalg.norm(P[1] - P[2]), np.linalg.norm(P[2] - P[0]), np.linalg.norm(P[0] - P[1])]
        )
    S = ExactGeodesicSolver(F=F, l=np.array(lens))
    src = 1 + k  # on the outer ring at angle 0
    d = S.distance(src)
    assert S.n_vertices == n_in
    # expected: straight in the unfolding when the angle between source and target, measured
    # around the cone the short way, is < pi; else around the apex
    for v in range(1, n_in):
        r = 1.0 if v <= k else 2.0
        a = ((v - 1) % k) * th
        a = min(a, 3 * np.pi - a)
        if a < np.pi:
            e = np.sqrt(4 + r * r - 4 * r * np.cos(a))
        else:
            e = 2.0 + r
        assert abs(d[v] - e) < TOL, (v, d[v], e)
    assert d[0] == pytest.approx(2.0, abs=TOL)
    # the source's 3 faces (two of sector k-1, one of sector 0), and the apex's shadow: sectors
    # 3 to 6; a whole-fan emission would send 10 from the apex and 2 to 3 from each rim vertex
    assert S.n_emitted == 3 + 4, S.n_emitted


def test_a_query_resumes_exactly_across_kernel_calls(monkeypatch):
    """The kernel stops every few items (progress) and whenever an array might overflow; the
    caller grows it and calls again.  Stopping after every 7 items, from the smallest arrays,
    gives the same distances bit for bit, and a bar is drawn for a query that runs long."""
    import meschers_igl.geodesic.exact as eg
    import meschers_igl.progress as progress

    V, F = ordinary_torus(40, 14)
    m = Mescher.from_mesh(V, F).with_periods([0.3, 0.0])
    S = ExactGeodesicSolver(m)
    ref = S.distance([3, 200])
    n_ref = S.n_windows
    grown = []
    real_grow = eg._State.grow
    monkeypatch.setattr(eg, "_POPS_PER_CALL", 7)
    monkeypatch.setattr(eg, "_FIRST_SIZE", 4)
    monkeypatch.setattr(eg._State, "grow", lambda st, k: grown.append(k) or real_grow(st, k))
    drawn = []
    real_update = progress.Meter.update

    def update(self, done):
        self.after = 0.0  # draw at once
        real_update(self, done)
        drawn.append((done, self.total, self._bar is not None))

    monkeypatch.setattr(progress.Meter, "update", update)
    monkeypatch.setenv("FORCE_COLOR", "1")  # rich: stderr counts as a terminal
    d = S.distance([3, 200])
    np.testing.assert_array_equal(d, ref)
    assert S.n_windows == n_ref
    assert {2, 3, 4} <= set(grown)  # the heap, the window table and the arena all grew
    assert drawn and all(bar for _, _, bar in drawn)
    assert drawn[-1][1] == m.n_vertices and 0 < drawn[-1][0] <= m.n_vertices


def test_targets_stop_early_with_the_same_distances():
    """With targets the propagation stops once they are final: the same values there (and at
    every vertex up to the farthest target), inf beyond, and far fewer windows for a near pair."""
    V, F = ordinary_torus(60, 20)
    m = Mescher.from_mesh(V, F).with_periods([0.3, 0.0])
    S = ExactGeodesicSolver(m)
    full = S.distance(7)
    n_full = S.n_windows
    near = int(np.argsort(full)[40])  # a vertex near the source
    d = S.distance(7, targets=[near, 8])
    assert S.n_windows < 0.5 * n_full
    assert d[near] == full[near] and d[8] == full[8]
    done = np.isfinite(d)
    np.testing.assert_array_equal(d[done], full[done])
    assert done.sum() < 0.5 * m.n_vertices
    assert (full[~done] > max(full[near], full[8])).all()
    # the farthest vertex as target: the whole field
    np.testing.assert_array_equal(S.distance(7, targets=int(np.argmax(full))), full)
    d1 = geodesic_distance(m, 7, "exact", targets=[near])
    assert d1[near] == full[near] and (d1[np.isfinite(d1)] == full[np.isfinite(d1)]).all()


def test_bad_input():
    V, F = ordinary_torus(8, 4)
    m = Mescher.from_mesh(V, F)
    with pytest.raises(MescherError, match="sources"):
        geodesic_distance(m, len(V), "exact")
    with pytest.raises(MescherError, match="targets"):
        ExactGeodesicSolver(m).distance(0, targets=[-1])
    with pytest.raises(MescherError, match="method"):
        geodesic_distance(m, 0, "mmp")
    with pytest.raises(MescherError, match="F, l"):
        ExactGeodesicSolver(F=F, l=np.ones((len(F), 2)))
    with pytest.raises(MescherError, match="m"):
        ExactGeodesicSolver()


def test_faces_without_area_are_crossed_exactly():
    """A T-junction closed by a face of zero area (its apex on its base, as in exported CAD
    and artist models): distances from every vertex equal MMP's, and the shortest path's
    length the exact distance, with no division by zero."""
    from meschers_igl.geodesic import shortest_path

    V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [2, 1, 0], [1, 2, 0.5]], float)
    F = np.array([[0, 2, 4], [0, 4, 3], [0, 1, 2], [3, 4, 5]])
    m = Mescher.from_mesh(V, F)
    assert igl.doublearea(V, F)[2] == 0.0  # (the operators see it mollified)
    for s in range(len(V)):
        np.testing.assert_allclose(geodesic_distance(m, s, "exact"), _igl(V, F, s), atol=TOL)
        for t in range(len(V)):
            if t != s:
                assert shortest_path(m, s, t).length == pytest.approx(_igl(V, F, s)[t], rel=1e-12)
