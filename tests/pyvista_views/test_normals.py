"""Smooth shading splits normals at a feature angle (pyvista_views.normals)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from pvv_helpers import luminance, requires_gl

from meschers_igl import Mescher, MescherError
from meschers_igl.gallery import get_model
from pyvista_views import render
from pyvista_views.normals import as_feature_angle, corner_groups


def _box():
    b = pv.Box(level=2).triangulate().clean()
    V = np.asarray(b.points, dtype=np.float64)
    R = pv.transformations.axis_angle_rotation((1, 1, 0), 35)[:3, :3]
    return Mescher.from_mesh(V @ R.T, b.regular_faces.astype(np.int64))


def test_at_180_degrees_the_groups_are_the_vertices_and_their_normals():
    s = pv.Sphere(theta_resolution=12, phi_resolution=12)
    m = Mescher.from_mesh(np.asarray(s.points, float), s.regular_faces.astype(np.int64))
    F = np.asarray(m.F)
    groups, gv, gn = corner_groups(F, m.face_normals(), m.face_areas(), 180.0)
    assert np.unique(groups).shape[0] == m.n_vertices
    np.testing.assert_array_equal(gv[groups], F)
    np.testing.assert_allclose(gn[groups], np.asarray(m.vertex_normals())[F], atol=1e-12)


def test_a_box_keeps_its_face_normals_at_every_corner():
    m = _box()
    F = np.asarray(m.F)
    N = np.asarray(m.face_normals())
    groups, gv, gn = corner_groups(F, N, m.face_areas(), 30.0)
    np.testing.assert_allclose(gn[groups], np.repeat(N[:, None], 3, axis=1), atol=1e-12)
    # a box corner vertex belongs to three groups (one per side)
    counts = np.bincount(gv[np.unique(groups)], minlength=m.n_vertices)
    assert counts.max() == 3 and counts.min() == 1


def test_a_fine_sphere_is_not_split():
    s = pv.Sphere(theta_resolution=48, phi_resolution=48)
    m = Mescher.from_mesh(np.asarray(s.points, float), s.regular_faces.astype(np.int64))
    groups, _, _ = corner_groups(np.asarray(m.F), m.face_normals(), m.face_areas(), 30.0)
    assert np.unique(groups).shape[0] == m.n_vertices


@pytest.mark.parametrize("bad", [-1, 181, "x"])
def test_feature_angle_is_checked(bad):
    with pytest.raises(MescherError, match="feature_angle"):
        as_feature_angle(bad)


@requires_gl
@pytest.mark.parametrize("name", ["penrose_stairs", "penrose_triangle"])
def test_smooth_shading_of_a_box_model_invents_no_crease(name):
    """On a model made of flat sides, smooth shading equals flat shading (no blurred bands at
    the edges, no false diagonal); with plain vertex normals it does not."""
    g = get_model(name)
    m, order = g.mescher.subdivide(1, order=g.order)
    kw = dict(window_size=(256, 256), lights=[(1, 1, 1)])
    flat = luminance(render(m, order, shading="flat", **kw))
    smooth = luminance(render(m, order, shading="smooth", **kw))
    blurred = luminance(render(m, order, shading="smooth", feature_angle=None, **kw))
    figure = flat < 250
    assert np.abs(smooth - flat)[figure].mean() < 0.5
    assert np.abs(blurred - flat)[figure].mean() > 3.0
