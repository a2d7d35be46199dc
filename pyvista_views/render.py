"""Head-on rendering of meschers and of real meshes with one camera, one light rig, one path.

Every picture of the project goes through two functions:

- :func:`add_mescher` / :func:`add_embedding` put a mescher (flattened, painter-ordered soup) or a
  real mesh (z-buffered soup) into a :class:`pyvista.Plotter` and return a :class:`Layer`;
- :func:`relight` lights every layer of a plotter, with VTK directional lights or, for an
  environment map, with irradiance baked per corner.

:class:`MescherScene` keeps a plotter, its layers and the camera together (the plotter component
``plotter.mescher`` of issue 9 is meant to be this class), and :func:`render` is the one-shot
wrapper of DESIGN.md.  The camera is always orthographic, looking down -z with y up, so the camera
frame of DESIGN.md is the scene frame and ``bounds = (xmin, xmax, ymin, ymax)`` is exactly the
image's extent.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import numpy_to_vtk

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_choice, as_float_array, as_positive

from . import _offscreen
from .envmap import EnvironmentMap, as_env_map
from .lights import DirectionalLight, as_lights, lambert, set_vtk_lights
from .polydata import SHADINGS, embedding_polydata, to_polydata

#: Matte grey: lit faces stay below the white background (silhouettes are measurable).
DEFAULT_COLOR = (0.85, 0.85, 0.85)
DEFAULT_LIGHTS = ((1.0, 1.0, 1.0),)
DEFAULT_MARGIN = 0.05
REPRESENTATIONS = ("mescher", "cut", "bent")
_BAKED = "_shaded_rgb"


@dataclass
class Layer:
    """One mescher or real mesh in a plotter.

    Attributes
    ----------
    mesh : pyvista.PolyData
        The soup being drawn (:func:`~pyvista_views.polydata.to_polydata`).
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
    _mapper_state: tuple = field(default=(), repr=False)

    @property
    def xy_box(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the layer on screen."""
        b = self.mesh.bounds
        return (b[0], b[1], b[2], b[3])

    def corner_normals(self) -> np.ndarray:
        """(3k, 3) unit normals per soup corner, as the shader sees them.

        VTK's two-sided lighting flips the normal of a triangle whose screen winding is
        clockwise; baked shading does the same so both paths agree.
        """
        if self.shading == "flat":
            n = np.repeat(np.asarray(self.mesh.cell_data.active_normals), 3, axis=0)
        else:
            n = np.asarray(self.mesh.point_data.active_normals, dtype=np.float64)
        p = np.asarray(self.mesh.points).reshape(-1, 3, 3)
        e1, e2 = p[:, 1, :2] - p[:, 0, :2], p[:, 2, :2] - p[:, 0, :2]
        facing = np.where(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0, -1.0, 1.0)
        return n * np.repeat(facing, 3)[:, None]

    def corner_albedo(self) -> np.ndarray:
        """(3k, 3) linear RGB base colour per corner (colour-mapped scalars or the colour)."""
        n_points = self.mesh.n_points
        if self.scalars is None:
            return np.broadcast_to(np.asarray(self.color, float), (n_points, 3))
        if self.scalars in self.mesh.point_data:
            values = np.asarray(self.mesh.point_data[self.scalars], dtype=np.float64)
        else:
            values = np.repeat(np.asarray(self.mesh.cell_data[self.scalars], float), 3)
        lut = self.actor.mapper.lookup_table
        rgba = lut.MapScalars(numpy_to_vtk(np.ascontiguousarray(values)), 0, -1)
        from vtkmodules.util.numpy_support import vtk_to_numpy

        return vtk_to_numpy(rgba).reshape(n_points, -1)[:, :3] / 255.0


def _check_material(color: object, ambient: float, diffuse: float) -> tuple:
    rgb = tuple(float(c) for c in as_float_array(pv.Color(color).float_rgb, "color", (3,)))
    return (
        rgb,
        as_positive(ambient, "ambient", allow_zero=True),
        as_positive(diffuse, "diffuse", allow_zero=True),
    )


def _add_soup(
    plotter: pv.Plotter,
    mesh: pv.PolyData,
    kind: str,
    shading: str,
    *,
    color: object,
    cmap: str,
    clim: Sequence[float] | None,
    isolines: int | Sequence[float],
    isoline_color: object,
    isoline_lift: float,
    ambient: float,
    diffuse: float,
    name: str | None,
) -> Layer:
    rgb, ambient, diffuse = _check_material(color, ambient, diffuse)
    active = mesh.active_scalars_name  # set by the soup builders from the user's fields only
    if active is not None and clim is None:
        values = mesh.active_scalars
        clim = (float(np.min(values)), float(np.max(values)))
    actor = plotter.add_mesh(
        mesh,
        color=rgb,
        scalars=active,
        cmap=cmap if active is not None else None,
        clim=clim,
        show_scalar_bar=False,
        ambient=ambient,
        diffuse=diffuse,
        specular=0.0,
        interpolation="flat" if shading == "flat" else "gouraud",
        smooth_shading=False,  # would recompute normals from the flat geometry (FACTS.md)
        lighting=True,
        name=name,
        reset_camera=False,
    )
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
        _mapper_state=(
            mapper.GetScalarVisibility(),
            mapper.GetScalarMode(),
            mapper.GetArrayName(),
            mapper.GetColorMode(),
        ),
    )
    if not (isinstance(isolines, (int, np.integer)) and isolines == 0):
        layer.isolines = _add_isolines(plotter, layer, isolines, clim, isoline_color, isoline_lift)
    return layer


def _add_isolines(
    plotter: pv.Plotter,
    layer: Layer,
    isolines: int | Sequence[float],
    clim: Sequence[float] | None,
    color: object,
    lift: float,
) -> Any:
    """Contours of the active per-vertex scalars, computed on the drawn soup.

    Every segment lies inside one face.  A line is a few pixels wide, so it spills onto the
    faces around its own; on a real mesh those are at about the same depth and a lift of ``lift``
    toward the viewer suffices.  On a mescher the neighbours may be drawn much later (the painter
    order is only partial), so a segment of the face drawn k-th is put just above the latest-drawn
    face sharing a vertex with it: it stays hidden by faces drawn after its whole neighbourhood
    (real occluders) without being chopped by its own neighbours.
    """
    if layer.scalars is None or layer.scalars not in layer.mesh.point_data:
        raise MescherError(
            "isolines: expected per-vertex scalars to contour, found "
            + ("no scalars" if layer.scalars is None else "per-face scalars")
        )
    if isinstance(isolines, (int, np.integer)):
        if isolines < 0:
            raise MescherError(f"isolines: expected a count >= 0 or levels, found {isolines}")
        lo, hi = clim
        levels = np.linspace(lo, hi, int(isolines) + 2)[1:-1]
    else:
        levels = as_float_array(isolines, "isolines", (-1,))
    lines = layer.mesh.contour(isosurfaces=levels, scalars=layer.scalars)
    if lines.n_points == 0:
        return None
    if layer.kind == "mescher":
        step = float(layer.mesh.field_data["painter_step"][0])
        corners = np.asarray(layer.mesh.point_data["vertex_id"]).reshape(-1, 3)
        k = corners.shape[0]
        latest = np.full(int(corners.max()) + 1, -1, dtype=np.int64)
        np.maximum.at(latest, corners.reshape(-1), np.repeat(np.arange(k), 3))
        neighbourhood = latest[corners].max(axis=1)  # (k,) latest rank around each drawn face
        rank = np.clip(np.rint(lines.points[:, 2] / step).astype(np.int64), 0, k - 1)
        lines.points[:, 2] = (neighbourhood[rank] + 0.5) * step
    else:
        lines.points[:, 2] += lift
    return plotter.add_mesh(
        lines,
        color=color,
        line_width=1.5,
        lighting=False,
        show_scalar_bar=False,
        reset_camera=False,
    )


def _representation_kwargs(**kw: Any) -> dict:
    return {
        "color": kw.pop("color", DEFAULT_COLOR),
        "cmap": kw.pop("cmap", "viridis"),
        "clim": kw.pop("clim", None),
        "isolines": kw.pop("isolines", 0),
        "isoline_color": kw.pop("isoline_color", "black"),
        "ambient": kw.pop("ambient", 0.2),
        "diffuse": kw.pop("diffuse", 0.8),
        "name": kw.pop("name", None),
    }


def add_mescher(
    plotter: pv.Plotter,
    m: Any,
    order: object = None,
    shading: str = "flat",
    scalars: object = None,
    **kwargs: Any,
) -> Layer:
    """Add a mescher to ``plotter`` as a flattened soup drawn back to front.

    Parameters
    ----------
    plotter : pyvista.Plotter
    m : meschers_igl.Mescher
    order, shading, scalars
        As in :func:`~pyvista_views.polydata.to_polydata`.
    **kwargs
        ``color`` (material colour), ``cmap``, ``clim``, ``isolines`` (a count of evenly spaced
        levels in ``clim`` or the levels), ``isoline_color``, ``ambient`` (0.2), ``diffuse`` (0.8),
        ``name``.

    Returns
    -------
    Layer
    """
    opts = _representation_kwargs(**kwargs)
    mesh = to_polydata(m, order=order, shading=shading, scalars=scalars)
    lift = 0.5 * float(mesh.field_data["painter_step"][0])
    return _add_soup(plotter, mesh, "mescher", shading.lower(), isoline_lift=lift, **opts)


def add_embedding(
    plotter: pv.Plotter,
    V: np.ndarray,
    F: np.ndarray,
    shading: str = "flat",
    scalars: object = None,
    **kwargs: Any,
) -> Layer:
    """Add a real 3D mesh (cut or bent embedding, or any mesh) as a z-buffered soup.

    Same camera, lights and material as :func:`add_mescher`, so a mescher and its embeddings line
    up pixel for pixel.  ``V`` is in the camera frame; other arguments as in :func:`add_mescher`.
    """
    opts = _representation_kwargs(**kwargs)
    mesh = embedding_polydata(V, F, shading=shading, scalars=scalars)
    lift = 1e-4 * float(np.hypot(*np.ptp(np.asarray(mesh.points)[:, :2], axis=0)) or 1.0)
    return _add_soup(plotter, mesh, "embedding", shading.lower(), isoline_lift=lift, **opts)


def _use_vtk_lighting(layer: Layer) -> None:
    visible, mode, array, color_mode = layer._mapper_state
    mapper = layer.actor.mapper
    mapper.SetScalarVisibility(visible)
    mapper.SetScalarMode(mode)
    mapper.SelectColorArray(array)
    mapper.SetColorMode(color_mode)
    layer.actor.prop.lighting = True


def _use_baked(layer: Layer, irradiance: np.ndarray) -> None:
    rgb = layer.corner_albedo() * (layer.ambient + layer.diffuse * irradiance)
    layer.mesh.point_data[_BAKED] = np.clip(np.rint(255.0 * rgb), 0, 255).astype(np.uint8)
    mapper = layer.actor.mapper
    mapper.SetScalarVisibility(True)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(_BAKED)
    mapper.SetColorModeToDirectScalars()
    layer.actor.prop.lighting = False


def relight(
    plotter: pv.Plotter,
    layers: Sequence[Layer],
    lights: object = DEFAULT_LIGHTS,
    env_map: object = None,
) -> tuple[list[DirectionalLight], EnvironmentMap | None]:
    """Light every layer of ``plotter``; the geometry is not rebuilt.

    Without an environment map the lights are VTK directional lights (the light kit and
    headlight removed) and each layer's matte material gives
    ``colour * (ambient + diffuse * sum_i I_i max(0, n . l_i))``.  With one, VTK lighting is off
    and the same formula with ``E_env(n) + sum_i ...`` as irradiance is evaluated per corner
    (:mod:`.envmap`) and drawn as colours.  Call ``plotter.render()`` before a screenshot.

    Returns
    -------
    (list of DirectionalLight, EnvironmentMap or None)
        The validated lighting, for callers that keep it.
    """
    directional = as_lights(lights)
    env = as_env_map(env_map)
    if env is None:
        set_vtk_lights(plotter, directional)
        for layer in layers:
            _use_vtk_lighting(layer)
    else:
        plotter.remove_all_lights()
        for layer in layers:
            n = layer.corner_normals()
            _use_baked(layer, env.irradiance(n) + lambert(n, directional))
    return directional, env


def default_bounds(
    box: Sequence[float], window_size: Sequence[int], margin: float = DEFAULT_MARGIN
) -> tuple[float, float, float, float]:
    """``box`` (xmin, xmax, ymin, ymax) grown by ``margin`` of its size, then widened in x or y to
    the window's aspect ratio so that pixels are square."""
    xmin, xmax, ymin, ymax = (float(b) for b in box)
    w, h = xmax - xmin, ymax - ymin
    size = max(w, h) or 1.0
    w, h = max(w, 1e-9 * size), max(h, 1e-9 * size)
    cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
    w, h = w * (1 + 2 * margin), h * (1 + 2 * margin)
    aspect = window_size[0] / window_size[1]
    if w / h < aspect:
        w = h * aspect
    else:
        h = w / aspect
    return (cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2)


def as_bounds(bounds: object) -> tuple[float, float, float, float]:
    """Validate ``(xmin, xmax, ymin, ymax)`` with ``xmin < xmax`` and ``ymin < ymax``."""
    b = as_float_array(bounds, "bounds", (4,))
    if not (b[0] < b[1] and b[2] < b[3]):
        raise MescherError(
            f"bounds: expected (xmin, xmax, ymin, ymax) with xmin < xmax and ymin < ymax, "
            f"found {tuple(b.tolist())}"
        )
    return tuple(float(v) for v in b)


def set_view(plotter: pv.Plotter, bounds: Sequence[float]) -> None:
    """Orthographic camera down -z, y up, whose image is exactly ``bounds`` (xmin, xmax, ymin,
    ymax): the vertical extent is ``2 * parallel_scale`` and an explicit aspect ratio fixes the
    horizontal one (pixels are square only when the window has the same aspect as ``bounds``).
    The clipping range hugs the scene's z range so the painter's steps stay resolvable in the
    depth buffer."""
    xmin, xmax, ymin, ymax = as_bounds(bounds)
    zmin, zmax = plotter.bounds[4], plotter.bounds[5]
    if not np.isfinite([zmin, zmax]).all() or zmax < zmin:  # empty scene
        zmin, zmax = 0.0, 0.0
    size = max(xmax - xmin, ymax - ymin)
    pad = 0.01 * (zmax - zmin) + 1e-6 * size
    distance = size + pad
    camera = plotter.camera
    camera.parallel_projection = True
    cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
    camera.focal_point = (cx, cy, zmin)
    camera.position = (cx, cy, zmax + distance)
    camera.up = (0.0, 1.0, 0.0)
    camera.parallel_scale = 0.5 * (ymax - ymin)
    camera.SetExplicitAspectRatio((xmax - xmin) / (ymax - ymin))
    camera.SetUseExplicitAspectRatio(True)
    camera.clipping_range = (distance - pad, distance + (zmax - zmin) + pad)
    plotter.camera_set = True


class MescherScene:
    """A plotter with meschers and embeddings, a fixed head-on camera and a relightable rig.

    Parameters
    ----------
    plotter : pyvista.Plotter, optional
        Use this plotter (its light kit is removed at the first :meth:`relight`); by default a new
        one (offscreen when ``pyvista.OFF_SCREEN`` is set or there is no display).
    window_size : (int, int)
        (width, height) in pixels for a new plotter.
    background : color
    off_screen : bool, optional
    anti_aliasing : bool
        Off by default so that image extents and silhouettes are exact.

    Examples
    --------
    >>> scene = MescherScene(window_size=(400, 400))          # doctest: +SKIP
    >>> scene.add(m, order=order, shading="smooth")           # doctest: +SKIP
    >>> scene.view(); scene.relight([(1, 1, 1)])              # doctest: +SKIP
    >>> a = scene.screenshot(); scene.relight([(-1, 0, 1)])   # doctest: +SKIP
    >>> b = scene.screenshot()                                # same geometry, new light
    """

    def __init__(
        self,
        plotter: pv.Plotter | None = None,
        *,
        window_size: tuple[int, int] = (800, 800),
        background: object = "white",
        off_screen: bool | None = None,
        anti_aliasing: bool = False,
    ) -> None:
        self.window_size = _as_window_size(window_size)
        if plotter is None:
            plotter = _offscreen.new_plotter(
                self.window_size, off_screen, background, anti_aliasing
            )
        self.plotter = plotter
        self.layers: list[Layer] = []
        self.bounds: tuple[float, float, float, float] | None = None
        self.lights: list[DirectionalLight] = []
        self.env_map: EnvironmentMap | None = None
        self._box: list[tuple[float, float, float, float]] = []

    # -- content ---------------------------------------------------------------------------
    def add(
        self,
        m: Any,
        order: object = None,
        shading: str = "flat",
        scalars: object = None,
        **kwargs: Any,
    ) -> Layer:
        """Add a mescher (:func:`add_mescher`); it is lit by the current lights."""
        layer = add_mescher(self.plotter, m, order, shading, scalars, **kwargs)
        self._box.append(_xy_box(np.asarray(m.xy)))
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
            self._box.append(_xy_box(np.asarray(V, dtype=float)[:, :2]))
        else:
            V, F, scalars = embedding_of(m_or_V, kind, scalars)
            self._box.append(_xy_box(np.asarray(m_or_V.xy)))
        layer = add_embedding(self.plotter, V, F, shading, scalars, **kwargs)
        return self._adopt(layer)

    def _adopt(self, layer: Layer) -> Layer:
        self.layers.append(layer)
        if self.env_map is not None:
            relight(self.plotter, [layer], self.lights, self.env_map)
        if self.bounds is not None:
            set_view(self.plotter, self.bounds)  # the z range may have grown
        return layer

    def clear(self) -> None:
        """Remove every layer (lights and camera stay)."""
        for layer in self.layers:
            self.plotter.remove_actor(layer.actor, render=False)
            if layer.isolines is not None:
                self.plotter.remove_actor(layer.isolines, render=False)
        self.layers.clear()
        self._box.clear()

    # -- camera and light ------------------------------------------------------------------
    def view(self, bounds: object = None, margin: float = DEFAULT_MARGIN) -> tuple:
        """Fix the camera; ``bounds=None`` frames every layer's xy box plus ``margin``."""
        if bounds is None:
            if not self._box:
                raise MescherError("bounds: expected bounds or at least one layer, found neither")
            boxes = np.array(self._box)
            box = (boxes[:, 0].min(), boxes[:, 1].max(), boxes[:, 2].min(), boxes[:, 3].max())
            bounds = default_bounds(box, self.window_size, margin)
        self.bounds = as_bounds(bounds)
        set_view(self.plotter, self.bounds)
        return self.bounds

    def relight(self, lights: object = DEFAULT_LIGHTS, env_map: object = None) -> None:
        """Change the lighting of every layer (no geometry rebuilt); see :func:`relight`."""
        self.lights, self.env_map = relight(self.plotter, self.layers, lights, env_map)

    def screenshot(self) -> np.ndarray:
        """(H, W, 3) uint8 of the current state (renders first, as VTK needs after a relight)."""
        if self.bounds is None:
            self.view()
        self.plotter.render()
        image = self.plotter.screenshot(return_img=True, transparent_background=False)
        return np.ascontiguousarray(image[..., :3])

    def close(self) -> None:
        """Release the plotter and its GL context."""
        self.plotter.close()

    def __enter__(self) -> MescherScene:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _as_window_size(window_size: object) -> tuple[int, int]:
    w = np.asarray(window_size)
    if w.shape != (2,) or not np.issubdtype(w.dtype, np.integer) or (w <= 0).any():
        raise MescherError(
            f"window_size: expected (width, height) positive integers, found {window_size!r}"
        )
    return (int(w[0]), int(w[1]))


def _xy_box(xy: np.ndarray) -> tuple[float, float, float, float]:
    return (
        float(xy[:, 0].min()),
        float(xy[:, 0].max()),
        float(xy[:, 1].min()),
        float(xy[:, 1].max()),
    )


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


def render(
    m: Any,
    order: object = None,
    lights: object = DEFAULT_LIGHTS,
    shading: str = "flat",
    scalars: object = None,
    env_map: object = None,
    window_size: tuple[int, int] = (800, 800),
    bounds: object = None,
    background: object = "white",
    **kwargs: Any,
) -> np.ndarray:
    """Render a mescher head-on (paper Section 4.1).

    The mescher is flattened (absolute depth set to zero) and shaded with normals derived from
    zeta; overlaps follow ``order``'s linear extension (painter's algorithm).  Only directional
    lights and environment maps are supported: they are the only illumination compatible with
    meschers, because radiance that depends only on the incoming direction makes shading
    invariant to translations in R^3, whereas point, spot or area lights would need the absolute
    3D positions a mescher does not have (paper Section 4.1).  A positional light raises
    :class:`~meschers_igl.MescherError`.

    Parameters
    ----------
    m : meschers_igl.Mescher or (V, F)
        A mescher, or an ordinary 3D mesh (``V`` (#V, 3) in the camera frame) drawn z-buffered
        with the same camera and lights.
    order : None, DepthOrder or (#F,) array_like
        Back-to-front order of a mescher's faces (``None``: face-index order).
    lights : direction, sequence of directions / DirectionalLight / non-positional pyvista.Light
        Directions *toward* directional lights in the camera frame (x right, y up, z toward the
        viewer); ``None`` or ``[]`` for none.  VTK's light kit and headlight are off.
    shading : {"flat", "smooth"}
        Face normals, or interpolated vertex normals, both from zeta.
    scalars : None, (#V,) or (#F,) array_like, or dict
        Colour-mapped (``cmap``, ``clim``) and lit like the material; ``isolines=k`` draws k
        evenly spaced contours of per-vertex scalars (or ``isolines=levels``).
    env_map : None, str, path, (H, W, 3) array or EnvironmentMap
        A built-in environment (``"studio"``, ``"sky"``, ``"uniform"``) or a lat-long image
        (:mod:`pyvista_views.envmap`), evaluated per normal as Lambertian irradiance and added to
        the directional lights.
    window_size : (int, int)
        (width, height) in pixels; the image is (height, width, 3).
    bounds : (xmin, xmax, ymin, ymax), optional
        Exactly the image's extent in screen units; pixel (row r, column c) covers
        ``x in xmin + [c, c+1] * (xmax-xmin)/width`` and ``y in ymax - [r+1, r] * (ymax-ymin)/height``.
        Default: the xy box plus a 5% margin, widened to the window's aspect ratio.
    background : color
    **kwargs
        ``representation`` ("mescher", or "cut" / "bent" to draw ``m.cut_embedding()`` /
        ``m.bent_embedding()`` with identical camera and default bounds), ``color``, ``cmap``,
        ``clim``, ``isolines``, ``isoline_color``, ``ambient`` (0.2), ``diffuse`` (0.8),
        ``anti_aliasing`` (False).

    Returns
    -------
    (H, W, 3) uint8
    """
    representation = as_choice(
        kwargs.pop("representation", "mescher"), "representation", REPRESENTATIONS
    )
    anti_aliasing = bool(kwargs.pop("anti_aliasing", False))
    as_choice(shading, "shading", SHADINGS)
    directional = as_lights(lights)  # refuse point lights before any GL work
    env = as_env_map(env_map)
    if bounds is not None:
        bounds = as_bounds(bounds)
    with MescherScene(
        window_size=window_size, background=background, anti_aliasing=anti_aliasing
    ) as scene:
        if isinstance(m, (tuple, list)):
            if representation != "mescher" or len(m) != 2:
                raise MescherError(
                    "m: expected a Mescher, or a (V, F) pair with representation='mescher', "
                    f"found a {len(m)}-tuple with representation={representation!r}"
                )
            scene.add_embedding(m[0], m[1], shading=shading, scalars=scalars, **kwargs)
        elif representation == "mescher":
            if order is not None and not hasattr(m, "F"):
                raise MescherError(f"m: expected a Mescher, found {type(m).__name__}")
            scene.add(m, order=order, shading=shading, scalars=scalars, **kwargs)
        else:
            scene.add_embedding(m, kind=representation, shading=shading, scalars=scalars, **kwargs)
        scene.view(bounds)
        scene.relight(directional, env)
        return scene.screenshot()
