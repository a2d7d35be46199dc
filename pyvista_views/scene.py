"""The scene: meschers and real meshes in one plotter, one head-on camera, one light rig.

Every picture of the project goes through :class:`MescherScene`, which is also PyVista's plotter
component ``plotter.mescher`` (registered by :mod:`pyvista_views.plugin` and the
``pyvista.plotter_components`` entry point):

- :func:`add_mescher` / :func:`add_embedding` put a mescher (flattened, drawn in the order's
  linear extension) or a real mesh (z-buffered) into a :class:`pyvista.Plotter` and return a
  :class:`Layer`;
- :func:`relight` lights every layer of a plotter, with VTK directional lights or, for an
  environment map, with irradiance baked per face or per vertex.

The camera (:mod:`.camera`) is always orthographic, looking down -z with y up, so the camera
frame of docs/conventions.rst is the scene frame and ``bounds = (xmin, xmax, ymin, ymax)`` is exactly the
image's extent.

A mescher is drawn as an *indexed* mesh at ``z = 0`` (:mod:`.polydata`): its cells go front to
back and the renderer's depth test is ``GL_LESS`` (:func:`~pyvista_views.gl.use_early_z`), so the
first fragment drawn at a pixel, the frontmost in the depth order, wins and every hidden fragment
is rejected before it is shaded.  Flat shading puts each face's normal on the last (provoking)
vertex of its cell and makes the normals ``flat`` varyings
(:func:`~pyvista_views.gl.use_flat_varyings`; the ``"provoking"`` layout), smooth shading uses
vertex normals: no per-triangle cell-data lookup, so a frame costs about what an ordinary mesh of
the same size costs (``benchmarks/bench_render.py``).  Isolines on a mescher (and scalar/shading
combinations that baked lighting cannot represent per face or per vertex) use the per-face-depth
soup instead (:func:`~pyvista_views.polydata.needs_soup`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_choice, as_float_array, as_positive

from . import headless
from .camera import DEFAULT_MARGIN, as_bounds, as_window_size, default_bounds, set_view, xy_box
from .envmap import EnvironmentMap, as_env_map
from .gl import face_id_image, flat_varyings_work, use_early_z, use_flat_varyings
from .isolines import levels_of, visible_isolines
from .lights import (
    TONE_MAPS,
    DirectionalLight,
    as_lights,
    exposure_scale,
    lambert,
    peak_irradiance,
    set_vtk_lights,
    tone_map_curve,
)
from .normals import DEFAULT_FEATURE_ANGLE
from .overlays import (
    PATH_COLORS,
    PathMark,
    PointMark,
    as_path_marks,
    as_point_marks,
    clip_polyline,
    disc_on_figure,
    place_labels,
    polyline_pieces_mesh,
    triangles_mesh,
    visible_vertices,
)
from .polydata import (
    SHADINGS,
    as_scalars,
    embedding_polydata,
    needs_soup,
    screen_facing,
    split_folds,
    to_polydata,
)
from .theme import COLOR, LIGHT_RIG

#: Matte grey: lit faces stay below the white background (silhouettes are measurable).
DEFAULT_COLOR = COLOR
#: The key light of the study's rig (:data:`pyvista_views.theme.LIGHT_RIG`), toward (1, 1, 1).
DEFAULT_LIGHTS = LIGHT_RIG[:1]
REPRESENTATIONS = ("mescher", "cut", "bent")
#: Share of the window's width on the right that :meth:`MescherScene.add_scalar_bar` takes.
SCALAR_BAR_STRIP = 0.2
_BAKED = "_shaded_rgb"
#: Ambient share of a colour-mapped layer's material (the rest diffuse): faces are shaded
#: between 70% and 100% of their colour-bar colour, so the shape reads and the colours match.
SCALAR_AMBIENT = 0.7
#: Colour of NaN / +inf scalars ("unreached": parts no source reaches).
UNREACHED_COLOR = "#c8c8c8"
#: Smallest label line height in pixels (glyphs of about 11 pixels: readable at page width).
MIN_LABEL_PX = 14


def scalar_bar_strip(width: int) -> float:
    """Share of a window ``width`` pixels wide kept for a colour bar: room for labels of
    :data:`MIN_LABEL_PX` (six characters) where that takes 20-30% of the width."""
    needed = MIN_LABEL_PX * 0.6 * 6 / 0.55 / max(width, 1) + 0.04
    return float(np.clip(needed, SCALAR_BAR_STRIP, 0.3))


def label_font_size(window: tuple[int, int]) -> int:
    """Line height in pixels of in-figure labels: 1/32 of the window's smaller side, at least
    :data:`MIN_LABEL_PX`."""
    return int(max(MIN_LABEL_PX, round(min(window) / 32)))


@dataclass
class Layer:
    """One mescher or real mesh in a plotter.

    Attributes
    ----------
    mesh : pyvista.PolyData
        What is drawn (:func:`~pyvista_views.polydata.to_polydata`).
    actor : pyvista.Actor
    kind : {"mescher", "embedding"}
    shading : {"flat", "smooth"}
    color : (3,) float
        Material colour when no scalars are shown.
    scalars : str or None
        Active scalar array (colour-mapped), if any.
    ambient, diffuse : float
        Matte material: ``colour * (ambient + diffuse * irradiance)``, no specular.
    isolines : pyvista.Actor or None
        Contour lines; on a mescher only where they lie on the visible surface's levels
        (:mod:`.isolines`), recomputed by :meth:`update_isolines` when the view changes.
    layout : {"provoking", "indexed", "soup"}
        :mod:`.polydata`; a soup's points are the corners of its cells, 3 per cell.
    early_z : bool
        Cells go front to back under a ``GL_LESS`` depth test (:func:`~pyvista_views.gl.use_early_z`).
    clim : (float, float) or None
        Colour range of the scalars.
    title : str or None
        Name of the scalar field (the colour bar's title).
    """

    mesh: pv.PolyData
    actor: Any
    kind: str
    shading: str
    color: tuple[float, float, float]
    scalars: str | None
    ambient: float
    diffuse: float
    isolines: Any = None
    layout: str = "soup"
    early_z: bool = False
    clim: tuple[float, float] | None = None
    title: str | None = None
    _contour: tuple | None = field(default=None, repr=False)
    _contour_key: tuple | None = field(default=None, repr=False)
    _mapper_state: tuple = field(default=(), repr=False)
    _folds_split: bool = field(default=False, repr=False)
    #: screen positions and faces of what the layer draws (the mescher, or V[:, :2] and F)
    source: tuple | None = field(default=None, repr=False)
    #: how overlaps are resolved: "order" (a given depth order), "local depth" (an order built
    #: from the mescher's relative depths), "z-buffer" (a possible mescher drawn as its 3D
    #: embedding) or "index" (face-index order)
    depth: str = "order"
    _face_map: tuple | None = field(default=None, repr=False)

    @property
    def xy_box(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the layer on screen."""
        b = self.mesh.bounds
        return (b[0], b[1], b[2], b[3])

    @property
    def shading_location(self) -> str:
        """Where baked colours live: ``"cell"`` for a flat indexed mesh, else ``"point"``."""
        return "cell" if (self.layout != "soup" and self.shading == "flat") else "point"

    def shading_normals(self) -> np.ndarray:
        """Unit normals as the shader sees them, at :attr:`shading_location`.

        VTK's two-sided lighting flips the normal of a triangle whose screen winding is
        clockwise; baked shading does the same so both paths agree (an indexed smooth mesh is
        split on folds before its first baking, so each point belongs to cells of one winding;
        :attr:`mesh` is then that split mesh).

        Returns
        -------
        (#cells, 3) or (#points, 3) float64
        """
        cells = self.mesh.regular_faces
        facing = screen_facing(self.mesh.points, cells)
        if self.shading == "flat":
            if self.layout == "provoking":  # each cell's normal sits on its last point
                n = np.asarray(self.mesh.point_data.active_normals, dtype=np.float64)[cells[:, 2]]
            else:
                n = np.asarray(self.mesh.cell_data.active_normals, dtype=np.float64)
            n = n * facing[:, None]
            return n if self.layout != "soup" else np.repeat(n, 3, axis=0)
        point_facing = np.ones(self.mesh.n_points)
        point_facing[cells] = facing[:, None]
        n = np.asarray(self.mesh.point_data.active_normals, dtype=np.float64)
        return n * point_facing[:, None]

    def update_isolines(self, plotter: pv.Plotter, bounds: Sequence[float]) -> None:
        """(Re)compute a mescher's isolines for the image ``bounds`` in ``plotter``'s window.

        The lines are the contours of the field where they lie on a level of the visible
        surface (:func:`~pyvista_views.isolines.visible_isolines`, visibility from
        :func:`~pyvista_views.gl.face_id_image`), so they depend on the view; nothing is done
        when the view has not changed.
        """
        if self._contour is None:
            return
        window = (int(plotter.window_size[0]), int(plotter.window_size[1]))
        bounds = as_bounds(bounds)
        key = (bounds, window)
        if key == self._contour_key:
            return
        if self.isolines is not None:
            plotter.remove_actor(self.isolines, render=False)
            self.isolines = None
        xy, F, values, levels, color, width = self._contour
        face_map = self.face_map(plotter, bounds)
        b = self.mesh.bounds
        lift = 1e-3 * float(np.hypot(b[1] - b[0], b[3] - b[2]) or 1.0)
        lines = visible_isolines(xy, F, values, levels, face_map, bounds, z=b[5] + lift)
        if lines.n_cells:
            self.isolines = plotter.add_mesh(
                lines,
                color=color,
                line_width=width,
                lighting=False,
                show_scalar_bar=False,
                reset_camera=False,
            )
        self._contour_key = key

    def face_map(self, plotter: pv.Plotter, bounds: Sequence[float]) -> np.ndarray:
        """The face drawn at each pixel of ``plotter``'s window for the image ``bounds``
        (:func:`~pyvista_views.gl.face_id_image`; -1 on the background), computed once per view.

        Returns
        -------
        (height, width) int64
        """
        window = (int(plotter.window_size[0]), int(plotter.window_size[1]))
        key = (as_bounds(bounds), window, id(self.mesh))
        if self._face_map is None or self._face_map[0] != key:
            self._face_map = (key, face_id_image(self.mesh, window, key[0], self.early_z))
        return self._face_map[1]

    def albedo(self) -> np.ndarray:
        """(n, 3) linear RGB base colour at :attr:`shading_location` (colour-mapped or plain)."""
        location = self.shading_location
        n = self.mesh.n_cells if location == "cell" else self.mesh.n_points
        if self.scalars is None:
            return np.broadcast_to(np.asarray(self.color, float), (n, 3))
        if self.scalars in self.mesh.point_data:
            values = np.asarray(self.mesh.point_data[self.scalars], dtype=np.float64)
        else:
            values = np.asarray(self.mesh.cell_data[self.scalars], dtype=np.float64)
            if location == "point":  # a soup: 3 corners per cell
                values = np.repeat(values, 3)
        lut = self.actor.mapper.lookup_table
        rgba = lut.MapScalars(numpy_to_vtk(np.ascontiguousarray(values)), 0, -1)
        return vtk_to_numpy(rgba).reshape(n, -1)[:, :3] / 255.0


def _check_material(color: object, ambient: float, diffuse: float) -> tuple:
    rgb = tuple(float(c) for c in as_float_array(pv.Color(color).float_rgb, "color", (3,)))
    return (
        rgb,
        as_positive(ambient, "ambient", allow_zero=True),
        as_positive(diffuse, "diffuse", allow_zero=True),
    )


def _add_layer(
    plotter: pv.Plotter,
    mesh: pv.PolyData,
    kind: str,
    shading: str,
    layout: str,
    *,
    color: object,
    cmap: str,
    clim: Sequence[float] | None,
    isolines: int | Sequence[float],
    isoline_color: object,
    isoline_width: float,
    isoline_lift: float,
    ambient: float,
    diffuse: float,
    name: str | None,
    contour: tuple | None = None,
    early_z: bool = False,
) -> Layer:
    rgb, ambient, diffuse = _check_material(color, ambient, diffuse)
    active = mesh.active_scalars_name  # set by the builders from the user's fields only
    if active is not None and clim is None:
        values = np.asarray(mesh.active_scalars, dtype=np.float64)
        finite = values[np.isfinite(values)]
        clim = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    actor = plotter.add_mesh(
        mesh,
        color=rgb,
        scalars=active,
        cmap=cmap if active is not None else None,
        clim=clim,
        nan_color=UNREACHED_COLOR,
        show_scalar_bar=False,
        ambient=ambient,
        diffuse=diffuse,
        specular=0.0,
        # Point normals need Gouraud interpolation; "provoking" then makes them flat varyings.
        interpolation="flat" if (shading == "flat" and layout != "provoking") else "gouraud",
        smooth_shading=False,  # would recompute normals from the flat geometry
        lighting=True,
        name=name,
        reset_camera=False,
    )
    if layout == "provoking":
        use_flat_varyings(actor)
    mapper = actor.mapper
    layer = Layer(
        mesh,
        actor,
        kind,
        shading,
        rgb,
        active,
        ambient,
        diffuse,
        layout=layout,
        early_z=early_z,
        clim=None if clim is None else (float(clim[0]), float(clim[1])),
        title=active,
        _mapper_state=(
            mapper.GetScalarVisibility(),
            mapper.GetScalarMode(),
            mapper.GetArrayName(),
            mapper.GetColorMode(),
        ),
    )
    if _wants_isolines(isolines):
        width = as_positive(isoline_width, "isoline_width")
        if contour is not None:  # a mescher: lines on its visible layer, once the view is known
            xy, F, values = contour
            levels = levels_of(isolines, clim)
            layer._contour = (xy, F, values, levels, isoline_color, width)
        else:
            layer.isolines = _add_isolines(
                plotter, layer, isolines, clim, isoline_color, width, isoline_lift
            )
    return layer


def _wants_isolines(isolines: object) -> bool:
    return not (isinstance(isolines, (int, np.integer)) and isolines == 0)


def _add_isolines(
    plotter: pv.Plotter,
    layer: Layer,
    isolines: int | Sequence[float],
    clim: Sequence[float] | None,
    color: object,
    width: float,
    lift: float,
) -> Any:
    """Contours of a real mesh's active per-vertex scalars, z-buffered with the mesh.

    Every segment lies inside one face; a line is a few pixels wide, so it spills onto the
    faces around its own, which on a real mesh are at about the same depth: a lift of ``lift``
    toward the viewer suffices.  (A mescher's isolines are computed on its visible layer
    instead, :meth:`Layer.update_isolines`.)
    """
    if layer.scalars is None or layer.scalars not in layer.mesh.point_data:
        raise MescherError(
            "isolines: expected per-vertex scalars to contour, found "
            + ("no scalars" if layer.scalars is None else "per-face scalars")
        )
    lines = layer.mesh.contour(isosurfaces=levels_of(isolines, clim), scalars=layer.scalars)
    if lines.n_points == 0:
        return None
    lines.points[:, 2] += lift
    return plotter.add_mesh(
        lines,
        color=color,
        line_width=width,
        lighting=False,
        show_scalar_bar=False,
        reset_camera=False,
    )


def _representation_kwargs(**kw: Any) -> dict:
    """The layer's material and isoline options; any other keyword is refused (a misspelt one
    would otherwise be ignored without a word)."""
    opts = {
        "color": kw.pop("color", DEFAULT_COLOR),
        "cmap": kw.pop("cmap", "viridis"),
        "clim": kw.pop("clim", None),
        "isolines": kw.pop("isolines", 0),
        "isoline_color": kw.pop("isoline_color", "black"),
        "isoline_width": kw.pop("isoline_width", 2.0),
        "ambient": kw.pop("ambient", 0.2),
        "diffuse": kw.pop("diffuse", 0.8),
        "name": kw.pop("name", None),
    }
    if kw:
        import difflib

        known = sorted({*opts, *LAYER_KEYWORDS})
        bad = sorted(kw)[0]
        near = difflib.get_close_matches(bad, [*known, *CALL_KEYWORDS], n=1)
        raise MescherError(
            f"{bad}: expected a keyword of render / add_mescher ({', '.join(known)}), found "
            f"an unknown one" + (f" (did you mean {near[0]!r}?)" if near else "")
        )
    return opts


#: keywords the layer functions take besides the material's (for the message above)
LAYER_KEYWORDS = ("feature_angle", "early_z", "bounds", "fit_isolines")
#: the positional parameters of render(), which a misspelt keyword may have meant
CALL_KEYWORDS = ("lights", "order", "shading", "scalars", "env_map", "window_size", "background")


def add_mescher(
    plotter: pv.Plotter,
    m: Any,
    order: object = None,
    shading: str = "flat",
    scalars: object = None,
    *,
    early_z: bool = True,
    bounds: object = None,
    fit_isolines: bool = True,
    **kwargs: Any,
) -> Layer:
    """Add a mescher to ``plotter``, flattened and drawn in the order's linear extension.

    Parameters
    ----------
    plotter : pyvista.Plotter
    m : meschers_igl.Mescher
    order, shading, scalars
        As in :func:`~pyvista_views.polydata.to_polydata`.
    early_z : bool, default: True
        Draw the indexed mesh front to back with a ``GL_LESS`` depth test (:func:`use_early_z`,
        fastest); ``False`` draws it back to front with VTK's default test, which also displays
        right where the scene is exported or drawn by another renderer (vtk.js, glTF).
    bounds : (xmin, xmax, ymin, ymax), optional
        The image extent the isolines are fitted to (they follow the visible surface, so they
        depend on the view; :meth:`Layer.update_isolines` refits them).  Default: the
        mescher's default bounds (:func:`~pyvista_views.camera.default_bounds`) in this window.
    fit_isolines : bool, default: True
        ``False`` leaves fitting the isolines to the caller (:class:`MescherScene` does it
        once its camera is set).
    **kwargs
        ``color`` (material colour), ``cmap``, ``clim``, ``isolines`` (a count of evenly spaced
        levels in ``clim`` or the levels; per-vertex scalars only), ``isoline_color``,
        ``isoline_width`` (2 pixels), ``ambient`` (0.2), ``diffuse`` (0.8), ``name``.

    Returns
    -------
    Layer
    """
    feature_angle = kwargs.pop("feature_angle", DEFAULT_FEATURE_ANGLE)
    if scalars is not None:  # a shading floor: each face stays close to its colour bar's
        kwargs.setdefault("ambient", SCALAR_AMBIENT)
        kwargs.setdefault("diffuse", 1.0 - SCALAR_AMBIENT)
    opts = _representation_kwargs(**kwargs)
    shading = as_choice(shading, "shading", SHADINGS)
    F = np.asarray(m.F)
    fields = as_scalars(scalars, np.asarray(m.xy).shape[0], F.shape[0])
    contour = None
    if _wants_isolines(opts["isolines"]):
        active = next(iter(fields.items()), None)
        if active is None or active[1][1] != "vertex":
            raise MescherError(
                "isolines: expected per-vertex scalars to contour, found "
                + ("no scalars" if active is None else "per-face scalars")
            )
        contour = (np.asarray(m.xy, dtype=np.float64), F, active[1][0])
    layout = _layout(shading, fields, False)  # isolines need no soup (see .isolines)
    front_to_back = layout != "soup" and bool(early_z)
    mesh = to_polydata(
        m,
        order=order,
        shading=shading,
        scalars=scalars,
        layout=layout,
        front_to_back=front_to_back,
        split_folds=False,  # done on the first baked relight, if ever (_use_baked)
        feature_angle=feature_angle,
    )
    if front_to_back:
        use_early_z(plotter.renderer)
    layer = _add_layer(
        plotter,
        mesh,
        "mescher",
        shading,
        layout,
        isoline_lift=0.0,
        contour=contour,
        early_z=front_to_back,
        **opts,
    )
    if layer._contour is not None and fit_isolines:
        if bounds is None:
            size = plotter.window_size
            bounds = default_bounds(xy_box(m.xy), (int(size[0]), int(size[1])))
        layer.update_isolines(plotter, bounds)
    return layer


def add_embedding(
    plotter: pv.Plotter,
    V: np.ndarray,
    F: np.ndarray,
    shading: str = "flat",
    scalars: object = None,
    **kwargs: Any,
) -> Layer:
    """Add a real 3D mesh (cut or bent embedding, or any mesh), z-buffered.

    Same camera, lights and material as :func:`add_mescher`, so a mescher and its embeddings line
    up pixel for pixel.  ``V`` is in the camera frame; other arguments as in :func:`add_mescher`.
    """
    feature_angle = kwargs.pop("feature_angle", DEFAULT_FEATURE_ANGLE)
    if scalars is not None:
        kwargs.setdefault("ambient", SCALAR_AMBIENT)
        kwargs.setdefault("diffuse", 1.0 - SCALAR_AMBIENT)
    opts = _representation_kwargs(**kwargs)
    shading = as_choice(shading, "shading", SHADINGS)
    V = np.asarray(V, dtype=np.float64)
    fields = as_scalars(scalars, V.shape[0] if V.ndim == 2 else -1, np.asarray(F).shape[0])
    layout = _layout(shading, fields, False)
    mesh = embedding_polydata(
        V, F, shading=shading, scalars=scalars, layout=layout, split_folds=False,
        feature_angle=feature_angle,
    )  # fmt: skip
    lift = 1e-4 * float(np.hypot(*np.ptp(np.asarray(mesh.points)[:, :2], axis=0)) or 1.0)
    return _add_layer(plotter, mesh, "embedding", shading, layout, isoline_lift=lift, **opts)


def _layout(shading: str, fields: dict, isolines: bool) -> str:
    if needs_soup(shading, fields, isolines):
        return "soup"
    return "provoking" if shading == "flat" and flat_varyings_work() else "indexed"


def _mapper_time(actor: Any) -> int:
    """VTK's modification time of an actor's mapper: a new actor (new mapper) or new geometry
    gets a new one (VTK's clock only grows), a relight (material, lights) does not."""
    mapper = actor.GetMapper() if hasattr(actor, "GetMapper") else None
    return int(mapper.GetMTime()) if mapper is not None else -id(actor)


def _use_vtk_lighting(layer: Layer) -> None:
    visible, mode, array, color_mode = layer._mapper_state
    mapper = layer.actor.mapper
    mapper.SetScalarVisibility(visible)
    mapper.SetScalarMode(mode)
    mapper.SelectColorArray(array)
    mapper.SetColorMode(color_mode)
    layer.actor.prop.lighting = True


def _split_folds(layer: Layer) -> None:
    """Give a smooth indexed layer separate vertices on folds before per-vertex baking (once)."""
    if layer.layout == "soup" or layer.shading != "smooth" or layer._folds_split:
        return
    mesh = split_folds(layer.mesh)
    if mesh is not layer.mesh:
        layer.actor.mapper.SetInputData(mesh)
        layer.mesh = mesh
    layer._folds_split = True


def _use_baked(
    layer: Layer, irradiance: np.ndarray, tone_map: str = "none", white: float = 1.0
) -> None:
    light = layer.ambient + layer.diffuse * irradiance
    rgb = layer.albedo() * tone_map_curve(light, white, tone_map)
    baked = np.clip(np.rint(255.0 * rgb), 0, 255).astype(np.uint8)
    mapper = layer.actor.mapper
    if layer.shading_location == "cell":
        layer.mesh.cell_data[_BAKED] = baked
        mapper.SetScalarModeToUseCellFieldData()
    else:
        layer.mesh.point_data[_BAKED] = baked
        mapper.SetScalarModeToUsePointFieldData()
    mapper.SetScalarVisibility(True)
    mapper.SelectColorArray(_BAKED)
    mapper.SetColorModeToDirectScalars()
    layer.actor.prop.lighting = False


def relight(
    plotter: pv.Plotter,
    layers: Sequence[Layer],
    lights: object = DEFAULT_LIGHTS,
    env_map: object = None,
    *,
    exposure: float = 1.0,
    tone_map: str = "none",
    normalize: bool = True,
) -> tuple[list[DirectionalLight], EnvironmentMap | None]:
    """Light every layer of ``plotter``; the geometry is not rebuilt.

    Each layer's matte material gives ``colour * (ambient + diffuse * s * E(n))`` with
    ``E(n) = E_env(n) + sum_i I_i max(0, n . l_i)``.  By default (``normalize``) the factor
    ``s`` keeps the brightest visible normal at ``ambient + diffuse * s * E <= 1``
    (:func:`~pyvista_views.lights.exposure_scale`): however many lights and whatever
    environment, nothing is brighter than the material's colour, so the figure never washes
    out into a white background; one light of intensity 1 is left as it is.  ``exposure``
    multiplies ``s``; ``tone_map="reinhard"`` then compresses what exceeds 1 instead of
    clipping it (:func:`~pyvista_views.lights.tone_map_curve`, white point at the brightest
    visible normal).

    Without an environment map or tone map the lights are VTK directional lights (the light
    kit and headlight removed, ``s`` folded into each layer's diffuse coefficient).  Otherwise
    VTK lighting is off and the formula is evaluated per face (flat indexed meshes) or per
    point (:mod:`.envmap`) and drawn as colours.  Call ``plotter.render()`` before a screenshot.

    Returns
    -------
    (list of DirectionalLight, EnvironmentMap or None)
        The validated lighting, for callers that keep it.
    """
    directional = as_lights(lights)
    env = as_env_map(env_map)
    tone_map = as_choice(tone_map, "tone_map", TONE_MAPS)
    exposure = as_positive(exposure, "exposure")
    peak = peak_irradiance(directional, env)
    scales = [exposure_scale(peak, la.ambient, la.diffuse, exposure, normalize) for la in layers]
    # VTK clamps a material's diffuse coefficient to [0, 1]: brighter than that is baked.
    fits = all(la.diffuse * s <= 1.0 for la, s in zip(layers, scales))
    if env is None and tone_map == "none" and fits:
        set_vtk_lights(plotter, directional)
        for layer, s in zip(layers, scales):
            _use_vtk_lighting(layer)
            layer.actor.prop.diffuse = layer.diffuse * s
    else:
        plotter.remove_all_lights()
        for layer, s in zip(layers, scales):
            layer.actor.prop.diffuse = layer.diffuse
            _split_folds(layer)
            n = layer.shading_normals()
            irradiance = lambert(n, directional)
            if env is not None:
                irradiance = irradiance + env.irradiance(n)
            white = layer.ambient + layer.diffuse * s * peak
            _use_baked(layer, s * irradiance, tone_map, white)
    return directional, env


class MescherScene:
    """A plotter with meschers and embeddings, a fixed head-on camera and a relightable rig.

    This is PyVista's plotter component ``plotter.mescher`` (:mod:`pyvista_views.plugin`):
    ``pv.Plotter().mescher`` is a scene bound to that plotter, and a scene that makes its own
    plotter is that plotter's ``.mescher``.

    Parameters
    ----------
    plotter : pyvista.Plotter, optional
        Use this plotter (its light kit is replaced by the scene's lights at the first layer); by
        default a new one (offscreen when ``pyvista.OFF_SCREEN`` is set or there is no display).
    window_size : (int, int), optional
        (width, height) in pixels of a new plotter (default 800 x 800), or of ``plotter``.
    background : color
        Of a new plotter.
    off_screen : bool, optional
    anti_aliasing : bool or {"fxaa", "ssaa", "msaa"}, optional
        Default :data:`~pyvista_views.headless.DEFAULT_ANTI_ALIASING` (FXAA);
        ``False`` keeps silhouettes pixel-exact (image measures)
        (:func:`~pyvista_views.headless.new_plotter`).
    early_z : bool, default: True
        :func:`add_mescher`'s drawing mode for every mescher added.

    Examples
    --------
    >>> pl = pv.Plotter(off_screen=True)                     # doctest: +SKIP
    >>> pl.mescher.add(m, order=order, shading="smooth")     # framed head-on, key light
    >>> a = pl.mescher.screenshot()                          # doctest: +SKIP
    >>> pl.mescher.relight((-1, 0, 1))                       # same geometry, new light
    >>> b = pl.mescher.screenshot()                          # doctest: +SKIP
    """

    def __init__(
        self,
        plotter: pv.Plotter | None = None,
        *,
        window_size: tuple[int, int] | None = None,
        background: object = "white",
        off_screen: bool | None = None,
        anti_aliasing: bool | str | None = None,
        early_z: bool = True,
    ) -> None:
        if plotter is None:
            self.window_size = as_window_size((800, 800) if window_size is None else window_size)
            if anti_aliasing is None:
                anti_aliasing = headless.DEFAULT_ANTI_ALIASING
            plotter = headless.new_plotter(self.window_size, off_screen, background, anti_aliasing)
            # This scene is the new plotter's component (what ``plotter.mescher`` would build).
            plotter.__dict__["mescher"] = self
            components = plotter.__dict__.setdefault("_components", [])
            components.append(self)
        else:
            if window_size is not None:
                plotter.window_size = list(as_window_size(window_size))
            self.window_size = as_window_size(tuple(plotter.window_size))
        self.plotter = plotter
        self.early_z = bool(early_z)
        self.layers: list[Layer] = []
        self.bounds: tuple[float, float, float, float] | None = None
        self.lights: list[DirectionalLight] = []
        self.env_map: EnvironmentMap | None = None
        self._lit = False
        self._box: list[tuple[float, float, float, float]] = []
        #: what the camera was last set for (see _frame): no second bounds pass per frame
        self._view_key: tuple | None = None
        self._reserve = 0.0  # share of the window's width kept for a colour bar
        self.exposure, self.tone_map, self.normalize = 1.0, "none", True
        #: paths and points on the visible surface, with the layer each lies on
        self.overlays: list[tuple[Any, Layer]] = []
        self._overlay_actors: list[Any] = []
        self._overlay_key: tuple | None = None

    # -- content ---------------------------------------------------------------------------
    def add(
        self,
        m: Any,
        order: object = None,
        shading: str = "flat",
        scalars: object = None,
        **kwargs: Any,
    ) -> Layer:
        """Add a mescher (:func:`add_mescher`), lit by the scene's lights (the key light of the
        study's rig until :meth:`relight` is called) and framed head-on unless :meth:`view`
        fixed the bounds."""
        kwargs.setdefault("early_z", self.early_z)
        self._box.append(xy_box(np.asarray(m.xy)))
        try:  # isolines are fitted by _frame, once the camera is set
            layer = add_mescher(
                self.plotter, m, order, shading, scalars, fit_isolines=False, **kwargs
            )
        except Exception:
            self._box.pop()
            raise
        layer.source = (np.asarray(m.xy, dtype=np.float64), np.asarray(m.F, dtype=np.int64))
        return self._adopt(layer)

    def add_embedding(
        self,
        m_or_V: Any,
        F: np.ndarray | None = None,
        kind: str | None = None,
        shading: str = "flat",
        scalars: object = None,
        **kwargs: Any,
    ) -> Layer:
        """Add a real mesh: ``add_embedding(V, F)`` or ``add_embedding(m, kind="cut"|"bent")``.

        For ``kind="cut"`` per-vertex ``scalars`` of the mescher are carried to the cut copies.
        """
        if kind is None:
            if F is None:
                raise MescherError("F: expected faces with V, or kind='cut'|'bent' with a mescher")
            V = m_or_V
            self._box.append(xy_box(np.asarray(V, dtype=float)[:, :2]))
        else:
            V, F, scalars = embedding_of(m_or_V, kind, scalars)
            self._box.append(xy_box(np.asarray(m_or_V.xy)))
        layer = add_embedding(self.plotter, V, F, shading, scalars, **kwargs)
        layer.depth = "z-buffer"
        layer.source = (
            np.ascontiguousarray(np.asarray(V, dtype=np.float64)[:, :2]),
            np.asarray(F, dtype=np.int64),
        )
        return self._adopt(layer)

    # -- marks on the visible surface ------------------------------------------------------
    def _overlay_layer(self, layer: Layer | None) -> Layer:
        if layer is not None:
            return layer
        drawn = [la for la in self.layers if la.source is not None]
        if not drawn:
            raise MescherError("layer: expected a mescher added before its paths, found none")
        return drawn[-1]

    def add_path(
        self,
        path: Any,
        *,
        color: object = None,
        width: float = 3.0,
        hidden: str = "omit",
        label: str | None = None,
        layer: Layer | None = None,
    ) -> None:
        """Draw a polyline on a mescher's surface where that surface is the visible one.

        Parameters
        ----------
        path : SurfacePath or (xy (n, 2), faces (n,))
            Segment ``k`` lies in face ``faces[k]`` of the layer's mescher (e.g.
            ``m.shortest_path(...)`` or a closed geodesic of ``shortest_loops(m)``).
        color : color, optional
            Default: the next of :data:`~pyvista_views.overlays.PATH_COLORS`.
        width : float
            Pixels.
        hidden : {"omit", "dashed"}
            Pieces on sheets hidden by others are left out, or drawn dashed.
        label : str, optional
            Placed beside the path's longest visible run, clear of other labels.
        layer : Layer, optional
            Default: the last layer added.
        """
        layer = self._overlay_layer(layer)
        n_paths = sum(isinstance(mark, PathMark) for mark, _ in self.overlays)
        spec = {"path": path, "width": width, "hidden": hidden, "label": label}
        if color is not None:
            spec["color"] = color
        (mark,) = as_path_marks(spec, layer.source[1].shape[0])
        if color is None:
            mark.color = PATH_COLORS[n_paths % len(PATH_COLORS)]
        self.overlays.append((mark, layer))
        self._overlay_key = None
        self._frame()

    def add_points(
        self,
        vertices: Any,
        *,
        color: object = "white",
        radius: float = 5.0,
        labels: Sequence[str] | None = None,
        layer: Layer | None = None,
    ) -> None:
        """Mark vertices with discs where they lie on the visible surface.

        A disc is clipped to the figure's outline (it never spills onto the background); a
        vertex on a hidden sheet gets no disc.  ``radius`` is in pixels; ``labels`` (one per
        vertex) are placed beside the discs, clear of other labels.
        """
        layer = self._overlay_layer(layer)
        spec = {"vertices": vertices, "color": color, "radius": radius}
        if labels is not None:
            spec["labels"] = list(labels)
        (mark,) = as_point_marks(spec, layer.source[0].shape[0])
        self.overlays.append((mark, layer))
        self._overlay_key = None
        self._frame()

    def _fit_overlays(self, bounds: tuple[float, float, float, float]) -> None:
        """(Re)draw the paths, points and labels for the image ``bounds`` (once per view)."""
        window = (int(self.plotter.window_size[0]), int(self.plotter.window_size[1]))
        key = (tuple(float(b) for b in bounds), window, len(self.overlays))
        if not self.overlays or key == self._overlay_key:
            return
        for actor in self._overlay_actors:
            self.plotter.remove_actor(actor, render=False)
        self._overlay_actors = []
        top = max(float(la.mesh.bounds[5]) for la in self.layers)
        lift = 1e-3 * float(np.hypot(bounds[1] - bounds[0], bounds[3] - bounds[2]))
        labels: list[tuple[np.ndarray, str, Any]] = []
        for i, (mark, layer) in enumerate(self.overlays):
            xy, F = layer.source
            face_map = layer.face_map(self.plotter, bounds)
            z = top + lift * (2 + i)
            if isinstance(mark, PathMark):
                labels += self._draw_path(mark, xy, F, face_map, bounds, z)
            else:
                labels += self._draw_points(mark, xy, F, face_map, bounds, z)
        if labels:
            self._draw_labels(labels, bounds, window)
        self._overlay_key = key

    def _draw_path(self, mark: PathMark, xy, F, face_map, bounds, z: float) -> list:
        p0, p1, visible, arc = clip_polyline(mark.xy, mark.faces, F, face_map, bounds)
        keep = visible.copy()
        if mark.hidden == "dashed":  # 6 pixels on, 4 off along the hidden pieces
            keep |= ~visible & (np.mod(arc, 10.0) < 6.0)
        lines = polyline_pieces_mesh(p0[keep], p1[keep], z)
        if lines.n_cells:
            self._overlay_actors.append(
                self.plotter.add_mesh(
                    lines,
                    color=mark.color,
                    line_width=mark.width,
                    lighting=False,
                    show_scalar_bar=False,
                    reset_camera=False,
                )  # fmt: skip
            )
        if mark.label is None or not visible.any():
            return []
        # the label's anchor: the middle of the longest visible run
        edges = np.flatnonzero(np.diff(np.concatenate([[0], visible.astype(np.int8), [0]])))
        starts, ends = edges[::2], edges[1::2]
        j = int(np.argmax(ends - starts))
        mid = (starts[j] + ends[j]) // 2
        return [(0.5 * (p0[mid] + p1[mid]), mark.label, mark.color)]

    def _draw_points(self, mark: PointMark, xy, F, face_map, bounds, z: float) -> list:
        vertex_face = np.empty(xy.shape[0], dtype=np.int64)
        vertex_face[F.reshape(-1)] = np.repeat(np.arange(F.shape[0]), 3)
        seen = visible_vertices(mark.vertices, xy, F, vertex_face, face_map, bounds)
        pixel = (bounds[1] - bounds[0]) / face_map.shape[1]
        out = []
        for k, v in enumerate(mark.vertices):  # a few marked vertices
            if not seen[k]:
                continue
            T, rim = disc_on_figure(xy[v], mark.radius * pixel, xy, F)
            if T.shape[0] == 0:
                continue
            self._overlay_actors.append(
                self.plotter.add_mesh(
                    triangles_mesh(T, z),
                    color=mark.color,
                    lighting=False,
                    show_scalar_bar=False,
                    reset_camera=False,
                )
            )
            for line in rim:
                P = np.column_stack([line, np.full(line.shape[0], z + 1e-6 * pixel)])
                self._overlay_actors.append(
                    self.plotter.add_mesh(
                        pv.lines_from_points(P),
                        color="black",
                        line_width=1.5,
                        lighting=False,
                        show_scalar_bar=False,
                        reset_camera=False,
                    )
                )
            if mark.labels is not None:
                out.append((xy[v], mark.labels[k], "black"))
        return out

    def _draw_labels(self, labels: list, bounds, window: tuple[int, int]) -> None:
        from vtkmodules.vtkRenderingCore import vtkTextRenderer

        W, H = window
        size = label_font_size(window)
        measure, box = vtkTextRenderer(), [0, 0, 0, 0]
        actors, sizes = [], []
        for _, text, color in labels:
            actor = self.plotter.add_text(text, position=(0, 0), color=color)
            tp = actor.GetTextProperty()
            tp.SetFontSize(size)  # VTK's font size: the line height in pixels
            tp.SetBackgroundColor(1.0, 1.0, 1.0)
            tp.SetBackgroundOpacity(0.75)
            measure.GetBoundingBox(tp, text, box, self.plotter.render_window.GetDPI())
            actors.append(actor)
            sizes.append((box[1] - box[0] + 4.0, box[3] - box[2] + 4.0))
        P = np.array([p for p, _, _ in labels], dtype=np.float64)
        anchors = np.column_stack(
            [
                (P[:, 0] - bounds[0]) / (bounds[1] - bounds[0]) * W,
                (bounds[3] - P[:, 1]) / (bounds[3] - bounds[2]) * H,
            ]
        )
        for (x0, y0), (_w, h), actor in zip(place_labels(anchors, sizes, (W, H)), sizes, actors):
            actor.SetPosition(int(x0 + 2), int(H - y0 - h + 2))
            self._overlay_actors.append(actor)

    def _adopt(self, layer: Layer) -> Layer:
        self.layers.append(layer)
        if not self._lit:
            self.relight(DEFAULT_LIGHTS)
        else:  # the new layer's material takes the scene's exposure
            relight(self.plotter, [layer], self.lights, self.env_map, **self._exposure())
        self._frame()
        return layer

    def _frame(self) -> tuple[float, float, float, float]:
        """Point the camera (fixed bounds, or every layer's box) and fit the isolines to it.

        The z range may have grown with a layer (or with isolines), so the camera is set last.
        """
        bounds = self.bounds if self.bounds is not None else self._auto_bounds()
        for layer in self.layers:
            layer.update_isolines(self.plotter, bounds)
        self._fit_overlays(bounds)
        # set_view costs a bounds pass over every point (7 ms at 1M): skip it when neither the
        # image bounds, the window, the scene's actors nor the camera changed since the last
        # time (a relit frame); any other camera change (a user's) is undone as before
        renderer = self.plotter.renderer
        key = (
            tuple(float(b) for b in bounds),
            tuple(int(w) for w in self.plotter.window_size),
            tuple(_mapper_time(a) for a in renderer.actors.values()),
        )
        camera = renderer.GetActiveCamera()
        if self._view_key is None or self._view_key != (key, camera.GetMTime()):
            set_view(self.plotter, bounds)
            self._view_key = (key, camera.GetMTime())
        return bounds

    def clear(self) -> None:
        """Remove every layer and colour bar (lights and camera stay)."""
        for title in list(self.plotter.scalar_bars.keys()):
            self.plotter.remove_scalar_bar(title, render=False)
        for layer in self.layers:
            self.plotter.remove_actor(layer.actor, render=False)
            if layer.isolines is not None:
                self.plotter.remove_actor(layer.isolines, render=False)
        for actor in self._overlay_actors:
            self.plotter.remove_actor(actor, render=False)
        self._overlay_actors, self.overlays, self._overlay_key = [], [], None
        self.layers.clear()
        self._box.clear()

    # -- camera and light ------------------------------------------------------------------
    def _auto_bounds(self, margin: float = DEFAULT_MARGIN) -> tuple[float, float, float, float]:
        if not self._box:
            raise MescherError("bounds: expected bounds or at least one layer, found neither")
        boxes = np.array(self._box)
        box = (boxes[:, 0].min(), boxes[:, 1].max(), boxes[:, 2].min(), boxes[:, 3].max())
        size = self.plotter.window_size
        return default_bounds(box, (int(size[0]), int(size[1])), margin, reserve=self._reserve)

    def view(self, bounds: object = None, margin: float = DEFAULT_MARGIN) -> tuple:
        """Fix the camera; ``bounds=None`` frames every layer's xy box plus ``margin`` (and
        leaves the colour bar's strip free, :meth:`add_scalar_bar`)."""
        self.bounds = as_bounds(self._auto_bounds(margin) if bounds is None else bounds)
        self._frame()
        return self.bounds

    def reserve_scalar_bar(self, share: float | bool = True) -> None:
        """Keep the window's right ``share`` (default :func:`scalar_bar_strip`; ``False``: none) free
        for a colour bar or a panel when framing by default (call it before adding layers to
        frame them, and fit their isolines, once)."""
        if share is True:
            share = scalar_bar_strip(int(self.plotter.window_size[0]))
        self._reserve = float(share or 0.0)

    def add_scalar_bar(
        self, title: str | None = None, layer: Layer | None = None, **kwargs: Any
    ) -> Any:
        """A vertical colour bar with a title in a strip on the right, beside the figure.

        Unless :meth:`view` fixed the bounds, the figure is framed in the window's left
        ``1 - scalar_bar_strip(width)`` so the bar never covers it.

        Parameters
        ----------
        title : str, optional
            Default: the layer's scalar name.
        layer : Layer, optional
            Default: the last layer with scalars.
        **kwargs
            Passed to :meth:`pyvista.Plotter.add_scalar_bar` (``fmt``, ``n_labels``, ...).

        Returns
        -------
        vtkScalarBarActor
        """
        if layer is None:
            with_scalars = [la for la in self.layers if la.scalars is not None]
            if not with_scalars:
                raise MescherError(
                    "layer: expected a layer with scalars for a colour bar, found none"
                )
            layer = with_scalars[-1]
        title = (layer.title if title is None else str(title)) or " "
        if self._reserve < scalar_bar_strip(int(self.plotter.window_size[0])):
            self.reserve_scalar_bar()
        if len(title) > 12 and " " in title and "\n" not in title:  # two lines, split mid-way
            spaces = [i for i, c in enumerate(title) if c == " "]
            cut = min(spaces, key=lambda i: abs(i - len(title) / 2))
            title = title[:cut] + "\n" + title[cut + 1 :]
        longest = max(len(line) for line in title.split("\n"))
        strip = self._reserve
        # Text sized to the window, and the title to the strip (a glyph is ~0.6 em wide):
        # readable at 800 x 800, never wider than the strip.
        width_px, height_px = (int(v) for v in self.plotter.window_size)
        box_px = float(kwargs.get("width", strip - 0.04)) * width_px
        # ... and at least MIN_LABEL_PX where the strip has room (scalar_bar_strip)
        title_size = int(
            max(6, min(max(height_px / 30, MIN_LABEL_PX), 1.1 * box_px / (0.6 * longest)))
        )
        label_size = int(max(6, min(max(height_px / 36, MIN_LABEL_PX), 0.55 * box_px / (0.6 * 6))))
        options = dict(
            title=title,
            title_font_size=title_size,
            label_font_size=label_size,
            unconstrained_font_size=True,
            mapper=layer.actor.mapper,
            vertical=True,
            position_x=1.0 - strip + 0.02,
            position_y=0.12,
            width=strip - 0.04,
            height=0.76,
            n_labels=5,
            fmt="%.3g",
            color="black",
            bold=False,
            fill=False,
        )
        options.update(kwargs)
        actor = self.plotter.add_scalar_bar(**options)
        values = layer.mesh.active_scalars
        if values is not None and np.isnan(np.asarray(values, dtype=np.float64)).any():
            actor.SetDrawNanAnnotation(True)  # its own swatch under the bar
            actor.SetNanAnnotation("unreached")
        _exact_zero_labels(actor, layer.actor.mapper.GetScalarRange(), int(options["n_labels"]))
        # the top label sits half above the bar: keep the title clear of it
        actor.SetVerticalTitleSeparation(int(options["label_font_size"]))
        if self.layers:
            self._frame()
        return actor

    def relight(
        self,
        lights: object = DEFAULT_LIGHTS,
        env_map: object = None,
        *,
        exposure: float | None = None,
        tone_map: str | None = None,
        normalize: bool | None = None,
    ) -> None:
        """Change the lighting of every layer (no geometry rebuilt); see :func:`relight`.

        ``lights`` may be one direction ``(x, y, z)`` toward a light (``relight((1, 0, 1))``).
        ``exposure``, ``tone_map`` and ``normalize`` are kept for later relights and layers
        (defaults 1, ``"none"``, True).
        """
        if exposure is not None:
            self.exposure = exposure
        if tone_map is not None:
            self.tone_map = tone_map
        if normalize is not None:
            self.normalize = bool(normalize)
        self.lights, self.env_map = relight(
            self.plotter, self.layers, lights, env_map, **self._exposure()
        )
        self._lit = True

    def _exposure(self) -> dict:
        return {"exposure": self.exposure, "tone_map": self.tone_map, "normalize": self.normalize}

    def screenshot(self) -> np.ndarray:
        """(H, W, 3) uint8 of the current state (renders first, as VTK needs after a relight)."""
        if self.bounds is None:
            self.view()
        else:
            self._frame()  # isolines follow a changed window size
        self.plotter.render()
        image = self.plotter.screenshot(return_img=True, transparent_background=False)
        return np.ascontiguousarray(image[..., :3])

    def close(self) -> None:
        """Release the plotter and its GL context."""
        self.plotter.close()

    def __plotter_close__(self) -> None:
        """PyVista's component hook: drop the layers with the plotter."""
        self.layers.clear()
        self._box.clear()

    def __enter__(self) -> MescherScene:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def embedding_of(m: Any, kind: str, scalars: object = None) -> tuple:
    """``(V, F, scalars)`` of the cut or bent embedding of ``m`` (DESIGN ``cut_embedding`` and
    ``bent_embedding``), with per-vertex mescher scalars carried to the cut's vertex copies."""
    kind = as_choice(kind, "kind", ("cut", "bent"))
    method = f"{kind}_embedding"
    if not hasattr(m, method):
        raise MescherError(
            f"m: expected a Mescher with {method}() (meschers_igl embedding module), found "
            f"{type(m).__name__} without it"
        )
    if kind == "bent":
        V, F = getattr(m, method)()
        return V, F, scalars
    V, F, vmap = m.cut_embedding()
    if scalars is None:
        return V, F, None
    vmap = np.asarray(vmap, dtype=np.int64)
    n_v, n_f = np.asarray(m.xy).shape[0], np.asarray(m.F).shape[0]

    def carry(values: Any) -> Any:
        a = np.asarray(values)
        if a.ndim == 1 and a.shape[0] == n_v and n_v != n_f:
            return a[vmap]
        return a

    if isinstance(scalars, dict):
        return V, F, {k: carry(v) for k, v in scalars.items()}
    return V, F, carry(scalars)


def _exact_zero_labels(actor: Any, scalar_range: Sequence[float], n_labels: int) -> None:
    """Label the bar at evenly spaced values, the inner ones rounded to 1/100 of the range.

    VTK labels the bar at ``lo + k (hi - lo) / (n - 1)``; for a symmetric range the middle
    value is round-off (``1.74e-13``), printed as such. Custom labels carry the same values
    with that round-off removed.
    """
    if n_labels < 2:
        return
    from vtkmodules.vtkCommonCore import vtkDoubleArray

    lo, hi = (float(v) for v in scalar_range)
    values = np.linspace(lo, hi, n_labels)
    span = abs(hi - lo)
    if span > 0:
        # a bar shows about 1/100 of its span: inner labels are rounded to that (the middle of
        # (-0.582, 0.578) reads 0, not -0.00178; of (-0.593, 0.5929) 0, not -3.21e-05); the
        # ends stay the data's range
        digits = int(2 - np.floor(np.log10(span)))
        values[1:-1] = np.round(values[1:-1], digits) + 0.0  # + 0.0: no "-0"
    values[np.abs(values) <= 1e-3 * span] = 0.0
    labels = vtkDoubleArray()
    for v in values:
        labels.InsertNextValue(v)
    actor.SetCustomLabels(labels)
    actor.SetUseCustomLabels(True)
