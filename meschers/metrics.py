"""The study's measurements on fields and meshes (pure numpy; tested on hand-made cases).

Image measurements (luminance, dL, silhouette agreement) have their one owner in
:mod:`pyvista_views.compare`; this module measures distance fields, seams and periods.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError

__all__ = [
    "distance_error",
    "vertices_after_midpoint",
    "exact_distance",
    "loop_periods",
    "one_source_per_component",
    "seam_gap",
]


def distance_error(d: np.ndarray, d_exact: np.ndarray) -> dict:
    """Error of a distance field against an exact one, over vertices where both are finite.

    Parameters
    ----------
    d, d_exact : (#V,) float

    Returns
    -------
    dict
        ``mean``: mean |d - d*| / max d*; ``max``: max |d - d*| / max d*; ``n``: vertices used.
        (Relative to the largest exact distance so that vertices next to the source, where
        ``d*`` is near zero, do not dominate.)
    """
    d, de = np.asarray(d, dtype=np.float64), np.asarray(d_exact, dtype=np.float64)
    if d.shape != de.shape:
        raise MescherError(f"d: expected shape {de.shape} like d_exact, found {d.shape}")
    ok = np.isfinite(d) & np.isfinite(de)
    scale = float(de[ok].max()) if ok.any() else 0.0
    if scale <= 0:
        return {"mean": math.nan, "max": math.nan, "n": int(ok.sum())}
    err = np.abs(d[ok] - de[ok]) / scale
    return {"mean": float(err.mean()), "max": float(err.max()), "n": int(ok.sum())}


def seam_gap(xy: np.ndarray, vmap: np.ndarray) -> float:
    """Largest screen distance between two copies of one vertex in a cut model.

    A cut model duplicates the vertices on its seam (``vmap[i]`` is the mescher vertex of cut
    vertex ``i``).  Copies coincide on screen until an operation moves them differently:
    smoothing the cut model as a mesh opens a crack of this width along the seam.

    Parameters
    ----------
    xy : (#Vc, 2) float
    vmap : (#Vc,) int

    Returns
    -------
    float
        ``max_i |xy_i - xy_first(vmap_i)|`` (0 when nothing is duplicated); twice this bounds
        the distance between any two copies.
    """
    xy = np.asarray(xy, dtype=np.float64)
    vmap = np.asarray(vmap, dtype=np.int64)
    if xy.ndim != 2 or vmap.shape != (xy.shape[0],):
        raise MescherError(
            f"vmap: expected shape ({xy.shape[0]},) matching xy {xy.shape}, found {vmap.shape}"
        )
    _, first, inverse = np.unique(vmap, return_index=True, return_inverse=True)
    return float(np.linalg.norm(xy - xy[first[inverse]], axis=1).max(initial=0.0))


def one_source_per_component(m: Any) -> np.ndarray:
    """One source vertex per connected component, the one nearest the top-left corner of the
    xy box, so that a distance field covers models made of separate pieces (Reutersvard's
    cubes, the stair boxes).

    Returns
    -------
    (c,) int64
        Sorted vertex indices, one per component that has faces.
    """
    from meschers_igl.topology import connected_components

    xy = np.asarray(m.xy)
    _, label = connected_components(np.asarray(m.F), int(m.n_vertices))
    label = np.asarray(label)
    used = np.zeros(label.size, dtype=bool)
    used[np.asarray(m.F).ravel()] = True
    corner = np.array([xy[:, 0].min(), xy[:, 1].max()])
    dist = np.where(used, np.linalg.norm(xy - corner, axis=1), np.inf)
    # per component, the vertex of least distance: sort by (label, distance), keep the firsts
    idx = np.lexsort((dist, label))
    first = idx[np.r_[True, label[idx][1:] != label[idx][:-1]]]
    return np.sort(first[np.isfinite(dist[first])]).astype(np.int64)


def loop_periods(m: Any, zeta: np.ndarray) -> np.ndarray:
    """Depth gained by the 1-form ``zeta`` around each of ``m``'s homology generators.

    Lets the periods of a processed mescher with the same edges (smoothed: same topology) be
    compared loop by loop with ``m.periods()``, whatever generators it would pick itself.

    Parameters
    ----------
    m : Mescher
    zeta : (#E,) float
        A 1-form on ``m``'s edges.

    Returns
    -------
    (#generators,) float64
        ``sum_i s_i zeta[e_i]`` per generator ``(e, s)``.
    """
    zeta = np.asarray(zeta, dtype=np.float64)
    return np.array([float(np.dot(s, zeta[e])) for e, s in m.homology_generators()])


def exact_distance(m: Any, sources: Any, at: Any = None) -> tuple[np.ndarray | None, str]:
    """Exact distances on a 3-sheet covering (``igl.exact_geodesic``), or why there are none.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) int
    at : (t,) int, optional
        Only at these vertices (``inf`` elsewhere, so :func:`distance_error` skips them):
        libigl's MMP answers each target vertex for about 0.5 ms on a 70k-face covering, most of
        the cost of a full field.

    Returns
    -------
    (d, how)
        ``d`` (#V,) float64 or ``None``; ``how`` says which (or the covering's refusal, e.g.
        two independent periods have no 1D stack of sheets).
    """
    from meschers_igl.covering import covering_distance

    where = "" if at is None else f" at {np.size(at)} of {int(m.n_vertices)} vertices"
    try:
        return covering_distance(m, sources, targets=at), f"covering (igl.exact_geodesic){where}"
    except MescherError as exc:
        return None, f"no covering: {exc}"


def vertices_after_midpoint(n_vertices: int, n_edges: int, n_faces: int, levels: int) -> int:
    """Vertices of a mesh after ``levels`` midpoint subdivisions.

    Each level adds one vertex per edge and splits each edge in two and each face in four:
    ``V' = V + E``, ``E' = 2E + 3F``, ``F' = 4F``.  Midpoint subdivision keeps the old vertices
    first, so the vertices ``0 .. n-1`` of a finer mesh are those of the coarser one.
    """
    v, e, f = int(n_vertices), int(n_edges), int(n_faces)
    for _ in range(int(levels)):
        v, e, f = v + e, 2 * e + 3 * f, 4 * f
    return v
