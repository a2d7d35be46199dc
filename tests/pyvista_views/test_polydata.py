"""The flattened soup: geometry, painter's depths, normals from zeta, scalars (no GL needed)."""

from __future__ import annotations

import igl
import numpy as np
import pytest
from pvv_helpers import back_to_front, sphere

from meschers_igl import Mescher, MescherError
from pyvista_views import to_polydata
from pyvista_views.polydata import PAINTER_DEPTH_FRACTION, draw_order, embedding_polydata


@pytest.fixture(scope="module")
def ball():
    V, F = sphere(12)
    return V, F, Mescher.from_mesh(V, F)


class OrderStub:
    """Anything with linear_extension() is accepted as a depth order (DesignOrder's protocol)."""

    def __init__(self, draw):
        self.draw = draw

    def linear_extension(self):
        return list(self.draw)


def test_soup_is_flat_xy_in_draw_order_with_increasing_depth(ball):
    V, F, m = ball
    draw = back_to_front(V, F)
    mesh = to_polydata(m, order=OrderStub(draw))
    P = np.asarray(mesh.points).reshape(-1, 3, 3)
    np.testing.assert_array_equal(mesh.cell_data["face_id"], draw)
    np.testing.assert_allclose(P[:, :, :2], np.asarray(m.xy)[F[draw]])
    np.testing.assert_array_equal(mesh.point_data["vertex_id"], F[draw].reshape(-1))
    z = P[:, :, 2]
    assert np.all(z == z[:, :1])  # each face flat in its own plane
    step = float(mesh.field_data["painter_step"][0])
    np.testing.assert_allclose(z[:, 0], np.arange(len(F)) * step)  # later faces nearer
    diagonal = np.hypot(*np.ptp(m.xy, axis=0))
    np.testing.assert_allclose(step * len(F), PAINTER_DEPTH_FRACTION * diagonal)


def test_default_order_is_face_index_order(ball):
    _, F, m = ball
    np.testing.assert_array_equal(to_polydata(m).cell_data["face_id"], np.arange(len(F)))


def test_flat_normals_are_the_meschers_face_normals_as_active_cell_normals(ball):
    V, F, m = ball
    draw = back_to_front(V, F)
    mesh = to_polydata(m, order=draw, shading="flat")
    np.testing.assert_allclose(mesh.cell_data.active_normals, m.face_normals()[draw])
    # an embeddable mescher: zeta's normals are the 3D mesh's (libigl) normals
    np.testing.assert_allclose(
        m.face_normals(), igl.per_face_normals(V, F, np.zeros(3)), atol=1e-12
    )
    assert mesh.point_data.active_normals is None


def test_smooth_normals_are_vertex_normals_per_corner(ball):
    V, F, m = ball
    mesh = to_polydata(m, shading="smooth", feature_angle=None)  # nothing split
    np.testing.assert_allclose(
        np.asarray(mesh.point_data.active_normals).reshape(-1, 3, 3),
        m.vertex_normals()[F],
        atol=1e-7,  # float32, as VTK draws them
    )
    area = igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA)
    np.testing.assert_allclose(m.vertex_normals(), area, atol=1e-12)


def test_scalars_per_vertex_go_to_corners_and_per_face_to_cells(ball):
    V, F, m = ball
    draw = back_to_front(V, F)
    s_v, s_f = V[:, 0], np.arange(len(F), dtype=float)
    mesh = to_polydata(m, order=draw, scalars={"x": s_v, "id": s_f})
    np.testing.assert_allclose(mesh.point_data["x"], s_v[F[draw]].reshape(-1))
    np.testing.assert_allclose(mesh.cell_data["id"], s_f[draw])
    assert mesh.active_scalars_name == "x"
    assert to_polydata(m).active_scalars_name is None  # ids are never colour-mapped by accident


@pytest.mark.parametrize(
    "order, words",
    [
        (np.arange(5), "permutation"),
        (np.zeros(1, dtype=int), "permutation"),
        ("pattern", "permutation"),
    ],
)
def test_bad_orders_are_refused(ball, order, words):
    *_, m = ball
    with pytest.raises(MescherError, match="order") as info:
        to_polydata(m, order=order)
    assert words in str(info.value)


def test_repeated_face_in_order_is_refused():
    draw = np.array([0, 1, 1, 3])
    with pytest.raises(MescherError, match="exactly once"):
        draw_order(draw, 4)


def test_bad_shading_and_scalars_are_refused(ball):
    *_, m = ball
    with pytest.raises(MescherError, match="shading"):
        to_polydata(m, shading="phong")
    with pytest.raises(MescherError, match=r"scalars.*per vertex"):
        to_polydata(m, scalars=np.zeros(7))


def test_embedding_soup_keeps_real_depth_and_libigl_normals(ball):
    V, F, _ = ball
    mesh = embedding_polydata(V, F, shading="flat")
    np.testing.assert_allclose(np.asarray(mesh.points).reshape(-1, 3, 3), V[F])
    np.testing.assert_allclose(
        mesh.cell_data.active_normals, igl.per_face_normals(V, F, np.zeros(3))
    )
    with pytest.raises(MescherError, match="V"):
        embedding_polydata(V[:, :2], F)


def test_render_kernels_compile_one_specialisation_for_read_only_and_writable_input(ball):
    """A mescher's arrays are read-only, a user's are writable: numba would compile a kernel once
    per flag combination (a first run compiling again inside each worker); the wrappers pass
    read-only views (copies only where the type or layout differ), so each kernel holds one
    signature."""
    from pyvista_views import normals, polydata

    V, F, m = ball
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    for writable in (True, False):
        Fi, Vi, Ni = F.copy(), V.copy(), fn.copy()
        for a in (Fi, Vi, Ni):
            a.flags.writeable = writable
        draw = np.arange(Fi.shape[0])
        draw.flags.writeable = writable
        polydata.provoking_cells(Fi, Vi.shape[0])
        polydata.indexed(Vi, Fi, draw, face_normals=Ni, provoking=True)
        normals.corner_groups(Fi, Ni, np.ones(Fi.shape[0]), 30.0)
    for d in (polydata._provoking_mesh, normals._rough_vertices):
        assert len(d.signatures) == 1, (d.py_func.__name__, d.signatures)
