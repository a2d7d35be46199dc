"""Paths, points and labels drawn on the *visible* surface of a mescher.

A mescher overlaps itself on screen, so a polyline on its surface (a shortest path, a closed
geodesic around a loop) passes behind other sheets; drawn on top of the picture as a plain
screen polyline it would show through them and give the figure away.  Here every mark is kept
only where the surface it lies on is the one the viewer sees:

1. the visible face at each pixel comes from the renderer itself
   (:func:`pyvista_views.gl.face_id_image`, the layer drawn once more with face-id colours);
2. a polyline given with the face each segment lies in (a
   :class:`meschers_igl.geodesic.SurfacePath`: segment ``k`` in ``faces[k]``) is cut into
   pieces of at most ``step`` pixels; a piece is *visible* when, within ``reach`` pixels of its
   midpoint, the face map shows its own face or a face sharing a corner with it (faces a pixel
   or smaller are not sampled by every pixel, so the one-ring stands in for them); pieces on a
   hidden sheet are dropped (or dashed, on request);
3. a point (a vertex) is drawn when it is visible by the same rule, as a disc clipped to the
   figure's outline (the union of the faces under the disc), so a dot on the silhouette never
   spills onto the background;
4. labels are placed next to their anchors without overlapping each other, inside the image
   (:func:`place_labels`).

Everything here is geometry in screen units; :class:`pyvista_views.scene.MescherScene` draws
the results as line, polygon and text actors above the layer they annotate.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_float_array, as_index_array, as_positive

__all__ = [
    "PathMark",
    "PointMark",
    "as_path_marks",
    "as_point_marks",
    "clip_polyline",
    "disc_on_figure",
    "place_labels",
    "polyline_pieces_mesh",
    "refine_path",
    "visible_vertices",
]

#: Colours given to paths without one, in turn.
PATH_COLORS = ("#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00", "#a65628")
HIDDEN_MODES = ("omit", "dashed")


@dataclass
class PathMark:
    """A polyline on a mescher's surface and how to draw it.

    Attributes
    ----------
    xy : (n, 2) float64
        Screen positions of the points.
    faces : (n,) int64
        ``faces[k]`` holds segment ``k`` (points ``k`` and ``k + 1``).
    color : color
    width : float
        Line width in pixels.
    hidden : {"omit", "dashed"}
        What becomes of the pieces on hidden sheets.
    label : str or None
        Text placed beside the path's longest visible run.
    """

    xy: np.ndarray
    faces: np.ndarray
    color: Any
    width: float = 3.0
    hidden: str = "omit"
    label: str | None = None


@dataclass
class PointMark:
    """Vertices marked with discs.

    Attributes
    ----------
    vertices : (k,) int64
    color : color
    radius : float
        Disc radius in pixels.
    labels : list of str or None
    """

    vertices: np.ndarray
    color: Any = "white"
    radius: float = 5.0
    labels: list | None = None


def _path_arrays(path: Any, n_faces: int, name: str) -> tuple[np.ndarray, np.ndarray]:
    if hasattr(path, "xy") and hasattr(path, "faces"):
        xy, faces = path.xy, path.faces
    elif isinstance(path, (tuple, list)) and len(path) == 2:
        xy, faces = path
    else:
        raise MescherError(
            f"{name}: expected a SurfacePath (xy, faces) or an (xy, faces) pair, found "
            f"{type(path).__name__}"
        )
    xy = as_float_array(xy, f"{name}.xy", (-1, 2))
    faces = as_index_array(faces, f"{name}.faces", n_faces)
    if faces.shape[0] != xy.shape[0]:
        raise MescherError(
            f"{name}: expected one face per point ({xy.shape[0]}), found {faces.shape[0]}"
        )
    return xy, faces


def as_path_marks(paths: object, n_faces: int, width: float = 3.0) -> list[PathMark]:
    """Normalise ``paths`` to :class:`PathMark` s.

    Parameters
    ----------
    paths : None, SurfacePath, (xy, faces), dict, or a sequence of them
        A dict has ``"path"`` and optionally ``"color"``, ``"width"``, ``"hidden"``
        (``"omit"`` or ``"dashed"``) and ``"label"``.
    n_faces : int
        Faces of the mescher the paths lie on (their face indices are checked).
    width : float
        Default line width in pixels.
    """
    if paths is None:
        return []
    single = hasattr(paths, "faces") or isinstance(paths, dict)
    if isinstance(paths, tuple) and len(paths) == 2 and np.ndim(paths[1]) == 1:
        single = single or np.ndim(paths[0]) == 2
    items = [paths] if single else list(paths)
    marks = []
    for i, item in enumerate(items):
        spec = item if isinstance(item, dict) else {"path": item}
        unknown = set(spec) - {"path", "color", "width", "hidden", "label"}
        if unknown or "path" not in spec:
            raise MescherError(
                f"paths[{i}]: expected keys path, color, width, hidden, label, found {sorted(spec)}"
            )
        xy, faces = _path_arrays(spec["path"], n_faces, f"paths[{i}]")
        hidden = spec.get("hidden", "omit")
        if hidden not in HIDDEN_MODES:
            raise MescherError(f"paths[{i}].hidden: expected 'omit' or 'dashed', found {hidden!r}")
        marks.append(
            PathMark(
                xy,
                faces,
                spec.get("color", PATH_COLORS[i % len(PATH_COLORS)]),
                as_positive(spec.get("width", width), f"paths[{i}].width"),
                hidden,
                None if spec.get("label") is None else str(spec["label"]),
            )
        )
    return marks


def as_point_marks(points: object, n_vertices: int) -> list[PointMark]:
    """Normalise ``points`` to :class:`PointMark` s.

    Parameters
    ----------
    points : None, int, (k,) int array_like, dict, or a sequence of dicts
        Vertex ids; a dict has ``"vertices"`` and optionally ``"color"``, ``"radius"``,
        ``"labels"``.
    n_vertices : int
    """
    if points is None:
        return []
    if isinstance(points, dict):
        items = [points]
    elif isinstance(points, (list, tuple)) and points and isinstance(points[0], dict):
        items = list(points)
    else:
        items = [{"vertices": points}]
    marks = []
    for i, spec in enumerate(items):
        unknown = set(spec) - {"vertices", "color", "radius", "labels"}
        if unknown or "vertices" not in spec:
            raise MescherError(
                f"points[{i}]: expected keys vertices, color, radius, labels, found {sorted(spec)}"
            )
        v = as_index_array(np.atleast_1d(spec["vertices"]), f"points[{i}].vertices", n_vertices)
        labels = spec.get("labels")
        if labels is not None and len(labels) != v.shape[0]:
            raise MescherError(
                f"points[{i}].labels: expected {v.shape[0]} labels, found {len(labels)}"
            )
        marks.append(
            PointMark(
                v,
                spec.get("color", "white"),
                as_positive(spec.get("radius", 5.0), f"points[{i}].radius"),
                None if labels is None else [str(t) for t in labels],
            )
        )
    return marks


def _pixel_of(P: np.ndarray, bounds: Sequence[float], shape: tuple[int, int]) -> tuple:
    """Row and column of the pixels containing screen points ``P`` (may fall outside)."""
    H, W = shape
    xmin, xmax, ymin, ymax = (float(b) for b in bounds)
    col = np.floor((P[:, 0] - xmin) / (xmax - xmin) * W).astype(np.int64)
    row = np.floor((ymax - P[:, 1]) / (ymax - ymin) * H).astype(np.int64)
    return row, col


def _seen_near(
    faces: np.ndarray,
    P: np.ndarray,
    F: np.ndarray,
    face_map: np.ndarray,
    bounds: Sequence[float],
    reach: int,
) -> np.ndarray:
    """Whether face ``faces[i]``, or a face sharing a corner with it, is drawn within ``reach``
    pixels (a square window) of screen point ``P[i]``.

    Returns
    -------
    (k,) bool
    """
    H, W = face_map.shape
    row, col = _pixel_of(P, bounds, (H, W))
    seen = np.zeros(faces.shape[0], dtype=bool)
    corners = F[faces]  # (k, 3)
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            r, c = row + dr, col + dc
            inside = (r >= 0) & (r < H) & (c >= 0) & (c < W)
            g = np.full(faces.shape[0], -1, dtype=np.int64)
            g[inside] = face_map[r[inside], c[inside]]
            drawn = g >= 0
            near = np.zeros_like(seen)
            if drawn.any():
                a, b = corners[drawn], F[g[drawn]]
                near[drawn] = (a[:, :, None] == b[:, None, :]).any(axis=(1, 2))
            seen |= near
    return seen


def clip_polyline(
    xy: np.ndarray,
    faces: np.ndarray,
    F: np.ndarray,
    face_map: np.ndarray,
    bounds: Sequence[float],
    *,
    step: float = 0.5,
    reach: int = 1,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Cut a surface polyline into short pieces and say which lie on the visible surface.

    Parameters
    ----------
    xy : (n, 2) float64
        Screen positions of the polyline's points.
    faces : (n,) int64
        Face of each segment (``faces[k]`` holds points ``k`` and ``k + 1``).
    F : (#F, 3) int64
        The mescher's faces.
    face_map : (H, W) int64
        Visible face per pixel, -1 on the background (:func:`pyvista_views.gl.face_id_image`,
        or :func:`meschers_igl.painter.visible_faces` on the same grid).
    bounds : (xmin, xmax, ymin, ymax)
        The extent of ``face_map``.
    step : float
        Longest piece, in pixels.
    reach : int
        Pixels around a piece's midpoint searched for its face (module docstring).

    Returns
    -------
    p0, p1 : (k, 2) float64
        Ends of each piece (screen units), in order along the polyline.
    visible : (k,) bool
    arc : (k,) float64
        Length along the polyline to each piece's start, in pixels (for dashes).
    """
    H, W = face_map.shape
    xmin, xmax, ymin, ymax = (float(b) for b in bounds)
    dx, dy = (xmax - xmin) / W, (ymax - ymin) / H
    if xy.shape[0] < 2:
        empty = np.zeros((0, 2))
        return empty, empty, np.zeros(0, dtype=bool), np.zeros(0)
    a, b = xy[:-1], xy[1:]
    length_px = np.hypot((b[:, 0] - a[:, 0]) / dx, (b[:, 1] - a[:, 1]) / dy)
    n_pieces = np.maximum(np.ceil(length_px / step).astype(np.int64), 1)
    seg = np.repeat(np.arange(a.shape[0]), n_pieces)
    first = np.cumsum(n_pieces) - n_pieces
    k = np.arange(seg.shape[0]) - first[seg]
    t0 = (k / n_pieces[seg])[:, None]
    t1 = ((k + 1) / n_pieces[seg])[:, None]
    d = b[seg] - a[seg]
    p0, p1 = a[seg] + t0 * d, a[seg] + t1 * d
    visible = _seen_near(faces[:-1][seg], 0.5 * (p0 + p1), F, face_map, bounds, reach)
    seg_start = np.concatenate([[0.0], np.cumsum(length_px)[:-1]])
    arc = seg_start[seg] + t0[:, 0] * length_px[seg]
    piece_px = (t1[:, 0] - t0[:, 0]) * length_px[seg]
    # Along a silhouette the test flickers from pixel to pixel: gaps shorter than `reach`
    # pixels between visible runs are closed, then visible runs shorter than 2 `reach` + 1
    # pixels dropped (a dotted line along an outline says nothing).
    visible = _runs_at_least(
        ~_runs_at_least(~visible, piece_px, reach + 1e-9), piece_px, 2 * reach + 1
    )
    return p0, p1, visible, arc


def refine_path(
    xy: np.ndarray,
    faces: np.ndarray,
    child_xy: np.ndarray,
    child_F: np.ndarray,
    face_parent: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """A polyline on a mesh carried to a subdivision whose children tile their parents on screen.

    Segment ``k`` lies in parent face ``faces[k]``; after midpoint subdivision it crosses the
    children of that face.  Each segment is clipped against each child triangle
    (Cyrus-Beck: the parameter interval where it is on the inner side of all three edges) and
    split where it passes from one child to the next, so every piece of the result lies in the
    child face it is given.  A piece running along an edge shared by two children goes to one of
    them (both hold it).  A segment its children do not cover (its face edge-on on screen) is
    kept whole, in the child nearest its midpoint.

    Parameters
    ----------
    xy : (n, 2) float64
        Screen positions of the polyline's points.
    faces : (n,) int64
        Parent face of each segment (``faces[k]`` holds points ``k`` and ``k + 1``; the last
        entry is ignored).
    child_xy : (#V', 2) float64
    child_F : (#F', 3) int64
    face_parent : (#F',) int64
        Parent face of each child (every parent has the same number of children).

    Returns
    -------
    xy : (m, 2) float64
    faces : (m,) int64
        The same polyline with child faces (the last entry repeats the last piece's face).

    Raises
    ------
    MescherError
        When ``face_parent`` does not give every parent the same number of children.
    """
    xy = as_float_array(xy, "xy", (-1, 2))
    child_F = np.asarray(child_F, dtype=np.int64)
    face_parent = np.asarray(face_parent, dtype=np.int64)
    n_parents = int(face_parent.max(initial=-1)) + 1
    counts = np.bincount(face_parent, minlength=n_parents)
    if counts.size == 0 or np.any(counts != counts[0]):
        raise MescherError(
            "face_parent: expected the same number of children for every parent face, found "
            f"{np.unique(counts).tolist()}"
        )
    faces = as_index_array(faces, "faces", n_parents)
    if xy.shape[0] < 2:
        return xy.copy(), faces.copy()
    kids = np.argsort(face_parent, kind="stable").reshape(n_parents, counts[0])[faces[:-1]]
    a, d = xy[:-1], xy[1:] - xy[:-1]  # (n, 2)
    T = np.asarray(child_xy, dtype=np.float64)[child_F[kids]]  # (n, c, 3, 2)
    U, E = T, np.roll(T, -1, axis=2) - T  # edge k from corner k to corner k + 1
    area = np.cross(E[:, :, 0], -E[:, :, 2])  # (n, c) signed, twice the area
    normal = np.sign(area)[..., None, None] * np.stack([-E[..., 1], E[..., 0]], axis=-1)
    normal /= np.maximum(np.linalg.norm(normal, axis=-1, keepdims=True), 1e-300)
    scale = np.abs(T - T.mean(axis=2, keepdims=True)).max(axis=(2, 3))
    tol = 1e-9 * np.maximum(scale, 1e-300)  # (n, c) distance tolerance
    num = np.einsum("nckx,nckx->nck", normal, a[:, None, None, :] - U)  # >= 0 inside
    den = np.einsum("nckx,nx->nck", normal, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -(num + tol[..., None]) / den
    t0 = np.where(den > 0, t, 0.0).max(axis=2)
    t1 = np.where(den < 0, t, 1.0).min(axis=2)
    parallel_out = ((den == 0) & (num < -tol[..., None])).any(axis=2)
    t0, t1 = np.clip(t0, 0.0, 1.0), np.clip(t1, 0.0, 1.0)
    keep = (t1 > t0) & ~parallel_out & (np.abs(area) > 0)
    seg, child = np.nonzero(keep)
    lo, hi = t0[seg, child], t1[seg, child]
    # in order along the polyline; overlaps (a piece on a shared edge, tolerance) trimmed
    ordering = np.lexsort((-(hi - lo), lo, seg))
    seg, child, lo, hi = seg[ordering], child[ordering], lo[ordering], hi[ordering]
    reach = np.maximum.accumulate(seg + hi)  # monotone across segments: seg + t in [seg, seg+1]
    before = np.concatenate([[-1.0], reach[:-1]]) - seg
    lo = np.maximum(lo, before)
    ok = hi - lo > 1e-12
    seg, child, lo, hi = seg[ok], child[ok], lo[ok], hi[ok]
    # a segment not covered by its children (a face edge-on on screen, a segment off its face)
    # keeps the child nearest its midpoint for the whole of it
    short = np.bincount(seg, weights=hi - lo, minlength=a.shape[0]) < 1.0 - 1e-6
    if short.any():
        bad = np.flatnonzero(short)
        mid = a[bad] + 0.5 * d[bad]
        nearest = np.argmin(np.linalg.norm(T[bad].mean(axis=2) - mid[:, None], axis=-1), axis=1)
        good = ~short[seg]
        seg = np.concatenate([seg[good], bad])
        child = np.concatenate([child[good], nearest])
        lo = np.concatenate([lo[good], np.zeros(bad.size)])
        ordering = np.lexsort((lo, seg))
        seg, child, lo = seg[ordering], child[ordering], lo[ordering]
    out_xy = np.vstack([a[seg] + lo[:, None] * d[seg], xy[-1:]])
    out_faces = kids[seg, child]
    return out_xy, np.concatenate([out_faces, out_faces[-1:]])


def _runs_at_least(flags: np.ndarray, piece_px: np.ndarray, length: float) -> np.ndarray:
    """``flags`` with the runs of True shorter than ``length`` pixels set to False."""
    if not flags.any():
        return flags
    edges = np.flatnonzero(np.diff(np.concatenate([[0], flags.astype(np.int8), [0]])))
    starts, ends = edges[::2], edges[1::2]
    csum = np.concatenate([[0.0], np.cumsum(piece_px)])
    short = (csum[ends] - csum[starts]) < length
    out = flags.copy()
    for s, e in zip(starts[short], ends[short]):  # runs of one polyline: few
        out[s:e] = False
    return out


def visible_vertices(
    vertices: np.ndarray,
    xy: np.ndarray,
    F: np.ndarray,
    vertex_face: np.ndarray,
    face_map: np.ndarray,
    bounds: Sequence[float],
    reach: int = 1,
) -> np.ndarray:
    """Whether each vertex lies on the visible surface: a face around it is drawn within
    ``reach`` pixels of it (as :func:`clip_polyline`'s pieces).

    Parameters
    ----------
    vertices : (k,) int64
    xy : (#V, 2) float64
    F : (#F, 3) int64
    vertex_face : (#V,) int64
        One face incident to each vertex (its one-ring is the set tested).
    face_map, bounds
        As in :func:`clip_polyline`.

    Returns
    -------
    (k,) bool
    """
    return _seen_near(vertex_face[vertices], xy[vertices], F, face_map, bounds, reach)


def polyline_pieces_mesh(p0: np.ndarray, p1: np.ndarray, z: float) -> pv.PolyData:
    """Line cells through consecutive pieces (pieces that touch are joined into one polyline).

    Parameters
    ----------
    p0, p1 : (k, 2) float64
        Piece ends in order along a polyline.
    z : float
        Depth given to the lines (in front of the layer they annotate).
    """
    if p0.shape[0] == 0:
        return pv.PolyData()
    joined = np.all(np.isclose(p1[:-1], p0[1:], rtol=0.0, atol=1e-12), axis=1)
    starts = np.flatnonzero(np.concatenate([[True], ~joined]))
    ends = np.concatenate([starts[1:], [p0.shape[0]]])
    points, cells, offset = [], [], 0
    for s, e in zip(starts, ends):  # runs: a handful per path
        run = np.vstack([p0[s:e], p1[e - 1 : e]])
        points.append(run)
        cells.append(np.concatenate([[run.shape[0]], offset + np.arange(run.shape[0])]))
        offset += run.shape[0]
    P = np.zeros((offset, 3))
    P[:, :2] = np.vstack(points)
    P[:, 2] = z
    return pv.PolyData(P, lines=np.concatenate(cells))


def disc_on_figure(
    centre: np.ndarray, radius: float, xy: np.ndarray, F: np.ndarray, n_sides: int = 32
) -> np.ndarray:
    """A disc clipped to the figure's outline: ``disc & union(faces under it)``, triangulated.

    Parameters
    ----------
    centre : (2,) float64
    radius : float
        Screen units.
    xy : (#V, 2) float64
    F : (#F, 3) int64
    n_sides : int

    Returns
    -------
    triangles : (t, 3, 2) float64
        Triangles covering the clipped disc (none when the disc misses the figure).
    rim : list of (k, 2) float64
        The disc's circle inside the figure (its outline on the figure, not on the background).
    """
    import shapely

    T = xy[F]
    lo, hi = T.min(axis=1), T.max(axis=1)
    near = np.all((lo <= centre + radius) & (hi >= centre - radius), axis=1)
    if not near.any():
        return np.zeros((0, 3, 2)), []
    triangles = shapely.polygons(np.concatenate([T[near], T[near][:, :1]], axis=1))
    figure = shapely.union_all(triangles[shapely.area(triangles) > 0])
    angle = np.linspace(0.0, 2.0 * np.pi, n_sides, endpoint=False)
    disc = shapely.Polygon(centre + radius * np.column_stack([np.cos(angle), np.sin(angle)]))
    clipped = shapely.intersection(disc, figure)
    if clipped.is_empty:
        return np.zeros((0, 3, 2)), []
    parts = shapely.get_parts(shapely.constrained_delaunay_triangles(clipped))
    if parts.size == 0:
        return np.zeros((0, 3, 2)), []
    coords = np.stack([np.asarray(p.exterior.coords)[:3] for p in parts])
    # the rim: the circle where it runs inside the figure (shrunk a little so a rim line's
    # width stays off the outline)
    inner = shapely.buffer(figure, -0.15 * radius)
    rim = shapely.get_parts(shapely.line_merge(shapely.intersection(disc.exterior, inner)))
    lines = [np.asarray(r.coords) for r in rim if r.geom_type == "LineString" and r.length > 0]
    return coords, lines


def triangles_mesh(T: np.ndarray, z: float) -> pv.PolyData:
    """(t, 3, 2) screen triangles as a PolyData at depth ``z``."""
    P = np.zeros((T.shape[0] * 3, 3))
    P[:, :2] = T.reshape(-1, 2)
    P[:, 2] = z
    return pv.PolyData.from_regular_faces(P, np.arange(P.shape[0]).reshape(-1, 3))


def place_labels(
    anchors: np.ndarray, sizes: Sequence[tuple[float, float]], image_size: tuple[int, int]
) -> np.ndarray:
    """Top-left corners for text boxes near their anchors, no two boxes overlapping.

    Greedy: each label tries offsets around its anchor, nearest first (right, left, above,
    below, then twice and three times as far), and takes the first whose box stays in the image
    and misses every box placed before it; if none does, the candidate with the least overlap.

    Parameters
    ----------
    anchors : (k, 2) float
        Pixel positions (column, row from the top) the labels belong to.
    sizes : k pairs (width, height)
        Text box sizes in pixels.
    image_size : (width, height)

    Returns
    -------
    (k, 2) float
        Top-left corner of each box (column, row from the top), inside the image.
    """
    W, H = image_size
    placed: list[tuple[float, float, float, float]] = []
    corners = np.zeros((len(sizes), 2))
    for i, ((c, r), (w, h)) in enumerate(zip(np.asarray(anchors, float).reshape(-1, 2), sizes)):
        best, best_cost = None, np.inf
        for reach in (1, 2, 3, 5):
            d = 6 * reach
            for dx, dy in (
                (d, -h / 2),
                (-w - d, -h / 2),
                (-w / 2, -h - d),
                (-w / 2, d),
                (d, -h - d),
                (-w - d, -h - d),
                (d, d),
                (-w - d, d),
            ):
                x0 = min(max(c + dx, 0.0), max(W - w, 0.0))
                y0 = min(max(r + dy, 0.0), max(H - h, 0.0))
                box = (x0, y0, x0 + w, y0 + h)
                cost = sum(_overlap(box, b) for b in placed)
                if cost < best_cost:
                    best, best_cost = box, cost
                if cost == 0:
                    break
            if best_cost == 0:
                break
        placed.append(best)
        corners[i] = best[:2]
    return corners


def _overlap(a: tuple, b: tuple) -> float:
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return max(w, 0.0) * max(h, 0.0)
