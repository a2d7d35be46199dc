"""The straight cut (issue 17): a cut model cut as an artist cuts a bar.

``embedding.straight_cut`` splits the faces under one screen line and cuts the mescher there.
Checked: the split changes nothing (screen positions, zeta, periods); the cut model integrates
zeta on every face and jumps by the period across the seam; every seam vertex lies on one screen
line; and, against the painter's oracle, the z-buffered cut model shows exactly what the mescher
shows in its depth order, where the old cut along mesh edges showed slivers.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError
from meschers_igl.embedding import cut_embedding, cut_mismatch, straight_cut
from meschers_igl.gallery import get_model
from meschers_igl.shapes import torus

# the figures impossible through their period, at the study's first subdivision level (the
# gallery's impossible cube has straight bars and no period: its period-carrying variant)
CASES = {
    "penrose_triangle": {},
    "penrose_stairs": {"resolution": 1},
    "impossible_cube": {"resolution": 5, "straight_bars": False},
}


@pytest.fixture(scope="module", params=sorted(CASES))
def cut_case(request):
    g = get_model(request.param, **CASES[request.param])
    m, order = g.mescher.subdivide(1, scheme="midpoint", order=g.order)
    return g, m, order, straight_cut(m, order)


def test_split_keeps_the_mescher(cut_case):
    g, m, _, cut = cut_case
    m2 = cut.mescher
    n = m.n_vertices
    np.testing.assert_array_equal(m2.xy[:n], m.xy)
    # zeta integrated from vertex to vertex is unchanged: same depth differences along m's
    # unsplit edges, found by their end points in m2
    from meschers_igl.topology import edge_lookup

    e2, sign = edge_lookup(m2.edges, m2.n_vertices, m.edges[:, 0], m.edges[:, 1])
    kept = e2 >= 0
    assert kept.mean() > 0.9
    np.testing.assert_allclose(sign[kept] * m2.zeta[e2[kept]], m.zeta[kept], atol=1e-12 * m.scale())
    # the split faces cover the parent faces: screen areas add up
    a2 = np.bincount(cut.face_parent, weights=m2.face_areas(), minlength=m.n_faces)
    np.testing.assert_allclose(a2, m.face_areas(), rtol=1e-9, atol=1e-14)
    # the impossibility is intact: one jump of the gallery's period
    assert abs(abs(cut.jump) - g.expected_period) < 1e-9 * g.expected_period
    assert np.abs(m2.integrability_residual()).max() < 1e-10 * m.scale()


def test_cut_model_integrates_zeta_and_jumps_by_the_period(cut_case):
    g, _, _, cut = cut_case
    m2 = cut.mescher
    V, F, vmap = cut_embedding(m2, cut.cut_edges)
    np.testing.assert_array_equal(vmap[F], m2.F)  # face i is the mescher's face i
    # on every face: depth differences are the corner depths' (zeta on all uncut edges)
    Zc = V[F][:, :, 2]
    Zm = np.asarray(m2.corner_depths())
    np.testing.assert_allclose(Zc - Zc[:, :1], Zm - Zm[:, :1], atol=1e-9 * m2.scale())
    # across the seam: every vertex of the cut has two copies, one period apart in depth
    seam_v = np.unique(m2.edges[cut.cut_edges])
    copies = [np.flatnonzero(vmap == v) for v in seam_v]
    assert all(len(c) == 2 for c in copies)
    gaps = np.array([V[c[1], 2] - V[c[0], 2] for c in copies])
    np.testing.assert_allclose(np.abs(gaps), g.expected_period, rtol=1e-9)
    # only the seam is cut: no other vertex is duplicated
    assert V.shape[0] == m2.n_vertices + seam_v.size


def test_the_seam_is_one_straight_screen_line(cut_case):
    _, _, _, cut = cut_case
    m2 = cut.mescher
    seam_xy = m2.xy[np.unique(m2.edges[cut.cut_edges])]
    off = np.abs((seam_xy - cut.point) @ cut.normal)
    assert off.max() < 1e-12 * m2.scale()
    # and within the segment the cut reports
    d = cut.segment[1] - cut.segment[0]
    u = (seam_xy - cut.segment[0]) @ d / (d @ d)
    assert u.min() > -1e-9 and u.max() < 1 + 1e-9
    # a closed curve around the bar: every seam vertex ends two seam edges
    deg = np.bincount(m2.edges[cut.cut_edges].ravel(), minlength=m2.n_vertices)
    assert set(deg[deg > 0]) == {2}


def test_cut_model_shows_what_the_mescher_shows(cut_case):
    """Painter's oracle: the z-buffered cut model and the mescher in its order show the same
    face at every pixel; the old cut along mesh edges did not (slivers, wedges)."""
    _, m, order, cut = cut_case
    assert cut_mismatch(cut, order) == 0.0
    from meschers_igl.order import DepthOrder
    from meschers_igl.painter import visible_faces

    V, F, _ = cut_embedding(m)  # the cut along mesh edges, for contrast
    own = DepthOrder.from_embedding(m, V[F][:, :, 2])
    a, b = visible_faces(m, order, size=128), visible_faces(m, own, size=128)
    hit = (a >= 0) | (b >= 0)
    assert np.mean(a[hit] != b[hit]) > 0.01


def test_no_new_vertex_on_a_fold_of_the_penrose_triangle():
    """The cut passes through the bar's corner vertices, so every new vertex lies inside a flat
    side: its faces share one normal (no smooth-shading tick where the cut crosses a fold)."""
    g = get_model("penrose_triangle")
    m, order = g.mescher.subdivide(2, scheme="midpoint", order=g.order)
    cut = straight_cut(m, order)
    m2 = cut.mescher
    new = np.arange(m.n_vertices, m2.n_vertices)
    N, F = m2.face_normals(), m2.F
    rows = np.flatnonzero(np.isin(F, new).any(axis=1))
    vn = m2.vertex_normals()
    for f in rows:  # a few dozen faces
        for v in F[f][np.isin(F[f], new)]:
            assert np.dot(N[f], vn[v]) > 1 - 1e-9


def test_straight_cut_refuses_what_it_cannot_cut():
    V, F = torus(12, 6, 2.0, 0.6)
    m = Mescher.from_mesh(V, F, view=(0.0, 0.3, 1.0), up=(0.0, 1.0, 0.0))
    with pytest.raises(MescherError, match="every period 0"):
        straight_cut(m)
    with pytest.raises(MescherError, match="directions"):
        straight_cut(m.with_periods([0.0, 1.0]), directions=0)
    # the gallery's straight-barred cube is impossible through its order only: nothing to cut
    with pytest.raises(MescherError, match="every period 0"):
        straight_cut(get_model("impossible_cube", resolution=2).mescher)


def test_mescher_method_is_the_function():
    from meschers_igl import shapes

    m = shapes.impossible_torus(24, 8, climb=1.0)
    cut = m.straight_cut()
    assert cut.jump == pytest.approx(1.0, rel=1e-12)
    Vc, Fc, vmap = cut.mescher.cut_embedding(cut.cut_edges)
    # the seam's copies sit one period apart in depth, on one screen line
    seam = np.bincount(vmap, minlength=cut.mescher.n_vertices) > 1
    assert seam.any()
    for v in np.flatnonzero(seam):
        z = np.sort(Vc[vmap == v, 2])
        assert z[-1] - z[0] == pytest.approx(1.0, rel=1e-9)
    d = (np.asarray(cut.mescher.xy)[seam] - cut.point) @ cut.normal
    assert np.abs(d).max() < 1e-9
