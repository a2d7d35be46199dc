"""save/load round trips bit-exactly; corrupt and truncated files raise MescherError."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, load, save, shapes


@pytest.fixture
def mescher():
    m = shapes.impossible_torus(12, 6, climb=0.7)
    # user edge order/orientation that is not canonical must survive too
    perm = np.random.default_rng(0).permutation(m.n_edges)
    E = m.edges[perm].copy()
    E[::3] = E[::3, ::-1]
    z = m.zeta[perm].copy()
    z[::3] *= -1
    return Mescher(m.F, m.xy, E, z)


@pytest.mark.parametrize("ext", [".ply", ".npz"])
def test_round_trip_is_bit_exact(tmp_path, mescher, ext):
    p = save(mescher, tmp_path / f"m{ext}")
    m2 = load(p)
    for a, b in [
        (mescher.F, m2.F),
        (mescher.xy, m2.xy),
        (mescher.edges, m2.edges),
        (mescher.zeta, m2.zeta),
    ]:
        assert np.array_equal(a, b) and a.dtype == b.dtype


@pytest.mark.parametrize("ext", [".ply", ".npz"])
def test_corrupt_and_truncated_files(tmp_path, mescher, ext):
    p = save(mescher, tmp_path / f"m{ext}")
    data = p.read_bytes()
    (tmp_path / f"t{ext}").write_bytes(data[: len(data) * 2 // 3])
    with pytest.raises(MescherError):
        load(tmp_path / f"t{ext}")
    (tmp_path / f"g{ext}").write_bytes(b"\x00garbage" * 50)
    with pytest.raises(MescherError):
        load(tmp_path / f"g{ext}")
    with pytest.raises(MescherError, match="expected an existing file"):
        load(tmp_path / f"missing{ext}")


def test_ply_with_broken_zeta_is_refused(tmp_path, mescher):
    p = save(mescher, tmp_path / "m.ply")
    data = bytearray(p.read_bytes())
    # overwrite the last edge's zeta with a large value: after the header, the vertices
    # (3 doubles), faces (uchar + 3 ints) and edges (2 ints + a double)
    body = data.index(b"end_header\n") + len(b"end_header\n")
    m = mescher
    end_of_edges = body + 24 * m.n_vertices + 13 * m.n_faces + 16 * m.n_edges
    data[end_of_edges - 8 : end_of_edges] = np.float64(123.0).tobytes()
    p.write_bytes(bytes(data))
    with pytest.raises(MescherError, match="locally integrable"):
        load(p)


def test_unknown_extension(tmp_path, mescher):
    with pytest.raises(MescherError, match=r"\.ply or \.npz"):
        save(mescher, tmp_path / "m.obj")


def test_ply_opens_as_flat_mesh_in_pymeshlab(tmp_path, mescher):
    pymeshlab = pytest.importorskip("pymeshlab")
    p = save(mescher, tmp_path / "m.ply")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(p))
    cm = ms.current_mesh()
    assert cm.vertex_number() == mescher.n_vertices and cm.face_number() == mescher.n_faces
    assert np.allclose(cm.vertex_matrix()[:, :2], mescher.xy)
    assert np.array_equal(cm.face_matrix(), mescher.F)


@pytest.mark.parametrize("fmt", ["ply", "npz"])
def test_explicit_format_reads_and_writes_any_name(tmp_path, mescher, fmt):
    # The PyVista reader hands us "x.mescher": no renaming needed with format=.
    p = save(mescher, tmp_path / "x.mescher", format=fmt)
    assert p == tmp_path / "x.mescher" and p.is_file()
    assert sorted(q.name for q in tmp_path.iterdir()) == ["x.mescher"]  # no suffix added
    m2 = load(p, format=fmt)
    assert np.array_equal(m2.zeta, mescher.zeta) and np.array_equal(m2.F, mescher.F)
    with pytest.raises(MescherError, match=r"\.ply or \.npz"):
        load(p)  # without format=, the suffix decides
    with pytest.raises(MescherError, match="format: expected one of 'ply', 'npz', found 'obj'"):
        save(mescher, tmp_path / "y.obj", format="obj")


@pytest.mark.parametrize("ext", [".ply", ".npz"])
def test_load_returns_the_same_shape_whatever_the_file_holds(tmp_path, mescher, ext):
    from meschers_igl import DepthOrder

    order = DepthOrder(mescher.n_faces, [[0, 1], [2, 3]], m=mescher)
    with_order = save(mescher, tmp_path / f"o{ext}", order=order)
    without = save(mescher, tmp_path / f"n{ext}")
    # return_order=False (the default): always a Mescher, also when the file holds an order
    assert isinstance(load(with_order), Mescher) and isinstance(load(without), Mescher)
    # return_order=True: always a pair, the order None when the file holds none
    m1, o1 = load(with_order, return_order=True)
    m2, o2 = load(without, return_order=True)
    assert o2 is None and isinstance(m2, Mescher)
    assert sorted(map(tuple, np.asarray(o1.arcs).tolist())) == [(0, 1), (2, 3)]
    with pytest.raises(MescherError, match="return_order: expected True or False"):
        load(without, return_order="yes")


@pytest.mark.parametrize("ext", [".ply", ".npz"])
def test_a_loaded_mescher_keeps_the_homology_basis(tmp_path, ext):
    """A subdivided mescher measures periods on its parent's loops (not a fresh tree-cotree's):
    the file keeps them, so periods() read back entry by entry (issue 13.2)."""
    from meschers_igl import shapes

    m = shapes.impossible_torus(12, 6, climb=0.9)
    c = m.subdivide(1).smooth(t_zeta=0.01)
    np.testing.assert_allclose(c.periods(), m.periods(), atol=1e-12)  # [0, 0.9]
    c2 = load(save(c, tmp_path / f"c{ext}"))
    np.testing.assert_allclose(c2.periods(), [0.0, 0.9], atol=1e-12)
    fresh = Mescher(c.F, c.xy, c.edges, c.zeta)  # without the stored loops: another basis
    assert not np.allclose(fresh.periods(), [0.0, 0.9], atol=1e-6)


def test_with_generators_checks_the_loops():
    from meschers_igl import shapes

    m = shapes.impossible_torus(8, 4, climb=0.5)
    loops = m.homology_generators()
    assert np.array_equal(m.with_generators(loops[::-1]).periods(), m.periods()[::-1])
    with pytest.raises(MescherError, match="loops: expected 2 homology loops, found 1"):
        m.with_generators(loops[:1])
    e, s = loops[0]
    with pytest.raises(MescherError, match=r"loops\[0\]: expected a closed edge loop"):
        m.with_generators([(e[1:], s[1:]), loops[1]])
    with pytest.raises(MescherError, match=r"loops\[1\]: expected signs \+1 or -1"):
        m.with_generators([loops[0], (loops[1][0], 2 * loops[1][1])])
