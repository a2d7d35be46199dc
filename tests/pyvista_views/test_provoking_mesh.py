"""The provoking layout built in one pass (points and normals written as the cells claim their
last corner) is exactly the claim pass followed by the gathers it replaces."""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import sphere

from pyvista_views import polydata


@pytest.mark.parametrize("columns", [2, 3])
def test_one_pass_equals_claims_then_gathers(columns):
    V, F = sphere(14)
    V = np.vstack([V, [[5.0, 6.0, 7.0]]])  # a vertex no face uses: it ends no cell
    rng = np.random.default_rng(columns)
    draw = rng.permutation(len(F))
    fn = rng.normal(size=(len(F), 3))
    points = V[:, :columns].copy()
    cells, source, P, N = polydata._provoking_mesh(
        *(polydata._frozen(a, t) for a, t in ((F, np.int64), (draw, np.int64))),
        polydata._frozen(points, np.float64),
        polydata._frozen(fn, np.float64),
    )
    ref_cells, ref_source = polydata.provoking_cells(F[draw], len(V))
    np.testing.assert_array_equal(cells, ref_cells)
    np.testing.assert_array_equal(source, ref_source)
    expected = np.zeros((len(source), 3))
    expected[:, :columns] = points[source]
    np.testing.assert_array_equal(P, expected)
    k = len(F)
    np.testing.assert_array_equal(N[:k], fn[draw].astype(np.float32))
    np.testing.assert_array_equal(N[k:], np.tile(np.float32([0, 0, 1]), (len(source) - k, 1)))
    assert len(V) - 1 in source[k:].tolist()  # the unused vertex is kept, after the cells


def test_inputs_are_not_copied_when_already_right():
    a = np.arange(12, dtype=np.int64).reshape(4, 3)
    frozen = polydata._frozen(a, np.int64)
    assert np.shares_memory(frozen, a) and not frozen.flags.writeable
    assert a.flags.writeable  # the caller's array keeps its flag
    assert not np.shares_memory(polydata._frozen(a[::-1], np.int64), a)
