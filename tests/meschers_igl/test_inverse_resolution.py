"""Region outlines fitted to a picture's pixels do not depend on its resolution or pixel phase.

A polygon whose edges run along the three screen directions of a box figure's edges (an
isometric view) is rasterised at pixel centres, at several resolutions and sub-pixel offsets;
:func:`meschers_igl.inverse.regions.region_polygons` with ``straighten="fit"`` must give back
its corners (sub-pixel accurate) and only its corners: a pixel step of a straight edge is never
a corner, so never a notch (reflex corner) that the hidden-line rules would start from.
(Douglas-Peucker, the default, keeps pixel steps as corners in 24 of these 24 pictures.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

from meschers_igl.inverse.regions import region_polygons  # noqa: E402

A = np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
B = np.array([math.cos(math.radians(150)), math.sin(math.radians(150))])
C = np.array([0.0, 1.0])


def _figure(turn_deg: float = 0.0) -> np.ndarray:
    """(7, 2) counter-clockwise corners, edges along A, C, B, -C, B, -C, -B (turned by
    ``turn_deg`` about the centre); one reflex corner (index 4), the rest convex."""
    P = [np.array([0.0, -0.6])]
    for step in (0.7 * A, 0.6 * C, 0.35 * B, -0.3 * C, 0.7 * B):
        P.append(P[-1] + step)
    P.append(np.array([P[-1][0], -0.6 + 0.5 * 0.35]))  # down, to meet -B from the start
    t = math.radians(turn_deg)
    return np.asarray(P) @ np.array([[math.cos(t), math.sin(t)], [-math.sin(t), math.cos(t)]])


def _labels(P: np.ndarray, res: int, shift) -> np.ndarray:
    """0 at pixel centres inside the polygon ``P + shift`` (pixels), -1 outside."""
    c = -1.0 + (2.0 * np.arange(res) + 1.0) / res
    X, Y = np.meshgrid(c, -c)
    poly = shapely.Polygon(P + np.asarray(shift) * (2.0 / res))
    return np.where(shapely.contains_xy(poly, X, Y), 0, -1)


def _corners(polys) -> np.ndarray:
    """The outline's corners (collinear points dropped), counter-clockwise."""
    out = shapely.union_all(polys)
    out = shapely.set_precision(out, 0.0)
    Q = np.asarray(shapely.orient_polygons(out).exterior.coords)[:-1]
    u = np.roll(Q, -1, axis=0) - Q
    w = Q - np.roll(Q, 1, axis=0)
    turn = np.abs(w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0])
    keep = turn > 1e-9 * np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1)
    return Q[keep]


def test_figure_is_what_the_test_says():
    P = _figure()
    assert shapely.Polygon(P).is_valid
    u = np.roll(P, -1, axis=0) - P
    w = P - np.roll(P, 1, axis=0)
    cross = w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0]
    assert np.nonzero(cross < 0)[0].tolist() == [4]
    d = u / np.linalg.norm(u, axis=1, keepdims=True)
    assert np.all(np.abs(np.stack([d @ A, d @ B, d @ C], 1)).max(axis=1) > 1 - 1e-12)


# an edge along an image axis is known to half a pixel only (any line between two columns of
# pixel centres draws the same pixels), which moves its corner with a 30-degree edge up to
# 0.5 / cos 30 = 0.58 pixels along that edge; a slanted edge is known to a fraction
@pytest.mark.parametrize(("turn", "within_px"), [(0.0, 0.65), (7.0, 0.3)])
@pytest.mark.parametrize("res", [128, 256, 512])
@pytest.mark.parametrize("shift", [(0.0, 0.0), (0.25, 0.5), (0.5, 0.13), (0.77, 0.41)])
def test_outline_corners_at_subpixel_accuracy(turn, within_px, res, shift):
    P = _figure(turn) + np.asarray(shift) * (2.0 / res)
    polys, region, _ = region_polygons(_labels(_figure(turn), res, shift), straighten="fit")
    assert set(region.tolist()) == {0}
    Q = _corners(polys)
    px = 2.0 / res
    # exactly the seven corners: no pixel step of an edge became one
    assert len(Q) == len(P)
    d = np.linalg.norm(Q[:, None] - P[None], axis=2) / px
    assert d.min(axis=0).max() < within_px
    u = np.roll(Q, -1, axis=0) - Q
    w = Q - np.roll(Q, 1, axis=0)
    reflex = (w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0]) < 0
    assert reflex.sum() == 1
    assert np.linalg.norm(Q[reflex][0] - P[4]) / px < within_px


def test_unknown_straightening_is_refused():
    from meschers_igl import MescherError

    with pytest.raises(MescherError, match="straighten"):
        region_polygons(_labels(_figure(), 64, (0.0, 0.0)), straighten="hough")
