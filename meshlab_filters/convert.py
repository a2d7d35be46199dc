"""Cut models to meschers, and meschers out to files MeshLab opens.

Exports go through PyMeshLab's own writers (``MeshSet.save_current_mesh``), so every format it
writes works (.ply, .obj, .off, .stl, ...); scalar fields become vertex colours through MeshLab's
own colormaps (filter ``compute_color_from_scalar_per_vertex``: 'Viridis', 'RGB', 'Plasma',
'Cividis', 'Turbo', 'RdPu').  STL has no vertex colours; OFF gets no normals (MeshLab's OFF
writer and reader disagree on them).
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import numpy as np
import pymeshlab

from meschers_igl import Mescher, MescherError
from meschers_igl.obtain import cut_model_to_mescher as core_cut_model_to_mescher
from meschers_igl.validate import as_faces, as_points

from ._filters import apply
from .load import _as_path, load_artist_model

#: MeshLab's colormap names (``compute_color_from_scalar_per_vertex``'s ``colormap`` enum).
COLORMAPS = ("Viridis", "RGB", "Plasma", "Cividis", "Turbo", "RdPu")
_NORMAL_ATTR = "meschers_normal"
#: Default depth spread of :func:`export_render_mesh`, relative to the screen diagonal.
RENDER_Z_SPREAD = 1e-2


def _mesh_pair(path_or_V_F: Any) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)`` checked, from a pair given in place of a file path."""
    if isinstance(path_or_V_F, (tuple, list)) and len(path_or_V_F) == 2:
        V = as_points(path_or_V_F[0], "path_or_V_F[0] (V)", 3)
        return V, as_faces(path_or_V_F[1], "path_or_V_F[1] (F)", V.shape[0])
    raise MescherError(
        f"path_or_V_F: expected a file path or a pair (V, F), found {type(path_or_V_F).__name__}"
    )


def _mescher(m: Any, name: str = "m") -> Mescher:
    if not isinstance(m, Mescher):
        raise MescherError(f"{name}: expected a meschers_igl.Mescher, found {type(m).__name__}")
    return m


def cut_model_to_mescher(
    path_or_V_F: Any,
    view=(0.0, 0.0, 1.0),
    up=(0.0, 1.0, 0.0),
    tol: float | None = None,
    merge: Any = None,
    merge_tol: float = 0.0,
    return_report: bool = False,
):
    """A mescher and its depth order from a cut 3D model (paper Sec. 3.4-3.5).

    A path is loaded and cleaned with :func:`load_artist_model` (exact duplicates only, so the
    cut's front/back pairs survive); arrays are used as given.  Then
    :func:`meschers_igl.obtain.cut_model_to_mescher` glues the cut and orders the faces that
    overlap on screen by the cut model's own depths (the one implementation, shared with the
    PyVista accessor and the command line).

    Parameters
    ----------
    path_or_V_F : str, os.PathLike or (V (n,3), F (m,3))
        A mesh file, or the cut model's arrays.
    view : (3,) array_like, default: (0, 0, 1)
        Direction from the model toward the orthographic camera.
    up : (3,) array_like, default: (0, 1, 0)
        Screen up.
    tol : float, optional
        Gluing tolerance relative to the model's bounding-box diagonal (see
        :func:`meschers_igl.cutmesh.mescher_from_cut_mesh`).
    merge : (k, 2) array_like of int, optional
        Explicit vertex pairs to glue.  With a path they index the *file's* vertices and are
        translated through the clean-up's ``vertex_map``.
    merge_tol : float, default: 0.0
        3D duplicate tolerance of the clean-up (only with a path).
    return_report : bool, default: False
        Also return the clean-up report (``None`` for arrays).

    Returns
    -------
    m : Mescher
        Face ``i`` is face ``i`` of the (cleaned) model.
    order : DepthOrder
        Arc ``i -> j`` when face ``i`` is behind face ``j`` where they overlap on screen.
    report : CleanupReport or None
        Only with ``return_report``.
    """
    report = None
    if isinstance(path_or_V_F, (str, os.PathLike)):
        V, F, report = load_artist_model(path_or_V_F, merge_tol=merge_tol)
        if merge is not None:
            merge = _translate_pairs(merge, report.vertex_map, path_or_V_F)
    else:
        V, F = _mesh_pair(path_or_V_F)
    m, order = core_cut_model_to_mescher(V, F, view=view, up=up, tol=tol, merge=merge)
    return (m, order, report) if return_report else (m, order)


def model_to_mescher(
    path_or_V_F: Any,
    view: Any = (0.0, 0.0, 1.0),
    up: Any = (0.0, 1.0, 0.0),
    perceive: str | None = None,
    merge_tol: float = 0.0,
    tol: float | None = None,
    hidden: bool | str = "auto",
    view_start: Any = None,
    route: str = "auto",
):
    """Any artist model -- cut models, closed solids, separate blocks, reliefs, STL soups,
    scenes -- as seen from a view: (mescher, depth order, report); the route (cut model glued
    at its seam, or seen from the view) is picked by :func:`meschers_igl.obtain.model_to_mescher`
    and named in ``report.route`` / ``report.reason``.

    A path is read with PyMeshLab (polygons triangulated); vertices that coincide in 3D are
    welded and pairs of coincident opposite faces -- blocks touching face to face -- removed
    *before* PyMeshLab's clean-up (which would keep one face of each pair and then cut the
    non-manifold edges this leaves, removing real surface faces); then :func:`clean_mesh`
    repairs what is left (duplicate and zero-area faces, non-manifold edges -- split, no face
    removed -- and vertices, orientation; its :class:`CleanupReport` lands in ``report.cleanup``) and
    :func:`meschers_igl.obtain.model_to_mescher` builds what the viewer sees.

    Parameters
    ----------
    path_or_V_F : str, os.PathLike or (V (n,3), F (m,3))
    view : (3,) array_like or "auto", default: (0, 0, 1)
    up : (3,) array_like, default: (0, 1, 0)
    perceive : {None, "manhattan"}
    merge_tol : float, default: 0.0
        3D weld distance of the clean-up (only with a path).
    tol : float, optional
        Relative tolerance of the conversion.
    hidden : {"auto", True, False}, default: "auto"
        Keep the hidden side (a closed surface glued at its junctions) or build the visible
        surface only (see :func:`meschers_igl.obtain.see_model`).
    view_start : (3,) array_like, optional
        With ``view="auto"``: a view near the intended one (within 10 degrees).
    route : {"auto", "cut", "seen"}, default: "auto"
        Override the route the model picks.

    Returns
    -------
    m : Mescher
    order : DepthOrder
    report : meschers_igl.obtain.ConversionReport
        Junctions with their depth gaps, arcs, repairs (clean-up included), warnings, the view.
    """
    from meschers_igl.obtain import drop_contact_faces, drop_repeated_faces, weld
    from meschers_igl.obtain import model_to_mescher as core_model_to_mescher

    from .cleanup import clean_mesh
    from .load import read_meshset

    cleanup, pre = None, []
    if isinstance(path_or_V_F, (str, os.PathLike)):
        ms = read_meshset(path_or_V_F)
        mesh = ms.current_mesh()
        V0 = np.asarray(mesh.vertex_matrix(), dtype=np.float64)
        F0 = np.asarray(mesh.face_matrix(), dtype=np.int64)
        if F0.shape[0] == 0 or not np.isfinite(V0).all():
            raise MescherError(
                f"path: expected faces with finite coordinates in '{path_or_V_F}', found "
                f"{F0.shape[0]} faces"
            )
        diag = float(np.linalg.norm(np.ptp(V0, axis=0)))
        V0, F0, n_w = weld(V0, F0, max(merge_tol, 1e-9 * diag))
        F0, n_r = drop_repeated_faces(F0)
        F0, n_c = drop_contact_faces(F0)
        if F0.shape[0] == 0:
            raise MescherError(
                f"path: expected faces left after clean-up in '{path_or_V_F}', found none (every "
                "face lies on another, facing it)"
            )
        if n_w:
            pre.append(f"welded {n_w} vertex(es) that coincide in 3D (before PyMeshLab)")
        if n_r:
            pre.append(f"removed {n_r} repeated face(s) (a part duplicated in place)")
        if n_c:
            pre.append(f"removed {n_c} pair(s) of coincident opposite faces (blocks touching)")
        # blocks that touch along an edge keep every face (their vertices split, then welded
        # again by the conversion, which handles such edges): removing faces would open the
        # solids and lose their corners from the search for a view
        V, F, cleanup = clean_mesh(V0, F0, merge_tol=merge_tol, non_manifold_edges="split")
        cleanup.source = str(path_or_V_F)
    else:
        V, F = _mesh_pair(path_or_V_F)
    m, order, report = core_model_to_mescher(
        V,
        F,
        view=view,
        up=up,
        perceive=perceive,
        tol=tol,
        hidden=hidden,
        view_start=view_start,
        route=route,
    )
    report.cleanup = cleanup
    report.repairs[:0] = pre
    if cleanup is not None:
        report.repairs[len(pre) : len(pre)] = [
            f"PyMeshLab: {k.replace('_', ' ')} {v}"
            for k, v in cleanup.as_dict().items()
            if k.endswith(("_merged", "_removed", "_split", "_flipped")) and v
        ]
    return m, order, report


def _translate_pairs(merge: Any, vmap: np.ndarray, path: Any) -> np.ndarray:
    pairs = np.asarray(merge)
    if pairs.ndim != 2 or pairs.shape[1] != 2 or not np.issubdtype(pairs.dtype, np.integer):
        raise MescherError(f"merge: expected (k, 2) integer vertex pairs, found {pairs.shape}")
    if pairs.size and (pairs.min() < 0 or pairs.max() >= vmap.size):
        raise MescherError(
            f"merge: expected vertex indices of '{path}' in [0, {vmap.size}), found "
            f"{int(pairs.min())}..{int(pairs.max())}"
        )
    out = vmap[pairs]
    if np.any(out < 0):
        bad = pairs[np.any(out < 0, axis=1)][0].tolist()
        raise MescherError(
            f"merge: expected vertices that survive clean-up of '{path}', found pair {bad} "
            "with a removed (unreferenced) vertex"
        )
    return out


# ---------------------------------------------------------------------------------- colours
def _colormap(colormap: str) -> str:
    if colormap not in COLORMAPS:
        raise MescherError(f"colormap: expected one of {COLORMAPS}, found {colormap!r}")
    return colormap


def _range(s: np.ndarray, vmin: float | None, vmax: float | None) -> tuple[float, float]:
    lo = float(s.min()) if vmin is None else float(vmin)
    hi = float(s.max()) if vmax is None else float(vmax)
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi < lo:
        raise MescherError(f"vmin, vmax: expected finite vmin <= vmax, found {lo}, {hi}")
    if hi == lo:  # MeshLab reads minval == maxval as "choose the range yourself"
        hi = lo + 1.0
    return lo, hi


def scalars_to_colors(
    scalars: Any, colormap: str = "Viridis", vmin: float | None = None, vmax: float | None = None
) -> np.ndarray:
    """Colours of ``scalars`` under MeshLab's colormap (what the exports write).

    Parameters
    ----------
    scalars : (n,) array_like of float
    colormap : str, default: 'Viridis'
        One of :data:`COLORMAPS`.
    vmin, vmax : float, optional
        Values mapped to the ends of the colormap (default: the scalars' min and max); values
        outside are clamped.

    Returns
    -------
    (n, 4) float64
        RGBA in [0, 1].
    """
    s = _as_scalars(scalars, "scalars", None)
    ms = pymeshlab.MeshSet()
    V = np.zeros((s.size, 3))
    V[:, 0] = np.arange(s.size)
    ms.add_mesh(pymeshlab.Mesh(V, v_scalar_array=s))
    _color(ms, s, colormap, vmin, vmax)
    return ms.current_mesh().vertex_color_matrix()


def _as_scalars(scalars: Any, name: str, n: int | None) -> np.ndarray:
    from meschers_igl.validate import as_float_array

    s = as_float_array(scalars, name, (-1 if n is None else n,))
    if s.size == 0:
        raise MescherError(f"{name}: expected at least one value, found none")
    return s


def _color(ms: pymeshlab.MeshSet, s: np.ndarray, colormap: str, vmin, vmax) -> None:
    lo, hi = _range(s, vmin, vmax)
    apply(
        ms,
        "compute_color_from_scalar_per_vertex",
        minval=lo,
        maxval=hi,
        perc=0.0,
        zerosym=False,
        colormap=_colormap(colormap),
    )


def _save(ms: pymeshlab.MeshSet, path: Path, colors: bool, normals: bool) -> Path:
    """``save_current_mesh`` with the options this format has (unknown ones are dropped)."""
    ext = path.suffix.lower()
    params = {"save_vertex_color": colors, "save_vertex_normal": normals and ext != ".off"}
    if ext == ".ply":
        params["binary"] = True
    while True:
        try:
            ms.save_current_mesh(str(path), **params)
            return path
        except pymeshlab.PyMeshLabException as exc:
            msg = " ".join(str(exc).split())
            bad = re.search(r"Parameter (\w+) not found", msg)
            if bad and bad.group(1) in params:  # this format lacks the option: drop it
                params.pop(bad.group(1))
                continue
            raise MescherError(
                f"path: expected a file PyMeshLab can write, found '{path}' ({msg})"
            ) from None


def _write(
    path: Any,
    V: np.ndarray,
    F: np.ndarray,
    scalars: np.ndarray | None,
    colormap: str,
    vmin,
    vmax,
    label: str,
    normals: np.ndarray | None = None,
) -> Path:
    p = _as_path(path)
    if not p.parent.exists():
        raise MescherError(f"path: expected a file in an existing folder, found '{p}'")
    kw = {} if scalars is None else {"v_scalar_array": scalars}
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32), **kw), label)
    if normals is not None:
        # pymeshlab.Mesh(v_normals_matrix=...) recomputes normals from the geometry; set them
        # through custom attributes and MeshLab's per-vertex normal function instead.
        mesh = ms.current_mesh()
        names = [f"{_NORMAL_ATTR}_{c}" for c in "xyz"]
        for i, name in enumerate(names):
            mesh.add_vertex_custom_scalar_attribute(np.ascontiguousarray(normals[:, i]), name)
        apply(ms, "compute_normal_by_function_per_vertex", x=names[0], y=names[1], z=names[2])
    if scalars is not None:
        _color(ms, scalars, colormap, vmin, vmax)
    return _save(ms, p, colors=scalars is not None, normals=normals is not None)


def export_cut_embedding(
    m: Mescher,
    path: str | os.PathLike,
    scalars: Any = None,
    cut_edges: Any = None,
    colormap: str = "Viridis",
    vmin: float | None = None,
    vmax: float | None = None,
) -> Path:
    """Write the mescher's cut embedding (``m.cut_embedding``) to a file MeshLab opens.

    Parameters
    ----------
    m : Mescher
    path : str or os.PathLike
        Format by extension (.ply, .obj, .off, .stl, ...).
    scalars : (#V,) or (#Vc,) array_like, optional
        Per mescher vertex (copied to each of its cut copies through ``vmap``) or per cut-model
        vertex; written as vertex colours.
    cut_edges : (k,) int, optional
        Passed to ``m.cut_embedding`` (default: the homology generators).
    colormap, vmin, vmax
        See :func:`scalars_to_colors`.

    Returns
    -------
    Path
        The written file: ``#Vc`` vertices ``(x, y, depth)``, ``#F`` faces (face i is m's face i).
    """
    m = _mescher(m)
    V, F, vmap = m.cut_embedding(cut_edges)
    s = None
    if scalars is not None:
        s = np.asarray(scalars)
        if s.ndim == 1 and s.shape[0] == m.n_vertices and V.shape[0] != m.n_vertices:
            s = _as_scalars(s, "scalars", m.n_vertices)[vmap]
        else:
            s = _as_scalars(s, f"scalars (per mescher vertex: {m.n_vertices}, or)", V.shape[0])
    return _write(path, V, F, s, colormap, vmin, vmax, "mescher_cut")


def export_bent_embedding(
    m: Mescher,
    path: str | os.PathLike,
    scalars: Any = None,
    colormap: str = "Viridis",
    vmin: float | None = None,
    vmax: float | None = None,
) -> Path:
    """Write the mescher's bent embedding (``m.bent_embedding``: depth from the Hodge
    decomposition's exact part) to a file MeshLab opens.

    Parameters
    ----------
    m : Mescher
    path : str or os.PathLike
    scalars : (#V,) array_like, optional
        Per-vertex values written as colours.
    colormap, vmin, vmax
        See :func:`scalars_to_colors`.

    Returns
    -------
    Path
        The written file: ``#V`` vertices ``(x, y, z)``, ``#F`` faces.
    """
    m = _mescher(m)
    V, F = m.bent_embedding()
    s = None if scalars is None else _as_scalars(scalars, "scalars", m.n_vertices)
    return _write(path, V, F, s, colormap, vmin, vmax, "mescher_bent")


def render_levels(order: Any, n_faces: int) -> tuple[np.ndarray, np.ndarray]:
    """Back-to-front face permutation and a depth level per face for the flattened soup.

    ``perm = order.linear_extension()``; ``level[j] = 1 + max(level[i])`` over the arcs
    ``i -> j`` that agree with ``perm`` (the longest chain behind ``j``), so faces in front get
    higher levels and faces with no arc stay at level 0.  Computed by relaxation on arrays (one
    pass per level; networkx's longest path is a Python loop over nodes).

    Parameters
    ----------
    order : DepthOrder, (n_faces,) permutation, or None
        ``None``: faces in index order, all at level 0.
    n_faces : int

    Returns
    -------
    perm : (n_faces,) int64
    level : (n_faces,) int64
    """
    from meschers_igl.order import DepthOrder

    if order is None:
        return np.arange(n_faces), np.zeros(n_faces, dtype=np.int64)
    if isinstance(order, DepthOrder):
        if order.n_faces != n_faces:
            raise MescherError(
                f"order: expected a DepthOrder over {n_faces} faces, found {order.n_faces}"
            )
        perm = np.asarray(order.linear_extension(), dtype=np.int64)
        arcs = np.asarray(order.arcs, dtype=np.int64).reshape(-1, 2)
    else:
        perm = np.asarray(order)
        if (
            perm.shape != (n_faces,)
            or not np.issubdtype(perm.dtype, np.integer)
            or not np.array_equal(np.sort(perm), np.arange(n_faces))
        ):
            raise MescherError(
                f"order: expected a DepthOrder or a permutation of {n_faces} faces, found "
                f"{perm.dtype} array of shape {perm.shape}"
            )
        perm = perm.astype(np.int64)
        pos = np.empty(n_faces, dtype=np.int64)
        pos[perm] = np.arange(n_faces)
        return perm, pos  # a bare permutation: every face its own level
    pos = np.empty(n_faces, dtype=np.int64)
    pos[perm] = np.arange(n_faces)
    arcs = arcs[pos[arcs[:, 0]] < pos[arcs[:, 1]]]  # drop arcs a cycle forced to break
    level = np.zeros(n_faces, dtype=np.int64)
    for _ in range(n_faces):  # terminates: the kept arcs form a DAG, one pass per level
        new = level.copy()
        np.maximum.at(new, arcs[:, 1], level[arcs[:, 0]] + 1)
        if np.array_equal(new, level):
            break
        level = new
    return perm, level


def export_render_mesh(
    m: Mescher,
    path: str | os.PathLike,
    order: Any = None,
    scalars: Any = None,
    colormap: str = "Viridis",
    vmin: float | None = None,
    vmax: float | None = None,
    z_spread: float = RENDER_Z_SPREAD,
) -> Path:
    """Write the flattened triangle soup a mescher renders as (paper Sec. 4.1).

    Each face becomes its own three vertices ``(x, y, level * dz)``: the screen triangle, lifted
    by its depth level in the order (see :func:`render_levels`) so a z-buffer (MeshLab's) draws
    faces in front over faces behind; faces are written back to front (a linear extension), so
    painter's-algorithm viewers agree.  Vertex normals are the mescher's face normals (camera
    frame), so MeshLab's lighting shades the flat soup like the mescher.

    Parameters
    ----------
    m : Mescher
    path : str or os.PathLike
    order : DepthOrder or (#F,) permutation, optional
        ``None``: index order, every face at depth 0.
    scalars : (#V,) array_like, optional
        Per mescher vertex, copied to the corners; written as colours.
    colormap, vmin, vmax
        See :func:`scalars_to_colors`.
    z_spread : float, default: 1e-2
        Depth of the highest level, relative to the screen diagonal of ``m.xy``.

    Returns
    -------
    Path
        The written file: ``3 #F`` vertices and ``#F`` faces; file face ``k`` is mescher face
        ``perm[k]`` with vertices ``3k, 3k+1, 3k+2``.
    """
    m = _mescher(m)
    z_spread = float(z_spread)
    if not np.isfinite(z_spread) or z_spread < 0:
        raise MescherError(f"z_spread: expected a finite value >= 0, found {z_spread}")
    perm, level = render_levels(order, m.n_faces)
    xy = np.asarray(m.xy)
    diag = float(np.linalg.norm(xy.max(axis=0) - xy.min(axis=0)))
    top = int(level.max(initial=0))
    dz = z_spread * diag / top if top > 0 else 0.0
    Fm = np.asarray(m.F)[perm]
    V = np.empty((3 * m.n_faces, 3))
    V[:, :2] = xy[Fm.reshape(-1)]
    V[:, 2] = np.repeat(level[perm] * dz, 3)
    F = np.arange(3 * m.n_faces, dtype=np.int64).reshape(-1, 3)
    N = np.repeat(np.asarray(m.face_normals())[perm], 3, axis=0)
    s = None
    if scalars is not None:
        s = _as_scalars(scalars, "scalars", m.n_vertices)[Fm.reshape(-1)]
    return _write(path, V, F, s, colormap, vmin, vmax, "mescher_render", normals=N)
