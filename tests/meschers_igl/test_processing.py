"""Subdivision, smoothing and embeddings: invariants (periods, integrability) and exact values."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, shapes


@pytest.fixture(scope="module")
def itorus():
    return shapes.impossible_torus(16, 8, climb=0.9)


@pytest.mark.parametrize("scheme", ["midpoint", "loop"])
def test_subdivision_keeps_integrability_and_periods(itorus, scheme):
    c, S, parent = itorus.subdivide(2, scheme, return_matrix=True, return_face_parent=True)
    assert c.n_faces == 16 * itorus.n_faces
    assert np.abs(c.integrability_residual()).max() < 1e-12
    assert np.allclose(c.periods(), itorus.periods(), atol=1e-12)
    assert c.is_impossible()
    assert S.shape == (c.n_vertices, itorus.n_vertices)
    assert np.allclose(S @ np.ones(itorus.n_vertices), 1.0)  # affine
    assert np.array_equal(parent, np.repeat(np.arange(itorus.n_faces), 16))
    assert c.euler_characteristic() == itorus.euler_characteristic()


def test_midpoint_halves_zeta_and_matches_libigl(itorus):
    c = itorus.subdivide(1, "midpoint")
    nv = itorus.n_vertices
    assert np.array_equal(c.xy[:nv], itorus.xy)  # original vertices keep their indices
    # each parent edge splits into two halves with exactly half its zeta
    key = {tuple(e): i for i, e in enumerate(c.edges.tolist())}
    for e in range(0, itorus.n_edges, 7):
        t, h = itorus.edges[e]
        mid = nv + e
        z1 = c.zeta[key[(t, mid)]]
        z2 = -c.zeta[key[(h, mid)]]
        assert z1 == 0.5 * itorus.zeta[e] and z2 == 0.5 * itorus.zeta[e]
    V, F = igl.upsample(np.c_[itorus.xy, np.zeros(nv)], np.asarray(itorus.F))
    assert np.allclose(np.sort(c.xy, axis=0), np.sort(V[:, :2], axis=0))
    # child faces: same pattern as libigl's upsample (children of f are 4f..4f+3)
    assert np.allclose(c.xy[c.F], V[F][:, :, :2])


def test_midpoint_on_embedded_mesh_equals_upsampled_mesh():
    V, F = shapes.torus(10, 6)
    V = V @ shapes.random_rotation(2).T
    m = Mescher.from_mesh(V, F)
    c = m.subdivide(1)
    V2, F2 = igl.upsample(V, F)
    # libigl numbers the new vertices in its own edge order: match them by 3D position
    from scipy.spatial import cKDTree

    Vc, _ = c.bent_embedding()
    Vc = Vc - Vc.mean(axis=0) + V2.mean(axis=0)
    dist, perm = cKDTree(V2).query(Vc)
    assert dist.max() < 1e-9 and np.unique(perm).size == perm.size
    L2 = igl.cotmatrix(V2, F2)[perm][:, perm]
    assert np.abs(c.cotmatrix() - L2).max() < 1e-10


def test_loop_on_embedded_mesh_equals_libigl_loop():
    V, F = shapes.icosphere(1)
    V = V @ shapes.random_rotation(4).T
    c = Mescher.from_mesh(V, F).subdivide(1, "loop")
    V2, _ = igl.loop(V, F)
    # same positions (up to vertex numbering): compare sorted xy and bent depth spread
    assert np.allclose(np.sort(c.xy, axis=0), np.sort(V2[:, :2], axis=0), atol=1e-12)
    Vb, _ = c.bent_embedding()
    zb = Vb[:, 2] - Vb[:, 2].mean()
    zl = V2[:, 2] - V2[:, 2].mean()
    assert np.allclose(np.sort(zb), np.sort(zl), atol=1e-9)


def test_subdivision_errors(itorus):
    with pytest.raises(MescherError, match="scheme"):
        itorus.subdivide(1, "catmull")
    with pytest.raises(MescherError, match="levels"):
        itorus.subdivide(-1)


def test_smoothing_keeps_periods_and_reduces_energy(itorus):
    assert itorus.smooth(0, 0) is itorus
    energies = []
    for t in [0.0, 0.01, 0.1, 1.0]:
        s = itorus.smooth(t_zeta=t)
        assert np.allclose(s.periods(), itorus.periods(), atol=1e-12)
        assert np.allclose(s.hodge().omega, itorus.hodge().omega, atol=1e-12) or t > 0
        assert np.allclose(s.xy, itorus.xy)
        z = np.asarray(itorus.hodge().z) if t == 0 else None
        dz = s.zeta - itorus.hodge().omega  # the exact part after smoothing
        energies.append(float(dz @ (itorus.star1 @ dz)))
        del z
    assert all(a > b for a, b in zip(energies, energies[1:]))
    sx = itorus.smooth(t_xy=0.05)
    assert np.array_equal(sx.zeta, itorus.zeta)
    assert np.allclose(sx.periods(), itorus.periods(), atol=1e-12)
    both = itorus.smooth(0.05, 0.05)
    assert np.allclose(both.xy, sx.xy) and np.allclose(both.periods(), itorus.periods(), atol=1e-12)
    with pytest.raises(MescherError, match="t_xy"):
        itorus.smooth(t_xy=-1)


def test_bent_embedding_reproduces_exact_part(itorus):
    V, F = itorus.bent_embedding()
    mb = Mescher.from_mesh(V, F)
    h = itorus.hodge()
    assert np.allclose(mb.zeta, itorus.d01 @ h.z, atol=1e-12)
    assert np.allclose(mb.xy, itorus.xy)
    assert not mb.is_impossible()


def test_cut_embedding_integrates_zeta_and_jumps_by_period(itorus):
    V, F, vmap = itorus.cut_embedding()
    assert np.allclose(V[:, :2], itorus.xy[vmap])
    # inside every face, depth differences are zeta
    m2 = Mescher.from_corner_depths(itorus.F, itorus.xy, V[F][:, :, 2])
    assert np.allclose(m2.zeta, itorus.zeta, atol=1e-12)
    # the cut model is a real mesh: duplicated vertices only on the cut
    assert V.shape[0] > itorus.n_vertices
    jumps = []
    for v in np.flatnonzero(np.bincount(vmap) > 1):
        d = V[vmap == v, 2]
        jumps.append(d.max() - d.min())
    p = np.abs(itorus.periods()).max()
    # every jump is an integer combination of the periods
    assert np.allclose(np.asarray(jumps) / p, np.round(np.asarray(jumps) / p), atol=1e-9)
    assert np.isclose(max(jumps), p) or max(jumps) > p


def test_cut_embedding_rejects_insufficient_cut(itorus):
    with pytest.raises(MescherError, match="cut_edges"):
        itorus.cut_embedding(cut_edges=[0])
    # an ordinary mesh needs no cut
    V, F = shapes.torus(8, 5)
    m = Mescher.from_mesh(V, F)
    Vc, Fc, vmap = m.cut_embedding(cut_edges=[])
    assert Vc.shape[0] == m.n_vertices


def test_cut_embedding_of_impossible_ring_with_boundary():
    """A ring (two boundary loops) climbing 0.5 per turn is cut across, boundary to boundary."""
    V, F = shapes.annulus(24, 4)
    m0 = Mescher.from_mesh(V, F)
    ang = np.unwrap(np.arctan2(m0.xy[:, 1], m0.xy[:, 0])[m0.F], axis=1)
    m = Mescher.from_corner_depths(m0.F, m0.xy, 0.5 * ang / (2 * np.pi))
    assert np.allclose(np.abs(m.periods()), [0.5])
    Vc, Fc, vmap = m.cut_embedding()
    # one seam from the inner to the outer boundary: its vertices are doubled, and they form a
    # path of mesh edges touching both boundaries.  Which of the equally short paths is cut
    # depends on the graph library's tie-breaking (networkx 3.0 and 3.6 choose differently).
    count = np.bincount(vmap)
    dup = np.flatnonzero(count == 2)
    assert count.max() == 2 and Vc.shape[0] == m.n_vertices + len(dup)
    assert len(dup) >= 4  # at least the 4 rings from the inner boundary to the outer
    r = np.linalg.norm(m.xy[dup], axis=1)
    rr = np.linalg.norm(m.xy, axis=1)
    assert np.isclose(r.min(), rr.min()) and np.isclose(r.max(), rr.max())
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    E = np.asarray(m.edges)[np.isin(m.edges, dup).all(axis=1)]
    idx = np.searchsorted(dup, E)
    G = sp.coo_matrix((np.ones(len(idx)), (idx[:, 0], idx[:, 1])), shape=(len(dup),) * 2)
    assert connected_components(G, directed=False)[0] == 1  # one seam, through mesh edges
    for v in dup:
        d = Vc[vmap == v, 2]
        assert np.isclose(d.max() - d.min(), 0.5)
    m2 = Mescher.from_corner_depths(m.F, m.xy, Vc[Fc][:, :, 2])
    assert np.allclose(m2.zeta, m.zeta, atol=1e-12)


def test_smoothing_that_collapses_the_figure_is_refused_and_shrinking_is_warned_about():
    import warnings as _w

    from meschers_igl import MescherWarning, gallery

    m = gallery.get_model("penrose_triangle").mescher
    size = float(np.ptp(m.xy, axis=0).max())
    with pytest.raises(MescherError, match=r"t_xy: expected a smoothing time .* found 1e\+300"):
        m.smooth(t_xy=1e300)
    # backward Euler divides each mode by 1 + lambda t: at t = 1000 size^2 / 24 little is left
    with pytest.warns(MescherWarning, match=r"shrank the figure to \d\.\d\d% of its size"):
        ms = m.smooth(t_xy=1000.0)
    assert float(np.ptp(ms.xy, axis=0).max()) < 0.05 * size
    with _w.catch_warnings():
        _w.simplefilter("error")  # an ordinary time keeps the figure, silently
        ms = m.smooth(t_xy=1e-3)
    assert float(np.ptp(ms.xy, axis=0).max()) > 0.99 * size
