"""The step a flight of stairs climbs where it turns, which no cut can carry.

Where a flight turns, the turning tread's edge runs on behind the tread in front to a notch
of the outline (the corner line of :func:`meschers_igl.inverse.occlusion.hidden_occlusions`).
The treads on either side of it are parallel and nothing the picture shows joins them, so a
lift that joins them anywhere makes them one plane there and loses the step; the rest of the
turn's cut reaches a hole, so the corner line cannot be cut to its notch without cutting the
figure apart.  :func:`meschers_igl.inverse.occlusion.hidden_steps` makes the faces in front
climb the step in place, as high as the next step: the riser the corner line lies off the
onward line parallel to it.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import metrics as met
from meschers_igl.inverse import models as mdl
from meschers_igl.inverse import picture as pic
from meschers_igl.inverse.occlusion import hidden_steps
from meschers_igl.topology import boundary_loops, edge_topology


def _strip():
    """A 3 x 2 grid of squares (x in [-1.5, 0], y in [-0.5, 0.5]) cut into triangles, the
    hidden line along y = 0 from (0, 0) to (-1.5, 0)."""
    X, Y = np.meshgrid([-1.5, -1.0, -0.5, 0.0], [-0.5, 0.0, 0.5])
    xy = np.stack([X.ravel(), Y.ravel()], axis=1)
    F = []
    for r in range(2):
        for c in range(3):
            a, b = r * 4 + c, r * 4 + c + 1
            F += [[a, b, b + 4], [a, b + 4, a + 4]]
    return xy, np.asarray(F, dtype=np.int64)


def test_corner_line_left_whole_climbs_the_riser_it_lies_off():
    xy, F = _strip()
    edges = edge_topology(F, len(xy))[0]
    on = np.abs(xy[:, 1]) < 1e-12
    line = np.nonzero(on[edges].all(axis=1))[0]
    # the corner line starts on a line k (x = 0) and runs along -x; the onward line parallel
    # to it ends on k too, 0.3 off it toward +y: the side behind is +y, the front -y
    hidden = [
        np.array([[0.0, 0.0], [-1.5, 0.0]]),
        np.array([[0.0, -1.0], [0.0, 1.0]]),
        np.array([[1.0, 0.3], [0.0, 0.3]]),
    ]
    n = np.array([0.0, 0.6, 0.8])  # the treads' normal: |n_xy x u| = 0.6
    normals = np.array([n, [1.0, 0.0, 0.0], [0.0, -0.8, 0.6]])
    region = np.zeros(len(F), dtype=np.int64)
    # planes 0.3 apart across the line on screen lie s = 0.3 / 0.6 apart along n and
    # s / n_z = 0.625 apart in depth at one screen point
    climbs = hidden_steps(xy, F, edges, np.zeros(0, np.int64), hidden, [line], normals, region)
    assert climbs is not None
    front = xy[F].mean(axis=1)[:, 1] < 0
    assert np.all(climbs[~front] == 0.0) and np.any(climbs[front] != 0.0)
    m = pic.lift(xy, F, np.tile(n, (len(F), 1)), None, climbs)
    z = m.hodge().z
    g = -n[:2] / n[2]  # the plane's depth gradient
    for v in np.nonzero(xy[:, 1] < 0)[0]:  # a vertex in front and the one on the line above it
        w = int(np.nonzero(on & (np.abs(xy[:, 0] - xy[v, 0]) < 1e-12))[0][0])
        assert z[v] - z[w] == pytest.approx(g @ (xy[v] - xy[w]) + 0.625, abs=1e-9)
    for v in np.nonzero(xy[:, 1] > 0)[0]:  # behind: the plane through the line
        w = int(np.nonzero(on & (np.abs(xy[:, 0] - xy[v, 0]) < 1e-12))[0][0])
        assert z[v] - z[w] == pytest.approx(g @ (xy[v] - xy[w]), abs=1e-9)


def test_no_parallel_line_no_climb():
    xy, F = _strip()
    edges = edge_topology(F, len(xy))[0]
    on = np.abs(xy[:, 1]) < 1e-12
    line = np.nonzero(on[edges].all(axis=1))[0]
    hidden = [np.array([[0.0, 0.0], [-1.5, 0.0]]), np.array([[0.0, -1.0], [0.0, 1.0]])]
    normals = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, -0.8, 0.6]])
    region = np.zeros(len(F), dtype=np.int64)
    empty = np.zeros(0, np.int64)
    assert hidden_steps(xy, F, edges, empty, hidden, [line], normals, region) is None
    # a line cut open all along carries its own step: nothing to climb in place
    hidden.append(np.array([[1.0, 0.3], [0.0, 0.3]]))
    assert hidden_steps(xy, F, edges, line, hidden, [line], normals, region) is None


#: Lights under which the stairs' three face orientations have three shades: three of
#: ``benchmarks/bench_inverse_real.py`` (seed 0, its lights 0, 2 and 4) and one of
#: ``test_inverse_stairs.py``.
LIGHTS = [
    (0.1888, -0.1984, 0.9618),
    (0.7415, 0.5385, 0.4002),
    (-0.8784, -0.0827, 0.4707),
    (0.6, -0.1, 1.0),
]


@pytest.mark.render
@pytest.mark.parametrize("light", LIGHTS, ids=["bench0", "bench2", "bench4", "front"])
def test_stairs_climb_the_step_where_the_flights_turn(light):
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_stairs()  # flights of 4, 4, 2, 2 seen from (1, 1, 2)
    light = np.asarray(light) / np.linalg.norm(light)
    image, scale = zbuffer_picture(model, 128, light=light, ambient=0.2)
    m, _, info = pic.mescher_from_picture(image, light, 0.2)
    gap = model.gap * scale
    # without the turn's step the lift climbs 11 of the 12 steps, less what the bent faces
    # around make up: 3.7-5.8% short of the depth gained per turn (2.2-4.0% over with it)
    assert abs(met.figure_period(m) - gap) < 0.05 * gap
    assert m.is_impossible() and len(boundary_loops(m.F)) >= 2
    assert np.abs(m.d12 @ np.asarray(m.zeta)).max() < 1e-10
