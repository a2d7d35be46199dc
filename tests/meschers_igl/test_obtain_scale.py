"""Scenes of many parts convert in time: a city block of separate boxes on a huge ground plane.

The steps that compare parts with parts (the view vote over vertex pairs, pairing the caps of
equal boxes, the bridges between them) must not grow with the square of the number of parts
(times the number of faces): each is checked here against its brute-force definition, and a
10 x 10 grid of boxes on a ground plane 20 times its size must convert, possible, within a
bound a loaded machine keeps (measured 2.4 to 4 s on 2 shared cores; before, 190 to 300 s).
"""

from __future__ import annotations

import time
import warnings

import igl
import numpy as np
from scipy.spatial import cKDTree

from meschers_igl.obtain import bar_end_pairs, model_to_mescher
from meschers_igl.obtain.directions import votes
from meschers_igl.obtain.junctions import bridges_blocked
from meschers_igl.obtain.view import find_view
from meschers_igl.operators import view_frame
from meschers_igl.shapes import block_grid


def _convert(V, F, view=(1.0, 2.0, 3.0)):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        m, order, report = model_to_mescher(V, F, view=view)
        return m, order, report, time.perf_counter() - t


def test_block_grid_on_ground_converts_in_time_and_stays_possible():
    n = 10
    V, F = block_grid(n, ground=20.0 * 3 * n)
    _convert(*block_grid(2))  # warm-up: compiled kernels loaded once per process
    m, order, report, seconds = _convert(V, F)
    assert seconds < 20.0, seconds
    # separate boxes on a plane are an ordinary scene: no period, every zeta integrable
    assert np.all(m.periods() == 0.0), np.abs(m.periods()).max()
    assert report.route == "visible", report.route
    assert not [j for j in report.junctions if j.depth_gap > 0], report.junctions
    # each box shows its top and two sides (6 triangles) and the ground shows around them
    assert m.n_faces >= 6 * n * n + 2, m.n_faces


def test_vote_counts_equal_the_ball_counts():
    """The vote over exactly repeated directions (a lattice) equals the brute-force count of
    directions (of either sign) within the vote's chord of each one."""
    rng = np.random.default_rng(3)
    V, _ = block_grid(3)
    i, j = np.triu_indices(V.shape[0], k=1)
    D = V[j] - V[i]
    U = D / np.linalg.norm(D, axis=1, keepdims=True)
    U = np.vstack([U, rng.normal(size=(200, 3))])
    U /= np.linalg.norm(U, axis=1, keepdims=True)
    U *= np.where(U @ np.array([1e-3, 1e-2, 1.0]) < 0, -1.0, 1.0)[:, None]
    tree = cKDTree(np.vstack([U, -U]))
    for angle in (2e-4, 0.05, 0.4):
        want = np.array([len(c) for c in tree.query_ball_point(U, angle)])
        counts, W, inv, _ = votes(U, angle)
        np.testing.assert_array_equal(counts, want)
        np.testing.assert_array_equal(W[inv], U)
        assert W.shape[0] < U.shape[0]  # the lattice repeats directions


def test_cap_pairs_are_the_congruent_opposite_caps():
    """Without a view, equal boxes pair each cap with the opposite caps of every box (loops
    congruent by a translation, normals opposite), each pair once per orientation, with the
    translation between the loops."""
    n = 3
    V, F = block_grid(n, heights=[1.0] * (n * n - 1) + [2.0])  # the last box is taller
    pairs = bar_end_pairs(V, F, 1e-6)
    b = n * n
    # x caps: the unit boxes' (2 x 1) pair among themselves, the tall box's (2 x 2) only with
    # each other; the same for y; z caps (2 x 2): every top with every bottom
    want = 2 * (2 * ((b - 1) ** 2 + 1) + b**2)
    assert len(pairs) == want, (len(pairs), want)
    for be in pairs:
        A, B = V[be.first.loop], V[be.second.loop]
        assert be.first.normal @ be.second.normal < -1 + 1e-9
        d = cKDTree(B).query(A + be.T)[0]
        assert d.max() <= 1e-9


def test_bridges_blocked_is_the_winding_number_of_each_axis():
    """The batched test equals libigl's winding number at each bridge's axis points."""
    V, F = block_grid(4, heights=np.arange(16) % 3 + 1.0)
    R = view_frame((1.0, 2.0, 3.0), (0.0, 0.0, 1.0))
    pairs = [be for be in bar_end_pairs(V, F, 1e-6) if be.d is not None][:400]
    got = bridges_blocked(V, F, R, pairs)
    want = []
    for be in pairs:
        if be.first.normal @ be.d <= 0:
            want.append(False)
            continue
        M = np.stack([be.d, R[2]], axis=1)
        (ell, _), *_ = np.linalg.lstsq(M, be.T, rcond=None)
        c0 = V[be.first.loop].mean(axis=0)
        axis = c0 + np.array([[0.25], [0.5], [0.75]]) * ell * be.d
        want.append(bool(np.any(np.abs(igl.winding_number(V, F, axis)) > 0.5)))
    np.testing.assert_array_equal(got, want)
    assert 0 < got.sum() < got.size  # some bridges run through a box, some through air


def test_find_view_on_a_lattice_is_quick_and_lines_up_pairs():
    """A lattice of equal boxes lines up many vertex pairs along each lattice direction: the
    vote takes well under a second per thousand vertices, and the view it returns lines up
    (on screen, to round-off) the pairs it says support it."""
    V, F = block_grid(10)
    t = time.perf_counter()
    v, up, pairs = find_view(V, F, return_support=True)
    assert time.perf_counter() - t < 5.0
    R = view_frame(v, up)
    s = V @ R[:2].T
    assert pairs.shape[0] >= 2
    assert np.abs(s[pairs[:, 0]] - s[pairs[:, 1]]).max() <= 1e-9 * np.ptp(s)


def test_pair_gate_keeps_every_junction():
    """The vectorized gate drops only pairs that :func:`junction_at` finds no junction for:
    on the U-tribar (a false edge from its view) and on a grid of boxes of three heights."""
    from visible_models import ISO_UP, ISO_VIEW, triangulate, u_tribar

    from meschers_igl.obtain import weld
    from meschers_igl.obtain.junctions import junction_at, may_be_junctions, parts_and_front

    Vt, P, _ = u_tribar()
    Vt, Ft, _ = weld(Vt, triangulate(P), 1e-9)
    Vg, Fg = block_grid(4, heights=np.arange(16) % 3 + 1.0)
    n_found = n_dropped = 0
    for V, F, view, up in ((Vt, Ft, ISO_VIEW, ISO_UP), (Vg, Fg, (1.0, 2.0, 3.0), (0, 0, 1.0))):
        R = view_frame(view, up)
        TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
        pairs = bar_end_pairs(V, F, 1e-6, TT)
        part, C, front = parts_and_front(V, F, TT, R)
        may = may_be_junctions(pairs, R, 1e-6, True)
        for be, m in zip(pairs, may.tolist()):
            found = junction_at(V, F, C, R, be, 1e-6, front, part, True)
            assert m or found is None
            n_found += found is not None
        n_dropped += int((~may).sum())
    assert n_found >= 1 and n_dropped >= 1, (n_found, n_dropped)
