"""Layers: a mescher or a real mesh put into a :class:`pyvista.Plotter`, and their lighting.

:func:`add_mescher` / :func:`add_embedding` add a mescher (flattened, drawn in the order's
linear extension) or a real mesh (z-buffered) and return a :class:`Layer`; :func:`relight`
lights every layer of a plotter, with VTK directional lights or, for an environment map, with
irradiance baked per face or per vertex.  :class:`~pyvista_views.scene.MescherScene` builds on
them (see :mod:`pyvista_views.scene` for how a mescher is drawn).
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

from .camera import as_bounds, default_bounds, xy_box
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
        V,
        F,
        shading=shading,
        scalars=scalars,
        layout=layout,
        split_folds=False,
        feature_angle=feature_angle,
    )
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
