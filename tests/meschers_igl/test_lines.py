"""Line drawings: exact lines on hand-sized figures, and pixel agreement with the painter."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from meschers_igl import DepthOrder, Mescher, MescherError, shapes
from meschers_igl.line_pixels import visible_face_edges
from meschers_igl.lines import KINDS, crease_edges, line_drawing
from meschers_igl.painter import visible_faces


def _squares():
    """Two unit-facing squares: A = [0,2]^2 at z=0 behind B = [1,3]^2 at z=1."""
    sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=float)
    V = np.concatenate(
        [np.c_[sq, np.zeros(4)], np.c_[sq + 1.0, np.ones(4)]]
    )  # z toward the viewer: B in front
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    m = Mescher.from_mesh(V, F)
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    return m, order


def _box(view=(1.0, 1.0, 1.0)):
    """A unit cube (quads split along a diagonal) seen from ``view``."""
    V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    F = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    # orient outward
    c = V[F].mean(axis=1) - 0.5
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    flip = (n * c).sum(axis=1) < 0
    F[flip] = F[flip][:, ::-1]
    m = Mescher.from_mesh(V, F, view=view, up=(0, 0, 1))
    from meschers_igl.cutmesh import camera_coordinates

    Zc = camera_coordinates(V, view, (0, 0, 1))[:, 2][F]
    return m, DepthOrder.from_embedding(m, Zc)


def _has_point(ld, p, tol=1e-12):
    return bool(np.any(np.linalg.norm(ld.points - np.asarray(p), axis=1) <= tol))


def test_overlapping_squares_exact_lengths_and_t_junctions():
    m, order = _squares()
    ld = line_drawing(m, order, hidden=True)
    # B's whole boundary (8) and A's boundary outside B (6) are seen
    assert ld.length(visible=True) == pytest.approx(14.0, abs=1e-12)
    # where B passes over A: B's left and bottom edges inside A are occlusion lines
    assert ld.length("occlusion") == pytest.approx(2.0, abs=1e-12)
    assert ld.length("outline") == pytest.approx(12.0, abs=1e-12)
    assert ld.length("crease") == 0.0
    # A's edges behind B (top x in [1,2], right y in [1,2]) are hidden
    assert ld.length(visible=False) == pytest.approx(2.0, abs=1e-12)
    # A's lines stop exactly where they pass behind B
    assert _has_point(ld, (1.0, 2.0)) and _has_point(ld, (2.0, 1.0))
    # the figure's outline is one closed polyline of its 8 corners: A's and B's outline pieces
    # joined at the T-junctions, straight points (the quads' corners on it) dropped
    out = ld.polylines("outline")
    assert len(out) == 1 and ld.closed[ld.kind == 0].all() and len(out[0]) == 9
    corners = {(0, 0), (2, 0), (2, 1), (3, 1), (3, 3), (1, 3), (1, 2), (0, 2)}
    assert {tuple(p) for p in out[0].tolist()} == corners


def _has_point_in(P, p):
    return bool(np.any(np.linalg.norm(P - np.asarray(p), axis=1) <= 1e-12))


def test_reversed_order_swaps_which_square_is_whole():
    m, order = _squares()
    back = DepthOrder(m.n_faces, order.arcs[:, ::-1])
    ld = line_drawing(m, back)
    # now A is whole (8) and B loses its corner inside A (2)
    assert ld.length() == pytest.approx(14.0, abs=1e-12)
    assert _has_point(ld, (1.0, 2.0)) and _has_point(ld, (2.0, 1.0))
    hidden = line_drawing(m, back, hidden=True)
    seg = hidden.segments(visible=False)
    # the hidden part is B's corner: x = 1 for y in [1, 2] and y = 1 for x in [1, 2]
    assert np.all(np.isclose(seg[..., 0], 1.0) | np.isclose(seg[..., 1], 1.0))


def test_cube_creases_outline_and_hidden_diagonals():
    m, order = _box()
    angle, crease = crease_edges(m)
    # box edges at 90 degrees, quad diagonals flat
    assert np.allclose(angle[crease], 90.0) and crease.sum() == 12
    assert np.allclose(angle[~crease], 0.0)
    ld = line_drawing(m, order)
    edge = np.sqrt(2.0 / 3.0)  # a unit edge seen along the diagonal
    assert ld.length("outline") == pytest.approx(6 * edge, rel=1e-9)
    assert ld.length("crease") == pytest.approx(3 * edge, rel=1e-9)
    assert ld.length("occlusion") == pytest.approx(0.0, abs=1e-12)
    # the hidden corner projects onto the centre; its three creases lie under the front quads'
    # diagonals, covered on both sides, so they stay hidden
    assert ld.length() == pytest.approx(9 * edge, rel=1e-9)
    # one closed hexagon (6 corners) and a Y of three creases meeting at the centre
    assert ld.closed[ld.kind == 0].all() and len(ld.polylines("outline")[0]) == 7
    assert len(ld.polylines("crease")) == 3
    # no crease above 90 degrees: only the outline remains
    assert line_drawing(m, order, crease_angle=95).length("crease") == 0.0


def _drawn_mask(ld, bounds, shape, step=0.2):
    """Pixels the drawing's visible segments pass through (dense samples, no rasterizer)."""
    H, W = shape
    x0, x1, y0, y1 = bounds
    S = ld.segments()
    if len(S) == 0:
        return np.zeros(shape, dtype=bool)
    px = (x1 - x0) / W
    n = np.maximum(np.ceil(np.linalg.norm(S[:, 1] - S[:, 0], axis=1) / (step * px)), 1).astype(int)
    t = np.concatenate([np.linspace(0, 1, k + 1) for k in n])
    s = np.repeat(np.arange(len(S)), n + 1)
    P = S[s, 0] + t[:, None] * (S[s, 1] - S[s, 0])
    col = np.clip(((P[:, 0] - x0) / px).astype(int), 0, W - 1)
    row = np.clip(((y1 - P[:, 1]) / px).astype(int), 0, H - 1)
    out = np.zeros(shape, dtype=bool)
    out[row, col] = True
    return out


def pixel_scores(m, order, size=384, tol=1.5, **kw):
    """(recall, precision): painter's line pixels near a drawn line, drawn pixels near one."""
    ld = line_drawing(m, order, **kw)
    lo, hi = np.asarray(m.xy).min(0), np.asarray(m.xy).max(0)
    pad = 0.05 * (hi - lo).max()
    c, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max() + pad
    bounds = (c[0] - half, c[0] + half, c[1] - half, c[1] + half)
    faces = visible_faces(m, order, size=size, bounds=bounds)
    gt = visible_face_edges(faces, m, bounds, crease_angle=kw.get("crease_angle", 30.0))
    drawn = _drawn_mask(ld, bounds, faces.shape)
    d_drawn = ndimage.distance_transform_edt(~drawn)
    d_gt = ndimage.distance_transform_edt(~gt)
    return float(np.mean(d_drawn[gt] <= tol)), float(np.mean(d_gt[drawn] <= tol))


@pytest.mark.parametrize(
    "name",
    ["penrose_triangle", "impossible_cube", "penrose_stairs", "reutersvard_triangle", "window"],
)
def test_gallery_lines_match_the_painters_picture(name):
    from meschers_igl.gallery import get_model

    g = get_model(name)
    recall, precision = pixel_scores(g.mescher, g.order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


def test_impossibagel_interpolated_contours_match_the_picture():
    from meschers_igl.gallery import get_model

    g = get_model("impossibagel")
    recall, precision = pixel_scores(g.mescher, g.order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


def test_sphere_contour_is_the_equator_and_smooth():
    V, F = shapes.icosphere(3)
    V = V @ shapes.random_rotation(3).T  # no vertex on the equator
    m = Mescher.from_mesh(V, F)
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    ld = line_drawing(m, order, contours="interpolated")
    assert ld.n_lines == 1 and ld.closed[0] and KINDS[ld.kind[0]] == "outline"
    r = np.linalg.norm(ld.points, axis=1)
    # interpolated between vertices of the unit sphere: within the chord sag of its edges
    assert np.all(np.abs(r - 1.0) < 0.01)
    # mesh contours zig-zag along edges, interpolated ones do not: fewer, straighter turns
    mesh = line_drawing(m, order, contours="mesh")
    assert mesh.length() > ld.length()


def _max_turn(P):
    a, b = P[1:-1] - P[:-2], P[2:] - P[1:-1]
    cos = (a * b).sum(1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
    return float(np.degrees(np.arccos(np.clip(cos, -1, 1))).max()) if len(a) else 0.0


def test_loop_subdivided_impossibagel_outline_is_smooth():
    from meschers_igl.gallery import get_model

    g = get_model("impossibagel")
    m, order = g.mescher.subdivide(1, scheme="loop", order=g.order)
    ld = line_drawing(m, order)
    outline = max(ld.polylines("outline"), key=len)
    # the outer silhouette: one closed curve whose direction turns by a few degrees a step
    assert np.allclose(outline[0], outline[-1]) and len(outline) > 100
    assert _max_turn(outline) < 15.0


def test_pieces_join_into_maximal_polylines():
    from meschers_igl.lines import _join

    # a square loop cut into 8 pieces (given out of order and reversed), a T (three pieces
    # meeting at (5, 1)) and a duplicate piece: one closed polyline of 4 corners, three open
    # two-point lines at the T, the duplicate drawn once
    sq = [(0, 0), (1, 0), (2, 0), (2, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    P0 = [sq[i] for i in (3, 0, 5, 1, 7, 2, 4, 6)]
    P1 = [sq[(i + 1) % 8] for i in (3, 0, 5, 1, 7, 2, 4, 6)]
    P0[2], P1[2] = P1[2], P0[2]
    P0 += [(4, 1), (5, 1), (5, 1), (4, 1)]
    P1 += [(5, 1), (6, 1), (5, 3), (5, 1)]
    group = np.zeros(len(P0), dtype=np.int64)
    # the loop made of seam pieces only; of the T's pieces one seam's, one drawn by a seam and
    # by another source, one not a seam's
    seam = np.array([True] * 8 + [True, True, False, False])
    X, off, grp, closed, alone = _join(np.array(P0, float), np.array(P1, float), group, 1.0, seam)
    lines = [X[off[i] : off[i + 1]] for i in range(len(off) - 1)]
    loops = [L for L, c in zip(lines, closed) if c]
    assert len(loops) == 1 and len(loops[0]) == 5
    assert {tuple(p) for p in loops[0].tolist()} == {(0, 0), (2, 0), (2, 2), (0, 2)}
    opens = [L for L, c in zip(lines, closed) if not c]
    assert len(opens) == 3 and all(len(L) == 2 for L in opens)
    got = {
        tuple(sorted(map(tuple, L.tolist()))): a for L, a, c in zip(lines, alone, closed) if not c
    }
    assert got == {((4, 1), (5, 1)): False, ((5, 1), (6, 1)): True, ((5, 1), (5, 3)): False}
    assert alone[closed].all()
    # the same pieces in two groups are never joined across them
    group[:4] = 1
    X, off, grp, closed, _ = _join(np.array(P0, float), np.array(P1, float), group, 1.0, seam)
    assert not closed.any()


def test_bad_input():
    m, order = _squares()
    with pytest.raises(MescherError, match="contours"):
        line_drawing(m, order, contours="fancy")
    with pytest.raises(MescherError, match="crease_angle"):
        line_drawing(m, order, crease_angle=-1)
    with pytest.raises(MescherError, match="order"):
        line_drawing(m, DepthOrder(3))
    with pytest.raises(MescherError, match="Mescher"):
        line_drawing("not a mescher")
    with pytest.raises(MescherError, match="kind"):
        line_drawing(m, order).polylines("shadow")


def test_gallery_polylines_are_maximal():
    from meschers_igl.gallery import get_model

    for name in ("penrose_stairs", "window", "impossible_cube"):
        g = get_model(name)
        ld = line_drawing(g.mescher, g.order)
        # two lines of the same kind never end at a point that no other line touches
        ends, own = [], []
        for i in np.flatnonzero(~ld.closed):
            P = ld.points[ld.offsets[i] : ld.offsets[i + 1]]
            ends += [P[0], P[-1]]
            own += [(ld.kind[i], i), (ld.kind[i], i)]
        ends = np.array(ends)
        for a in range(len(ends)):
            same = np.flatnonzero(np.linalg.norm(ends - ends[a], axis=1) < 1e-9)
            kinds = [own[b][0] for b in same]
            if len(same) == 2 and kinds[0] == kinds[1] and own[same[0]][1] != own[same[1]][1]:
                # allowed only where a third line passes through the point
                touching = np.linalg.norm(ld.points - ends[a], axis=1) < 1e-9
                assert touching.sum() > 2, (name, ends[a])


def test_face_map_edges_oracle_on_hand_cases():
    # a flat grid of faces far smaller than a pixel is one sheet: only its outline is a line
    V, F = shapes.grid(120, 120, size=1.0)  # the unit square in the plane z = 0
    m = Mescher.from_mesh(V, F)
    bounds = (-0.25, 1.25, -0.25, 1.25)
    faces = visible_faces(m, size=48, bounds=bounds)
    gt = visible_face_edges(faces, m, bounds)
    inside = ndimage.binary_erosion(faces >= 0, iterations=2)
    assert gt.any() and not gt[inside].any()
    assert np.array_equal(gt & (faces >= 0), (faces >= 0) & ~ndimage.binary_erosion(faces >= 0))
    # the overlapping squares: the line pixels hug B's boundary and A's boundary outside B
    m, order = _squares()
    bounds = (-0.5, 3.5, -0.5, 3.5)
    faces = visible_faces(m, order, size=64, bounds=bounds)
    gt = visible_face_edges(faces, m, bounds)
    c = np.stack(np.meshgrid(np.arange(64) + 0.5, np.arange(64) + 0.5), -1) / 16.0 - 0.5
    x, y = c[..., 0], 3.0 - c[..., 1]
    near_b = (np.abs(x - 1) < 0.07) & (y > 0.93) & (y < 3.07)
    near_b |= (np.abs(x - 3) < 0.07) & (y > 0.93) & (y < 3.07)
    near_b |= (np.abs(y - 1) < 0.07) & (x > 0.93) & (x < 3.07)
    near_b |= (np.abs(y - 3) < 0.07) & (x > 0.93) & (x < 3.07)
    near_a = (np.abs(x) < 0.07) & (y < 2.07) | (np.abs(y) < 0.07) & (x < 2.07)
    near_a |= (np.abs(x - 2) < 0.07) & (y < 1.07) | (np.abs(y - 2) < 0.07) & (x < 1.07)
    assert np.array_equal(gt, (near_a | near_b) & gt)  # no line pixel elsewhere
    assert gt[near_b & (faces >= 0)].mean() > 0.9


@pytest.mark.parametrize("name", ["impossibagel", "penrose_stairs"])
def test_loop_subdivided_lines_match_the_picture(name):
    from meschers_igl.gallery import get_model

    g = get_model(name)
    m, order = g.mescher.subdivide(1, scheme="loop", order=g.order)
    recall, precision = pixel_scores(m, order)
    assert recall >= 0.98 and precision >= 0.98, (recall, precision)


def test_line_agreement_finds_a_wrong_drawing():
    from meschers_igl.gallery import get_model
    from meschers_igl.line_pixels import line_agreement

    g = get_model("impossible_cube")
    right = line_drawing(g.mescher, g.order)
    assert min(line_agreement(right, g.mescher, g.order, size=256)) >= 0.98
    # the same figure drawn in the reversed order: its back bar's lines no longer match
    wrong = line_drawing(g.mescher, DepthOrder(g.mescher.n_faces, g.order.arcs[:, ::-1]))
    recall, precision = line_agreement(wrong, g.mescher, g.order, size=256)
    assert min(recall, precision) < 0.95
    # every line, hidden ones included, drawn as if seen: precision drops
    every = line_drawing(g.mescher, g.order, hidden=True)
    every = type(every)(
        every.points,
        every.offsets,
        every.kind,
        np.ones_like(every.visible),
        every.closed,
        every.box,
    )
    assert line_agreement(every, g.mescher, g.order, size=256)[1] < 0.9


def test_seam_across_a_strip_seen_edge_on_is_no_line():
    # two unit plates facing the viewer, the second one lower, joined by a vertical strip in
    # the plane x = 1 (seen edge-on): on screen one 2 x 1 rectangle, as the Penrose stairs'
    # junction, whose only line is its outline
    V = np.array(
        [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],  # upper plate
            [1, 0, -1],
            [1, 1, -1],
            [2, 0, -1],
            [2, 1, -1],
        ],  # lower plate
        dtype=float,
    )
    F = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2], [4, 6, 7], [4, 7, 5]])
    m = Mescher.from_mesh(V, F)
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    angle, crease = crease_edges(m)
    assert crease.sum() == 2  # the strip meets each plate at 90 degrees
    ld = line_drawing(m, order)
    assert ld.length("outline") == pytest.approx(6.0, abs=1e-12)
    assert ld.length() == pytest.approx(6.0, abs=1e-12)
    assert ld.n_lines == 1 and ld.closed[0] and len(ld.polylines()[0]) == 5
    bounds = (-0.5, 2.5, -1.0, 2.0)
    faces = visible_faces(m, order, size=48, bounds=bounds)
    gt = visible_face_edges(faces, m, bounds)
    inner = ndimage.binary_erosion(faces >= 0, iterations=2)
    assert gt.any() and not gt[inner].any()


def _inner_contour_misses(m, order):
    """Stray drawn pixels (over 1.5 px from any line pixel of the painter's picture) and the
    largest distance from a line pixel of the picture up the right end of the hole to the
    drawing, at 512 px."""
    ld = line_drawing(m, order)
    lo, hi = np.asarray(m.xy).min(0), np.asarray(m.xy).max(0)
    c, half = 0.5 * (lo + hi), 0.55 * (hi - lo).max()
    bounds = (c[0] - half, c[0] + half, c[1] - half, c[1] + half)
    faces = visible_faces(m, order, size=512, bounds=bounds)
    gt = visible_face_edges(faces, m, bounds)
    drawn = _drawn_mask(ld, bounds, faces.shape)
    stray = drawn & (ndimage.distance_transform_edt(~gt) > 1.5)
    px = 2 * half / 512
    x = bounds[0] + (np.arange(512) + 0.5) * px
    y = bounds[3] - (np.arange(512) + 0.5) * px
    band = ((x > 1.35) & (x < 1.5))[None, :] & ((y > -0.2) & (y < 0.1))[:, None]
    assert (gt & band).sum() > 20
    return stray, ndimage.distance_transform_edt(~drawn)[gt & band].max()


@pytest.mark.parametrize("levels", [0, 1, 2])
def test_impossibagel_inner_contour_is_not_dashed(levels):
    # the impossible order flips between neighbouring faces of the fold at the hole's right end;
    # the interpolated contour must neither flicker into dashes where the painter shows no line
    # nor break where it shows one
    from meschers_igl.gallery import get_model

    g = get_model("impossibagel")
    m, order = g.mescher, g.order
    if levels:
        m, order = m.subdivide(levels, scheme="loop", order=order)
    # no dash: every drawn pixel lies within 1.5 px of a line pixel of the painter's picture
    stray, gap = _inner_contour_misses(m, order)
    assert not stray.any(), np.argwhere(stray)[:5]
    if levels == 2:
        # Loop's overlaps ordered from local depth instead of the sheets beside them: the
        # painter shows the figure's order flipping inside a sheet there, and the drawing
        # dashes (the test can fail)
        m1, o1, parent = g.mescher.subdivide(
            1, scheme="loop", order=g.order, return_face_parent=True
        )
        m2, parent = m1.subdivide(1, scheme="loop", return_face_parent=True)
        assert _inner_contour_misses(m2, o1.follow(m2, parent))[0].sum() >= 3
    # the contour up the right end of the hole, unbroken in the picture, is drawn unbroken; at
    # Loop x2 the edited order's seam (back half in front of the front half) runs beside it,
    # the contour passes into faces behind the front sheet, and the seam's line closes it
    assert gap <= 2.0, gap


def test_triangles_overlap_and_crossing_rule():
    from meschers_igl.line_folds import NEAR_BASE, crossed, triangles_overlap

    a = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    T1 = np.stack([a, a, a, a, a])
    T2 = np.stack(
        [
            a + 0.5,  # overlapping
            a[[1, 0, 2]] * 0.25 + 0.1,  # inside (either orientation)
            np.array([[2.0, 0.0], [0.0, 2.0], [2.0, 2.0]]),  # sharing the hypotenuse only
            a + [2.0, 0.0],  # touching at a corner
            a + 5.0,
        ]  # far
    )
    assert triangles_overlap(T1, T2).tolist() == [True, True, False, False, False]
    assert triangles_overlap(T2, T1).tolist() == [True, True, False, False, False]
    # the fold of face 0 is {0, 1}; face 2 overlaps face 1 and is drawn before it: face 2
    # crosses the fold (face 1 passes in front of it); face 3 is drawn after both: it does not
    T = np.stack([a, a + 0.5, a + 1.0, a + 1.2])
    rank = np.array([0, 3, 1, 4])
    near = np.array([0, 1], dtype=np.int64)  # keys 0 * NEAR_BASE + face
    assert NEAR_BASE > 4
    got = crossed(near, np.array([0, 0]), np.array([2, 3]), T, rank, np.ones(4))
    assert got.tolist() == [True, False]


@pytest.mark.parametrize(
    "name",
    ["penrose_triangle", "impossible_cube", "penrose_stairs", "reutersvard_triangle", "window"],
)
def test_gallery_outline_closes_round_the_figure(name):
    """Every pixel of the figure next to the ground is within a pixel and a half of a visible
    line: a stair's tread past the end of the riser seen edge-on under it meets the ground
    there, and that stretch of its edge is drawn (the outline's jog; a gap lets a reader of
    the drawing's paper into the figure)."""
    from meschers_igl.gallery import get_model

    g = get_model(name)
    m, order = g.mescher, g.order
    ld = line_drawing(m, order)
    lo, hi = np.asarray(m.xy).min(0), np.asarray(m.xy).max(0)
    c, half = 0.5 * (lo + hi), 0.55 * (hi - lo).max()
    bounds = (c[0] - half, c[0] + half, c[1] - half, c[1] + half)
    fig = visible_faces(m, order, size=1024, bounds=bounds) >= 0
    rim = fig & ~ndimage.binary_erosion(fig, border_value=0)
    far = ndimage.distance_transform_edt(~_drawn_mask(ld, bounds, fig.shape))[rim] > 1.5
    assert far.sum() == 0, f"{far.sum()} of {rim.sum()} rim pixels far from every line"
