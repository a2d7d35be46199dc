"""``view="auto"`` for figures seen partly edge-on from their own view.

Artists bevel a tribar's bars, or shear its closing bar so that its side faces contain the
view: from the figure's view those faces are lines on screen.  The view vote refuses a
direction seeing over :data:`~meschers_igl.obtain.view.MAX_EDGE_ON` of the model edge-on (a
box seen along an axis lines up many vertex pairs), so such a figure's own view was refused
although a junction is seen from it.  Such a better-supported view is now judged after the
others, and taken when a junction is seen from it; an ordinary box scene seen along its axes
stays refused.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from visible_models import AXES, ISO_VIEW, convex_block, triangulate, weld_blocks

from meschers_igl import MescherError
from meschers_igl.obtain import PERIOD_RTOL, model_to_mescher
from meschers_igl.obtain.view import EDGE_ON_FALLBACK, MAX_EDGE_ON, find_view

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"


def _bevelled_bar(R0, R1, d, t, k, m0, m1):
    """A square bar ``t`` wide along axis ``d`` from R0 to R1, its four long edges bevelled
    (``|(p - R0) . (e1 +- e2)| <= k``, an octagonal section), ends cut by planes with normals
    ``m0`` (start) and ``m1`` (end)."""
    e1, e2 = [e for e in AXES if abs(e @ d) < 0.5]
    hs = [np.r_[s * e, -s * (R0 @ e) - t / 2] for e in (e1, e2) for s in (1.0, -1.0)]
    for w in (e1 + e2, e1 - e2, -e1 + e2, -e1 - e2):
        hs.append(np.r_[w, -(R0 @ w) - k])
    hs += [np.r_[-m0, m0 @ R0], np.r_[m1, -(m1 @ R1)]]
    return convex_block(np.asarray(hs), 0.5 * (R0 + R1))


def bevelled_tribar(L=4.0, t=1.0, k=0.72):
    """The capped Penrose tribar (bars +x, +y, +z of length L, opened in the middle of the x bar
    by a plane containing the view (1, 1, 1)) with bevelled bars: each bar's bevels between a
    face toward the viewer and one away contain the view.  Returns (V, polygons, gap) with the
    junction's depth gap L sqrt(3)."""
    x, y, z = AXES
    m = x - (x @ ISO_VIEW) * ISO_VIEW
    R1 = L * x
    R2, R3 = R1 + L * y, R1 + L * y + L * z
    blocks = [
        _bevelled_bar(0.5 * L * x, R1, x, t, k, m, x + y),
        _bevelled_bar(R1, R2, y, t, k, x + y, y + z),
        _bevelled_bar(R2, R3, z, t, k, y + z, z + x),
        _bevelled_bar(R3, R3 + 0.5 * L * x, x, t, k, z + x, m),
    ]
    V, polys = weld_blocks(blocks)
    return V, polys, float(R3 @ ISO_VIEW)


def _edge_on_share(V, F, v):
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    a = np.linalg.norm(n, axis=1)
    return float(a[np.abs(n @ v) < 1e-3 * a].sum() / a.sum())


def _periods(m):
    p = np.abs(np.asarray(m.periods()))
    return p[p > PERIOD_RTOL * m.scale()]


def test_a_bevelled_tribar_is_found_from_its_own_view():
    """The bevelled tribar's view lines up the most vertex pairs but sees over MAX_EDGE_ON of
    it edge-on (the bevels): it is judged after the others, a junction is seen from it, and the
    period is the built gap, as from the given view."""
    V, P, gap = bevelled_tribar()
    F = triangulate(P)
    share = _edge_on_share(V, F, ISO_VIEW)
    assert MAX_EDGE_ON < share < EDGE_ON_FALLBACK
    v, _ = find_view(V, F, max_edge_on=1.0)
    assert np.linalg.norm(np.cross(v, ISO_VIEW)) <= 1e-12  # the best-supported direction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = model_to_mescher(V, F, view="auto")
        m_given, _, _ = model_to_mescher(V, F, view=ISO_VIEW, up=(-1.0, -1.0, 2.0))
    assert np.linalg.norm(np.cross(report.view, ISO_VIEW)) <= 1e-9
    p = _periods(m)
    assert p.size == 1 and abs(p[0] - gap) <= 1e-9 * gap
    assert np.allclose(_periods(m_given), p, rtol=1e-9)
    assert m.is_impossible(order=order).kind == "zeta"


@pytest.mark.parametrize("name", ["two_boxes", "stairs"])
def test_ordinary_models_seen_along_their_axes_stay_refused(name):
    """Ordinary models whose best-supported direction sees them largely edge-on (two boxes in
    a row along their axis, a staircase along its flight's diagonal): no junction is seen from
    any candidate, so ``view="auto"`` still refuses in one line saying what to pass."""
    from builders import box_mesh, merge_meshes, ordinary_stairs

    if name == "two_boxes":
        V, F = merge_meshes([box_mesh([0, 0, 0], [1, 1, 1]), box_mesh([3, 0, 0], [4, 1, 1])])
    else:
        V, F = ordinary_stairs()
    v, _ = find_view(V, F, max_edge_on=1.0)
    assert _edge_on_share(V, F, v) > MAX_EDGE_ON
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(MescherError, match="view: expected a view from which junctions"):
            model_to_mescher(V, F, view="auto")


@pytest.mark.skipif(not REAL.is_dir(), reason="the development set is absent")
def test_the_sheared_torus_file_is_found_from_its_view():
    """PenroseTriangle2.obj (a real torus whose closing bar's side faces contain the view: 20%
    of its area edge-on from it): ``view="auto"`` finds the isometric view, and the period is
    the junction's coincident-pair gap, as from the given view."""
    pytest.importorskip("pymeshlab")
    from meshlab_filters import model_to_mescher as from_file

    d = json.loads((REAL / "views.json").read_text())["PenroseTriangle2.obj"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = from_file(REAL / "PenroseTriangle2.obj", view="auto")
    assert np.linalg.norm(np.cross(report.view, d["view"])) <= 1e-6
    p = _periods(m)
    assert (
        p.size == 1 and np.min(np.abs(np.asarray(d["coincident_depth_gaps"]) - p[0])) <= 1e-4 * p[0]
    )
    assert m.is_impossible(order=order).kind == "zeta"
