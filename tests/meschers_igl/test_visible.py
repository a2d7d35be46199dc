"""Models as artists make them, seen from their view: closed solids, separate blocks,
hidden gaps, welded quads and unwelded STL soups.

The models are built here (``visible_models``: convex blocks from half-spaces, written as OBJ
quads or float32 STL soups), never by the code under test; each knows the depth gap it was built
with, which must come out as the mescher's period.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from builders import tilted_view
from visible_models import (
    ISO_UP,
    ISO_VIEW,
    block_stairs,
    hidden_gap_cube,
    hidden_gap_frame,
    sheared_tribar_torus,
    soup,
    triangulate,
    u_tribar,
    write_obj,
    write_stl,
)

from meschers_igl import Mescher, MescherError, MescherWarning
from meschers_igl.obtain import find_view, model_to_mescher, see_model
from meschers_igl.operators import view_frame

MODELS = {
    "u_tribar": u_tribar,
    "block_stairs": block_stairs,
    "hidden_gap_frame": hidden_gap_frame,
    "hidden_gap_cube": hidden_gap_cube,
}
#: Euler characteristic of the closed surface (hidden side kept), from how each model is built:
#: the U-tribar and the stairs (four blocks touching face to face: one U-shaped solid) are
#: spheres (2) that lose two caps (0) and are glued along a loop (chi unchanged): a torus; the
#: tribar frame is such a U (2) plus its crossing bar (2), less two caps, plus the bridging
#: tube (an annulus, chi 0): 2; the cube frame (7 corners, 8 bars: genus 2, chi -2) plus its
#: crossing bar (2), less two caps, plus the tube: -2 (genus 3 and a sphere).
CLOSED_CHI = {"u_tribar": 0, "block_stairs": 0, "hidden_gap_frame": 2, "hidden_gap_cube": -2}


def _nonzero_periods(m, gap):
    p = np.abs(m.periods())
    return np.sort(p[p > 1e-5 * gap])


def _period_lattice(m, gap, name, how):
    """Every period is an integer multiple of the gap and one is the gap itself: the loops
    through the junction gain the gap, the others nothing (a genus-3 frame has two loops
    through its broken bar in any homology basis, a torus one)."""
    p = _nonzero_periods(m, gap)
    assert p.size >= 1, (name, how, m.periods())
    k = p / gap
    assert np.allclose(k, np.round(k), rtol=0, atol=1e-6), (name, how, p, gap)
    assert abs(p[0] - gap) <= 1e-6 * gap, (name, how, p, gap)
    return p


@pytest.fixture(scope="module", params=sorted(MODELS))
def converted(request, tmp_path_factory):
    """Each model through the library (arrays), as welded OBJ quads and as an STL soup (files,
    through meshlab_filters' PyMeshLab clean-up)."""
    from meshlab_filters import model_to_mescher as from_file

    V, P, gap = MODELS[request.param]()
    F = triangulate(P)
    d = tmp_path_factory.mktemp(request.param)
    out = {"arrays": model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)}
    out["obj quads"] = from_file(write_obj(d / "m.obj", V, P), view=ISO_VIEW, up=ISO_UP)
    Vs, Fs = soup(V, F)
    out["stl soup"] = from_file(write_stl(d / "m.stl", Vs, Fs), view=ISO_VIEW, up=ISO_UP)
    out["soup arrays"] = model_to_mescher(Vs, Fs, view=ISO_VIEW, up=ISO_UP)
    out["visible arrays"] = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP, hidden=False)
    out["visible soup"] = model_to_mescher(Vs, Fs, view=ISO_VIEW, up=ISO_UP, hidden=False)
    return request.param, V, F, gap, out


def test_period_is_the_depth_gap(converted):
    name, _, _, gap, out = converted
    for how, (m, _, report) in out.items():
        if name == "hidden_gap_cube" and how.startswith("visible"):
            continue  # test_visible_cube_frame_has_no_loop_through_its_gap
        p = _period_lattice(m, gap, name, how)
        if name != "hidden_gap_cube":
            assert p.size == 1, (name, how, m.periods())  # a torus: one loop gains depth
        assert m.is_impossible()
        # the report names the junction with the same gap
        gaps = [j.depth_gap for j in report.junctions if j.depth_gap > 1e-5 * gap]
        assert len(gaps) == 1 and abs(gaps[0] - gap) <= 1e-6 * gap, (name, how, str(report))


def test_closed_surface_keeps_the_hidden_side(converted):
    """By default (hidden="auto") the whole model is kept, opened at its junction and glued
    crosswise: a closed surface (no boundary) of the Euler characteristic the model's
    construction gives, with the hidden side (faces turned away from the viewer)."""
    from meschers_igl.topology import boundary_loops

    name, V, F, gap, out = converted
    for how in ("arrays", "obj quads", "stl soup", "soup arrays"):
        m, order, report = out[how]
        assert boundary_loops(np.asarray(m.F)) == [], (name, how)
        assert m.euler_characteristic() == CLOSED_CHI[name], (name, how)
        n = np.asarray(m.face_normals())
        assert (n[:, 2] < -0.1).any() and (n[:, 2] > 0.1).any()
        assert "kept the hidden side" in str(report)
        # the bridge of a hidden gap lies behind the crossing bar
        bridge = np.flatnonzero(report.source_face < 0)
        if name.startswith("hidden_gap"):
            assert bridge.size > 0 and np.isin(bridge, np.asarray(order.arcs)[:, 0]).all()
        else:
            assert bridge.size == 0


def test_visible_cube_frame_has_no_loop_through_its_gap():
    """A limitation the closed surface lifts: on the visible surface alone, the cube frame's
    far piece disappears behind the corner it is attached to (a concave corner seen from
    outside), so no visible loop runs through the bridged gap and there is no period."""
    V, P, gap = hidden_gap_cube()
    m, _, report = model_to_mescher(V, triangulate(P), view=ISO_VIEW, up=ISO_UP, hidden=False)
    assert any(
        j.kind == "hidden gap" and abs(j.depth_gap - gap) <= 1e-6 * gap for j in report.junctions
    )
    assert _nonzero_periods(m, gap).size == 0


def test_arrays_and_files_agree(converted):
    _, _, _, gap, out = converted
    for kind in ("", "visible "):
        _arrays_and_files_agree(
            {
                k: v
                for k, v in out.items()
                if k.startswith(kind) and (kind or not k.startswith("visible"))
            },
            kind + "arrays",
        )


def _arrays_and_files_agree(out, ref_name):
    ref, _, rep0 = out[ref_name]
    area0 = ref.face_areas()[rep0.source_face >= 0].sum()
    for how, (m, _, rep) in out.items():
        # the same visible surface whichever door the model comes in through (STL stores
        # float32 coordinates: 1e-7 of the size, so areas agree to ~1e-6 there)
        assert m.euler_characteristic() == ref.euler_characteristic(), how
        area = m.face_areas()[rep.source_face >= 0].sum()
        assert np.isclose(area, area0, rtol=1e-5 if "stl" in how or "soup" in how else 1e-9), how


def test_visible_surface_faces_the_viewer_and_keeps_the_models_normals(converted):
    name, V, F, _, out = converted
    m, order, report = out["visible arrays"]
    n = np.asarray(m.face_normals())
    assert np.all(n[:, 2] > 0)  # only faces toward the viewer
    # each face keeps the normal of the model face it comes from (camera frame), bridges the
    # normal of the piece they continue
    src = report.source_face
    R = view_frame(ISO_VIEW, ISO_UP)
    Vc = V @ R.T
    Vw, Fw = _cleaned(V, F)
    C = Vw @ R.T
    N = np.cross(C[Fw[:, 1]] - C[Fw[:, 0]], C[Fw[:, 2]] - C[Fw[:, 0]])
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    real = src >= 0
    err = np.linalg.norm(n[real] - N[src[real]], axis=1)
    # clipped pieces sit on a fixed grid of 1e-9 of the size: small pieces tilt by ~1e-8
    assert err.max() <= 1e-7
    # the visible map covers the model's silhouette exactly: its screen area equals the area
    # of the union of the model's projected faces
    import shapely

    sil = shapely.union_all(shapely.polygons(Vc[F][:, :, :2]))
    vis = shapely.union_all(shapely.polygons(np.asarray(m.xy)[np.asarray(m.F)[real]]))
    # up to the overlay grid (1e-9 of the size) along the clipped pieces' boundaries
    Tm = np.asarray(m.xy)[np.asarray(m.F)[real]]
    perimeter = np.linalg.norm(Tm - np.roll(Tm, 1, axis=1), axis=2).sum()
    grid = 1e-9 * np.linalg.norm(np.ptp(V, axis=0))
    assert abs(vis.area - sil.area) <= perimeter * grid, (vis.area, sil.area)
    assert np.isclose(np.asarray(m.face_areas())[real].sum() > 0, True)


def _cleaned(V, F):
    from meschers_igl.obtain import drop_contact_faces, orient_outward, weld

    diag = np.linalg.norm(np.ptp(V, axis=0))
    Vw, Fw, _ = weld(V, F, 1e-9 * diag)
    Fw, _ = drop_contact_faces(Fw)
    Fo = orient_outward(Vw, Fw)[0]
    return Vw, Fo


def test_true_occlusions_are_arcs_from_far_to_near(converted):
    name, _, _, _, out = converted
    m, order, report = out["arrays"]
    assert order.n_arcs == report.n_arcs and order.cycles(warn=False) == []
    m, order, report = out["visible arrays"]
    assert order.n_arcs == report.n_arcs and order.cycles(warn=False) == []
    if name.startswith("hidden_gap"):
        # the crossing bar is in front of both bar pieces and of the bridge behind it
        bridges = np.flatnonzero(report.source_face < 0)
        assert bridges.size > 0
        arcs = np.asarray(order.arcs)
        assert np.isin(bridges, arcs[:, 0]).all()  # every bridge face is behind something
        assert not np.isin(bridges, arcs[:, 1]).any()  # and in front of nothing


def test_from_model_classmethod_matches_models():
    V, P, gap = u_tribar()
    F = triangulate(P)
    m, rep = Mescher.from_model(V, F, view=ISO_VIEW, up=ISO_UP, return_report=True)
    m2, order, rep2 = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)
    assert np.array_equal(m.F, m2.F) and np.array_equal(m.zeta, m2.zeta)
    assert order == type(order)(m.n_faces, rep.arcs)  # the same arcs (canonical order)
    assert "false edge" in str(rep) and f"{gap:.6g}" in str(rep)


def test_soup_repairs_are_reported():
    V, P, _ = block_stairs()
    Vs, Fs = soup(V, triangulate(P))
    # flip half the soup's faces: orientation must be recovered per part by signed volume
    Fs = Fs.copy()
    Fs[::2] = Fs[::2, [0, 2, 1]]
    _, _, report = model_to_mescher(Vs, Fs, view=ISO_VIEW, up=ISO_UP)
    text = "\n".join(report.repairs)
    assert "welded" in text and "re-oriented" in text and "coincident opposite faces" in text


def test_possible_model_warns_with_what_to_try():
    # a plain box seen from the isometric view: nothing lines up, nothing is glued
    V, P, _ = u_tribar()
    from visible_models import AXES, convex_block

    hs = np.array([np.r_[a, -1.0] for a in AXES] + [np.r_[-a, -1.0] for a in AXES])
    Vb, Pb = convex_block(hs, np.zeros(3))
    with pytest.warns(MescherWarning, match="possible.*perceive='manhattan'"):
        m, order, report = model_to_mescher(Vb, triangulate(Pb), view=ISO_VIEW, up=ISO_UP)
    assert not m.is_impossible() and report.junctions == [] and order.n_arcs == 0
    # the three visible faces of a cube: a hexagon, a disk
    assert m.euler_characteristic() == 1 and np.isclose(m.face_areas().sum() > 0, True)
    assert report.warnings


@pytest.mark.parametrize("name", ["u_tribar", "block_stairs"])
def test_auto_view_finds_the_junction(name):
    V, P, gap = MODELS[name]()
    F = triangulate(P)
    v, up, S = find_view(V, F, return_support=True)
    # the view is the top eigenvector of M = sum d d^T over the supporting pair differences:
    # rounding M by eps |M| turns it by at most ~eps w1 / (w1 - w2) (Davis-Kahan); the angle is
    # measured by |v x v_iso| (arccos near 1 cannot resolve angles under sqrt(eps) ~ 1e-8)
    D = V[S[:, 1]] - V[S[:, 0]]
    w = np.linalg.eigvalsh(D.T @ D)
    bound = 16 * np.finfo(float).eps * (1.0 + w[-1] / (w[-1] - w[-2]))
    assert np.linalg.norm(np.cross(v, ISO_VIEW)) <= bound
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m, _, report = model_to_mescher(V, F, view="auto")
    assert np.allclose(report.view, ISO_VIEW, atol=1e-12)
    assert abs(_nonzero_periods(m, gap)[0] - gap) <= 1e-6 * gap


@pytest.mark.parametrize("name", ["hidden_gap_frame", "hidden_gap_cube"])
def test_auto_view_lines_up_a_hidden_gap(name):
    """The pieces of a bar broken behind an occluder line up only for views in the plane of the
    bar and the pieces' offset (one circle); along it the artist centred the crossing bar on
    the gap.  From the model alone and from views 3 degrees off, the view comes back to
    round-off (the bar: 0.1 degree) and the period is the gap."""
    V, P, gap = MODELS[name]()
    F = triangulate(P)
    starts = [None] + [tilted_view(ISO_VIEW, 3.0, seed) for seed in range(3)]
    for start in starts:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            m, _, report = model_to_mescher(V, F, view="auto", view_start=start)
        assert np.linalg.norm(report.view - ISO_VIEW) < 1e-9, (start, report.view)
        assert np.linalg.norm(report.up - ISO_UP) < 1e-9
        _period_lattice(m, gap, name, start)
    # the coincidence vote alone cannot: it finds no view (the cube) or one 2.8 degrees off
    try:
        v, _ = find_view(V, F)
        assert np.degrees(np.arccos(min(1.0, v @ ISO_VIEW))) > 1.0
    except MescherError:
        pass


def test_auto_view_start_is_checked():
    V, P, _ = hidden_gap_frame()
    F = triangulate(P)
    with pytest.raises(MescherError, match="view_start"):
        see_model(V, F, view=ISO_VIEW, view_start=ISO_VIEW)
    with pytest.raises(MescherError, match="within 10 degrees"):
        see_model(V, F, view="auto", view_start=(0.0, 0.0, 1.0))  # 55 degrees off
    with pytest.raises(MescherError, match="start"):
        see_model(V, F, view="auto", view_start=(0.0, 0.0, 0.0))


def test_auto_view_recovers_the_shipped_paradox_views():
    from visible_models import read_obj

    from meschers_igl.paradox import list_paradox_models, paradox_model

    names = list_paradox_models()
    assert len(names) == 18
    worst = 0.0
    for name in names:
        pm = paradox_model(name)
        V, F = read_obj(pm.obj)
        v, up = find_view(V, F)
        ref = np.asarray(pm.view) / np.linalg.norm(pm.view)
        ang = np.degrees(np.arccos(np.clip(v @ ref, -1, 1)))
        worst = max(worst, ang)
        refu = np.asarray(pm.up) / np.linalg.norm(pm.up)
        assert np.degrees(np.arccos(np.clip(up @ refu, -1, 1))) < 0.1, name
        # the same through the conversion (a cut model takes the vote's view)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MescherWarning)
            report = see_model(V, F, view="auto").report
        worst = max(worst, np.degrees(np.arccos(np.clip(report.view @ ref, -1, 1))))
    assert worst < 0.1  # the bar; measured: ~6e-6 degrees (float32 files)


def test_bad_input_names_what_was_found():
    V, P, _ = u_tribar()
    F = triangulate(P)
    with pytest.raises(MescherError, match="perceive"):
        see_model(V, F, perceive="cubist")
    with pytest.raises(MescherError, match="view"):
        see_model(V, F, view="best")
    with pytest.raises(MescherError, match="facing the view"):
        # a single triangle seen edge-on
        see_model(np.eye(3), [[0, 2, 1]], view=(1, -1, 0))
    # seen from behind, an open sheet is turned toward the viewer (and the report says so)
    with pytest.warns(MescherWarning, match="possible"):
        vm = see_model(np.eye(3), [[0, 2, 1]], view=(1, 1, 1))
    assert vm.F.shape == (1, 3) and any("toward the viewer" in r for r in vm.report.repairs)
    with pytest.raises(MescherError, match="V"):
        see_model(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(MescherError, match="single point"):
        see_model(np.zeros((3, 3)), [[0, 1, 2]])


def test_pinch_vertex_warns():
    # two tetrahedra sharing one vertex
    T = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    V = np.vstack([T, -T[1:]])
    F = np.array(
        [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 5, 4], [0, 4, 6], [0, 6, 5], [4, 5, 6]]
    )
    with pytest.warns(MescherWarning, match="pinch vertex"):
        m, _, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)
    assert any("pinch" in w for w in report.warnings)


def test_sheared_torus_is_possible_until_right_angles_are_perceived():
    V, P, gap = sheared_tribar_torus()
    F = triangulate(P)
    # the model is a real closed torus (chi 0, every edge in two faces)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, cnt = np.unique(E, axis=0, return_counts=True)
    assert np.all(cnt == 2) and V.shape[0] - cnt.size + F.shape[0] == 0
    with pytest.warns(MescherWarning, match="perceive='manhattan'"):
        m, _, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP)
    assert not m.is_impossible() and report.snapped is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m, order, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP, perceive="manhattan")
    p = _nonzero_periods(m, gap)
    assert p.size == 1 and abs(p[0] - gap) <= 1e-6 * gap  # the tribar a person sees
    # the report says how far faces were snapped: the unsheared x piece not at all, the
    # sheared bars by up to 90 degrees; every snapped normal is one of three orthogonal axes
    assert report.snapped.min() < 1e-6 and np.degrees(report.snapped.max()) > 45
    n = np.asarray(m.face_normals())
    axes = n[[0]]
    for v in n:  # cluster the normals (few faces)
        if np.abs(axes @ v).max() < 1 - 1e-6:
            axes = np.vstack([axes, v])
    assert axes.shape == (3, 3) and np.allclose(axes @ axes.T, np.eye(3), atol=1e-6)
    assert np.all(np.abs(n @ axes.T).max(axis=1) > 1 - 1e-6)
    assert f"max {np.degrees(report.snapped.max()):.3g} deg" in str(report)


@pytest.mark.parametrize("name", ["u_tribar", "block_stairs", "hidden_gap_frame"])
def test_manhattan_leaves_right_angled_models_alone(name):
    V, P, gap = MODELS[name]()
    F = triangulate(P)
    m0, _, _ = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP, hidden=False)
    m, _, report = model_to_mescher(V, F, view=ISO_VIEW, up=ISO_UP, perceive="manhattan")
    assert report.snapped.max() < 1e-6  # already right-angled: nothing to snap
    assert np.allclose(np.abs(m.periods()), np.abs(m0.periods()), rtol=1e-9, atol=1e-9 * gap)


def _moebius(n=12, w=0.3):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = np.concatenate(
        [
            np.c_[
                np.cos(t) * (1 + s * w * np.cos(t / 2)),
                np.sin(t) * (1 + s * w * np.cos(t / 2)),
                s * w * np.sin(t / 2),
            ]
            for s in (-1, 1)
        ]
    )
    F = []
    for i in range(n):
        j = (i + 1) % n
        # the last quad closes the strip with a half twist: bottom row joins top row
        F += [[i, j, n + i], [j, n + j, n + i]] if j else [[i, n, n + i], [n, 0, n + i]]
    return V, np.array(F)


def test_bad_files_are_repaired_and_reported_or_refused(tmp_path):
    from visible_models import write_obj as w

    from meshlab_filters import model_to_mescher as from_file

    # a non-manifold edge (three faces on it): PyMeshLab splits its vertices (no face lost:
    # each face keeps its own copy) and the report says so
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.warns(MescherWarning):
        m, _, report = from_file(w(tmp_path / "nm.obj", V, F.tolist()), view=(0.3, 0.2, 1))
    assert any("non manifold edges split" in r for r in report.repairs)
    assert report.cleanup.non_manifold_faces_removed == 0
    assert report.cleanup.non_manifold_edges_split >= 1
    assert report.cleanup.faces_out == 3
    # the command-line clean-up keeps a manifold surface: it removes the fewest faces
    from meshlab_filters import clean_mesh

    _, F2, rep2 = clean_mesh(V, F)
    assert (
        rep2.non_manifold_faces_removed >= 1 and F2.shape[0] == 3 - rep2.non_manifold_faces_removed
    )
    _, F3, rep3 = clean_mesh(V, F, non_manifold_edges="split")
    assert F3.shape[0] == 3 and rep3.non_manifold_edges_split >= 1
    # the same arrays straight into the library: noted as a warning, nothing crashes
    with pytest.warns(MescherWarning, match="non-manifold edge"):
        model_to_mescher(V, F, view=(0.3, 0.2, 1))
    # a Moebius strip (non-orientable): warned, converted
    Vm, Fm = _moebius()
    with pytest.warns(MescherWarning, match="non-orientable"):
        m, _, report = from_file(w(tmp_path / "mb.obj", Vm, Fm.tolist()), view=(0.3, 0.2, 1))
    assert m.n_faces > 0 and any("non-orientable" in x for x in report.warnings)
    # files nothing can be made of: refused, naming the path and what was found
    (tmp_path / "empty.obj").write_text("")
    with pytest.raises(MescherError, match="empty file"):
        from_file(tmp_path / "empty.obj")
    (tmp_path / "junk.stl").write_text("solid x\n facet normal 0 0 1\n garbage\n")
    with pytest.raises(MescherError, match="junk.stl"):
        from_file(tmp_path / "junk.stl")
    with pytest.raises(MescherError, match="path_or_V_F"):
        from_file(42)


def test_shipped_cut_models_seen_from_their_view():
    """All 18 shipped ParadoxToolkit cut models through from_model give the cut-model path's
    surface and periods: the hidden side is kept and the cut loops are glued
    crosswise, so the impossible cubes (whose loop passes behind a corner, invisible on the
    visible surface) and the block figures (12 separate boxes, impossible through their order
    only) come out as the tool meant.  Regression: a bridge polygon that was not simple raised
    on impossible_cube.obj; blocks a hair apart were bridged through the block between them."""
    from visible_models import read_obj

    from meschers_igl.obtain import cut_model_to_mescher
    from meschers_igl.paradox import list_paradox_models, paradox_model

    names = list_paradox_models()
    assert len(names) == 18
    for name in names:
        pm = paradox_model(name)
        V, F = read_obj(pm.obj)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MescherWarning)
            m, order, report = model_to_mescher(V, F, view=pm.view, up=pm.up)
            mc, oc = cut_model_to_mescher(V, F, view=pm.view, up=pm.up)
        assert order.cycles(warn=False) == []
        gaps = np.abs(pm.meta["verification"]["depth_gaps"])
        p, pc = _nonzero_periods(m, gaps.max()), _nonzero_periods(mc, gaps.max())
        assert p.size == pc.size and np.allclose(p, pc, rtol=1e-9), (name, p, pc)
        chi = pm.meta["verification"]["glued_chi"]  # the tool's own count after gluing
        assert m.euler_characteristic() == mc.euler_characteristic() == chi, name
        if p.size:  # every period is the depth gap the tool recorded (or twice it)
            assert np.allclose(p / gaps.max(), np.round(p / gaps.max()), atol=1e-5), (name, p)
        r, rc = m.is_impossible(order=order), mc.is_impossible(order=oc)
        assert bool(r) == bool(rc) and r.kind == rc.kind, (name, str(r), str(rc))
        assert bool(r) == ("stair" not in name), name  # the tool's stairs are realisable


def test_shipped_solids_are_their_builders_output_and_give_their_gaps(tmp_path):
    """The study's solids (meschers_igl/data/solids, written by make_solid_models.py) are what
    the builders here make, and through the file door (PyMeshLab clean-up, sidecar view) each
    right-angled one comes out impossible with its recorded depth gap as period."""
    import json
    from importlib.resources import files

    from make_solid_models import MODELS as SOLIDS

    from meshlab_filters import model_to_mescher as from_file

    root = files("meschers_igl") / "data" / "solids"
    assert {"hidden_gap_cube", "hidden_gap_frame", "u_tribar", "block_stairs"} <= set(SOLIDS)
    for name, (build, perceive, _) in SOLIDS.items():
        V, P, gap = build()
        obj = (root / f"{name}.obj").read_text()
        assert write_obj(tmp_path / "m.obj", V, P).read_text() == obj, name
        meta = json.loads((root / f"{name}.json").read_text())
        assert meta["depth_gap"] == pytest.approx(gap, rel=1e-12)
        if perceive is not None or name not in MODELS:
            continue  # perceived right angles: tested with their own models
        m, order, report = from_file(str(root / f"{name}.obj"), view=meta["view"], up=meta["up"])
        _period_lattice(m, gap, name, "shipped file")
        assert order.cycles(warn=False) == []


def test_nearly_closed_part_is_oriented_by_its_volume():
    """A box missing one face (a cut box, or a solid a repair opened), given inside out: its
    summed normal z is ~0 from every view, so it is oriented by the volume it encloses with its
    hole capped (a fan), not by the view."""
    from visible_models import AXES, convex_block

    from meschers_igl.obtain import orient_outward, solid_like_parts

    hs = np.array([np.r_[a, -1.0] for a in AXES] + [np.r_[-a, -1.0] for a in AXES])
    Vb, Pb = convex_block(hs, np.zeros(3))
    F = triangulate(Pb[1:])[:, ::-1]  # one face gone, the rest inside out
    Fo, n_flip, part = orient_outward(Vb, F)
    assert n_flip == F.shape[0] and solid_like_parts(Vb, Fo, part).all()
    T = Vb[Fo]
    c = T.mean(axis=1)
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    assert np.all(np.einsum("ij,ij->i", n, c) > 0)  # every face points away from the centre
    # a flat sheet is not solid-like: it is left to face the viewer
    Vs = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])
    Fs = np.array([[0, 1, 2], [1, 3, 2]])
    assert not solid_like_parts(Vs, Fs, np.zeros(2, np.int64)).any()


def test_a_grid_of_blocks_has_no_junction():
    """27 separate cubes on a grid, seen from a generic view: opposite faces of neighbouring
    cubes are congruent caps facing each other, but nothing lines up (the pieces are in line
    in 3D, g = 0): no junction is glued, no period, the visible surface is built."""
    from visible_models import box_block, separate_blocks

    blocks = [
        box_block(np.array([i, j, k]) * 1.5, np.array([i, j, k]) * 1.5 + 1)
        for i in range(3)
        for j in range(3)
        for k in range(3)
    ]
    V, P = separate_blocks(blocks)
    with pytest.warns(MescherWarning, match="possible"):
        m, order, report = model_to_mescher(V, triangulate(P), view=(1, 1.3, 1.7), up=(0, 0, 1))
    assert not m.is_impossible() and "kept the hidden side" not in str(report)
    assert all(j.depth_gap < 1e-9 for j in report.junctions)
