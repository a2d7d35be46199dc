"""The crossbar of a T-junction is an occlusion on both sides of the stem.

A bar seen ending against a bar in front: the front bar's edge passes in front of one face of
the bar behind, then, past the stem (the crease between the bar behind's two faces), of the
other.  When the bar in front runs along the third axis, that second stretch runs along the
crease of the front face and the face behind, and its direction alone cannot tell it from a
crease; the crossbar can (:func:`meschers_igl.inverse.occlusion.crossbar_occlusions`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from meschers_igl.inverse.occlusion import crossbar_occlusions

MAX_SIN = math.sin(math.radians(15.0))


def _frame():
    """Rows: the normals of an isometric view (``n_z > 0``, screen axes 120 degrees apart)."""
    s2, s3, s6 = math.sqrt(2.0), math.sqrt(3.0), math.sqrt(6.0)
    return np.array(
        [
            [2.0 / s6, 0.0, 1.0 / s3],
            [-1.0 / s6, 1.0 / s2, 1.0 / s3],
            [-1.0 / s6, -1.0 / s2, 1.0 / s3],
        ]
    )


def _unit(v):
    return np.asarray(v, dtype=np.float64) / np.linalg.norm(v)


def _crease(N, i, j):
    """Unit screen direction of the crease of regions ``i`` and ``j``."""
    return _unit(np.cross(N[i], N[j])[:2])


def _t_junction(turn_deg: float = 0.0, chain_len: float = 10.0, mirror: bool = False):
    """A junction at vertex 1 (the origin): the chain ``A | Q`` (regions 0 | 1, occluding)
    arrives from vertex 0, ``chain_len`` away, along the crease of 0 and 2 turned by
    ``turn_deg``; the boundary ``A | S`` (0 | 2) goes on along that crease in two edges
    (1 -> 2 -> 3); the stem ``Q | S`` (1 | 2) leaves along the screen axis of normal 0.
    ``Q``'s normal leans toward the chain (a convex stem); ``mirror`` turns the picture half
    round about the junction (the normals stay): a concave one."""
    N = _frame()
    u = _crease(N, 0, 2)
    t = math.radians(turn_deg)
    w = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]]) @ u
    stem = _unit(N[0, :2])
    xy = np.array([-chain_len * w, [0.0, 0.0], 5.0 * u, 10.0 * u, 6.0 * stem])
    if mirror:
        xy = -xy
    ends = np.array([[0, 1], [1, 2], [2, 3], [1, 4]])
    pairs = np.array([[0, 1], [0, 2], [2, 0], [2, 1]])  # either order
    occluding = np.array([True, False, False, False])
    return xy, ends, pairs, occluding, N


def test_a_crossbar_runs_on_past_the_stem_to_where_its_boundary_ends():
    xy, ends, pairs, occ, N = _t_junction()
    out = crossbar_occlusions(xy, ends, pairs, occ, N, MAX_SIN, 1.0)
    assert out.tolist() == [True, True, True, False]
    assert occ.tolist() == [True, False, False, False]  # the input is left alone


def test_a_boundary_at_an_angle_to_the_occlusion_stays_a_crease():
    # the occlusion arrives 30 degrees off the crease of 0 and 2: the boundary turns there,
    # which an edge of one face does not
    xy, ends, pairs, occ, N = _t_junction(turn_deg=30.0)
    out = crossbar_occlusions(xy, ends, pairs, occ, N, MAX_SIN, 1.0)
    assert out.tolist() == occ.tolist()


def test_no_stem_no_crossbar():
    xy, ends, pairs, occ, N = _t_junction()
    keep = [0, 1, 2]
    out = crossbar_occlusions(xy, ends[keep], pairs[keep], occ[keep], N, MAX_SIN, 1.0)
    assert out.tolist() == [True, False, False]


@pytest.mark.parametrize(("chain_len", "flagged"), [(3.0, False), (4.5, True)])
def test_a_chain_must_be_long_enough_to_show_its_direction(chain_len, flagged):
    # a pixel's uncertainty at its ends: the chain tells its direction within 15 degrees
    # from 1 / sin(15 deg) = 3.86 pixels on
    xy, ends, pairs, occ, N = _t_junction(chain_len=chain_len)
    out = crossbar_occlusions(xy, ends, pairs, occ, N, MAX_SIN, 1.0)
    assert out.tolist() == [True, flagged, flagged, False]


def test_a_concave_stem_is_left_alone():
    # Q's normal leans away from the chain: the faces behind meet in an inner corner, or the
    # stem is the silhouette of a wall standing on A's edge, whose foot is a crease
    xy, ends, pairs, occ, N = _t_junction()
    assert N[1, :2] @ (xy[1] - xy[0]) < 0  # convex as built
    xy, ends, pairs, occ, N = _t_junction(mirror=True)
    out = crossbar_occlusions(xy, ends, pairs, occ, N, MAX_SIN, 1.0)
    assert out.tolist() == occ.tolist()
