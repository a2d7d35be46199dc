"""cut_model_to_mescher and the exports to files MeshLab opens."""

from __future__ import annotations

import numpy as np
import pymeshlab
import pytest
from mlf_helpers import ramp_ring, tris, write_obj

from meschers_igl import MescherError
from meschers_igl.order import DepthOrder
from meschers_igl.paradox import paradox_model
from meshlab_filters import (
    cut_model_to_mescher,
    export_bent_embedding,
    export_cut_embedding,
    export_render_mesh,
    scalars_to_colors,
)
from meshlab_filters.convert import render_levels

VIRIDIS_0 = np.array([68, 1, 84]) / 255  # MeshLab's viridis at the bottom and top of the range
VIRIDIS_1 = np.array([253, 231, 36]) / 255


@pytest.fixture(scope="module")
def ring():
    V, Q, cut = ramp_ring(N=12, gap=0.9)
    m, order = cut_model_to_mescher((V, tris(Q)), merge=cut)
    return m, order


@pytest.fixture(scope="module")
def penrose():
    pm = paradox_model("penrose_triangle")  # shipped with meschers_igl (ParadoxToolkit, GPL-3.0)
    m, order, rep = cut_model_to_mescher(pm.obj, view=pm.view, up=pm.up, return_report=True)
    return m, order, rep, pm


def test_ring_cut_model_has_the_depth_gap_as_period(ring):
    m, order = ring
    # 13 columns of 3 vertices, the last column glued onto the first: an annulus (chi 0)
    assert (m.n_vertices, m.n_faces, m.euler_characteristic()) == (36, 48, 0)
    assert np.allclose(np.abs(m.periods()), [0.9], atol=1e-12)
    assert m.is_impossible()
    assert order.n_arcs == 0  # a flat annulus seen head-on: no face overlaps another


def test_ring_from_a_file_translates_merge_through_clean_up(tmp_path):
    V, Q, cut = ramp_ring(N=10, gap=0.5)
    # an unused vertex first shifts every index; quads are triangulated by the loader
    Vx = np.vstack([[[9.0, 9.0, 9.0]], V])
    path = write_obj(tmp_path / "ring.obj", Vx, Q + 1)
    m, order, rep = cut_model_to_mescher(path, merge=cut + 1, return_report=True)
    assert rep.unreferenced_vertices_removed == 1 and rep.polygons_triangulated == Q.shape[0]
    assert np.allclose(np.abs(m.periods()), [0.5], atol=1e-12)
    with pytest.raises(MescherError, match="removed"):
        cut_model_to_mescher(path, merge=[[0, 1]])


def test_penrose_triangle_period_and_order(penrose):
    m, order, rep, pm = penrose
    meta = pm.meta
    gap = meta["verification"]["depth_gaps"][0]
    p = np.abs(m.periods())
    assert np.isclose(p.max(), gap, rtol=1e-5) and np.count_nonzero(p > 1e-6 * gap) == 1
    assert rep.polygons_triangulated == meta["verification"]["F"]  # 28 quads
    assert m.euler_characteristic() == meta["verification"]["glued_chi"]
    # the order is DepthOrder.from_embedding with the cut model's own depths V . view_dir
    V = np.loadtxt([ln[2:] for ln in pm.obj.read_text().splitlines() if ln.startswith("v ")])
    view = np.asarray(meta["camera"]["view_dir"])
    # the loader keeps the file's vertices here (nothing to clean), so F indexes V
    assert rep.vertex_map.tolist() == list(range(V.shape[0]))
    F = _cleaned_faces(pm.obj)
    expected = DepthOrder.from_embedding(m, (V @ view / np.linalg.norm(view))[F])
    assert order == expected and order.n_arcs > 0
    assert order.cycles(warn=False) == []


def _cleaned_faces(path):
    from meshlab_filters import load_artist_model

    return load_artist_model(path)[1]


def test_bad_input_to_cut_model_to_mescher():
    with pytest.raises(MescherError, match="path_or_V_F"):
        cut_model_to_mescher(42)
    with pytest.raises(MescherError, match="V"):
        cut_model_to_mescher((np.zeros((3, 2)), [[0, 1, 2]]))


# ----------------------------------------------------------------------------------- exports
_KEEP = []  # a Mesh from current_mesh() is a view into its MeshSet: keep the MeshSets alive


def _reopen(path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    _KEEP.append(ms)
    return ms.current_mesh()


@pytest.mark.parametrize("ext", ["ply", "obj", "off"])
def test_export_cut_embedding_counts_and_colours(tmp_path, ring, ext):
    m, _ = ring
    # cut along the ring's seam (the radius on the +x axis); the default cut is the core's
    xy = np.asarray(m.xy)
    on_seam = (np.abs(xy[:, 1]) < 1e-12) & (xy[:, 0] > 0)
    cut = np.flatnonzero(on_seam[m.edges].all(axis=1))
    assert cut.size == 2
    Vc, Fc, vmap = m.cut_embedding(cut)
    s = np.asarray(m.xy[:, 0])
    path = export_cut_embedding(m, tmp_path / f"cut.{ext}", scalars=s, cut_edges=cut)
    mesh = _reopen(path)
    assert (mesh.vertex_number(), mesh.face_number()) == (Vc.shape[0], m.n_faces)
    assert np.allclose(mesh.vertex_matrix(), Vc, atol=1e-6)
    assert np.array_equal(mesh.face_matrix(), Fc)
    C = mesh.vertex_color_matrix()
    assert np.allclose(C, scalars_to_colors(s[vmap]), atol=1.5 / 255)
    assert np.allclose(C[np.argmin(s[vmap]), :3], VIRIDIS_0, atol=1.5 / 255)
    assert np.allclose(C[np.argmax(s[vmap]), :3], VIRIDIS_1, atol=1.5 / 255)
    # the cut: the depth jumps by the period somewhere, so there are more vertices than m has
    assert Vc.shape[0] > m.n_vertices


def test_export_bent_embedding_and_stl(tmp_path, ring):
    m, _ = ring
    Vb, Fb = m.bent_embedding()
    mesh = _reopen(export_bent_embedding(m, tmp_path / "bent.ply"))
    assert np.array_equal(mesh.vertex_matrix(), Vb)  # binary PLY keeps float64 exactly
    assert np.array_equal(mesh.face_matrix(), Fb)
    assert not mesh.has_vertex_color()
    z = np.asarray(m.hodge().z)
    mesh = _reopen(export_bent_embedding(m, tmp_path / "bent.stl", scalars=z))
    assert mesh.face_number() == m.n_faces  # STL keeps no colours, but the file is written


def test_colours_clamp_to_vmin_vmax():
    C = scalars_to_colors([-5.0, 0.0, 0.5, 1.0, 5.0], vmin=0.0, vmax=1.0)
    assert np.allclose(C[0, :3], VIRIDIS_0, atol=1 / 255)
    assert np.allclose(C[-1, :3], VIRIDIS_1, atol=1 / 255)
    assert np.allclose(C[0], C[1]) and np.allclose(C[-1], C[-2])
    # a constant field is the bottom colour, not MeshLab's automatic range
    assert np.allclose(scalars_to_colors([2.0, 2.0])[:, :3], VIRIDIS_0, atol=1 / 255)
    with pytest.raises(MescherError, match="colormap"):
        scalars_to_colors([0.0, 1.0], colormap="jet")
    with pytest.raises(MescherError, match="vmin"):
        scalars_to_colors([0.0, 1.0], vmin=2.0, vmax=1.0)


def test_export_render_mesh_respects_the_order(tmp_path, penrose):
    m, order, _, _ = penrose
    s = np.asarray(m.xy[:, 1])
    path = export_render_mesh(m, tmp_path / "render.ply", order=order, scalars=s)
    mesh = _reopen(path)
    assert (mesh.vertex_number(), mesh.face_number()) == (3 * m.n_faces, m.n_faces)
    V = mesh.vertex_matrix()
    perm = order.linear_extension(warn=False)
    Fm = np.asarray(m.F)[perm]
    assert np.array_equal(V[:, :2], np.asarray(m.xy)[Fm.reshape(-1)])  # flattened screen soup
    z = V[::3, 2]
    assert np.all(V[:, 2].reshape(-1, 3) == z[:, None])  # each face flat at one depth
    zf = np.empty(m.n_faces)
    zf[perm] = z
    arcs = np.asarray(order.arcs)
    assert np.all(zf[arcs[:, 1]] > zf[arcs[:, 0]])  # every face in front is drawn nearer
    # the file carries the mescher's normals (PyMeshLab's reader recomputes its own, so read the
    # binary PLY's vertex records directly: x y z nx ny nz as doubles, rgba bytes, quality)
    raw = path.read_bytes()
    body = raw[raw.index(b"end_header\n") + len(b"end_header\n") :]
    rec = np.dtype([("p", "<f8", 3), ("n", "<f8", 3), ("c", "u1", 4), ("q", "<f8")])
    assert b"property double nx" in raw[: len(raw) - len(body)]
    verts = np.frombuffer(body, dtype=rec, count=3 * m.n_faces)
    N = np.repeat(np.asarray(m.face_normals())[perm], 3, axis=0)
    assert np.allclose(verts["n"], N, atol=1e-12)
    assert np.array_equal(verts["q"], s[Fm.reshape(-1)])  # the scalars themselves, exactly
    C = mesh.vertex_color_matrix()
    assert np.allclose(C, scalars_to_colors(s[Fm.reshape(-1)]), atol=1.5 / 255)


def test_render_levels_longest_chain():
    # arcs 0 -> 1 -> 2 and 0 -> 2, 3 alone: levels 0, 1, 2, 0
    order = DepthOrder(4, [[0, 1], [1, 2], [0, 2]])
    perm, level = render_levels(order, 4)
    assert level.tolist() == [0, 1, 2, 0]
    assert sorted(perm.tolist()) == [0, 1, 2, 3]
    perm, level = render_levels(None, 4)
    assert perm.tolist() == [0, 1, 2, 3] and level.tolist() == [0, 0, 0, 0]
    with pytest.raises(MescherError, match="order"):
        render_levels(np.array([0, 0, 1, 2]), 4)


def test_render_mesh_without_order_is_flat(tmp_path, ring):
    m, _ = ring
    mesh = _reopen(export_render_mesh(m, tmp_path / "flat.obj"))
    assert mesh.face_number() == m.n_faces and np.all(mesh.vertex_matrix()[:, 2] == 0)


def test_export_errors(tmp_path, ring):
    m, _ = ring
    with pytest.raises(MescherError, match="m: expected a meschers_igl.Mescher, found str"):
        export_bent_embedding("not a mescher", tmp_path / "x.ply")
    # the message names the argument, the expected count and the found shape
    with pytest.raises(MescherError, match=rf"scalars.*{m.n_vertices}.*3"):
        export_bent_embedding(m, tmp_path / "x.ply", scalars=np.ones(3))
    with pytest.raises(MescherError, match="existing folder"):
        export_bent_embedding(m, tmp_path / "no" / "x.ply")
    with pytest.raises(MescherError, match=r"can write, found '.*x\.unknownformat'"):
        export_bent_embedding(m, tmp_path / "x.unknownformat")
    # a refused export leaves nothing behind: no partial file, no folder created
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    # and the refusals did not touch the mescher: a valid export still writes it exactly
    Vb, Fb = m.bent_embedding()
    mesh = _reopen(export_bent_embedding(m, tmp_path / "ok.ply"))
    assert np.array_equal(mesh.vertex_matrix(), Vb) and np.array_equal(mesh.face_matrix(), Fb)


def test_model_to_mescher_keeps_the_hidden_side_of_a_cut_file_or_not():
    """A cut file through the any-model door: by default the cut-model path's closed surface
    (the same faces and periods as cut_model_to_mescher); hidden=False the visible surface
    only (every face toward the viewer, open), with the same period."""
    from meschers_igl import MescherError
    from meschers_igl.paradox import paradox_model
    from meshlab_filters import model_to_mescher

    pm = paradox_model("penrose_triangle")
    mc, _ = cut_model_to_mescher(pm.obj, view=pm.view, up=pm.up)
    m, order, rep = model_to_mescher(pm.obj, view=pm.view, up=pm.up)
    assert m.n_faces == mc.n_faces and m.euler_characteristic() == mc.euler_characteristic()
    assert np.allclose(np.sort(np.abs(m.periods())), np.sort(np.abs(mc.periods())))
    assert rep.route == "cut" and "route: cut (an open seam" in str(rep)
    mv, _, repv = model_to_mescher(pm.obj, view=pm.view, up=pm.up, hidden=False)
    assert np.all(np.asarray(mv.face_normals())[:, 2] > 0) and mv.n_faces != m.n_faces
    assert np.isclose(np.abs(mv.periods()).max(), np.abs(mc.periods()).max(), rtol=1e-6)
    with pytest.raises(MescherError, match="hidden"):
        model_to_mescher(pm.obj, view=pm.view, up=pm.up, hidden="sometimes")
