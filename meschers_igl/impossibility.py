"""Two ways a mescher is impossible, and which one holds.

1. **Through zeta**: ``zeta`` does not integrate around some loop (a period is non-zero,
   ``omega != 0``); no height function exists at all (the Penrose triangle).
2. **Through its depth order**: zeta integrates (the *bent embedding* ``z`` of the Hodge
   decomposition is a real height function), but the order says a face is in front of another
   where no placement of the parts agrees.  The only freedom an integrable mescher leaves is one
   depth offset ``o_k`` per connected component, so the order is realisable iff the linear
   program

   ``maximise t  s.t.  z_j(c) + o_{k(j)} - z_i(c) - o_{k(i)} >= t  for every arc i -> j,  t <= 1``

   (``c`` a point of the screen overlap of faces ``i`` and ``j``, ``z_f(c)`` the bent depth of
   face ``f`` there) has an optimum ``t > tol``.  Faces of one component have no freedom: their
   arcs are checked directly.  The paper's Window and Reutersvärd's triangle of separate cubes are
   impossible this way.

This module takes a mescher through its public arrays (it never imports :mod:`.mescher`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .errors import MescherError
from .geometry2d import barycentric, intersection_centroids, triangles_overlap

__all__ = ["Impossibility", "order_realisable", "impossibility"]


@dataclass(frozen=True)
class Impossibility:
    """The answer of ``m.is_impossible(order=...)``: truthy when impossible, with the kind.

    Attributes
    ----------
    kind : {"zeta", "order", None}
        ``"zeta"``: a non-zero period; ``"order"``: zeta integrates but the order is not
        realisable by the bent embedding with one offset per component; ``None``: possible.
    reason : str
    margin : float
        ``"order"``/possible: the LP's optimal margin ``t`` (negative when impossible).
    """

    kind: str | None
    reason: str
    margin: float = float("nan")

    def __bool__(self) -> bool:
        return self.kind is not None

    def __str__(self) -> str:
        return self.reason


def _overlap_points(xy: np.ndarray, F: np.ndarray, arcs: np.ndarray):
    """A screen point common to faces ``i`` and ``j`` of each arc (overlap centroid, or the mean
    of their shared screen corners when they only touch), and whether they only touch."""
    A, B = xy[F[arcs[:, 0]]], xy[F[arcs[:, 1]]]
    scale = float(np.linalg.norm(np.ptp(xy, axis=0)))
    # intersection_centroids assumes an overlap: test it first (SAT, positive area)
    touch = ~triangles_overlap(A, B, 1e-9 * scale)
    cen = np.zeros((arcs.shape[0], 2))
    if (~touch).any():
        cen[~touch] = intersection_centroids(A[~touch], B[~touch])[0]
    if touch.any():
        # touching faces: points of A that lie on B's boundary (shared corners), averaged
        a, b = A[touch], B[touch]
        d = np.linalg.norm(a[:, :, None, :] - b[:, None, :, :], axis=3)  # (k, 3, 3)
        shared = d.min(axis=2) <= 1e-9 * scale  # (k, 3) corners of A also corners of B
        n = shared.sum(axis=1, keepdims=True)
        cen[touch] = np.where(
            n > 0, (a * shared[:, :, None]).sum(axis=1) / np.maximum(n, 1), a.mean(axis=1)
        )
    return cen, touch


def order_realisable(m: Any, order: Any, tol: float | None = None) -> tuple[bool, float, str]:
    """Can the bent embedding, one depth offset per component, realise ``order``?

    Parameters
    ----------
    m : Mescher
    order : DepthOrder or (k, 2) array_like of int
        Arcs ``i -> j``: face ``i`` behind face ``j``.
    tol : float, optional
        Depth margin counted as zero, relative to the model's size (default 1e-9).

    Returns
    -------
    ok : bool
    margin : float
        Optimal LP margin (depth units): the least depth by which every arc can be honoured.
    reason : str
    """
    from scipy.optimize import linprog

    arcs = np.asarray(getattr(order, "arcs", order), dtype=np.int64).reshape(-1, 2)
    F = np.asarray(m.F)
    xy = np.asarray(m.xy)
    if arcs.size and (arcs.min() < 0 or arcs.max() >= F.shape[0]):
        raise MescherError(
            f"order: expected arcs between faces 0..{F.shape[0] - 1}, found "
            f"{int(arcs.min())}..{int(arcs.max())}"
        )
    Vb, _ = m.bent_embedding()
    z = np.asarray(Vb)[:, 2]
    scale = float(np.linalg.norm(np.ptp(np.c_[xy, z], axis=0)))
    tol = (1e-9 if tol is None else float(tol)) * scale
    if arcs.shape[0] == 0:
        return True, np.inf, "no arcs"
    c, touch = _overlap_points(xy, F, arcs)
    zi = (barycentric(c, xy[F[arcs[:, 0]]]) * z[F[arcs[:, 0]]]).sum(axis=1)
    zj = (barycentric(c, xy[F[arcs[:, 1]]]) * z[F[arcs[:, 1]]]).sum(axis=1)
    dz = zj - zi  # must become > 0 after the offsets
    E = np.asarray(m.edges)
    n = xy.shape[0]
    _, comp_v = csgraph.connected_components(
        sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)), directed=False
    )
    ci, cj = comp_v[F[arcs[:, 0], 0]], comp_v[F[arcs[:, 1], 0]]
    # faces that overlap on screen must be strictly ordered; faces that only touch there (an
    # occlusion contour) need not be apart in depth: of one part they carry no information,
    # of two parts they may be in contact (a block resting against another, flush faces
    # meeting on screen both ways at equal depth)
    strict = ~touch
    same = ci == cj
    # two faces of one part at equal depth (to tol) where the arc is checked meet there: the
    # arc says nothing a placement could break (round-off decides its sign)
    level = same & (np.abs(dz) <= tol)
    bad = same & (dz < -tol)
    if bad.any():
        k = int(np.flatnonzero(bad)[np.argmin(dz[bad])])
        return (
            False,
            float(dz[k]),
            f"arc {arcs[k].tolist()} puts face {arcs[k, 1]} in front of face {arcs[k, 0]} of "
            f"the same part, but the bent embedding has it {-dz[k]:.4g} behind",
        )
    cross = ~same
    if not cross.any():
        return True, float(dz.min()), "every arc holds in the bent embedding"
    comps, inv = np.unique(np.r_[ci[cross], cj[cross]], return_inverse=True)
    K = comps.size
    a, b = inv[: cross.sum()], inv[cross.sum() :]
    rows = np.arange(a.size)
    # variables (o_1..o_K, t); constraint  o_a - o_b + t <= dz  (i.e. dz + o_b - o_a >= t)
    st = strict[cross]
    A = sp.coo_matrix(
        (
            np.r_[np.ones(a.size), -np.ones(a.size), np.ones(int(st.sum()))],
            (np.r_[rows, rows, rows[st]], np.r_[a, b, np.full(int(st.sum()), K)]),
        ),
        shape=(a.size, K + 1),
    ).tocsr()
    # dz + o_{k(j)} - o_{k(i)} >= t  <=>  o_{k(i)} - o_{k(j)} + t <= dz ; i -> a, j -> b
    cost = np.zeros(K + 1)
    cost[K] = -1.0
    bounds = [(None, None)] * K + [(None, scale)]
    bounds[0] = (0.0, 0.0)  # offsets are relative: pin one
    b_ub = np.where(st, dz[cross], dz[cross] + tol)
    res = linprog(cost, A_ub=A, b_ub=b_ub, bounds=bounds, method="highs")
    if res.status == 2:  # the touching arcs alone admit no offsets: by how much at best
        A = sp.hstack([A[:, :K], sp.csr_matrix(np.ones((a.size, 1)))]).tocsr()
        res = linprog(cost, A_ub=A, b_ub=b_ub, bounds=bounds, method="highs")
        st = np.ones_like(st)
    if res.status != 0:
        raise MescherError(f"order: the realisability LP failed ({res.message})")
    t = float(res.x[K]) if st.any() else scale
    if (same & strict & ~level).any():
        t = min(t, float(dz[same & strict & ~level].min()))
    if t > tol:
        return True, t, f"realisable with one offset per part (margin {t:.4g})"
    return (
        False,
        t,
        (
            f"no depth offsets of the {K} parts realise the order: some arc is violated by "
            f"{-t:.4g} at best (a cycle of arcs through parts that no placement satisfies)"
        ),
    )


def impossibility(m: Any, order: Any = None, tol: float | None = None) -> Impossibility:
    """Both kinds of impossibility (see the module docstring): zeta first, then the order.

    ``tol`` is the mescher's own ``is_impossible`` tolerance for the periods (relative to its
    size); the order margin counts as zero below 1e-9 of the size.
    """
    if m.is_impossible(tol=tol):
        p = np.asarray(m.periods())
        big = np.abs(p) > 1e-9 * float(m.scale())
        return Impossibility(
            "zeta", f"zeta does not integrate: period(s) {np.round(p[big], 6).tolist()}"
        )
    if order is None:
        return Impossibility(None, "zeta integrates and no order was given")
    ok, t, why = order_realisable(m, order)
    if ok:
        return Impossibility(None, f"zeta integrates and the order is {why}", t)
    return Impossibility("order", f"zeta integrates but the order is not realisable: {why}", t)
