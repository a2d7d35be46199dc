"""Any 3D model seen from a view: the surface the viewer sees, with its false edges glued.

Real models of impossible figures are closed solids, separate blocks or reliefs, not cut models
open along a seam.  What makes them look impossible from their view is a **false edge**: two
3D edges of the model that project onto the same screen segment and are parallel in 3D (so they
carry the same relative depth ``zeta``), but lie at different depths.  A person sees one edge --
a crease or a flat continuation -- where there are two.  This module builds what the viewer
sees, as arrays (the :class:`~meschers_igl.Mescher` is made from them by the caller, so there
is no import circle with :mod:`meschers_igl.mescher`):

1. **Clean-up**: vertices that coincide in 3D are welded (STL soups), degenerate faces dropped,
   each connected part oriented outward by its signed volume (``igl.bfs_orient`` first).
2. **Hidden-surface removal** from the orthographic view, exactly, by 2D polygon clipping:
   faces facing the viewer (``n_z > 0``) that overlap on screen
   (:func:`meschers_igl.geometry2d.overlapping_pairs`) are clipped by the faces in front of them
   with ``shapely`` (every overlay on a fixed ``grid_size`` grid so coordinates stay exact and
   shared); faces nobody overlaps are kept as they are (most faces of a large model).
3. **Visible map**: the clipped pieces are triangulated (constrained Delaunay, ``triangle``,
   no Steiner points), near-duplicate screen points merged, T-junctions split; each triangle's
   corner depths come from its *source face's plane*, so normals are the model's own.
4. **Gluing**: every screen edge shared by two triangles is either *continuous* (same depth on
   both sides: glued), a *false edge* (depth jump, parallel in 3D -- equal zeta -- and both sides
   end there on their own surface, i.e. the model's edge is a silhouette or boundary: glued
   crosswise, the depth gap becomes a period), or a *true occlusion* (kept apart; the far face
   gets a ``DepthOrder`` arc to the near one).
5. **Amodal completion** of hidden gaps: two occluded pieces of the same plane orientation that
   line up across an occluder (parallel chains, side lines parallel to their bar's edges, the
   strip between them hidden behind nearer faces) are bridged by faces of the same normal behind
   the occluder; their depth offset becomes a period.

**Keeping the hidden side** (``hidden="auto"``, the default, when junctions are found): the
whole model, not only what is visible, opened at its junctions and glued crosswise like a cut
model (:func:`close_junctions`).  A junction is a pair of *caps* -- planar patches bounded by
one loop, opposite normals, congruent by a translation (:func:`bar_end_pairs`): a false edge
when they coincide on screen (both contain the view), a hidden gap when they are the two ends
of a bar broken behind an occluder (the pieces line up on screen, the bridge between them runs
through empty space and is hidden).  The caps are removed, a hidden gap is bridged by a tube
continuing the first piece, and :func:`meschers_igl.cutmesh.glue_cut_mesh` glues the open
loops that coincide on screen; the order of overlapping faces comes from the model's own
depths.  The result is a closed surface like the cut-model path's (for a cut file it *is* the
cut-model path's), and loops that pass behind the model (the impossible cube's, behind a
corner) keep their period.

``view="auto"`` (:func:`find_model_view`): the view in which vertex pairs coincide
(:func:`meschers_igl.autoview.find_view`), or, for a hidden gap, the view on the circle of
views lining up its pieces that centres the occluder on the gap.

Returns plain arrays and a :class:`ConversionReport`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from scipy.spatial import cKDTree

from .errors import MescherError, MescherWarning
from .geometry2d import overlapping_pairs
from .operators import view_frame
from .validate import as_faces, as_points

__all__ = [
    "BarEnds",
    "ConversionReport",
    "Junction",
    "VisibleModel",
    "bar_end_pairs",
    "close_junctions",
    "find_model_view",
    "orient_outward",
    "see_model",
    "weld",
]

#: Relative tolerance (of the model's bounding-box diagonal) for screen coincidence and depth
#: continuity: float32 coordinates are off by ~1e-7 of the size; gaps of 1e-5 are noise.
REL_TOL = 1e-5
#: Grid of every shapely overlay, relative to the model's size (exact shared coordinates).
REL_GRID = 1e-9
#: A face faces the viewer when its unit normal has n_z above this (edge-on faces are hidden).
FRONT_NZ = 1e-6


@dataclass(frozen=True)
class Junction:
    """A glued false edge (a connected chain of screen edges) or a bridged hidden gap.

    Attributes
    ----------
    kind : str
        ``"false edge"`` (visible junction), ``"hidden gap"`` (amodal bridge across a depth
        offset) or ``"occluded continuation"`` (amodal bridge without offset).
    position : (2,) float
        Screen position (middle of the chain).
    depth_gap : float
        Depth of the far side minus the near side is ``-depth_gap``: the jump a loop through
        the junction gains, i.e. (up to sign and multiplicity) the period it creates.
    n_edges : int
        Screen edges in the chain.
    """

    kind: str
    position: np.ndarray
    depth_gap: float
    n_edges: int


@dataclass
class ConversionReport:
    """What :func:`see_model` found and did.

    Attributes
    ----------
    junctions : list of Junction
    n_arcs : int
        Depth-order arcs added (true occlusions and bridges behind their occluders).
    repairs : list of str
        Clean-up steps that changed the input (welds, flips, dropped faces).
    warnings : list of str
    snapped : (#F,) float or None
        ``perceive="manhattan"`` only: angle (radians) each mescher face's normal was snapped.
    view, up : (3,) float
        The view used (``view="auto"`` reports the one it found).
    source_face : (#F,) int64
        Input face (after clean-up) each mescher face comes from (-1 for bridge faces: the
        visible path's strips, the closed path's tubes).
    arcs : (k, 2) int64
        The depth-order arcs ``i -> j`` (face ``i`` behind face ``j``).
    cleanup : object or None
        A loader's clean-up report (``meshlab_filters`` puts its ``CleanupReport`` here).
    route : {"cut", "closed", "visible"}
        How the mescher was obtained: the cut model glued at its seam, the whole model opened
        at its junctions and glued crosswise, or the visible surface.
    reason : str
        Why that route was taken.
    """

    junctions: list = field(default_factory=list)
    n_arcs: int = 0
    repairs: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    snapped: np.ndarray | None = None
    arcs: np.ndarray | None = None
    view: np.ndarray | None = None
    up: np.ndarray | None = None
    source_face: np.ndarray | None = None
    cleanup: Any = None
    route: str = "visible"
    reason: str = ""

    def __str__(self) -> str:
        lines = [f"route: {self.route} ({self.reason})" if self.reason else f"route: {self.route}"]
        lines.append(f"view {np.round(self.view, 6).tolist()}, up {np.round(self.up, 6).tolist()}")
        for j in self.junctions:
            lines.append(
                f"{j.kind} at screen ({j.position[0]:.4g}, {j.position[1]:.4g}): depth gap "
                f"{j.depth_gap:.6g} over {j.n_edges} edge(s)"
            )
        lines.append(f"{self.n_arcs} depth-order arc(s)")
        if self.snapped is not None:
            lines.append(
                f"normals snapped to the perceived frame: max {np.degrees(self.snapped.max()):.3g}"
                f" deg, mean {np.degrees(self.snapped.mean()):.3g} deg"
            )
        if self.cleanup is not None:
            lines.append(f"clean-up: {self.cleanup}")
        lines += [f"repair: {r}" for r in self.repairs]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass
class VisibleModel:
    """Arrays of the visible surface (build the mescher with ``Mescher.from_corner_depths``).

    Attributes
    ----------
    F : (#F, 3) int64
        Oriented triangles (counter-clockwise on screen).
    xy : (#V, 2) float64
    Z : (#F, 3) float64
        Corner depths of each face, from its source face's plane (corner-wise, so faces on the
        two sides of a false edge disagree by the depth gap; their zeta agrees).
    arcs : (k, 2) int64
        Depth-order arcs ``i -> j``: face ``i`` behind face ``j``.
    report : ConversionReport
    """

    F: np.ndarray
    xy: np.ndarray
    Z: np.ndarray
    arcs: np.ndarray
    report: ConversionReport


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


def _open_faces(F: np.ndarray) -> np.ndarray:
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
    open_face = _open_faces(Fo)
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
    from .topology import boundary_loops

    out = np.zeros(k)
    if not _open_faces(F).any():
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
    vol = (np.bincount(comp, weights=np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2])),
                       minlength=k) + _cap_volumes(V, F, comp, k)) / 6.0  # fmt: skip
    area = 0.5 * np.bincount(
        comp,
        weights=np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1),
        minlength=k,
    )
    return 36.0 * np.pi * vol**2 > 0.05 * np.maximum(area, 1e-300) ** 3


# ------------------------------------------------------------------------------ planar map
def _planes(C: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(#F, 3) depth plane ``z = a x + b y + c`` of each (front-facing) face."""
    T = C[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    a = -n[:, 0] / n[:, 2]
    b = -n[:, 1] / n[:, 2]
    c = T[:, 0, 2] - a * T[:, 0, 0] - b * T[:, 0, 1]
    return np.stack([a, b, c], axis=1)


def _plane_depth(P: np.ndarray, pl: np.ndarray) -> np.ndarray:
    return pl[..., 0] * P[..., 0] + pl[..., 1] * P[..., 1] + pl[..., 2]


def _polygonal(g: np.ndarray) -> np.ndarray:
    """Keep the polygons of overlay results (grid snapping can leave collapsed lines or points
    in a collection, which the next overlay refuses as mixed-dimension)."""
    import shapely

    t = shapely.get_type_id(g)
    odd = np.flatnonzero((t != 3) & (t != 6) & ~shapely.is_empty(g))
    for k in odd.tolist():  # rare: only collections from degenerate overlaps
        parts = shapely.get_parts(g[k])
        parts = parts[np.isin(shapely.get_type_id(parts), (3, 6))]
        g[k] = shapely.union_all(parts) if parts.size else shapely.Polygon()
    return g


def _clip_occluded(T: np.ndarray, pl: np.ndarray, tol: float, grid: float):
    """Visible pieces of front faces: (pieces, involved) with pieces a list of (face, polygon).

    Faces overlapping nothing are not touched (``involved`` False) and stay exact.
    """
    import shapely

    pairs, cen = overlapping_pairs(T, tol, centroids=True)
    involved = np.zeros(T.shape[0], dtype=bool)
    if pairs.shape[0] == 0:
        return [], involved
    i, j = pairs[:, 0], pairs[:, 1]
    dz = _plane_depth(cen, pl[j]) - _plane_depth(cen, pl[i])
    # the farther face of each overlapping pair is clipped by the nearer one
    back = np.where(dz > 0, i, j)
    front = np.where(dz > 0, j, i)
    keep = (
        np.abs(dz) > tol
    )  # faces crossing in 3D at the overlap: leave to the z-order of centroids
    back, front = back[keep], front[keep]
    involved[i] = involved[j] = True
    # only faces that overlap something go through shapely (on the fixed grid)
    polys = np.empty(T.shape[0], dtype=object)
    inv_ids = np.flatnonzero(involved)
    polys[inv_ids] = shapely.set_precision(shapely.polygons(T[inv_ids]), grid)
    # visible part = face minus each face in front of it, one vectorised GEOS pass per rank
    # (the k-th occluder of every face at once): no Python loop over faces
    order = np.argsort(back, kind="stable")
    back, front = back[order], front[order]
    starts = np.flatnonzero(np.r_[True, back[1:] != back[:-1]])
    rank = np.arange(back.size) - np.repeat(starts, np.diff(np.r_[starts, back.size]))
    vis = polys.copy()
    for r in range(int(rank.max(initial=-1)) + 1):  # as many passes as the most occluders
        sel = rank == r
        b = back[sel]
        vis[b] = _polygonal(shapely.difference(vis[b], polys[front[sel]], grid_size=grid))
    pieces = [(int(f), vis[f]) for f in inv_ids.tolist()]
    return pieces, involved


def _triangulate_pieces(pieces, grid: float):
    """Constrained triangulation of the visible pieces: (P (n,2), tris (m,3), source (m,))."""
    import shapely
    import triangle as tr

    if not pieces:
        return np.zeros((0, 2)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    geoms = np.array([g for _, g in pieces], dtype=object)
    src = np.array([f for f, _ in pieces], dtype=np.int64)
    parts, idx = shapely.get_parts(geoms, return_index=True)
    polys_all = parts[shapely.get_type_id(parts) == 3]
    keepmask = shapely.area(polys_all) > grid * grid * 4
    polys = polys_all[keepmask]
    pidx = idx[shapely.get_type_id(parts) == 3][keepmask]
    if polys.size == 0:
        return np.zeros((0, 2)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    # node the boundaries on the grid (shapely splits crossing and overlapping segments), so
    # the triangulator gets a clean planar straight-line graph
    lines = shapely.union_all(shapely.boundary(polys), grid_size=grid)
    segs = shapely.get_parts(lines)
    coords, ridx = shapely.get_coordinates(segs, return_index=True)
    same = ridx[1:] == ridx[:-1]
    seg_pts = np.stack([coords[:-1][same], coords[1:][same]], axis=1)
    P, inv = np.unique(np.round(seg_pts.reshape(-1, 2) / grid).astype(np.int64), axis=0,
                       return_inverse=True)  # fmt: skip
    P = P.astype(np.float64) * grid
    S = inv.reshape(-1, 2)
    S = S[S[:, 0] != S[:, 1]]
    S = np.unique(np.sort(S, axis=1), axis=0)
    out = tr.triangulate({"vertices": P, "segments": S}, "pQ")
    Pt = out["vertices"]
    Tt = np.asarray(out["triangles"], dtype=np.int64)
    # which visible piece each triangle lies in (pieces have disjoint interiors)
    cen = Pt[Tt].mean(axis=1)
    tree = shapely.STRtree(polys)
    qi, qp = tree.query(shapely.points(cen), predicate="within")
    source = np.full(Tt.shape[0], -1, dtype=np.int64)
    source[qi] = src[pidx[qp]]
    keep = source >= 0
    return Pt, Tt[keep], source[keep]


def _merge_points(P: np.ndarray, tol: float) -> np.ndarray:
    """(n,) label of each point after merging points closer than ``tol`` (first index wins)."""
    n = P.shape[0]
    pairs = cKDTree(P).query_pairs(tol, output_type="ndarray")
    A = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    return lab


def _split_t_junctions(xy: np.ndarray, Ft: np.ndarray, src: np.ndarray, tol: float):
    """Split faces whose edges pass through other vertices (T-junctions), as fans.

    Only edges with a single incident face can carry a T-junction in a planar map; each pass
    splits one such edge per face at all vertices lying on it, until none is left.
    """
    tree = cKDTree(xy)
    for _ in range(64):  # each pass removes the T-junctions of one edge per face
        he = np.stack([Ft[:, [1, 2]], Ft[:, [2, 0]], Ft[:, [0, 1]]], axis=1).reshape(-1, 2)
        key = np.minimum(he[:, 0], he[:, 1]) * xy.shape[0] + np.maximum(he[:, 0], he[:, 1])
        _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
        single = np.flatnonzero(cnt[inv] == 1)
        a, b = xy[he[single, 0]], xy[he[single, 1]]
        mid, half = 0.5 * (a + b), 0.5 * np.linalg.norm(b - a, axis=1)
        near = tree.query_ball_point(mid, half + tol)
        split: dict[int, tuple[int, list[int]]] = {}
        for s, cand in zip(single.tolist(), near):  # only boundary edges, few
            f, k = divmod(s, 3)
            if f in split:
                continue
            p, q = he[s]
            d = xy[q] - xy[p]
            L2 = float(d @ d)
            on = []
            for v in cand:
                # (a face's own apex is never within tol of its edge: thinner faces were dropped)
                if v == p or v == q:
                    continue
                w = xy[v] - xy[p]
                t = float(w @ d) / L2
                if 0.0 < t < 1.0 and abs(w[0] * d[1] - w[1] * d[0]) / np.sqrt(L2) <= tol:
                    on.append((t, v))
            if on:
                split[f] = (k, [v for _, v in sorted(on)])
        if not split:
            return Ft, src
        keep = np.ones(Ft.shape[0], dtype=bool)
        newF, newS = [], []
        for f, (k, vs) in split.items():
            keep[f] = False
            c, p, q = Ft[f, k], Ft[f, (k + 1) % 3], Ft[f, (k + 2) % 3]
            chain = [p, *vs, q]
            for u, v in zip(chain[:-1], chain[1:]):
                newF.append([c, u, v])
                newS.append(src[f])
        Ft = np.vstack([Ft[keep], np.asarray(newF, dtype=np.int64)])
        src = np.concatenate([src[keep], np.asarray(newS, dtype=np.int64)])
    raise MescherError(
        "F: expected the visible map's T-junctions to resolve, found more after 64 passes"
    )


# ------------------------------------------------------------------------------ gluing
def _edge_on_source(xy, E, src, C, F, tol):
    """Index k of the source face's edge that screen edge E lies on (-1: inside the face).

    ``k`` is libigl's convention: edge ``k`` runs ``F[f, k] -> F[f, (k + 1) % 3]``.
    """
    out = np.full(E.shape[0], -1, dtype=np.int64)
    p, q = xy[E[:, 0]], xy[E[:, 1]]
    for k in range(3):
        a = C[F[src, k], :2]
        b = C[F[src, (k + 1) % 3], :2]
        d = b - a
        L = np.linalg.norm(d, axis=1)
        L = np.where(L > 0, L, 1.0)

        wp, wq = p - a, q - a
        dp = np.abs(wp[:, 0] * d[:, 1] - wp[:, 1] * d[:, 0]) / L
        dq = np.abs(wq[:, 0] * d[:, 1] - wq[:, 1] * d[:, 0]) / L
        out[(dp <= tol) & (dq <= tol) & (out < 0)] = k
    return out


def see_model(
    V: Any,
    F: Any,
    view: Any = (0.0, 0.0, 1.0),
    up: Any = (0.0, 1.0, 0.0),
    perceive: str | None = None,
    *,
    tol: float | None = None,
    bridge: bool = True,
    hidden: bool | str = "auto",
    view_start: Any = None,
) -> VisibleModel:
    """The visible surface of a 3D model from an orthographic view, false edges glued.

    Parameters
    ----------
    V : (#V, 3) array_like of float
        Model vertices (world frame); closed solids, separate parts, open reliefs, soups.
    F : (#F, 3) array_like of int
        Triangles (any orientation: each part is oriented outward by its signed volume).
    view : (3,) array_like or "auto", default: (0, 0, 1)
        Direction from the model toward the camera; ``"auto"``: the view from which the
        model's junctions line up (:func:`find_model_view`: vertex pairs that coincide, or
        the pieces of a bar broken behind an occluder; reported in ``report.view``).
    up : (3,) array_like, default: (0, 1, 0)
        Screen up (with ``view="auto"``: world +z projected, as modelling tools do).
    perceive : {None, "manhattan"}, default: None
        ``"manhattan"``: snap each face's normal to the perceived orthogonal frame and
        re-project zeta (paper Eq. 3-4), see :mod:`meschers_igl.manhattan`; the angles are in
        ``report.snapped``.
    tol : float, optional
        Relative tolerance (of the bounding-box diagonal) for screen coincidence and depth
        continuity; default :data:`REL_TOL`.
    bridge : bool, default: True
        Bridge hidden gaps (amodal completion).
    view_start : (3,) array_like, optional
        With ``view="auto"``: a view near the intended one (searched within 10 degrees).
    hidden : {"auto", True, False}, default: "auto"
        Keep the hidden side: the whole model, opened at its junctions and glued crosswise by
        the cut-model path (:func:`close_junctions`, :func:`meschers_igl.cutmesh.glue_cut_mesh`),
        a closed surface like a cut model's, with its own depths and the order of its
        overlapping faces.  ``"auto"``: when junctions are found (paired caps, hidden gaps,
        coinciding cut loops) and the gluing is a manifold, else (and with ``perceive``) the
        visible surface; ``True``: refuse when it cannot be built; ``False``: always the
        visible surface.

    Returns
    -------
    VisibleModel
        ``F``, ``xy``, per-face corner depths ``Z`` (zeta of an edge is the depth difference
        along it, the same on both sides of a glued false edge), depth-order ``arcs`` and the
        ``report``.

    Raises
    ------
    MescherError
        Bad arrays, a model with no face toward the viewer.
    """
    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    if perceive not in (None, "manhattan"):
        raise MescherError(f"perceive: expected None or 'manhattan', found {perceive!r}")
    used = np.unique(F)
    diag = float(np.linalg.norm(V[used].max(axis=0) - V[used].min(axis=0)))
    if diag == 0.0:
        raise MescherError("V: expected vertices spanning a non-empty box, found a single point")
    report = ConversionReport()
    rel = REL_TOL if tol is None else float(tol)
    tol_abs = rel * diag
    grid = REL_GRID * diag

    V, F, n_merged = weld(V, F, 0.5 * tol_abs)  # a soup: corners apart by less than the tolerance
    if n_merged:
        report.repairs.append(f"welded {n_merged} vertex(es) that coincide in 3D")
    F, n_contact = drop_contact_faces(F)
    if n_contact:
        report.repairs.append(
            f"removed {n_contact} pair(s) of coincident opposite faces (blocks touching)"
        )
    F, n_flip, part = orient_outward(V, F)
    if n_flip:
        n_parts = int(part.max()) + 1
        report.repairs.append(f"re-oriented {n_flip} face(s) outward ({n_parts} part(s))")
    if view_start is not None and not (isinstance(view, str) and view == "auto"):
        raise MescherError(f"view_start: expected view='auto' with it, found view={view!r}")
    if isinstance(view, str):
        if view != "auto":
            raise MescherError(f"view: expected a direction (3,) or 'auto', found {view!r}")
        view, up = find_model_view(V, F, tol_abs, start=view_start)
    R = view_frame(view, up)
    report.view, report.up = R[2].copy(), R[1].copy()
    _pinch_warning(F, report)
    _manifold_notes(F, report)
    if hidden not in ("auto", True, False):
        raise MescherError(f"hidden: expected 'auto', True or False, found {hidden!r}")
    if hidden is True and perceive is not None:
        raise MescherError(
            f"hidden: expected False or 'auto' with perceive={perceive!r} (perceived depths are "
            "read on the visible surface), found True"
        )
    if hidden is not False and perceive is None:
        closed = _closed_surface(V, F, R, tol_abs, rel, bridge, report, strict=hidden is True)
        if closed is not None:
            return closed

    C = V @ R.T
    N = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    # an open part (a relief, a sheet) has no outside: it is seen from the side facing the view
    open_face = _open_faces(F)
    k = int(part.max()) + 1
    is_open = np.bincount(part, weights=open_face, minlength=k) > 0
    is_open &= ~solid_like_parts(V, F, part)  # nearly closed: oriented by its volume already
    away = is_open & (np.bincount(part, weights=N[:, 2], minlength=k) < 0)
    if away.any():
        turn = away[part]
        F[turn] = F[turn][:, [0, 2, 1]]
        N[turn] *= -1
        report.repairs.append(f"turned {int(away.sum())} open part(s) toward the viewer")
    nrm = np.linalg.norm(N, axis=1)
    front = N[:, 2] > FRONT_NZ * np.maximum(nrm, 1e-300)
    if not front.any():
        raise MescherError(f"F: expected faces facing the view {R[2].tolist()}, found none")
    fid = np.flatnonzero(front)
    pl_all = np.zeros((F.shape[0], 3))
    pl_all[fid] = _planes(C, F[fid])
    T = C[F[fid], :2]

    pieces, involved = _clip_occluded(T, pl_all[fid], tol_abs, grid)
    # visible map: untouched faces as they are, clipped faces retriangulated
    Pt, Tt, st = _triangulate_pieces(pieces, grid)
    quiet = fid[~involved]
    xy0 = C[:, :2]
    P = np.vstack([xy0, Pt])
    Fa = np.vstack([F[quiet], Tt + xy0.shape[0]])
    src = np.concatenate([quiet, fid[st]])
    lab = _merge_points(P, tol_abs)
    usedp, Fa = np.unique(lab[Fa], return_inverse=True)
    Fa = Fa.reshape(-1, 3)
    xy = np.zeros((usedp.size, 2))
    first = np.full(usedp.size, -1)
    # the representative of a merged group: its first point (exact input positions win)
    flat = lab[np.concatenate([F[quiet].reshape(-1), Tt.reshape(-1) + xy0.shape[0]])]
    pts = np.concatenate([F[quiet].reshape(-1), Tt.reshape(-1) + xy0.shape[0]])
    gi = np.searchsorted(usedp, flat)
    first[gi[::-1]] = pts[::-1]
    xy = P[first]
    # drop faces that collapsed or lost their area to rounding: thinner than tol over their
    # longest edge (a cap whose apex lies on its base edge within tol is a T-junction of the
    # face across that edge, split there below, so no hole is left)
    T2 = xy[Fa]
    area2 = (T2[:, 1, 0] - T2[:, 0, 0]) * (T2[:, 2, 1] - T2[:, 0, 1]) - (
        T2[:, 2, 0] - T2[:, 0, 0]
    ) * (T2[:, 1, 1] - T2[:, 0, 1])
    longest = np.linalg.norm(T2 - T2[:, [1, 2, 0]], axis=2).max(axis=1)
    ok = area2 > tol_abs * np.maximum(longest, tol_abs)
    Fa, src = Fa[ok], src[ok]
    Fa, src = _split_t_junctions(xy, Fa, src, tol_abs)

    # each part's own precision: rel times its bounding-box diagonal (a scene's boxes are small)
    n_parts = int(part.max()) + 1
    lo = np.full((n_parts, 3), np.inf)
    hi = np.full((n_parts, 3), -np.inf)
    np.minimum.at(lo, np.repeat(part, 3), V[F].reshape(-1, 3))
    np.maximum.at(hi, np.repeat(part, 3), V[F].reshape(-1, 3))
    ftol = np.minimum(tol_abs, rel * np.linalg.norm(hi - lo, axis=1))[part]
    E = axes_model = None
    for _ in range(4):  # occlusion edges that stay glued through their end fans get split
        Z = _plane_depth(xy[Fa], pl_all[src][:, None, :])
        glue, arcs, fe = _classify(xy, Fa, src, Z, C, F, front, tol_abs, ftol)
        is_bridge = np.zeros(Fa.shape[0], dtype=bool)
        bridges: list = []
        Fb, sb, Zb = Fa, src, Z
        if bridge:
            Fb, sb, Zb, is_bridge, glue, arcs, bridges = _bridge(
                xy, Fa, src, Z, pl_all, N, glue, arcs, fe, tol_abs, C[F][:, :, :2], (C, F)
            )
        if perceive == "manhattan":
            from .manhattan import model_face_axes, perceive_manhattan, perceived_frame

            if E is None:
                E = perceived_frame(xy, Fb, Zb)
                axes_model = model_face_axes(C, F, E)  # read from the model's own polygons
            Zb, report.snapped = perceive_manhattan(xy, Fb, Zb, axis=axes_model[sb], E=E)
            glue, arcs = _reglue(glue, Fb, Zb, arcs, tol_abs)
        Fm, corner_vertex = _cut_and_glue(Fb, glue)
        h1, h2 = glue["h1"][~glue["glue"]], glue["h2"][~glue["glue"]]
        stuck = _stuck_cuts(Fm, h1, h2)
        if stuck.size == 0:
            break
        xy, Fa, src = _split_cut_faces(xy, Fa, src, h1[stuck], h2[stuck])
    report.junctions = _false_edge_junctions(xy, fe) + bridges
    report.route = "visible"
    if not report.reason:
        report.reason = (
            "perceived depths are read on the visible surface"
            if perceive
            else "no junction to open on the whole model: the surface the viewer sees"
        )
    report.n_arcs = int(arcs.shape[0])
    report.source_face = np.where(is_bridge, -1, sb)
    first = np.zeros(int(Fm.max()) + 1, dtype=np.int64)
    first[Fm.reshape(-1)] = corner_vertex
    xym = xy[first]
    report.arcs = arcs
    _expectation_warning(report, V, F, C, front)
    return VisibleModel(F=Fm, xy=xym, Z=Zb, arcs=arcs, report=report)


def _reglue(glue: dict, Fb: np.ndarray, Z: np.ndarray, arcs: np.ndarray, tol: float):
    """Glued edges whose (perceived) depths on the two sides are no longer parallel become
    occlusions (cut, far -> near arc); parallel jumps stay glued (perceived false edges)."""
    h1, h2, ok = glue["h1"], glue["h2"], glue["glue"].copy()
    a = _he_depth(Z, h1)
    b = _he_depth(Z, h2)[:, ::-1]  # the partner runs the other way
    d = b - a  # (k, 2): depth jump at tail and head
    # the model's own continuous edges stay glued (a crease a person sees; the projection onto
    # integrable forms reconciles the snapped planes there)
    jump = ok & (np.abs(d[:, 0] - d[:, 1]) > tol)
    bad = jump & ~glue["cont"]
    # the model's own continuous edges become cuts too, unless that cuts the loops a person
    # follows (a relief whose snapped planes disagree at every crease): then they stay glued
    # and the projection onto integrable forms reconciles the snapped planes there
    cut_all = {"h1": h1, "h2": h2, "glue": ok & ~jump}
    if _betti1(_cut_and_glue(Fb, cut_all)[0]) >= _betti1(
        _cut_and_glue(Fb, {**cut_all, "glue": ok & ~bad})[0]
    ):
        bad = jump
    if bad.any():
        ok[bad] = False
        far1 = d[bad].sum(axis=1) > 0
        f1, f2 = h1[bad] // 3, h2[bad] // 3
        new = np.stack([np.where(far1, f1, f2), np.where(far1, f2, f1)], axis=1)
        arcs = np.vstack([arcs, new]).astype(np.int64)
    return {"h1": h1, "h2": h2, "glue": ok, "cont": glue["cont"]}, arcs


def _betti1(F: np.ndarray) -> int:
    """First Betti number of a triangle mesh (orientable, manifold): ``E - V - F + C + closed``
    with ``C`` its connected parts and ``closed`` those without boundary (``b2``)."""
    he = np.stack([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]], axis=1).reshape(-1, 2)
    n = int(F.max(initial=0)) + 1
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    f = np.repeat(np.arange(F.shape[0]), 3)
    A = sp.coo_matrix((np.ones(f.size), (f, he[:, 0])), shape=(F.shape[0], n)).tocsr()
    A = sp.bmat([[None, A], [A.T, None]])
    k, lab = csgraph.connected_components(A, directed=False)
    comp = lab[: F.shape[0]]
    used = np.unique(F)
    parts = np.unique(comp)
    open_part = np.zeros(k, dtype=bool)
    open_part[comp[f[(cnt[inv] == 1)]]] = True
    n_closed = int(np.count_nonzero(~open_part[parts]))
    return int(cnt.size - used.size - F.shape[0] + parts.size + n_closed)


def _stuck_cuts(Fm: np.ndarray, h1: np.ndarray, h2: np.ndarray) -> np.ndarray:
    """Cut edges whose two sides still share both end vertices after gluing (indices)."""
    f1, k1, f2, k2 = h1 // 3, h1 % 3, h2 // 3, h2 % 3
    a1, b1 = Fm[f1, (k1 + 1) % 3], Fm[f1, (k1 + 2) % 3]
    b2, a2 = Fm[f2, (k2 + 1) % 3], Fm[f2, (k2 + 2) % 3]
    return np.flatnonzero((a1 == a2) & (b1 == b2))


def _split_cut_faces(xy, Fa, src, h1, h2):
    """Split both faces of each stuck cut edge at the edge's midpoint, one new vertex per side."""
    hs = np.concatenate([h1, h2])
    f, k = hs // 3, hs % 3
    _, first = np.unique(f, return_index=True)  # one split per face per pass
    f, k = f[first], k[first]
    a, b, c = Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3], Fa[f, k]
    m = xy.shape[0] + np.arange(f.size)
    xy = np.vstack([xy, 0.5 * (xy[a] + xy[b])])
    keep = np.ones(Fa.shape[0], dtype=bool)
    keep[f] = False
    Fa = np.vstack([Fa[keep], np.stack([a, m, c], 1), np.stack([m, b, c], 1)])
    src = np.concatenate([src[keep], src[f], src[f]])
    return xy, Fa, src


def _expectation_warning(report, V, F, C, front) -> None:
    """Warn when nothing impossible was found although the model looks built for it.

    Two signs that a junction was meant: silhouette vertices that *nearly* line up on screen
    (within 1% of the size) far apart in depth -- the view is slightly off, try ``view="auto"``
    -- and faces whose normals are near, but not exactly on, three orthogonal directions -- a
    sheared trick, try ``perceive="manhattan"``.
    """
    if any(j.depth_gap > 0 for j in report.junctions if j.kind != "occluded continuation"):
        return
    if report.snapped is not None and report.snapped.max(initial=0.0) > 1e-6:
        return  # the perceived (snapped) depths decide; the caller sees the periods
    diag = float(np.linalg.norm(np.ptp(V, axis=0)))
    vs = np.unique(F[front])
    P = C[vs]
    near = cKDTree(P[:, :2]).query_pairs(1e-2 * diag, output_type="ndarray")
    dz = np.abs(P[near[:, 0], 2] - P[near[:, 1], 2]) if near.size else np.zeros(0)
    hints = []
    if np.any(dz > 0.2 * diag):
        hints.append("view='auto' (vertices far apart in depth nearly line up on screen)")
    if report.snapped is None:
        hints.append("perceive='manhattan' (if the figure looks impossible by its right angles)")
    msg = "the result is possible (no junction glued, no period); try " + " or ".join(hints)
    report.warnings.append(msg)
    warnings.warn(f"see_model: {msg}", MescherWarning, stacklevel=4)


def _manifold_notes(F: np.ndarray, report: ConversionReport) -> None:
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


def _pinch_warning(F: np.ndarray, report: ConversionReport) -> None:
    ok = np.asarray(igl.is_vertex_manifold(F)).reshape(-1)
    bad = np.flatnonzero(~ok.astype(bool))
    if bad.size:
        msg = (
            f"{bad.size} pinch vertex(es) where separate fans of faces meet (e.g. vertex "
            f"{bad[:4].tolist()}); each fan is treated as its own sheet"
        )
        report.warnings.append(msg)
        warnings.warn(f"see_model: {msg}", MescherWarning, stacklevel=3)


def _interior_edges(Fa: np.ndarray, n: int):
    """(pairs of faces sharing an edge, the edge's vertices, corner index in each face)."""
    he = np.stack([Fa[:, [1, 2]], Fa[:, [2, 0]], Fa[:, [0, 1]]], axis=1).reshape(-1, 2)
    key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
    order = np.argsort(key, kind="stable")
    ks = key[order]
    same = np.flatnonzero(ks[1:] == ks[:-1])
    h1, h2 = order[same], order[same + 1]
    return h1, h2, he


def _classify(xy, Fa, src, Z, C, F, front, tol, ftol=None):
    """Per shared screen edge: glue (continuous or false edge) or cut with an arc.

    ``ftol`` (#F,): per model face, the tolerance of its own part (``tol`` relative to the
    part's size, not the scene's): a false edge needs both model edges to coincide on screen
    to their parts' precision, so blocks a hair apart in a large scene are not glued.
    """
    ftol = np.full(F.shape[0], tol) if ftol is None else ftol
    h1, h2, he = _interior_edges(Fa, xy.shape[0])
    f1, f2 = h1 // 3, h2 // 3
    E = he[h1]  # p -> q as in face f1
    # depth of p and q in each face (corner positions of the half-edge)
    k1 = h1 % 3
    z1p, z1q = Z[f1, (k1 + 1) % 3], Z[f1, (k1 + 2) % 3]
    k2 = h2 % 3
    # in f2 the half-edge runs q -> p
    z2q, z2p = Z[f2, (k2 + 1) % 3], Z[f2, (k2 + 2) % 3]
    dp, dq = z2p - z1p, z2q - z1q
    continuous = (np.abs(dp) <= tol) & (np.abs(dq) <= tol)
    parallel = np.abs(dp - dq) <= tol
    # does each side end there on its own surface (silhouette or boundary of the model)?
    TT, _ = igl.triangle_triangle_adjacency(F)
    TT = np.asarray(TT)

    def ends(fs):
        s = src[fs]
        k = _edge_on_source(xy, E, s, C, F, np.minimum(ftol[src[f1]], ftol[src[f2]]))
        nb = np.where(k >= 0, TT[s, np.maximum(k, 0)], 0)
        return k >= 0, (k >= 0) & ((nb < 0) | ~front[np.maximum(nb, 0)])

    (on1, e1), (on2, e2) = ends(f1), ends(f2)
    far1 = (dp + dq) > 0  # face 2 nearer
    # a false edge: both sides lie on an edge of their own model face and the nearer side ends
    # there (silhouette or boundary); the farther side may turn a crease whose other face the
    # nearer one hides -- the viewer sees one crease or one flat continuation
    false_edge = ~continuous & parallel & on1 & on2 & np.where(far1, e2, e1)
    glue = continuous | false_edge
    cut = ~glue
    # true occlusion: the far face gets an arc to the near one
    arcs = np.stack([np.where(far1, f1, f2), np.where(far1, f2, f1)], axis=1)[cut]
    return (
        {"h1": h1, "h2": h2, "glue": glue, "he": he, "cont": continuous},
        arcs.astype(np.int64),
        {"h1": h1[false_edge], "f1": f1[false_edge], "f2": f2[false_edge],
         "E": E[false_edge], "gap": 0.5 * (dp + dq)[false_edge],
         "occl_far": np.where(far1, h1, h2)[cut & ~np.where(far1, e1, e2)]},
    )  # fmt: skip


def _false_edge_junctions(xy, fe) -> list:
    """Chains of false edges (connected on screen) as junctions."""
    E = fe["E"]
    if E.shape[0] == 0:
        return []
    n = xy.shape[0]
    A = sp.coo_matrix((np.ones(E.shape[0]), (E[:, 0], E[:, 1])), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    comp = lab[E[:, 0]]
    out = []
    for c in np.unique(comp).tolist():  # one per junction, few
        s = comp == c
        mid = 0.5 * (xy[E[s, 0]] + xy[E[s, 1]])
        out.append(Junction("false edge", mid.mean(axis=0), float(np.median(np.abs(fe["gap"][s]))),
                            int(s.sum())))  # fmt: skip
    return out


def _cut_and_glue(Fa, glue):
    """Mescher faces: corners united across glued half-edge pairs (connected components).

    Returns
    -------
    Fm : (#F, 3) int64
        Faces over the mescher's vertices.
    corner_vertex : (3 #F,) int64
        Planar (screen) vertex of each corner, to take the mescher vertices' positions from.
    """
    nf = Fa.shape[0]
    h1, h2, ok = glue["h1"], glue["h2"], glue["glue"]
    g1, g2 = h1[ok], h2[ok]
    f1, k1, f2, k2 = g1 // 3, g1 % 3, g2 // 3, g2 % 3
    # half-edge k of face f runs corner k+1 -> k+2; its partner runs the other way
    c1p, c1q = 3 * f1 + (k1 + 1) % 3, 3 * f1 + (k1 + 2) % 3
    c2q, c2p = 3 * f2 + (k2 + 1) % 3, 3 * f2 + (k2 + 2) % 3
    rows = np.concatenate([c1p, c1q])
    cols = np.concatenate([c2p, c2q])
    n = 3 * nf
    A = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    _, lab = csgraph.connected_components(A, directed=False)
    _, Fm = np.unique(lab, return_inverse=True)
    return Fm.reshape(-1, 3).astype(np.int64), Fa.reshape(-1)


def _chains(xy, Fa, hs):
    """Connected chains of half-edges ``hs`` (each as its ordered vertex list, tail first)."""
    if hs.size == 0:
        return []
    f, k = hs // 3, hs % 3
    p, q = Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]
    nxt = dict(zip(p.tolist(), q.tolist()))
    heads = set(q.tolist())
    out = []
    for start in p.tolist():  # a few occluded edges per junction
        if start in heads:
            continue
        ch = [start]
        while ch[-1] in nxt and len(ch) <= hs.size:
            ch.append(nxt[ch[-1]])
        out.append(ch)
    return out


def _bridge(xy, Fa, src, Z, pl, N, glue, arcs, fe, tol, Tm, model=None):
    """Amodal completion: bridge occluded pieces that line up across an occluder.

    Occluded edges (far side of a true occlusion where the far surface continues) are grouped
    into chains per source plane orientation.  Chains ``A`` and ``B`` of equal normals are
    bridged when the strip between them is a quadrilateral whose sides are parallel to an edge
    of ``A``'s source face (the bar's own edge lines continue behind the occluder) and which is
    hidden behind visible faces nearer than both planes.  The strip is triangulated, takes
    ``A``'s plane (so it is continuous with ``A``) and is glued to ``B`` across the depth
    offset, which becomes a period.  Each bridge face gets arcs to the visible faces in front.
    """
    import shapely

    nf = Fa.shape[0]
    none = (Fa, src, Z, np.zeros(nf, dtype=bool), glue, arcs, [])
    occ = fe["occl_far"]
    if occ.size < 2:
        return none
    n_unit = N / np.linalg.norm(N, axis=1, keepdims=True)
    # group occluded half-edges by the orientation of their source face
    nk = np.round(n_unit[src[occ // 3]] / 1e-6).astype(np.int64)
    _, grp = np.unique(nk, axis=0, return_inverse=True)
    grp = grp.reshape(-1)
    chains = []  # (group, vertex list, source face)
    for g in np.unique(grp).tolist():
        for ch in _chains(xy, Fa, occ[grp == g]):
            he = occ[grp == g]
            f0 = he[Fa[he // 3, (he % 3 + 1) % 3] == ch[0]][0] // 3
            chains.append((g, ch, int(src[f0])))
    T = xy[Fa]
    new_faces, new_src, bridges, used = [], [], [], set()
    for ia, (ga, A, sa) in enumerate(chains):  # few chains
        best = None
        for ib, (gb, B, sb) in enumerate(chains):
            if ib == ia or gb != ga or ia in used or ib in used:
                continue
            a0, a1, b0, b1 = xy[A[0]], xy[A[-1]], xy[B[0]], xy[B[-1]]
            s0, s1 = b1 - a0, b0 - a1  # the strip's sides
            L0, L1 = np.linalg.norm(s0), np.linalg.norm(s1)
            if L0 <= tol or L1 <= tol or abs(_cross(s0, s1)) > tol * (L0 + L1):
                continue
            da = a1 - a0
            if _cross(da, s0) >= 0:  # the strip must lie to the right of A (outside its face)
                continue
            if not (_parallel_to_edge(s0, Tm[sa], tol) or _parallel_to_edge(s0, Tm[sb], tol)):
                continue
            poly = [*A[::-1], *B[::-1]]
            ring = shapely.Polygon(xy[poly])
            if not ring.is_valid or ring.area <= tol * (L0 + L1):  # not a simple strip
                continue
            c = xy[poly].mean(axis=0)
            gap = float(_plane_depth(c, pl[sb]) - _plane_depth(c, pl[sa]))
            if not _hidden(xy[poly], pl[sa], pl[sb], T, Z, tol):
                continue
            plane = sa  # the strip continues A's plane (glued to B across the gap) ...
            if model is not None:
                # ... and must run through empty space, not through a block lying between the
                # pieces or through the occluder (libigl's generalized winding number, camera
                # coordinates); else it continues B's plane, if that one is free
                P = c[None]  # the strip's middle (its rim touches the pieces' surfaces)
                plane = None
                for s_ in (sa, sb):
                    P3 = np.c_[P, _plane_depth(P, pl[s_])]
                    if np.all(np.abs(igl.winding_number(model[0], model[1], P3)) <= 0.5):
                        plane = s_
                        break
                if plane is None:
                    continue
            if best is None or L0 < best[0]:
                best = (L0, ib, poly, sb, gap, plane)
        if best is None:
            continue
        _, ib, poly, sb, gap, plane = best
        P = xy[poly]
        tri = _polygon_triangles(P)
        if tri is None:
            continue
        used |= {ia, ib}
        new_faces += [[poly[i] for i in t] for t in tri]
        new_src += [plane] * len(tri)
        kind = "hidden gap" if abs(gap) > tol else "occluded continuation"
        bridges.append(Junction(kind, P.mean(axis=0), abs(gap), len(poly) // 2))
    if not new_faces:
        return none
    Fb = np.vstack([Fa, np.asarray(new_faces, dtype=np.int64)])
    sb_all = np.concatenate([src, np.asarray(new_src, dtype=np.int64)])
    is_bridge = np.r_[np.zeros(nf, dtype=bool), np.ones(len(new_faces), dtype=bool)]
    Zb = _plane_depth(xy[Fb], pl[sb_all][:, None, :])
    # glue: bridge half-edges to the occluded half-edges they run against, and to each other
    bh = np.arange(3 * nf, 3 * Fb.shape[0])
    bp, bq = Fb[bh // 3, (bh % 3 + 1) % 3], Fb[bh // 3, (bh % 3 + 2) % 3]
    op, oq = Fa[occ // 3, (occ % 3 + 1) % 3], Fa[occ // 3, (occ % 3 + 2) % 3]
    key_o = dict(zip(zip(oq.tolist(), op.tolist()), occ.tolist()))
    g1, g2 = [], []
    for h, u, v in zip(bh.tolist(), bp.tolist(), bq.tolist()):
        if (u, v) in key_o:
            g1.append(h)
            g2.append(key_o[(u, v)])
    h1b, h2b, _ = _interior_edges(Fb[nf:], xy.shape[0])
    h1b, h2b = h1b + 3 * nf, h2b + 3 * nf
    zc = np.abs(_he_depth(Zb, h1b) - _he_depth(Zb, h2b)[:, ::-1]).max(axis=1) <= tol
    g1 += h1b[zc].tolist()
    g2 += h2b[zc].tolist()
    glue = {
        "h1": np.concatenate([glue["h1"], g1]).astype(np.int64),
        "h2": np.concatenate([glue["h2"], g2]).astype(np.int64),
        "glue": np.concatenate([glue["glue"], np.ones(len(g1), dtype=bool)]),
        "cont": np.concatenate([glue["cont"], np.zeros(len(g1), dtype=bool)]),
    }
    # bridge faces lie behind the visible faces they overlap on screen
    Tb = xy[Fb]
    pairs, _ = overlapping_pairs(Tb, tol)
    mixed = is_bridge[pairs[:, 0]] != is_bridge[pairs[:, 1]]
    pr = pairs[mixed]
    behind = np.where(is_bridge[pr[:, 0]], pr[:, 0], pr[:, 1])
    front = np.where(is_bridge[pr[:, 0]], pr[:, 1], pr[:, 0])
    arcs = np.vstack([arcs, np.stack([behind, front], axis=1)]).astype(np.int64)
    return Fb, sb_all, Zb, is_bridge, glue, arcs, bridges


def _he_depth(Z, h):
    """(k, 2) depths of the tail and head of half-edges ``h`` (= 3 f + k)."""
    f, k = h // 3, h % 3
    return np.stack([Z[f, (k + 1) % 3], Z[f, (k + 2) % 3]], axis=1)


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _polygon_triangles(P: np.ndarray) -> list:
    """Triangles (local corner indices, CCW) of a simple polygon whose consecutive vertices may
    be collinear (a fan would make flat triangles there): constrained Delaunay, no new points."""
    import triangle as tr

    n = P.shape[0]
    seg = np.stack([np.arange(n), (np.arange(n) + 1) % n], axis=1)
    out = tr.triangulate({"vertices": P, "segments": seg}, "pQ")
    T = np.asarray(out["triangles"], dtype=np.int64)
    if out["vertices"].shape[0] != n:
        return None  # not a simple polygon after all: no bridge here
    Q = P[T]
    a2 = (Q[:, 1, 0] - Q[:, 0, 0]) * (Q[:, 2, 1] - Q[:, 0, 1]) - (Q[:, 2, 0] - Q[:, 0, 0]) * (
        Q[:, 1, 1] - Q[:, 0, 1]
    )
    T[a2 < 0] = T[a2 < 0][:, [0, 2, 1]]
    return T.tolist()


def _parallel_to_edge(s, tri, tol) -> bool:
    """Is screen direction ``s`` parallel to an edge of the screen triangle ``tri`` (3, 2)?
    (A bar's model face has its long edges along the bar: the strip continues them.)"""
    E = tri[[1, 2, 0]] - tri
    L = np.linalg.norm(E, axis=1)
    c = np.abs(E[:, 0] * s[1] - E[:, 1] * s[0]) / np.maximum(L, 1e-300) / np.linalg.norm(s)
    return bool(np.any((c <= 1e-6) & (L > tol)))


def _hidden(P, pla, plb, T, Z, tol) -> bool:
    """Is the polygon ``P`` covered by visible faces nearer than both planes (sample points)?"""
    from .geometry2d import barycentric

    c = P.mean(axis=0)
    pts = np.vstack([c, 0.5 * (P + c)])
    for x in pts:  # a handful of sample points
        B = barycentric(np.repeat(x[None], T.shape[0], 0), T)
        inside = np.all(B >= -1e-9, axis=1)
        if not inside.any():
            return False
        z = (B[inside] * Z[inside]).sum(axis=1).max()
        if z <= max(_plane_depth(x, pla), _plane_depth(x, plb)) + tol:
            return False
    return True


# ------------------------------------------------------------------------------ closed surface
#: Unit normals closer than this (1 - cos) count as equal or opposite when caps are paired.
CAP_NORMAL_TOL = 1e-9


@dataclass(frozen=True)
class _Cap:
    """A planar patch bounded by one loop (a bar's end face): its faces, loop and normal."""

    faces: np.ndarray
    loop: np.ndarray
    normal: np.ndarray


def _planar_patches(V: np.ndarray, F: np.ndarray, TT: np.ndarray, tol: float) -> np.ndarray:
    """(#F,) label of the coplanar patch of each face (faces joined across shared edges)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    f = np.repeat(np.arange(F.shape[0]), 3)
    g = TT.reshape(-1)
    ok = g >= 0
    f, g = f[ok], g[ok]
    same = (np.einsum("ij,ij->i", n[f], n[g]) >= 1.0 - CAP_NORMAL_TOL) & (
        np.abs(np.einsum("ij,ij->i", V[F[g, 0]] - V[F[f, 0]], n[f])) <= tol
    )
    A = sp.coo_matrix((np.ones(int(same.sum())), (f[same], g[same])), shape=(F.shape[0],) * 2)
    return csgraph.connected_components(A, directed=False)[1]


def _caps(V, F, TT, patch, tol) -> list:
    """Patches bounded by a single loop whose normal has an opposite among the patches (the
    candidates for the two ends of a broken bar); others are never caps."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    k = int(patch.max()) + 1
    first = np.full(k, F.shape[0])
    np.minimum.at(first, patch, np.arange(F.shape[0]))
    pn = n[first]
    key = np.round(pn / 1e-6).astype(np.int64)
    have = {tuple(r) for r in key.tolist()}
    cand = np.flatnonzero([tuple(-x for x in r) in have for r in key.tolist()])  # per patch
    # boundary half-edges of each patch: its faces' half-edges whose neighbour is elsewhere
    fe = np.repeat(np.arange(F.shape[0]), 3)
    nb = TT.reshape(-1)
    bd = (nb < 0) | (patch[np.maximum(nb, 0)] != patch[fe])
    corner = np.tile(np.arange(3), F.shape[0])
    tail, head = F[fe, corner], F[fe, (corner + 1) % 3]
    in_cand = np.isin(patch[fe], cand) & bd
    out = []
    pe = patch[fe[in_cand]]
    order = np.argsort(pe, kind="stable")
    pe, t, h = pe[order], tail[in_cand][order], head[in_cand][order]
    if pe.size == 0:
        return out
    starts = np.flatnonzero(np.r_[True, pe[1:] != pe[:-1]])
    fo = np.argsort(patch, kind="stable")  # faces grouped by patch
    fstart = np.searchsorted(patch[fo], np.arange(k + 1))
    for s, e in zip(starts.tolist(), np.r_[starts[1:], pe.size].tolist()):  # candidate caps
        nxt = dict(zip(t[s:e].tolist(), h[s:e].tolist()))
        if len(nxt) != e - s:
            continue  # a vertex with two outgoing boundary edges: not a simple loop
        loop = [t[s]]
        while len(loop) <= e - s and nxt[loop[-1]] != loop[0]:
            loop.append(nxt[loop[-1]])
        if len(loop) != e - s:
            continue  # more than one loop (a patch with a hole)
        p = int(pe[s])
        out.append(_Cap(fo[fstart[p] : fstart[p + 1]], np.asarray(loop, np.int64), pn[p]))
    return out


def _match_loops(A: np.ndarray, B: np.ndarray, tol: float):
    """Correspondence ``B[perm] == A + T`` of two loops congruent by a translation, or None."""
    if A.shape != B.shape:
        return None
    T = B.mean(axis=0) - A.mean(axis=0)
    d, perm = cKDTree(B).query(A + T)
    if np.max(d) > tol or np.unique(perm).size != perm.size:
        return None
    return perm, T


def _side_direction(V, F, TT, cap: _Cap, tol: float):
    """The common direction of the side faces next to a cap (a prism's lateral edges), or None."""
    fs = cap.faces
    nbs = TT[fs].reshape(-1)
    nbs = np.unique(nbs[(nbs >= 0) & ~np.isin(nbs, fs)])
    if nbs.size < 2:
        return None  # a loose patch (no side faces): not a bar's end
    n = np.cross(V[F[nbs, 1]] - V[F[nbs, 0]], V[F[nbs, 2]] - V[F[nbs, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    # two side planes that are not parallel meet along the bar's direction
    c = np.cross(n[0], n)
    k = int(np.argmax(np.linalg.norm(c, axis=1)))
    if np.linalg.norm(c[k]) < 1e-6:
        return None
    d = c[k] / np.linalg.norm(c[k])
    if np.max(np.abs(n @ d)) > 1e-6:
        return None  # the side faces do not share one direction: not a bar's end
    return d if d @ cap.normal > 0 else -d


def _tube_hidden(points, depth_gap, C, F, front, R, tol, own, margin) -> bool:
    """Are the 3D ``points`` (on a bridge) behind model faces nearer than both pieces?

    Faces of the pieces' own parts (``own``, (#F,) bool) count only when they are nearer by
    more than ``margin`` (a bar's width): two blocks a hair apart cover the hair between them
    with their own faces, which hides nothing a viewer would complete.
    """
    from .geometry2d import barycentric

    P = points @ R.T
    T = C[F[front]]
    slack = np.where(own[front], margin, 0.0)
    lo, hi = T[:, :, :2].min(axis=1), T[:, :, :2].max(axis=1)
    for x, z in zip(P[:, :2], P[:, 2]):  # a dozen sample points
        cand = np.flatnonzero(np.all((lo <= x + tol) & (hi >= x - tol), axis=1))
        if cand.size == 0:
            return False
        B = barycentric(np.repeat(x[None], cand.size, 0), T[cand, :, :2])
        inside = np.all(B >= -1e-9, axis=1)
        if not inside.any():
            return False
        zf = (B[inside] * T[cand[inside], :, 2]).sum(axis=1) - slack[cand[inside]]
        if zf.max() <= max(z, z + depth_gap) + tol:
            return False
    return True


@dataclass(frozen=True)
class BarEnds:
    """Two caps that may be the ends of one broken bar (view-independent).

    Attributes
    ----------
    first, second : _Cap
    T : (3,) float
        Translation from ``first``'s loop to ``second``'s.
    d : (3,) float or None
        The bar's direction at ``first`` (its side faces' common direction, pointing out of
        the cap), None when the caps' sides do not run along one direction.
    """

    first: _Cap
    second: _Cap
    T: np.ndarray
    d: np.ndarray | None


#: Without a view, at most this many cap pairs are compared (all pairs of caps with opposite
#: normals and equal loops); a model with more (thousands of equal boxes) gets no hidden-gap
#: search for view="auto" (with a view, the pairs are found on screen, in linear time).
MAX_CAP_PAIRS = 20000


def bar_end_pairs(
    V: np.ndarray, F: np.ndarray, tol: float, TT: np.ndarray | None = None, R: Any = None
) -> list:
    """Pairs of caps -- planar patches bounded by one loop -- with opposite normals whose loops
    are congruent by a translation: the candidates for the two ends of a broken bar.  Each
    unordered pair comes once per orientation.

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
    tol : float
        Absolute tolerance.
    TT : (#F, 3) int64, optional
        ``igl.triangle_triangle_adjacency(F)[0]``.
    R : (3, 3) float64, optional
        A view frame: only pairs that can be junctions from it are returned, found on screen
        (caps that coincide, or that lie on one screen line along their bar) in linear time.
        Without it (the automatic view), every pair with opposite normals and equal loops is
        compared, up to :data:`MAX_CAP_PAIRS`.

    Returns
    -------
    list of BarEnds
    """
    if TT is None:
        TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    caps = _caps(V, F, TT, _planar_patches(V, F, TT, tol), tol)
    if len(caps) < 2:
        return []
    size = np.array([c.loop.size for c in caps])
    nkey = np.round(np.array([c.normal for c in caps]) / 1e-6).astype(np.int64)
    cen = np.array([V[c.loop].mean(axis=0) for c in caps])
    sides: dict[int, Any] = {}

    def side(i):
        if i not in sides:
            sides[i] = _side_direction(V, F, TT, caps[i], tol)
        return sides[i]

    if R is None:
        groups: dict[tuple, list] = {}
        for i, key in enumerate(map(tuple, np.c_[size, nkey].tolist())):  # one per cap
            groups.setdefault(key, []).append(i)
        cand = []
        for i in range(len(caps)):  # caps, and their opposite group
            cand += [(i, j) for j in groups.get((size[i], *(-nkey[i]).tolist()), []) if j > i]
            if len(cand) > MAX_CAP_PAIRS:
                return []
    else:
        R = np.asarray(R, dtype=np.float64)
        s2 = cen @ R[:2].T
        cand = cKDTree(s2).query_pairs(tol, output_type="ndarray").tolist()
        # caps on one screen line along their bar: key (direction angle, offset of the line)
        rows, keys = [], []
        for i in range(len(caps)):  # one per cap
            d = side(i)
            if d is None:
                continue
            u = R[:2] @ d
            if np.linalg.norm(u) <= 1e-9:
                continue
            u /= np.linalg.norm(u)
            if u[0] < 0 or (u[0] == 0 and u[1] < 0):
                u = -u
            rows.append(i)
            keys.append([np.arctan2(u[1], u[0]), u[0] * s2[i, 1] - u[1] * s2[i, 0]])
        if rows:
            K = np.asarray(keys) * [np.linalg.norm(np.ptp(s2, axis=0)) + 1.0, 1.0]
            lp = cKDTree(K).query_pairs(10 * tol, output_type="ndarray")
            cand += np.asarray(rows)[lp].tolist()
    out = []
    for i, j in sorted({(min(p), max(p)) for p in cand}):  # the candidate pairs
        a, b = caps[i], caps[j]
        if size[i] != size[j] or a.normal @ b.normal > -1.0 + CAP_NORMAL_TOL:
            continue
        match = _match_loops(V[a.loop], V[b.loop], tol)
        if match is None:
            continue
        T = match[1]
        da, db = side(i), side(j)
        facing = da is not None and db is not None and da @ db <= -1.0 + 1e-9
        out.append(BarEnds(a, b, T, da if facing else None))
        out.append(BarEnds(b, a, -T, db if facing else None))
    return out


def _junction_at(V, F, C, R, be: BarEnds, tol, front, part, bridge):
    """What the bar ends ``be`` are from view ``R``: ("false edge", gap, None),
    ("hidden gap", g, ell) or None.  Pieces in line in 3D (``g`` = 0) are no junction: joining
    them behind an occluder would change the topology without a period (a grid of blocks
    would be joined into a lattice)."""
    v = R[2]
    gap = float(be.T @ v)
    if np.linalg.norm(be.T - gap * v) <= tol and abs(gap) > tol:
        # both caps contain the view and coincide on screen: a false edge
        if abs(be.first.normal @ v) > 1e-6 or gap < 0:
            return None  # (each unordered pair once: the one gaining depth)
        return "false edge", gap, None
    d = be.d
    if not bridge or d is None or be.first.normal @ d <= 0:
        return None
    M = np.stack([d, v], axis=1)
    (ell, g), *_ = np.linalg.lstsq(M, be.T, rcond=None)
    if ell <= tol or abs(g) <= tol or np.linalg.norm(M @ [ell, g] - be.T) > tol:
        return None
    P0 = V[be.first.loop]
    c0 = P0.mean(axis=0)
    axis = c0 + np.array([[0.25], [0.5], [0.75]]) * ell * d
    # the bridge must run through empty space (not through a block in between) and be hidden
    # (libigl's generalized winding number: ~1 inside a solid)
    if np.any(np.abs(igl.winding_number(V, F, axis)) > 0.5):
        return None
    S = [0.9 * P0 + 0.1 * c0 + s * ell * d for s in (0.25, 0.5, 0.75)] + [axis]
    own = np.isin(part, part[[be.first.faces[0], be.second.faces[0]]])
    width = float(np.ptp(P0, axis=0).max())
    if not _tube_hidden(np.vstack(S), g, C, F, front, R, tol, own, width):
        return None
    return "hidden gap", float(g), float(ell)


def _parts_and_front(V, F, TT, R):
    f = np.repeat(np.arange(F.shape[0]), 3)
    ok = TT.reshape(-1) >= 0
    A = sp.coo_matrix((np.ones(int(ok.sum())), (f[ok], TT.reshape(-1)[ok])), (F.shape[0],) * 2)
    part = csgraph.connected_components(A, directed=False)[1]
    C = V @ R.T
    N = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    front = N[:, 2] > FRONT_NZ * np.maximum(np.linalg.norm(N, axis=1), 1e-300)
    return part, C, front


def close_junctions(V, F, R, tol: float, bridge: bool = True, pairs: list | None = None):
    """Open a closed model at its junctions so that the cut-model gluing closes it crosswise.

    Pairs of *caps* (:func:`bar_end_pairs`: planar patches bounded by one loop, normals
    opposite, loops congruent by a translation ``T``) are the two ends of a bar the artist
    broke:

    * **false edge**: ``T`` is along the view (the caps coincide on screen, each containing the
      view direction, e.g. a capped U-tribar): both caps are removed; the two open loops
      coincide on screen and are glued crosswise by the cut-model path, ``|T|`` is the period;
    * **hidden gap** (``bridge``): ``T = l d + g v`` with ``d`` the bar's direction (the common
      direction of the faces beside each cap, pointing from one cap to the other), the bridge
      between them through empty space and hidden behind nearer faces: both caps are removed
      and the bar is continued from the first cap by ``l d`` (a tube of the same cross-section,
      the first piece's depth); its end loop coincides on screen with the second cap's loop,
      ``g`` apart in depth: the period.  Pieces in line in 3D (``g`` = 0) are left apart.

    Parameters
    ----------
    V : (#V, 3) float64, F : (#F, 3) int64
        A cleaned model (welded, oriented outward).
    R : (3, 3) float64
        ``view_frame(view, up)``.
    tol : float
        Absolute tolerance.
    bridge : bool
        Also bridge hidden gaps.
    pairs : list of BarEnds, optional
        :func:`bar_end_pairs` of the model, when already computed.

    Returns
    -------
    V2 : (#V2, 3) float64
        ``V`` with the tube ends appended.
    F2 : (#F2, 3) int64
        Faces of the opened model (caps removed, tubes added).
    source : (#F2,) int64
        Face of ``F`` each face comes from, -1 for tube faces.
    junctions : list of Junction
    """
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    if pairs is None:
        pairs = bar_end_pairs(V, F, tol, TT, R)
    part, C, front = _parts_and_front(V, F, TT, R)
    used, drop, junctions = set(), [], []
    newV, newF = [], []
    nV = V.shape[0]
    for be in pairs:  # a few candidate pairs
        ids = {id(be.first), id(be.second)}
        if ids & used:
            continue
        found = _junction_at(V, F, C, R, be, tol, front, part, bridge)
        if found is None:
            continue
        kind, gap, ell = found
        used |= ids
        drop += [be.first.faces, be.second.faces]
        loop = be.first.loop
        if kind == "hidden gap":
            ends = nV + np.arange(loop.size)
            nV += loop.size
            newV.append(V[loop] + ell * be.d)
            nxt = np.roll(np.arange(loop.size), -1)
            p, q, pe, qe = loop, loop[nxt], ends, ends[nxt]
            newF += [np.stack([p, q, qe], 1), np.stack([p, qe, pe], 1)]
        pos = C[be.second.loop, :2].mean(axis=0)  # where the two sides are glued
        junctions.append(Junction(kind, pos, abs(gap), int(loop.size)))
    if not junctions:
        return V, F, np.arange(F.shape[0]), []
    keep = np.ones(F.shape[0], dtype=bool)
    keep[np.concatenate(drop)] = False
    tubes = np.vstack(newF) if newF else np.zeros((0, 3), np.int64)
    V2 = np.vstack([V, *newV]) if newV else V
    F2 = np.vstack([F[keep], tubes]).astype(np.int64)
    source = np.concatenate([np.flatnonzero(keep), np.full(tubes.shape[0], -1)])
    return V2, F2, source, junctions


def _closed_surface(V, F, R, tol, rel, bridge, report, strict):
    """The whole model opened at its junctions and glued crosswise (``hidden=True``), or None."""
    from types import SimpleNamespace

    from .cutmesh import glue_cut_mesh
    from .order import DepthOrder

    V2, F2, source, junctions = close_junctions(V, F, R, tol, bridge)
    try:
        g = glue_cut_mesh(V2, F2, view=R[2], up=R[1], tol=rel)
    except MescherError as err:
        if strict:
            raise
        msg = f"the closed surface could not be glued ({err}); the visible surface instead"
        report.warnings.append(msg)
        return None
    for p in g["pairings"]:  # cut loops the model came with (a cut model)
        pos = g["xy"][g["vmap"][p.loop_a]].mean(axis=0)
        if not any(np.linalg.norm(pos - j.position) <= 10 * tol for j in junctions):
            junctions.append(Junction("false edge", pos, abs(p.depth_gap), int(p.loop_a.size)))
    if not junctions:
        if strict:
            raise MescherError(
                "hidden: expected junctions to glue (caps that pair up, hidden gaps, cut loops "
                "that coincide on screen), found none"
            )
        return None
    Z = (V2 @ R.T)[F2][:, :, 2]
    order = DepthOrder.from_embedding(SimpleNamespace(F=g["F"], xy=g["xy"]), Z)
    report.junctions = junctions
    report.route = "closed"
    report.reason = (
        f"{len(junctions)} junction(s) found: the whole model opened there and glued crosswise"
    )
    report.arcs = np.asarray(order.arcs)
    report.n_arcs = order.n_arcs
    report.source_face = source
    report.repairs.append(
        f"kept the hidden side: {len(junctions)} junction(s) opened and glued crosswise, "
        f"{int(np.count_nonzero(source < 0))} bridge face(s)"
    )
    return VisibleModel(F=g["F"], xy=g["xy"], Z=Z, arcs=report.arcs, report=report)


# ------------------------------------------------------------------------------ automatic view
#: A hidden gap is looked for on circles passing within this angle of a start view.
START_ANGLE = np.radians(10.0)
#: At most this many pairs of bar ends (the nearest first) are searched for a hidden gap.
MAX_AUTO_BARS = 16


def _occluder_centred_view(V, F, TT, part, be: BarEnds, tol, v0, iters: int = 50):
    """The view on the circle where ``be``'s pieces line up that centres the part hiding the
    gap (seen from ``v0``) on the gap: ``v`` along ``c_occ - p`` with ``c_occ`` the occluding
    part's (area-weighted) centroid and ``p`` the gap's middle on the first piece's line."""
    from .autoview import up_for_view
    from .geometry2d import barycentric

    w = np.cross(be.d, be.T)
    w /= np.linalg.norm(w)
    R = view_frame(v0, up_for_view(v0))
    _, C, front = _parts_and_front(V, F, TT, R)
    found = _junction_at(V, F, C, R, be, tol, front, part, True)
    if found is None or found[0] == "false edge":
        return None
    ell = found[2]
    c0 = V[be.first.loop].mean(axis=0)
    mid = (c0 + 0.5 * ell * be.d) @ R.T
    T = C[F[front]]
    B = barycentric(np.repeat(mid[None, :2], T.shape[0], 0), T[:, :, :2])
    inside = np.flatnonzero(np.all(B >= -1e-9, axis=1))
    z = (B[inside] * T[inside, :, 2]).sum(axis=1)
    occ = part[np.flatnonzero(front)[inside[np.argmax(z)]]]
    Fo = F[part == occ]
    Tw = V[Fo]
    area = 0.5 * np.linalg.norm(np.cross(Tw[:, 1] - Tw[:, 0], Tw[:, 2] - Tw[:, 0]), axis=1)
    c_occ = (area[:, None] * Tw.mean(axis=1)).sum(axis=0) / area.sum()
    v = v0 / np.linalg.norm(v0)
    for _ in range(iters):  # converges in a few steps (the gap's middle moves little)
        M = np.stack([be.d, v], axis=1)
        (ell, _), *_ = np.linalg.lstsq(M, be.T, rcond=None)
        u = c_occ - (c0 + 0.5 * ell * be.d)
        u -= (u @ w) * w
        u /= np.linalg.norm(u)
        if np.linalg.norm(u - v) < 1e-15:
            break
        v = u
    R = view_frame(v, up_for_view(v))
    _, C, front = _parts_and_front(V, F, TT, R)
    found = _junction_at(V, F, C, R, be, tol, front, part, True)
    return None if found is None or found[0] != "hidden gap" else v


def _false_edge_seen(V, F, v, up, tol) -> bool:
    """Does the visible surface from ``v`` glue a false edge with a depth gap (a junction)?"""
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        try:
            vm = see_model(V, F, v, up, tol=tol / diag, bridge=False, hidden=False)
        except MescherError:
            return False
    if not any(j.kind == "false edge" and j.depth_gap > tol for j in vm.report.junctions):
        return False
    return _depths_have_period(vm.F, vm.Z, 10.0 * tol)


def _depths_have_period(F: np.ndarray, Z: np.ndarray, tol: float) -> bool:
    """Do the per-face corner depths ``Z`` fail to integrate on the glued surface ``F``?

    Edge values ``zeta`` (the faces' depth differences, averaged per edge) are integrable iff
    ``zeta = d01 z`` for some ``z``: the least-squares residual (``scipy.sparse.linalg.lsqr``)
    exceeds ``tol`` somewhere exactly when a loop gains depth (a period spreads over its edges).
    """
    from scipy.sparse.linalg import lsqr

    n = int(F.max()) + 1
    a = F.reshape(-1)
    b = F[:, [1, 2, 0]].reshape(-1)
    dz = (Z[:, [1, 2, 0]] - Z).reshape(-1)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    uk, inv = np.unique(key, return_inverse=True)
    sgn = np.where(a < b, 1.0, -1.0)
    zeta = np.bincount(inv, weights=sgn * dz) / np.bincount(inv)
    lo, hi = uk // n, uk % n
    m = uk.size
    D = sp.csr_matrix((np.r_[-np.ones(m), np.ones(m)], (np.r_[np.arange(m), np.arange(m)],
                       np.r_[lo, hi])), shape=(m, n))  # fmt: skip
    z = lsqr(D, zeta, atol=1e-14, btol=1e-14, iter_lim=10 * n)[0]
    return bool(np.abs(D @ z - zeta).max(initial=0.0) > tol)


def find_model_view(V: Any, F: Any, tol: float | None = None, start: Any = None):
    """``view="auto"`` for any model: the view from which its junctions line up.

    1. Coincidences (:func:`meschers_igl.autoview.find_view`, a vote over vertex pairs that
       line up, refined to round-off): taken when a false edge (two caps coinciding on
       screen) or a hidden gap is seen from it -- cut files and capped solids.
    2. Hidden gaps: the two pieces of a broken bar (:func:`bar_end_pairs`, bar direction
       ``d``, pieces ``T`` apart) line up on screen exactly for the views ``v`` in the plane
       of ``d`` and ``T``: one circle of views.  Along it, the view is the one that centres the
       part hiding the gap on the gap (``v`` along the line from the gap's middle to the
       occluder's centroid, iterated with the gap's middle): where an artist puts the crossing
       bar.  The circle is searched from ``start`` (circles within 10 degrees of it) or, from
       the model alone, in 2-degree steps for a view where the gap is hidden (the
       :data:`MAX_AUTO_BARS` pairs of bar ends nearest each other).  A cut model (open loops)
       takes the vote's view, as :func:`~meschers_igl.autoview.find_view` gives it.

    Parameters
    ----------
    V : (#V, 3) array_like of float, F : (#F, 3) array_like of int
        The model (cleaned: welded, oriented outward -- :func:`see_model` passes it so).
    tol : float, optional
        Absolute tolerance (default 1e-5 of the bounding-box diagonal).
    start : (3,) array_like, optional
        A view near the intended one (e.g. off by a few degrees).

    Returns
    -------
    view, up : (3,) float64
        Unit view (toward the camera) and screen up (world +z projected).

    Raises
    ------
    MescherError
        When no view lines up a junction (near ``start``, when given).
    """
    from .autoview import find_view, up_for_view
    from .topology import boundary_loops

    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    diag = float(np.linalg.norm(np.ptp(V[np.unique(F)], axis=0)))
    tol = REL_TOL * diag if tol is None else float(tol)
    if start is not None:
        start = as_points(np.reshape(start, (1, 3)), "start", 3)[0]
        if np.linalg.norm(start) == 0:
            raise MescherError("start: expected a non-zero direction, found (0, 0, 0)")
        start = start / np.linalg.norm(start)
    TT = np.asarray(igl.triangle_triangle_adjacency(F)[0], dtype=np.int64)
    pairs = bar_end_pairs(V, F, tol, TT)
    R0 = view_frame((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))
    part = _parts_and_front(V, F, TT, R0)[0]

    def seen(v):
        R = view_frame(v, up_for_view(v))
        _, C, front = _parts_and_front(V, F, TT, R)
        return any(_junction_at(V, F, C, R, be, tol, front, part, True) for be in pairs)

    err = None
    try:
        v, up = find_view(V, F)
    except MescherError as e:
        v, err = None, e
    # a cut model's junctions are its open loops, which the vote pairs (as autoview does)
    if v is not None and bool(boundary_loops(F)):
        if start is None or v @ start >= np.cos(START_ANGLE):
            return v, up
    near = v is not None and (start is None or v @ start >= np.cos(START_ANGLE))
    # the best-supported direction, when a junction is seen from it (caps that pair up, or a
    # false edge on the visible surface closing a loop that gains depth); a weaker direction
    # lines up pairs by accident (a staircase seen from below, a frame along its diagonal)
    if near and (seen(v) or _false_edge_seen(V, F, v, up, tol)):
        return v, up
    best = None
    # hidden gaps: the bar ends nearest each other first, a bounded number of them
    cand = [be for be in pairs
            if be.d is not None and np.linalg.norm(np.cross(be.d, be.T)) > tol]  # fmt: skip
    cand.sort(key=lambda be: float(np.linalg.norm(be.T)))
    for be in cand[:MAX_AUTO_BARS]:  # a few candidate bar ends
        w = np.cross(be.d, be.T)
        w /= np.linalg.norm(w)
        e1 = be.d
        e2 = np.cross(w, e1)
        if start is not None:
            if abs(start @ w) > np.sin(START_ANGLE):
                continue
            th0 = np.arctan2(start @ e2, start @ e1)
            k = np.repeat(np.arange(1.0, 11.0), 2) * np.tile([-1.0, 1.0], 10)
            steps = th0 + np.radians(np.r_[0.0, k])  # the start first, then 1 degree apart
        else:
            steps = np.radians(np.arange(0.0, 360.0, 2.0))
        # T = l d + g v(theta) in the circle's frame: keep the views with l > 0 and g != 0
        t1, t2 = be.T @ e1, be.T @ e2
        sn = np.sin(steps)
        g = t2 / np.where(np.abs(sn) > 1e-9, sn, np.nan)
        steps = steps[(t1 - g * np.cos(steps) > tol) & (np.abs(g) > tol)]
        vb = None
        for th in steps:  # until a view hiding the gap is met
            v0 = np.cos(th) * e1 + np.sin(th) * e2
            vb = _occluder_centred_view(V, F, TT, part, be, tol, v0)
            if vb is not None:
                break
        if vb is None:
            continue
        score = 0.0 if start is None else -float(vb @ start)
        if best is None or score < best[0]:
            best = (score, vb)
    if best is not None:
        return best[1], up_for_view(best[1])
    if start is not None:
        raise MescherError(
            f"view: expected a view within {np.degrees(START_ANGLE):.0f} degrees of "
            f"{np.round(start, 6).tolist()} from which junctions line up, found none"
        )
    if err is not None:
        raise err
    raise MescherError(
        f"view: expected a view from which junctions line up, found none (tried the view "
        f"{np.round(v, 4).tolist()} lining up the most vertex pairs, and {len(cand)} pair(s) of "
        "bar ends for a hidden gap); pass view= or view_start="
    )
