"""The triangulation of a picture's pieces covers them: gaps of rounding are not holes."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import picture as pic

shapely = pytest.importorskip("shapely")
pytest.importorskip("triangle")


def _area(xy, F) -> float:
    P = xy[F]
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    return float(0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum())


@pytest.mark.parametrize("width", [1e-9, 1e-7, 1e-5])
def test_a_sliver_interior_is_not_a_hole(width):
    """A square with an interior sliver far under a pixel (the gap two pieces split by a
    line leave): the triangles cover the square, as the pieces do."""
    pixel = 0.1
    sliver = [(1.0, 1.0), (3.0, 1.0), (2.0, 1.0 + width)]
    P = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], holes=[sliver])
    lines = [shapely.LineString(np.asarray(P.exterior.coords))]
    xy, F, region = pic.triangulate_regions([P], [0], lines, pixel)
    assert abs(_area(xy, F) - 16.0) < 1e-6
    assert np.all(region == 0)


def test_a_hole_of_pixels_stays_a_hole():
    pixel = 0.1
    hole = [(1.0, 1.0), (1.3, 1.0), (1.3, 1.3), (1.0, 1.3)]  # 9 pixels
    P = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], holes=[hole])
    lines = [shapely.LineString(np.asarray(r.coords)) for r in (P.exterior, P.interiors[0])]
    xy, F, _ = pic.triangulate_regions([P], [0], lines, pixel)
    assert abs(_area(xy, F) - (16.0 - 0.09)) < 1e-6


def test_a_gap_between_two_pieces_is_meshed_whole():
    """Two pieces whose shared side a rounding left a sliver apart (a wedge far under a pixel
    between them, its sides constraints of the triangulation): the triangles in the sliver
    lie in no piece; they take the nearest piece's region, so the mesh has no pinhole (a
    boundary loop of its own, which the cuts would take for a hole of the figure)."""
    from meschers_igl.topology import boundary_loops

    pixel = 0.1
    for w in (1e-4, 2e-3):  # a thousandth and a fiftieth of a pixel wide, under half a pixel
        A = shapely.Polygon([(0, 0), (2, 0), (2, 4), (0, 4)])
        B = shapely.Polygon([(2, 0), (4, 0), (4, 4), (2, 4), (2, 3), (2 + w, 2), (2, 1)])
        lines = [shapely.LineString(np.asarray(p.exterior.coords)) for p in (A, B)]
        xy, F, region = pic.triangulate_regions([A, B], [0, 1], lines, pixel)
        assert abs(_area(xy, F) - 16.0) < 1e-9
        assert len(boundary_loops(F)) == 1
        # each triangle lies within one piece or in the sliver beside its own piece
        c = xy[F].mean(axis=1)
        assert np.all(region[c[:, 0] < 2.0 - 1e-9] == 0) and np.all(region[c[:, 0] > 2.0 + w] == 1)
