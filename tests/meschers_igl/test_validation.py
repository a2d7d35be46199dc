"""Every bad input gets a MescherError naming the argument, what was expected and found."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, shapes
from meschers_igl import validate as val

F1 = np.array([[0, 1, 2], [0, 2, 3]])
XY = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
E1 = np.array([[0, 1], [1, 2], [0, 2], [2, 3], [0, 3]])
Z1 = np.zeros(5)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(F=[[0, 1, 7], [0, 2, 3]]), "F: expected indices < 4"),
        (dict(F=[[0, 1, -1], [0, 2, 3]]), "F: expected indices >= 0"),
        (dict(F=[[0, 1.5, 2], [0, 2, 3]]), "F: expected integer values"),
        (dict(F=[[0, 1], [0, 2]]), r"F: expected an integer array of shape \(n, 3\)"),
        (dict(F=np.zeros((0, 3), int)), "F: expected at least one triangle"),
        (dict(F=[[0, 1, 1], [0, 2, 3]]), "three distinct corners"),
        (dict(xy=np.zeros((4, 3))), r"xy: expected shape \(n, 2\)"),
        (dict(xy=[[0, 0], [1, np.nan], [1, 1], [0, 1]]), "xy: expected finite values"),
        (dict(zeta=np.zeros(4)), r"zeta: expected shape \(5,\)"),
        (dict(zeta=[0, 0, np.inf, 0, 0]), "zeta: expected finite"),
        (
            dict(edges=[[0, 1], [1, 2], [0, 2], [2, 3], [1, 3]]),
            "edges: expected exactly the edges of F",
        ),
        (
            dict(edges=[[0, 1], [1, 2], [0, 2], [2, 3]], zeta=np.zeros(4)),
            "edges: expected the 5 edges",
        ),
        (
            dict(edges=[[0, 1], [1, 2], [0, 2], [2, 3], [0, 1]]),
            "edges: expected exactly the edges|duplicated",
        ),
        (dict(F=[[0, 1, 2], [0, 3, 2]]), "consistently oriented"),
        (dict(zeta=[1.0, 0, 0, 0, 0]), "locally integrable.*project=True"),
        (dict(zeta="abc"), "zeta"),
        (dict(F=None), "F: expected an array, found None"),
    ],
)
def test_bad_input(kwargs, match):
    args = dict(F=F1, xy=XY, edges=E1, zeta=Z1)
    args.update(kwargs)
    with pytest.raises(MescherError, match=match):
        Mescher(args["F"], args["xy"], args["edges"], args["zeta"])


def test_non_manifold_edge():
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    xy = np.random.default_rng(0).random((5, 2))
    with pytest.raises(MescherError, match="non-manifold"):
        Mescher.from_mesh(np.c_[xy, np.zeros(5)], F)


def test_mobius_strip_is_non_orientable():
    n = 12
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = np.r_[
        np.c_[np.cos(t), np.sin(t), -0.2 * np.cos(t / 2)],
        np.c_[np.cos(t), np.sin(t), 0.2 * np.cos(t / 2)],
    ]
    F = []
    for i in range(n):
        a, b = i, n + i
        j = (i + 1) % n
        c, d = (j, n + j) if j else (n + j, j)  # the twist swaps the two rails
        F += [[a, c, b], [b, c, d]]
    with pytest.raises(MescherError, match="orient"):
        Mescher.from_mesh(V, np.array(F))


def test_user_edge_order_and_orientation_are_kept():
    m0 = Mescher.from_mesh(*shapes.grid(3, 3))
    perm = np.random.default_rng(0).permutation(m0.n_edges)
    flip = np.random.default_rng(1).random(m0.n_edges) < 0.5
    E = m0.edges[perm]
    E[flip] = E[flip][:, ::-1]
    z = np.where(flip, -1, 1) * m0.zeta[perm]
    m = Mescher(m0.F, m0.xy, E, z)
    assert np.array_equal(m.edges, E) and np.array_equal(m.zeta, z)
    assert np.abs(m.integrability_residual()).max() < 1e-14
    assert np.allclose(m.cotmatrix().toarray(), m0.cotmatrix().toarray())


def test_arrays_are_read_only():
    m = Mescher.from_mesh(*shapes.grid(3, 3))
    for a in (m.F, m.xy, m.edges, m.zeta):
        with pytest.raises(ValueError):
            a[0] = 0


def test_validators_report_name_expected_found():
    with pytest.raises(MescherError, match=r"sources: expected indices in \[0, 5\), found 7"):
        val.as_index_array([1, 7], "sources", 5)
    with pytest.raises(MescherError, match="view: expected a non-zero direction"):
        val.as_direction([0, 0, 0], "view")
    with pytest.raises(MescherError, match="t: expected a finite number > 0, found -1.0"):
        val.as_positive(-1, "t")
    with pytest.raises(MescherError, match="kind: expected one of"):
        Mescher.from_mesh(*shapes.grid(3, 3)).massmatrix("cotan")
    assert val.as_index_array(3, "s", 5).tolist() == [3]
    assert val.as_faces(np.array([[0.0, 1.0, 2.0]]), "F", 3).dtype == np.int64
    with pytest.raises(MescherError, match="up: expected a direction not parallel"):
        Mescher.from_mesh(*shapes.grid(3, 3), view=(0, 1, 0), up=(0, 2, 0))


def test_as_count_names_argument_expected_found():
    assert val.as_count(3, "levels") == 3 and isinstance(val.as_count(np.int64(2), "k"), int)
    for bad, found in [(-1, "-1"), (2.0, "2.0"), (True, "True"), ("3", "'3'"), (None, "None")]:
        with pytest.raises(MescherError, match=f"levels: expected an integer >= 0, found {found}"):
            val.as_count(bad, "levels")
    with pytest.raises(MescherError, match=r"K: expected an integer in \[1, 5\], found 9"):
        val.as_count(9, "K", minimum=1, maximum=5)


def test_check_budget_refuses_with_faces_and_bytes():
    gib = 2**30
    # 1e6 faces at 400 B = 0.37 GiB: fits in 8 GiB
    assert val.check_budget(1e6, 400, available=8 * gib) == 4e8
    with pytest.raises(MescherError, match=r"subdivide\(levels=30\).*1\.2e\+20 faces and .*PB"):
        val.check_budget(104 * 4.0**30, 400, what="subdivide(levels=30)", available=8 * gib)
    # over half the available memory is refused, under it is not
    with pytest.raises(MescherError, match="4.1 GB"):
        val.check_budget(1.1e7, 400, available=8 * gib)
    assert val.check_budget(1.0e7, 400, available=8 * gib) == 4e9
    # an overflowing estimate is refused, force=True lets anything through
    with pytest.raises(MescherError, match="inf faces"):
        val.check_budget(float("inf"), 1, available=8 * gib)
    assert val.check_budget(1e30, 400, force=True, available=1) == 4e32
    assert val.available_memory() > 0


def test_unreferenced_vertices_are_refused_by_every_constructor(unreferenced_mesh, tmp_path):
    """Issue 13.3: before, the mescher was accepted and cotmatrix came out (F.max()+1)-sized,
    so heat_diffuse / smooth / geodesic_distance failed with a raw ValueError later."""
    _, V, F, k = unreferenced_mesh
    want = rf"expected every vertex to be a corner of some face, found 1 unreferenced vertex\(es\) \[{k}\]"
    with pytest.raises(MescherError, match="V: " + want):
        Mescher.from_mesh(V, F)
    ok = np.delete(np.arange(V.shape[0]), k)
    m = Mescher.from_mesh(V[ok], np.searchsorted(ok, F))  # the same mesh without it is fine
    xy = np.insert(np.asarray(m.xy), k, [5.0, 5.0], axis=0)
    with pytest.raises(MescherError, match="xy: " + want):
        Mescher(F, xy, np.where(m.edges >= k, m.edges + 1, m.edges), m.zeta)
    with pytest.raises(MescherError, match="xy: " + want):
        Mescher.from_corner_depths(F, xy, np.zeros(F.shape))
    # a file holding such a mescher is refused by name too
    np.savez(
        tmp_path / "u.npz",
        F=F,
        xy=xy,
        edges=np.where(m.edges >= k, m.edges + 1, m.edges),
        zeta=m.zeta,
    )
    from meschers_igl import load

    with pytest.raises(MescherError, match="u.npz: the stored mescher is invalid: xy: " + want):
        load(tmp_path / "u.npz")
    # a cut model may have stray vertices: they are dropped (vmap -1), not refused
    mc, vmap = Mescher.from_cut_mesh(V, F, return_map=True)
    assert vmap[k] == -1 and mc.n_vertices == V.shape[0] - 1
    assert mc.cotmatrix().shape == (mc.n_vertices, mc.n_vertices)
