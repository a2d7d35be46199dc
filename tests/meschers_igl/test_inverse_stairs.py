"""Penrose stairs from their picture: the hidden step edges where a flight turns, and the climb.

Pictures are z-buffered by PyVista (``meschers.inverse_cli.zbuffer_picture``) from real 3D
models: the box stairs of :mod:`meschers_igl.inverse.models` and the gallery's ribbon of
steps (:func:`meschers_igl.gallery.penrose.penrose_stairs`), so the code under test never
renders its own target.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import metrics as met
from meschers_igl.inverse import models as mdl
from meschers_igl.inverse import picture as pic
from meschers_igl.inverse.cuts import _one_contact, cut_along
from meschers_igl.topology import boundary_loops, edge_topology

LIGHT = (0.6, -0.1, 1.0)


def _gallery_stairs(**kw) -> mdl.BoxModel:
    from meschers_igl.gallery import penrose

    c = penrose.penrose_stairs(**kw)
    v = np.asarray(c.view, dtype=float)
    v /= np.linalg.norm(v)
    up = np.asarray(c.up, dtype=float)
    up -= (up @ v) * v
    return mdl.BoxModel(
        "gallery stairs",
        np.asarray(c.V, float),
        np.asarray(c.F),
        v,
        up / np.linalg.norm(up),
        float(c.period),
    )


def _ends_on_another(lines, tol):
    """Indices of the lines whose end lies on another line (inside the figure)."""
    out = []
    for k, s in enumerate(lines):
        for j, t in enumerate(lines):
            d = t[1] - t[0]
            u = float(np.clip((s[1] - t[0]) @ d / (d @ d), 0.0, 1.0))
            if j != k and np.linalg.norm(t[0] + u * d - s[1]) < tol:
                out.append(k)
    return out


def _picture_mescher(model, complete=True):
    from meschers.inverse_cli import zbuffer_picture

    image, scale = zbuffer_picture(model, 128, light=LIGHT, ambient=0.2)
    m, _, info = pic.mescher_from_picture(image, LIGHT, 0.2, complete=complete)
    return m, info, model.gap * scale


@pytest.mark.render
def test_stairs_picture_climbs_its_period_where_the_flights_turn():
    pytest.importorskip("pyvista")
    model = mdl.penrose_stairs()  # flights of 4, 4, 2, 2 seen from (1, 1, 2)
    m, info, gap = _picture_mescher(model)
    px = 2.0 / 128
    lines = info["hidden_lines"]
    # where a flight turns, a step edge goes on behind the next tread and meets the next
    # tread's edge; the tread in front of both turns at its corner on to a notch: three
    # lines, two ending on the third, beside the six of the straight flights
    assert len(lines) == 9 and len(_ends_on_another(lines, 1e-6 * px)) >= 2
    # with every step cut, the lift climbs the depth gained per turn: 1.32 for 1.39 (the
    # flight's turn left whole, 1.15); the annulus is kept and zeta is closed
    assert abs(met.figure_period(m) - gap) < 0.07 * gap
    assert m.is_impossible() and len(boundary_loops(m.F)) >= 2
    assert np.abs(m.d12 @ np.asarray(m.zeta)).max() < 1e-10


@pytest.mark.render
@pytest.mark.parametrize(
    "make",
    [
        lambda: mdl.penrose_stairs((4, 4, 2, 2), 1.0, 0.6, 1.5),
        lambda: _gallery_stairs(long_side=4, short_side=2, steepness=2.0, thickness=1.0),
    ],
    ids=["boxes-steep-1.5", "gallery-4-2"],
)
def test_stairs_made_otherwise_keep_their_loop_and_come_nearer(make):
    pytest.importorskip("pyvista")
    model = make()
    m, info, gap = _picture_mescher(model)
    m0, _, _ = _picture_mescher(model, complete=False)
    # the hidden lines never cut the ring open (each piece of the cut touches the boundary
    # once): the loop that carries the period stays, and the period comes nearer the climb
    assert info["hidden_lines"] and m.is_impossible() and len(boundary_loops(m.F)) >= 2
    assert abs(met.figure_period(m) - gap) < 0.8 * abs(met.figure_period(m0) - gap)


def _annulus(n: int = 12):
    """Three rings of ``n`` vertices (radii 1, 1.5, 2: inner, middle, outer) joined by
    counter-clockwise triangles; vertex ``r n + i`` is ring ``r``'s ``i``-th."""
    a = 2 * np.pi * np.arange(n) / n
    ring = np.c_[np.cos(a), np.sin(a)]
    xy = np.concatenate([ring, 1.5 * ring, 2.0 * ring])
    i = np.arange(n)
    j = (i + 1) % n
    F = []
    for r in (0, 1):
        lo, hi = r * n, (r + 1) * n
        F += [np.c_[lo + i, lo + j, hi + j], np.c_[lo + i, hi + j, hi + i]]
    return xy, np.concatenate(F)


def test_a_cut_touches_the_boundary_once():
    n = 12
    xy, F = _annulus(n)
    edges, _, _ = edge_topology(F, len(xy))
    key = {tuple(sorted(e)): k for k, e in enumerate(edges.tolist())}
    seen = np.array([key[(0, n)]])  # a visible occlusion from the hole to the middle ring
    hidden = np.array([key[(n, 2 * n)]])  # its hidden part, on to the outline
    apart = np.array([key[(n + 6, 2 * n + 6)]])  # a line of its own, elsewhere

    # both together would cut the annulus open from the hole to the outline: a disk, the loop
    # that carries the period gone
    xy2, F2 = cut_along(xy, F, edges, np.concatenate([seen, hidden]))
    assert len(boundary_loops(F2)) == 1
    # the hidden line that would touch the boundary a second time stops one edge short
    cut = _one_contact(F, edges, seen, [hidden])
    assert cut.tolist() == seen.tolist()
    # a line on its own keeps its one contact, and so does one apart from the visible cut
    assert _one_contact(F, edges, np.zeros(0, dtype=np.int64), [hidden]).tolist() == hidden.tolist()
    cut = _one_contact(F, edges, seen, [apart])
    assert sorted(cut.tolist()) == sorted(np.concatenate([seen, apart]).tolist())
    # cut there, the annulus stays an annulus (its outline and hole, slits opening onto them)
    xy3, F3 = cut_along(xy, F, edges, cut)
    loops = boundary_loops(F3)
    assert len(loops) == 2
    assert len(xy3) == len(xy) + 2  # each slit splits its vertex on the boundary in two
