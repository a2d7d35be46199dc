"""Two occlusions ending at a vertex that a crease runs straight through: the surface is held
whole there (:func:`meschers_igl.inverse.cuts.keep_junctions`)."""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import cuts


def _fan(moved_deg: float = 0.0):
    """A vertex 0 at the origin with eight spokes (every 45 degrees, spoke ``i`` to vertex
    ``i + 1``) and their fan of triangles, counter-clockwise; the spoke at 315 degrees turned
    by ``moved_deg``.  Faces from 90 to 135 and 315 to 90 degrees are region 0, the others 1:
    the spokes at 135 and 315 degrees are one straight crease between regions 0 and 1."""
    ang = np.radians(np.arange(8) * 45.0)
    ang[7] += np.radians(moved_deg)
    xy = np.vstack([[0.0, 0.0], np.c_[np.cos(ang), np.sin(ang)]])
    F = np.array([[0, 1 + i, 1 + (i + 1) % 8] for i in range(8)])
    region = np.array([0, 0, 0, 1, 1, 1, 1, 0])  # face i spans spokes i and i + 1
    edges = np.array([[0, 1 + i] for i in range(8)] + [[1 + i, 1 + (i + 1) % 8] for i in range(8)])
    return xy, F, region, edges


def _spoke(deg: int) -> int:
    return deg // 45  # spoke i is edge i


CREASES = np.array([_spoke(135), _spoke(315)])
PAIRS = np.array([[0, 1], [0, 1]])


def test_a_crease_through_two_occlusions_keeps_their_vertex():
    xy, F, _, edges = _fan()
    cut = np.array([_spoke(90), _spoke(225)])
    at = cuts._through_creases(F, xy, edges, cut, cut, CREASES, PAIRS)
    assert len(at) == 1 and at[0][0] == 0 and at[0][1] in cut


@pytest.mark.parametrize(
    "case", ["crease turns", "one occlusion going on", "a hidden line", "other regions"]
)
def test_no_junction_without_all_of_it(case):
    xy, F, _, edges = _fan(30.0 if case == "crease turns" else 0.0)
    cut = np.array([_spoke(90), _spoke(270 if case == "one occlusion going on" else 225)])
    seen = cut[:1] if case == "a hidden line" else cut
    pairs = np.array([[0, 1], [0, 2]]) if case == "other regions" else PAIRS
    assert cuts._through_creases(F, xy, edges, cut, seen, CREASES, pairs) == []


def _signed_areas(xy, F):
    p, q, r = xy[F[:, 0]], xy[F[:, 1]], xy[F[:, 2]]
    return 0.5 * ((q - p)[:, 0] * (r - p)[:, 1] - (q - p)[:, 1] * (r - p)[:, 0])


def test_the_cut_edge_is_split_and_its_piece_at_the_vertex_kept_whole():
    xy, F, region, edges = _fan()
    cut = np.array([_spoke(90), _spoke(225)])
    ids = np.array([_spoke(135), _spoke(315), *cut])
    pairs = np.array([[0, 1], [0, 1], [0, 0], [1, 1]])
    xy2, F2, region2, edges2, cut2 = cuts.keep_junctions(
        xy, F, region, edges, cut, cut, ids, pairs, 0.1
    )
    # one vertex and two faces more, the same area, every face still counter-clockwise
    assert len(xy2) == len(xy) + 1 and len(F2) == len(F) + 2
    a, a2 = _signed_areas(xy, F), _signed_areas(xy2, F2)
    assert np.all(a2 > 0) and a2.sum() == pytest.approx(a.sum(), rel=1e-12)
    # the new faces keep their parents' regions: each region's area is unchanged
    for r in (0, 1):
        assert a2[region2 == r].sum() == pytest.approx(a[region == r].sum(), rel=1e-12)
    # edges match the faces: every face's three sides are edges
    key = {tuple(sorted(e)) for e in edges2.tolist()}
    sides = {tuple(sorted((f[i], f[(i + 1) % 3]))) for f in F2.tolist() for i in range(3)}
    assert sides == key
    # the split spoke: its piece 0.1 from the vertex is whole, the rest still cut
    m = len(xy)
    assert np.allclose(xy2[m], 0.1 * xy[1 + 2])  # spoke at 90 degrees is vertex 3
    cut_sides = {tuple(sorted(e)) for e in edges2[cut2].tolist()}
    assert cut_sides == {(0, 6), (3, m)}
    # cut open, the vertex keeps one copy: its fan holds together
    xy3, _ = cuts.cut_along(xy2, F2, edges2, cut2)
    assert np.count_nonzero(np.all(xy3 == 0.0, axis=1)) == 1
    xy4, _ = cuts.cut_along(xy, F, edges, cut)  # both spokes cut: two copies
    assert np.count_nonzero(np.all(xy4 == 0.0, axis=1)) == 2


@pytest.mark.render
def test_without_it_the_box_cube_at_512_loses_its_climb(bench_start, monkeypatch):
    """The counterfactual of ``test_inverse_cube_resolution``'s 512 px cases: with no junction
    held whole the two holes beside the front bar's end open into one (in the reading of the
    picture's checkerboards kept; the other reading, every block made whole, climbs there
    too, and is not let in)."""
    pytest.importorskip("pyvista")
    from meschers_igl.inverse import picture
    from meschers_igl.inverse.metrics import figure_period
    from meschers_igl.inverse.models import impossible_cube

    model = impossible_cube()
    m0, _, gap = bench_start(model, 0, 512)
    assert abs(figure_period(m0) / gap - 1.0) < 0.01
    monkeypatch.setattr(cuts, "_through_creases", lambda *a, **k: [])
    monkeypatch.setattr(picture, "CLIMB_MARGIN", float("inf"))
    m1, _, gap = bench_start(model, 0, 512)
    assert figure_period(m1) / gap < 0.1


def test_a_cut_edge_between_two_junctions_is_split_once(monkeypatch):
    xy, F, region, edges = _fan()
    e = _spoke(90)  # vertex 0 to vertex 3
    cut = np.array([e, _spoke(225)])
    monkeypatch.setattr(cuts, "_through_creases", lambda *a, **k: [(0, e), (3, e)])
    ids = np.array([_spoke(135), _spoke(315)])
    xy2, F2, _, edges2, cut2 = cuts.keep_junctions(xy, F, region, edges, cut, cut, ids, PAIRS, 0.1)
    assert len(xy2) == len(xy) + 1 and len(F2) == len(F) + 2
    assert {tuple(sorted(q)) for q in edges2[cut2].tolist()} == {(0, 6), (3, len(xy))}
