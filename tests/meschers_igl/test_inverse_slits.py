"""Cuts along occlusions that stop a pixel or two short of a hole run on to it.

A slit (a piece of the cut touching no boundary) holds a depth step the surface cannot close
at its tips: going around the slit climbs part of the step the hole's loop should climb.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import metrics as met
from meschers_igl.inverse import models as mdl
from meschers_igl.inverse import picture as pic
from meschers_igl.inverse.cuts import _one_contact, _to_holes, cut_along
from meschers_igl.topology import boundary_loops, edge_topology


def _rings(n: int = 16, radii=(1.0, 1.25, 1.5, 1.75, 2.0)):
    """Rings of ``n`` vertices (vertex ``r n + i``: ring ``r``'s ``i``-th) joined by
    counter-clockwise triangles: an annulus whose hole is ring 0 and outline the last ring."""
    a = 2 * np.pi * np.arange(n) / n
    ring = np.c_[np.cos(a), np.sin(a)]
    xy = np.concatenate([r * ring for r in radii])
    i = np.arange(n)
    j = (i + 1) % n
    F = []
    for r in range(len(radii) - 1):
        lo, hi = r * n, (r + 1) * n
        F += [np.c_[lo + i, lo + j, hi + j], np.c_[lo + i, hi + j, hi + i]]
    return xy, np.concatenate(F)


def test_a_slit_short_of_a_hole_runs_on_to_it():
    n = 16
    xy, F = _rings(n)
    edges, _, _ = edge_topology(F, len(xy))
    key = {tuple(sorted(e)): k for k, e in enumerate(edges.tolist())}
    radial = [key[(n + r * n, n + (r + 1) * n)] for r in range(2)]  # ring 1 -> 2 -> 3
    slit = np.array(radial)
    allowed = slit
    # ring 1 is 0.25 from the hole and ring 3 0.25 from the outline: the path goes to the hole
    paths = _to_holes(F, xy, edges, slit, allowed, 0.3)
    assert len(paths) == 1
    assert sorted(edges[paths[0][0]].tolist()) == [0, n]
    cut = _one_contact(F, edges, slit, paths)
    xy2, F2 = cut_along(xy, F, edges, cut)
    loops = boundary_loops(F2)
    assert len(loops) == 2  # the slit opened onto the hole: outline and hole, no third loop
    xy3, F3 = cut_along(xy, F, edges, slit)
    assert len(boundary_loops(F3)) == 3  # left short, it is a loop of its own
    # out of reach, nothing
    assert _to_holes(F, xy, edges, slit, allowed, 0.2) == []
    # only tips of visible occlusions run on, not of hidden lines
    assert _to_holes(F, xy, edges, slit, np.zeros(0, dtype=np.int64), 0.3) == []
    # a lone interior edge opens nothing and is left alone
    lone = np.array([key[(n + 5, 2 * n + 5)]])
    assert _to_holes(F, xy, edges, lone, lone, 0.3) == []
    # a piece that touches the boundary already does not run on (it would cut the loop)
    touching = np.array([key[(5, n + 5)], key[(n + 5, 2 * n + 5)]])
    assert _to_holes(F, xy, edges, touching, touching, 0.3) == []


def test_the_impossible_cube_climbs_its_whole_step_around_the_hole():
    """The cube seen with both bar faces along the front bar at the ambient shade: the
    occlusion of the front bar over the back bar stops short of the hole's corner, 1.20 of
    the step 1.41 left around the hole."""
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.impossible_cube()
    light = np.array([-0.7583158229918717, -0.5636195521419911, 0.32755169522293953])
    ground = (0.55, 0.7, 0.9)
    image, scale = zbuffer_picture(model, 128, light=light, ambient=0.2, background=ground)
    m, _, _ = pic.mescher_from_picture(image, light, 0.2, background=ground)
    gap = model.gap * scale
    assert abs(met.figure_period(m) - gap) < 0.02 * gap
    periods, areas = met.boundary_loop_periods(m)
    # no slit keeps a step of its own
    slits = np.abs(areas) <= 1e-6 * np.abs(areas).max()
    assert np.abs(periods[slits]).max(initial=0.0) < 0.02 * gap
