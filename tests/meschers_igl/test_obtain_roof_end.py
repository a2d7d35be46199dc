"""A bar broken behind an occluder whose ends are not square caps -- pointed (one corner of
the end pushed out: a two-triangle roof folded along the diagonal, as modellers bevel bar ends),
notched (the same cut on both pieces) or bevelled (one tilted plane, mirrored on the other
piece) -- is completed by a viewer just as a bar with square caps: the ends lie in the gap the
occluder hides.  The closed impossible-cube frame converts with its built depth gap as the
period whatever the ends' shape.
"""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest
from visible_models import ISO_VIEW, hidden_gap_cube, triangulate

from meschers_igl.obtain import model_to_mescher, weld
from meschers_igl.obtain.junctions import find_caps, planar_patches, pointed_end_pairs, pointed_ends

L, T, HOLE = 6.0, 1.0, 0.6
UP = (-1.0, -1.0, 2.0)
SHAPES = ["pointed", "notch", "bevel", "mixed"]


def shaped_cube(shape: str, h: float = 0.2, occluder: bool = True):
    """:func:`hidden_gap_cube` with the broken y bar's two square caps reshaped by moving
    corners along y by ``h`` (less than half the hole, so the ends stay apart on screen):
    ``pointed`` one corner out of each end (mirror images), ``notch`` the same corner by the
    same vector on both (one folded cut, the pieces pulled apart), ``bevel`` two adjacent
    corners out of each end (one tilted plane each, mirror images), ``mixed`` the far piece
    pointed and the near one square.  Every side face stays
    planar (corners move along the bar).  Without the ``occluder`` (the crossing bar, the
    last box of :func:`hidden_gap_cube`) the shaped ends are seen.  Returns (V, F, gap)."""
    V, P, gap = hidden_gap_cube(L, T, HOLE)
    V, polys = V.copy(), [list(p) for p in P][: None if occluder else -6]
    caps = {}
    for k, p in enumerate(polys):  # the two caps, found by their coordinates
        for y, out in ((L / 2 + HOLE / 2, -1.0), (1.5 * L - HOLE / 2, 1.0)):
            if len(p) == 4 and np.allclose(V[p, 1], y):
                caps[out] = k
    assert len(caps) == 2
    for out, k in caps.items():
        if shape == "mixed" and out > 0:
            continue
        p = polys[k]
        rel = V[p] - V[p].mean(axis=0)
        c = int(np.argmax(rel[:, 0] + 2.0 * rel[:, 2]))  # the (+x, +z) corner of the section
        move = out * h if shape != "notch" or out < 0 else -out * h
        corners = [c] if shape != "bevel" else [c, (c + 1) % 4]
        for j in corners:
            V[p[j], 1] += move
        polys[k] = p[c:] + p[:c]  # fanned from the moved corner: the fold runs through it
    return V, triangulate(polys), gap


def _convert(V, F):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model_to_mescher(V, F, view=ISO_VIEW, up=UP)


@pytest.mark.parametrize("shape", SHAPES)
def test_a_cube_broken_with_shaped_ends_has_its_gap_as_period(shape):
    """The whole frame is opened at the two shaped ends and bridged: one hidden gap, the
    period the built gap L sqrt(3) (to rounding), impossible through zeta, and the render's
    faces are the model's (the bridge lies behind the crossing bar)."""
    V, F, gap = shaped_cube(shape)
    m, order, report = _convert(V, F)
    assert report.route == "closed"
    assert [j.kind for j in report.junctions] == ["hidden gap"]
    assert np.isclose(report.junctions[0].depth_gap, gap, rtol=1e-9)
    p = np.abs(np.asarray(m.periods()))
    assert np.isclose(p.max(), gap, rtol=1e-9)
    assert m.is_impossible(order=order).kind == "zeta"


@pytest.mark.parametrize("shape", SHAPES)
def test_shaped_ends_pair_by_their_cross_section(shape):
    """One pair (both orientations) of ends facing opposite ways along y; the correspondence
    takes each loop vertex to the one on the same side edge: their offset across the bar is
    one translation (the frame's L along x and z), and it is a permutation."""
    V, F, _ = shaped_cube(shape)
    V, F, _ = weld(V, F, 1e-9)
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    patch = planar_patches(V, F, TT, 1e-9)
    caps = find_caps(V, F, TT, patch, 1e-9)
    pairs = pointed_end_pairs(V, F, TT, patch, 1e-9, caps=caps)
    assert len(pairs) == 2
    for be in pairs:
        assert abs(be.d[1]) == 1.0 and be.first.normal @ be.second.normal == -1.0
        assert not (be.first.flat and be.second.flat)
        A, B = V[be.first.loop], V[be.second.loop[be.match]]
        off = (B - A)[:, [0, 2]]  # across the bar
        assert np.allclose(off, off[0], atol=1e-12)
        assert np.allclose(np.abs(off[0]), L, atol=1e-12)
        assert sorted(be.match.tolist()) == list(range(be.first.loop.size))


def test_square_caps_pair_as_caps_only():
    """With two square caps no shaped end is found, and no pair is made here (the caps' own
    pairing in :func:`bar_end_pairs` finds them)."""
    V, P, _ = hidden_gap_cube(L, T, HOLE)
    V, F, _ = weld(V, triangulate(P), 1e-9)
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    patch = planar_patches(V, F, TT, 1e-9)
    assert pointed_ends(V, F, TT, patch) == []
    caps = find_caps(V, F, TT, patch, 1e-9)
    assert pointed_end_pairs(V, F, TT, patch, 1e-9, caps=caps) == []


@pytest.mark.parametrize("shape", SHAPES)
def test_shaped_ends_in_sight_are_a_broken_bar(shape):
    """Without the crossing bar the shaped ends are seen: the bar visibly stops, nothing is
    bridged and the frame is possible."""
    V, F, _ = shaped_cube(shape, occluder=False)
    m, order, report = _convert(V, F)
    assert not [j for j in report.junctions if j.kind in ("hidden gap", "crossing")]
    assert not m.is_impossible(order=order)
    assert np.all(np.asarray(m.periods()) == 0.0)


@pytest.mark.parametrize("shape", SHAPES)
def test_the_automatic_view_lines_shaped_ends_up(shape):
    """``view="auto"`` finds a view within half a degree of the diagonal (exactly it for the
    mirror-image ends; shapes that move the gap's middle along the bar move the view that
    centres the crossing bar on it) from which the pieces line up behind the crossing bar; the
    period is their offset across the bar, L sqrt(2) along x and z, over the view's share
    across the bar."""
    V, F, _ = shaped_cube(shape)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m, order, report = model_to_mescher(V, F, view="auto")
    v = report.view
    assert abs(v @ ISO_VIEW) >= np.cos(np.radians(0.5))
    if shape in ("pointed", "bevel"):
        assert np.isclose(abs(v @ ISO_VIEW), 1.0, atol=1e-12)
    expected = L * np.sqrt(2.0) / np.linalg.norm(v[[0, 2]])
    assert np.isclose(np.abs(np.asarray(m.periods())).max(), expected, rtol=1e-9)
    assert m.is_impossible(order=order).kind == "zeta"


def _bevelled_pieces(h: float, tilt: int):
    """Two square bars along x (x in [0, 2.5] and [3.5, 6], y and z in [0, 1]) whose facing
    ends are bevelled in mirror: the end plane leans by ``h`` per unit along axis ``tilt``
    (2: z, a plane containing y; 1: y), and a bar along z lying behind their gap (y in [4, 5])."""
    from visible_models import box_block, convex_block, separate_blocks

    e = np.zeros(3)
    e[tilt] = h
    side = [[0, -1, 0, 0], [0, 1, 0, -1], [0, 0, -1, 0], [0, 0, 1, -1]]
    a = convex_block(
        np.array([[-1, 0, 0, 0], *side, [1, -e[1], -e[2], -2.5]], float), np.array([1, 0.5, 0.5])
    )
    b = convex_block(
        np.array([[1, 0, 0, -6], *side, [-1, -e[1], -e[2], 3.5]], float), np.array([5, 0.5, 0.5])
    )
    V, polys = separate_blocks([a, b, box_block([2.5, 4, -3], [3.5, 5, 4])])
    return V, triangulate(polys)


@pytest.mark.parametrize("tilt, kinds", [(2, ["crossing"]), (1, [])])
def test_bevelled_ends_seen_edge_on_are_a_crossing(tilt, kinds):
    """Seen along -y, ends bevelled in planes containing the view show no end face: the bar is
    completed behind the bar in its gap (a crossing); bevelled towards the viewer, the end
    faces are seen and the bar visibly stops."""
    V, F = _bevelled_pieces(0.2, tilt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, _, report = model_to_mescher(V, F, view=(0.0, -1.0, 0.0), up=(0.0, 0.0, 1.0))
    assert [j.kind for j in report.junctions if j.kind == "crossing"] == kinds
