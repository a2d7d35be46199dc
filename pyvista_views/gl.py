"""GL tricks that make a flattened mescher cost what an ordinary mesh costs to draw.

- :func:`use_early_z`: a depth test ``GL_LESS`` while a renderer draws, so an indexed mescher at
  ``z = 0`` drawn front to back keeps the first (frontmost) fragment at each pixel and the GPU
  rejects every hidden fragment before shading it.
- :func:`use_flat_varyings`: per-point normals as ``flat`` varyings, so each triangle takes its
  provoking vertex's normal (the ``"provoking"`` layout of :mod:`.polydata`) without VTK's
  per-primitive cell-normal lookup; :func:`flat_varyings_work` checks once per process that this
  VTK's shaders accept the replacement.

Both are shader/state hooks of VTK's OpenGL renderer; nothing here knows about meschers.
"""

from __future__ import annotations

import functools
import weakref
from typing import Any

import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError

from . import headless
from .camera import set_view
from .lights import DirectionalLight, set_vtk_lights

_GL_LESS, _GL_LEQUAL = 0x0201, 0x0203

#: Renderers whose depth test is ``GL_LESS`` while they draw (:func:`use_early_z`).
_EARLY_Z: weakref.WeakSet = weakref.WeakSet()


def use_early_z(renderer: Any) -> None:
    """Make ``renderer`` draw with the depth test ``GL_LESS`` (VTK's default is ``GL_LEQUAL``).

    An indexed mescher lies at ``z = 0``: every fragment has the same depth, so the test decides
    by drawing order alone.  With ``GL_LESS`` the *first* fragment drawn at a pixel wins, so the
    cells go front to back (the reverse linear extension) and the GPU rejects each hidden
    fragment before shading it (early depth test); with ``GL_LEQUAL`` they would go back to
    front and every fragment would be shaded, about twice the work on a closed surface.
    Real meshes in the same renderer are z-buffered as usual (distinct depths: the test's
    equality case never arises).  Set on the renderer's start event and restored on its end
    event, so other renderers and VTK's own passes keep their state.
    """
    if renderer in _EARLY_Z:
        return

    def depth_func(func: int) -> Any:
        def callback(obj: Any, _event: str) -> None:
            window = obj.GetRenderWindow()
            state = window.GetState() if hasattr(window, "GetState") else None
            if state is not None:
                state.vtkglDepthFunc(func)

        return callback

    renderer.AddObserver("StartEvent", depth_func(_GL_LESS))
    renderer.AddObserver("EndEvent", depth_func(_GL_LEQUAL))
    _EARLY_Z.add(renderer)


_FLAT_VARYINGS = (
    ("out vec3 normalVCVSOutput;", "flat out vec3 normalVCVSOutput;"),
    ("in vec3 normalVCVSOutput;", "flat in vec3 normalVCVSOutput;"),
)


def use_flat_varyings(actor: Any) -> None:
    """Make ``actor``'s per-point normals ``flat`` varyings: each triangle takes the normal of
    its last (provoking) vertex for all its fragments.

    With the ``"provoking"`` layout (:func:`~pyvista_views.polydata.provoking_cells`) that is
    the face's own normal, so flat shading costs what an ordinary mesh costs; VTK's cell normals
    give the same picture but read ``gl_PrimitiveID``, which software rasterizers (Mesa's
    llvmpipe) pay for per triangle.  Done with VTK's shader replacements, after VTK's own.
    """
    prop = actor.GetShaderProperty()
    (vs_old, vs_new), (fs_old, fs_new) = _FLAT_VARYINGS
    prop.AddVertexShaderReplacement(vs_old, False, vs_new, False)
    prop.AddFragmentShaderReplacement(fs_old, False, fs_new, False)


@functools.lru_cache(maxsize=1)
def flat_varyings_work() -> bool:
    """Whether :func:`use_flat_varyings` gives flat shading here (tried once per process).

    Two triangles whose provoking normals face the light and whose other normals face away:
    with flat varyings both are lit evenly; if this VTK's shaders do not match the replacement,
    they come out graded and the renderer falls back to cell normals.
    """
    try:
        plotter = headless.new_plotter((16, 8), off_screen=True)
        P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0]], float)
        mesh = pv.PolyData.from_regular_faces(P, np.array([[0, 1, 2], [1, 3, 4]]))
        normals = np.tile([0.0, 0.0, -1.0], (5, 1))
        normals[[2, 4]] = (0.0, 0.0, 1.0)
        mesh.point_data.active_normals = normals
        actor = plotter.add_mesh(
            mesh, color="white", ambient=0.0, diffuse=1.0, specular=0.0, interpolation="gouraud"
        )
        use_flat_varyings(actor)
        set_view(plotter, (0.0, 2.0, 0.0, 1.0))
        set_vtk_lights(plotter, [DirectionalLight(np.array([0.0, 0.0, 1.0]))])
        image = plotter.screenshot(return_img=True)[..., :3].astype(int)
        plotter.close()
    except Exception:  # any VTK/GL failure: fall back to cell normals, always correct
        return False
    lit = image[2:7, 9:14].reshape(-1, 3)  # inside the second triangle, away from its edges
    return bool(lit.size) and bool((np.abs(lit - 255) <= 1).all())


#: Cell array that carries the face-id colours of :func:`face_id_image`.
_ID_RGB = "_face_id_rgb"


def face_id_image(
    mesh: pv.PolyData,
    window_size: tuple[int, int],
    bounds: tuple[float, float, float, float],
    early_z: bool,
) -> np.ndarray:
    """Which cell's ``face_id`` is drawn at each pixel: the renderer's own visibility.

    ``mesh`` (a layer's PolyData, with ``cell_data["face_id"]``) is drawn once more, unlit and
    without anti-aliasing, in its own offscreen plotter with the same camera, window and depth
    test, each cell coloured by ``face_id + 1`` in 24 bits on a black background; the
    screenshot decoded is what the picture shows face by face, exactly (same rasterizer, same
    drawing order).

    Parameters
    ----------
    mesh : pyvista.PolyData
    window_size : (width, height)
    bounds : (xmin, xmax, ymin, ymax)
    early_z : bool
        The mesh's cells go front to back (:func:`use_early_z`).

    Returns
    -------
    (height, width) int64
        Face id per pixel, -1 where no face is drawn.
    """
    ids = np.asarray(mesh.cell_data["face_id"], dtype=np.int64) + 1
    if ids.size and ids.max() >= 2**24:
        raise MescherError(
            f"mesh: expected at most 2**24 - 1 faces (24-bit colours), found {ids.max()}"
        )
    rgb = np.stack([(ids >> 16) & 255, (ids >> 8) & 255, ids & 255], axis=1).astype(np.uint8)
    shallow = mesh.copy(deep=False)
    shallow.cell_data[_ID_RGB] = rgb
    plotter = _id_plotter(window_size, early_z)
    try:
        plotter.add_mesh(
            shallow,
            scalars=_ID_RGB,
            rgb=True,
            preference="cell",
            lighting=False,
            interpolation="flat",
            show_scalar_bar=False,
            reset_camera=False,
            name="ids",
        )
        set_view(plotter, bounds)
        plotter.render()  # PyVista's screenshot renders only a plotter's first frame
        image = plotter.screenshot(return_img=True)[..., :3].astype(np.int64)
    finally:
        plotter.remove_actor("ids", render=False)
    return ((image[..., 0] << 16) | (image[..., 1] << 8) | image[..., 2]) - 1


_ID_PLOTTERS: list[tuple[pv.Plotter, list[bool]]] = []


def _id_plotter(window_size: tuple[int, int], early_z: bool) -> pv.Plotter:
    """One offscreen plotter per process for :func:`face_id_image` (a new GL context costs
    about as much as a frame), made again if it was closed (``pyvista.close_all``); its depth
    test is ``GL_LESS`` while it draws a front-to-back mesh (:func:`use_early_z`)."""
    while _ID_PLOTTERS and getattr(_ID_PLOTTERS[-1][0], "render_window", None) is None:
        _ID_PLOTTERS.pop()
    if not _ID_PLOTTERS:
        plotter = headless.new_plotter(window_size, off_screen=True, background="black")
        flag = [False]

        def depth_func(obj: Any, _event: str, start: bool) -> None:
            window = obj.GetRenderWindow()
            state = window.GetState() if hasattr(window, "GetState") else None
            if state is not None:
                state.vtkglDepthFunc(_GL_LESS if (start and flag[0]) else _GL_LEQUAL)

        plotter.renderer.AddObserver("StartEvent", lambda o, e: depth_func(o, e, True))
        plotter.renderer.AddObserver("EndEvent", lambda o, e: depth_func(o, e, False))
        _ID_PLOTTERS.append((plotter, flag))
    plotter, flag = _ID_PLOTTERS[-1]
    flag[0] = bool(early_z)
    if tuple(plotter.window_size) != tuple(window_size):
        # A new window rather than a resized one: the first frame after resizing an offscreen
        # EGL window comes back nearly empty (seen with VTK 9.4-9.7 on Mesa).
        plotter.close()
        _ID_PLOTTERS.pop()
        return _id_plotter(window_size, early_z)
    return plotter
