"""Real cut models from another tool (ParadoxToolkit, shipped in meschers_igl/data/paradox): issue 8.

Every file is glued with only its JSON's ``view_dir`` and ``up``; the tool's own bookkeeping
(``illusion_pairs``, ``verification``) is the independent oracle.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from meschers_igl import Mescher, MescherError
from meschers_igl.cutmesh import camera_coordinates, glue_cut_mesh
from meschers_igl.paradox import data_dir
from meschers_igl.topology import boundary_loops, connected_components

DATA = data_dir()
NAMES = sorted(p.stem for p in DATA.glob("*.obj")) + sorted(
    "variants/" + p.stem for p in (DATA / "variants").glob("*.obj")
)
TORI = ("penrose_triangle", "reutersvard_rectangle", "impossible_arch")


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and fan-triangulated faces of a plain OBJ (``v`` and ``f`` lines only)."""
    V, F = [], []
    for line in path.read_text().splitlines():
        tok = line.split()
        if not tok:
            continue
        if tok[0] == "v":
            V.append([float(t) for t in tok[1:4]])
        elif tok[0] == "f":
            idx = [int(t.split("/")[0]) - 1 for t in tok[1:]]
            F.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(V), np.array(F, dtype=np.int64)


def load(name: str):
    V, F = read_obj(DATA / f"{name}.obj")
    meta = json.loads((DATA / f"{name}.json").read_text())
    return V, F, meta


def figure(name: str) -> str:
    return name.split("/")[-1].split("__")[0]


@pytest.fixture(scope="module", params=NAMES)
def model(request):
    V, F, meta = load(request.param)
    cam = meta["camera"]
    m, vmap = Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"], return_map=True)
    return request.param, V, F, meta, m, vmap


def test_all_eighteen_files_present():
    assert len(NAMES) == 18
    assert (DATA / "README.md").read_text().count("GPL-3.0") >= 2


def test_counts_and_euler_characteristic(model):
    name, V, F, meta, m, vmap = model
    ver = meta["verification"]
    n_pairs = len(meta["illusion_pairs"])
    assert V.shape[0] == ver["V"]
    assert m.n_vertices == ver["V"] - n_pairs
    assert m.n_faces == F.shape[0] == 2 * ver["F"]  # quads split in two, face i stays face i
    np.testing.assert_array_equal(m.F, vmap[F])
    assert m.euler_characteristic() == ver["glued_chi"]
    assert not boundary_loops(np.asarray(m.F))  # glued_closed


def test_pairs_found_are_the_tools_pairs(model):
    """Loop-level gluing recovers exactly the pairs the tool meant, without being told them."""
    name, V, F, meta, m, vmap = model
    pairs = np.array(meta["illusion_pairs"])
    np.testing.assert_array_equal(vmap[pairs[:, 0]], vmap[pairs[:, 1]])
    # and nothing else was glued
    assert np.unique(vmap).size == V.shape[0] - len(pairs)


def test_screen_position_alone_is_ambiguous():
    """The trap the README describes: a cut face is seen edge-on, so a cut vertex can have two
    candidates on the other loop within the gluing tolerance; the loop-level gluing still finds
    the tool's pairs there (test_pairs_found_are_the_tools_pairs)."""
    ambiguous = set()
    for name in NAMES:
        V, F, meta = load(name)
        cam = meta["camera"]
        g = glue_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"])
        a, b = boundary_loops(F)
        xy = g["camera"][:, :2]
        hits = cKDTree(xy[b]).query_ball_point(xy[a], g["tol"])
        if max(len(h) for h in hits) > 1:
            ambiguous.add(name)
    assert {"penrose_triangle", "penrose_triangle_block", "impossible_cube"} <= ambiguous
    assert len(ambiguous) >= 10


def test_periods_equal_the_depth_gap(model):
    name, V, F, meta, m, vmap = model
    gap = meta["verification"]["depth_gaps"][0]
    p = m.periods()
    if figure(name) in TORI + ("impossible_cube",):
        assert m.is_impossible()
        assert np.abs(p).max() == pytest.approx(gap, rel=1e-4)
        # every period is an integer multiple of the gap (loops cross the cut a whole number
        # of times), and a torus has exactly one non-zero period
        k = p / gap
        np.testing.assert_allclose(k, np.round(k), atol=1e-4)
        if figure(name) in TORI:
            assert p.size == 2 and np.sort(np.abs(np.round(k))).tolist() == [0.0, 1.0]
        else:
            assert p.size == 6  # genus 3
    else:
        # 12 closed boxes: spheres, no homology, no harmonic part at all
        assert p.size == 0 and not m.is_impossible()
        n, _ = connected_components(np.asarray(m.F), m.n_vertices)
        assert n == 12
        assert np.abs(m.hodge().omega).max() < 1e-9 * m.scale()


def test_local_depths_are_the_models(model):
    """Gluing by a translation along the view keeps every face's own shape: the mescher's local
    corner depths equal the cut model's, and zeta was already integrable (float32 noise only)."""
    name, V, F, meta, m, vmap = model
    cam = meta["camera"]
    Zc = camera_coordinates(V, cam["view_dir"], cam["up"])[:, 2][F]
    np.testing.assert_allclose(m.corner_depths(), Zc - Zc[:, :1], atol=1e-5 * m.scale())
    np.testing.assert_allclose(m.integrability_residual(), 0.0, atol=1e-9 * m.scale())


@pytest.mark.parametrize("name", ["penrose_triangle", "impossible_cube", "penrose_stair"])
def test_explicit_pairs_give_the_same_mescher(name):
    V, F, meta = load(name)
    cam = meta["camera"]
    auto = Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"])
    pairs = meta["illusion_pairs"]
    m = Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"], merge=pairs)
    np.testing.assert_array_equal(m.F, auto.F)
    np.testing.assert_allclose(m.zeta, auto.zeta, atol=1e-12)


def test_explicit_pairs_are_checked_against_the_geometry():
    V, F, meta = load("penrose_triangle")
    cam = meta["camera"]
    pairs = np.array(meta["illusion_pairs"])
    wrong = pairs.copy()
    wrong[0, 1] = pairs[1, 1]  # a front vertex with the back partner of another
    with pytest.raises(MescherError, match=r"merge: .*coincide on screen"):
        Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"], merge=wrong)
    # Pair each vertex with the *other* back vertex at its screen point: this passes the
    # screen check but glues the loops the wrong way round, which must be refused by name.
    xy = camera_coordinates(V, cam["view_dir"], cam["up"])[:, :2]
    back = pairs[:, 1]
    swapped = pairs.copy()
    for k in range(len(pairs)):
        d = np.linalg.norm(xy[back] - xy[pairs[k, 0]], axis=1)
        d[k] = np.inf
        if d.min() < 1e-4:
            swapped[k, 1] = back[np.argmin(d)]
    assert (swapped != pairs).any()
    with pytest.raises(MescherError, match=r"merge: expected .*(manifold|orientable|distinct)"):
        Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"], merge=swapped)


def test_float32_rounding_and_partial_matches():
    """Re-rounding to float32 does not change the gluing; a back loop that only partly
    coincides with the front loop on screen is refused with a clear message."""
    V, F, meta = load("impossible_cube")  # the largest screen mismatch, 1.6e-6
    cam = meta["camera"]
    m = Mescher.from_cut_mesh(V.astype(np.float32), F, view=cam["view_dir"], up=cam["up"])
    assert m.euler_characteristic() == -4
    R = np.array([cam["right"], cam["up"], cam["view_dir"]])
    moved = V.copy()
    moved[meta["illusion_pairs"][0][1]] += 1e-3 * R[0]  # 1e-3 to the right on screen
    with pytest.raises(MescherError, match="no consistent pairing of whole loops"):
        Mescher.from_cut_mesh(moved, F, view=cam["view_dir"], up=cam["up"])
    # a looser tolerance accepts it again (averaged and projected)
    m2 = Mescher.from_cut_mesh(moved, F, view=cam["view_dir"], up=cam["up"], tol=1e-4)
    assert np.abs(m2.periods()).max() == pytest.approx(17.320674, rel=1e-3)


def test_components_before_and_after_gluing():
    V, F, meta = load("penrose_stair")
    n_cut, _ = connected_components(F, V.shape[0])
    m = Mescher.from_cut_mesh(V, F, view=meta["camera"]["view_dir"], up=meta["camera"]["up"])
    n_glued, _ = connected_components(np.asarray(m.F), m.n_vertices)
    assert (n_cut, n_glued) == (meta["verification"]["comps"], 12)
