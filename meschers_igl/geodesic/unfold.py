"""Strips of faces unfolded into the plane from their edge lengths, and paths pulled taut in them.

A path on a mescher is a polyline whose segments each lie in one face (:doc:`/conventions`);
a *strip* is a sequence of faces, each sharing an edge with the next, laid out face by face
(:func:`meschers_igl.intrinsic.place_apex`) and funnelled into the taut path through it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from .. import intrinsic, topology
from ..jit import kernel


class _MeshData:
    """Per-face data for tracing: corners, neighbours, Gram matrices, vertex-to-face map."""

    def __init__(self, m: Any) -> None:
        self.F = np.asarray(m.F, dtype=np.int64)
        nf, n = self.F.shape[0], int(m.n_vertices)
        # paths are unfolded and measured in the true metric; mollification (which adds eps to
        # every length: +4.5% along a 0.001-degree fan) only serves the trace's direction field
        self.l = np.asarray(m.face_edge_lengths(), dtype=np.float64)
        self.K, self.area = intrinsic.hat_gradient_gram(m.face_edge_lengths(mollified=True))
        self.tiny = 1e-12 * float(self.l.mean()) if self.l.size else 0.0
        self.cone = None  # angle defects, on first need (_cone_detours)
        fe = np.asarray(m.face_edges)  # the mescher's edge topology
        ef = topology.edge_faces(fe, int(m.n_edges))
        # neighbour across the edge opposite each corner (-1 on the boundary)
        other = np.where(ef[fe, 0] == np.arange(nf)[:, None], ef[fe, 1], ef[fe, 0])
        self.opp = other
        # vertex -> incident faces (CSR)
        self.vf = sp.csr_matrix(
            (np.ones(3 * nf), (self.F.reshape(-1), np.repeat(np.arange(nf), 3))), shape=(n, nf)
        )

    def faces_of(self, v: int) -> np.ndarray:
        return self.vf.indices[self.vf.indptr[v] : self.vf.indptr[v + 1]]


def _seg_len2(l: np.ndarray, w: np.ndarray) -> float:
    """Squared length of a displacement with barycentric change ``w`` (sum 0) in a triangle."""
    return float(-(w[1] * w[2] * l[0] ** 2 + w[2] * w[0] * l[1] ** 2 + w[0] * w[1] * l[2] ** 2))


def _cross(u: np.ndarray, w: np.ndarray) -> float:
    return float(u[0] * w[1] - u[1] * w[0])


def _intersect(p: np.ndarray, r: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[float, float]:
    """``(t, u)`` with ``p + t r = q0 + u (q1 - q0)`` (``(-inf, nan)`` for parallel lines)."""
    e = q1 - q0
    den = _cross(r, e)
    if den == 0.0:
        return -np.inf, np.nan
    w = q0 - p
    return _cross(w, e) / den, _cross(w, r) / den


def _unfold(md: _MeshData, g: int, Pg: np.ndarray, k: int) -> tuple[int, np.ndarray]:
    """The face across the edge opposite corner ``k`` of face ``g`` (corners at ``Pg``),
    unfolded into the same plane: ``(face, (3, 2) corner positions)``; face -1 at a boundary."""
    F, l = md.F, md.l
    n = int(md.opp[g, k])
    if n < 0:
        return n, Pg
    a, b = F[g, (k + 1) % 3], F[g, (k + 2) % 3]
    Pn = np.zeros((3, 2))
    ia, ib = np.flatnonzero(F[n] == a)[0], np.flatnonzero(F[n] == b)[0]
    iw = 3 - ia - ib
    Pn[ia], Pn[ib] = Pg[(k + 1) % 3], Pg[(k + 2) % 3]
    # faces are laid out counter-clockwise (consistent orientation), so w is left of a -> b
    # when a, b, w run in the face's order; the offsets use the edge's own length, not the
    # unfolded one (a face without area would turn a round-off there into a sqrt(eps) height)
    side = 1.0 if (ib - ia) % 3 == 1 else -1.0
    e = Pn[ib] - Pn[ia]
    e = e / max(float(np.hypot(*e)), 1e-300)
    x, y = intrinsic.apex_offsets(l[n, iw], l[n, ib], l[n, ia])
    Pn[iw] = Pn[ia] + float(x) * e + side * float(y) * np.array([-e[1], e[0]])
    return n, Pn


_apex_offset = intrinsic.apex_kernel()  # the law-of-cosines layout, compiled


@kernel(no_cpython_wrapper=True)  # called by kernels only
def _area2(a0, a1, b0, b1, c0, c1) -> float:
    return (b0 - a0) * (c1 - a1) - (c0 - a0) * (b1 - a1)


@kernel()
def _funnel_kernel(F, l, faces, v0, v1):  # pragma: no cover - compiled
    """Unfold a strip of faces and pull the path from ``v0`` to ``v1`` taut in it.

    The strip is laid out face by face from the intrinsic lengths (the first face as
    :func:`meschers_igl.intrinsic.layout`, each next apex as :func:`intrinsic.place_apex`), then
    the "simple stupid funnel" (Mononen's string pulling; Lee-Preparata) finds the taut path.
    Hand-written in numba: no library pulls strings on an unfolded intrinsic strip, and both
    walks are sequential (each face is placed from the previous one; the funnel's apex moves
    along the strip).  One function: the layout writes the portal arrays the string pulling
    reads, and splitting them would pass those six arrays through every call.

    Returns corner point indices, corner vertices, corner positions, and per point ``k`` (point
    ``k`` lies on the portal between ``faces[k-1]`` and ``faces[k]``) the crossing parameter
    ``tpar`` (0 at the left end, 1 at the right) and the portal's left and right vertices.
    """
    n = faces.shape[0]
    npt = n + 1
    pl = np.empty((npt, 2), dtype=np.float64)
    pr = np.empty((npt, 2), dtype=np.float64)
    il = np.empty(npt, dtype=np.int64)
    ir = np.empty(npt, dtype=np.int64)
    cv = np.empty(3, dtype=np.int64)
    cp = np.empty((3, 2), dtype=np.float64)  # np.empty: np.zeros is a compilation more
    f0 = faces[0]
    for c in range(3):
        cv[c] = F[f0, c]
    L0, L1, L2 = l[f0, 0], l[f0, 1], l[f0, 2]
    cp[0, 0] = cp[0, 1] = cp[1, 1] = 0.0
    cp[1, 0] = L2
    cp[2, 0], cp[2, 1] = _apex_offset(L2, L1, L0)
    for c in range(3):
        if cv[c] == v0:
            pl[0, 0] = pr[0, 0] = cp[c, 0]
            pl[0, 1] = pr[0, 1] = cp[c, 1]
    il[0] = ir[0] = v0
    for k in range(1, n):
        g = faces[k]
        # the portal: the two vertices of g that the previous face has
        ka = -1
        kb = -1
        kc = -1
        for c in range(3):
            found = False
            for q in range(3):
                if cv[q] == F[g, c]:
                    found = True
            if found:
                if ka < 0:
                    ka = c
                else:
                    kb = c
            else:
                kc = c
        a, b, cc = F[g, ka], F[g, kb], F[g, kc]
        pa0 = pa1 = pb0 = pb1 = 0.0
        for q in range(3):
            if cv[q] == a:
                pa0, pa1 = cp[q, 0], cp[q, 1]
            elif cv[q] == b:
                pb0, pb1 = cp[q, 0], cp[q, 1]
        la = l[g, kb]  # |c a| is opposite b
        lb = l[g, ka]  # |c b| is opposite a
        e0, e1 = pb0 - pa0, pb1 - pa1
        # faces are laid out counter-clockwise (consistent orientation): the apex is left of
        # a -> b when a, b, apex run in the face's order (ka < kb here), and the previous
        # face's apex on the other side; the offsets use the portal's own length (a face
        # without area would turn a round-off in the unfolded one into a sqrt(eps) height)
        side = 1.0 if kb - ka == 1 else -1.0
        LL = np.sqrt(e0 * e0 + e1 * e1)
        x, y = _apex_offset(l[g, kc], la, lb)
        if LL > 0:  # in units of the portal
            x /= LL
            y /= LL
        pc0 = pa0 + x * e0 - side * y * e1
        pc1 = pa1 + x * e1 + side * y * e0
        if side < 0:
            il[k], ir[k] = b, a
            pl[k, 0], pl[k, 1], pr[k, 0], pr[k, 1] = pb0, pb1, pa0, pa1
        else:
            il[k], ir[k] = a, b
            pl[k, 0], pl[k, 1], pr[k, 0], pr[k, 1] = pa0, pa1, pb0, pb1
        cv[0], cv[1], cv[2] = a, b, cc
        cp[0, 0], cp[0, 1], cp[1, 0], cp[1, 1], cp[2, 0], cp[2, 1] = pa0, pa1, pb0, pb1, pc0, pc1
    for c in range(3):
        if cv[c] == v1:
            pl[n, 0] = pr[n, 0] = cp[c, 0]
            pl[n, 1] = pr[n, 1] = cp[c, 1]
    il[n] = ir[n] = v1
    # string pulling
    ci = np.empty(npt + 1, dtype=np.int64)
    cx = np.empty((npt + 1, 2), dtype=np.float64)
    cvid = np.empty(npt + 1, dtype=np.int64)
    nc = 0
    ci[0], cx[0, 0], cx[0, 1], cvid[0] = 0, pl[0, 0], pl[0, 1], v0
    nc = 1
    ax, ay = pl[0, 0], pl[0, 1]
    lx, ly, rx, ry = ax, ay, ax, ay
    api, li, ri = 0, 0, 0
    i = 1
    while i < npt:
        qlx, qly, qrx, qry = pl[i, 0], pl[i, 1], pr[i, 0], pr[i, 1]
        restart = False
        if _area2(ax, ay, rx, ry, qrx, qry) >= 0:
            if (ax == rx and ay == ry) or _area2(ax, ay, lx, ly, qrx, qry) < 0:
                rx, ry, ri = qrx, qry, i
            else:
                ax, ay, api = lx, ly, li
                ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = li, lx, ly, il[li]
                nc += 1
                rx, ry, ri = ax, ay, api
                i = api + 1
                restart = True
        if not restart and _area2(ax, ay, lx, ly, qlx, qly) <= 0:
            if (ax == lx and ay == ly) or _area2(ax, ay, rx, ry, qlx, qly) > 0:
                lx, ly, li = qlx, qly, i
            else:
                ax, ay, api = rx, ry, ri
                ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = ri, rx, ry, ir[ri]
                nc += 1
                lx, ly, li = ax, ay, api
                rx, ry, ri = ax, ay, api
                i = api + 1
                restart = True
        if restart:
            lx, ly, li = ax, ay, api
            rx, ry, ri = ax, ay, api
            continue
        i += 1
    if ci[nc - 1] != npt - 1:
        ci[nc], cx[nc, 0], cx[nc, 1], cvid[nc] = npt - 1, pl[n, 0], pl[n, 1], v1
        nc += 1
    # where the taut path crosses each portal
    tpar = np.empty(npt, dtype=np.float64)
    for k in range(npt):
        tpar[k] = 0.0
    for c in range(nc - 1):
        ia, ib = ci[c], ci[c + 1]
        pa0, pa1, pb0, pb1 = cx[c, 0], cx[c, 1], cx[c + 1, 0], cx[c + 1, 1]
        tpar[ia] = 0.0 if (pa0 == pl[ia, 0] and pa1 == pl[ia, 1]) else 1.0
        dp0, dp1 = pb0 - pa0, pb1 - pa1
        for k in range(ia + 1, ib):
            dq0, dq1 = pr[k, 0] - pl[k, 0], pr[k, 1] - pl[k, 1]
            den = dp0 * dq1 - dp1 * dq0
            t = 0.0
            if den != 0:
                t = ((pl[k, 0] - pa0) * dp1 - (pl[k, 1] - pa1) * dp0) / den
            tpar[k] = min(max(t, 0.0), 1.0)
    return ci[:nc], cvid[:nc], cx[:nc].copy(), tpar, il, ir


def _funnel(md: _MeshData, v0: int, faces, v1: int):
    """:func:`_funnel_kernel` on ``md``: (corner indices, corner vertices, corner xy, tpar,
    left ids, right ids)."""
    return _funnel_kernel(md.F, md.l, np.asarray(faces, dtype=np.int64), int(v0), int(v1))


def _segments(md: _MeshData, faces, tpar, il, ir) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Barycentric start and end of the path in each face of a funnelled strip (vectorized)."""
    faces = np.asarray(faces, dtype=np.int64)
    Ff = md.F[faces]
    k = np.arange(faces.size)

    def bary(j):
        return (Ff == il[j][:, None]) * (1.0 - tpar[j])[:, None] + (Ff == ir[j][:, None]) * tpar[j][
            :, None
        ]

    return faces, bary(k), bary(k + 1)


def _taut(md: _MeshData, v0: int, faces: list[int], v1: int) -> list[tuple]:
    """Funnel a strip and split it at the taut path's corners.

    Returns pieces ``(va, faces, vb, length)``: straight in their unfolded strip, from corner
    vertex ``va`` to ``vb``.
    """
    ci, cv, cx, _, _, _ = _funnel(md, v0, faces, v1)
    seg = np.hypot(*(cx[1:] - cx[:-1]).T)
    out = []
    for k in range(ci.size - 1):  # corners of one taut path: few
        # a piece from a vertex to itself without length would pin its corner: dropped (one
        # with a length is a closed loop, kept)
        if cv[k] != cv[k + 1] or seg[k] > md.tiny:
            out.append((int(cv[k]), faces[ci[k] : ci[k + 1]], int(cv[k + 1]), float(seg[k])))
    return out


def _pieces(md: _MeshData, strips: list[tuple]) -> list[tuple]:
    """Taut pieces of a path given as strips ``(v_start, faces, v_end)`` (target -> source)."""
    out = []
    for v0, faces, v1 in strips:
        out.extend(_taut(md, v0, list(faces), v1))
    return out
