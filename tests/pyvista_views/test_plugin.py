"""Meschers inside PyVista through its registries (issue 9): component, accessor, files, theme.

The discovery tests run in fresh interpreters (``subprocess``) that import only ``pyvista`` and
``meschers_igl``, so they prove the entry points of the installed ``meschers`` distribution do
the work, not an import made by the test.  Each child prints one JSON line checked here.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from importlib.metadata import entry_points

import numpy as np
import pytest
import pyvista as pv
from pvv_helpers import back_to_front, luminance, mask, ramp_ring, requires_gl, sphere

from meschers_igl import DepthOrder, Mescher, MescherError, load, save
from meschers_igl.paradox import paradox_model
from pyvista_views import MescherScene, render, to_polydata
from pyvista_views.polydata import needs_soup, provoking_cells, screen_facing, split_by_facing

GROUPS = {
    "pyvista.plotter_components": ("mescher", "pyvista_views.plugin"),
    "pyvista.accessors": ("mescher", "pyvista_views.accessor"),
    "pyvista.readers": (".mescher", "pyvista_views.fileio:read_mescher"),
    "pyvista.writers": (".mescher", "pyvista_views.fileio:write_mescher"),
    "pyvista.themes": ("meschers", "pyvista_views.theme:MeschersTheme"),
}


def run_child(code: str, cwd) -> dict:
    """Run ``code`` in a fresh interpreter; return the JSON its last stdout line holds."""
    env = dict(os.environ, PYVISTA_OFF_SCREEN="true")
    if not (env.get("DISPLAY") or env.get("WAYLAND_DISPLAY")):
        env.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
        cwd=str(cwd),
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def squares() -> Mescher:
    """Two unit-ish squares overlapping in [0.4, 0.6]^2 (faces 0, 1 and 2, 3)."""
    V = np.array([[0, 0], [0.6, 0], [0.6, 0.6], [0, 0.6]], float)
    V = np.c_[np.r_[V, V + 0.4], np.zeros(8)]
    return Mescher.from_mesh(V, np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]))


@pytest.fixture(scope="module")
def ring(tmp_path_factory):
    F, xy, Z, _, _ = ramp_ring(24, 3, 0.6)
    m = Mescher.from_corner_depths(F, xy, Z)
    path = tmp_path_factory.mktemp("ring") / "ring.npz"
    save(m, path)
    return m, path


# -- entry points and the core's independence -----------------------------------------------------


@pytest.mark.parametrize("group", sorted(GROUPS))
def test_entry_points_are_declared_by_the_installed_distribution(group):
    name, value = GROUPS[group]
    found = {(ep.name, ep.value) for ep in entry_points(group=group) if ep.dist.name == "meschers"}
    assert found == {(name, value)}, f"run `pip install -e .` to register {group}"


def test_meschers_igl_never_imports_pyvista(tmp_path):
    out = run_child(
        """
        import json, sys
        import meschers_igl
        from meschers_igl import DepthOrder, Mescher, load, save
        from meschers_igl import cutmesh, io, order, paradox
        print(json.dumps({"mods": sorted(m for m in sys.modules if m.split(".")[0] in
                          ("pyvista", "vtk", "vtkmodules", "pyvista_views", "pymeshlab"))}))
        """,
        tmp_path,
    )
    assert out["mods"] == []


# -- the plotter component ---------------------------------------------------------------------------


@requires_gl
def test_plotter_component_is_discovered_and_draws_the_depth_order(tmp_path):
    m = squares()
    save(m, tmp_path / "squares.npz")
    out = run_child(
        """
        import json, sys
        import numpy as np
        import pyvista as pv
        from meschers_igl import load
        before = "pyvista_views" in sys.modules
        m = load("squares.npz")
        kw = dict(scalars=np.array([0.0, 0, 1, 1]), cmap="gray", ambient=1.0, diffuse=0.0)
        pixels = {}
        for order in ([0, 1, 2, 3], [2, 3, 0, 1]):
            pl = pv.Plotter(window_size=[50, 50])
            layer = pl.mescher.add(m, order=order, **kw)
            pl.mescher.view((0, 1, 0, 1))
            image = pl.mescher.screenshot()
            np.save(f"component_{order[0]}.npy", image)
            pixels[order[0]] = image[20, 25].tolist()  # x = 0.5, y = 0.59: in both squares
            scene_type = type(pl.mescher).__name__
            pl.close()
        print(json.dumps({"before": before, "after": "pyvista_views" in sys.modules,
                          "type": scene_type, "pixels": pixels}))
        """,
        tmp_path,
    )
    assert not out["before"] and out["after"] and out["type"] == "MescherScene"
    assert min(out["pixels"]["0"]) > 200 and max(out["pixels"]["2"]) < 50  # last drawn in front
    # One rendering path: render() gives the component's picture, pixel for pixel.
    kw = dict(scalars=np.array([0.0, 0, 1, 1]), cmap="gray", ambient=1.0, diffuse=0.0)
    for first, order in ((0, [0, 1, 2, 3]), (2, [2, 3, 0, 1])):
        expected = render(
            m, order, window_size=(50, 50), bounds=(0, 1, 0, 1), scalar_bar=False, **kw
        )
        np.testing.assert_array_equal(np.load(tmp_path / f"component_{first}.npy"), expected)


@requires_gl
def test_component_relights_and_adds_embeddings_like_render(ring, tmp_path):
    m, path = ring
    out = run_child(
        f"""
        import json
        import numpy as np
        import pyvista as pv
        from meschers_igl import load
        m = load({str(path)!r})
        pl = pv.Plotter(window_size=[64, 64])
        pl.disable_anti_aliasing()  # as render() draws: silhouettes pixel for pixel
        layer = pl.mescher.add(m, shading="smooth")
        mesh_id = id(layer.mesh)
        pl.mescher.relight((-1.0, 0.0, 0.5))
        np.save("relit.npy", pl.mescher.screenshot())
        same = id(pl.mescher.layers[0].mesh) == mesh_id and len(pl.mescher.layers) == 1
        pl.mescher.clear()
        cut = pl.mescher.add_embedding(m, kind="cut", shading="smooth")
        np.save("cut.npy", pl.mescher.screenshot())
        print(json.dumps({{"same": same, "kind": cut.kind}}))
        """,
        tmp_path,
    )
    assert out["same"] and out["kind"] == "embedding"
    light = [(-1.0, 0.0, 0.5)]
    relit = np.load(tmp_path / "relit.npy")
    np.testing.assert_array_equal(
        relit, render(m, lights=light, shading="smooth", window_size=(64, 64))
    )
    cut = np.load(tmp_path / "cut.npy")
    expected = render(
        m, representation="cut", lights=light, shading="smooth", window_size=(64, 64)
    )  # clear() keeps the scene's lights
    np.testing.assert_array_equal(cut, expected)
    # relighting is real: the default key light gives another picture
    assert np.abs(relit.astype(int) - render(m, shading="smooth", window_size=(64, 64))).mean() > 2


# -- the dataset accessor --------------------------------------------------------------------------------


def test_accessor_on_a_cut_model_read_with_pv_read(tmp_path):
    pm = paradox_model("penrose_triangle")
    out = run_child(
        f"""
        import json
        import numpy as np
        import pyvista as pv
        poly = pv.read({str(pm.obj)!r})
        m, order = poly.mescher.to_mescher(view={pm.view!r}, up={pm.up!r})
        flat = poly.mescher.to_polydata(view={pm.view!r}, up={pm.up!r})
        m2, order2 = flat.mescher.to_mescher()
        print(json.dumps({{
            "quads": poly.n_cells, "faces": m.n_faces, "chi": m.euler_characteristic(),
            "periods": np.abs(m.periods()).tolist(), "arcs": order.n_arcs,
            "exact": bool(np.array_equal(m2.F, m.F) and np.array_equal(m2.xy, m.xy)
                          and np.array_equal(m2.edges, m.edges)
                          and np.array_equal(m2.zeta, m.zeta) and order2 == order),
            "flat_z": float(np.abs(flat.points[:, 2]).max()), "n_points": flat.n_points,
        }}))
        """,
        tmp_path,
    )
    gap = pm.meta["verification"]["depth_gaps"]
    gap = float(np.max(np.abs(gap))) if np.ndim(gap) else abs(float(gap))
    assert out["faces"] == 2 * out["quads"] and out["chi"] == 0  # quads split, glued to a torus
    assert max(out["periods"]) == pytest.approx(gap, rel=1e-3)  # the cut's depth gap (README)
    assert out["arcs"] > 0 and out["exact"]
    assert out["flat_z"] == 0.0 and out["n_points"] == 28  # indexed: the mescher's own vertices


@pytest.mark.parametrize(
    "layout, front_to_back", [("soup", False), ("indexed", False), ("indexed", True)]
)
@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_flattened_polydata_recovers_the_mescher_bit_for_bit(layout, shading, front_to_back):
    V, F = sphere(10)
    m = Mescher.from_mesh(V, F)
    order = DepthOrder.from_embedding(m, V[F][:, :, 2])
    poly = to_polydata(
        m, order, shading=shading, layout=layout, front_to_back=front_to_back, embed=True
    )
    m2, order2 = poly.mescher.to_mescher()
    for name in ("F", "xy", "edges", "zeta"):
        np.testing.assert_array_equal(getattr(m2, name), getattr(m, name))
    assert order2 == order
    with pytest.raises(MescherError, match="view"):
        poly.mescher.to_mescher(view=(1, 0, 0))


def test_accessor_refuses_what_is_not_a_surface():
    with pytest.raises(MescherError, match="mesh"):
        pv.PolyData().mescher.to_mescher()
    with pytest.raises(MescherError, match="surface cells"):
        pv.Line().mescher.to_mescher()


# -- files through PyVista ----------------------------------------------------------------------------------


def test_mescher_files_round_trip_through_pyvista_bit_for_bit(ring, tmp_path):
    m, _ = ring
    order = DepthOrder.from_local_depth(m) if hasattr(DepthOrder, "from_local_depth") else None
    save(m, tmp_path / "x.ply", order=order)
    (tmp_path / "x.ply").rename(tmp_path / "x.mescher")
    save(m, tmp_path / "flat.ply", order=order)
    out = run_child(
        """
        import json
        import numpy as np
        import pyvista as pv
        poly = pv.read("x.mescher")
        poly.save("y.mescher")
        flat = pv.read("flat.ply")  # the PLY variant: any PLY reader sees the flat mesh
        np.save("flat_points.npy", np.asarray(flat.points))
        np.save("zeta.npy", np.asarray(poly.field_data["zeta"]))
        print(json.dumps({"n_points": poly.n_points, "n_cells": poly.n_cells,
                          "normals": poly.cell_data.active_normals is not None,
                          "flat_cells": flat.n_cells}))
        """,
        tmp_path,
    )
    assert (tmp_path / "y.mescher").read_bytes() == (tmp_path / "x.mescher").read_bytes()
    assert out["n_points"] == m.n_vertices and out["n_cells"] == m.n_faces and out["normals"]
    zeta = np.load(tmp_path / "zeta.npy")
    assert zeta.dtype == np.float64 and np.array_equal(zeta.view(np.int64), m.zeta.view(np.int64))
    flat = np.load(tmp_path / "flat_points.npy")  # VTK's PLY reader keeps float32 points
    assert out["flat_cells"] == m.n_faces
    np.testing.assert_allclose(flat[:, :2], m.xy, rtol=0, atol=1e-6)
    assert not flat[:, 2].any()
    (tmp_path / "y.mescher").rename(tmp_path / "y.ply")
    loaded = load(tmp_path / "y.ply", return_order=True)[0]
    np.testing.assert_array_equal(loaded.zeta, m.zeta)


def test_writer_refuses_a_mesh_without_a_mescher(tmp_path):
    with pytest.raises(MescherError, match="to_polydata"):
        pv.Sphere().save(tmp_path / "s.mescher")
    assert not (tmp_path / "s.mescher").exists()


# -- the theme ----------------------------------------------------------------------------------------------


def test_theme_is_found_by_name_and_gives_the_papers_look(tmp_path):
    out = run_child(
        """
        import json, sys
        import pyvista as pv
        pv.set_plot_theme("meschers")
        t = pv.global_theme
        pl = pv.Plotter()
        print(json.dumps({"name": t.name, "background": list(t.background.float_rgb),
                          "parallel": pl.camera.parallel_projection,
                          "specular": t.lighting_params.specular,
                          "loaded": "pyvista_views.theme" in sys.modules}))
        """,
        tmp_path,
    )
    assert out == {
        "name": "meschers",
        "background": [1.0, 1.0, 1.0],
        "parallel": True,
        "specular": 0.0,
        "loaded": True,
    }


# -- the indexed layout behind the speed (issue 5 item 7) ---------------------------------------------------


def test_screen_facing_and_fold_splitting_by_hand():
    P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    cells = np.array([[0, 1, 2], [1, 2, 3], [1, 3, 2]])  # ccw, cw, ccw (3 mirrors 1)
    facing = screen_facing(P, cells)
    np.testing.assert_array_equal(facing, [1, -1, 1])
    out, source = split_by_facing(cells, facing, 4)
    # vertices 1, 2, 3 are shared by both windings: the clockwise cell gets copies 4, 5, 6
    np.testing.assert_array_equal(source, [0, 1, 2, 3, 1, 2, 3])
    np.testing.assert_array_equal(out, [[0, 1, 2], [4, 5, 6], [1, 3, 2]])
    np.testing.assert_array_equal(source[out], cells)  # the same triangles
    out, source = split_by_facing(cells[:2], facing[:2], 4)  # vertex 0 only ccw, 3 only cw
    np.testing.assert_array_equal(source, [0, 1, 2, 3, 1, 2])
    np.testing.assert_array_equal(out, [[0, 1, 2], [4, 5, 3]])


def test_needs_soup_only_where_per_face_and_per_vertex_values_meet():
    v, f = (np.zeros(3), "vertex"), (np.zeros(2), "face")
    assert not needs_soup("flat", {}, False) and not needs_soup("smooth", {}, False)
    assert not needs_soup("flat", {"a": f}, False) and not needs_soup("smooth", {"a": v}, False)
    assert needs_soup("flat", {"a": v}, False) and needs_soup("smooth", {"a": f}, False)
    assert needs_soup("smooth", {}, True)


def test_indexed_mescher_has_the_meshs_points_at_zero_depth_in_either_direction():
    V, F = sphere(12)
    m = Mescher.from_mesh(V, F)
    draw = back_to_front(V, F)
    a = to_polydata(m, draw, layout="indexed")
    b = to_polydata(m, draw, layout="indexed", front_to_back=True)
    assert a.n_points == m.n_vertices and not np.asarray(a.points)[:, 2].any()
    np.testing.assert_array_equal(a.cell_data["face_id"], draw)
    np.testing.assert_array_equal(b.cell_data["face_id"], draw[::-1])
    np.testing.assert_array_equal(a.regular_faces, F[draw])
    s = to_polydata(m, draw, shading="smooth", layout="indexed")
    np.testing.assert_allclose(
        s.point_data.active_normals, m.vertex_normals()[s.point_data["vertex_id"]], atol=1e-7
    )
    p = to_polydata(m, draw, layout="provoking")  # each face's normal on its own last point
    last = p.regular_faces[:, 2]
    np.testing.assert_array_equal(last, np.arange(m.n_faces))
    assert p.cell_data.active_normals is None
    np.testing.assert_allclose(p.point_data.active_normals[last], m.face_normals()[draw], atol=1e-7)
    np.testing.assert_array_equal(
        np.sort(p.point_data["vertex_id"][p.regular_faces], axis=1), np.sort(F[draw], axis=1)
    )
    assert m.n_vertices <= s.n_points < 1.2 * m.n_vertices  # copies only along the silhouette


def test_provoking_cells_are_rotations_ending_with_their_own_point():
    V, F = sphere(16)
    rng = np.random.default_rng(3)
    cells = F[rng.permutation(len(F))]
    out, source = provoking_cells(cells, len(V))
    np.testing.assert_array_equal(out[:, 2], np.arange(len(out)))  # cell k ends with point k
    mapped = source[out]
    same = [(np.roll(cells, -k, axis=1) == mapped).all(axis=1) for k in range(3)]
    assert np.logical_or.reduce(same).all()  # each row a rotation: same triangle, orientation
    assert set(source.tolist()) == set(range(len(V)))  # every vertex kept
    # a closed mesh has ~2x as many faces as vertices: #F points, plus vertices nobody claimed
    assert len(F) <= len(source) <= len(F) + 2


@requires_gl
def test_flat_varyings_draw_exactly_what_cell_normals_draw(monkeypatch):
    import sys as _sys

    render_module = _sys.modules["pyvista_views.layers"]  # where add_mescher picks its layout
    assert render_module.flat_varyings_work()
    V, F = sphere(20)
    m = Mescher.from_mesh(V, F)
    order = back_to_front(V, F)
    kw = dict(order=order, lights=[(1, -0.5, 0.7)], window_size=(96, 96))
    provoking = render(m, **kw)
    monkeypatch.setattr(render_module, "flat_varyings_work", lambda: False)  # cell normals
    with MescherScene(window_size=(96, 96)) as scene:
        assert scene.add(m, order=order).layout == "indexed"
    np.testing.assert_array_equal(provoking, render(m, **kw))


@requires_gl
@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_early_z_and_default_depth_test_draw_the_same_picture(shading):
    V, F = sphere(20)
    m = Mescher.from_mesh(V, F)
    order = back_to_front(V, F)
    images = []
    for early_z in (True, False):
        with MescherScene(window_size=(96, 96), early_z=early_z) as scene:
            layer = scene.add(m, order=order, shading=shading)
            assert layer.layout == ("provoking" if shading == "flat" else "indexed")
            images.append(scene.screenshot())
    np.testing.assert_array_equal(images[0], images[1])
    z_buffered = render((V, F), shading=shading, window_size=(96, 96))
    assert np.abs(images[0].astype(int) - z_buffered).mean() < 1.0


def folded_strip() -> tuple[Mescher, np.ndarray]:
    """A wavy strip folded over itself on screen, the clockwise (back-facing) half drawn last,
    so that it is the half seen; returns the mescher and that drawing order."""
    x = np.linspace(0, 1, 9)
    V = np.c_[np.r_[x, x], np.r_[np.zeros(9), np.ones(9)], np.r_[np.sin(6 * x), np.sin(6 * x)]]
    V[:, 0] = np.abs(V[:, 0] - 0.5)
    i = np.arange(8)
    m = Mescher.from_mesh(V, np.r_[np.c_[i, i + 1, i + 10], np.c_[i, i + 10, i + 9]])
    facing = screen_facing(np.c_[m.xy, np.zeros(m.n_vertices)], np.asarray(m.F))
    assert (facing < 0).sum() == (facing > 0).sum() == 8
    return m, np.argsort(facing < 0, kind="stable")


@requires_gl
def test_baked_flat_shading_flips_back_facing_faces_like_vtk():
    """A black environment map bakes the Lambert term alone: it must equal VTK's two-sided
    lighting of the same light, here on faces seen from behind."""
    m, draw = folded_strip()
    kw = dict(order=draw, shading="flat", window_size=(64, 64), lights=[(0.3, 0.5, 0.8)])
    lit = render(m, **kw)
    baked = render(m, env_map=np.zeros((8, 16, 3)), **kw)
    assert np.abs(lit.astype(int) - baked).max() <= 1
    assert len(np.unique(luminance(lit)[mask(lit)])) >= 4  # several shades, not one


@requires_gl
def test_baked_smooth_shading_on_the_split_mesh_equals_the_per_corner_soup():
    """Baked smooth colours live on vertices: the indexed mesh (folds split) must give what the
    soup, whose corners are all separate, gives.  A constant scalar per vertex keeps the indexed
    layout, the same constant per face forces the soup (needs_soup)."""
    m, draw = folded_strip()
    kw = dict(
        order=draw,
        shading="smooth",
        window_size=(64, 64),
        lights=[(0.3, 0.5, 0.8)],
        env_map="studio",
        clim=(0.0, 1.0),
        cmap="gray",
        scalar_bar=False,  # the shading is compared, not the colour bar
    )
    indexed_img = render(m, scalars=np.full(m.n_vertices, 0.8), **kw)
    soup_img = render(m, scalars=np.full(m.n_faces, 0.8), **kw)
    assert np.abs(indexed_img.astype(int) - soup_img).max() <= 1
    assert len(np.unique(luminance(soup_img)[mask(soup_img)])) >= 8


def test_accessor_sees_a_closed_solid_from_its_view_with_the_converter_options():
    from pathlib import Path

    import meschers_igl

    folder = Path(meschers_igl.__file__).parent / "data" / "solids"
    meta = json.loads((folder / "u_tribar.json").read_text())
    mesh = pv.read(folder / "u_tribar.obj")
    m, order, report = mesh.mescher.seen_from(view=meta["view"], up=meta["up"])
    assert np.abs(m.periods()).max() == pytest.approx(meta["depth_gap"], rel=1e-6)
    assert m.is_impossible(order=order).kind == "zeta"
    # the keywords reach the converter: the visible surface only has a boundary, the default
    # (hidden side kept) is closed
    mv, _, _ = mesh.mescher.seen_from(view=meta["view"], up=meta["up"], hidden=False)

    def boundary_edges(mm):
        return int((np.bincount(np.asarray(mm.face_edges).ravel()) == 1).sum())

    assert boundary_edges(m) == 0 and boundary_edges(mv) > 0
    assert np.abs(mv.periods()).max() == pytest.approx(meta["depth_gap"], rel=1e-6)
