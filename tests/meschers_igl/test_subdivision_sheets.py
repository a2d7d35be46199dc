"""Loop subdivision carries the depth order sheet by sheet (``follow_sheets`` with parents).

Loop moves screen positions, so children of faces that did not overlap come to overlap.  Those
pairs continue the order of the sheets next to them; the arcs between children of ordered
parents are carried unchanged; pairs of faces sharing a vertex keep local depth.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl import MescherError
from meschers_igl.gallery import get_model
from meschers_igl.geometry2d import default_tol, overlapping_pairs
from meschers_igl.smoothing import follow_sheets


def _pairs(m):
    T = np.ascontiguousarray(np.asarray(m.xy, dtype=np.float64)[np.asarray(m.F)])
    return np.asarray(overlapping_pairs(T, default_tol(T), centroids=True)[0]).reshape(-1, 2)


@pytest.mark.parametrize("name", ["impossibagel", "penrose_triangle", "window"])
def test_loop_carries_parent_arcs_and_orders_only_overlaps(name):
    g = get_model(name)
    m, o = g.mescher, g.order
    m2, o2, parent = m.subdivide(1, scheme="loop", order=o, return_face_parent=True)
    assert o2 == follow_sheets(o, m2, parent)
    n, n2 = m.n_faces, m2.n_faces
    arcs = np.asarray(o2.arcs)
    pairs = _pairs(m2)
    keys = set((np.minimum(pairs[:, 0], pairs[:, 1]) * n2 + np.maximum(*pairs.T)).tolist())
    # every arc joins faces that overlap on screen
    assert set((arcs.min(axis=1) * n2 + arcs.max(axis=1)).tolist()) <= keys
    # every overlapping pair whose parents were ordered keeps their direction
    parent_arcs = set((np.asarray(o.arcs)[:, 0] * n + np.asarray(o.arcs)[:, 1]).tolist())
    got = set((arcs[:, 0] * n2 + arcs[:, 1]).tolist())
    pa, pb = parent[pairs[:, 0]], parent[pairs[:, 1]]
    fwd = np.isin(pa * n + pb, list(parent_arcs))
    bwd = np.isin(pb * n + pa, list(parent_arcs))
    assert fwd.any() or bwd.any()
    expect = np.concatenate((pairs[fwd & ~bwd], pairs[bwd & ~fwd][:, ::-1]))
    assert set((expect[:, 0] * n2 + expect[:, 1]).tolist()) <= got
    # the new overlaps are ordered too (up to arcs dropped to keep the carried order acyclic)
    new = ~(fwd | bwd)
    assert new.sum() > 0
    ordered = set((arcs.min(axis=1) * n2 + arcs.max(axis=1)).tolist())
    new_keys = np.minimum(pairs[new, 0], pairs[new, 1]) * n2 + np.maximum(*pairs[new].T)
    assert np.isin(new_keys, list(ordered)).mean() > 0.95


def test_follow_sheets_parents_default_and_validation():
    g = get_model("impossibagel")
    m, o = g.mescher, g.order
    ms = m.smooth(t_xy=1e-3)
    # the faces themselves are the default parents
    assert follow_sheets(o, ms, np.arange(m.n_faces)) == follow_sheets(o, ms)
    m2, parent = m.subdivide(1, scheme="loop", return_face_parent=True)
    with pytest.raises(MescherError, match="face_parent: expected one parent per child face"):
        follow_sheets(o, m2, parent[:-1])
    with pytest.raises(MescherError, match="face_parent: expected parent faces in"):
        follow_sheets(o, m2, np.where(parent == 0, m.n_faces, parent))
