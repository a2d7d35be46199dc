"""A studio in the browser: turn, relight, measure and reshape a mescher (``meschers studio``).

The page is served by trame (the web framework PyVista's Jupyter backend uses) and every
picture is rendered on the server with :func:`pyvista_views.render` (VTK off screen, so the
studio runs on a machine without a display) and sent to the page as an image.  On the page:

* drag on the picture -- in *light* mode the light follows the pointer (the point under it
  gives the light's direction on a virtual hemisphere facing the viewer); in *turn* mode the
  figure turns a few degrees (:meth:`~meschers_igl.Mescher.rotated`, about screen y for a
  horizontal drag and screen x for a vertical one); in *path* mode two clicks pick two points
  and the geodesic between them is drawn (only where its faces are seen);
* sliders smooth screen positions and depths (:meth:`~meschers_igl.Mescher.smooth`);
* *paint a period*: pick a loop of the homology basis (drawn on the figure) and drag its
  period (:meth:`~meschers_igl.Mescher.with_periods`): a torus that embeds becomes an
  impossible one as the period leaves 0;
* save the current mescher and its depth order to ``.ply`` / ``.npz`` (the only file the
  studio writes), or load one.

:class:`StudioModel` holds the state and does the work (no web code: it is tested directly);
:func:`build_page` lays out the page; :func:`serve` runs it; :func:`notebook` gives the same
page in a Jupyter cell.
"""

from __future__ import annotations

import base64
import errno
import io
import socket
import sys
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl import MescherError
from meschers_igl.mescher import IMPOSSIBLE_RTOL

#: Pixels of the square picture the server renders.
IMAGE_SIZE = 560
#: Degrees of turn per pixel dragged, and the largest turn about each axis.
TURN_PER_PIXEL = 0.15
MAX_TURN = 45.0
#: Share of the figure's size by which the frame exceeds it (room to turn).
FRAME_MARGIN = 0.3
#: Suffixes Save writes.
SAVE_SUFFIXES = (".ply", ".npz")
#: The model shown without a MODEL argument: a torus that embeds, seen from above the
#: front, so that painting a period on its loop around the hole makes it impossible.
DEFAULT_MODEL = "torus"
MODES = ("light", "turn", "path")


def _require_trame() -> None:
    try:
        import trame  # noqa: F401
        import trame_vuetify  # noqa: F401
    except ImportError:
        raise ImportError(
            "the studio needs trame: pip install 'meschers[studio]' (trame, trame-vuetify)"
        ) from None


def default_torus() -> tuple[Any, Any]:
    """(mescher, order): an ordinary torus seen from above its front, order from its depths."""
    from meschers_igl import DepthOrder, Mescher, shapes
    from meschers_igl.operators import view_frame

    V, F = shapes.torus(64, 24)
    view, up = (0.0, -0.75, 0.66), (0.0, 0.66, 0.75)
    m = Mescher.from_mesh(V, F, view=view, up=up)
    Zc = (V @ view_frame(view, up)[2])[F]
    return m, DepthOrder.from_embedding(m, Zc)


def load_model(spec: str | None) -> tuple[Any, Any, str]:
    """(mescher, order or None, label) of a model name (:mod:`meschers.inputs`) or the torus."""
    if spec is None or spec == DEFAULT_MODEL:
        m, order = default_torus()
        return m, order, DEFAULT_MODEL
    from .inputs import load_mescher, resolve

    model = resolve(spec, "MODEL")
    m, order = load_mescher(model)
    return m, order, model.label


def light_from_pointer(u: float, v: float) -> np.ndarray:
    """(3,) unit direction toward the light for a pointer at ``(u, v)`` in [-1, 1]^2 of the
    picture (u right, v up): the point of the hemisphere facing the viewer above it
    (outside the unit disc, the rim)."""
    p = np.array([u, v], dtype=np.float64)
    r = float(np.hypot(*p))
    if r > 0.98:
        p *= 0.98 / r
    return np.array([p[0], p[1], np.sqrt(max(0.0, 1.0 - p @ p))])


def _periods_text(m: Any) -> str:
    """Periods to 4 digits, those at round-off of the model's size as 0."""
    tol = IMPOSSIBLE_RTOL * m.scale()
    return ", ".join(f"{x:.4g}" if abs(x) > tol else "0" for x in m.periods())


class StudioModel:
    """The studio's state and operations (everything but the web page).

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional
    label : str
        Shown in the title.
    size : int
        Pixels of the square picture.

    Notes
    -----
    The picture is ``base`` with the painted periods, then smoothed, then turned: each
    change recomputes from ``base``, so turning back to 0 degrees gives back the unturned
    figure.
    """

    def __init__(self, m: Any, order: Any = None, label: str = "", size: int = IMAGE_SIZE):
        self.size = int(size)
        self.set_model(m, order, label)

    # ------------------------------------------------------------------ state
    def set_model(self, m: Any, order: Any, label: str) -> None:
        """Start over with a new model (turn, smoothing, periods and picks reset)."""
        self.base, self.base_order, self.label = m, order, label
        p = np.asarray(m.periods(), dtype=np.float64)
        # periods at round-off of a model that embeds show as 0 (and painting starts there)
        self.base_periods = np.where(np.abs(p) > IMPOSSIBLE_RTOL * m.scale(), p, 0.0)
        self.periods = self.base_periods.copy()
        self.turn = [0.0, 0.0]  # degrees about screen x, screen y
        self.turn_base = [0.0, 0.0]  # the turn a drag starts from
        self.light = np.array([0.4, 0.6, 0.7]) / np.linalg.norm([0.4, 0.6, 0.7])
        self.t_xy = self.t_zeta = 0.0
        # the longest loop first: on a torus, the one around the hole (an impossibagel's)
        sizes = [len(edges) for edges, _ in m.homology_generators()]
        self.loop = int(np.argmax(sizes)) if sizes else 0
        self.picks: list[int] = []
        lo, hi = np.min(m.xy, axis=0), np.max(m.xy, axis=0)
        c, r = (lo + hi) / 2, (0.5 + FRAME_MARGIN) * float(np.max(hi - lo))
        self.bounds = (c[0] - r, c[0] + r, c[1] - r, c[1] + r)
        self._current = None

    @property
    def n_loops(self) -> int:
        return int(self.base_periods.size)

    def current(self) -> tuple[Any, Any]:
        """(mescher, order) shown: base with the painted periods, smoothed, turned."""
        if self._current is None:
            m, order = self.base, self.base_order
            if not np.array_equal(self.periods, self.base_periods):
                m = m.with_periods(self.periods)  # same xy: the order still holds
            if self.t_xy > 0 or self.t_zeta > 0:
                s = m.scale() ** 2
                if order is None:
                    m = m.smooth(self.t_xy * s, self.t_zeta * s)
                else:
                    m, order = m.smooth(self.t_xy * s, self.t_zeta * s, order=order)
            if self.turn != [0.0, 0.0]:
                from scipy.spatial.transform import Rotation

                from meschers_igl.rotation import rotate, rotation_matrix

                R = rotation_matrix(self.turn[1], "y") @ rotation_matrix(self.turn[0], "x")
                rv = Rotation.from_matrix(R).as_rotvec()
                t = rotate(m, np.rad2deg(np.linalg.norm(rv)), rv, order=order)
                m, order = t.mescher, t.order
            self._current = (m, order)
        return self._current

    def _changed(self) -> None:
        self._current = None

    # ------------------------------------------------------------------ actions
    def drag(self, mode: str, start, end, extent, final: bool = True) -> str:
        """A drag on the picture from ``start`` to ``end`` (pixels of a picture ``extent``
        (width, height) on the page).  Returns a line for the status bar.

        While the button is held the page sends previews (``final=False``): the light and the
        turn follow the pointer, measured from where the drag began; the release commits.
        A pick happens on release only.
        """
        if mode not in MODES:
            raise MescherError(f"mode: expected one of {', '.join(MODES)}, found {mode!r}")
        (x0, y0), (x1, y1), (w, h) = np.asarray(start, float), np.asarray(end, float), extent
        if mode == "light":
            self.light = light_from_pointer(2 * x1 / w - 1, 1 - 2 * y1 / h)
            return "light toward ({:.2f}, {:.2f}, {:.2f})".format(*self.light)
        if mode == "turn":
            k = TURN_PER_PIXEL * self.size / max(w, 1)
            turn = [
                float(np.clip(self.turn_base[0] + k * (y1 - y0), -MAX_TURN, MAX_TURN)),
                float(np.clip(self.turn_base[1] + k * (x1 - x0), -MAX_TURN, MAX_TURN)),
            ]
            self.set_turn(turn, final)
            return f"turned {self.turn[0]:.1f} deg about x, {self.turn[1]:.1f} deg about y"
        return self.pick(x1 / w, y1 / h) if final else ""

    def set_turn(self, turn, final: bool = True) -> None:
        """Degrees about screen x and y; ``final`` makes it where the next drag starts."""
        if list(turn) != self.turn:
            self.turn = [float(turn[0]), float(turn[1])]
            self._changed()
        if final:
            self.turn_base = list(self.turn)

    def pick(self, fx: float, fy: float) -> str:
        """Pick the vertex under the point at ``(fx, fy)`` of the picture (0-1, from its
        top-left); the second pick draws the geodesic from the first."""
        from meschers_igl.painter import visible_faces

        m, order = self.current()
        faces = visible_faces(m, order, size=self.size, bounds=self.bounds)
        r = min(int(fy * self.size), self.size - 1)
        c = min(int(fx * self.size), self.size - 1)
        f = int(faces[r, c])
        if f < 0:
            return "no surface there: pick a point on the figure"
        x0, x1, y0, y1 = self.bounds
        p = np.array([x0 + fx * (x1 - x0), y1 - fy * (y1 - y0)])
        corners = np.asarray(m.F[f])
        v = int(corners[np.argmin(np.linalg.norm(m.xy[corners] - p, axis=1))])
        self.picks = [v] if len(self.picks) != 1 else [self.picks[0], v]
        if len(self.picks) == 1:
            return f"picked vertex {v}; pick a second point"
        return f"geodesic {self.picks[0]} -> {v}: length {self.path().length:.4g}"

    def path(self):
        """The geodesic between the two picks on the current mescher, or None."""
        if len(self.picks) != 2:
            return None
        m, _ = self.current()
        return m.shortest_path(*self.picks)

    def set_smoothing(self, t_xy: float, t_zeta: float) -> str:
        """Smoothing times, as shares of the figure's size squared (0: none)."""
        self.t_xy, self.t_zeta = max(0.0, float(t_xy)), max(0.0, float(t_zeta))
        self._changed()
        return f"smoothing t_xy {self.t_xy:g}, t_zeta {self.t_zeta:g} (x size^2)"

    def set_period(self, loop: int, value: float) -> str:
        """Paint ``value`` as the period of loop ``loop`` (the others kept)."""
        if not 0 <= int(loop) < self.n_loops:
            raise MescherError(f"loop: expected 0..{self.n_loops - 1}, found {loop}")
        value = float(value)
        if not np.isfinite(value):
            raise MescherError(f"period: expected a finite number, found {value}")
        self.loop = int(loop)
        self.periods = self.periods.copy()
        self.periods[self.loop] = value
        self._changed()
        m, _ = self.current()
        word = "impossible" if m.is_impossible() else "possible"
        return f"period of loop {self.loop + 1} set to {value:.4g}: the figure is {word}"

    def save(self, path: str) -> str:
        """Write the current mescher and its order (``.ply`` or ``.npz``)."""
        from meschers_igl import save

        p = Path(str(path).strip()).expanduser()
        if p.suffix.lower() not in SAVE_SUFFIXES:
            raise MescherError(f"save path: expected a .ply or .npz file name, found {str(p)!r}")
        if not p.parent.is_dir():
            raise MescherError(f"save path: expected an existing folder, found {str(p.parent)!r}")
        m, order = self.current()
        save(m, p, order=order)
        return f"saved {p} ({m.n_faces} faces, periods ({_periods_text(m)}))"

    def load(self, spec: str) -> str:
        m, order, label = load_model(str(spec).strip())
        self.set_model(m, order, label)
        return f"loaded {label}: {m.n_faces} faces, {self.n_loops} loop(s)"

    # ------------------------------------------------------------------ picture
    def image(self) -> np.ndarray:
        """(size, size, 3) uint8: the current figure, its picked points, geodesic and loop."""
        from pyvista_views import render

        m, order = self.current()
        img = render(
            m, order, lights=[self.light], window_size=(self.size, self.size), bounds=self.bounds
        )
        F = np.asarray(m.F)
        strokes = []  # (overlay keyword, items, faces the drawing lies on)
        if self.n_loops and self.loop < self.n_loops:
            edges, _ = m.homology_generators()[self.loop]
            E = np.asarray(m.edges)[np.asarray(edges)]
            on = np.isin(np.asarray(m.face_edges), np.asarray(edges)).any(axis=1)
            strokes.append(("segments", (m.xy[E], "#ff8c00", 3), np.flatnonzero(on)))
        path = self.path()
        if path is not None:
            P = np.asarray(path.xy)
            segs = np.stack([P[:-1], P[1:]], 1)
            strokes.append(("segments", (segs, "#e0102f", 3), np.asarray(path.faces)))
        for v, colour in zip(self.picks, ("#1060ff", "#e0102f")):
            on = np.flatnonzero((F == v).any(axis=1))
            strokes.append(("points", (m.xy[[v]], colour, 5), on))
        if strokes:
            img = self._draw_seen(img, m, order, strokes)
        return img

    def _draw_seen(self, img: np.ndarray, m: Any, order: Any, strokes) -> np.ndarray:
        """Draw each stroke only on pixels that show its faces or faces sharing a vertex
        with them: a path or loop on a hidden layer stays hidden."""
        from meschers_igl.painter import visible_faces

        from .figures import overlay

        seen = visible_faces(m, order, size=self.size, bounds=self.bounds)
        covered = seen >= 0
        F = np.asarray(m.F)
        out, blank = img.copy(), np.full_like(img, 255)
        for kind, item, faces in strokes:
            near = np.isin(F, F[faces]).any(axis=1)
            drawn = overlay(blank, self.bounds, **{kind: [item]})
            mask = np.any(drawn != 255, axis=-1) & covered & near[np.where(covered, seen, 0)]
            out[mask] = drawn[mask]
        return out

    def image_url(self) -> str:
        """The picture as a PNG data URL for the page."""
        from PIL import Image

        buf = io.BytesIO()
        Image.fromarray(self.image()).save(buf, format="PNG", compress_level=1)
        return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")

    def summary(self) -> str:
        m, _ = self.current()
        p = _periods_text(m) or "none"
        word = "impossible" if m.is_impossible() else "possible"
        return f"{self.label}: {m.n_faces} faces, periods ({p}), {word}"


# ---------------------------------------------------------------------- the page
def build_page(model: StudioModel, server: Any = None) -> tuple[Any, Any]:
    """Lay out the studio page for ``model``; returns ``(server, layout)``."""
    _require_trame()
    from trame.app import get_server

    if server is None:
        server = get_server(f"meschers-studio-{id(model)}", client_type="vue3")
    _bind(model, server)
    return server, _layout(model, server)


def _bind(model: StudioModel, server: Any) -> None:
    """The page's state and what each control does to ``model``."""
    state, ctrl = server.state, server.controller

    def refresh(message: str | None = None, error: bool = False) -> None:
        state.image = model.image_url()
        state.summary = model.summary()
        if message is not None:
            state.status, state.status_error = message, error

    def guarded(fn):
        def run(*args, **kwargs):
            try:
                refresh(fn(*args, **kwargs))
            except MescherError as exc:
                state.status, state.status_error = str(exc).splitlines()[0], True

        return run

    def reset_state() -> None:
        state.loops = [f"loop {i + 1}" for i in range(model.n_loops)]
        state.loop = model.loop
        state.period = float(model.periods[model.loop]) if model.n_loops else 0.0
        span = float(np.max(np.abs(model.base_periods), initial=0.0)) or 0.5 * model.base.scale()
        state.period_span = float(max(3 * span, 1e-9))
        state.t_xy = state.t_zeta = 0.0
        state.title = f"meschers studio - {model.label}"

    state.mode = "light"
    state.drag0 = [0, 0]
    state.busy = False
    state.status, state.status_error = "drag on the figure", False
    state.save_path = f"{model.label.replace('/', '_').replace(':', '_')}_studio.ply"
    state.load_path = ""
    reset_state()

    @ctrl.trigger("drag_end")
    def drag_end(start, end, extent):
        guarded(model.drag)(state.mode, start, end, extent)
        _ready_for_more(state)

    @ctrl.trigger("drag_move")
    def drag_move(start, end, extent):
        if state.mode != "path":
            guarded(model.drag)(state.mode, start, end, extent, final=False)
        _ready_for_more(state)

    @state.change("t_xy", "t_zeta")
    def smooth(t_xy, t_zeta, **_):
        if (float(t_xy or 0), float(t_zeta or 0)) != (model.t_xy, model.t_zeta):
            guarded(model.set_smoothing)(t_xy or 0, t_zeta or 0)

    @state.change("period")
    def period(period, **_):
        try:
            value = float(period)
        except (TypeError, ValueError):
            state.status, state.status_error = f"period: expected a number, found {period!r}", True
            return
        tol = IMPOSSIBLE_RTOL * model.base.scale()
        if model.n_loops and abs(value - float(model.periods[model.loop])) > tol:
            guarded(model.set_period)(state.loop, value)

    @state.change("loop")
    def loop(loop, **_):
        if model.n_loops:
            model.loop = int(loop or 0)
            model._changed()
            state.period = float(model.periods[model.loop])
            refresh(f"loop {model.loop + 1} drawn in orange: drag its period")

    @ctrl.trigger("save")
    def save_now():
        guarded(model.save)(state.save_path)

    @ctrl.trigger("load")
    def load_now():
        def load(spec):
            msg = model.load(spec)
            reset_state()
            return msg

        guarded(load)(state.load_path)

    @ctrl.trigger("reset_turn")
    def reset_turn():
        def reset():
            model.set_turn([0.0, 0.0])
            return "turn reset to 0 deg"

        guarded(reset)()

    refresh()


def _ready_for_more(state: Any) -> None:
    """Let the page send its next drag preview (it sets ``busy`` itself, so the server may
    already hold False: pushed regardless)."""
    state.busy = False
    state.dirty("busy")


def _layout(model: StudioModel, server: Any) -> Any:
    """The page: controls in a drawer, the picture and two lines of text beside it."""
    from trame.ui.vuetify3 import SinglePageWithDrawerLayout
    from trame.widgets import html
    from trame.widgets import vuetify3 as v3

    with SinglePageWithDrawerLayout(server, full_height=True) as layout:
        layout.title.set_text(model.label)
        layout.title.children = ["{{ title }}"]
        with layout.drawer as drawer:
            drawer.width = 330
            with v3.VContainer(classes="pa-3"):
                html.Div("Drag on the figure to", classes="text-subtitle-2")
                with v3.VBtnToggle(
                    v_model=("mode",), mandatory=True, density="compact", color="primary", id="mode"
                ):
                    v3.VBtn("light", value="light", id="mode-light")
                    v3.VBtn("turn", value="turn", id="mode-turn")
                    v3.VBtn("path", value="path", id="mode-path")
                v3.VBtn(
                    "turn back to 0 deg",
                    click="trigger('reset_turn')",
                    size="small",
                    variant="text",
                    id="reset-turn",
                )
                html.Div("Smooth (time x size^2)", classes="text-subtitle-2 mt-3")
                v3.VSlider(
                    v_model=("t_xy",),
                    min=0,
                    max=0.01,
                    step=0.0005,
                    label="xy",
                    thumb_label=True,
                    hide_details=True,
                    id="smooth-xy",
                )
                v3.VSlider(
                    v_model=("t_zeta",),
                    min=0,
                    max=0.05,
                    step=0.0025,
                    label="depth",
                    thumb_label=True,
                    hide_details=True,
                    id="smooth-zeta",
                )
                _period_and_file_controls()
        with layout.content:
            with v3.VContainer(fluid=True, classes="pa-2"):
                html.Img(
                    src=("image",),
                    id="figure",
                    draggable="false",
                    style=f"width: {model.size}px; height: {model.size}px; cursor: crosshair;"
                    " user-select: none; border: 1px solid #ddd",
                    mousedown="drag0 = [$event.offsetX, $event.offsetY]; $event.preventDefault()",
                    mousemove="if ($event.buttons === 1 && !busy && mode !== 'path') { busy = true;"
                    " trigger('drag_move', [drag0, [$event.offsetX, $event.offsetY],"
                    " [$event.target.clientWidth, $event.target.clientHeight]]) }",
                    mouseup="trigger('drag_end', [drag0, [$event.offsetX, $event.offsetY], "
                    "[$event.target.clientWidth, $event.target.clientHeight]])",
                )
                html.Div("{{ summary }}", id="summary", classes="text-body-2 mt-1")
                html.Div(
                    "{{ status }}",
                    id="status",
                    classes="text-body-2",
                    style=("status_error ? 'color: #c00' : 'color: #333'",),
                )
    return layout


def _period_and_file_controls() -> None:
    """Drawer controls: the loop and its period, then Save and Load (inside a container)."""
    from trame.widgets import html
    from trame.widgets import vuetify3 as v3

    html.Div("Paint a period", classes="text-subtitle-2 mt-3")
    v3.VSelect(
        v_model=("loop",),
        items=("loops.map((t, i) => ({title: t, value: i}))",),
        density="compact",
        hide_details=True,
        id="loop",
        disabled=("loops.length == 0",),
    )
    v3.VSlider(
        v_model=("period",),
        min=("-period_span",),
        max=("period_span",),
        step=("period_span / 200",),
        hide_details=True,
        id="period-slider",
        disabled=("loops.length == 0",),
    )
    v3.VTextField(
        v_model_number=("period",),
        type="number",
        label="period",
        density="compact",
        hide_details=True,
        id="period",
        disabled=("loops.length == 0",),
    )
    html.Div("Files", classes="text-subtitle-2 mt-3")
    v3.VTextField(
        v_model=("save_path",),
        label="save as (.ply / .npz)",
        density="compact",
        hide_details=True,
        id="save-path",
    )
    v3.VBtn(
        "Save",
        click="trigger('save')",
        color="primary",
        size="small",
        classes="mt-1",
        id="save",
    )
    v3.VTextField(
        v_model=("load_path",),
        label="load (file or gallery name)",
        density="compact",
        hide_details=True,
        classes="mt-2",
        id="load-path",
    )
    v3.VBtn("Load", click="trigger('load')", size="small", classes="mt-1", id="load")


def check_port(host: str, port: int) -> int:
    """``port`` if it is free on ``host`` (0: a free one), else a :class:`MescherError`."""
    try:
        with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET) as s:
            s.bind((host, int(port)))
            return int(s.getsockname()[1])
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise MescherError(
                f"--port: expected a free port on {host}, found {port} in use (another studio "
                "or server?); choose another with --port, or --port 0 for any free port"
            ) from None
        raise MescherError(
            f"--host: expected an address of this machine, found {host!r} ({exc.strerror})"
        ) from None


def serve(
    spec: str | None = None,
    host: str = "127.0.0.1",
    port: int = 8080,
    open_browser: bool = False,
    size: int = IMAGE_SIZE,
) -> int:
    """Serve the studio for model ``spec`` until Ctrl-C; returns 0.

    The port is checked first (a clear :class:`MescherError` when it is taken); nothing is
    written to disk except by the page's Save button.
    """
    from .warmup import ensure_compiled

    _require_trame()
    port = check_port(host, port)
    # the page turns, relights and draws geodesics at once: its kernels compiled before serving
    ensure_compiled(lambda line: print(f"meschers studio: {line}", flush=True))
    m, order, label = load_model(spec)
    model = StudioModel(m, order, label, size=size)
    server, _ = build_page(model)
    print(f"meschers studio: {label} at http://{host}:{port}/ (Ctrl-C to stop)", flush=True)
    try:
        server.start(
            port=port,
            host=host,
            open_browser=open_browser,
            show_connection_info=False,
            disable_logging=True,
            timeout=0,
        )
    except KeyboardInterrupt:
        pass
    print("meschers studio: stopped", flush=True)
    return 0


def notebook(spec: str | None = None, size: int = IMAGE_SIZE) -> Any:
    """The studio page for a Jupyter cell: ``ui = notebook("penrose_triangle")``, then
    ``await ui.ready`` and ``ui`` (the layout shows itself in an iframe)."""
    m, order, label = load_model(spec)
    _, layout = build_page(StudioModel(m, order, label, size=size))
    return layout


def main_studio(args: Any) -> int:
    """``meschers studio`` (see :func:`add_parser`)."""
    return serve(
        args.model, host=args.host, port=args.port, open_browser=args.open, size=args.image_size
    )


def add_parser(sub: Any, **kwargs: Any) -> Any:
    """Register ``meschers studio [MODEL] [--host H] [--port P] [--open]``."""
    p = sub.add_parser(
        "studio",
        help="a studio in the browser: turn, relight, geodesics, smoothing, paint periods",
        description="Serve a page (trame; rendering on the server, so no display is needed) "
        "to turn, relight, measure and reshape a mescher, and to paint a period onto a loop "
        "of a model that embeds. Nothing is written except by the page's Save button.",
        **kwargs,
    )
    p.add_argument(
        "model",
        nargs="?",
        default=None,
        metavar="MODEL",
        help="gallery name, paradox:NAME, .ply/.npz mescher or mesh with a sidecar "
        f"view (default: a {DEFAULT_MODEL} that embeds)",
    )
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default %(default)s)")
    p.add_argument("--port", type=int, default=8080, help="port (default %(default)s; 0: any free)")
    p.add_argument("--open", action="store_true", help="open a browser on the page")
    p.add_argument(
        "--image-size",
        type=int,
        default=IMAGE_SIZE,
        help="pixels of the rendered picture (default %(default)s)",
    )
    p.set_defaults(func=main_studio)
    return p


if __name__ == "__main__":  # python -m meschers.studio [MODEL]
    sys.exit(serve(sys.argv[1] if len(sys.argv) > 1 else None))
