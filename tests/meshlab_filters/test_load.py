"""load_artist_model: hand-made artist files with known defects, exact report counts."""

from __future__ import annotations

import numpy as np
import pymeshlab
import pytest
from mlf_helpers import grid, tris, write_obj

from meschers_igl import MescherError
from meschers_igl.topology import edge_topology
from meshlab_filters import CleanupReport, clean_mesh, load_artist_model, read_meshset
from meshlab_filters._filters import FILTERS, check_filters, missing_filters


def check_consistent(rep: CleanupReport, V, F):
    """The report's counts add up and the output is manifold and coherently oriented."""
    assert rep.vertices_out == V.shape[0] and rep.faces_out == F.shape[0]
    assert rep.vertices_out == (
        rep.vertices_in
        - rep.duplicate_vertices_merged
        - rep.unreferenced_vertices_removed
        + rep.non_manifold_vertices_split
    )
    assert rep.faces_out == (
        rep.faces_in
        - rep.duplicate_faces_removed
        - rep.zero_area_faces_removed
        - rep.non_manifold_faces_removed
    )
    assert V.dtype == np.float64 and F.dtype == np.int64 and F.shape[1] == 3
    edge_topology(F, V.shape[0])  # raises on non-manifold or incoherent faces
    assert rep.orientable
    assert np.unique(F).size == V.shape[0]  # no unreferenced vertex left


def test_all_filters_exist_and_missing_ones_are_named():
    assert missing_filters() == []
    check_filters()
    with pytest.raises(MescherError, match="no_such_filter_xyz"):
        check_filters(["meshing_remove_null_faces", "no_such_filter_xyz"])
    assert set(FILTERS) <= set(pymeshlab.filter_list())


def test_quads_are_triangulated(tmp_path):
    V, Q = grid(2)
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "quads.obj", V, Q))
    assert (rep.polygons, rep.polygons_triangulated) == (4, 4)
    assert (rep.vertices_in, rep.faces_in) == (9, 8)
    assert not rep.changed and rep.changes() == {"polygons_triangulated": 4}
    assert np.array_equal(V1, V)
    check_consistent(rep, V1, F1)
    # Each quad became two triangles covering its area, all facing +z like the quads.
    A = np.cross(V1[F1[:, 1]] - V1[F1[:, 0]], V1[F1[:, 2]] - V1[F1[:, 0]])
    assert np.allclose(A[:, 2], 1.0) and np.allclose(A[:, :2], 0.0)
    assert "polygons triangulated: 4" in str(rep)


def test_mixed_polygon_sizes(tmp_path):
    # a pentagon fan (5 corners -> 3 triangles) beside a triangle
    ang = np.linspace(0, 2 * np.pi, 6)[:-1]
    V = np.column_stack([np.cos(ang), np.sin(ang), np.zeros(5)])
    V = np.vstack([V, [[2.0, 0.0, 0.0]]])
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "p.obj", V, [[0, 1, 2, 3, 4], [5, 1, 0]]))
    assert (rep.polygons, rep.polygons_triangulated, rep.faces_in) == (2, 1, 4)
    check_consistent(rep, V1, F1)


def test_duplicated_corners_are_merged_exactly(tmp_path):
    V, Q = grid(2)
    # every quad with its own four corners: 16 vertices for 9 positions
    Vd = V[Q.reshape(-1)]
    Qd = np.arange(16).reshape(4, 4)
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "dup.obj", Vd, Qd))
    assert rep.duplicate_vertices_merged == 7 and rep.vertices_out == 9
    check_consistent(rep, V1, F1)
    # vertex_map sends each input corner to the cleaned vertex at the same position
    assert np.array_equal(V1[rep.vertex_map], Vd)


def test_near_duplicates_survive_unless_merge_tol(tmp_path):
    # the cut of an impossible object: equal on screen, 1e-6 apart in depth -> never merged
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 1e-6], [1, 1, 0], [0, 1, 1e-6]])
    path = write_obj(tmp_path / "near.obj", V, [[0, 1, 2], [3, 4, 5]])
    V1, F1, rep = load_artist_model(path)
    assert rep.duplicate_vertices_merged == 0 and V1.shape[0] == 6
    V2, F2, rep2 = load_artist_model(path, merge_tol=1e-5)
    assert rep2.duplicate_vertices_merged == 2 and V2.shape[0] == 4
    assert rep2.vertex_map[1] == rep2.vertex_map[3] >= 0
    assert rep2.vertex_map[2] == rep2.vertex_map[5] >= 0
    check_consistent(rep2, V2, F2)
    with pytest.raises(MescherError, match="merge_tol"):
        load_artist_model(path, merge_tol=-1.0)


@pytest.mark.parametrize("which", [0, 3, 7])
def test_a_flipped_face_is_flipped_back(tmp_path, which):
    V, Q = grid(2)
    F = tris(Q)
    Fbad = F.copy()
    Fbad[which] = Fbad[which, ::-1]
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "flip.obj", V, Fbad))
    assert rep.faces_flipped == 1  # whichever face MeshLab took as its seed
    check_consistent(rep, V1, F1)
    # all faces face +z again, as the majority did
    A = np.cross(V1[F1[:, 1]] - V1[F1[:, 0]], V1[F1[:, 2]] - V1[F1[:, 0]])
    assert np.all(A[:, 2] > 0)


def test_duplicated_faces_are_removed(tmp_path):
    V, Q = grid(2)
    F = tris(Q)
    Fd = np.vstack([F, F[2], F[5, ::-1]])  # one exact copy, one reversed copy
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "dupf.obj", V, Fd))
    assert rep.duplicate_faces_removed == 2 and rep.faces_out == 8
    assert rep.non_manifold_faces_removed == 0
    check_consistent(rep, V1, F1)


def test_unreferenced_vertices_are_removed(tmp_path):
    V, Q = grid(2)
    Vx = np.vstack([V[:4], [[7.0, 7.0, 7.0]], V[4:], [[8.0, 8.0, 8.0], [9.0, 9.0, 9.0]]])
    Qx = np.where(Q >= 4, Q + 1, Q)
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "unref.obj", Vx, Qx))
    assert rep.unreferenced_vertices_removed == 3
    assert np.array_equal(np.flatnonzero(rep.vertex_map < 0), [4, 10, 11])
    keep = rep.vertex_map >= 0
    assert np.array_equal(V1[rep.vertex_map[keep]], Vx[keep])
    check_consistent(rep, V1, F1)


def test_zero_area_faces_are_removed(tmp_path):
    V, Q = grid(1)
    V = np.vstack([V, [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0]]])  # collinear with vertex 1
    faces = [list(Q[0]), [1, 4, 5]]
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "null.obj", V, faces))
    assert rep.zero_area_faces_removed == 1
    assert rep.unreferenced_vertices_removed == 2  # the sliver's own two vertices
    assert (rep.vertices_out, rep.faces_out) == (4, 2)
    check_consistent(rep, V1, F1)


def test_non_manifold_edges_are_repaired(tmp_path):
    V, Q = grid(2)
    F = tris(Q)
    # a fin: a third face on the interior edge (0, 4) of the grid, out of the plane
    V = np.vstack([V, [[0.5, 0.5, 1.0]]])
    Fx = np.vstack([F, [[0, 4, 9]]])
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "fin.obj", V, Fx))
    assert rep.non_manifold_faces_removed == 1
    assert rep.polygons is None  # PyMeshLab cannot walk polygons across a non-manifold edge
    check_consistent(rep, V1, F1)


def test_non_manifold_vertex_is_split():
    # two triangles touching at one vertex: a bow tie
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0.0]])
    F = np.array([[0, 1, 2], [0, 3, 4]])
    V1, F1, rep = clean_mesh(V, F)
    assert rep.non_manifold_vertices_split == 1 and rep.vertices_out == 6
    assert rep.components == 2
    check_consistent(rep, V1, F1)


def test_messy_file_counts_add_up(tmp_path):
    V, Q = grid(3)
    F = tris(Q)
    rng = np.random.default_rng(3)
    Fb = F.copy()
    Fb[rng.choice(len(F), 3, replace=False)] = Fb[rng.choice(len(F), 3, replace=False)][:, ::-1]
    Vx = np.vstack([V, V[:5], [[5.0, 5, 5]]])  # 5 exact duplicates, 1 unused
    Fb = np.vstack([Fb, Fb[:2]])
    Fb[1] = np.where(Fb[1] < 5, Fb[1] + 16, Fb[1])  # use the duplicated corners
    V1, F1, rep = load_artist_model(write_obj(tmp_path / "messy.obj", Vx, Fb))
    check_consistent(rep, V1, F1)
    d = rep.as_dict()
    assert "vertex_map" not in d and d["duplicate_faces_removed"] >= 2
    assert set(rep.changes()) <= set(d)


def _write_all_formats(tmp_path, V, F):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F))
    paths = {}
    for ext, kw in [("ply", {"binary": True}), ("off", {}), ("stl", {}), ("obj", {})]:
        p = tmp_path / f"model.{ext}"
        ms.save_current_mesh(str(p), **kw)
        paths[ext] = p
    p = tmp_path / "ascii.ply"
    ms.save_current_mesh(str(p), binary=False)
    paths["ascii ply"] = p
    return paths


def test_each_format(tmp_path):
    V, Q = grid(2)
    F = tris(Q)
    for fmt, path in _write_all_formats(tmp_path, V, F).items():
        V1, F1, rep = load_artist_model(path)
        check_consistent(rep, V1, F1)
        assert (rep.vertices_out, rep.faces_out) == (9, 8), fmt
        # (PyMeshLab's STL reader already unifies the 24 corners it stores into 9 vertices)
        assert rep.duplicate_vertices_merged == 0 and rep.vertices_in == 9, fmt
        # same surface: the same set of triangles as point triples
        key = np.sort(np.sort(V1[F1].reshape(-1, 9), axis=1), axis=0)
        assert np.allclose(key, np.sort(np.sort(V[F].reshape(-1, 9), axis=1), axis=0)), fmt


@pytest.mark.parametrize(
    "name, content, match",
    [
        ("garbage.obj", bytes(range(256)) * 3, "unreadable or corrupt"),
        ("empty.obj", b"", "empty file"),
        ("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        (
            "bad_index.off",
            b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 50\n",
            r"indices in \[0, 3\)|no faces",
        ),
        (
            "truncated.ply",
            b"ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
            b"property float y\nproperty float z\nelement face 10\n"
            b"property list uchar int vertex_indices\nend_header\n\x00\x00\x80\x3f",
            "unreadable or corrupt",
        ),
        ("garbage.stl", b"solid x\nthis is not an stl\n" * 3, "unreadable or corrupt"),
    ],
)
def test_corrupt_files_raise_naming_the_path(tmp_path, name, content, match):
    p = tmp_path / name
    p.write_bytes(content)
    with pytest.raises(MescherError, match=match) as info:
        load_artist_model(p)
    assert name in str(info.value)


def test_missing_path_and_directory(tmp_path):
    with pytest.raises(MescherError, match="nothing at .*nope.obj"):
        load_artist_model(tmp_path / "nope.obj")
    with pytest.raises(MescherError, match="directory"):
        load_artist_model(tmp_path)
    with pytest.raises(MescherError, match="path: expected a file path"):
        load_artist_model(3)


def test_read_meshset_keeps_the_raw_mesh(tmp_path):
    V, Q = grid(1)
    ms = read_meshset(write_obj(tmp_path / "q.obj", np.vstack([V, V[:1]]), Q))
    assert ms.current_mesh().vertex_number() == 5  # nothing cleaned yet


def test_report_str_and_dict_for_a_clean_mesh():
    V, Q = grid(1)
    V1, F1, rep = clean_mesh(V, tris(Q))
    assert not rep.changed and rep.changes() == {}
    assert "nothing to change" in str(rep) and "<arrays>" in str(rep)
    assert rep.as_dict()["faces_out"] == 2
