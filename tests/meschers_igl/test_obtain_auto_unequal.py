"""``view="auto"`` on Penrose tribars of three separate boxes with unequal legs.

Built as modelling tools do: an x-bar, a y-bar and a column (z), each a box of 8 corners and
12 triangles, overlapping or abutting at the two real corners.  With legs ``(a, b, c)`` the
x-bar's free end lies ``T = (a, b, c)`` behind the column's top: from ``T / |T|`` two vertex
pairs coincide (the end's top edge on the column's top edge) and the mescher's period is
``|T|``.  Box corners line up two pairs each along many lattice directions too (``(a + w, b,
c + w)``: the end's bottom edge on the column's far top edge), so the vote ties; the junction is
the tie whose corners are flush (their outline edges run on along each other on screen) and
far apart through the model (:mod:`meschers_igl.obtain.view_rank`).
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from meschers_igl import Mescher
from meschers_igl.obtain import see_model
from meschers_igl.obtain.view import _pick, _vote

#: Corners of the unit cube, index ``4 x + 2 y + z``, and its 12 outward triangles.
CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float64)
CUBE_F = np.array(
    [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1]]
    + [[2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
)
LEGS = [(8.0, 12.0, 16.0), (10.0, 10.0, 14.0), (10.0, 6.0, 8.0), (6.0, 14.0, 9.0)]


def boxes(lo_hi):
    """One unwelded mesh of the boxes ``[lo, hi]`` (12 outward triangles each)."""
    V = np.vstack([lo + CUBE * (np.subtract(hi, lo)) for lo, hi in lo_hi])
    F = np.vstack([CUBE_F + 8 * k for k in range(len(lo_hi))])
    return V, F


def tribar(legs, joint, w=1.0):
    """Three boxes: the x-bar ``[0, a] x [0, w]^2`` (to ``a + w/2`` when overlapping), the
    y-bar along ``x = a`` to ``y = b`` (``b + w/2``), the column at ``(a, b)`` up to ``c + w``;
    ``joint`` ``"abut"`` (faces touching) or ``"overlap"`` (by half a width).  Returns
    ``(V, F, T)`` with ``T`` the junction vector from the x-bar's free end to the column's top."""
    a, b, c = legs
    e = 0.5 * w if joint == "overlap" else 0.0
    V, F = boxes(
        [
            ([0, 0, 0], [a + e, w, w]),
            ([a, 0, 0], [a + w, b + e, w]),
            ([a, b, 0], [a + w, b + w, c + w]),
        ]
    )
    return V, F, np.asarray(legs, np.float64)


def convert(V, F):
    """``see_model(V, F, "auto")``: (view, periods, impossible?, seconds)."""
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vm = see_model(V, F, "auto")
    dt = time.perf_counter() - t
    m = Mescher.from_corner_depths(vm.F, vm.xy, vm.Z)
    p = np.abs(np.asarray(m.periods(), np.float64))
    return np.asarray(vm.report.view, np.float64), p, dt


def check(V, F, T):
    v, p, dt = convert(V, F)
    gap = float(np.linalg.norm(T))
    assert abs(abs(v @ T) / gap - 1.0) <= 1e-6, (v, T / gap)
    big = p[p > 1e-6 * gap]
    assert big.size > 0, p  # impossible: a period round the loop
    assert np.allclose(big, gap, rtol=1e-6, atol=0.0), (big, gap)
    assert dt < 2.0, dt


@pytest.mark.parametrize("joint", ["abut", "overlap"])
@pytest.mark.parametrize("legs", LEGS)
def test_auto_view_is_the_junction_view(legs, joint):
    """The view along ``T``, the period ``|T|`` (the gap between the coincident ends)."""
    check(*tribar(legs, joint))


@pytest.mark.parametrize("seed", range(4))
def test_auto_view_of_a_rotated_tribar(seed):
    """A random rotation and offset: the view turns with the model, the period stays."""
    legs, joint = LEGS[seed % len(LEGS)], ["abut", "overlap"][seed % 2]
    V, F, T = tribar(legs, joint)
    Q = Rotation.random(random_state=100 + seed).as_matrix()
    offset = np.random.default_rng(seed).normal(size=3) * 20.0
    check(V @ Q.T + offset, F, Q @ T)


@pytest.mark.parametrize("legs", LEGS[:3])
def test_the_junction_ties_with_accidental_lattice_directions(legs):
    """The premise: along ``T`` two pairs line up, and as many along other directions seen
    from no closer to edge-on, some with longer pairs (the old tie-break's choice)."""
    V, F, T = tribar(legs, "abut")
    cands = _pick(_vote(V, F), V, F, 200, 0.2)
    t = T / np.linalg.norm(T)
    k = [i for i, (v, _, _) in enumerate(cands) if abs(v @ t) > 1 - 1e-12]
    assert len(k) == 1
    n_true = cands[k[0]][2].shape[0]
    assert n_true == 2
    tied = [c for c in cands if c[2].shape[0] == n_true and abs(c[0] @ t) < 1 - 1e-9]
    assert len(tied) >= 3
    L = lambda c: np.linalg.norm(V[c[2][:, 1]] - V[c[2][:, 0]], axis=1).max()  # noqa: E731
    assert max(L(c) for c in tied) > L(cands[k[0]])


def test_flush_corners_oracle():
    """Flush by construction: a box and its translated copy, seen along the translation: every
    corner coincides with its copy's and all their edges run along each other.  Corners of
    opposite kind (a bottom corner on a top corner, offset ``(1, 1, 1)``) are not flush."""
    from meschers_igl.obtain.view_rank import feature_adjacency, flush_pairs

    V, F = boxes([([0, 0, 0], [1, 2, 3]), ([5, 7, 11], [6, 9, 14])])
    adj = feature_adjacency(V, F)
    assert np.all(np.diff(adj[0]) == 3)  # a box's corner: three outline edges, no diagonal
    d = np.array([5.0, 7.0, 11.0])
    P = np.stack([np.arange(8), np.arange(8) + 8], axis=1)
    assert flush_pairs(V, adj, P, d / np.linalg.norm(d)).all()
    # corner 0 (x, y, z lowest) against corner 7 of the copy (highest): edges run opposite
    P2 = np.array([[0, 15]])
    d2 = V[15] - V[0]
    assert not flush_pairs(V, adj, P2, d2 / np.linalg.norm(d2)).any()


@pytest.mark.parametrize("joint", ["abut", "overlap"])
def test_the_junction_is_far_through_the_model(joint):
    """The walk through the model from the x-bar's free end to the column's top goes round
    the figure: at least ``|T|`` and at most along the three legs' edges ``a + b + c`` plus
    the widths; for separate boxes that did not touch there would be no walk at all."""
    legs = (8.0, 12.0, 16.0)
    V, F, T = tribar(legs, joint)
    from scipy.sparse.csgraph import dijkstra

    from meschers_igl.obtain.view_rank import model_graph

    G = model_graph(V, F, 1e-9)
    p = int(np.flatnonzero(np.all(V == [0, 0, 1], axis=1))[0])  # the end's top corner
    q = np.flatnonzero(np.all(np.isclose(V, V[p] + T), axis=1))
    assert q.size == 1
    d = dijkstra(G, indices=[p])[0, q[0]]
    assert np.linalg.norm(T) * 1.2 < d <= sum(legs) + 3.0 + 1e-9
    apart = dijkstra(model_graph(V + np.repeat([[0, 0, 0], [0, 0, 0], [0, 0, 5.0]], 8, 0), F, 1e-9))
    assert np.isinf(apart[p, 16:]).all()  # the column lifted off: no walk to it


@pytest.mark.parametrize("joint", ["abut", "overlap"])
def test_auto_view_from_a_file(tmp_path, joint):
    """From an OBJ (PyMeshLab's clean-up first, as ``meschers convert --view auto``): the same
    view and period."""
    from visible_models import write_obj

    from meshlab_filters import model_to_mescher

    V, F, T = tribar((8.0, 12.0, 16.0), joint)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = model_to_mescher(
            write_obj(tmp_path / "tribar.obj", V, F.tolist()), view="auto"
        )
    gap = float(np.linalg.norm(T))
    assert abs(abs(np.asarray(report.view) @ T) / gap - 1.0) <= 1e-6
    assert m.is_impossible(order=order).kind == "zeta"
    p = np.abs(np.asarray(m.periods(), np.float64))
    assert np.allclose(p[p > 1e-6 * gap], gap, rtol=1e-6, atol=0.0)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_auto_view_near_a_start_on_either_side(side):
    """``view_start`` a few degrees off ``T`` or ``-T``: the view on that side, exactly."""
    V, F, T = tribar((10.0, 6.0, 8.0), "overlap")
    t = T / np.linalg.norm(T)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vm = see_model(V, F, "auto", view_start=side * t + np.array([0.03, -0.02, 0.01]))
    assert np.asarray(vm.report.view) @ t == pytest.approx(side, abs=1e-12)


@pytest.mark.parametrize("joint", ["abut", "overlap"])
@pytest.mark.parametrize("legs", LEGS)
def test_the_junction_ranks_first(legs, joint):
    """Of the vote's directions with two flush pairs or more, the junction's corners are the
    farthest apart through the model (ratio 1.59 to 1.77 here, the others' at most sqrt 2):
    it ranks first, and once."""
    from meschers_igl.obtain.view_rank import rank_directions

    V, F, T = tribar(legs, joint)
    cands = _pick(_vote(V, F), V, F, 200, 0.2)
    ranked = rank_directions(V, F, cands, 1e-9)
    assert len(ranked) >= 2
    assert abs(ranked[0][0] @ T) / np.linalg.norm(T) == pytest.approx(1.0, abs=1e-12)
    assert all(abs(w @ T) / np.linalg.norm(T) < 1 - 1e-6 for w, _, _ in ranked[1:])
