"""Meschers (and real meshes) as PyVista meshes ready for head-on rendering.

A mescher has no absolute depth, so it is drawn flat (paper Section 4.1): its shade comes from
normals derived from zeta, not from the flat geometry, and overlaps are resolved by the painter's
algorithm in a linear extension of the depth order.  Two layouts do this:

``"indexed"`` (what :mod:`.render` uses)
    The mescher's own ``#V`` vertices at ``z = 0`` and its faces as cells in drawing order.  All
    fragments have the same depth, so OpenGL's depth test decides by drawing order alone: with
    VTK's default ``GL_LEQUAL`` the *last* coplanar fragment wins (cells back to front), with
    ``GL_LESS`` the *first* (cells front to back, which also lets the GPU reject hidden fragments
    before shading them; see :func:`pyvista_views.gl.use_early_z`).  No per-face copies: the
    same number of points as an ordinary mesh.
``"provoking"`` (what :mod:`.render` uses for flat shading)
    The indexed layout without cell data: each cell is rotated (orientation kept) so that its
    *last* corner, OpenGL's provoking vertex, is a point no other cell ends with (cell ``k``
    ends with point ``k``; vertices are copied where needed, about ``#F`` points in all), and
    that point carries the face's normal.
    Drawn with ``flat`` varyings (:func:`pyvista_views.gl.use_flat_varyings`) every fragment
    gets its face's normal exactly as with cell normals, without the per-primitive lookup
    (``gl_PrimitiveID``) that VTK's cell normals cost on software rasterizers.  Only for drawing:
    a plain VTK pipeline would interpolate those normals.
``"soup"``
    Each face gets its own three points at ``z = k * step`` for the face drawn k-th, so under the
    orthographic camera looking down -z the z-buffer reproduces the drawing order with any depth
    test and any renderer (exporters, vtk.js).  Per-corner values come for free, which isolines on
    a mescher and some baked-colour combinations need (:func:`needs_soup`).

Flat shading sets the faces' normals as the *active cell normals* (VTK ignores point normals with
flat interpolation); smooth shading sets per-vertex normals as active point normals (Gouraud).
"""

from __future__ import annotations

from typing import Any

import igl
import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.jit import kernel
from meschers_igl.validate import as_choice, as_faces, as_float_array, as_points

from .normals import DEFAULT_FEATURE_ANGLE, as_feature_angle, corner_groups

#: Total depth span of the painter's offsets as a fraction of the xy bounding-box diagonal: small
#: enough to be invisible to everything but the z-buffer, large enough for 24-bit depth at 1M faces
#: once the camera's clipping range is fitted to it.
PAINTER_DEPTH_FRACTION = 1e-3

SHADINGS = ("flat", "smooth")
LAYOUTS = ("soup", "indexed", "provoking")

#: Field-data names under which :func:`to_polydata` (``embed=True``) stores the mescher itself,
#: so that ``poly.mescher.to_mescher()`` and the ``.mescher`` writer recover it exactly.
FIELD_EDGES, FIELD_ZETA, FIELD_ARCS, FIELD_HAS_ORDER = "edges", "zeta", "depth_arcs", "has_order"


def draw_order(order: object, n_faces: int) -> np.ndarray:
    """Back-to-front face order.

    Parameters
    ----------
    order : None, DepthOrder or (#F,) array_like
        ``None``: face-index order.  An object with ``linear_extension()`` (a
        :class:`meschers_igl.DepthOrder`): its topological sort.  An array: a permutation of
        ``range(n_faces)``, back to front.
    n_faces : int

    Returns
    -------
    (#F,) int64
        ``draw[k]`` is the face drawn k-th.
    """
    if order is None:
        return np.arange(n_faces, dtype=np.int64)
    if hasattr(order, "linear_extension"):
        draw = np.asarray(order.linear_extension())
    else:
        draw = np.asarray(order)
    if draw.ndim != 1 or draw.shape[0] != n_faces or not np.issubdtype(draw.dtype, np.integer):
        raise MescherError(
            f"order: expected a DepthOrder or a permutation of the {n_faces} faces, found "
            f"{draw.dtype} array of shape {draw.shape}"
        )
    draw = draw.astype(np.int64, copy=False)
    if draw.min() < 0 or draw.max() >= n_faces or np.bincount(draw, minlength=n_faces).max() > 1:
        raise MescherError(
            f"order: expected each face index in [0, {n_faces}) exactly once, found repeated or "
            "out-of-range indices"
        )
    return draw


def as_scalars(
    scalars: object, n_vertices: int, n_faces: int, name: str = "scalars"
) -> dict[str, tuple[np.ndarray, str]]:
    """Normalise scalar fields to ``{name: (values, "vertex" | "face")}``.

    Parameters
    ----------
    scalars : None, (#V,) or (#F,) array_like, or dict of them
        A length equal to #V is read per vertex (also when #V == #F), #F per face.  ``+inf``
        (e.g. a distance to a part no source reaches) becomes NaN, drawn as "unreached".
    """
    if scalars is None:
        return {}
    items = scalars.items() if isinstance(scalars, dict) else [(name, scalars)]
    out = {}
    for key, values in items:
        arr_name = name if key == name else f"{name}[{key!r}]"
        a = np.asarray(values)
        n = a.shape[0] if a.ndim == 1 else -1
        # +inf (a distance to a part no source reaches) is drawn as "unreached": NaN, with
        # its own colour (UNREACHED_COLOR); any other non-finite value is refused
        unreached = np.isposinf(a) if np.issubdtype(a.dtype, np.floating) else None
        if unreached is not None and unreached.any():
            a = np.where(unreached, 0.0, a)
        if n == n_vertices:
            v = as_float_array(a, arr_name, (n_vertices,))
            location = "vertex"
        elif n == n_faces:
            v = as_float_array(a, arr_name, (n_faces,))
            location = "face"
        else:
            raise MescherError(
                f"{arr_name}: expected one value per vertex ({n_vertices},) or per face "
                f"({n_faces},), found shape {a.shape}"
            )
        if unreached is not None and unreached.any():
            v[unreached] = np.nan
        out[str(key)] = (v, location)
    return out


def soup(
    corners: np.ndarray,
    F: np.ndarray,
    draw: np.ndarray,
    face_normals: np.ndarray | None = None,
    corner_normals: np.ndarray | None = None,
    scalars: dict[str, tuple[np.ndarray, str]] | None = None,
) -> pv.PolyData:
    """A triangle soup with normals and scalars, cells in draw order.

    Parameters
    ----------
    corners : (k, 3, 3) float64
        Corner positions of the drawn faces, in draw order.
    F : (#F, 3) int64
        Faces of the source mesh (for vertex ids and per-vertex scalars).
    draw : (k,) int64
        Source face of each cell.
    face_normals : (k, 3) float64, optional
        Set as the active cell normals (flat shading; VTK then ignores point normals).
    corner_normals : (k, 3, 3) float64, optional
        Set as the active point normals (smooth shading, interpolated over each triangle).
    scalars : dict, optional
        From :func:`as_scalars`; vertex values become per-corner point data, face values cell data.

    Returns
    -------
    pyvista.PolyData
        3k points, k triangles; ``cell_data["face_id"]`` (source face) and
        ``point_data["vertex_id"]`` (source vertex of each corner) for picking and mapping back.
    """
    k = corners.shape[0]
    mesh = pv.PolyData.from_regular_faces(
        corners.reshape(-1, 3), np.arange(3 * k, dtype=np.int64).reshape(k, 3)
    )
    mesh.cell_data["face_id"] = draw
    mesh.point_data["vertex_id"] = F[draw].reshape(-1)
    if face_normals is not None:
        mesh.cell_data.active_normals = face_normals
    if corner_normals is not None:
        mesh.point_data.active_normals = corner_normals.reshape(-1, 3)
    for key, (values, location) in (scalars or {}).items():
        if location == "vertex":
            mesh.point_data[key] = values[F[draw]].reshape(-1)
        else:
            mesh.cell_data[key] = values[draw]
    # PyVista makes the first array added active; only a user's scalar field may be.
    mesh.set_active_scalars(next(iter(scalars)) if scalars else None)
    return mesh


def screen_facing(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """+1 for cells counter-clockwise on screen (or degenerate), -1 for clockwise ones.

    Parameters
    ----------
    points : (n, 3) or (n, 2) float64
    cells : (k, 3) int64

    Returns
    -------
    (k,) float64
        The sign of the screen-space signed area: VTK's two-sided lighting flips the normal of a
        clockwise (back-facing) triangle, and baked shading must do the same.
    """
    p = np.asarray(points)[:, :2]
    a, b, c = p[cells[:, 0]], p[cells[:, 1]], p[cells[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return np.where(cross < 0, -1.0, 1.0)


def split_by_facing(cells: np.ndarray, facing: np.ndarray, n_points: int) -> tuple:
    """Give clockwise cells their own copy of every vertex they share with counter-clockwise ones.

    Then each point is used by cells of one facing only, so a per-point colour can carry the
    flipped normal of back-facing cells (baked smooth shading) while front-facing neighbours keep
    theirs.  Only vertices on a fold (where facing changes) are copied.

    Returns
    -------
    cells : (k, 3) int64
        Cells indexing the extended point list.
    source : (n_points + c,) int64
        Original point of each point (``arange(n_points)`` then the ``c`` copied ones).
    """
    ccw = facing > 0
    used = np.zeros((2, n_points), dtype=bool)
    used[0, cells[ccw].reshape(-1)] = True
    used[1, cells[~ccw].reshape(-1)] = True
    mixed = np.flatnonzero(used[0] & used[1])
    if mixed.size == 0:
        return cells, np.arange(n_points, dtype=np.int64)
    copy_of = np.full(n_points, -1, dtype=np.int64)
    copy_of[mixed] = n_points + np.arange(mixed.size)
    out = cells.copy()
    cw = out[~ccw]
    out[~ccw] = np.where(copy_of[cw] >= 0, copy_of[cw], cw)
    return out, np.concatenate([np.arange(n_points, dtype=np.int64), mixed])


def split_folds(mesh: pv.PolyData) -> pv.PolyData:
    """``mesh`` (triangles) with its vertices split on folds (:func:`split_by_facing`).

    Every point array is carried to the copies, cell and field arrays are kept; returns
    ``mesh`` itself when no vertex lies on a fold.
    """
    cells = np.asarray(mesh.regular_faces, dtype=np.int64)
    out, source = split_by_facing(cells, screen_facing(mesh.points, cells), mesh.n_points)
    if source.shape[0] == mesh.n_points:
        return mesh
    split = pv.PolyData.from_regular_faces(np.asarray(mesh.points)[source], out)
    for name in mesh.point_data.keys():
        split.point_data[name] = np.asarray(mesh.point_data[name])[source]
    for name in mesh.cell_data.keys():
        split.cell_data[name] = np.asarray(mesh.cell_data[name])
    for name in mesh.field_data.keys():
        split.field_data[name] = np.asarray(mesh.field_data[name])
    if mesh.point_data.active_normals is not None:
        split.point_data.active_normals = np.asarray(mesh.point_data.active_normals)[source]
    split.set_active_scalars(mesh.active_scalars_name)
    if "vertex_id" in mesh.point_data:  # copies keep their source vertex
        split.point_data["vertex_id"] = np.asarray(mesh.point_data["vertex_id"])[source]
    return split


@kernel(inline="always")
def _claim(F: np.ndarray, f: int, new_index: np.ndarray, i: int) -> tuple[int, int, int]:
    # Cell i (face f) claims the first of its corners 2, 0, 1 that no earlier cell claimed and
    # returns its corners rotated (orientation kept) to end with it; with every corner taken,
    # unrotated (it will end with a copy of its corner 2).
    a, b, c = F[f, 0], F[f, 1], F[f, 2]
    if new_index[c] < 0:
        new_index[c] = i
        return a, b, c
    if new_index[a] < 0:
        new_index[a] = i
        return b, c, a
    if new_index[b] < 0:
        new_index[b] = i
        return c, a, b
    return a, b, c


@kernel()
def _provoking_mesh(
    F: np.ndarray, draw: np.ndarray, points: np.ndarray, face_normals: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    # One sequential greedy pass over the cells F[draw] (numba: each cell's claim depends on the
    # claims before it, which numpy can only approximate with several whole-array rounds, about
    # 10x slower at 1M faces; reading F through draw also saves the copy F[draw]), the points
    # (``points`` of 0, 2 or 3 columns, z = 0 for the missing) and the provoking normals
    # written in the same pass: point i is written when cell i claims it,
    # while its face's row is in cache (a second pass gathering them cost as much as the claims
    # at 1M faces, in a random depth order more).  Output rows are allocated for the most
    # points there can be (k + n); the rows past the last are never touched (no memory used).
    k, n, d = draw.shape[0], points.shape[0], points.shape[1]
    new_index = np.empty(n, dtype=np.int64)
    for v in range(n):  # a loop, not np.full: one allocation spelling in every kernel
        new_index[v] = -1
    out = np.empty((k, 3), dtype=np.int64)
    source = np.empty(k + n, dtype=np.int64)
    P = np.empty((k + n, 3), dtype=np.float64)
    N = np.empty((k + n, 3), dtype=np.float32)
    for i in range(k):
        f = draw[i]
        out[i, 0], out[i, 1], v = _claim(F, f, new_index, i)
        source[i] = v
        P[i, 2] = 0.0
        for c in range(d):
            P[i, c] = points[v, c]
        N[i, 0], N[i, 1], N[i, 2] = face_normals[f, 0], face_normals[f, 1], face_normals[f, 2]
    j = k
    for v in range(n):
        if new_index[v] < 0:  # ends no cell: its normal is never read, but unit
            new_index[v] = j
            source[j] = v
            P[j, 2] = 0.0
            for c in range(d):
                P[j, c] = points[v, c]
            N[j, 0], N[j, 1], N[j, 2] = 0.0, 0.0, 1.0
            j += 1
    for i in range(k):
        out[i, 0] = new_index[out[i, 0]]
        out[i, 1] = new_index[out[i, 1]]
        out[i, 2] = i
    return out, source[:j], P[:j], N[:j]


def _frozen(a: Any, dtype: Any) -> np.ndarray:
    """``a`` as a C-contiguous read-only array of ``dtype``, copied only if it must be.

    The kernels always get read-only input (a mescher's arrays are read-only, a user's may be
    writable): numba compiles one specialisation per flag, so one flag means one signature, the
    one the first run compiles, and no copy of arrays that are already right.
    """
    out = np.ascontiguousarray(a, dtype=dtype).view()
    out.flags.writeable = False
    return out


def provoking_cells(cells: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Renumber points so that cell ``k`` ends with point ``k``, each cell's corners rotated.

    OpenGL takes a ``flat`` varying from a triangle's last (provoking) vertex, so a per-face value
    stored on point ``k`` reaches exactly the fragments of cell ``k``.  Each cell in turn claims
    the first of its corners 2, 0, 1 that no earlier cell claimed and is rotated, orientation
    kept, to end with it; a cell left without one ends with a copy of its corner 2.  Points
    ``0 .. k-1`` follow the cells (sequential vertex fetches), the vertices no cell claimed come
    after.  A closed mesh has about twice as many faces as vertices, so about ``#F - #V`` copies
    are unavoidable.

    Parameters
    ----------
    cells : (k, 3) int64
    n_points : int

    Returns
    -------
    cells : (k, 3) int64
        Row ``i`` is a rotation of input row ``i`` (through ``source``) and ends with ``i``.
    source : (k + u,) int64
        Original point of each new point; every original point appears.
    """
    cells = _frozen(cells, np.int64)
    k = cells.shape[0]
    draw = _frozen(np.arange(k, dtype=np.int64), np.int64)
    # the renderer's kernel with no point columns and zero normals: one compiled kernel for both
    # (the types are the renderer's, so nothing more to compile)
    none = _frozen(np.empty((int(n_points), 0)), np.float64)
    out, source, _, _ = _provoking_mesh(cells, draw, none, _frozen(np.zeros((k, 3)), np.float64))
    return out, source


def indexed(
    points: np.ndarray,
    F: np.ndarray,
    draw: np.ndarray,
    face_normals: np.ndarray | None = None,
    vertex_normals: np.ndarray | None = None,
    scalars: dict[str, tuple[np.ndarray, str]] | None = None,
    provoking: bool = False,
    split_folds: bool = True,
) -> pv.PolyData:
    """An indexed triangle mesh with normals and scalars, cells in draw order.

    Parameters
    ----------
    points : (#V, 3) or (#V, 2) float64
        Two columns: ``z = 0``.
    F : (#F, 3) int64
    draw : (k,) int64
        Source face of each cell, in drawing order.
    face_normals : (#F, 3) float64, optional
        Flat shading: ``face_normals[draw]`` become the active cell normals.
    vertex_normals : (#V, 3) float64, optional
        Smooth shading: active point normals (stored as float32, what VTK draws with, like
        every normal here); vertices on a fold between counter-clockwise and
        clockwise cells are split (:func:`split_by_facing`) so that baked colours stay exact.
    scalars : dict, optional
        From :func:`as_scalars`: vertex values become point data, face values cell data.
    provoking : bool, default: False
        With ``face_normals``: the ``"provoking"`` layout (module docstring,
        :func:`provoking_cells`): the normals go to each cell's last point, no cell normals.
    split_folds : bool, default: True
        With ``vertex_normals``: split vertices on folds now (:func:`split_by_facing`); only
        baked colours need it, so the renderer defers it to :func:`split_folds`.

    Returns
    -------
    pyvista.PolyData
        ``cell_data["face_id"]`` (source face) and ``point_data["vertex_id"]`` (source vertex).
    """
    n = points.shape[0]
    source = np.arange(n, dtype=np.int64)
    provoking = provoking and face_normals is not None
    normals = None
    if provoking and not (vertex_normals is not None and split_folds):
        cells, source, points, normals = _provoking_mesh(
            _frozen(F, np.int64),
            _frozen(draw, np.int64),
            _frozen(points, np.float64),
            _frozen(face_normals, np.float64),
        )
    else:
        provoking = False
        cells = F[draw]
        if vertex_normals is not None and split_folds:
            cells, source = split_by_facing(cells, screen_facing(points, cells), n)
        if points.shape[1] == 2:  # z = 0
            points = np.column_stack([points, np.zeros(n)])
    remapped = provoking or source.shape[0] > n
    if remapped and not provoking:
        points = points[source]
    mesh = pv.PolyData.from_regular_faces(points, cells)
    mesh.cell_data["face_id"] = draw
    mesh.point_data["vertex_id"] = source
    if normals is not None:
        mesh.point_data.active_normals = normals
    elif face_normals is not None:
        mesh.cell_data.active_normals = np.asarray(face_normals, dtype=np.float32)[draw]
    if vertex_normals is not None:
        normals = np.asarray(vertex_normals, dtype=np.float32)
        mesh.point_data.active_normals = normals[source] if remapped else normals
    for key, (values, location) in (scalars or {}).items():
        if location == "vertex":
            mesh.point_data[key] = values[source]
        else:
            mesh.cell_data[key] = values[draw]
    mesh.set_active_scalars(next(iter(scalars)) if scalars else None)
    return mesh


def needs_soup(shading: str, scalars: dict[str, tuple[np.ndarray, str]], isolines: bool) -> bool:
    """Whether a layer must be a soup rather than an indexed mesh.

    Isolines on a mescher are hidden by the faces drawn after them through per-face depths, and
    baked colours (environment maps) multiply an albedo and an irradiance that must live at the
    same place: per face for flat shading, per vertex for smooth shading.  A per-vertex scalar
    with flat shading (or a per-face one with smooth shading) varies where the other is constant,
    which only per-corner values represent.
    """
    if isolines:
        return True
    wanted = "face" if shading == "flat" else "vertex"
    return any(location != wanted for _, location in scalars.values())


def _painter_step(xy: np.ndarray, n_faces: int) -> float:
    extent = np.ptp(xy, axis=0)
    diagonal = float(np.hypot(*extent)) or 1.0
    return PAINTER_DEPTH_FRACTION * diagonal / max(n_faces, 1)


def to_polydata(
    m: Any,
    order: object = None,
    shading: str = "flat",
    scalars: object = None,
    layout: str = "soup",
    *,
    front_to_back: bool = False,
    embed: bool = False,
    split_folds: bool = True,
    feature_angle: float | None = DEFAULT_FEATURE_ANGLE,
) -> pv.PolyData:
    """The flattened mescher, drawn back to front (paper Section 4.1).

    Parameters
    ----------
    m : meschers_igl.Mescher
    order : None, DepthOrder or (#F,) array_like
        Back-to-front order (:func:`draw_order`); ``None`` draws in face-index order.
    shading : {"flat", "smooth"}
        ``"flat"``: ``m.face_normals()`` (from zeta) as the active cell normals.  ``"smooth"``:
        ``m.vertex_normals()`` as active point normals, interpolated (Gouraud).  Never use
        PyVista's ``smooth_shading=True`` on the result: it recomputes normals from the flattened
        geometry, which are all (0, 0, 1).
    scalars : None, (#V,) or (#F,) array_like, or dict name -> array
        Scalar fields; the first one is the active scalars.
    layout : {"soup", "indexed", "provoking"}
        ``"soup"``: ``3 #F`` points ``(x, y, k * step)`` for the face drawn k-th (renders right
        with any depth test, any renderer).  ``"indexed"``: the ``#V`` vertices at ``z = 0``
        (plus copies on folds for smooth shading, :func:`split_by_facing`), right with VTK's
        default ``GL_LEQUAL`` depth test.  ``"provoking"``: for drawing with ``flat`` varyings
        only (module docstring); its cells' corners are rotated.
    front_to_back : bool, default: False
        Indexed and provoking layouts: cells in reverse drawing order, for a ``GL_LESS`` depth test
        (:func:`pyvista_views.gl.use_early_z`).
    embed : bool, default: False
        Also store the mescher in field data (``"edges"`` (#E, 2), ``"zeta"`` (#E,), and
        ``"depth_arcs"`` (#A, 2) with ``"has_order"`` when ``order`` is a DepthOrder) so that
        ``poly.mescher.to_mescher()`` recovers ``m`` (and the order) exactly.
    split_folds : bool, default: True
        Smooth indexed layout: copy vertices where the screen winding changes
        (:func:`split_by_facing`), so per-vertex baked colours can differ across a fold.
    feature_angle : float or None, default: 30
        Smooth shading: normals are not shared across edges whose dihedral angle (from zeta)
        exceeds this many degrees (:func:`pyvista_views.normals.corner_groups`), so creases stay
        crisp; ``None`` or 180: plain vertex normals.

    Returns
    -------
    pyvista.PolyData
        Cells in drawing order with ``cell_data["face_id"]``, ``point_data["vertex_id"]``,
        normals, scalars and ``field_data["painter_step"]`` (0 for the indexed layout).
    """
    shading = as_choice(shading, "shading", SHADINGS)
    layout = as_choice(layout, "layout", LAYOUTS)
    F = np.asarray(m.F, dtype=np.int64)
    xy = np.asarray(m.xy, dtype=np.float64)
    n_faces = F.shape[0]
    draw = draw_order(order, n_faces)
    fields = as_scalars(scalars, xy.shape[0], n_faces)
    groups = None
    if shading == "smooth":
        groups, group_vertex, group_normals = corner_groups(
            F,
            np.asarray(m.face_normals()),
            np.asarray(m.face_areas()),
            as_feature_angle(feature_angle),
            vertex_normals=np.asarray(m.vertex_normals()),
        )
    if layout != "soup":
        flat = shading == "flat"
        points = xy  # z = 0 (indexed pads it; the provoking kernel writes its own points)
        if not flat:
            points = np.column_stack([xy, np.zeros(xy.shape[0])])
        cells, normals, drawn_fields = F, None, fields
        if not flat:  # one point per group of corners (vertices split at creases)
            points, cells, normals = points[group_vertex], groups, group_normals
            drawn_fields = {
                k: ((v[group_vertex], loc) if loc == "vertex" else (v, loc))
                for k, (v, loc) in fields.items()
            }
        mesh = indexed(
            points,
            cells,
            np.ascontiguousarray(draw[::-1]) if front_to_back else draw,
            face_normals=m.face_normals() if flat else None,
            vertex_normals=normals,
            scalars=drawn_fields,
            provoking=layout == "provoking",
            split_folds=split_folds,
        )
        if not flat:
            mesh.point_data["vertex_id"] = group_vertex[np.asarray(mesh.point_data["vertex_id"])]
        step = 0.0
    else:
        step = _painter_step(xy, n_faces)
        corners = np.empty((n_faces, 3, 3))
        corners[:, :, :2] = xy[F[draw]]
        corners[:, :, 2] = (np.arange(n_faces) * step)[:, None]
        if shading == "flat":
            normals = np.asarray(m.face_normals())[draw]
            mesh = soup(corners, F, draw, face_normals=normals, scalars=fields)
        else:
            mesh = soup(
                corners, F, draw, corner_normals=group_normals[groups[draw]], scalars=fields
            )
    mesh.field_data["painter_step"] = np.array([step])
    if embed:
        mesh.field_data[FIELD_EDGES] = np.asarray(m.edges, dtype=np.int64)
        mesh.field_data[FIELD_ZETA] = np.asarray(m.zeta, dtype=np.float64)
        arcs = getattr(order, "arcs", None)
        mesh.field_data[FIELD_HAS_ORDER] = np.array([arcs is not None])
        if arcs is not None and len(arcs):  # VTK arrays cannot be empty: no arcs, no array
            mesh.field_data[FIELD_ARCS] = np.asarray(arcs, dtype=np.int64).reshape(-1, 2)
    return mesh


def embedding_polydata(
    V: np.ndarray,
    F: np.ndarray,
    shading: str = "flat",
    scalars: object = None,
    layout: str = "soup",
    split_folds: bool = True,
    feature_angle: float | None = DEFAULT_FEATURE_ANGLE,
) -> pv.PolyData:
    """A real 3D mesh (a cut or bent embedding, or any ordinary mesh), z-buffered.

    Normals are libigl's (``per_face_normals``; for smooth shading area-weighted per group of
    corners split at ``feature_angle``, :func:`pyvista_views.normals.corner_groups`, as for a
    mescher), so a mescher of this mesh and the mesh itself get identical shading input.

    Parameters
    ----------
    V : (#V, 3) float64
        Positions in the camera frame (x right, y up, z toward the viewer).
    F : (#F, 3) int64
    shading : {"flat", "smooth"}
    scalars : as in :func:`to_polydata`, per vertex or face of this mesh.
    layout : {"soup", "indexed", "provoking"}
        One triangle per face with its own corners, or the mesh's own vertices (split on folds
        for smooth shading, :func:`split_by_facing`; for flat shading with ``"provoking"``,
        normals on each cell's last point, :func:`provoking_cells`).
    """
    shading = as_choice(shading, "shading", SHADINGS)
    layout = as_choice(layout, "layout", LAYOUTS)
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", n_vertices=V.shape[0])
    fields = as_scalars(scalars, V.shape[0], F.shape[0])
    draw = np.arange(F.shape[0], dtype=np.int64)
    if shading == "flat":
        normals = igl.per_face_normals(V, F, np.array([0.0, 0.0, 1.0]))
        if layout != "soup":
            return indexed(
                V, F, draw, face_normals=normals, scalars=fields, provoking=layout == "provoking"
            )
        return soup(V[F], F, draw, face_normals=normals, scalars=fields)
    face_normals = igl.per_face_normals(V, F, np.array([0.0, 0.0, 1.0]))
    groups, group_vertex, normals = corner_groups(
        F,
        face_normals,
        igl.doublearea(V, F),
        as_feature_angle(feature_angle),
        vertex_normals=igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA),
    )
    if layout != "soup":
        split = {
            k: ((v[group_vertex], loc) if loc == "vertex" else (v, loc))
            for k, (v, loc) in fields.items()
        }
        mesh = indexed(
            V[group_vertex],
            groups,
            draw,
            vertex_normals=normals,
            scalars=split,
            split_folds=split_folds,
        )
        mesh.point_data["vertex_id"] = group_vertex[np.asarray(mesh.point_data["vertex_id"])]
        return mesh
    return soup(V[F], F, draw, corner_normals=normals[groups], scalars=fields)
