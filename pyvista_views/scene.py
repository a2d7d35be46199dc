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
from typing import Any

import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_choice

from . import headless
from .camera import DEFAULT_MARGIN, as_bounds, as_window_size, default_bounds, set_view, xy_box
from .envmap import EnvironmentMap

#: Matte grey: lit faces stay below the white background (silhouettes are measurable).
from .layers import (
    DEFAULT_LIGHTS,
    MIN_LABEL_PX,
    Layer,
    _mapper_time,
    add_embedding,
    add_mescher,
    label_font_size,
    relight,
    scalar_bar_strip,
)
from .lights import (
    DirectionalLight,
)
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
                )
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
