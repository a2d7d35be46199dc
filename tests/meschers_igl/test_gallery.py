"""The gallery of impossible figures: topology after the seam merge, periods, depth orders."""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest

from meschers_igl import Mescher, MescherError, shapes
from meschers_igl.cutmesh import glue_cut_mesh
from meschers_igl.gallery import GalleryModel, get_model, list_models
from meschers_igl.operators import view_frame
from meschers_igl.topology import boundary_loops, connected_components

NAMES = list_models()
# name -> (Euler characteristic after gluing, connected components, impossible)
EXPECTED = {
    "penrose_triangle": (0, 1, True),
    "penrose_stairs": (0, 1, True),
    "impossible_cube": (-8, 1, False),  # straight bars: impossible through its order
    "reutersvard_triangle": (18, 9, False),  # 9 closed cubes
    "window": (-6, 1, False),  # genus 4, a real object
    "impossibagel": (0, 1, True),
}


@pytest.fixture(scope="module", params=NAMES)
def model(request) -> GalleryModel:
    return get_model(request.param)


def test_list_models():
    assert NAMES == sorted(EXPECTED)
    with pytest.raises(MescherError, match="name: expected one of"):
        get_model("blivet")
    with pytest.raises(MescherError, match="params: expected parameters of 'penrose_triangle'"):
        get_model("penrose_triangle", colour="red")
    with pytest.raises(MescherError, match="bar_width"):
        get_model("penrose_triangle", bar_length=1.0, bar_width=2.0)


def test_cut_model_is_a_clean_outward_surface(model):
    V, F = model.V, model.F
    assert F.dtype == np.int64 and V.dtype == np.float64
    assert igl.is_edge_manifold(F)[0]
    assert igl.is_vertex_manifold(F)[np.unique(F)].all()
    # outward: the face furthest along a generic direction faces that direction
    d = np.array([0.31, 0.52, 0.79])
    N = igl.per_face_normals(V, F, np.zeros(3))
    far = np.argmax((V[F].mean(axis=1)) @ d)
    assert N[far] @ d > 0


def test_seam_merge_counts_and_euler_characteristic(model):
    chi, comps, _ = EXPECTED[model.name]
    m, vmap = model.mescher, model.vmap
    n_loop_vertices = sum(lp.size for lp in boundary_loops(model.F))
    assert m.n_vertices == model.V.shape[0] - n_loop_vertices // 2
    np.testing.assert_array_equal(m.F, vmap[model.F])  # face i stays face i
    assert m.euler_characteristic() == chi
    assert connected_components(np.asarray(m.F), m.n_vertices)[0] == comps
    assert not boundary_loops(np.asarray(m.F))


def test_impossible_with_the_expected_period(model):
    _, _, impossible = EXPECTED[model.name]
    m = model.mescher
    p = m.periods()
    assert m.is_impossible() == impossible
    if impossible:
        assert np.abs(p).max() == pytest.approx(model.expected_period, rel=1e-9)
        k = p / model.expected_period  # every loop crosses the seam a whole number of times
        np.testing.assert_allclose(k, np.round(k), atol=1e-9)
    else:
        assert model.expected_period == 0.0
        np.testing.assert_allclose(p, 0.0, atol=1e-9 * m.scale())
        np.testing.assert_allclose(m.hodge().omega, 0.0, atol=1e-9 * m.scale())


def test_depth_gap_of_the_cut_is_the_period(model):
    """The period is the depth gap measured on the cut model itself."""
    g = glue_cut_mesh(model.V, model.F, view=model.view, up=model.up)
    gaps = [abs(p.depth_gap) for p in g["pairings"]]
    if model.name in ("window", "reutersvard_triangle"):
        assert gaps == []  # no cut: impossible only through the depth order
    elif model.name == "impossible_cube":
        # two cuts around the rigidly moved piece: equal and opposite jumps (no period), each
        # the period of the one-cut variant (straight_bars=False)
        a = get_model("impossible_cube", straight_bars=False).expected_period
        assert sorted(p.depth_gap for p in g["pairings"]) == pytest.approx([-a, a], rel=1e-12)
        assert max(p.translation_residual for p in g["pairings"]) < 1e-12 * a
    else:
        assert gaps == pytest.approx([model.expected_period], rel=1e-12)
        assert max(p.translation_residual for p in g["pairings"]) < 1e-12 * model.expected_period


@pytest.mark.parametrize(("L", "w", "res"), [(4.0, 1.0, 4), (3.0, 0.5, 6), (7.5, 2.0, 3)])
def test_penrose_triangle_period_is_sqrt3_bar_length(L, w, res):
    g = get_model("penrose_triangle", bar_length=L, bar_width=w, resolution=res)
    assert g.expected_period == pytest.approx(np.sqrt(3.0) * L, rel=1e-15)
    p = np.sort(np.abs(g.mescher.periods()))
    np.testing.assert_allclose(p, [0.0, np.sqrt(3.0) * L], atol=1e-9 * L)


def test_resolution_refines_without_changing_the_figure():
    coarse = get_model("penrose_stairs", resolution=1)
    fine = get_model("penrose_stairs", resolution=3)
    assert fine.F.shape[0] > 2 * coarse.F.shape[0]
    np.testing.assert_allclose(fine.V.min(0), coarse.V.min(0))
    np.testing.assert_allclose(fine.V.max(0), coarse.V.max(0))
    assert np.abs(fine.mescher.periods()).max() == pytest.approx(
        np.abs(coarse.mescher.periods()).max(), rel=1e-9
    )


def test_impossibagel_is_the_torus_with_the_cut_models_periods():
    """with_periods on the ordinary torus gives, generator by generator, the periods of the
    sheared cut torus glued by from_cut_mesh (same faces, so the same homology basis)."""
    g = get_model("impossibagel", climb=1.7, resolution=6)
    m = g.mescher
    cut, vmap = Mescher.from_cut_mesh(g.V, g.F, view=g.view, up=g.up, return_map=True)
    np.testing.assert_array_equal(vmap, g.vmap)
    np.testing.assert_array_equal(cut.F, m.F)
    np.testing.assert_allclose(cut.periods(), m.periods(), atol=1e-9)
    assert sorted(np.abs(m.periods()).round(12).tolist()) == [0.0, 1.7]
    # with_periods keeps the torus's exact part (its depth z) and adds a 1-form harmonic on
    # the torus: closed, and co-closed in the torus's own metric
    Vt, Ft = shapes.torus(24, 6, R=2.0, r=0.6)
    Vt = Vt[:, [1, 0, 2]] * np.array([-1.0, 1.0, 1.0])  # a quarter turn: the seam at the back
    np.testing.assert_array_equal(Ft, m.F)
    m0 = Mescher.from_mesh(Vt, Ft, view=g.view, up=g.up)
    h = np.asarray(m.zeta) - m0.d01 @ (Vt @ view_frame(g.view, g.up)[2])
    np.testing.assert_allclose(m0.d12 @ h, 0.0, atol=1e-10)
    np.testing.assert_allclose(m0.d01.T @ (m0.star1 @ h), 0.0, atol=1e-10)
    assert np.abs(h).max() > 0.01


def _zbuffer(xy_pts: np.ndarray, C: np.ndarray, F: np.ndarray, margin: float = 1e-6):
    """(P, #F) coverage and interpolated depth of every face at every screen point (brute
    force, the independent oracle)."""
    T = C[F]  # (#F, 3, 3)
    a, b, c = T[:, 0, :2], T[:, 1, :2], T[:, 2, :2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    ok = np.abs(det) > 1e-12
    det = np.where(ok, det, 1.0)
    px, py = xy_pts[:, None, 0] - a[None, :, 0], xy_pts[:, None, 1] - a[None, :, 1]
    l1 = (px * (c[:, 1] - a[:, 1]) - py * (c[:, 0] - a[:, 0])) / det
    l2 = ((b[:, 0] - a[:, 0]) * py - (b[:, 1] - a[:, 1]) * px) / det
    l0 = 1 - l1 - l2
    cover = ok & (l0 > margin) & (l1 > margin) & (l2 > margin)
    depth = l0 * T[:, 0, 2] + l1 * T[:, 1, 2] + l2 * T[:, 2, 2]
    return cover, depth


def test_order_agrees_with_a_zbuffer_of_the_cut_model(model):
    C = model.V @ view_frame(model.view, model.up).T
    rng = np.random.default_rng(7)
    lo, hi = C[:, :2].min(0), C[:, :2].max(0)
    pts = lo + rng.random((1500, 2)) * (hi - lo)
    cover, depth = _zbuffer(pts, C, model.F)
    tol = 1e-6 * np.ptp(C)
    arcs = {tuple(a) for a in np.asarray(model.order.arcs).tolist()}
    rank = np.empty(model.F.shape[0], dtype=np.int64)
    rank[model.order.linear_extension()] = np.arange(model.F.shape[0])
    # faces the model puts in front of others on purpose (an order no 3D model has)
    edited = np.zeros(model.F.shape[0], dtype=bool)
    if model.front_back is not None:
        edited[np.concatenate(model.front_back)] = True
    n_checked = 0
    for k in np.flatnonzero(cover.sum(1) > 1):  # points where faces overlap
        f = np.flatnonzero(cover[k])
        if edited[f].any():
            continue
        front = f[np.argmax(depth[k, f])]
        for b in f[depth[k, f] < depth[k, front] - tol]:
            assert (int(b), int(front)) in arcs and (int(front), int(b)) not in arcs
            assert rank[b] < rank[front]  # drawn before: behind
            n_checked += 1
    assert n_checked > 100


def test_no_order_cycles_after_one_subdivision(model):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a cycle warning would fail the test
        assert model.order.cycles() == []
        mc, oc = model.mescher.subdivide(order=model.order)
        assert oc.cycles() == []
    assert mc.n_faces == 4 * model.F.shape[0]
    np.testing.assert_allclose(mc.periods(), model.mescher.periods(), atol=1e-9)
    assert oc.n_arcs >= model.order.n_arcs


def test_window_is_impossible_only_through_its_depth_order():
    """The transom is in front of the left mullion and behind the right one (z-buffer of the
    real 3D model), while the mescher has no period."""
    W, H, w = 12.0, 8.0, 1.0
    g = get_model("window", width=W, height=H, bar_width=w)
    assert not g.mescher.is_impossible()
    R = view_frame(g.view, g.up)
    C = g.V @ R.T
    fronts = []
    for xm in (W / 3, 2 * W / 3):
        q = np.array([xm + 0.1, H / 2 + 0.2, w]) @ R.T  # on the mullion's front face
        cover, depth = _zbuffer(q[None, :2], C, g.F)
        f = np.flatnonzero(cover[0])
        fronts.append(depth[0, f].max() - q[2])
    assert fronts[0] > 0.5 * w  # something (the transom) in front of the left mullion
    assert fronts[1] == pytest.approx(0.0, abs=1e-9)  # the right mullion is the front
    # the mescher is what a person sees: a straight transom (flat faces, no slide), so no depth
    # offset realises the order
    verdict = g.mescher.is_impossible(order=g.order)
    assert verdict and verdict.kind == "order"
    n = g.mescher.face_normals()
    assert np.unique(np.round(n, 9), axis=0).shape[0] == 6  # an axis-aligned frame, no shear


def _backface_share(m, order) -> float:
    from meschers_igl.painter import backface_share

    return backface_share(m, order, size=300)


def test_no_back_face_is_visible(model):
    """Every gallery figure is a closed surface seen from outside: the painter's algorithm in
    the order's linear extension shows front faces only (cuts seen edge-on, no notch). Before
    this test the cuts opened toward the camera: 4.3% of the Penrose triangle's pixels showed
    the inside of its top bar (stairs 2.9%, impossible cube 0.26%, Reutersvard 4.9%)."""
    assert _backface_share(model.mescher, model.order) <= 1e-3


@pytest.mark.parametrize("scheme", ["midpoint", "loop"])
def test_no_back_face_is_visible_after_subdivision(model, scheme):
    m, order = model.mescher.subdivide(1, scheme=scheme, order=model.order)
    assert _backface_share(m, order) <= 1e-3


def test_cuts_are_seen_edge_on():
    """A slanted cut's loop lies in a plane containing the view: it projects to a segment."""
    for name, params in [
        ("penrose_triangle", {}),
        ("penrose_stairs", {}),
        ("impossible_cube", {}),
        ("impossible_cube", {"straight_bars": False}),
    ]:
        g = get_model(name, **params)
        C = g.V @ view_frame(g.view, g.up).T
        for lp in boundary_loops(g.F):
            xy = C[lp, :2] - C[lp, :2].mean(0)
            s = np.linalg.svd(xy, compute_uv=False)
            assert s[1] <= 1e-9 * s[0], (name, s)


def test_reutersvard_is_impossible_through_its_order():
    """One depth per cube cannot give this order: contracted to cubes, the arcs form a cycle
    (first < second < ... < last < first), while faces alone have none (it renders)."""
    import networkx as nx

    g = get_model("reutersvard_triangle")
    labels = connected_components(np.asarray(g.mescher.F), g.mescher.n_vertices)[1]
    face_cube = labels[np.asarray(g.mescher.F)[:, 0]]
    arcs = np.asarray(g.order.arcs)
    cube_arcs = {(int(a), int(b)) for a, b in face_cube[arcs] if a != b}
    front, back = g.front_back
    first, last = np.unique(face_cube[front]), np.unique(face_cube[back])
    assert len(first) == 1 and len(last) == 1
    cycle = nx.find_cycle(nx.DiGraph(list(cube_arcs)), source=int(first[0]))
    cubes = {a for a, _ in cycle}
    assert len(cycle) >= 6 and {int(first[0]), int(last[0])} <= cubes  # once around the path
    assert g.order.cycles(warn=False) == []
    with pytest.raises(MescherError, match="pitch"):
        get_model("reutersvard_triangle", pitch=1.25)  # three cubes would share pixels


def _bagel_halves(g: GalleryModel, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(#F,) bool: face in the back half of the ring (world y > 0), in its right half (x > 0)."""
    _, _, u = shapes.torus(4 * n, n, R=2.0, r=0.6, seam=True, return_angles=True)
    w = u[g.F].mean(axis=1) + np.pi / 2  # world angle around the axis (seam at the back)
    return np.sin(w) > 0, np.cos(w) > 0


def test_impossibagel_front_passes_in_front_on_the_left_and_behind_on_the_right():
    """The sense in which the default impossibagel is impossible beyond its period: where the
    ring's front and back overlap on screen, the front is in front at the left end of the hole
    and behind at the right end.  Contracted to its two halves the order is a 2-cycle (no rigid
    front and back could give it), and a person sees it: the painter's picture shows the back
    where the ordinary ring (same view, its own depths) shows the front -- on the right only,
    and not with the climb alone."""
    from meschers_igl import DepthOrder
    from meschers_igl.painter import visible_faces

    g = get_model("impossibagel")
    back, right = _bagel_halves(g, 16)
    nz = np.asarray(g.mescher.face_normals())[:, 2]
    behind, front = np.asarray(g.order.arcs).T
    across = back[behind] != back[front]
    left = across & ~right[behind] & ~right[front]
    assert left.sum() > 100 and not back[front[left]].any()  # left: the front is in front
    facing = back & (nz > 0)  # the back's faces toward the viewer
    ahead = (facing[behind] & ~back[front]) | (facing[front] & ~back[behind])
    ahead &= right[behind] & right[front]
    assert ahead.sum() > 100 and back[front[ahead]].all()  # right: the back is in front
    assert not g.order.cycles(warn=False)  # faces alone: no cycle (it renders)
    ordinary = get_model("impossibagel", climb=1e-3)
    np.testing.assert_allclose(ordinary.mescher.xy, g.mescher.xy, atol=1e-12)
    seen_as = {
        "edited": visible_faces(g.mescher, g.order, size=300),
        "climb alone": visible_faces(
            g.mescher, DepthOrder.from_embedding(g.mescher, g.corner_depths), size=300
        ),
        "ordinary": visible_faces(
            ordinary.mescher,
            DepthOrder.from_embedding(ordinary.mescher, ordinary.corner_depths),
            size=300,
        ),
    }
    vis0 = seen_as["ordinary"]
    half = vis0.shape[1] // 2
    n_figure = (vis0 >= 0).sum()
    flipped = {}
    for name, vis in seen_as.items():
        np.testing.assert_array_equal(vis >= 0, vis0 >= 0)  # the same outline
        f = (vis0 >= 0) & back[np.maximum(vis, 0)] & ~back[np.maximum(vis0, 0)]
        flipped[name] = (f[:, :half].sum() / n_figure, f[:, half:].sum() / n_figure)
    assert flipped["ordinary"] == (0.0, 0.0)
    assert flipped["climb alone"] == (0.0, 0.0)  # the period alone does not show (module notes)
    assert flipped["edited"][0] == 0.0 and flipped["edited"][1] > 0.01  # 1.5% of the figure


def test_every_tread_of_the_stairs_is_seen():
    """Penrose's stairs show every tread from the view (issue 17: "treads visible only on one
    side" was checked here). Painter's oracle over the mescher in its order: each of the 16
    steps' tops is seen over at least 60% of a full tread's pixels, so no step hides another;
    the look of two sides as one slope comes from
    their risers facing away (flat shading gives level treads one shade), not from hidden
    treads."""
    from meschers_igl.painter import visible_faces

    g = get_model("penrose_stairs")
    T = g.V[g.F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    tread = np.flatnonzero(n[:, 2] > 1 - 1e-9)
    height = np.round(T[tread, :, 2].mean(1), 9)
    seen = visible_faces(g.mescher, g.order, size=400)
    px = np.bincount(seen[seen >= 0], minlength=len(g.F))
    levels = np.unique(height)
    per_step = np.array([px[tread[height == z]].sum() for z in levels])
    assert len(levels) == 2 * (5 + 3)
    # the two steps at the cut have slanted ends (smaller / larger treads): 60% of the median
    assert per_step.min() >= 0.6 * np.median(per_step), per_step


def test_impossible_cube_has_straight_bars():
    """The default cube (``straight_bars=True``): the back bar's piece moves rigidly along the
    view, so every face keeps its bar's normal (no sheared dark band); the two cuts are seen
    edge-on, no back face shows; the jumps cancel (no period) and the figure is impossible
    through its order, with the back bar drawn over the front top bar where they cross
    (painter's oracle)."""
    from meschers_igl.gallery.frames import CUBE_UP, CUBE_VIEW, _crossing
    from meschers_igl.painter import visible_faces

    g = get_model("impossible_cube")
    np.testing.assert_array_equal(g.V, get_model("impossible_cube", straight_bars=True).V)
    m, order = g.mescher, g.order
    assert np.unique(np.round(m.face_normals(), 9), axis=0).shape[0] == 6
    assert np.abs(m.periods()).max() < 1e-9 * m.scale() and g.expected_period == 0.0
    verdict = m.is_impossible(order=order)
    assert verdict and verdict.kind == "order"
    assert _backface_share(m, order) <= 1e-3
    m1, o1 = m.subdivide(1, scheme="midpoint", order=order)
    assert _backface_share(m1, o1) <= 1e-3
    C = g.V @ view_frame(g.view, g.up).T
    loops = boundary_loops(g.F)
    assert len(loops) == 4  # two cuts, two ends each
    for lp in loops:
        s = np.linalg.svd(C[lp, :2] - C[lp, :2].mean(0), compute_uv=False)
        assert s[1] <= 1e-9 * s[0]
    # just right of the crossing the back bar shows its +y side and the front top bar its +x
    # side: the +y side is seen (back bar in front); with the order of the real frame (the
    # bent embedding's depths) the +x side is
    from meschers_igl.order import DepthOrder

    zc, _ = _crossing(10.0, CUBE_VIEW, CUBE_UP)
    p = (view_frame(CUBE_VIEW, CUBE_UP) @ np.array([0.0, 0.0, zc]))[:2] + [0.4, 0.0]
    box = (p[0] - 0.05, p[0] + 0.05, p[1] - 0.05, p[1] + 0.05)
    # and the period-carrying variant (one cut, a sheared stretch)
    for model in (g, get_model("impossible_cube", straight_bars=False)):
        T = model.V[model.F]
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        n /= np.linalg.norm(n, axis=1)[:, None]
        Vb, Fb = model.mescher.bent_embedding()
        real = DepthOrder.from_embedding(model.mescher, Vb[Fb][:, :, 2])
        for o, side in ((model.order, 1), (real, 0)):
            seen = visible_faces(model.mescher, o, size=16, bounds=box)
            assert (seen >= 0).all()
            np.testing.assert_allclose(
                n[seen.ravel()], np.eye(3)[side][None].repeat(seen.size, 0), atol=1e-9
            )


def test_impossible_cube_period_variant_shears_a_visible_stretch():
    """``straight_bars=False``: one cut above the crossing, the part below moved by
    ``a = d + 2.5 w`` along the view and eased back at the bottom corner: one period class,
    every period a whole multiple of ``a``.  Same outline on screen as the default cube, but
    the eased stretch's sheared faces (normals off the six axes) are *seen* -- the dark band
    that made the straight-barred cube the default -- while the default shows none."""
    from meschers_igl.gallery.frames import CUBE_UP, CUBE_VIEW, _crossing
    from meschers_igl.painter import visible_faces

    w = 1.0
    g = get_model("impossible_cube", straight_bars=False, bar_width=w)
    m = g.mescher
    _, d = _crossing(10.0, CUBE_VIEW, CUBE_UP)
    assert g.expected_period == pytest.approx(d + 2.5 * w, rel=1e-12)
    verdict = m.is_impossible(order=g.order)
    assert m.is_impossible() and verdict and verdict.kind == "zeta"
    p = m.periods()
    assert np.abs(p).max() == pytest.approx(g.expected_period, rel=1e-9)
    k = p / g.expected_period
    np.testing.assert_allclose(k, np.round(k), atol=1e-9)
    assert m.euler_characteristic() == -8
    assert len(boundary_loops(g.F)) == 2  # one cut
    assert _backface_share(m, g.order) <= 1e-3
    seen = {}
    for name, model in (("sheared", g), ("straight", get_model("impossible_cube"))):
        vis = visible_faces(model.mescher, model.order, size=300)
        T = model.V[model.F]  # world frame: the bars' sides are square to the axes
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        off_axis = np.abs(n).max(axis=1) < (1 - 1e-9) * np.linalg.norm(n, axis=1)
        seen[name] = (
            vis >= 0,
            (off_axis[np.maximum(vis, 0)] & (vis >= 0)).sum() / (vis >= 0).sum(),
        )
    np.testing.assert_array_equal(seen["sheared"][0], seen["straight"][0])  # the same outline
    assert seen["straight"][1] == 0.0
    assert seen["sheared"][1] > 0.02  # 4.7% of the figure


@pytest.mark.parametrize(("c", "thickness"), [(1.0, 1.0), (2.0, 1.0), (1.5, 0.9375)])
def test_penrose_stairs_seen_steeper_keep_their_period_and_climb(c, thickness):
    """Stairs seen along (1, 1, c): the rise per step is c m step / N and the walk ends moved by
    m step (1, 1, c), along the view, so the period -- the depth gap on the cut model and the
    mescher's only nonzero period -- is sqrt(2 + c^2) m step, and the figure stays impossible."""
    step, n_long, n_short = 1.0, 5, 3
    g = get_model("penrose_stairs", steepness=c, thickness=thickness, resolution=1)
    m = g.mescher
    expected = np.sqrt(2.0 + c * c) * (n_long - n_short) * step
    assert g.expected_period == pytest.approx(expected, rel=1e-15)
    assert m.is_impossible() and m.euler_characteristic() == 0
    assert np.abs(m.periods()).max() == pytest.approx(expected, rel=1e-9)
    gaps = [abs(p.depth_gap) for p in glue_cut_mesh(g.V, g.F, view=g.view, up=g.up)["pairings"]]
    assert gaps == pytest.approx([expected], rel=1e-12)
    # the treads (faces with normal +z) lie at heights i s: consecutive levels one rise apart
    V, F = np.asarray(g.V), np.asarray(g.F)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    up = (n[:, 2] > 0) & (np.abs(n[:, :2]).max(axis=1) <= 1e-9 * np.abs(n).max())
    levels = np.unique(np.round(V[F[up]][:, :, 2].mean(axis=1), 9))
    rise = c * (n_long - n_short) * step / (2 * (n_long + n_short))
    np.testing.assert_allclose(np.diff(levels), rise, rtol=1e-9)


def test_penrose_stairs_thickness_is_a_whole_number_of_rises():
    with pytest.raises(MescherError, match="thickness: expected a whole number of rises"):
        get_model("penrose_stairs", steepness=1.5)  # rise 0.1875: 1.0 is 5.33 rises
