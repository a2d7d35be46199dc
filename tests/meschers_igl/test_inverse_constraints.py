"""Constraints handed to Triangle form a planar straight-line graph (``regions.node_constraints``).

``data/triangle_t_junction.npz`` holds the boundaries traced from a 128-pixel picture of the
project's own impossible cube (one light, the shared shade split without its majority pass): one
vertex lies 1.3e-15 pixels off a segment that does not end there.  Triangle's quality refinement
(``pq25``) crashes the process on it (a segfault: measured with triangle 20250106); noded, the
same boundaries triangulate.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import shapely

from meschers_igl import MescherError
from meschers_igl.inverse.regions import node_constraints

DATA = Path(__file__).parent / "data" / "triangle_t_junction.npz"
PIXEL = 2.0 / 128


def _segments(V, S):
    return shapely.linestrings(np.stack([V[S[:, 0]], V[S[:, 1]]], axis=1))


def _foreign_touches(V, S, distance):
    """Pairs (vertex, segment) closer than ``distance`` where the segment does not end at it."""
    tree = shapely.STRtree(_segments(V, S))
    vi, si = tree.query(shapely.points(V), predicate="dwithin", distance=distance)
    own = (S[si, 0] == vi) | (S[si, 1] == vi)
    return int((~own).sum())


def _crossings(V, S):
    lines = _segments(V, S)
    a, b = shapely.STRtree(lines).query(lines, predicate="crosses")
    return int((a < b).sum())


def _planar(V, S, grid):
    assert _foreign_touches(V, S, 0.25 * grid) == 0
    assert _crossings(V, S) == 0
    assert np.all(S[:, 0] < S[:, 1]) and len(np.unique(S, axis=0)) == len(S)
    assert len(np.unique(np.round(V / grid), axis=0)) == len(V)


def test_t_junctions_crossings_and_near_vertices_are_noded_by_hand():
    grid = 1e-9
    chains = [
        [(0.0, 0.0), (2.0, 0.0)],
        [(1.0, 1e-15), (1.0, 1.0)],  # ends a rounding error above the first segment
        [(0.3, 0.1), (0.7, -1e-12), (0.9, 0.5)],  # touches it at 0.7
        [(1.5, -1.0), (1.5, 1.0)],  # crosses it at 1.5
        [(2.0, 3e-13), (3.0, 0.0)],  # starts at its end, off by less than the grid
    ]
    V, S = node_constraints(chains, grid)
    on_axis = np.sort(V[np.abs(V[:, 1]) < grid, 0])
    np.testing.assert_allclose(on_axis, [0.0, 0.7, 1.0, 1.5, 2.0, 3.0], atol=grid)
    # the x axis from 0 to 3 is now five segments, one per gap between those points
    ax = np.abs(V[S, 1]).max(axis=1) < grid
    assert ax.sum() == 5
    _planar(V, S, grid)
    # every input point is a vertex, within the grid
    pts = np.concatenate([np.asarray(c) for c in chains])
    d = np.linalg.norm(pts[:, None, :] - V[None, :, :], axis=2).min(axis=1)
    assert d.max() <= grid


def test_noding_covers_the_input_to_within_the_grid_on_random_polylines():
    rng = np.random.default_rng(7)
    grid = 1e-6
    chains = [rng.random((rng.integers(2, 6), 2)) for _ in range(12)]
    V, S = node_constraints(chains, grid)
    _planar(V, S, grid)
    before = shapely.multilinestrings([shapely.linestrings(c) for c in chains])
    after = shapely.multilinestrings(_segments(V, S))
    assert shapely.hausdorff_distance(before, after) <= 2 * grid
    assert abs(before.length - after.length) <= 1e-9 * before.length + 4 * grid * len(S)


def test_the_traced_cube_boundaries_are_noded_and_then_triangulate(tmp_path):
    pytest.importorskip("triangle")
    d = np.load(DATA)
    V0, S0 = d["vertices"], d["segments"]
    assert _foreign_touches(V0, S0, 0.05 * PIXEL) == 1  # the T-junction Triangle trips on
    V, S = node_constraints([np.stack([V0[a], V0[b]]) for a, b in S0], 1e-3 * PIXEL)
    _planar(V, S, 1e-3 * PIXEL)
    assert len(S) == len(S0) + 1  # the segment is split at the vertex, nothing else changes
    script = textwrap.dedent(
        """
        import sys, numpy as np, triangle
        d = np.load(sys.argv[1])
        t = triangle.triangulate(
            {"vertices": d["V"], "segments": d["S"], "holes": d["holes"]}, "pq25a2.930e-03"
        )
        print(len(t["triangles"]))
        """
    )
    path = tmp_path / "noded.npz"
    np.savez(path, V=V, S=S, holes=d["holes"])
    # in a child process: should Triangle still crash, the test fails instead of the run
    run = subprocess.run([sys.executable, "-c", script, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    assert int(run.stdout.strip()) > 0


def test_a_grid_that_is_not_positive_is_refused():
    with pytest.raises(MescherError, match="grid: expected a positive number"):
        node_constraints([[(0.0, 0.0), (1.0, 0.0)]], 0.0)
    V, S = node_constraints([[(0.0, 0.0)]], 1e-9)
    assert V.shape == (0, 2) and S.shape == (0, 2)


def test_a_picture_whose_boundaries_crashed_triangle_becomes_a_mescher(tmp_path):
    """``data/cube_picture_light5.npz``: the z-buffer picture of the project's impossible cube
    at 128 pixels under one light (two shades).  Without the majority pass of the shared shade
    its traced boundaries hold the T-junction above and the whole process died in Triangle;
    ``mescher_from_picture`` now nodes them first.  Run in a child process, so that a crash
    fails this test rather than the test run."""
    pytest.importorskip("triangle")
    script = textwrap.dedent(
        """
        import sys, numpy as np
        from meschers_igl.inverse import picture as pic
        split = pic.split_shared_shade
        pic.split_shared_shade = lambda *a, **k: split(*a, **{**k, "smooth": 0})
        d = np.load(sys.argv[1])
        light = d["light"] / np.linalg.norm(d["light"])
        m, region, info = pic.mescher_from_picture(
            d["image"], light, 0.2, background=(0.55, 0.7, 0.9)
        )
        print(m.n_faces, len(np.unique(region)))
        """
    )
    data = Path(__file__).parent / "data" / "cube_picture_light5.npz"
    run = subprocess.run([sys.executable, "-c", script, str(data)], capture_output=True, text=True)
    assert run.returncode == 0, f"status {run.returncode}: {run.stderr[-2000:]}"
    faces, regions = map(int, run.stdout.split())
    assert faces > 100 and regions >= 3
