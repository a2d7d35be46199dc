"""A real 3D covering of an impossible mescher: the exact-distance oracle for its geodesics.

A mescher whose periods are all integer multiples of one period ``p`` (every impossible torus,
staircase or ring with one "impossible" loop) is the quotient of a real surface in 3D: integrate
``zeta`` along a spanning tree (this cuts the mescher open along the cotree edges), then glue
copies of the cut surface whose depths differ by ``k p`` end to end along the cut.  Each copy is a
*sheet*; vertex ``v`` has one lift ``(v, j)`` per sheet ``j`` at depth ``z_v + j p``.  Every
covering edge has the mescher edge's length (same ``xy`` difference, same depth difference
``zeta``), so the covering is locally isometric to the mescher, and the intrinsic distance on the
mescher between ``s`` and ``v`` is the minimum over lifts of ``v`` of the covering distance from a
lift of ``s`` (provided the shortest path stays within the sheets built: put the source in the
middle sheet and build a few).  ``igl.exact_geodesic`` on the covering (Mitchell-Mount-
Papadimitriou) then gives exact mescher distances.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import igl
import numpy as np

from . import topology
from .errors import MescherError
from .validate import as_count, as_index_array, check_budget

__all__ = ["Covering", "CoveringGeodesicSolver", "covering_distance", "covering_from_cut"]


@dataclass(frozen=True)
class Covering:
    """A covering mesh of a mescher.

    Attributes
    ----------
    V : (#Vc, 3) float64
        Covering vertices (camera frame: x, y, depth).
    F : (#Fc, 3) int64
        Covering faces, oriented like the mescher's.
    vmap : (#Vc,) int64
        Mescher vertex of each covering vertex.
    sheet : (#Vc,) int64
        Sheet of each covering vertex, in ``[0, K)``.
    fmap : (#Fc,) int64
        Mescher face of each covering face.
    period : float
        Depth gained by one loop around the impossible generator (0 for a possible object).
    K : int
        Number of sheets.
    """

    V: np.ndarray
    F: np.ndarray
    vmap: np.ndarray
    sheet: np.ndarray
    fmap: np.ndarray
    period: float
    K: int


def _tree_depths(m: Any) -> np.ndarray:
    """(#V,) depths integrated from ``zeta`` along a breadth-first spanning forest (0 at roots)."""
    edges = np.asarray(m.edges)
    return topology.integrate_one_form(edges, np.asarray(m.zeta), int(m.n_vertices))


def covering_from_cut(
    m: Any, K: int = 3, period: float | None = None, tol: float = 1e-6
) -> Covering:
    """Build ``K`` sheets of the covering of an impossible mescher, glued along the cut.

    Parameters
    ----------
    m : Mescher
    K : int, default: 3
        Number of sheets (copies of the cut-open mescher).
    period : float, optional
        The base period ``p``; default: the smallest non-zero depth mismatch across the cut.
    tol : float, default: 1e-6
        Relative tolerance for "integer multiple of ``p``" and for "zero".

    Returns
    -------
    Covering

    Raises
    ------
    MescherError
        If ``K < 1`` or the depth mismatches across the cut are not integer multiples of one
        period (a mescher with two independent impossible loops needs a 2D lattice of sheets).
    """
    K = as_count(K, "K", minimum=1)
    check_budget(float(m.n_faces) * K, 200.0, what=f"covering_from_cut(K={K})")
    F = np.asarray(m.F, dtype=np.int64)
    n = int(m.n_vertices)
    z = _tree_depths(m)
    zeta = np.asarray(m.zeta, dtype=np.float64)
    zh = np.asarray(m.face_edge_signs) * zeta[np.asarray(m.face_edges)]  # along face boundary
    # mismatch of the corner-0 -> corner-1 and corner-0 -> corner-2 depth changes
    d01 = zh[:, 2] - (z[F[:, 1]] - z[F[:, 0]])
    d02 = -zh[:, 1] - (z[F[:, 2]] - z[F[:, 0]])
    scale = max(float(np.abs(zeta).max(initial=0.0)), float(np.ptp(np.asarray(m.xy))), 1e-300)
    mis = np.abs(np.r_[d01, d02])
    if period is None:
        big = mis[mis > tol * scale]
        period = float(big.min()) if big.size else 0.0
    period = float(period)
    if period != 0.0:
        s = np.stack([np.zeros(F.shape[0]), d01 / period, d02 / period], axis=1)
        off = np.rint(s)
        if np.abs(s - off).max() > tol * max(1.0, float(np.abs(s).max())):
            raise MescherError(
                f"m: expected depth mismatches across the cut that are integer multiples of one "
                f"period ({period:.6g}), found a residual of {np.abs(s - off).max():.3g} periods"
            )
        off = off.astype(np.int64)
    else:
        if mis.max(initial=0.0) > tol * scale:
            raise MescherError(f"period: expected a non-zero period, found {period}")
        off = np.zeros((F.shape[0], 3), dtype=np.int64)
        K = 1  # a possible object is its own covering: more sheets would be disjoint copies
    # face copy j has corners on sheets j + off; keep copies entirely within [0, K)
    js = np.arange(-int(off.max(initial=0)), K - int(off.min(initial=0)) + 1)
    sheets = js[:, None, None] + off[None, :, :]  # (J, #F, 3)
    ok = ((sheets >= 0) & (sheets < K)).all(axis=2)
    jj, ff = np.nonzero(ok)
    Fc = sheets[jj, ff] * n + F[ff]
    used, Fc = np.unique(Fc.reshape(-1), return_inverse=True)
    Fc = Fc.reshape(-1, 3).astype(np.int64)
    vmap, sheet = used % n, used // n
    xy = np.asarray(m.xy, dtype=np.float64)
    V = np.column_stack([xy[vmap], z[vmap] + sheet * period])
    return Covering(
        V, Fc, vmap.astype(np.int64), sheet.astype(np.int64), ff.astype(np.int64), period, int(K)
    )


def covering_distance(
    m: Any,
    sources: Any,
    K: int = 3,
    covering: Covering | None = None,
    targets: Any = None,
    max_sheets: int = 64,
) -> np.ndarray:
    """Exact intrinsic distance on a mescher: MMP on its covering, from the sources' lifts.

    ``igl.exact_geodesic`` (Mitchell-Mount-Papadimitriou window propagation) runs on the
    covering from the lifts of ``sources`` on the middle sheet ``K // 2``, and ``d(v)`` is the
    minimum over the lifts of ``v``.  That is exact when no shorter path leaves the sheets
    built: every path that leaves crosses a *frontier* edge (a covering boundary edge that is
    interior on the mescher), and no point of a frontier edge ``ab`` is nearer than
    ``min(d(a), d(b)) - |ab| / 2``; when some ``d(v)`` exceeds that bound the covering is
    rebuilt with ``2 K + 1`` sheets (odd, so the middle stays the middle).  A possible mescher
    is its own covering (one sheet, no frontier).  Independent of
    :class:`~meschers_igl.geodesic.ExactGeodesicSolver` (which needs no covering): an oracle.

    Parameters
    ----------
    m : Mescher
    sources : int or (k,) array_like of int
        A source that no face uses has no lift: it is at 0 and reaches nothing.
    K : int, default: 3
        Sheets of the first covering built.
    covering : Covering, optional
        A covering from :func:`covering_from_cut` to use as it is (no sheets are added).
    targets : (t,) array_like of int, optional
        Only these vertices' distances (the others are ``inf``): libigl's query costs about as
        much per target vertex as the whole window propagation costs per 2000 of them.
    max_sheets : int, default: 64
        Give up beyond this many sheets.

    Returns
    -------
    d : (#V,) float64
        ``inf`` for vertices with no path to a source.

    Raises
    ------
    MescherError
        Bad sources or targets; a mescher whose periods are not multiples of one period; more
        than ``max_sheets`` sheets needed.
    """
    n = int(m.n_vertices)
    src = np.unique(as_index_array(sources, "sources", n))
    tgt = None if targets is None else as_index_array(targets, "targets", n)
    max_sheets = as_count(max_sheets, "max_sheets", minimum=1)
    while True:
        cov = covering_from_cut(m, K) if covering is None else covering
        a, b, half = _frontier(m, cov)
        vt = None if tgt is None else np.union1d(np.flatnonzero(np.isin(cov.vmap, tgt)), [*a, *b])
        d, dc = _covering_query(m, cov, src, vt)
        if tgt is not None:
            keep = np.zeros(n, dtype=bool)
            keep[tgt] = True
            d[~keep] = np.inf
        reach = np.isfinite(d)
        bound = np.minimum(dc[a], dc[b]) - half
        if (
            covering is not None
            or a.size == 0
            or not reach.any()
            or d[reach].max() < bound.min(initial=np.inf)
        ):
            return d
        if 2 * cov.K + 1 > max_sheets:
            raise MescherError(
                f"max_sheets: expected enough sheets for exact distances, found {max_sheets} "
                "too few (shortest paths wind around the impossible loop more often)"
            )
        K = 2 * cov.K + 1


def _frontier(m: Any, cov: Covering) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The frontier: covering boundary edges that are interior edges of the mescher (a path
    that leaves the sheets crosses one).  Returns their ends ``a, b`` (covering vertices) and
    half lengths: no point of edge ``ab`` is nearer than ``min(d(a), d(b)) - |ab| / 2``."""
    e_count = np.bincount(np.asarray(m.face_edges).reshape(-1), minlength=int(m.n_edges))
    lengths = np.asarray(m.edge_lengths(), dtype=np.float64)
    _, fec, _ = topology.edge_topology(cov.F, cov.V.shape[0], check=False)
    bf, bc = np.nonzero(np.bincount(fec.reshape(-1))[fec] == 1)
    me = np.asarray(m.face_edges)[cov.fmap[bf], bc]
    front = e_count[me] == 2
    a = cov.F[bf[front], (bc[front] + 1) % 3]
    b = cov.F[bf[front], (bc[front] + 2) % 3]
    return a, b, 0.5 * lengths[me[front]]


def _covering_query(
    m: Any, cov: Covering, src: np.ndarray, vt: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """``(d, dc)``: mescher distances (min over lifts) and covering distances, computed at the
    covering vertices ``vt`` (default all; ``inf`` elsewhere)."""
    n = int(m.n_vertices)
    lift = np.full((cov.K, n), -1, dtype=np.int64)
    lift[cov.sheet, cov.vmap] = np.arange(cov.vmap.size)
    vs = lift[cov.K // 2, src]
    vs = vs[vs >= 0]
    nc = cov.V.shape[0]
    vt = np.arange(nc, dtype=np.int64) if vt is None else np.asarray(vt, dtype=np.int64)
    dc = np.full(nc, np.inf)
    if vs.size and vt.size:
        dt = igl.exact_geodesic(cov.V, cov.F, VS=vs, VT=vt)
        dt = np.asarray(dt, dtype=np.float64).reshape(-1)
        # libigl returns 0 (or DBL_MAX) on components without a source: unreachable
        _, comp = topology.connected_components(cov.F, nc)
        dt[~np.isin(comp[vt], comp[vs]) | ~(dt < 1e300)] = np.inf
        dc[vt] = dt
    d = np.full(n, np.inf)
    np.minimum.at(d, cov.vmap, dc)
    d[src] = 0.0
    return d, dc


class CoveringGeodesicSolver:
    """Exact distance by MMP on the covering (:func:`covering_distance`): the oracle.

    Parameters
    ----------
    m : Mescher
    max_sheets : int, default: 64
    """

    def __init__(self, m: Any, max_sheets: int = 64) -> None:
        self.m = m
        self.n_vertices = int(m.n_vertices)
        self.max_sheets = as_count(max_sheets, "max_sheets", minimum=1)

    def distance(self, sources: Any, targets: Any = None) -> np.ndarray:
        """(#V,) exact distance to the nearest source (``inf`` off the targets, if given)."""
        return covering_distance(self.m, sources, targets=targets, max_sheets=self.max_sheets)
