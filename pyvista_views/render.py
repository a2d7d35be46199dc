"""One-shot head-on rendering of a mescher (or a real mesh) to an image: :func:`render`.

The building blocks live beside it: :mod:`.scene` (layers, lights, :class:`MescherScene`),
:mod:`.camera` (bounds and the orthographic view) and :mod:`.gl` (the GL tricks that make a
mescher draw as fast as an ordinary mesh).  Their names are re-exported here too.
"""

from __future__ import annotations

import logging
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_choice

from .camera import DEFAULT_MARGIN, as_bounds, default_bounds, set_view, xy_box
from .envmap import as_env_map
from .gl import flat_varyings_work, use_early_z, use_flat_varyings
from .layers import (
    DEFAULT_COLOR,
    DEFAULT_LIGHTS,
    REPRESENTATIONS,
    Layer,
    add_embedding,
    add_mescher,
    relight,
)
from .lights import as_lights
from .overlays import as_path_marks, as_point_marks
from .polydata import SHADINGS
from .scene import MescherScene, embedding_of

_LOG = logging.getLogger(__name__)

__all__ = [
    "DEFAULT_COLOR",
    "DEFAULT_LIGHTS",
    "DEFAULT_MARGIN",
    "Layer",
    "MescherScene",
    "add_embedding",
    "add_mescher",
    "as_bounds",
    "default_bounds",
    "default_depth",
    "hide_back_faces",
    "embedding_of",
    "flat_varyings_work",
    "relight",
    "render",
    "render_scene",
    "set_view",
    "use_early_z",
    "use_flat_varyings",
    "xy_box",
]


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
        Back-to-front order of a mescher's faces.  ``None``: resolved so that no back face
        shows (:func:`default_depth`: the z-buffer for a possible mescher in one piece, else an
        order from local depth; logged, and kept as ``scene.layers[-1].depth``); pass
        ``np.arange(#F)`` for face-index order.
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
        ``clim``, ``paths`` (a SurfacePath, ``(xy, faces)`` or a dict with ``path``,
        ``color``, ``width``, ``hidden`` ("omit" or "dashed") and ``label``, or a list of them:
        drawn only where they lie on the visible surface,
        :meth:`MescherScene.add_path`), ``points`` (vertex ids, or a dict with ``vertices``,
        ``color``, ``radius``, ``labels``: discs on the visible surface, clipped to the
        figure, :meth:`MescherScene.add_points`), ``isolines``, ``isoline_color``, ``isoline_width`` (2), ``ambient`` (0.2),
        ``diffuse`` (0.8), ``anti_aliasing`` (default ``"fxaa"``, a cheap post-pass; ``"ssaa"``
        or True supersamples, ``False`` keeps pixel-exact silhouettes),
        ``feature_angle`` (30: smooth shading keeps edges sharper than this crisp, ``None``
        blends every edge), ``scalar_bar`` (with ``scalars``, a colour
        bar in a strip on the right, :meth:`MescherScene.add_scalar_bar`; the default bounds
        then frame the figure in the rest of the window.  Default: on unless ``bounds`` is
        given; with explicit bounds, leave the strip free with
        ``camera.default_bounds(box, window_size, reserve=scene.scalar_bar_strip(width))`` and pass
        ``scalar_bar=True``), ``scalar_bar_title`` (default:
        the field's name, the key of a dict of scalars, else ``"scalars"``), ``exposure`` (1),
        ``tone_map`` ("none" or "reinhard") and ``normalize_lights`` (True): by default the
        lights and environment are scaled so that no visible normal is lit brighter than the
        material's colour, however many lights there are (:func:`~pyvista_views.layers.relight`).

    Returns
    -------
    (H, W, 3) uint8
    """
    with render_scene(
        m, order, lights, shading, scalars, env_map, window_size, bounds, background, **kwargs
    ) as scene:
        return scene.screenshot()


def default_depth(m: Any) -> tuple[object, str]:
    """How :func:`render` resolves overlaps of a mescher given without an order.

    A possible mescher in one piece (every period 0) is an ordinary surface: its bent
    embedding (depth from zeta) is drawn with the z-buffer, exactly as the 3D mesh it is.
    Otherwise the order is built from the mescher's relative depths
    (:meth:`meschers_igl.DepthOrder.from_local_depth`).  Which one was used is logged and
    kept as the layer's ``depth``.

    Returns
    -------
    ((V, F), "z-buffer") or (DepthOrder, "local depth")
    """
    from meschers_igl import DepthOrder
    from meschers_igl.topology import connected_components

    F = np.asarray(m.F, dtype=np.int64)
    n_parts, _ = connected_components(F, int(np.asarray(m.xy).shape[0]))
    if n_parts == 1 and not m.is_impossible():
        depth: tuple[object, str] = (m.bent_embedding(), "z-buffer")
    else:
        depth = (hide_back_faces(m, DepthOrder.from_local_depth(m)), "local depth")
    _LOG.info("render: no order given; overlaps resolved by %s", depth[1])
    return depth


def hide_back_faces(m: Any, order: Any) -> Any:
    """Put every back face behind the front faces it overlaps, on a closed mescher.

    On a closed surface seen from outside the nearest sheet at every pixel faces the viewer
    (a ray enters the solid through a front face), so a back face (clockwise on screen,
    ``n_z <= 0``) is behind every front face it overlaps.  Orders carried through smoothing or
    subdivision (:meth:`~meschers_igl.DepthOrder.follow`) or built from local depth can miss a
    few such pairs where the surface turns edge-on; this adds them
    (:meth:`~meschers_igl.DepthOrder.put_in_front`; it only adds back-to-front arcs, so it
    closes no cycle).  A mescher with a boundary (a ribbon, a relief) shows its underside
    legitimately and is left as it is.

    Parameters
    ----------
    m : Mescher
    order : DepthOrder

    Returns
    -------
    DepthOrder
        ``order``, changed in place when ``m`` is closed.
    """
    F = np.asarray(m.F, dtype=np.int64)
    if 2 * int(np.asarray(m.edges).shape[0]) != 3 * F.shape[0]:
        return order  # a boundary: back faces may be seen
    T = np.asarray(m.xy, dtype=np.float64)[F]
    area = (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1]) - (T[:, 1, 1] - T[:, 0, 1]) * (
        T[:, 2, 0] - T[:, 0, 0]
    )
    front, back = np.flatnonzero(area > 0), np.flatnonzero(area <= 0)
    if front.size and back.size:
        order.put_in_front(front, back, m=m)
    return order


def render_scene(
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
) -> MescherScene:
    """The scene :func:`render` screenshots, left open (arguments as in :func:`render`).

    For callers that want the plotter itself: ``scene.plotter.show()`` (e.g. under
    pytest-pyvista's ``verify_image_cache``), more layers, or an export.  Close it when done
    (it is a context manager).
    """
    representation = as_choice(
        kwargs.pop("representation", "mescher"), "representation", REPRESENTATIONS
    )
    anti_aliasing = kwargs.pop("anti_aliasing", None)  # None: the scene's default
    paths = kwargs.pop("paths", None)
    points = kwargs.pop("points", None)
    scalar_bar = kwargs.pop("scalar_bar", None)
    if scalar_bar is None:  # by default only where the default framing leaves it its strip
        scalar_bar = bounds is None
    scalar_bar = bool(scalar_bar) and scalars is not None
    exposure = {
        "exposure": kwargs.pop("exposure", 1.0),
        "tone_map": kwargs.pop("tone_map", "none"),
        "normalize": bool(kwargs.pop("normalize_lights", True)),
    }
    bar_title = kwargs.pop("scalar_bar_title", None)
    as_choice(shading, "shading", SHADINGS)
    directional = as_lights(lights)  # refuse point lights before any GL work
    env = as_env_map(env_map)
    if bounds is not None:
        bounds = as_bounds(bounds)
    scene = MescherScene(
        window_size=window_size, background=background, anti_aliasing=anti_aliasing
    )
    try:
        scene.relight(directional, env, **exposure)  # before the layer: lit (and baked) once
        if scalar_bar:
            scene.reserve_scalar_bar()  # before the layer, so it is framed once
        if bounds is not None:
            scene.view(bounds)
        if isinstance(m, (tuple, list)):
            if representation != "mescher" or len(m) != 2:
                raise MescherError(
                    "m: expected a Mescher, or a (V, F) pair with representation='mescher', "
                    f"found a {len(m)}-tuple with representation={representation!r}"
                )
            scene.add_embedding(m[0], m[1], shading=shading, scalars=scalars, **kwargs)
        elif representation == "mescher":
            if not hasattr(m, "F"):
                raise MescherError(f"m: expected a Mescher, found {type(m).__name__}")
            depth = "order"
            if order is None:
                order, depth = default_depth(m)
            if depth == "z-buffer":
                V, F = order
                scene.add_embedding(V, F, shading=shading, scalars=scalars, **kwargs)
            else:
                scene.add(m, order=order, shading=shading, scalars=scalars, **kwargs)
            scene.layers[-1].depth = depth
        else:
            scene.add_embedding(m, kind=representation, shading=shading, scalars=scalars, **kwargs)
        for spec in as_path_marks(paths, scene.layers[-1].source[1].shape[0]):
            scene.add_path(
                (spec.xy, spec.faces),
                color=spec.color,
                width=spec.width,
                hidden=spec.hidden,
                label=spec.label,
            )
        for spec in as_point_marks(points, scene.layers[-1].source[0].shape[0]):
            scene.add_points(
                spec.vertices, color=spec.color, radius=spec.radius, labels=spec.labels
            )
        if scalar_bar:
            scene.add_scalar_bar(bar_title)
        if bounds is None:
            scene.view()
    except BaseException:
        scene.close()
        raise
    return scene
