"""Interactive views: live relighting, scalar toggles, and picking faces to reorder depth.

The window keeps the head-on orthographic camera (a mescher is only meaningful head-on),
so the widgets change the light, the scalar field shown, the shading, and the depth order, never
the view direction.  Off screen (``pyvista.OFF_SCREEN``, ``off_screen=True`` or no display) there
is nothing to interact with, and :func:`plot` returns a screenshot instead of blocking.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_index_array

from . import headless
from .camera import as_bounds
from .layers import DEFAULT_LIGHTS
from .polydata import SHADINGS, as_scalars, draw_order
from .scene import MescherScene

#: Font size of the help text in the side panel (PyVista's points: about 17-pixel lines).
HELP_FONT_SIZE = 9


def light_from_angles(azimuth: float, elevation: float) -> np.ndarray:
    """(3,) unit direction toward a light, camera frame.

    ``azimuth`` (degrees) turns around the view axis from +x (right) toward +y (up);
    ``elevation`` (degrees) rises from the screen plane toward the viewer (90: a headlight).
    """
    a, e = np.radians(azimuth), np.radians(elevation)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def angles_from_light(direction: np.ndarray) -> tuple[float, float]:
    """Inverse of :func:`light_from_angles` (degrees)."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    return float(np.degrees(np.arctan2(d[1], d[0]))), float(np.degrees(np.arcsin(d[2])))


class MescherViewer:
    """A mescher in a plotter with the state the widgets change.

    Parameters
    ----------
    m : meschers_igl.Mescher
    order : None, DepthOrder or (#F,) array_like
        Its ``put_in_front`` is used for picking when it is a DepthOrder; an array order is
        edited as a total order.
    lights, shading, env_map, window_size, bounds, background
        As in :func:`pyvista_views.render`.
    scalars : None, array or dict name -> array
        Fields the "s" key cycles through (``None``, i.e. plain shading, is one of the states).
    off_screen : bool, optional
    scalar_bar : bool, optional
        A colour bar titled with the field's name whenever a field is shown; default: unless
        ``bounds`` is given (as in :func:`pyvista_views.render`).
    **kwargs
        Passed to :func:`pyvista_views.layers.add_mescher` (``cmap``, ``isolines``, ...).
    """

    def __init__(
        self,
        m: Any,
        order: object = None,
        lights: object = DEFAULT_LIGHTS,
        shading: str = "flat",
        scalars: object = None,
        env_map: object = None,
        window_size: tuple[int, int] = (800, 800),
        bounds: object = None,
        background: object = "white",
        off_screen: bool | None = None,
        scalar_bar: bool | None = None,
        **kwargs: Any,
    ) -> None:
        self.m = m
        self.scalar_bar = bounds is None if scalar_bar is None else bool(scalar_bar)
        self._bounds = bounds
        self._panel = 0  # pixels of the side panel (widgets, help, colour bar) once shown
        self.order = order if hasattr(order, "linear_extension") or order is None else None
        self._draw = (
            None
            if self.order is not None or order is None
            else draw_order(order, np.asarray(m.F).shape[0])
        )
        self.shading = shading
        n_v, n_f = np.asarray(m.xy).shape[0], np.asarray(m.F).shape[0]
        self.fields = {k: v for k, (v, _) in as_scalars(scalars, n_v, n_f).items()}
        self.scalar_names: list[str | None] = [None, *self.fields]
        self.current_scalars = self.scalar_names[1] if self.fields else None
        self.kwargs = kwargs
        self.off_screen = headless.is_offscreen(off_screen)
        self.scene = MescherScene(
            window_size=window_size, background=background, off_screen=self.off_screen
        )
        self._picked: list[np.ndarray] = []
        self.scene.relight(lights, env_map)
        self._build()

    # -- state changes (each is what one widget does) -----------------------------------------
    def _build(self) -> None:
        self.scene.clear()
        fields = None
        if self.current_scalars is not None:
            fields = {self.current_scalars: self.fields[self.current_scalars]}
        order = self.order if self.order is not None else self._draw
        kwargs = dict(self.kwargs)
        if fields is None:
            kwargs.pop("isolines", None)
        bar = fields is not None and self.scalar_bar
        if self._panel:  # the panel holds the widgets and the colour bar
            self.scene.reserve_scalar_bar(self._panel / self.scene.plotter.window_size[0])
        else:
            self.scene.reserve_scalar_bar(bar)
        self.scene.add(self.m, order=order, shading=self.shading, scalars=fields, **kwargs)
        self.scene.relight(self.scene.lights, self.scene.env_map)
        self.scene.view(self._view_bounds())
        if bar:
            self.scene.add_scalar_bar(self.current_scalars, **self._bar_position())

    def _view_bounds(self) -> object:
        """The user's bounds (None: framed by default), widened over the side panel if any."""
        if self._bounds is None or not self._panel:
            return self._bounds
        xmin, xmax, ymin, ymax = as_bounds(self._bounds)
        width = self.scene.plotter.window_size[0] - self._panel
        return (xmin, xmax + (xmax - xmin) * self._panel / width, ymin, ymax)

    def _bar_position(self) -> dict:
        """Where the colour bar goes: the lower part of the side panel, or the default strip."""
        if not self._panel:
            return {}
        W = self.scene.plotter.window_size[0]
        return dict(
            position_x=(W - 0.92 * self._panel) / W,
            width=0.6 * self._panel / W,
            position_y=0.04,
            height=0.3,
        )

    def set_light(self, direction: object, index: int = 0) -> None:
        """Replace light ``index`` (appending when there is none) and redraw; no rebuild."""
        lights = list(self.scene.lights)
        from .lights import as_lights

        (light,) = as_lights([direction], name="direction")
        if index < len(lights):
            lights[index] = light
        else:
            lights.append(light)
        self.scene.relight(lights, self.scene.env_map)
        self.scene.plotter.render()

    def set_light_angles(
        self, azimuth: float | None = None, elevation: float | None = None
    ) -> None:
        """Move the first light (degrees, :func:`light_from_angles`); what the sliders call."""
        az, el = (
            angles_from_light(self.scene.lights[0].direction) if self.scene.lights else (45, 45)
        )
        self.set_light(
            light_from_angles(
                az if azimuth is None else azimuth, el if elevation is None else elevation
            )
        )

    def show_scalars(self, name: str | None) -> None:
        """Colour by scalar field ``name`` (``None``: plain material)."""
        if name not in self.scalar_names:
            raise MescherError(f"name: expected one of {self.scalar_names}, found {name!r}")
        self.current_scalars = name
        self._build()

    def cycle_scalars(self) -> None:
        """Next scalar field (the "s" key)."""
        i = self.scalar_names.index(self.current_scalars)
        self.show_scalars(self.scalar_names[(i + 1) % len(self.scalar_names)])

    def toggle_shading(self) -> None:
        """Flat <-> smooth (the "f" key)."""
        self.shading = SHADINGS[1 - SHADINGS.index(self.shading)]
        self._build()

    def put_in_front(self, front: object, back: object) -> None:
        """Draw faces ``front`` in front of faces ``back`` and redraw.

        With a DepthOrder its ``put_in_front`` adds the arcs (and warns about cycles).  With a
        total order (an array, or none) the front faces move, in their relative order, to just
        after the last back face.
        """
        n_f = np.asarray(self.m.F).shape[0]
        front = np.unique(as_index_array(front, "front", n_f))
        back = np.unique(as_index_array(back, "back", n_f))
        if self.order is not None:
            self.order.put_in_front(front, back)
        else:
            draw = self._draw if self._draw is not None else np.arange(n_f)
            moving = np.isin(draw, front)
            rank = np.empty(n_f, dtype=np.int64)
            rank[draw] = np.arange(n_f)
            last_back = rank[back].max()
            rest = draw[~moving]
            cut = np.searchsorted(rank[rest], last_back, side="right")
            self._draw = np.concatenate([rest[:cut], draw[moving], rest[cut:]])
        self._build()
        self.scene.plotter.render()

    def on_pick(self, picked: Any) -> None:
        """Cell-picking callback: the first selection is the front group, the second the back
        group; then :meth:`put_in_front`."""
        if picked is None or "face_id" not in getattr(picked, "cell_data", {}):
            return
        faces = np.unique(np.asarray(picked.cell_data["face_id"], dtype=np.int64))
        if faces.size == 0:
            return
        self._picked.append(faces)
        if len(self._picked) == 2:
            front, back = self._picked
            self._picked = []
            self.put_in_front(front, back)

    # -- output ---------------------------------------------------------------------------------
    def screenshot(self) -> np.ndarray:
        """(H, W, 3) uint8 of the current state."""
        return self.scene.screenshot()

    #: Help shown in the side panel (short lines: the panel is ~300 pixels wide).
    HELP = (
        "Keys\n"
        "r  select faces: the 1st\n"
        "   group goes in front\n"
        "   of the 2nd\n"
        "s  next scalar field\n"
        "f  flat / smooth\n"
        "mouse  pan and zoom\n"
        "q  close"
    )

    def open_panel(self) -> int:
        """Widen the window by a side panel on the right for the widgets, the help and the
        colour bar, so that nothing is drawn over the figure; returns its width in pixels.

        The figure keeps its size and framing (``window_size`` is the figure's); the panel is
        ``max(300, 0.4 * height)`` pixels wide, enough for the sliders' titles and the help at a
        readable size (:data:`HELP_FONT_SIZE`) at the default 800 x 800.
        """
        if self._panel:
            return self._panel
        w, h = (int(v) for v in self.scene.plotter.window_size)
        self._panel = max(300, int(0.4 * h))
        self.scene.plotter.window_size = [w + self._panel, h]
        self.scene.window_size = (w + self._panel, h)
        self._build()
        return self._panel

    def _add_widgets(self) -> None:
        plotter = self.scene.plotter
        panel = self.open_panel()
        W, H = (int(v) for v in plotter.window_size)
        x0, x1 = (W - 0.92 * panel) / W, (W - 0.08 * panel) / W  # inside the panel
        az, el = (
            angles_from_light(self.scene.lights[0].direction) if self.scene.lights else (45, 45)
        )
        common = dict(style="modern", title_height=0.022, fmt="%.0f", color="black")
        plotter.add_slider_widget(
            lambda v: self.set_light_angles(azimuth=v),
            [-180, 180],
            value=az,
            title="light azimuth (deg)",
            pointa=(x0, 0.90),
            pointb=(x1, 0.90),
            **common,
        )
        plotter.add_slider_widget(
            lambda v: self.set_light_angles(elevation=v),
            [-89, 90],
            value=el,
            title="light elevation (deg)",
            pointa=(x0, 0.77),
            pointb=(x1, 0.77),
            **common,
        )
        help_text = plotter.add_text(
            self.HELP,
            position=(int(W - 0.92 * panel), int(0.68 * H)),
            font_size=HELP_FONT_SIZE,
            color="black",
            name="help",
        )
        help_text.GetTextProperty().SetVerticalJustificationToTop()  # hangs below the sliders
        plotter.add_key_event("s", self.cycle_scalars)
        plotter.add_key_event("f", self.toggle_shading)
        plotter.enable_cell_picking(
            callback=self.on_pick,
            through=False,
            show_message=False,  # the help in the panel says it; a message would cover the figure
            style="surface",
            show=False,
        )
        # A mescher is only meaningful head-on: pan and zoom, no orbiting.
        plotter.enable_image_style()

    def show(self, jupyter_backend: str | None = None, **kwargs: Any) -> np.ndarray | None:
        """Open the window (or the notebook widget, trame by default); offscreen: a screenshot."""
        if self.off_screen and not headless.in_notebook():
            image = self.screenshot()
            self.scene.close()
            return image
        self._add_widgets()
        return self.scene.plotter.show(jupyter_backend=jupyter_backend, **kwargs)


def plot(
    m: Any,
    order: object = None,
    lights: object = DEFAULT_LIGHTS,
    shading: str = "flat",
    scalars: object = None,
    env_map: object = None,
    window_size: tuple[int, int] = (800, 800),
    bounds: object = None,
    background: object = "white",
    off_screen: bool | None = None,
    jupyter_backend: str | None = None,
    **kwargs: Any,
) -> np.ndarray | None:
    """Interactive view of a mescher.

    Widgets: two sliders move the first light (azimuth around the view axis, elevation toward the
    viewer) with live relighting; "s" cycles the scalar fields; "f" toggles flat/smooth; "r"
    starts a rectangle selection of faces: the first selection is put in front of the second
    (:meth:`MescherViewer.put_in_front`).  In Jupyter PyVista's trame backend is used
    (``jupyter_backend``).  Off screen it returns the (H, W, 3) uint8 screenshot that
    :func:`pyvista_views.render` would give, instead of blocking.

    Parameters
    ----------
    m, order, lights, shading, scalars, env_map, window_size, bounds, background
        As in :func:`pyvista_views.render`; ``scalars`` may be a dict of named fields.
    off_screen : bool, optional
        Default: ``pyvista.OFF_SCREEN`` or no display.
    jupyter_backend : str, optional
    **kwargs
        ``cmap``, ``clim``, ``isolines``, ``color``, ``ambient``, ``diffuse``.

    Returns
    -------
    (H, W, 3) uint8 or None
    """
    backend = jupyter_backend or getattr(pv.global_theme, "jupyter_backend", None)
    if backend == "client":
        # vtk.js draws with its own depth test: cells back to front (gl.use_early_z).
        kwargs.setdefault("early_z", False)
    viewer = MescherViewer(
        m,
        order,
        lights,
        shading,
        scalars,
        env_map,
        window_size,
        bounds,
        background,
        off_screen,
        **kwargs,
    )
    return viewer.show(jupyter_backend=jupyter_backend)
