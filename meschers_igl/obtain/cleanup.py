"""Clean-up of a model before it is seen: vertices welded, contact faces dropped, each part
oriented outward (``igl.bfs_orient``, signed volume with holes capped), notes on pinches and
non-manifold edges."""

from __future__ import annotations

import warnings

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from ..errors import MescherWarning
from .records import ConversionReport


# ------------------------------------------------------------------------------ clean-up
def weld(V: np.ndarray, F: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Merge vertices closer than ``tol`` in 3D (STL soups) and drop faces that collapse.

    Returns
    -------
    V : (#V', 3), F : (#F', 3), n_merged : int
    """
    pairs = cKDTree(V).query_pairs(tol, output_type="ndarray")
    n = V.shape[0]
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    k, lab = csgraph.connected_components(A, directed=False)
    cnt = np.bincount(lab, minlength=k)
    Vw = np.stack([np.bincount(lab, weights=V[:, c], minlength=k) / cnt for c in range(3)], 1)
    Fw = lab[F]
    ok = (Fw[:, 0] != Fw[:, 1]) & (Fw[:, 1] != Fw[:, 2]) & (Fw[:, 2] != Fw[:, 0])
    used = np.unique(Fw[ok])
    new = np.full(k, -1, dtype=np.int64)
    new[used] = np.arange(used.size)
    return Vw[used], new[Fw[ok]], n - k


def drop_repeated_faces(F: np.ndarray) -> tuple[np.ndarray, int]:
    """Keep one of each set of faces with the same corners in the same cyclic order.

    A part duplicated in place (a copy left where it was made) repeats every face with its
    orientation; :func:`drop_contact_faces` would take both copies for blocks touching face to
    face and remove the part.  Faces of opposite orientation are left to it.

    Returns
    -------
    F : (#F', 3) int64
        The first face of each repeated set kept, the input's order otherwise.
    n_repeats : int
        Faces removed.
    """
    if F.shape[0] == 0:
        return F, 0
    r = np.argmin(F, axis=1)  # each face from its smallest corner: its cyclic order kept
    R = np.take_along_axis(F, (r[:, None] + np.arange(3)) % 3, axis=1)
    _, first = np.unique(R, axis=0, return_index=True)
    return F[np.sort(first)], F.shape[0] - first.size


def drop_contact_faces(F: np.ndarray) -> tuple[np.ndarray, int]:
    """Remove faces whose vertex set appears more than once (two blocks touching face to face).

    Returns
    -------
    F : (#F', 3) int64, n_pairs : int
    """
    S = np.sort(F, axis=1)
    n = np.int64(F.max(initial=0) + 1)
    key = (S[:, 0] * n + S[:, 1]) * n + S[:, 2]  # one int64 per vertex set (n < 2e6)
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    dup = cnt[inv.reshape(-1)] > 1
    return F[~dup], int(np.count_nonzero(dup)) // 2


def open_faces(F: np.ndarray) -> np.ndarray:
    """(#F,) bool: faces with an edge no other face shares (one int64 key per edge)."""
    a = np.concatenate([F[:, 0], F[:, 1], F[:, 2]])
    b = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    n = np.int64(F.max(initial=0) + 1)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    return (cnt[inv] == 1).reshape(3, -1).any(axis=0)


def orient_outward(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, int, np.ndarray]:
    """Consistent orientation per connected part; closed parts outward by their signed volume.

    ``igl.bfs_orient`` makes each part coherent; a *closed* part whose signed volume
    ``sum det(v0, v1, v2) / 6`` is negative is flipped (an open part has no inside: the caller
    turns it toward the viewer).

    Returns
    -------
    F : (#F, 3) int64
    n_flipped_faces : int
        Faces whose orientation changed.
    part : (#F,) int64
        Connected part of each face.
    """
    Fo, comp = igl.bfs_orient(F)
    Fo = np.asarray(Fo, dtype=np.int64)
    comp = np.asarray(comp).reshape(-1).astype(np.int64)
    T = V[Fo]
    vol6 = np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2]))
    k = int(comp.max()) + 1
    vol = np.bincount(comp, weights=vol6, minlength=k)
    # a part is closed when every edge has two faces; an open part that is nearly closed (a
    # solid with a small hole: a cut box, a face lost in a repair) is oriented by the volume
    # it encloses with its holes capped
    open_face = open_faces(Fo)
    is_open = np.bincount(comp, weights=open_face, minlength=k) > 0
    solid = solid_like_parts(V, Fo, comp)
    vol = vol + _cap_volumes(V, Fo, comp, k)
    flip = (vol[comp] < 0) & (~is_open | solid)[comp]
    Fo[flip] = Fo[flip][:, [0, 2, 1]]
    changed = int(np.count_nonzero(np.any(Fo != F, axis=1)))
    return Fo, changed, comp


def _cap_volumes(V: np.ndarray, F: np.ndarray, comp: np.ndarray, k: int) -> np.ndarray:
    """(k,) six times the signed volume of fans closing each part's boundary loops (0 for a
    closed part): a fan from a loop's centroid traverses each boundary edge against its face."""
    from ..topology import boundary_loops

    out = np.zeros(k)
    if not open_faces(F).any():
        return out
    vpart = np.zeros(int(F.max()) + 1, dtype=np.int64)
    vpart[F.reshape(-1)] = np.repeat(comp, 3)
    for loop in boundary_loops(F):  # one per hole, few
        c = V[loop].mean(axis=0)
        a, b = V[loop], V[np.roll(loop, -1)]
        out[vpart[loop[0]]] += np.einsum("j,ij->", c, np.cross(b, a))
    return out


def solid_like_parts(V: np.ndarray, F: np.ndarray, comp: np.ndarray) -> np.ndarray:
    """(#parts,) bool: parts that enclose a volume once their holes are capped -- isoperimetric
    quotient ``36 pi vol^2 / area^3`` above 0.05 (a cube: 0.52; a sheet or a relief: ~0)."""
    k = int(comp.max()) + 1
    T = V[F]
    vol = (
        np.bincount(
            comp, weights=np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2])), minlength=k
        )
        + _cap_volumes(V, F, comp, k)
    ) / 6.0
    area = 0.5 * np.bincount(
        comp,
        weights=np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1),
        minlength=k,
    )
    return 36.0 * np.pi * vol**2 > 0.05 * np.maximum(area, 1e-300) ** 3


def manifold_notes(F: np.ndarray, report: ConversionReport) -> None:
    """Report non-manifold edges (more than two faces) and edges two faces traverse the same
    way after orientation (a non-orientable part, e.g. a Moebius strip): the visible map does
    not need the model to be a manifold, so these are noted, not refused."""
    a = np.concatenate([F[:, 0], F[:, 1], F[:, 2]])
    b = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    n = np.int64(F.max(initial=0) + 1)
    _, cnt = np.unique(np.minimum(a, b) * n + np.maximum(a, b), return_counts=True)
    _, dcnt = np.unique(a * n + b, return_counts=True)
    msgs = []
    if np.any(cnt > 2):
        msgs.append(f"{int(np.count_nonzero(cnt > 2))} non-manifold edge(s) (in 3+ faces)")
    if np.any(dcnt > 1):
        msgs.append(
            f"{int(np.count_nonzero(dcnt > 1))} edge(s) traversed the same way by two faces "
            "(a non-orientable part)"
        )
    for msg in msgs:
        full = f"{msg}: each face is seen on its own side; repair the file to glue them"
        report.warnings.append(full)
        warnings.warn(f"see_model: {full}", MescherWarning, stacklevel=3)


def pinch_warning(F: np.ndarray, report: ConversionReport) -> None:
    ok = np.asarray(igl.is_vertex_manifold(F)).reshape(-1)
    bad = np.flatnonzero(~ok.astype(bool))
    if bad.size:
        msg = (
            f"{bad.size} pinch vertex(es) where separate fans of faces meet (e.g. vertex "
            f"{bad[:4].tolist()}); each fan is treated as its own sheet"
        )
        report.warnings.append(msg)
        warnings.warn(f"see_model: {msg}", MescherWarning, stacklevel=3)
