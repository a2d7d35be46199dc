"""Depth order (issue 4 item 2; DESIGN "Depth ordering"; paper Sec. 3.5) and 2D overlap tests.

Oracles: brute force over all pairs (broad phase), Monte Carlo (intersection centroids), a
z-buffer at sampled screen points (orders from cut embeddings), the true 3D depths of ordinary
meshes (local-depth orders), networkx shortest paths (local depth on an impossible model) and
networkx reachability (feedback arcs).
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import igl
import networkx as nx
import numpy as np
import pytest

from meschers_igl import DepthOrder, Mescher, MescherError, MescherWarning, shapes
from meschers_igl.geometry2d import (
    TOL_FACTOR,
    barycentric,
    candidate_pairs,
    default_tol,
    intersection_centroids,
    overlapping_pairs,
    triangle_heights,
    triangles_overlap,
)
from meschers_igl.operators import view_frame
from meschers_igl.order_graph import reconcile_arcs, topological_sort
from meschers_igl.paradox import data_dir
from meschers_igl.topology import edge_topology

PARADOX = data_dir()  # the ParadoxToolkit cut models shipped with the package


# ---------------------------------------------------------------------------------- builders
def soup(T: np.ndarray, Z: np.ndarray | None = None) -> Mescher:
    """A mescher whose faces are separate triangles ``T (n, 3, 2)`` (flat unless ``Z``)."""
    n = T.shape[0]
    F = np.arange(3 * n).reshape(n, 3)  # any orientation: every face is its own component
    Zf = np.zeros((n, 3)) if Z is None else Z
    return Mescher.from_corner_depths(F, T.reshape(-1, 2), Zf)


def camera(V: np.ndarray, view, up=(0.0, 1.0, 0.0)) -> np.ndarray:
    return V @ view_frame(view, up).T


def torus(nu: int = 28, nv: int = 14, R: float = 1.0, r: float = 0.4):
    return shapes.torus(nu, nv, R, r)


def folded_strip(n_per_unit: int = 8, layers: int = 3, gap: float = 0.5, length: float = 2.0):
    """A strip folded back and forth ``layers`` times (an S seen from the side overlaps itself).

    Centre line in the (x, z) plane: straight runs of ``length`` joined by half circles of
    diameter ``gap``; the strip's width runs along y.
    """
    pts = []
    for k in range(layers):
        xs = np.linspace(0, length, int(length * n_per_unit) + 1)
        xs = xs if k % 2 == 0 else xs[::-1]
        pts.append(np.stack((xs, np.full_like(xs, k * gap)), 1)[:-1])
        if k < layers - 1:
            t = np.linspace(0, np.pi, 9)[:-1]
            cx = length if k % 2 == 0 else 0.0
            sgn = 1.0 if k % 2 == 0 else -1.0
            pts.append(
                np.stack(
                    (cx + sgn * 0.5 * gap * np.sin(t), k * gap + 0.5 * gap * (1 - np.cos(t))), 1
                )
            )
    pts.append(np.array([[0.0 if layers % 2 == 0 else length, (layers - 1) * gap]]))
    c = np.concatenate(pts)
    ys = np.linspace(0.0, 1.0, 4)
    V = np.array([[x, y, z] for x, z in c for y in ys])
    ny = ys.size
    idx = np.arange(len(c) * ny).reshape(len(c), ny)
    a, b = idx[:-1, :-1], idx[1:, :-1]
    cc, d = idx[1:, 1:], idx[:-1, 1:]
    F = np.concatenate((np.stack((a, b, cc), -1), np.stack((a, cc, d), -1))).reshape(-1, 3)
    return V, F


def zbuffer_violations(m: Mescher, Zc: np.ndarray, order: np.ndarray, n: int, seed: int) -> int:
    """Sampled screen points whose nearest covering face is drawn before another covering face."""
    rng = np.random.default_rng(seed)
    T = m.xy[m.F]
    lo, hi = T.reshape(-1, 2).min(0), T.reshape(-1, 2).max(0)
    P = rng.uniform(lo, hi, (n, 2))
    nf = T.shape[0]
    B = barycentric(np.repeat(P, nf, axis=0), np.tile(T, (n, 1, 1))).reshape(n, nf, 3)
    inside = (B > 1e-6).all(axis=2) & (triangle_heights(T) > 1e-9)[None, :]
    z = np.where(inside, np.einsum("pfc,fc->pf", B, Zc), -np.inf)
    top = z.argmax(axis=1)
    pos = np.empty(nf, dtype=np.int64)
    pos[order] = np.arange(nf)
    later = inside & (pos[None, :] > pos[top][:, None])  # covering faces drawn after the top one
    covered = inside.sum(1) >= 2
    assert covered.sum() > n // 10, "the test scene should overlap itself at many samples"
    return int((later.any(axis=1) & covered).sum())


def arcs_set(o: DepthOrder) -> set:
    return set(map(tuple, o.arcs.tolist()))


# ---------------------------------------------------------------------------------- 2D geometry
def test_sat_hand_cases():
    A = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    cases = {
        "overlap": (np.array([[0.5, 0.5], [3.0, 0.5], [0.5, 3.0]]), True),
        "shared edge, other side": (np.array([[2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]), False),
        "shared vertex": (np.array([[2.0, 0.0], [4.0, 0.0], [3.0, -1.0]]), False),
        "apart": (np.array([[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]]), False),
        "contained": (np.array([[0.2, 0.2], [0.6, 0.2], [0.2, 0.6]]), True),
        "identical": (A.copy(), True),
        "bbox overlaps only": (np.array([[1.5, 1.5], [3.0, 1.5], [1.5, 3.0]]), False),
    }
    for name, (B, want) in cases.items():
        got = triangles_overlap(A[None], B[None], 1e-9)[0]
        assert got == want, name
        assert triangles_overlap(B[None], A[None], 1e-9)[0] == want, name + " (swapped)"


def test_intersection_centroid_exact_and_monte_carlo():
    # the unit square's lower-left triangle clipped by a big triangle: the square's half
    A = np.array([[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]])
    B = np.array([[[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]]])
    c, area = intersection_centroids(A, B)
    np.testing.assert_allclose(c[0], [1 / 3, 1 / 3], atol=1e-14)
    np.testing.assert_allclose(area[0], 0.5, atol=1e-14)
    # two unit right triangles overlapping in the square [0.5, 1]^2 cut by x + y <= 1.5
    B = np.array([[[0.5, 0.5], [1.5, 0.5], [0.5, 1.5]]])
    A2 = np.array([[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]])
    c, area = intersection_centroids(A2, B)
    rng = np.random.default_rng(3)
    P = rng.uniform(0, 2, (400_000, 2))
    inA = (barycentric(P, np.repeat(A2, len(P), 0)) >= 0).all(1)
    inB = (barycentric(P, np.repeat(B, len(P), 0)) >= 0).all(1)
    both = P[inA & inB]
    np.testing.assert_allclose(area[0], both.shape[0] / len(P) * 4.0, rtol=0.02)
    np.testing.assert_allclose(c[0], both.mean(0), atol=3e-3)


def test_intersection_centroid_of_a_folded_pair_and_any_orientation():
    # B folded over A along their shared edge (0,0)-(2,0): the overlap is B itself; the shared
    # boundary must be counted once
    A = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    B = np.array([[0.0, 0.0], [2.0, 0.0], [0.5, 0.5]])
    for a, b in [(A, B), (A[::-1], B), (A, B[::-1]), (B, A), (B[::-1], A[::-1])]:
        c, area = intersection_centroids(a[None], b[None])
        np.testing.assert_allclose(area[0], 0.5, atol=1e-14)
        np.testing.assert_allclose(c[0], B.mean(0), atol=1e-14)
    assert triangles_overlap(A[None], B[None], 1e-9)[0]


def test_broad_and_narrow_phase_match_brute_force():
    rng = np.random.default_rng(0)
    n = 300
    T = rng.uniform(0, 10, (n, 1, 2)) + rng.normal(0, 0.7, (n, 3, 2))
    T[:20] *= np.array([1.0, 0.02])  # some slivers and long faces for the grid
    tol = default_tol(T)
    ii, jj = np.triu_indices(n, 1)
    ok = triangle_heights(T) > tol
    hit = ok[ii] & ok[jj] & triangles_overlap(T[ii], T[jj], tol)
    brute = np.stack((ii[hit], jj[hit]), 1)
    pairs, _ = overlapping_pairs(T)
    np.testing.assert_array_equal(pairs, brute)
    # only pairs across groups
    g = rng.integers(0, 3, n)
    pairs_g, _ = overlapping_pairs(T, groups=g)
    np.testing.assert_array_equal(pairs_g, brute[g[brute[:, 0]] != g[brute[:, 1]]])
    # the broad phase alone: every pair whose boxes overlap, exactly once
    lo, hi = T.min(1), T.max(1)
    got = candidate_pairs(lo, hi, 0.0)
    assert np.unique(got, axis=0).shape[0] == got.shape[0]
    box = ((np.minimum(hi[ii], hi[jj]) - np.maximum(lo[ii], lo[jj])) > 0).all(1)
    np.testing.assert_array_equal(got, np.stack((ii[box], jj[box]), 1))
    # clusters far apart make the grid sparse (cell keys sorted instead of counted): same pairs
    T2 = T.copy()
    T2[::2] += 1e6
    ok2 = triangle_heights(T2) > tol
    hit2 = ok2[ii] & ok2[jj] & triangles_overlap(T2[ii], T2[jj], tol)
    np.testing.assert_array_equal(overlapping_pairs(T2, tol)[0], np.stack((ii[hit2], jj[hit2]), 1))


# ---------------------------------------------------------------------------------- from_embedding
TWO = np.array([[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]], [[0.5, 0.5], [3.0, 0.5], [0.5, 3.0]]])


def test_two_overlapping_triangles_at_different_depths():
    m = soup(TWO)
    o = DepthOrder.from_embedding(m, [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    np.testing.assert_array_equal(o.arcs, [[0, 1]])  # 0 is behind 1
    np.testing.assert_array_equal(o.linear_extension(), [0, 1])
    o2 = DepthOrder.from_embedding(m, [[5.0, 5.0, 5.0], [1.0, 1.0, 1.0]])
    np.testing.assert_array_equal(o2.arcs, [[1, 0]])
    assert set(o.graph.nodes) == {0, 1} and list(o.graph.edges) == [(0, 1)]


def test_tilted_faces_are_compared_over_their_overlap():
    # face 1 tilts through face 0's plane (depth -1 + (x - 0.5) + 0.8 (y - 0.5)); over the
    # overlap, the triangle (0.5, 0.5), (1.5, 0.5), (0.5, 1.5), its mean depth is -0.4, so it is
    # behind face 0 (depth 0) although its mean corner depth (0.5) is in front.
    m = soup(TWO)
    o = DepthOrder.from_embedding(m, [[0.0, 0.0, 0.0], [-1.0, 1.5, 1.0]])
    np.testing.assert_array_equal(o.arcs, [[1, 0]])
    o = DepthOrder.from_embedding(m, [[0.0, 0.0, 0.0], [1.0, -1.5, -1.0]])
    np.testing.assert_array_equal(o.arcs, [[0, 1]])
    # face 0 at depth -0.39 / -0.41 instead: the comparison is at the overlap's mean (-0.4)
    o = DepthOrder.from_embedding(m, [[-0.39] * 3, [-1.0, 1.5, 1.0]])
    np.testing.assert_array_equal(o.arcs, [[1, 0]])
    o = DepthOrder.from_embedding(m, [[-0.41] * 3, [-1.0, 1.5, 1.0]])
    np.testing.assert_array_equal(o.arcs, [[0, 1]])
    # equal depths over the overlap: no arc
    o = DepthOrder.from_embedding(m, np.zeros((2, 3)))
    assert o.n_arcs == 0


def test_touching_faces_get_no_arc():
    # a square split along its diagonal (shared edge) and a third face at a shared vertex
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 1], [2, 2]], dtype=float)
    F = np.array([[0, 1, 2], [0, 2, 3], [2, 4, 5]])
    m = Mescher.from_corner_depths(F, xy, np.zeros((3, 3)))
    Zc = np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 5.0], [-3.0, -3.0, -3.0]])  # a cut embedding
    assert DepthOrder.from_embedding(m, Zc).n_arcs == 0


def test_float32_seam_far_from_origin_gets_no_arc_but_real_overlap_does():
    # Two separate faces that touch along an edge whose copies were rounded to float32 (as in
    # artist files), 1000 units from the origin: round-off overlaps of ~1e-4 are not overlaps.
    rng = np.random.default_rng(7)
    base = np.array([1000.0, -2000.0])
    p, q = base + rng.uniform(0, 3, 2), base + rng.uniform(0, 3, 2)
    nrm = np.array([-(q - p)[1], (q - p)[0]])
    A = np.array([p, q, 0.5 * (p + q) + nrm])
    Bt = np.array([q, p, 0.5 * (p + q) - nrm]).astype(np.float32).astype(np.float64)
    assert np.abs(Bt[:2] - A[1::-1]).max() > 0  # the seam really is perturbed
    m = soup(np.stack((A, Bt)))
    Zc = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    assert DepthOrder.from_embedding(m, Zc).n_arcs == 0
    # pushing B 1% of the edge length into A is a real overlap
    B2 = Bt + 0.01 * nrm
    o = DepthOrder.from_embedding(soup(np.stack((A, B2))), Zc)
    np.testing.assert_array_equal(o.arcs, [[0, 1]])


def test_edge_on_faces_overlap_nothing():
    # face 1 is seen edge-on (zero screen area) across face 0
    xy = np.array([[0, 0], [2, 0], [0, 2], [-1, 0.5], [3, 0.5], [1, 0.5]], dtype=float)
    F = np.array([[0, 1, 2], [3, 4, 5]])
    Z = np.array([[0.0, 0.0, 0.0], [-1.0, -1.0, 1.0]])
    m = Mescher.from_corner_depths(F, xy, Z)
    assert DepthOrder.from_embedding(m, [[0.0] * 3, [1.0] * 3]).n_arcs == 0


def test_three_sticks_cycle_is_reported_and_broken_minimally():
    # three long thin faces along the sides of a triangle, each rising along its length, so at
    # every corner the stick that ends there is in front of the one that starts there
    P = np.array([[0.0, 0.0], [4.0, 0.0], [2.0, 3.5]])
    T, Z = [], []
    for k in range(3):
        a, b = P[k], P[(k + 1) % 3]
        u = (b - a) / np.linalg.norm(b - a)
        nrm = np.array([-u[1], u[0]])
        s, e = a - 0.8 * u, b + 0.8 * u
        T.append([s - 0.25 * nrm, s + 0.25 * nrm, e])
        Z.append([0.0, 0.0, 1.0])
    m = soup(np.array(T))
    o = DepthOrder.from_embedding(m, np.array(Z))
    assert arcs_set(o) == {(1, 0), (2, 1), (0, 2)}
    with pytest.warns(MescherWarning, match=r"1 cycle\(s\).*0 -> 2 -> 1 -> 0"):
        cyc = o.cycles()
    assert cyc == [[0, 2, 1]]
    with pytest.warns(MescherWarning, match="breaks 1 of its 3 arcs"):
        perm = o.linear_extension()
    np.testing.assert_array_equal(np.sort(perm), np.arange(3))
    pos = np.argsort(perm)
    assert int((pos[o.arcs[:, 0]] > pos[o.arcs[:, 1]]).sum()) == 1  # fewest possible: one


def test_zbuffer_agrees_on_an_oblique_torus():
    V, F = torus()
    view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
    m = Mescher.from_mesh(V, F, view=view, up=up)
    Zc = camera(V, view, up)[F][:, :, 2]
    o = DepthOrder.from_embedding(m, Zc)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert o.cycles() == []
        perm = o.linear_extension()
    assert zbuffer_violations(m, Zc, perm, 1500, seed=1) == 0
    # reversing all depths reverses every arc
    assert arcs_set(DepthOrder.from_embedding(m, -Zc)) == {(b, a) for a, b in arcs_set(o)}


def _paradox(name: str):
    V, F = [], []
    for line in (PARADOX / f"{name}.obj").read_text().splitlines():
        tok = line.split()
        if tok and tok[0] == "v":
            V.append([float(t) for t in tok[1:4]])
        elif tok and tok[0] == "f":
            idx = [int(t.split("/")[0]) - 1 for t in tok[1:]]
            F.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    cam = json.loads((PARADOX / f"{name}.json").read_text())["camera"]
    V, F = np.array(V), np.array(F, dtype=np.int64)
    m = Mescher.from_cut_mesh(V, F, view=cam["view_dir"], up=cam["up"])
    Zc = camera(V, cam["view_dir"], cam["up"])[F][:, :, 2]
    return m, Zc


@pytest.mark.parametrize("name", ["penrose_triangle", "penrose_triangle_block", "impossible_cube"])
def test_zbuffer_agrees_on_real_cut_models(name):
    # float32 artist files with faces seen edge-on and seams that coincide only to float32
    m, Zc = _paradox(name)
    o = DepthOrder.from_embedding(m, Zc)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert o.cycles() == []
        perm = o.linear_extension()
    assert zbuffer_violations(m, Zc, perm, 3000, seed=2) == 0
    # faces sharing a mesh edge and facing the same way lie on either side of it: they only
    # touch (faces across a silhouette edge do overlap, one folded behind the other)
    T = m.xy[m.F]
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    side = np.sign(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    nb = _edge_neighbours(m)
    flat = nb[(side[nb[:, 0]] == side[nb[:, 1]]) & (side[nb[:, 0]] != 0)]
    assert flat.shape[0] > 10
    assert not {tuple(sorted(p)) for p in flat.tolist()} & {
        tuple(sorted(a)) for a in o.arcs.tolist()
    }


def _edge_neighbours(m: Mescher) -> np.ndarray:
    fe = m.face_edges.reshape(-1)
    f = np.repeat(np.arange(m.n_faces), 3)
    srt = np.argsort(fe, kind="stable")
    fe, f = fe[srt], f[srt]
    same = fe[1:] == fe[:-1]
    return np.stack((f[:-1][same], f[1:][same]), 1)


# ---------------------------------------------------------------------------------- local depth
def test_local_depth_of_a_folded_strip_is_its_true_depth_order():
    V, F = folded_strip()
    view = (0.15, 0.1, 1.0)
    m = Mescher.from_mesh(V, F, view=view)
    Zc = camera(V, view)[F][:, :, 2]
    truth = DepthOrder.from_embedding(m, Zc)
    assert truth.n_arcs > 100
    local = DepthOrder.from_local_depth(m)
    assert local == truth
    # the path machinery used for impossible meschers gives the same on a possible one
    assert DepthOrder.from_local_depth(m, _force_paths=True) == truth
    perm = local.linear_extension()
    assert zbuffer_violations(m, Zc, perm, 1500, seed=4) == 0


def test_local_depth_follows_the_short_way_round_an_impossible_loop():
    # A band along a limacon r = 1 + 2 cos(t): it crosses itself at the origin (t = 2pi/3 and
    # t = 4pi/3); the inner loop between them is the short way.  Depth rises by P/(2 pi) per
    # radian all the way round (a Penrose-stairs band, period P): along the short way the
    # branch at 4pi/3 is P/3 in front; along the long way it would be 2P/3 behind.
    nt, P, w = 360, 1.0, 0.06
    t = np.linspace(0, 2 * np.pi, nt, endpoint=False)
    c = np.stack(((1 + 2 * np.cos(t)) * np.cos(t), (1 + 2 * np.cos(t)) * np.sin(t)), 1)
    tan = np.gradient(np.r_[c[-1:], c, c[:1]], axis=0)[1:-1]
    nrm = np.stack((-tan[:, 1], tan[:, 0]), 1) / np.linalg.norm(tan, axis=1)[:, None]
    xy = np.concatenate((c - 0.5 * w * nrm, c + 0.5 * w * nrm))
    i = np.arange(nt)
    j = (i + 1) % nt
    F = np.concatenate((np.stack((i, j, j + nt), 1), np.stack((i, j + nt, i + nt), 1)))
    edges, _, _ = edge_topology(F)
    theta = np.r_[t, t]
    dth = np.angle(np.exp(1j * (theta[edges[:, 1]] - theta[edges[:, 0]])))
    m = Mescher(F, xy, edges, P / (2 * np.pi) * dth)
    assert m.is_impossible()
    o = DepthOrder.from_local_depth(m)
    assert o.n_arcs > 4
    ft = np.angle(np.exp(1j * theta[F]).mean(1)) % (2 * np.pi)  # each face's angle
    back, front = ft[o.arcs[:, 0]], ft[o.arcs[:, 1]]
    assert np.all(np.abs(back - 2 * np.pi / 3) < 0.3) and np.all(
        np.abs(front - 4 * np.pi / 3) < 0.3
    )


def test_local_depth_matches_networkx_shortest_paths_on_an_impossible_cut_model():
    m, _ = _paradox("penrose_triangle")
    assert m.is_impossible()
    o = DepthOrder.from_local_depth(m)
    G = nx.Graph()
    L = np.sqrt(((m.xy[m.edges[:, 1]] - m.xy[m.edges[:, 0]]) ** 2).sum(1) + m.zeta**2)
    for e, (a, b) in enumerate(m.edges.tolist()):
        G.add_edge(a, b, weight=L[e], z=m.zeta[e] if a < b else -m.zeta[e])
    T, Zl = m.xy[m.F], m.corner_depths()
    pairs, cen = overlapping_pairs(T, centroids=True)
    want = set()
    for (fi, fj), c in zip(pairs.tolist(), cen, strict=True):
        path = nx.shortest_path(G, m.F[fi, 0], m.F[fj, 0], weight="weight")
        s = sum(G[u][v]["z"] * (1 if u < v else -1) for u, v in zip(path[:-1], path[1:]))
        zi = barycentric(c[None], T[[fi]]) @ Zl[fi]
        zj = barycentric(c[None], T[[fj]]) @ Zl[fj]
        dz = float(s + zj[0] - zi[0])
        want.add((fi, fj) if dz > 0 else (fj, fi))
    assert arcs_set(o) == want


def test_local_depth_ignores_overlaps_between_components():
    m = soup(TWO, Z=np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]))
    assert DepthOrder.from_local_depth(m).n_arcs == 0


# ---------------------------------------------------------------------------------- editing
def test_put_in_front_flips_only_overlapping_pairs():
    T = np.concatenate((TWO, [[[10.0, 0.0], [11.0, 0.0], [10.0, 1.0]]]))
    m = soup(T)
    o = DepthOrder.from_embedding(m, [[0.0] * 3, [1.0] * 3, [2.0] * 3])
    np.testing.assert_array_equal(o.arcs, [[0, 1]])
    same = o.put_in_front([0, 2], [1])
    assert same is o
    np.testing.assert_array_equal(o.arcs, [[1, 0]])  # 2 overlaps nothing: no arc
    # contradicting arcs are removed even between faces that do not overlap
    o2 = DepthOrder(3, [[2, 1], [0, 1]], m=m).put_in_front([2], [1])
    np.testing.assert_array_equal(o2.arcs, [[0, 1]])
    with pytest.raises(MescherError, match="disjoint"):
        o.put_in_front([0, 1], [1])
    with pytest.raises(MescherError, match="front_faces.*\\[0, 3\\).*found 7"):
        o.put_in_front([7], [1])
    with pytest.raises(MescherError, match="m: put_in_front needs"):
        DepthOrder(3).put_in_front([0], [1])


def test_refine_equals_the_order_of_the_refined_embedding():
    V, F = torus(16, 8)
    view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
    m = Mescher.from_mesh(V, F, view=view, up=up)
    o = DepthOrder.from_embedding(m, camera(V, view, up)[F][:, :, 2])
    V2, F2 = igl.upsample(V, F)
    parent = np.repeat(np.arange(F.shape[0]), 4)  # igl.upsample: 4 consecutive children
    m2 = Mescher.from_mesh(V2, F2, view=view, up=up)
    r = o.refine(parent, m2)
    assert r.n_faces == 4 * o.n_faces and r.n_arcs > o.n_arcs
    assert r == DepthOrder.from_embedding(m2, camera(V2, view, up)[F2][:, :, 2])
    assert set(map(tuple, parent[r.arcs].tolist())) <= arcs_set(o)
    with pytest.raises(MescherError, match="face_parent: expected one parent per child"):
        o.refine(parent[:-1], m2)
    with pytest.raises(MescherError, match="face_parent: expected parent faces in"):
        o.refine(parent + 1, m2)


def test_mescher_subdivide_carries_the_order():
    V, F = torus(16, 8)
    view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
    m = Mescher.from_mesh(V, F, view=view, up=up)
    Zc = camera(V, view, up)[F][:, :, 2]
    o = DepthOrder.from_embedding(m, Zc)
    m2, o2, parent = m.subdivide(order=o, return_face_parent=True)
    # the children's depths are their parents' planes: interpolate them at the child corners
    T = m.xy[m.F]
    Fp = np.repeat(parent, 3)
    B = barycentric(m2.xy[m2.F].reshape(-1, 2), T[Fp])
    Zc2 = np.einsum("kc,kc->k", B, Zc[Fp]).reshape(-1, 3)
    assert o2 == DepthOrder.from_embedding(m2, Zc2)
    assert o2.n_arcs > o.n_arcs


# ---------------------------------------------------------------------------------- graph algorithms
def test_linear_extension_is_a_topological_order_of_a_random_dag():
    rng = np.random.default_rng(5)
    n = 3000
    rank = rng.permutation(n)
    a, b = rng.integers(0, n, (2, 12000))
    keep = rank[a] < rank[b]
    o = DepthOrder(n, np.stack((a[keep], b[keep]), 1))
    perm = o.linear_extension()
    np.testing.assert_array_equal(np.sort(perm), np.arange(n))
    pos = np.argsort(perm)
    assert np.all(pos[o.arcs[:, 0]] < pos[o.arcs[:, 1]])
    assert o.feedback_arcs().shape == (0, 2)
    assert nx.is_directed_acyclic_graph(o.graph)


def test_feedback_arcs_are_minimal_and_break_every_cycle():
    rng = np.random.default_rng(11)
    n = 60
    arcs = rng.integers(0, n, (200, 2))
    arcs = arcs[arcs[:, 0] != arcs[:, 1]]
    o = DepthOrder(n, arcs)
    with pytest.warns(MescherWarning):
        cyc = o.cycles()
    for c in cyc:  # each reported cycle is a real directed cycle
        assert all(o.graph.has_edge(a, b) for a, b in zip(c, c[1:] + c[:1], strict=True))
    fas = o.feedback_arcs()
    rest = nx.DiGraph(o.graph)
    rest.remove_edges_from(fas.tolist())
    assert nx.is_directed_acyclic_graph(rest)
    for a, b in fas.tolist():  # minimal: restoring any broken arc closes a cycle
        assert nx.has_path(rest, b, a)
    with pytest.warns(MescherWarning, match=f"breaks {fas.shape[0]} of"):
        perm = o.linear_extension()
    pos = np.argsort(perm)
    broken = o.arcs[pos[o.arcs[:, 0]] > pos[o.arcs[:, 1]]]
    np.testing.assert_array_equal(broken, fas[np.lexsort((fas[:, 1], fas[:, 0]))])


def test_two_cycle_and_components():
    o = DepthOrder(5, [[0, 1], [1, 0], [2, 3], [3, 4], [4, 2]])
    with pytest.warns(MescherWarning, match="2 cycle"):
        assert o.cycles() == [[0, 1], [2, 3, 4]]
    assert o.cycles(warn=False) == [[0, 1], [2, 3, 4]]


# ---------------------------------------------------------------------------------- arrays, validation
def test_arrays_round_trip_and_equality():
    o = DepthOrder(4, [[2, 3], [0, 1], [0, 1]])
    n, arcs = o.to_arrays()
    assert n == 4
    np.testing.assert_array_equal(arcs, [[0, 1], [2, 3]])
    assert DepthOrder.from_arrays(np.array(n), arcs) == o
    assert DepthOrder(4, [[0, 1]]) != o and DepthOrder(5, arcs) != o
    assert DepthOrder(3) == DepthOrder(3, []) == DepthOrder(3, np.zeros((0, 2)))
    assert not o.arcs.flags.writeable
    with pytest.raises(nx.NetworkXError):
        o.graph.add_edge(1, 2)


@pytest.mark.parametrize(
    "args, match",
    [
        ((-1,), "n_faces: expected an integer >= 0, found -1"),
        ((2.5,), "n_faces: expected an integer >= 0, found 2.5"),
        ((True,), "n_faces: expected an integer >= 0, found True"),
        ((3, [[0, 3]]), r"arcs: expected face indices in \[0, 3\), found arc 0 = \[0, 3\]"),
        ((3, [[1, 1]]), "arcs: expected arcs between two different faces.*self-loop"),
        ((3, [[0, 1, 2]]), r"arcs: expected an integer array of shape \(n, 2\)"),
        ((3, [[0.5, 1]]), "arcs: expected integer values"),
    ],
)
def test_constructor_validation(args, match):
    with pytest.raises(MescherError, match=match):
        DepthOrder(*args)


def test_from_embedding_validation():
    m = soup(TWO)
    with pytest.raises(MescherError, match=r"Zc: expected shape \(2, 3\), found \(3, 3\)"):
        DepthOrder.from_embedding(m, np.zeros((3, 3)))
    with pytest.raises(MescherError, match="Zc: expected finite values"):
        DepthOrder.from_embedding(m, [[0.0, np.nan, 0.0], [0.0, 0.0, 0.0]])
    with pytest.raises(MescherError, match="m: expected a Mescher"):
        DepthOrder.from_embedding("mesh", np.zeros((2, 3)))
    with pytest.raises(MescherError, match="tol: expected a finite number >= 0"):
        DepthOrder.from_embedding(m, np.zeros((2, 3)), tol=-1.0)
    with pytest.raises(MescherError, match="m: expected a mescher with 5 faces"):
        DepthOrder(5, m=m)


# ---------------------------------------------------------------------------------- stored arcs
# Arcs and overlap pairs computed by an earlier, pure-numpy implementation on the meshes of this
# file, the ParadoxToolkit models and a random soup (data/make_order_reference.py makes them).
# The compiled kernels must give the same *sets* of arcs and pairs.  Floating point may
# legitimately decide otherwise only where the mathematics is ill-conditioned, and the comparison
# allows exactly that: a pair whose overlap is thinner than a few tolerances (its "positive area"
# is a rounding decision), or an arc whose depth gap at the overlap is within a few depth
# tolerances of zero.  Overlap centroids are checked against shapely's exact polygon intersection
# with the conditioning of a centroid: its error is about eps * size^3 / area (the numerator is a
# sum of cross products of size^2 * size, the denominator the area).
REFERENCE = np.load(Path(__file__).parent / "data" / "order_reference.npz")
PARADOX_NAMES = [
    "penrose_triangle",
    "penrose_triangle_block",
    "impossible_cube",
    "penrose_stair",
    "impossible_arch",
    "reutersvard_rectangle",
]
EPS = float(np.finfo(np.float64).eps)


def _overlaps(T: np.ndarray, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """shapely's overlap polygon of each pair: area, centroid and its thickness (area / diameter)."""
    import shapely

    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    polys = shapely.polygons(T)
    inter = shapely.intersection(polys[pairs[:, 0]], polys[pairs[:, 1]])
    area = shapely.area(inter)
    c = shapely.centroid(inter)
    cen = np.stack((shapely.get_x(c), shapely.get_y(c)), axis=-1).reshape(-1, 2)  # nan if empty
    b = shapely.bounds(inter)
    diam = np.hypot(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])
    thick = np.where(diam > 0, area / np.where(diam > 0, diam, 1.0), 0.0)
    return area, cen, thick


def _as_set(a: np.ndarray) -> set:
    return set(map(tuple, np.asarray(a).reshape(-1, 2).tolist()))


def _same_pairs(got, cen, T, key):
    """Same overlapping pairs up to thin overlaps; centroids within their conditioning."""
    T = np.asarray(T, dtype=np.float64)
    tol = default_tol(T)
    ref = REFERENCE[key + "_pairs"]
    differ = np.array(sorted(_as_set(got) ^ _as_set(ref)), dtype=np.int64).reshape(-1, 2)
    _, _, thick = _overlaps(T, differ)
    assert np.all(thick < 8 * tol), (
        f"{key}: pairs {differ[thick >= 8 * tol].tolist()} differ although they overlap by "
        f"{thick[thick >= 8 * tol].max(initial=0):.3g} > 8 tol = {8 * tol:.3g}"
    )
    area, exact, thick = _overlaps(T, got)
    size = float(np.ptp(T.reshape(-1, 2), axis=0).max())
    well = thick >= 8 * tol
    assert well.sum() >= 0.9 * len(got)
    allowed = 1e-12 * size + 1e3 * EPS * size**3 / np.maximum(area, 1e-300)
    err = np.linalg.norm(cen - exact, axis=1)
    bad = well & ~(err <= allowed)
    assert not bad.any(), (
        f"{key}: centroid error {err[bad].max():.3g} at pairs {got[bad][:5].tolist()}"
    )


def _same_arcs(got, key, m, Zc=None):
    """Same arcs as the stored ones except on ill-conditioned pairs (see above)."""
    T = m.xy[m.F]
    tol = default_tol(T)
    differ = np.array(sorted(_as_set(got) ^ _as_set(REFERENCE[key])), dtype=np.int64).reshape(-1, 2)
    if not len(differ):
        return
    _, c, thick = _overlaps(T, differ)
    thin = thick < 8 * tol
    if Zc is None:  # local depth: the gap is that of the corner depths of each face's own frame
        flat = np.zeros(len(differ), dtype=bool)
    else:
        B0 = barycentric(c, T[differ[:, 0]])
        B1 = barycentric(c, T[differ[:, 1]])
        Zc = np.asarray(Zc, dtype=np.float64)
        dz = np.einsum("kc,kc->k", B1, Zc[differ[:, 1]]) - np.einsum(
            "kc,kc->k", B0, Zc[differ[:, 0]]
        )
        ztol = max(tol, TOL_FACTOR * float(np.abs(Zc).max()))  # as DepthOrder.from_embedding
        flat = np.abs(dz) < 8 * ztol
    ok = thin | flat
    assert ok.all(), f"{key}: arcs {differ[~ok][:5].tolist()} differ on well-conditioned overlaps"


def test_same_arcs_as_the_numpy_implementation_on_a_torus():
    view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
    V, F = torus()
    m = Mescher.from_mesh(V, F, view=view, up=up)
    Zc = camera(V, view, up)[F][:, :, 2]
    o = DepthOrder.from_embedding(m, Zc)
    _same_arcs(o.arcs, "torus_embedding", m, Zc)
    _same_arcs(DepthOrder.from_local_depth(m).arcs, "torus_local", m)
    _same_pairs(*overlapping_pairs(m.xy[m.F], centroids=True), m.xy[m.F], "torus")
    front = np.flatnonzero(m.xy[m.F][:, :, 0].mean(1) > 0.1)
    back = np.setdiff1d(np.arange(m.n_faces), front)
    _same_arcs(o.copy().put_in_front(front, back).arcs, "torus_put_in_front", m)
    V1, F1 = torus(16, 8)
    m1 = Mescher.from_mesh(V1, F1, view=view, up=up)
    o1 = DepthOrder.from_embedding(m1, camera(V1, view, up)[F1][:, :, 2])
    V2, F2 = igl.upsample(V1, F1)
    m2 = Mescher.from_mesh(V2, F2, view=view, up=up)
    r = o1.refine(np.repeat(np.arange(F1.shape[0]), 4), m2)
    _same_arcs(r.arcs, "refine", m2, camera(V2, view, up)[F2][:, :, 2])


@pytest.mark.parametrize("name", PARADOX_NAMES)
def test_same_arcs_as_the_numpy_implementation_on_cut_models(name):
    m, Zc = _paradox(name)
    _same_arcs(DepthOrder.from_embedding(m, Zc).arcs, name + "_embedding", m, Zc)
    _same_arcs(DepthOrder.from_local_depth(m).arcs, name + "_local", m)
    _same_pairs(*overlapping_pairs(m.xy[m.F], centroids=True), m.xy[m.F], name)


def test_same_arcs_as_the_numpy_implementation_on_a_folded_strip_and_a_soup():
    V, F = folded_strip()
    m = Mescher.from_mesh(V, F, view=(0.15, 0.1, 1.0))
    _same_arcs(DepthOrder.from_local_depth(m).arcs, "strip_local", m)
    _same_arcs(DepthOrder.from_local_depth(m, _force_paths=True).arcs, "strip_paths", m)
    T = REFERENCE["soup_T"]
    _same_pairs(*overlapping_pairs(T, centroids=True), T, "soup")


def test_stored_comparison_catches_a_changed_arc_and_a_moved_centroid():
    m, Zc = _paradox("penrose_triangle")
    arcs = DepthOrder.from_embedding(m, Zc).arcs
    pairs, cen = overlapping_pairs(m.xy[m.F], centroids=True)
    area, _, _ = _overlaps(m.xy[m.F], pairs)
    k = int(np.argmax(area))  # the best-conditioned overlap
    big = np.flatnonzero((np.sort(arcs, axis=1) == pairs[k]).all(axis=1))
    assert len(big) == 1
    flipped = arcs.copy()
    flipped[big[0]] = flipped[big[0], ::-1]
    with pytest.raises(AssertionError, match="differ on well-conditioned"):
        _same_arcs(flipped, "penrose_triangle_embedding", m, Zc)
    moved = cen.copy()
    moved[k] += 1e-6 * float(np.ptp(m.xy, axis=0).max())
    with pytest.raises(AssertionError, match="centroid error"):
        _same_pairs(pairs, moved, m.xy[m.F], "penrose_triangle")


@pytest.mark.slow
def test_arcs_of_a_24k_face_torus_agree_with_depths_and_local_depth():
    view, up = (0.3, -0.8, 0.5), (0.0, 0.0, 1.0)
    V, F = shapes.torus(200, 60, 1.0, 0.4)
    m = Mescher.from_mesh(V, F, view=view, up=up)
    Zc = camera(V, view, up)[F][:, :, 2]
    o = DepthOrder.from_embedding(m, Zc)
    # every arc i -> j has face j nearer the viewer at the centre of the overlap (shapely's)
    _, c, thick = _overlaps(m.xy[m.F], o.arcs)
    a, b = o.arcs[:, 0], o.arcs[:, 1]
    T = m.xy[m.F]
    dz = np.einsum("kc,kc->k", barycentric(c, T[b]), Zc[b]) - np.einsum(
        "kc,kc->k", barycentric(c, T[a]), Zc[a]
    )
    assert np.all(dz > 0)
    assert 96000 < o.n_arcs < 98000  # the count, up to borderline overlaps
    assert DepthOrder.from_local_depth(m) == o


# ---------------------------------------------------------------------------------- following xy
def _strip_and_truth():
    V, F = folded_strip()
    view = (0.15, 0.1, 1.0)
    m = Mescher.from_mesh(V, F, view=view)
    truth = DepthOrder.from_embedding(m, camera(V, view)[F][:, :, 2])
    return m, truth, V[:, 2]


def test_follow_orders_new_overlaps_from_local_depth_and_drops_vanished_ones():
    m, truth, z = _strip_and_truth()
    assert truth.n_arcs > 100
    # shear the layers apart in x by their height: most overlaps vanish
    m_apart = m.with_xy(m.xy + np.stack((20.0 * z, 0.0 * z), 1))
    apart = truth.follow(m_apart)
    before = set(map(tuple, overlapping_pairs(m.xy[m.F])[0].tolist()))
    after = set(map(tuple, overlapping_pairs(m_apart.xy[m_apart.F])[0].tolist()))
    assert len(before - after) > truth.n_arcs // 2  # most overlaps vanished
    assert {tuple(sorted(a)) for a in apart.arcs.tolist()} == after  # each remaining one ordered
    kept = {a for a in arcs_set(apart) if tuple(sorted(a)) in before}
    assert kept == {a for a in arcs_set(truth) if tuple(sorted(a)) in after}  # arcs carried
    assert arcs_set(apart) - kept <= arcs_set(DepthOrder.from_local_depth(m_apart))  # new ones
    # moving back: every overlap that reappears is ordered again, from local depth
    back = apart.follow(m)
    assert back == truth
    assert DepthOrder(m.n_faces).follow(m) == truth  # all overlaps new
    # an arc the user set is carried, not recomputed, while its faces overlap
    a, b = truth.arcs[0]
    flipped = truth.copy().put_in_front([a], [b])
    assert (b, a) in arcs_set(flipped.follow(m.with_xy(m.xy * 1.01)))


def test_with_xy_and_smooth_return_the_followed_order():
    m, truth, _ = _strip_and_truth()
    m2, o2 = m.with_xy(m.xy + 1.0, order=truth)
    assert o2 == truth and o2.n_faces == m2.n_faces  # a translation keeps every overlap
    m3, o3 = m.smooth(t_xy=1e-3, order=truth)
    from meschers_igl.smoothing import follow_sheets

    assert o3 == follow_sheets(truth, m3)
    carried = set(arcs_set(truth)) & set(arcs_set(truth.follow(m3)))
    assert carried <= set(arcs_set(o3))  # the arcs of pairs that still overlap are kept
    with pytest.raises(MescherError, match="m_new: expected a mescher with 3 faces"):
        DepthOrder(3).follow(m)


def _kahn_numpy(n, arcs):
    """The former numpy level-by-level Kahn (reference for the compiled one)."""
    indeg = np.bincount(arcs[:, 1], minlength=n)
    frontier, levels = np.flatnonzero(indeg == 0), []
    while frontier.size:
        levels.append(frontier)
        nb = np.concatenate([arcs[arcs[:, 0] == f, 1] for f in frontier])
        if nb.size == 0:
            break
        u, c = np.unique(nb, return_counts=True)
        indeg[u] -= c
        frontier = u[indeg[u] == 0]
    return np.concatenate(levels) if levels else np.zeros(0, dtype=np.int64)


@pytest.mark.parametrize("cyclic", [False, True])
def test_compiled_topological_sort_equals_the_numpy_one(cyclic):
    rng = np.random.default_rng(11)
    n = 400
    rank = rng.permutation(n)
    a, b = rng.integers(0, n, (2, 1500))
    keep = rank[a] < rank[b]
    arcs = np.stack((a[keep], b[keep]), 1)
    if cyclic:  # a 2-cycle blocks the sort part way
        arcs = np.concatenate((arcs, arcs[:1, ::-1]))
    arcs = DepthOrder(n, arcs).arcs
    order, complete = topological_sort(n, arcs)
    np.testing.assert_array_equal(order, _kahn_numpy(n, arcs))
    assert complete == (not cyclic) == (order.size == n)


def test_reconcile_arcs_lets_carried_arcs_win():
    hard = np.array([[0, 1], [1, 2], [7, 8], [8, 7]])
    soft = np.array([[2, 0], [3, 4], [5, 6], [6, 5], [8, 9]])
    got = reconcile_arcs(10, hard, soft)
    # 2 -> 0 contradicts 0 -> 1 -> 2: reversed; the soft 2-cycle 5 <-> 6 is dropped; the rest kept
    assert set(map(tuple, got.tolist())) == {(0, 2), (3, 4), (8, 9)}
    o = DepthOrder(10, np.concatenate((hard[:2], got)))
    assert o.cycles(warn=False) == []
    np.testing.assert_array_equal(reconcile_arcs(10, hard, np.zeros((0, 2))), np.zeros((0, 2)))


@pytest.mark.parametrize(
    "name",
    ["penrose_triangle", "penrose_stairs", "impossible_cube", "reutersvard_triangle", "window"],
)
def test_loop_subdivision_and_smoothing_show_no_back_face(name):
    # issue 17.2: Loop moves xy, so new overlaps appear; carrying the parents' arcs alone
    # (refine) leaves them unordered and back faces show through (measured: 1.2-4.7%)
    from meschers_igl import gallery
    from meschers_igl.painter import backface_share

    g = gallery.get_model(name)
    m, o = g.mescher, g.order
    # plain Loop rounds the boxes, so xy move most (crease Loop keeps them nearly in place)
    m2, o2, parent = m.subdivide(levels=2, scheme="loop-smooth", order=o, return_face_parent=True)
    assert backface_share(m2, o2) <= 1e-3
    assert backface_share(m2, o.refine(parent, m2)) > 1e-2  # the test can fail
    m3, o3 = m2.smooth(t_xy=1e-2, order=o2)
    assert backface_share(m3, o3) <= 1e-3
