"""Meschers (and real meshes) as PyVista triangle soups ready for head-on rendering.

A mescher has no absolute depth, so it is drawn flat (paper Section 4.1): every triangle lies in a
plane ``z = const`` and its shade comes from normals derived from zeta, not from the flat geometry.
Overlaps are resolved by the painter's algorithm in a linear extension of the depth order: the
face drawn k-th sits at ``z = k * step``, so under the orthographic camera looking down -z the
z-buffer reproduces the draw order exactly (no depth fighting), and the xy image is unchanged.

Each face gets its own three points (a soup): that is what lets one face sit at its own depth, and
it also gives per-corner normals and scalars for free.
"""

from __future__ import annotations

from typing import Any

import igl
import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_choice, as_faces, as_float_array, as_points

#: Total depth span of the painter's offsets as a fraction of the xy bounding-box diagonal: small
#: enough to be invisible to everything but the z-buffer, large enough for 24-bit depth at 1M faces
#: once the camera's clipping range is fitted to it.
PAINTER_DEPTH_FRACTION = 1e-3

SHADINGS = ("flat", "smooth")


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
        A length equal to #V is read per vertex (also when #V == #F), #F per face.
    """
    if scalars is None:
        return {}
    items = scalars.items() if isinstance(scalars, dict) else [(name, scalars)]
    out = {}
    for key, values in items:
        arr_name = name if key == name else f"{name}[{key!r}]"
        a = np.asarray(values)
        n = a.shape[0] if a.ndim == 1 else -1
        if n == n_vertices:
            out[str(key)] = (as_float_array(a, arr_name, (n_vertices,)), "vertex")
        elif n == n_faces:
            out[str(key)] = (as_float_array(a, arr_name, (n_faces,)), "face")
        else:
            raise MescherError(
                f"{arr_name}: expected one value per vertex ({n_vertices},) or per face "
                f"({n_faces},), found shape {a.shape}"
            )
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


def _painter_step(xy: np.ndarray, n_faces: int) -> float:
    extent = np.ptp(xy, axis=0)
    diagonal = float(np.hypot(*extent)) or 1.0
    return PAINTER_DEPTH_FRACTION * diagonal / max(n_faces, 1)


def to_polydata(
    m: Any, order: object = None, shading: str = "flat", scalars: object = None
) -> pv.PolyData:
    """The flattened mescher as a triangle soup drawn back to front (paper Section 4.1).

    Parameters
    ----------
    m : meschers_igl.Mescher
    order : None, DepthOrder or (#F,) array_like
        Back-to-front order (:func:`draw_order`); ``None`` draws in face-index order.
    shading : {"flat", "smooth"}
        ``"flat"``: ``m.face_normals()`` (from zeta) as the active cell normals.  ``"smooth"``:
        ``m.vertex_normals()`` at each corner as active point normals, interpolated (Gouraud).
        Never use PyVista's ``smooth_shading=True`` on the result: it recomputes normals from the
        flattened geometry, which are all (0, 0, 1).
    scalars : None, (#V,) or (#F,) array_like, or dict name -> array
        Scalar fields; the first one is the active scalars.

    Returns
    -------
    pyvista.PolyData
        ``3 #F`` points ``(x, y, k * step)`` for the face drawn k-th, ``#F`` triangles in draw
        order, ``cell_data["face_id"]``, ``point_data["vertex_id"]``, normals, scalars, and
        ``field_data["painter_step"]``.
    """
    shading = as_choice(shading, "shading", SHADINGS)
    F = np.asarray(m.F, dtype=np.int64)
    xy = np.asarray(m.xy, dtype=np.float64)
    n_faces = F.shape[0]
    draw = draw_order(order, n_faces)
    fields = as_scalars(scalars, xy.shape[0], n_faces)
    step = _painter_step(xy, n_faces)
    corners = np.empty((n_faces, 3, 3))
    corners[:, :, :2] = xy[F[draw]]
    corners[:, :, 2] = (np.arange(n_faces) * step)[:, None]
    if shading == "flat":
        mesh = soup(
            corners, F, draw, face_normals=np.asarray(m.face_normals())[draw], scalars=fields
        )
    else:
        normals = np.asarray(m.vertex_normals())[F[draw]]
        mesh = soup(corners, F, draw, corner_normals=normals, scalars=fields)
    mesh.field_data["painter_step"] = np.array([step])
    return mesh


def embedding_polydata(
    V: np.ndarray, F: np.ndarray, shading: str = "flat", scalars: object = None
) -> pv.PolyData:
    """A real 3D mesh (a cut or bent embedding, or any ordinary mesh) as a z-buffered soup.

    Normals are libigl's (``per_face_normals``; area-weighted ``per_vertex_normals``, the same
    weighting as a mescher's vertex normals), so a mescher of this mesh and the mesh itself get
    identical shading input.

    Parameters
    ----------
    V : (#V, 3) float64
        Positions in the camera frame (x right, y up, z toward the viewer).
    F : (#F, 3) int64
    shading : {"flat", "smooth"}
    scalars : as in :func:`to_polydata`, per vertex or face of this mesh.
    """
    shading = as_choice(shading, "shading", SHADINGS)
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", n_vertices=V.shape[0])
    fields = as_scalars(scalars, V.shape[0], F.shape[0])
    draw = np.arange(F.shape[0], dtype=np.int64)
    if shading == "flat":
        normals = igl.per_face_normals(V, F, np.array([0.0, 0.0, 1.0]))
        mesh = soup(V[F], F, draw, face_normals=normals, scalars=fields)
    else:
        normals = igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA)
        mesh = soup(V[F], F, draw, corner_normals=normals[F], scalars=fields)
    return mesh
