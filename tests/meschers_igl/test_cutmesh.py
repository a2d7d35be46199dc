"""Mescher.from_cut_mesh on hand-sized cut models with exact answers."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, MescherWarning
from meschers_igl.cutmesh import check_gluing, glue_cut_mesh
from meschers_igl.gallery.polycube import box_union_surface

SQUARE = np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])  # counter-clockwise


def tube(h: float = 3.0, rings: int = 4, z0: float = 0.0, top_tilt: float = 0.0):
    """Open square tube along z (seen along z its two end loops coincide), outward faces.

    Vertex ``4 k + j`` is corner ``j`` of ring ``k`` at height ``z0 + k h / (rings - 1)``.
    """
    z = z0 + np.linspace(0.0, h, rings)
    V = np.concatenate([np.c_[SQUARE, np.full(4, zk)] for zk in z])
    V[-4:, 2] += top_tilt * SQUARE[:, 0]
    k, j = np.meshgrid(np.arange(rings - 1), np.arange(4), indexing="ij")
    a, b = 4 * k + j, 4 * k + (j + 1) % 4
    c, d = b + 4, a + 4
    F = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return V, F


def test_tube_glues_into_a_torus_with_exact_depths():
    h = 3.0
    V, F = tube(h)
    m, vmap = Mescher.from_cut_mesh(V, F, return_map=True)
    assert (m.n_vertices, m.n_edges, m.n_faces) == (12, 36, 24)
    assert m.euler_characteristic() == 0
    np.testing.assert_array_equal(vmap, np.r_[np.arange(12), np.arange(4)])
    np.testing.assert_array_equal(m.F, vmap[F])
    np.testing.assert_allclose(m.xy, V[:12, :2])
    # zeta by hand: h/3 up from ring k to ring k+1 (mod 3, through the seam), 0 along a ring
    ring = np.asarray(m.edges) // 4
    step = (ring[:, 1] - ring[:, 0]) % 3
    want = np.select([step == 1, step == 2], [h / 3, -h / 3], 0.0)
    np.testing.assert_allclose(m.zeta, want, atol=1e-12)
    np.testing.assert_allclose(np.sort(np.abs(m.periods())), [0.0, h], atol=1e-12)
    assert m.is_impossible()


def test_tube_pairing_reports_the_translation():
    V, F = tube(3.0)
    g = glue_cut_mesh(V, F)
    (p,) = g["pairings"]
    assert abs(p.depth_gap) == pytest.approx(3.0)
    assert p.translation_residual == 0.0 and p.screen_residual == 0.0
    assert g["unpaired"] == []


def test_explicit_pairs_match_the_automatic_gluing():
    V, F = tube(2.0)
    auto = Mescher.from_cut_mesh(V, F)
    m = Mescher.from_cut_mesh(V, F, merge=[(j, 12 + j) for j in range(4)])
    np.testing.assert_array_equal(m.F, auto.F)
    np.testing.assert_allclose(m.zeta, auto.zeta)
    with pytest.raises(MescherError, match=r"merge: expected pairs that coincide on screen"):
        Mescher.from_cut_mesh(V, F, merge=[(0, 13)])
    with pytest.raises(MescherError, match=r"merge: expected an integer array of shape \(n, 2\)"):
        Mescher.from_cut_mesh(V, F, merge=[0, 12])
    with pytest.raises(MescherError, match=r"merge: expected vertex indices in \[0, 16\)"):
        Mescher.from_cut_mesh(V, F, merge=[(0, 16)])


def test_closed_mesh_front_back_pairs_are_never_merged():
    """A closed cube seen along its diagonal: two corners coincide on screen but are not on any
    boundary, so nothing is glued and the result is from_mesh's."""
    V, F, _ = box_union_surface([((0, 0, 0), (1, 1, 1))], h=1.0)
    assert V.shape == (8, 3)
    m, vmap = Mescher.from_cut_mesh(V, F, view=(1, 1, 1), up=(0, 0, 1), return_map=True)
    ref = Mescher.from_mesh(V, F, view=(1, 1, 1), up=(0, 0, 1))
    np.testing.assert_array_equal(vmap, np.arange(8))
    np.testing.assert_array_equal(m.F, ref.F)
    np.testing.assert_allclose(m.xy, ref.xy, atol=1e-15)
    np.testing.assert_allclose(m.zeta, ref.zeta, atol=1e-12)
    xy = np.asarray(m.xy)
    assert np.linalg.norm(xy[0] - xy[7]) < 1e-12  # the front/back pair is really there


def test_boundary_over_interior_vertices_is_not_glued():
    """An open box (no lid) seen from above: the rim coincides on screen with the bottom
    corners, which are interior vertices, so the rim stays open."""
    V, F, _ = box_union_surface([((0, 0, 0), (1, 1, 1))], h=0.5, cuts=[(2, 1.0, (0, 0), (1, 1))])
    m, vmap = Mescher.from_cut_mesh(V, F, return_map=True)
    np.testing.assert_array_equal(vmap, np.arange(V.shape[0]))
    assert m.euler_characteristic() == 1  # a disc
    np.testing.assert_allclose(m.zeta, Mescher.from_mesh(V, F).zeta, atol=1e-12)


def test_ambiguous_loops_are_refused():
    """Two coaxial tubes: four loops coincide on screen, each a translate of the others."""
    Va, Fa = tube(1.0)
    Vb, Fb = tube(1.0, z0=2.0)
    V, F = np.concatenate([Va, Vb]), np.concatenate([Fa, Fb + len(Va)])
    with pytest.raises(MescherError, match="ambiguous"):
        Mescher.from_cut_mesh(V, F)


def test_non_translation_gluing_is_averaged_projected_and_reported():
    """Tilting the top loop keeps it on the bottom loop on screen but breaks the common
    translation: the two sides' depths are averaged, with a warning, and made integrable."""
    V, F = tube(3.0, top_tilt=0.3)
    with pytest.warns(MescherWarning, match="averaged and projected"):
        m = Mescher.from_cut_mesh(V, F)
    assert m.euler_characteristic() == 0
    np.testing.assert_allclose(m.integrability_residual(), 0.0, atol=1e-10)
    # the tilt is antisymmetric across the square, so the climb per turn stays the mean gap
    assert np.abs(m.periods()).max() == pytest.approx(3.0, rel=1e-9)


def test_untilted_tube_does_not_warn():
    """A gluing by a pure translation needs no averaging: no warning, and zeta is the model's
    own depth differences, untouched by the projection (the climb is exactly the gap)."""
    V, F = tube(5.0, rings=5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m, vmap = Mescher.from_cut_mesh(V, F, return_map=True)
    # every face's own depth differences survive exactly (no averaging, no projection change)
    Z = V[:, 2][F]
    zh = Z[:, [2, 0, 1]] - Z[:, [1, 2, 0]]  # half-edge opposite corner i runs i+1 -> i+2
    np.testing.assert_allclose(m.face_edge_signs * m.zeta[m.face_edges], zh, atol=1e-12)
    assert np.abs(m.periods()).max() == pytest.approx(5.0, rel=1e-12)
    assert m.n_vertices == 16 and m.euler_characteristic() == 0


def test_bad_gluing_is_refused_by_name():
    F = np.array([[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    # one shared corner: two fans meeting at a point
    vmap = np.array([0, 1, 2, 0, 3, 4, 5, 6, 7])
    with pytest.raises(MescherError, match=r"separate fans meet .*\[0, 3\]"):
        check_gluing(F, vmap)
    # two corners of one face glued: the face collapses
    with pytest.raises(MescherError, match=r"face 0 = \[0, 1, 2\] collapsing .*\[0, 1\]"):
        check_gluing(F, np.array([0, 0, 1, 2, 3, 4, 5, 6, 7]))
    # an edge traversed the same way by two faces: non-orientable
    with pytest.raises(MescherError, match=r"orientable .*\[0, 3\], \[1, 4\]"):
        check_gluing(F, np.array([0, 1, 2, 0, 1, 3, 4, 5, 6]))
    # three faces on one edge
    with pytest.raises(
        MescherError, match=r"manifold surface after gluing, found edge \[0, 1\] in 3"
    ):
        check_gluing(F, np.array([0, 1, 2, 1, 0, 3, 0, 1, 4]))


def test_bad_input_names_the_argument():
    V, F = tube()
    with pytest.raises(MescherError, match="tol"):
        Mescher.from_cut_mesh(V, F, tol=-1.0)
    Vn = V.copy()
    Vn[0, 0] = np.nan
    with pytest.raises(MescherError, match="V: expected finite"):
        Mescher.from_cut_mesh(Vn, F)
    with pytest.raises(MescherError, match=r"F: expected indices < 16"):
        Mescher.from_cut_mesh(V, F + 1)
    with pytest.raises(MescherError, match="view"):
        Mescher.from_cut_mesh(V, F, view=(0, 0, 0))
