"""``view="auto"`` for the impossible cube's trick: a bar broken *in line*, its ends cut by
planes holding the view, completed behind a crossing bar (:func:`junction_at`'s "crossing").

The ends are seen edge-on only from the views on the great circle perpendicular to their
faces' normal; along it the crossing holds over an arc of views (the crossing bar moves across
the gap on screen) and the view taken is the arc's middle.  Artists' files carry T-junction
cracks (a vertex on another face's edge, a slit of collinear vertices): an open model whose
loops glue with nothing is not a cut model, and its slits do not choose the view.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_visible_crossing import VIEWS, _frame

from meschers_igl import MescherError
from meschers_igl.obtain import model_to_mescher
from meschers_igl.obtain.view import find_view
from meschers_igl.topology import boundary_loops


def _auto(V, F):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view="auto")


def _cut_normal(V, F, R):
    """Unit normal of the faces holding the construction view that are not axis-aligned (the
    slanted cuts of the broken bar)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    slanted = (np.abs(n @ R[2]) < 1e-9) & (np.abs(n).max(axis=1) < 1.0 - 1e-9)
    assert slanted.any()
    return n[slanted][0]


def _check_crossing_view(V, F, R):
    m, order, report = _auto(V, F)
    assert report.route == "closed" and [j.kind for j in report.junctions] == ["crossing"]
    assert m.is_impossible(order=order).kind == "order"
    assert np.abs(m.periods()).max(initial=0.0) <= 1e-9 * m.scale()  # in line: no period
    # the ends are edge-on from the view found, a few degrees along their circle from the
    # construction view (both on the arc of views from which the crossing holds)
    assert abs(_cut_normal(V, F, R) @ report.view) <= 1e-9
    assert np.degrees(np.arccos(min(1.0, report.view @ R[2]))) < 10.0


@pytest.mark.parametrize("view", VIEWS[:2])
def test_auto_view_finds_the_crossing(view):
    V, F, R, crossed = _frame(view)
    assert crossed
    _check_crossing_view(V, F, R)


def test_square_cut_ends_are_no_crossing_from_any_view():
    """Cut square, the ends are edge-on only from views perpendicular to the bar, from which
    no bar behind fills the gap as wide as it is: refused, as before."""
    V, F, _, _ = _frame(VIEWS[0], square=True)
    with pytest.raises(MescherError, match="view: expected a view from which junctions"):
        _auto(V, F)


def _crack(V, F, i, j):
    """A T-junction crack, as artists' files have: the edge ``i -> j`` gets two vertices at
    its thirds in its own face only (that face fanned in three), leaving a slit of four
    collinear vertices."""
    face = int(np.flatnonzero(np.any((F == i) & (np.roll(F, -1, axis=1) == j), axis=1))[0])
    c = [x for x in F[face].tolist() if x not in (i, j)][0]
    a, b = V.shape[0], V.shape[0] + 1
    V2 = np.vstack([V, (2 * V[i] + V[j]) / 3, (V[i] + 2 * V[j]) / 3])
    F2 = np.vstack([np.delete(F, face, axis=0), [[i, a, c], [a, b, c], [b, j, c]]])
    return V2, F2


def _two_cracks(V, F):
    """Cracks on the longest edge and on an edge parallel to it, as long and running the same
    way, offset from it along the least axis-like direction: the two slits of a frame whose
    bars were joined without splitting the faces they meet."""
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    D = V[he[:, 1]] - V[he[:, 0]]
    L = np.linalg.norm(D, axis=1)
    k = int(np.argmax(L))
    same = np.isclose(L, L[k]) & (D @ D[k] > (1.0 - 1e-12) * L * L[k])
    same &= np.linalg.norm(np.cross(V[he[:, 0]] - V[he[k, 0]], D[k]), axis=1) > 1e-6 * L[k]
    off = V[he[same, 0]] - V[he[k, 0]]
    off /= np.linalg.norm(off, axis=1, keepdims=True)
    slant = np.abs(off).max(axis=1)  # the least axis-like offset: not seen edge-on along it
    k2 = int(np.flatnonzero(same)[np.argmin(slant)])
    V, F = _crack(V, F, *he[k].tolist())
    return _crack(V, F, *he[k2].tolist())


def test_a_cracked_crossing_frame_is_not_taken_for_a_cut_model():
    """With two T-junction cracks the model is open: its loops (four collinear vertices each)
    glue with nothing, so they are no cut model's seam and do not choose the view (the vote
    over their vertices lines up pairs of them from a view far from the figure's); the
    crossing is found as on the whole frame."""
    V, F, R, _ = _frame(VIEWS[1])
    V, F = _two_cracks(V, F)
    loops = boundary_loops(F)
    assert sorted(len(loop) for loop in loops) == [4, 4]
    # the vote over the slits' vertices lines up some of their pairs: a view (not the figure's)
    v, _ = find_view(V, F)
    assert np.degrees(np.arccos(min(1.0, abs(v @ R[2])))) > 10.0
    _check_crossing_view(V, F, R)
