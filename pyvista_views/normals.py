"""Shading normals split at a feature angle: smooth surfaces stay smooth, boxes stay crisp.

Smooth shading interpolates one normal per vertex.  At a crease (a box's edge) the averaged
normal belongs to neither side, so the shade blurs across every face touching the crease and a
quad split into two triangles gets a false diagonal.  As PyVista's ``compute_normals
(feature_angle=...)`` and ``igl.per_corner_normals`` do for real meshes, the corners around a
vertex are grouped through the edges whose dihedral angle is below the feature angle, and each
group gets its own area-weighted normal: across a sharp edge the normals are not shared.

For a mescher the dihedral angles come from the face normals of its local frames
(``m.face_normals()``, derived from zeta), which are well defined although the faces share no
global embedding; the same code serves real meshes with their own face normals.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from meschers_igl.errors import MescherError
from meschers_igl.jit import kernel

__all__ = ["DEFAULT_FEATURE_ANGLE", "corner_groups", "as_feature_angle"]

#: Dihedral angle (degrees) above which an edge is a crease (PyVista's default).
DEFAULT_FEATURE_ANGLE = 30.0


def as_feature_angle(angle: object) -> float:
    """A feature angle in degrees in ``[0, 180]`` (``None``: 180, nothing split)."""
    if angle is None:
        return 180.0
    try:
        a = float(angle)
    except (TypeError, ValueError):
        raise MescherError(
            f"feature_angle: expected degrees in [0, 180] or None, found {angle!r}"
        ) from None
    if not (0.0 <= a <= 180.0):
        raise MescherError(f"feature_angle: expected degrees in [0, 180] or None, found {a}")
    return a


def corner_groups(
    F: np.ndarray,
    face_normals: np.ndarray,
    weights: np.ndarray,
    feature_angle: float,
    vertex_normals: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Corners grouped around each vertex through smooth edges, with one normal per group.

    Two faces sharing an edge are joined at its two end vertices when the angle between their
    normals is below ``feature_angle``; a group is a connected set of corners of one vertex.
    The group's normal is ``sum w_f n_f`` over its corners, normalised (area weights give the
    usual vertex normal when nothing is split).

    Parameters
    ----------
    F : (#F, 3) int64
    face_normals : (#F, 3) float64
        Unit normals.
    weights : (#F,) float64
        Per-face weights (areas).
    feature_angle : float
        Degrees; 180 joins every edge (plain vertex normals), 0 none (flat).
    vertex_normals : (#V, 3) float64, optional
        The ``weights``-weighted unit vertex normals if already known (a mescher caches its
        own); computed otherwise.

    Returns
    -------
    groups : (#F, 3) int64
        Group of each corner (``F`` itself when nothing is split).
    group_vertex : (#G,) int64
        Vertex of each group (#G >= #V; when nothing is split anywhere, group ``v`` is
        vertex ``v``).
    group_normals : (#G, 3) float64
        Unit normals (``(0, 0, 1)`` for a degenerate group).
    """
    F = np.ascontiguousarray(F, dtype=np.int64)
    face_normals = np.asarray(face_normals, dtype=np.float64)
    nv = int(F.max(initial=-1)) + 1
    weights = np.asarray(weights, dtype=np.float64)
    if vertex_normals is None:
        wn = face_normals * weights[:, None]
        vn = _unit(_accumulate(F.reshape(-1), np.repeat(wn, 3, axis=0), nv))
    else:
        vn = np.ascontiguousarray(vertex_normals, dtype=np.float64)
    if feature_angle >= 180.0:
        return F, np.arange(nv, dtype=np.int64), vn
    # A vertex whose faces all lie within half the feature angle of its normal has no crease
    # edge (two such faces are within the feature angle of each other): its corners form one
    # group, the vertex itself.  Only the faces around the other vertices are examined.
    half = np.cos(np.radians(0.5 * feature_angle)) - 1e-12
    # writeable copies: a read-only argument would compile (and cache) another specialisation
    rough = _rough_vertices(
        np.array(F, order="C"), np.array(face_normals, order="C"), np.array(vn, order="C"), half, nv
    )
    if not rough.any():
        return F, np.arange(nv, dtype=np.int64), vn
    wn = face_normals * weights[:, None]
    near = np.flatnonzero(rough[F].any(axis=1))
    sub = F[near]
    labels = _sub_groups(sub, face_normals[near], feature_angle)
    groups = F.copy()
    at_rough = rough[sub]
    n_sub = int(labels.max()) + 1
    groups[near] = np.where(at_rough, nv + labels.reshape(-1, 3), sub)
    group_vertex = np.concatenate([np.arange(nv, dtype=np.int64), np.zeros(n_sub, np.int64)])
    group_vertex[nv + labels.reshape(-1, 3)[at_rough]] = sub[at_rough]
    acc = np.zeros((nv + n_sub, 3))
    acc[:nv] = vn
    rough_c = at_rough.reshape(-1)
    acc[nv:] = _accumulate(labels[rough_c], np.repeat(wn[near], 3, axis=0)[rough_c], n_sub)
    normals = np.concatenate([vn, _unit(acc[nv:])])
    # number the groups in use only (a rough vertex's own id is replaced by its groups')
    used = np.zeros(nv + n_sub, dtype=bool)
    used[groups] = True
    remap = np.cumsum(used) - 1
    return remap[groups], group_vertex[used], normals[used]


@kernel()
def _rough_vertices(
    F: np.ndarray, N: np.ndarray, vn: np.ndarray, half: float, nv: int
) -> np.ndarray:
    # one pass over the corners without the (#F, 3, 3) gather numpy would need (5x faster at
    # 1M faces): a vertex is rough when one of its faces is more than half the feature angle
    # from its normal
    rough = np.zeros(nv, dtype=np.bool_)
    for f in range(F.shape[0]):
        for k in range(3):
            v = F[f, k]
            c = vn[v, 0] * N[f, 0] + vn[v, 1] * N[f, 1] + vn[v, 2] * N[f, 2]
            if c < half:
                rough[v] = True
    return rough


def _accumulate(index: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros((n, 3))
    for k in range(3):  # three coordinates, not a loop over faces
        out[:, k] = np.bincount(index, weights=values[:, k], minlength=n)
    return out


def _unit(acc: np.ndarray) -> np.ndarray:
    norm = np.linalg.norm(acc, axis=1)
    out = np.zeros_like(acc)
    out[:, 2] = 1.0
    ok = norm > 0
    out[ok] = acc[ok] / norm[ok, None]
    return out


def _sub_groups(F: np.ndarray, face_normals: np.ndarray, feature_angle: float) -> np.ndarray:
    """(3 #F,) connected groups of corners joined across smooth edges (corner graph)."""
    nf = F.shape[0]
    corner = np.arange(3 * nf).reshape(nf, 3)
    # half-edge (f, k): F[f, k] -> F[f, k+1]; an interior edge has two half-edges
    tail, head = F.reshape(-1), F[:, [1, 2, 0]].reshape(-1)
    key = np.minimum(tail, head) * (int(F.max(initial=0)) + 1) + np.maximum(tail, head)
    sort = np.argsort(key, kind="stable")
    same = key[sort[1:]] == key[sort[:-1]]
    h1, h2 = sort[:-1][same], sort[1:][same]
    f1, f2 = h1 // 3, h2 // 3
    cos = np.einsum("ij,ij->i", face_normals[f1], face_normals[f2])
    smooth = cos >= np.cos(np.radians(feature_angle)) - 1e-12
    h1, f2 = h1[smooth], f2[smooth]
    rows, cols = [], []
    for end in (0, 1):  # the edge's tail and head vertices
        c1 = (h1 // 3) * 3 + (h1 % 3 + end) % 3  # corner of f1 at that vertex
        v = F.reshape(-1)[c1]
        k2 = np.argmax(F[f2] == v[:, None], axis=1)  # the corner of f2 at the same vertex
        rows.append(c1)
        cols.append(corner[f2, k2])
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    n = 3 * nf
    graph = sp.coo_matrix((np.ones(rows.shape[0]), (rows, cols)), shape=(n, n))
    _, labels = csgraph.connected_components(graph, directed=False)
    return labels.astype(np.int64)
