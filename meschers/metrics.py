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
    """Exact geodesic distances on the mescher, or why there are none.

    Window propagation on the intrinsic mesh (``geodesic_distance(m, sources, "exact")``,
    equal to ``igl.exact_geodesic`` on a real 3D covering to round-off, as its tests check), for
    the whole field: 3-66 ms on the gallery's meschers midpoint-subdivided twice (1.7k-33k
    faces, two sources), where libigl on a covering took up to 15 s for a quarter of the
    vertices.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) int
    at : (t,) int, optional
        Keep only these vertices (``inf`` elsewhere, so :func:`distance_error` skips them).

    Returns
    -------
    (d, how)
        ``d`` (#V,) float64 or ``None``; ``how`` says which, or why none.
    """
    from meschers_igl.geodesic import geodesic_distance

    try:
        d = geodesic_distance(m, sources, "exact")
    except MescherError as exc:
        return None, f"no exact distances: {exc}"
    how = "exact (window propagation on the intrinsic mesh)"
    if at is None:
        return d, how
    keep = np.full(d.shape, np.inf)
    idx = np.asarray(at, dtype=np.int64)
    keep[idx] = d[idx]
    return keep, f"{how} at {idx.size} of {int(m.n_vertices)} vertices"
