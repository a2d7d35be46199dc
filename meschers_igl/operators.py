"""Geometry of a mescher from its locally integrated triangles, and the discrete operators.

Each triangle is locally integrable (``d12 zeta = 0``), so it has consistent corner positions
up to a translation in depth (:doc:`/conventions`):
``(x_0, y_0, 0), (x_1, y_1, zeta_01), (x_2, y_2, zeta_01 + zeta_12)``.  Edge lengths are then
per *edge*, shared by both faces, which is all libigl's intrinsic operators need.  Extrinsic
per-face quantities (gradients, normals) come from those local corners; they are invariant to the
per-face depth translation, so they are well defined although no global embedding exists.

All functions are vectorised over faces; none loops in Python.
"""

from __future__ import annotations

import igl
import numpy as np
import scipy.sparse as sp

from .errors import MescherError
from .intrinsic import MOLLIFY_FACTOR, double_areas, half_cotangents, layout, mollify
from .validate import as_direction

__all__ = [
    "MASS_TYPES",
    "MOLLIFY_FACTOR",
    "corner_depths",
    "cotmatrix",
    "double_areas_from_lengths",
    "edge_lengths",
    "face_cross",
    "face_normals",
    "grad",
    "grad_intrinsic",
    "grad_mollified",
    "half_cotangents",
    "intrinsic_operators",
    "local_corners",
    "massmatrix",
    "mollify",
    "star1_from_half_cot",
    "up_for_view",
    "vertex_normals",
    "view_frame",
]

#: the triangle-from-lengths geometry lives in :mod:`meschers_igl.intrinsic`; this name is kept
#: for the callers that read areas through the operators module
double_areas_from_lengths = double_areas


def view_frame(view=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """Rotation from world to camera coordinates.

    Parameters
    ----------
    view : (3,) array_like
        Direction from the object toward the (orthographic) camera; becomes +z.
    up : (3,) array_like
        Screen up; re-orthogonalised against ``view``.

    Returns
    -------
    R : (3, 3) float64
        Rows are screen right, screen up and ``view``; camera coordinates are ``V @ R.T``.
    """
    v = as_direction(view, "view")
    u = as_direction(up, "up")
    right = np.cross(u, v)
    n = np.linalg.norm(right)
    if n < 1e-12:
        raise MescherError(f"up: expected a direction not parallel to view {v.tolist()}, found {u}")
    right /= n
    u = np.cross(v, right)
    return np.stack([right, u, v])


def up_for_view(view: object) -> np.ndarray:
    """Screen up for ``view``: world +z projected onto the screen plane (+y if view is vertical)."""
    v = np.asarray(view, dtype=np.float64)
    v = v / np.linalg.norm(v)
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])):
        u = axis - (axis @ v) * v
        if np.linalg.norm(u) > 1e-6:
            return u / np.linalg.norm(u)
    raise MescherError(f"view: expected a finite direction, found {v.tolist()}")  # unreachable


def corner_depths(zeta: np.ndarray, face_edges: np.ndarray, signs: np.ndarray) -> np.ndarray:
    """(#F, 3) per-face local depths, corner 0 at depth 0.

    ``Z[:,1] = zeta(0->1)`` (edge opposite corner 2), ``Z[:,2] = Z[:,1] + zeta(1->2)``
    (edge opposite corner 0).
    """
    h01 = signs[:, 2] * zeta[face_edges[:, 2]]
    h12 = signs[:, 0] * zeta[face_edges[:, 0]]
    Z = np.zeros(face_edges.shape, dtype=np.float64)
    Z[:, 1] = h01
    Z[:, 2] = h01 + h12
    return Z


def local_corners(xy: np.ndarray, F: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """(#F, 3, 3) per-face corner positions ``(x, y, local depth)``."""
    P = np.empty((F.shape[0], 3, 3), dtype=np.float64)
    P[:, :, :2] = xy[F]
    P[:, :, 2] = Z
    return P


def edge_lengths(xy: np.ndarray, edges: np.ndarray, zeta: np.ndarray) -> np.ndarray:
    """(#E,) lengths ``sqrt(dx^2 + dy^2 + zeta^2)``."""
    d = xy[edges[:, 1]] - xy[edges[:, 0]]
    return np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2 + zeta**2)


def star1_from_half_cot(hc: np.ndarray, face_edges: np.ndarray, n_edges: int) -> np.ndarray:
    """(#E,) cotangent weights ``(cot a + cot b) / 2`` accumulated over the incident faces."""
    return np.bincount(face_edges.reshape(-1), weights=hc.reshape(-1), minlength=n_edges)


def cotmatrix(l_face: np.ndarray, F: np.ndarray) -> sp.csc_matrix:
    """Negative semi-definite cotangent Laplacian from edge lengths (``igl.cotmatrix_intrinsic``)."""
    return igl.cotmatrix_intrinsic(l_face, F)


MASS_TYPES = {
    "voronoi": igl.MASSMATRIX_TYPE_VORONOI,
    "barycentric": igl.MASSMATRIX_TYPE_BARYCENTRIC,
}


def massmatrix(l_face: np.ndarray, F: np.ndarray, kind: str = "voronoi") -> sp.csc_matrix:
    """Lumped mass matrix from edge lengths (``igl.massmatrix_intrinsic``)."""
    if kind not in MASS_TYPES:
        raise MescherError(f"kind: expected 'voronoi' or 'barycentric', found {kind!r}")
    return igl.massmatrix_intrinsic(l_face, F, MASS_TYPES[kind])


def face_cross(P: np.ndarray) -> np.ndarray:
    """(#F, 3) ``(p1 - p0) x (p2 - p0)`` of the local corners (twice the area times the normal)."""
    return np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])


def grad(P: np.ndarray, F: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """FEM gradient (#F*3, #V) in the camera frame, rows blocked x, y, z like ``igl.grad``.

    The gradient of the hat function of corner ``i`` in face ``f`` is ``n x e_i / (2A)`` with
    ``e_i`` the edge opposite ``i`` (counter-clockwise) and ``n`` the unit normal of the local
    corners.  Hand-written rather than ``igl.grad`` on a per-face triangle soup because that
    call alone costs 1.3x ``igl.grad`` on the mesh and needs a gather afterwards (measured at
    1M faces); the result equals ``igl.grad`` to round-off (tests check 1e-10).  Faces of zero
    area get zero rows instead of libigl's NaNs.
    """
    N = face_cross(P)
    dbl2 = np.einsum("ij,ij->i", N, N)  # (2A)^2
    with np.errstate(divide="ignore", invalid="ignore"):
        w = N / np.where(dbl2 > 0, dbl2, np.inf)[:, None]  # n / (2A); 0 on zero-area faces
    E = P[:, [2, 0, 1]] - P[:, [1, 2, 0]]  # e_i = p_{i+2} - p_{i+1}, opposite corner i
    Ex, Ey, Ez = E[..., 0], E[..., 1], E[..., 2]
    wx, wy, wz = w[:, 0:1], w[:, 1:2], w[:, 2:3]
    # (w x e_i) written out per coordinate, directly in the CSR data layout (coordinate,
    # face, corner): no (#F, 3, 3) temporary and no transpose copy at 1M faces
    data = np.empty((3, F.shape[0], 3))
    np.subtract(wy * Ez, wz * Ey, out=data[0])
    np.subtract(wz * Ex, wx * Ez, out=data[1])
    np.subtract(wx * Ey, wy * Ex, out=data[2])
    return _grad_csr_data(data.reshape(-1), F, n_vertices)


def _grad_csr(g: np.ndarray, F: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """Assemble per-face corner gradients g (#F, 3 corners, 3 coords) into the igl.grad layout."""
    return _grad_csr_data(g.transpose(2, 0, 1).reshape(-1), F, n_vertices)


def _grad_csr_data(data: np.ndarray, F: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """CSR from values laid out (coordinate, face, corner)."""
    nf = F.shape[0]
    # Row k*#F + f holds exactly the three corners of face f: build CSR directly (no COO sort).
    indices = np.tile(F.reshape(-1), 3)
    indptr = np.arange(0, 9 * nf + 1, 3, dtype=np.int64)
    return sp.csr_matrix((data, indices, indptr), shape=(3 * nf, n_vertices))


def grad_mollified(P: np.ndarray, l_face: np.ndarray, F: np.ndarray, n_vertices: int):
    """FEM gradient of the *mollified* metric, placed in each face's local camera-frame plane.

    Used when mollification changed the lengths (near-degenerate faces): each face is laid out
    in 2D from its mollified lengths ``l`` (corner 0 at the origin, corner 1 on the x axis), the
    hat-function gradients are taken there and mapped to 3D with the tangent frame of the local
    corners (``t1`` along p0->p1, ``t2 = n x t1``; an arbitrary frame where the corners are
    collinear).  Then ``G^T A G = -cotmatrix`` holds exactly with the mollified areas ``A``, which
    the heat method's gradient / divergence / Poisson steps need to agree.
    """
    # 2D layout from the lengths (Kahan's area: sqrt(l1^2 - x^2) cancels badly for the needles
    # mollification is for)
    dbl = double_areas(l_face)
    q = layout(l_face)
    e = q[:, [2, 0, 1]] - q[:, [1, 2, 0]]  # edge opposite each corner, counter-clockwise
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(dbl > 0, 1.0 / dbl, 0.0)
    g2 = np.stack([-e[..., 1], e[..., 0]], axis=-1) * inv[:, None, None]  # rotate by +90 deg
    # tangent frame of the local corners
    t1 = P[:, 1] - P[:, 0]
    n1 = np.linalg.norm(t1, axis=1)
    t1 = np.where(n1[:, None] > 0, t1 / np.where(n1 > 0, n1, 1.0)[:, None], [1.0, 0.0, 0.0])
    n = face_normals(P)
    t2 = np.cross(n, t1)
    n2 = np.linalg.norm(t2, axis=1)
    bad = n2 < 1e-12  # normal parallel to t1 (collinear corners): any perpendicular will do
    if bad.any():
        alt = np.cross(t1[bad], [0.0, 0.0, 1.0])
        alt[np.linalg.norm(alt, axis=1) < 1e-12] = [0.0, 1.0, 0.0]
        t2[bad] = alt
        n2 = np.linalg.norm(t2, axis=1)
    t2 = t2 / n2[:, None]
    g = g2[..., :1] * t1[:, None, :] + g2[..., 1:] * t2[:, None, :]
    return _grad_csr(g, F, n_vertices)


def grad_intrinsic(l_face: np.ndarray, F: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """FEM gradient (#F*2, #V) of an intrinsic mesh, each face in its own 2D frame.

    Face ``f`` is laid out by :func:`meschers_igl.intrinsic.layout` (corner 0 at the origin,
    corner 1 on the x axis); rows are blocked x then y like ``igl.grad``.  The per-face frames
    differ, which is harmless for the heat method (it uses ``|G u|`` and ``G^T A X`` with ``X``
    in the same frames); ``G^T A G = -cotmatrix_intrinsic(l, F)`` holds exactly.  Equal to
    ``igl.grad`` on the laid-out triangle soup gathered back to vertices, without the soup.
    """
    q = layout(l_face)
    dbl = double_areas(l_face)
    e = q[:, [2, 0, 1]] - q[:, [1, 2, 0]]  # edge opposite each corner, counter-clockwise
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(dbl > 0, 1.0 / dbl, 0.0)
    g = np.stack([-e[..., 1], e[..., 0]], axis=0) * inv[None, :, None]  # rotate by +90 deg
    nf = F.shape[0]
    indices = np.tile(np.asarray(F, dtype=np.int64).reshape(-1), 2)
    indptr = np.arange(0, 6 * nf + 1, 3, dtype=np.int64)
    return sp.csr_matrix((g.reshape(-1), indices, indptr), shape=(2 * nf, n_vertices))


def intrinsic_operators(
    l_face: np.ndarray, F: np.ndarray, n_vertices: int
) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix, np.ndarray]:
    """``L, M, G, area`` of the intrinsic mesh ``(l, F)`` with ``n_vertices`` vertices.

    ``L = igl.cotmatrix_intrinsic`` (negative semi-definite), ``M = igl.massmatrix_intrinsic``
    (Voronoi), ``G`` from :func:`grad_intrinsic` (#F*2 rows) and the Kahan face areas; all
    sized ``n_vertices`` even when the last vertices are unused (libigl sizes by ``F.max()+1``).
    """
    F = np.ascontiguousarray(F, dtype=np.int64)
    L = sp.csr_matrix(cotmatrix(l_face, F))
    M = sp.csr_matrix(massmatrix(l_face, F))
    if L.shape[0] < n_vertices:
        L.resize((n_vertices, n_vertices))
        M.resize((n_vertices, n_vertices))
    area = 0.5 * double_areas(l_face)
    return L, M, grad_intrinsic(l_face, F, n_vertices), area


def face_normals(P: np.ndarray) -> np.ndarray:
    """(#F, 3) unit normals of the local corners; zero-area faces get ``(0, 0, 1)``."""
    N = face_cross(P)
    n = np.linalg.norm(N, axis=1)
    out = np.zeros_like(N)
    out[:, 2] = 1.0
    ok = n > 0
    out[ok] = N[ok] / n[ok, None]
    return out


def vertex_normals(P: np.ndarray, F: np.ndarray, n_vertices: int) -> np.ndarray:
    """(#V, 3) area-weighted unit vertex normals from the faces' local frames.

    Face normals are invariant to each face's depth translation, so averaging them across
    faces is meaningful although the faces share no global embedding.
    """
    N = face_cross(P)  # 2A * n: area weighting for free
    acc = np.zeros((n_vertices, 3))
    for k in range(3):  # three coordinates, not a loop over faces
        acc[:, k] = np.bincount(F.reshape(-1), weights=np.repeat(N[:, k], 3), minlength=n_vertices)
    n = np.linalg.norm(acc, axis=1)
    out = np.zeros_like(acc)
    out[:, 2] = 1.0
    ok = n > 0
    out[ok] = acc[ok] / n[ok, None]
    return out
