"""Smoothing an impossible figure keeps its crossings clean: the order follows sheet by sheet.

At the impossible cube's and the window's crossings one bar passes in front of another at equal
depth.  Smoothing xy (the study's times, 2e-4 and 1e-3 of the squared diagonal) slides faces of
each bar into overlaps they did not have; ordered by local depth (a tie there) those pairs were
drawn in either order, and the hidden bar showed through the front one in specks.
:func:`meschers_igl.smoothing.follow_sheets` spreads the old arcs over the new overlaps.

The measure is independent of the rule: the CPU painter's face map is cut into regions of
pixels whose faces lie within two vertex rings of each other (one sheet of surface seen in one
piece); a speck is a region of fewer than 64 pixels.  The unsmoothed figures have none, nor may
the smoothed ones; with :meth:`DepthOrder.follow` alone they do (the test can fail).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from meschers_igl.gallery import get_model
from meschers_igl.painter import visible_faces
from meschers_igl.smoothing import follow_sheets

SIZE = 320
SPECK = 64  # pixels: a region of the figure smaller than this is a speck


def speck_pixels(F: np.ndarray, face_map: np.ndarray) -> int:
    """Pixels in regions of one sheet smaller than SPECK (module docstring)."""
    n = F.shape[0]
    incidence = sp.csr_matrix((np.ones(F.size), (np.repeat(np.arange(n), 3), F.ravel())))
    ring = ((incidence @ incidence.T) > 0).astype(float)
    ring2 = ((ring @ ring) > 0).tocsr()
    H, W = face_map.shape
    index = np.arange(H * W).reshape(H, W)
    rows, cols = [], []
    for a, b, ia, ib in (
        (face_map[:, :-1], face_map[:, 1:], index[:, :-1], index[:, 1:]),
        (face_map[:-1], face_map[1:], index[:-1], index[1:]),
    ):
        both = (a >= 0) & (b >= 0)
        same = np.asarray(ring2[a[both], b[both]]).ravel() > 0
        rows.append(ia[both][same])
        cols.append(ib[both][same])
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = sp.coo_matrix((np.ones(r.size), (r, c)), shape=(H * W, H * W))
    _, label = csgraph.connected_components(graph, directed=False)
    figure = face_map.ravel() >= 0
    sizes = np.bincount(label[figure], minlength=H * W)
    return int((sizes[label[figure]] < SPECK).sum())


def _bounds(xy):
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    return (c[0] - h, c[0] + h, c[1] - h, c[1] + h)


@pytest.fixture(scope="module", params=["impossible_cube", "window"])
def figure(request):
    g = get_model(request.param)
    m, order = g.mescher.subdivide(2, order=g.order)  # the study's levels
    return request.param, m, order


def test_no_specks_at_the_crossings_after_smoothing_xy(figure):
    name, m, order = figure
    F = np.asarray(m.F)
    xy = np.asarray(m.xy)
    bounds = _bounds(xy)
    assert speck_pixels(F, visible_faces(m, order, size=SIZE, bounds=bounds)) == 0, name
    scale = float(np.linalg.norm(np.ptp(xy, axis=0)))
    plain = 0
    for factor in (2e-4, 1e-3):
        t = factor * scale * scale
        ms = m.smooth(t_xy=t, t_zeta=10 * t)
        followed = follow_sheets(order, ms)
        assert not followed.cycles(warn=False)
        specks = speck_pixels(F, visible_faces(ms, followed, size=SIZE, bounds=bounds))
        assert specks == 0, f"{name} t = {factor:g} s^2: {specks} speck pixels"
        plain += speck_pixels(F, visible_faces(ms, order.follow(ms), size=SIZE, bounds=bounds))
    assert plain > 0, f"{name}: the measure finds the specks of the local-depth rule"


def test_follow_sheets_keeps_every_carried_arc(figure):
    """Pairs that overlapped before and still do keep their arcs (as DepthOrder.follow); only
    new overlaps are ordered by spreading."""
    name, m, order = figure
    scale = float(np.linalg.norm(np.ptp(np.asarray(m.xy), axis=0)))
    ms = m.smooth(t_xy=1e-3 * scale * scale)
    n = m.n_faces
    followed = {tuple(a) for a in np.asarray(order.follow(ms).arcs).tolist()}
    old = {tuple(a) for a in np.asarray(order.arcs).tolist()}
    carried = followed & old
    sheets = {tuple(a) for a in np.asarray(follow_sheets(order, ms).arcs).tolist()}
    assert carried and carried <= sheets, name
    assert all(0 <= a < n and 0 <= b < n for a, b in sheets)
