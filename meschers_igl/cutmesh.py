"""Meschers from "cut" 3D models (paper Section 3.5).

Artists build impossible figures as ordinary 3D models that are *cut* somewhere: the two sides
of the cut lie at different depths but coincide on screen, so the picture from one view looks
closed.  Gluing the cut back (identifying the boundary vertices that coincide on screen) gives a
surface whose edges carry the depth differences of the model; around a loop through the cut
they no longer sum to zero, which is exactly a mescher's harmonic part.

Gluing is done loop by loop: every cut face of a real model contains the view direction, so two
of its corners share a screen point and pairing vertices by screen position alone is ambiguous.
Two boundary loops are glued when a cyclic correspondence makes every pair coincide on screen;
among such correspondences the one that is a single translation along the view direction wins
(the cut loop and its copy differ by the depth gap, the same at every vertex).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from .errors import MescherError, MescherWarning
from .operators import view_frame
from .topology import boundary_loops, edge_topology, half_edges
from .validate import as_faces, as_int_array, as_points, as_positive

#: default gluing tolerance, relative to the bounding-box diagonal of the model: float32
#: coordinates are off by ~1e-7 of the model's size, so 1e-5 leaves a 100x margin, and whole
#: loops must match, so short edges (1.4e-5 in penrose_triangle_block) cannot confuse it.
DEFAULT_RELATIVE_TOL = 1e-5


@dataclass(frozen=True)
class LoopPairing:
    """How two boundary loops were glued.

    Attributes
    ----------
    loop_a, loop_b : (n,) int64
        Input vertices of the two loops, ``loop_a[i]`` glued to ``loop_b[i]``.
    screen_residual : float
        Largest screen distance between glued vertices.
    depth_gap : float
        Median depth difference ``depth(loop_a) - depth(loop_b)``.
    translation_residual : float
        Largest deviation from that common depth gap (0 for a translation along the view).
    """

    loop_a: np.ndarray
    loop_b: np.ndarray
    screen_residual: float
    depth_gap: float
    translation_residual: float


def camera_coordinates(V: np.ndarray, view=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """(#V, 3) camera coordinates ``V @ R.T``: screen x, screen y, depth toward the viewer."""
    return V @ view_frame(view, up).T


def _loop_candidates(
    a: np.ndarray, b: np.ndarray, xy: np.ndarray, depth: np.ndarray, tol: float
) -> list[tuple[tuple[bool, bool, float], LoopPairing]]:
    """Every cyclic correspondence of loops ``a`` and ``b`` that coincides on screen.

    Anchored at ``a[0]``: only the few vertices of ``b`` within ``tol`` of it on screen can be its
    partner, so this costs O(n k) with k such vertices instead of O(n^2).  Each candidate comes
    with a sort key (not a translation, orientation reversed, translation residual).
    """
    n = a.size
    anchors = np.flatnonzero(np.linalg.norm(xy[b] - xy[a[0]], axis=1) <= tol)
    out = []
    i = np.arange(n)
    for j in anchors.tolist():  # a handful of anchors per loop pair
        # direction -1 traverses b against a: the orientation-compatible gluing of two boundaries
        for direction in (-1, 1):
            bb = b[(j + direction * i) % n]
            res = float(np.max(np.linalg.norm(xy[a] - xy[bb], axis=1)))
            if res > tol:
                continue
            gaps = depth[a] - depth[bb]
            gap = float(np.median(gaps))
            tres = float(np.max(np.abs(gaps - gap)))
            key = (tres > tol, direction == 1, tres)
            out.append((key, LoopPairing(a, bb, res, gap, tres)))
    return out


def pair_boundary_loops(
    F: np.ndarray, xy: np.ndarray, depth: np.ndarray, tol: float
) -> tuple[list[LoopPairing], list[np.ndarray]]:
    """Pair the boundary loops of a cut model whose screen projections coincide.

    Parameters
    ----------
    F : (#F, 3) int64
        Oriented triangles of the cut model.
    xy : (#V, 2) float64
        Screen positions.
    depth : (#V,) float64
        Depth toward the viewer.
    tol : float
        Absolute screen (and depth-translation) tolerance.

    Returns
    -------
    pairings : list of LoopPairing
    unpaired : list of (n,) int64
        Loops left as boundary.

    Raises
    ------
    MescherError
        When a loop coincides on screen with more than one other loop equally well, or when an
        unpaired loop still has vertices that coincide on screen with other boundary vertices
        (no consistent pairing of whole loops exists).
    """
    loops = boundary_loops(F)
    if not loops:
        return [], []
    sizes = np.array([lp.size for lp in loops])
    # Loops that coincide vertex by vertex have centroids within tol of each other.
    centroids = np.stack([xy[lp].mean(axis=0) for lp in loops])
    pairs = cKDTree(centroids).query_pairs(tol * (1.0 + 1e-9), output_type="ndarray")
    cands: list[tuple[tuple[bool, bool, float], int, int, LoopPairing]] = []
    for p, q in pairs.tolist():  # over candidate loop pairs, few
        if sizes[p] != sizes[q]:
            continue
        for key, pairing in _loop_candidates(loops[p], loops[q], xy, depth, tol):
            cands.append((key, p, q, pairing))
    cands.sort(key=lambda c: c[0])
    used: dict[int, tuple] = {}
    chosen: list[LoopPairing] = []
    for key, p, q, pairing in cands:
        if p in used or q in used:
            # A loop matching a second, different loop just as well (same kind of match) means
            # the data are ambiguous; a worse kind of match is simply not taken.
            other = used.get(p) or used.get(q)
            if other[0] == key[:2] and other[1] != {p, q}:
                raise MescherError(
                    f"F: expected each cut loop to coincide on screen with one other loop, found "
                    f"loops through vertices {loops[p][:6].tolist()} and {loops[q][:6].tolist()} "
                    "matching as well as an earlier pair; the gluing is ambiguous, pass "
                    "merge=[(i, j), ...] explicitly"
                )
            continue
        used[p] = used[q] = (key[:2], {p, q})
        chosen.append(pairing)
    unpaired = [loops[k] for k in range(len(loops)) if k not in used]
    if unpaired:
        _check_unpaired(unpaired, loops, used, xy, tol)
    return chosen, unpaired


def _check_unpaired(
    unpaired: list[np.ndarray],
    loops: list[np.ndarray],
    used: dict[int, tuple],
    xy: np.ndarray,
    tol: float,
) -> None:
    """Refuse when a loop left open still touches other boundary vertices on screen."""
    label = np.concatenate([np.full(lp.size, k) for k, lp in enumerate(loops)])
    verts = np.concatenate(loops)
    tree = cKDTree(xy[verts])
    open_ids = {id(lp) for lp in unpaired}
    for k, lp in enumerate(loops):
        if id(lp) not in open_ids:
            continue
        hits = tree.query_ball_point(xy[lp], tol)
        others = {int(verts[h]) for hh in hits for h in hh if label[h] != k}
        if others:
            raise MescherError(
                f"F: expected the cut loop through vertices {lp[:8].tolist()}"
                f"{'...' if lp.size > 8 else ''} to match another boundary loop vertex by vertex "
                f"on screen, found only partial coincidences (with vertices "
                f"{sorted(others)[:8]}); no consistent pairing of whole loops exists, pass "
                "merge=[(i, j), ...] explicitly or a different tol"
            )


def _merge_map(n: int, pairs: np.ndarray, used: np.ndarray) -> np.ndarray:
    """Union of vertex pairs: (n,) mescher index per input vertex, -1 when unreferenced.

    Labels follow the smallest input index of each group, so an unglued model keeps its order.
    """
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = csgraph.connected_components(A, directed=False)
    first = np.full(labels.max() + 1, n, dtype=np.int64)
    np.minimum.at(first, labels, np.arange(n))
    keep = np.zeros(labels.max() + 1, dtype=bool)
    keep[labels[used]] = True
    order = np.argsort(first, kind="stable")
    new = np.full(labels.max() + 1, -1, dtype=np.int64)
    kept = order[keep[order]]
    new[kept] = np.arange(kept.size)
    return new[labels]


def _group_names(vmap: np.ndarray, g: np.ndarray) -> str:
    groups = [np.flatnonzero(vmap == int(x)).tolist() for x in np.unique(g)]
    return ", ".join(str(s) for s in groups)


def check_gluing(F: np.ndarray, vmap: np.ndarray) -> np.ndarray:
    """Glued faces ``vmap[F]``, refusing merges that break the surface.

    Raises
    ------
    MescherError
        Naming the input vertices glued together, when a face collapses, an edge gets more than
        two faces, two faces traverse an edge the same way (non-orientable), or a vertex's faces
        stop forming a single fan (non-manifold vertex).
    """
    Fg = vmap[F]
    deg = (Fg[:, 0] == Fg[:, 1]) | (Fg[:, 1] == Fg[:, 2]) | (Fg[:, 2] == Fg[:, 0])
    if deg.any():
        f = int(np.flatnonzero(deg)[0])
        raise MescherError(
            f"merge: expected glued vertices of distinct corners, found face {f} = "
            f"{F[f].tolist()} collapsing (glued groups: {_group_names(vmap, Fg[f])})"
        )
    n = int(Fg.max()) + 1
    # Only faces touching a glued vertex can change: check those alone (cheap on big models).
    glued = np.flatnonzero(np.bincount(vmap[vmap >= 0], minlength=n) > 1)
    if glued.size == 0:
        return Fg
    is_glued = np.zeros(n, dtype=bool)
    is_glued[glued] = True
    Fs = Fg[is_glued[Fg].any(axis=1)]
    tail, head = half_edges(Fs)
    t, h = tail.reshape(-1), head.reshape(-1)
    directed = t * np.int64(n) + h
    undirected = np.minimum(t, h) * np.int64(n) + np.maximum(t, h)
    uk, cnt = np.unique(undirected, return_counts=True)
    if cnt.max() > 2:
        k = uk[np.argmax(cnt)]
        raise MescherError(
            "merge: expected a manifold surface after gluing, found edge "
            f"{[int(k // n), int(k % n)]} in {int(cnt.max())} faces (glued input vertices: "
            f"{_group_names(vmap, [k // n, k % n])})"
        )
    dk, dcnt = np.unique(directed, return_counts=True)
    if dcnt.max() > 1:
        k = dk[np.argmax(dcnt)]
        raise MescherError(
            "merge: expected an orientable surface after gluing (each edge traversed once each "
            f"way), found edge {[int(k // n), int(k % n)]} traversed twice the same way; "
            f"glued input vertices: {_group_names(vmap, [k // n, k % n])}"
        )
    ok = igl.is_vertex_manifold(Fs)
    bad = np.flatnonzero(~ok[glued])
    if bad.size:
        g = glued[bad]
        raise MescherError(
            "merge: expected a manifold surface after gluing, found "
            f"{bad.size} vertex(es) where separate fans meet (glued input vertices: "
            f"{_group_names(vmap, g[:4])})"
        )
    return Fg


def _check_merge(merge: Any, n: int, xy: np.ndarray, tol: float) -> np.ndarray:
    pairs = as_int_array(merge, "merge", 2, 2)
    if pairs.size and (pairs.min() < 0 or pairs.max() >= n):
        raise MescherError(
            f"merge: expected vertex indices in [0, {n}), found {int(pairs.min())}.."
            f"{int(pairs.max())}"
        )
    if np.any(pairs[:, 0] == pairs[:, 1]):
        k = int(np.flatnonzero(pairs[:, 0] == pairs[:, 1])[0])
        raise MescherError(f"merge: expected pairs of distinct vertices, found {pairs[k].tolist()}")
    dist = np.linalg.norm(xy[pairs[:, 0]] - xy[pairs[:, 1]], axis=1)
    if np.any(dist > tol):
        k = int(np.argmax(dist))
        raise MescherError(
            f"merge: expected pairs that coincide on screen (within {tol:.3g}), found pair "
            f"{pairs[k].tolist()} {dist[k]:.3g} apart"
        )
    return pairs


def glue_cut_mesh(
    V: Any,
    F: Any,
    view=(0.0, 0.0, 1.0),
    up=(0.0, 1.0, 0.0),
    tol: float | None = None,
    merge: Any = None,
) -> dict:
    """Glue a cut model without building the mescher (the geometric half of
    :func:`cut_mesh_arrays`).

    Returns
    -------
    dict with ``F`` (#F, 3) glued faces, ``xy`` (#Vm, 2), ``vmap`` (#V,), ``camera`` (#V, 3)
    camera coordinates of the input, ``pairings`` (list of LoopPairing, empty with ``merge``),
    ``unpaired`` (boundary loops left open) and ``tol`` (the absolute tolerance used).
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", n_vertices=V.shape[0])
    C = camera_coordinates(V, view, up)
    xy, depth = C[:, :2], C[:, 2]
    used = np.unique(F)
    diag = float(np.linalg.norm(V[used].max(axis=0) - V[used].min(axis=0)))
    if diag == 0.0:
        raise MescherError("V: expected vertices spanning a non-empty box, found a single point")
    rel = DEFAULT_RELATIVE_TOL if tol is None else as_positive(tol, "tol")
    tol_abs = rel * diag
    n = V.shape[0]
    pairings: list[LoopPairing] = []
    unpaired: list[np.ndarray] = []
    if merge is None:
        pairings, unpaired = pair_boundary_loops(F, xy, depth, tol_abs)
        if pairings:
            pairs = np.concatenate(
                [np.stack([p.loop_a, p.loop_b], axis=1) for p in pairings], axis=0
            )
        else:
            pairs = np.zeros((0, 2), dtype=np.int64)
    else:
        pairs = _check_merge(merge, n, xy, tol_abs)
    vmap = _merge_map(n, pairs, used)
    Fg = check_gluing(F, vmap)
    nm = int(vmap.max()) + 1
    cnt = np.bincount(vmap[used], minlength=nm)
    xy_g = np.stack(
        [np.bincount(vmap[used], weights=xy[used, k], minlength=nm) / cnt for k in range(2)],
        axis=1,
    )
    return {
        "F": Fg,
        "xy": xy_g,
        "vmap": vmap,
        "camera": C,
        "pairings": pairings,
        "unpaired": unpaired,
        "tol": tol_abs,
    }


def edge_depth_differences(
    F_input: np.ndarray, depth: np.ndarray, face_edges: np.ndarray, signs: np.ndarray, n_edges: int
) -> tuple[np.ndarray, float]:
    """Average per-face depth differences onto edges.

    ``zeta[e]`` is the mean over the faces containing ``e`` of ``depth(head) - depth(tail)``
    measured with each face's own (input) corners, so glued edges average their two sides.

    Returns
    -------
    zeta : (#E,) float64
    conflict : float
        Largest deviation of a face's value from the edge mean (0 for a gluing by a translation).
    """
    tail, head = half_edges(F_input)
    val = signs * (depth[head] - depth[tail])  # in the stored edge direction
    fe = face_edges.reshape(-1)
    cnt = np.bincount(fe, minlength=n_edges)
    zeta = np.bincount(fe, weights=val.reshape(-1), minlength=n_edges) / np.maximum(cnt, 1)
    conflict = float(np.max(np.abs(val.reshape(-1) - zeta[fe]), initial=0.0))
    return zeta, conflict


@dataclass(frozen=True)
class CutMeshArrays:
    """A glued cut model as the arrays of a mescher (:meth:`Mescher.from_cut_mesh` builds it).

    Attributes
    ----------
    F : (#F, 3) int64
        Glued faces; face ``i`` is input face ``i``.
    xy : (#Vm, 2) float64
        Screen positions of the glued vertices.
    edges : (#E, 2) int64
        Canonical edges of ``F``.
    zeta : (#E,) float64
        Depth differences averaged over the faces of each edge; not yet projected onto
        locally integrable forms.
    vmap : (#V,) int64
        Mescher vertex of each input vertex (-1 for vertices no face uses).
    conflict : float
        Largest disagreement of a face's depth difference from its edge's average.
    """

    F: np.ndarray
    xy: np.ndarray
    edges: np.ndarray
    zeta: np.ndarray
    vmap: np.ndarray
    conflict: float


def cut_mesh_arrays(
    V: Any,
    F: Any,
    view=(0.0, 0.0, 1.0),
    up=(0.0, 1.0, 0.0),
    tol: float | None = None,
    merge: Any = None,
) -> CutMeshArrays:
    """The arrays of the mescher of a cut 3D model seen from ``view`` (see
    :meth:`meschers_igl.Mescher.from_cut_mesh`, which projects ``zeta`` and builds it).

    Warns (:class:`MescherWarning`) when glued edges disagree on their depth difference by more
    than 1e-3 of the model's size: the gluing was not a translation along the view.
    """
    g = glue_cut_mesh(V, F, view=view, up=up, tol=tol, merge=merge)
    F_in = as_faces(F, "F")
    depth = g["camera"][:, 2]
    edges, face_edges, signs = edge_topology(g["F"], g["xy"].shape[0])
    zeta, conflict = edge_depth_differences(F_in, depth, face_edges, signs, edges.shape[0])
    scale = float(np.ptp(depth)) + float(np.ptp(g["xy"]))
    if conflict > 1e-3 * scale:
        # Gluing by something other than a translation along the view direction: allowed
        # (averaged and projected), but the user should know the depths were changed.
        warnings.warn(
            f"from_cut_mesh: glued edges disagree on their depth difference by up to "
            f"{conflict:.3g}; averaged and projected onto locally integrable forms",
            MescherWarning,
            stacklevel=3,
        )
    return CutMeshArrays(g["F"], g["xy"], edges, zeta, g["vmap"], conflict)


__all__ = [
    "CutMeshArrays",
    "LoopPairing",
    "camera_coordinates",
    "check_gluing",
    "cut_mesh_arrays",
    "edge_depth_differences",
    "glue_cut_mesh",
    "pair_boundary_loops",
]
