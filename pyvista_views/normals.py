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
    F: np.ndarray, face_normals: np.ndarray, weights: np.ndarray, feature_angle: float
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

    Returns
    -------
    groups : (#F, 3) int64
        Group of each corner.
    group_vertex : (#G,) int64
        Vertex of each group.
    group_normals : (#G, 3) float64
        Unit normals (``(0, 0, 1)`` for a degenerate group).
    """
    F = np.ascontiguousarray(F, dtype=np.int64)
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
    h1, h2, f2 = h1[smooth], h2[smooth], f2[smooth]
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
    n_groups, labels = csgraph.connected_components(graph, directed=False)
    groups = labels.reshape(nf, 3).astype(np.int64)
    group_vertex = np.empty(n_groups, dtype=np.int64)
    group_vertex[labels] = F.reshape(-1)
    wn = face_normals * np.asarray(weights, dtype=np.float64)[:, None]
    acc = np.zeros((n_groups, 3))
    for k in range(3):  # three coordinates, not a loop over faces
        acc[:, k] = np.bincount(labels, weights=np.repeat(wn[:, k], 3), minlength=n_groups)
    norm = np.linalg.norm(acc, axis=1)
    normals = np.zeros_like(acc)
    normals[:, 2] = 1.0
    ok = norm > 0
    normals[ok] = acc[ok] / norm[ok, None]
    return groups, group_vertex, normals
