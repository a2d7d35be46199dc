"""The geodesic front door: every registered method through one call, the registry's contract.

Oracles: MMP on a real 3D covering (``"covering"``) for window propagation (``"exact"``), and
the exact distance as a bound for the heat presets and for a method registered by a test.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from builders import impossible_tube, mean_rel
from scipy.sparse.csgraph import dijkstra

from meschers_igl import MescherError
from meschers_igl.geodesic import (
    SOLVERS,
    geodesic_distance,
    geodesic_solver,
    methods,
    shortest_path,
)


@pytest.fixture(scope="module")
def tube():
    m = impossible_tube(24, 8)
    return m, geodesic_distance(m, [0, 50], "covering")


def test_every_method_through_the_front_door(tube):
    m, de = tube
    assert methods()[0] == "auto" and {"exact", "covering", "geometry_central"} <= set(methods())
    for name in methods():
        S = geodesic_solver(m, name)
        d = S.distance([0, 50])
        assert S.m is m and S.n_vertices == m.n_vertices
        assert d.shape == (m.n_vertices,)
        # potpourri3d's variant puts the mean over the sources at 0, the others each source
        at_src = d[[0, 50]].mean() if name == "geometry_central" else d[[0, 50]]
        np.testing.assert_allclose(at_src, 0.0, atol=1e-12)
        # exact methods agree to round-off; the heat presets are first-order accurate
        tol = 1e-9 if name in ("exact", "covering") else None
        if tol is None:
            assert mean_rel(d, de) < 0.12, name
        else:
            np.testing.assert_allclose(d, de, atol=tol)
        # Mescher.geodesic_distance is the same door
        np.testing.assert_array_equal(m.geodesic_distance([0, 50], method=name), d)


def test_targets_are_exact_where_asked(tube):
    m, de = tube
    far = int(np.argmax(de))
    for name in ("exact", "covering", "auto"):
        d = geodesic_distance(m, 0, name, targets=[7, far])
        full = geodesic_distance(m, 0, name)
        np.testing.assert_allclose(d[[7, far]], full[[7, far]], atol=1e-12)


def test_unknown_method_and_bad_sources_name_the_argument(tube):
    m, _ = tube
    with pytest.raises(MescherError, match="method: expected one of 'auto'.*'covering'"):
        geodesic_solver(m, "mmp")
    for name in ("exact", "covering", "auto"):
        with pytest.raises(MescherError, match="sources"):
            geodesic_distance(m, m.n_vertices, name)


class _EdgeGraphSolver:
    """A method registered by the test: Dijkstra along the edges (an upper bound)."""

    def __init__(self, m):
        self.m, self.n_vertices = m, int(m.n_vertices)
        E, n = np.asarray(m.edges), self.n_vertices
        w = np.asarray(m.edge_lengths())
        self._W = sp.csr_matrix(
            (np.r_[w, w], (np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]])), (n, n)
        )

    def distance(self, sources, targets=None):
        return dijkstra(self._W, indices=np.atleast_1d(sources), min_only=True)


def test_a_new_method_is_one_class_and_one_registry_line(tube, monkeypatch):
    m, de = tube
    monkeypatch.setitem(SOLVERS, "edge_graph", _EdgeGraphSolver)
    assert "edge_graph" in methods()
    d = m.geodesic_distance([0, 50], method="edge_graph")
    # along edges is never shorter than on the surface, and not much longer on this tube
    assert (d >= de - 1e-12).all() and mean_rel(d, de) < 0.3
    path = shortest_path(m, 0, 77, solver=geodesic_solver(m, "edge_graph"))
    assert path.length == pytest.approx(de_single(m, 0)[77], rel=1e-3)


def de_single(m, s):
    return geodesic_distance(m, s, "exact")
