"""A triangle from its three edge lengths: layout, areas, angles, cotangents, refinement.

This module is the one owner of intrinsic triangle geometry in ``meschers_igl`` (gpytoolbox's
style: one small vectorized function per quantity).  A mescher has per-edge lengths although it
has no global embedding (:doc:`/conventions`), so everything intrinsic -- the
operators, the heat method, unfolding strips of faces for shortest paths -- is computed here
from lengths alone.

Conventions are libigl's: ``l`` is (#F, 3) with column ``i`` the length of the edge *opposite*
corner ``i`` (edges [1,2], [2,0], [0,1]); a triangle's corners are counter-clockwise.

Formulas (``A`` the area, ``l_i`` opposite corner ``i``, ``j = i+1``, ``k = i+2`` mod 3)::

    2A          = sqrt((a+(b+c)) (c-(a-b)) (c+(a-b)) (a+(b-c))) / 2,  a >= b >= c   (Kahan)
    cot(t_i)    = (l_j^2 + l_k^2 - l_i^2) / (4 A)
    t_i         = atan2(4 A, l_j^2 + l_k^2 - l_i^2)
    layout      : p_0 = (0, 0), p_1 = (l_2, 0), p_2 = ((l_1^2 + l_2^2 - l_0^2) / (2 l_2), 2A / l_2)

Kahan's form of Heron's formula ("Miscalculating area and angles of a needle-like triangle",
2014) keeps full relative accuracy on needles, where the textbook ``sqrt(s(s-a)(s-b)(s-c))``
loses every digit; it is what ``igl::doublearea`` uses for lengths.
"""

from __future__ import annotations

import igl
import numpy as np

from .errors import MescherError

__all__ = [
    "MOLLIFY_FACTOR",
    "apex_offset",
    "apex_offsets",
    "corner_angles",
    "cotangents",
    "double_areas",
    "half_cotangents",
    "hat_gradient_gram",
    "intrinsic_delaunay",
    "is_delaunay",
    "layout",
    "midpoint_refine",
    "mollify",
    "place_apex",
]

#: Sharp & Crane 2020 ("A Laplacian for nonmanifold triangle meshes") mollification factor,
#: relative to the mean edge length; the same default as their robust-laplacian.
MOLLIFY_FACTOR = 1e-5


def _lengths(l) -> np.ndarray:
    l = np.asarray(l, dtype=np.float64)
    if l.ndim != 2 or l.shape[1] != 3:
        raise MescherError(f"l: expected a (#F, 3) array of edge lengths, found shape {l.shape}")
    return l


def double_areas(l) -> np.ndarray:
    """Twice the triangle areas from edge lengths (Kahan's stable Heron formula).

    Parameters
    ----------
    l : (#F, 3) array_like
        Edge lengths, column ``i`` opposite corner ``i``.

    Returns
    -------
    dbl : (#F,) float64
        ``2 A``; 0 for lengths that violate the triangle inequality (as ``igl.doublearea(l, 0)``).
    """
    l = _lengths(l)
    s = -np.sort(-l, axis=1)  # a >= b >= c
    a, b, c = s[:, 0], s[:, 1], s[:, 2]
    arg = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))
    return 0.5 * np.sqrt(np.maximum(arg, 0.0))


def half_cotangents(l, dbl=None) -> np.ndarray:
    """``cot(angle at corner i) / 2``: libigl's ``cotmatrix_entries`` from lengths.

    ``cot t_i / 2 = (l_j^2 + l_k^2 - l_i^2) / (8 A)``.  Written out rather than calling
    ``igl.cotmatrix_entries(l)`` because the areas are usually at hand already and libigl's call
    recomputes them (1.3x slower at 1M faces); the two agree to round-off (tested).  Faces of
    zero area get 0 (they carry no Dirichlet energy; only without mollification).

    Parameters
    ----------
    l : (#F, 3) array_like
    dbl : (#F,) array_like, optional
        ``double_areas(l)`` if already computed.

    Returns
    -------
    hc : (#F, 3) float64
    """
    l = _lengths(l)
    dbl = double_areas(l) if dbl is None else np.asarray(dbl, dtype=np.float64)
    l2 = l * l
    num = l2.sum(axis=1, keepdims=True) - 2.0 * l2  # l_j^2 + l_k^2 - l_i^2
    with np.errstate(divide="ignore", invalid="ignore"):
        c = num / (4.0 * dbl[:, None])
    c[~np.isfinite(c)] = 0.0
    return c


def cotangents(l) -> np.ndarray:
    """(#F, 3) ``cot`` of the angle at each corner (0 on zero-area faces)."""
    return 2.0 * half_cotangents(l)


def corner_angles(l) -> np.ndarray:
    """(#F, 3) interior angle at each corner, in radians.

    ``t_i = atan2(4 A, l_j^2 + l_k^2 - l_i^2)``: accurate for needles and caps alike (an
    ``arccos`` of the law of cosines loses half the digits near 0 and pi).  The three angles sum
    to pi up to round-off.
    """
    l = _lengths(l)
    l2 = l * l
    num = l2.sum(axis=1, keepdims=True) - 2.0 * l2
    return np.arctan2(2.0 * double_areas(l)[:, None], num)


def layout(l) -> np.ndarray:
    """(#F, 3, 2) planar corners of each triangle from its lengths, counter-clockwise.

    ``p_0`` at the origin, ``p_1 = (l_2, 0)`` on the +x axis, ``p_2`` above the axis with height
    ``2A / l_2`` (Kahan's area; ``sqrt(l_1^2 - x^2)`` would cancel on needles).  Hand-written:
    libigl's Python bindings have no intrinsic layout.
    """
    l = _lengths(l)
    l2 = l[:, 2]
    x2, y2 = apex_offsets(l2, l[:, 1], l[:, 0])
    y2 = np.where(l2 > 0, y2, l[:, 1])
    P = np.zeros((l.shape[0], 3, 2))
    P[:, 1, 0] = l2
    P[:, 2, 0] = x2
    P[:, 2, 1] = y2
    return P


def apex_offsets(base, la, lb) -> tuple[np.ndarray, np.ndarray]:
    """``(x, y)`` of the apex ``c`` of triangles over the segment from ``(0, 0)`` to
    ``(base, 0)`` with ``|c| = la`` and ``|c - (base, 0)| = lb``, ``y >= 0``: along the segment by
    the law of cosines, off it by Kahan's area (``sqrt(la^2 - x^2)`` would cancel on needles);
    ``(0, 0)`` where ``base`` is 0.  The one law-of-cosines layout (:func:`apex_offset` is its
    scalar twin for compiled kernels)."""
    base, la, lb = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in (base, la, lb)))
    dbl = double_areas(np.stack([lb, la, base], axis=-1).reshape(-1, 3)).reshape(base.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(base > 0, (la * la - lb * lb + base * base) / (2.0 * base), 0.0)
        y = np.where(base > 0, dbl / base, 0.0)
    return x, y


def apex_offset(base: float, la: float, lb: float) -> tuple[float, float]:
    """Scalar :func:`apex_offsets` for compiled kernels (compiled by :func:`apex_kernel`)."""
    if base <= 0.0:
        return 0.0, 0.0
    return (la * la - lb * lb + base * base) / (2.0 * base), _dbl_area(lb, la, base) / base


def place_apex(pa, pb, la, lb, side: float = 1.0) -> np.ndarray:
    """The third corner ``c`` of a triangle on a given segment ``pa pb`` (unfolding).

    Parameters
    ----------
    pa, pb : (..., 2) array_like
        The two known corners in the plane.
    la, lb : (...,) array_like
        ``|c - pa|`` and ``|c - pb|``.
    side : float or (...,) array_like, default: 1
        +1: ``c`` to the left of ``pa -> pb`` (counter-clockwise ``pa, pb, c``), -1: right.

    Returns
    -------
    c : (..., 2) float64
        Along the segment by the law of cosines, off it by Kahan's area (stable for needles).
    """
    pa = np.asarray(pa, dtype=np.float64)
    pb = np.asarray(pb, dtype=np.float64)
    e = pb - pa
    L = np.sqrt((e * e).sum(axis=-1))
    x, y = apex_offsets(L, la, lb)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(L > 0, x / L, 0.0)  # in units of the segment
        y = np.where(L > 0, y / L, 0.0)
    nrm = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    return pa + x[..., None] * e + (np.asarray(side, dtype=np.float64) * y)[..., None] * nrm


def hat_gradient_gram(l) -> tuple[np.ndarray, np.ndarray]:
    """Per-face Gram matrices of the hat-function gradients, and the face areas.

    ``K[f, i, j] = grad(phi_i) . grad(phi_j)`` on face ``f``: ``-cot(t_k) / (2 A)`` off the
    diagonal (``k`` the third corner) and minus the row sum on it.  ``A K`` is the face's block
    of ``-cotmatrix``; ``-K @ u[F[f]]`` is the barycentric velocity of ``-grad u``.

    Returns
    -------
    K : (#F, 3, 3) float64
    area : (#F,) float64
    """
    l = _lengths(l)
    dbl = double_areas(l)
    area = 0.5 * dbl
    hc = half_cotangents(l, dbl)  # cot / 2; w = -cot / (2A) below
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(area[:, None] > 0, -hc / np.where(area > 0, area, 1.0)[:, None], 0.0)
    K = np.zeros((l.shape[0], 3, 3))
    j, k = [1, 2, 0], [2, 0, 1]
    K[:, j, k] = w
    K[:, k, j] = w
    K[:, [0, 1, 2], [0, 1, 2]] = -(K.sum(axis=2))
    return K, area


def mollify(l, factor: float = MOLLIFY_FACTOR) -> tuple[np.ndarray, float]:
    """Intrinsic mollification (Sharp & Crane 2020, Sec. 4.5).

    Adds the smallest ``eps >= 0`` to every edge length so that each triangle satisfies the
    triangle inequality with margin ``delta = factor * mean length``.  ``eps`` is 0 on meshes
    without near-degenerate triangles, so operators then equal libigl's exactly.

    Returns
    -------
    l_mollified : (#F, 3) float64
    eps : float
    """
    l = _lengths(l)
    delta = factor * float(l.mean()) if l.size else 0.0
    a, b, c = l[:, 0], l[:, 1], l[:, 2]
    slack = np.minimum(np.minimum(b + c - a, c + a - b), a + b - c)
    eps = max(0.0, float(delta - slack.min())) if slack.size else 0.0
    return (l + eps if eps > 0 else l), eps


def is_delaunay(l, F, tol: float = 1e-9, face_edges=None) -> np.ndarray:
    """(#F, 3) bool: is the edge opposite each corner locally (intrinsic) Delaunay?

    An interior edge is Delaunay when its two opposite angles sum to at most pi, i.e. its
    cotangent weight ``(cot a + cot b) / 2 >= -tol``; boundary edges are Delaunay.  The
    tolerance lets the right angles of a grid's diagonals (weight exactly 0 up to round-off)
    count as Delaunay, which ``igl.is_intrinsic_delaunay`` decides by round-off.

    Parameters
    ----------
    l : (#F, 3) array_like
    F : (#F, 3) int
    tol : float, default: 1e-9
    face_edges : (#F, 3) int, optional
        Edge index opposite each corner (e.g. ``m.face_edges``); found from ``F`` if omitted.
    """
    l = _lengths(l)
    hc = half_cotangents(l)
    if face_edges is None:
        F = np.asarray(F, dtype=np.int64)
        a, b = F[:, [1, 2, 0]].reshape(-1), F[:, [2, 0, 1]].reshape(-1)
        key = np.minimum(a, b) * np.int64(max(int(F.max(initial=0)) + 1, 1)) + np.maximum(a, b)
        inv = np.unique(key, return_inverse=True)[1].reshape(-1)
    else:
        inv = np.asarray(face_edges, dtype=np.int64).reshape(-1)
    w = np.bincount(inv, weights=hc.reshape(-1))  # sum over both sides of each edge
    return (w[inv] >= -tol).reshape(-1, 3)


def intrinsic_delaunay(
    l, F, tol: float | None = None, face_edges=None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The intrinsic Delaunay triangulation of the surface ``(l, F)`` by edge flips.

    Fisher et al. 2007: same vertices, same piecewise-flat surface, every edge Delaunay, so
    every cotangent weight is >= 0 (>= ``-tol``).

    Parameters
    ----------
    l : (#F, 3) array_like
    F : (#F, 3) int
    tol : float, optional
        ``None``: ``igl.intrinsic_delaunay_triangulation``, which flips every edge whose weight
        ``(cot a + cot b) / 2`` is below 0 exactly, so the cocircular quads of a grid (weight 0
        up to round-off) are flipped or not by the sign of their round-off, and the result
        depends on the vertex numbering (two numberings of one torus gave heat distances 3.5%
        apart).  A float: flip only edges whose weight is below ``-tol`` (geometry-central's
        ``flipToDelaunay`` does the same with ``1e-6``), in a numba kernel; on meshes without
        such ties the result equals libigl's (same faces, same Laplacian to round-off).
    face_edges : (#F, 3) int, optional
        Edge opposite each corner of ``F`` (found if omitted); with ``tol`` the returned
        ``face_edges`` keep these edge numbers (a flipped edge keeps its number).

    Returns
    -------
    l : (#F, 3) float64
    F : (#F, 3) int64
        May hold duplicate faces and non-manifold edges combinatorially (libigl's note); the
        intrinsic geometry is well defined.  With ``tol``, an edge at a vertex of degree 2 is
        flipped too, as geometry-central does, making a loop edge (a face with a repeated
        vertex; the cotangent operators treat it correctly).
    face_edges : (#F, 3) int64
        Undirected edge opposite each corner (libigl's ``EMAP``), for boundary detection.
    """
    l = _lengths(l)
    F = np.ascontiguousarray(F, dtype=np.int64)
    if tol is None:
        lo, Fo, _E, _uE, emap, _ = igl.intrinsic_delaunay_triangulation(l, F)
        nf = Fo.shape[0]
        return lo, Fo, np.asarray(emap, dtype=np.int64).reshape(3, nf).T.copy()
    if face_edges is None:
        from .topology import edge_topology

        face_edges = edge_topology(F, check=False)[1]
    fe = np.array(face_edges, dtype=np.int64, order="C")
    lo, Fo, nf = np.array(l, order="C"), F.copy(), F.shape[0]
    # the other side of each corner's edge, as 3 * face + corner; -1 on boundary and on
    # non-manifold edges (neither is flipped)
    key = fe.reshape(-1)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    pair = np.flatnonzero(sk[1:] == sk[:-1])
    pair = pair[np.bincount(key)[sk[pair]] == 2]
    opp = np.full(3 * nf, -1, dtype=np.int64)
    opp[order[pair]], opp[order[pair + 1]] = order[pair + 1], order[pair]
    _flip_kernel()(Fo, lo, opp.reshape(nf, 3), fe, float(tol), 50 * nf + 100)
    return lo, Fo, fe


def double_area_kahan(a: float, b: float, c: float) -> float:
    """Twice the area of one triangle from its side lengths: Kahan's stable Heron formula (the
    scalar twin of :func:`double_areas`, for compiled kernels; :func:`double_area_kernel`)."""
    if a < b:
        a, b = b, a
    if b < c:
        b, c = c, b
    if a < b:
        a, b = b, a
    arg = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))
    return 0.5 * np.sqrt(max(arg, 0.0))


_FLIP_JIT = None
_AREA_JIT = None
_APEX_JIT = None


def double_area_kernel():
    """:func:`double_area_kahan` compiled by numba (on first use: importing numba costs 0.3 s,
    which every ``import meschers_igl.mescher`` would pay if it were compiled at import)."""
    global _AREA_JIT
    if _AREA_JIT is None:
        from .jit import kernel

        _AREA_JIT = kernel(nogil=True)(double_area_kahan)
    return _AREA_JIT


def apex_kernel():
    """:func:`apex_offset` compiled by numba on first use (see :func:`double_area_kernel`)."""
    global _APEX_JIT, _dbl_area
    if _APEX_JIT is None:
        from .jit import kernel

        _dbl_area = double_area_kernel()  # a compiled global for the kernel to call
        _APEX_JIT = kernel(nogil=True)(apex_offset)
    return _APEX_JIT


def _flip_kernel():
    """The flip loop compiled by numba on first use (see :func:`double_area_kernel`)."""
    global _FLIP_JIT, _dbl_area, _apex_offset
    if _FLIP_JIT is None:
        from .jit import kernel

        _dbl_area = double_area_kernel()  # compiled globals for the kernel to call
        _apex_offset = apex_kernel()
        _FLIP_JIT = kernel(nogil=True)(_flip_to_delaunay)
    return _FLIP_JIT


_dbl_area = double_area_kahan  # replaced by the compiled one before a kernel compiles
_apex_offset = apex_offset  # likewise


def _flip_to_delaunay(F, l, opp, fe, tol, max_flips):  # pragma: no cover - compiled
    """Lawson flips, in place, of edges whose cotangent weight is below ``-tol``.

    Face ``f`` = (a, b, c) and its neighbour ``g`` = (d, c, b) across edge b-c become
    (a, b, d) and (d, c, a); the new diagonal's length comes from laying the quad out in the
    plane.  A stack of edges to check, refilled with the four outer edges of each flip.
    """
    nf = F.shape[0]
    stack = np.empty(3 * nf + 4 * max_flips + 1, dtype=np.int64)
    top = 0
    for h in range(3 * nf):
        if opp[h // 3, h % 3] > h:
            stack[top] = h
            top += 1
    nflip = 0
    while top > 0 and nflip < max_flips:
        top -= 1
        f, i = stack[top] // 3, stack[top] % 3
        o = opp[f, i]
        if o < 0:
            continue
        g, j = o // 3, o % 3
        i1, i2, j1, j2 = (i + 1) % 3, (i + 2) % 3, (j + 1) % 3, (j + 2) % 3
        a, b, c, d = F[f, i], F[f, i1], F[f, i2], F[g, j]
        l_bc, l_ca, l_ab, l_bd, l_dc = l[f, i], l[f, i1], l[f, i2], l[g, j1], l[g, j2]
        # twice the areas of both faces (Kahan)
        A_f = _dbl_area(l_bc, l_ca, l_ab)
        A_g = _dbl_area(l_bc, l_bd, l_dc)
        if A_f <= 0.0 or A_g <= 0.0 or l_bc <= 0.0:
            continue
        # weight (cot a + cot d) / 2, cot = (sum of the adjacent sides^2 - opposite^2) / (4 A)
        w = 0.25 * ((l_ca * l_ca + l_ab * l_ab - l_bc * l_bc) / A_f)
        w += 0.25 * ((l_bd * l_bd + l_dc * l_dc - l_bc * l_bc) / A_g)
        if not w < -tol:
            continue
        if g == f:  # an edge glued to its own face (a vertex of degree 1): not flippable
            continue
        X, Y, Z, W = opp[g, j1], opp[f, i2], opp[f, i1], opp[g, j2]
        # the quad in the plane: b = (0, 0), c = (l_bc, 0), a above, d below
        xa, ya = _apex_offset(l_bc, l_ab, l_ca)
        xd, yd = _apex_offset(l_bc, l_bd, l_dc)
        l_ad = np.sqrt((xa - xd) ** 2 + (ya + yd) ** 2)
        if not np.isfinite(l_ad):
            continue
        e0, eX, eY, eZ, eW = fe[f, i], fe[g, j1], fe[f, i2], fe[f, i1], fe[g, j2]
        F[f, 0], F[f, 1], F[f, 2] = a, b, d
        l[f, 0], l[f, 1], l[f, 2] = l_bd, l_ad, l_ab
        fe[f, 0], fe[f, 1], fe[f, 2] = eX, e0, eY
        F[g, 0], F[g, 1], F[g, 2] = d, c, a
        l[g, 0], l[g, 1], l[g, 2] = l_ca, l_ad, l_dc
        fe[g, 0], fe[g, 1], fe[g, 2] = eZ, e0, eW
        # an outer side of the quad may be glued to another side of the same quad (a vertex of
        # degree 2, as on crumpled meshes; geometry-central flips these too, making a loop edge
        # or a self-glued face): such neighbours get their new half-edge numbers
        old_h = (3 * f + i1, 3 * f + i2, 3 * g + j1, 3 * g + j2)
        new_h = (3 * g, 3 * f + 2, 3 * f, 3 * g + 2)
        nbs = (X, Y, Z, W)
        for k in range(4):
            nbs_k = nbs[k]
            inside = False
            for q in range(4):
                if nbs[k] == old_h[q]:
                    nbs_k = new_h[q]
                    inside = True
            if not inside and nbs_k >= 0:
                # outside the quad: point it back at its new partner
                opp[nbs_k // 3, nbs_k % 3] = (3 * f, 3 * f + 2, 3 * g, 3 * g + 2)[k]
            if k == 0:
                X = nbs_k
            elif k == 1:
                Y = nbs_k
            elif k == 2:
                Z = nbs_k
            else:
                W = nbs_k
        opp[f, 0], opp[f, 1], opp[f, 2] = X, 3 * g + 1, Y
        opp[g, 0], opp[g, 1], opp[g, 2] = Z, 3 * f + 1, W
        for k in range(4):
            stack[top] = (3 * f, 3 * f + 2, 3 * g, 3 * g + 2)[k]
            top += 1
        nflip += 1
    return nflip


def midpoint_refine(
    l, F, edges: np.ndarray, face_edges: np.ndarray, n_vertices: int
) -> tuple[np.ndarray, np.ndarray, int]:
    """One 1-to-4 midpoint split of an intrinsic mesh; original vertices keep their indices.

    The connectivity is :func:`meschers_igl.subdivision.refine_connectivity`'s (new vertex
    ``n + e`` on edge ``e``).  Each child is its parent scaled by 1/2 (the middle one rotated by
    pi), so child lengths are parent lengths / 2 in permuted columns: the piecewise-flat surface
    is unchanged, only the triangulation is finer.

    Parameters
    ----------
    l : (#F, 3) array_like
    F : (#F, 3) int
    edges : (#E, 2) int
    face_edges : (#F, 3) int
        Edge opposite each corner.
    n_vertices : int

    Returns
    -------
    l_child : (4 #F, 3) float64
    F_child : (4 #F, 3) int64
        Children of face ``f`` are ``4f .. 4f+3``.
    n_child : int
        ``n_vertices + #E``.
    """
    from .subdivision import refine_connectivity

    l = 0.5 * _lengths(l)
    step = refine_connectivity(np.asarray(F), np.asarray(edges), np.asarray(face_edges), n_vertices)
    # child corner patterns (subdivision._CHILDREN): [a, m_c, m_b], [b, m_a, m_c],
    # [m_c, m_a, m_b], [m_a, c, m_b]; the edge opposite each child corner is parallel to the
    # parent edge listed here (column of l)
    cols = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [1, 2, 0]])
    lc = l[:, cols].reshape(-1, 3)
    return lc, step.F, int(step.S_mid.shape[0])
