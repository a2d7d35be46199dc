"""Start from the picture: a mescher whose topology, faces and depths come from the target.

The initialization, in four steps, none of which renders:

1. :func:`segment_picture`: the figure is every pixel unlike the background; its flat-shaded
   regions are the few grey levels that cover most of it (a z-buffered picture of a polyhedral
   figure under one directional light has one level per face orientation).  Two
   orientations of one shade (both turned away from a given light) are told apart by the
   figure's lines (:func:`.faces.split_shared_shade`).
2. :func:`region_polygons`: each region as polygons (shapely), simplified as a *coverage* so
   that neighbouring regions keep one shared boundary; their union is the silhouette with its
   holes (a Penrose triangle is an annulus, an impossible cube frame has several holes).
3. :func:`triangulate_regions`: Shewchuk's constrained Delaunay triangulation (``triangle``)
   of the silhouette with the region boundaries as constraints, so that no triangle straddles
   two shades.
4. :func:`normals_from_shading` and :func:`lift`: under a known light ``l`` a flat Lambertian
   shade ``I = a + (1 - a) max(0, n . l)`` gives ``n . l``; the figure's three face orientations
   are orthonormal, ``n_k = R e_k``, so ``R^T l = s`` fixes ``R`` up to a turn about ``l``,
   which is chosen so that the boundary between regions ``i`` and ``j`` runs along the screen
   projection of their crease ``n_i x n_j``.  Each triangle then asks for the depth gradient of
   its plane, ``grad z = -(n_x, n_y) / n_z``, on its three edges, and ``zeta = d01 z + H c`` is
   fitted to those wishes by least squares: closed by construction, with the periods ``c`` the
   picture implies.  Before the lift the mesh is cut along occlusions: region boundaries that
   do not run along their crease, the crossbars of T-junctions run on past their stems
   (:func:`.occlusion.crossbar_occlusions`), and (:func:`hidden_occlusions`) the occluding edges no
   picture shows because both sides have one shade (a stair's tread over the tread below),
   followed from where a visible occlusion turns into a crease to a notch of the outline.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numpy as np
import scipy.sparse as sp

from ..errors import MescherError
from ..mescher import Mescher
from ..validate import as_points
from .cuts import (
    _off_outline,
    _one_contact,
    _split_near_outline,
    _to_holes,
    cut_along,
    keep_junctions,
)
from .faces import (
    AMBIENT_LEVELS,
    _three_means,
    _three_means_ranked,
    _two_groups,
    split_shared_shade,
)
from .flatten import as_read, figure_mask
from .metrics import figure_period
from .occlusion import crossbar_occlusions, hidden_occlusions, hidden_steps
from .regions import _tips_through_corners, node_constraints, region_polygons
from .shading import (
    crease_directions,
    crease_misfit,
    crease_sines,
    estimate_exposure,
    estimate_light,
    frames_from_creases,
    normals_from_shading,
)
from .targets import target_mask
from .turn import PICTURE_TURN, _slope_wishes, _weighted_least_squares

_pieces = partial(region_polygons, corners=True)  # to lift: a thin tip through a corner whole

#: The grid (in pixels) region boundaries are snap-rounded to before triangulating: far below
#: anything a picture shows, far above rounding error.
NODE_GRID_PX = 1e-3

#: SoftRas ``sigma`` (squared screen units) at which a picture-made fit ends and renders: the
#: coverage ``sigmoid(d^2 / sigma)`` is within 1% of 0 or 1 beyond ``d = 6.8e-4``, 0.04 pixel
#: at 128 x 128 (0.09 at 256 x 256): the render of a picture sampled at pixel centres, but
#: for pixel centres that nearly touch an edge.
HARD_SIGMA = 1e-7


@dataclass
class Segmentation:
    """What :func:`segment_picture` finds.

    Attributes
    ----------
    mask : (H, W) bool
        Figure pixels.
    labels : (H, W) int64
        Region (shade) index per pixel, -1 on the background.
    shades : (K,) float64
        Grey level of each region (the median of its pixels: a bevel or a small face of a
        fourth shade joined to it leaves it as most of its faces show it; [0, 1]).
    normals : (3, 3) float64 or None
        Row ``k``: the normal of region ``k`` where the lines fixed it (a shade shared by two
        orientations, :func:`.faces.split_shared_shade`); None where the shades will.
    """

    mask: np.ndarray
    labels: np.ndarray
    shades: np.ndarray
    normals: np.ndarray | None = None


def segment_picture(
    target: np.ndarray,
    background=(1.0, 1.0, 1.0),
    min_share: float = 0.04,
    tol: float | None = None,
    line_step: float = 1.5 / 255.0,
    light=None,
    ambient: float = 0.2,
    shared: bool = False,
    alternative: int = 0,
) -> Segmentation:
    """Figure, faces and face orientations of a flat-shaded picture.

    Faces come from lines: a *line* runs between two neighbouring pixels whose grey levels
    (mean of the channels) differ by more than ``line_step``, and the faces are the connected
    pieces of the figure that no line crosses (4-neighbours; a z-buffered face of a polyhedron
    under one directional light is one flat grey, so two faces of shades only a few levels apart
    are still two faces).  The faces' shades are then grouped into the three orientations of a
    figure of boxes: the split of the sorted shades into three groups of least pixel-weighted
    variance (1D k-means, solved exactly); small faces of other orientations (a mitred end)
    join the nearest group.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
    background : (3,) float
    min_share : float
        Smallest share of the figure a group must cover to be an orientation of its own.
    tol : float, optional
        Largest per-channel difference to ``background`` still counted as background; None:
        :func:`.flatten.figure_mask` (on a ground of one exact colour, any other colour).
    line_step : float
        Grey difference across a line.
    light : (3,) float, optional
        Direction toward the light.  Given, a picture of two shades is read as three
        orientations, two of one shade, told apart by the figure's lines
        (:func:`.faces.split_shared_shade`).
    ambient : float
    shared : bool, default: False
        With ``light``: read two orientations of one shade even where three groups are found
        (the caller's frame does not fit their lines, :func:`mescher_from_picture`).
    alternative : int, default: 0
        ``k`` > 0: the shades grouped the ``k``-th next best way (by variance) that differs from
        the best, each group at least ``min_share`` of the figure and parted from the next by a
        jump over ``line_step`` (the caller's frame does not fit the best grouping's lines:
        two orientations a few levels apart taken for one beside a small face of a fourth).

    Returns
    -------
    Segmentation
        ``labels`` holds the orientation group of each pixel (0, 1, 2 by increasing shade).

    Raises
    ------
    MescherError
        No figure (fewer than 16 pixels unlike the background), or fewer than three groups
        whose shades differ by more than ``line_step`` when no ``light`` is given (two
        orientations under one shade, e.g. both turned away from the light: without the light
        nothing says which shade is shared).
    """

    target = np.asarray(target, dtype=np.float64)
    if target.ndim != 3 or target.shape[2] != 3:
        raise MescherError(f"target: expected an (H, W, 3) image, found shape {target.shape}")
    mask = figure_mask(target, background) if tol is None else target_mask(target, background, tol)
    if mask.sum() < 16:
        raise MescherError(
            "target: expected a figure (at least 16 pixels unlike the background "
            f"{np.round(np.asarray(background, dtype=float), 3).tolist()}), found "
            f"{int(mask.sum())}"
        )
    grey = target.mean(axis=-1)
    H, W = grey.shape
    cinv, size, cshade = _faces_between_lines(grey, mask, line_step)
    # the shades of the faces that matter (each at least a quarter of min_share) in three
    # groups: exact weighted 1D 3-means; smaller faces join the nearest group
    big = np.nonzero(size >= 0.25 * min_share * mask.sum())[0]
    order = big[np.argsort(cshade[big])]
    v, w = cshade[order], size[order].astype(np.float64)
    groups = _three_means(v, w)
    while len(v) > 3:
        # a group under min_share is a few faces of other orientations: leave them out
        gs = np.bincount(groups, weights=w, minlength=3) / mask.sum()
        if gs.min() >= min_share:
            break
        keep = groups != int(np.argmin(gs))
        if keep.sum() < 3:
            break
        v, w = v[keep], w[keep]
        groups = _three_means(v, w)
    centre = np.array([v[groups == k].mean() if np.any(groups == k) else np.nan for k in range(3)])
    grp = np.argmin(np.abs(cshade[:, None] - np.nan_to_num(centre, nan=9.0)[None]), axis=1)
    if alternative:
        grp = _other_grouping(cshade, size, big, centre, alternative, min_share, line_step)
    share = np.bincount(grp, weights=size, minlength=3) / mask.sum()
    # groups are distinct where a jump of more than line_step parts them: shades running on
    # in small steps across a split are one orientation (a relief's faces)
    cut = np.diff(groups) > 0
    sep = float((v[1:] - v[:-1])[cut].min()) if len(v) >= 3 else 0.0
    if shared or len(v) < 3 or not sep > line_step or share.min() < min_share:
        two = None if light is None else _two_groups(cshade, size, mask.sum(), line_step, min_share)
        if two is not None:  # two orientations of one shade: the lines tell them apart
            return _one_shade_shared(mask, grey, two[cinv], light, ambient, shared)
        if shared:
            raise MescherError("target: no two shades to read one of them as two orientations")
        found = 1 + int(np.sum(np.diff(v) > line_step))
        raise MescherError(
            "target: expected three face orientations of distinct shades (a figure of boxes "
            f"under one light), found {found} distinct shade(s) (two orientations of one shade, "
            "e.g. both turned away from the light, are told apart by the lines only when the "
            "light is given, and a face as light as the ground not at all; give the light, or "
            "try a picture lit from another side or on another ground)"
        )
    labels = np.full(H * W, -1, dtype=np.int64)
    labels[mask.ravel()] = grp[cinv]
    labels = labels.reshape(H, W)
    # the shade most of an orientation's pixels hold: a bevel or a small face of a fourth
    # shade joined to it must not shift the shade the light and frame are read from
    shades = np.array([np.median(grey[labels == k]) for k in range(3)])
    return Segmentation(mask, labels, shades)


#: Grey levels over which the shades read as one by ``segment_picture(shared=True)`` may
#: spread (10th to 90th percentile of their pixels): a lit orientation whose faces are not
#: quite parallel spans 10 (208-218); a JPEG's three orientations 73 levels apart, two of
#: them read as one, fit their noisy lines better than the right reading.
SHARED_LEVELS = 16.0


#: How much wider (weighted sum of squares about the groups' means) the shades' next
#: grouping may spread than the best for :func:`segment_picture`'s ``alternative`` to read
#: it: only a near tie is for the lines to settle (a sheared tribar's two orientations 16
#: levels apart beside a face of a fourth shade: 1.07; cubes with a bevel of a fourth shade
#: 1.14-1.81).
REGROUP_SPREAD = 2.0


def _spread(v: np.ndarray, w: np.ndarray, g: np.ndarray) -> float:
    """Weighted sum of squares of ``v`` about the weighted mean of each group of ``g``."""
    return float(
        sum(
            np.sum(w[g == j] * (v[g == j] - np.average(v[g == j], weights=w[g == j])) ** 2)
            for j in np.unique(g)
        )
    )


def _one_shade_shared(mask, grey, group, light, ambient: float, asked: bool) -> Segmentation:
    """Two shade groups (``group`` per figure pixel), one shared by two orientations told
    apart by the lines (:func:`.faces.split_shared_shade`); ``asked`` (a reading tried again
    with a shared shade): refused where the shared pixels span over :data:`SHARED_LEVELS`."""
    cg = np.full(mask.shape, -1, dtype=np.int64)
    cg[mask] = group
    lab, sh, nr = split_shared_shade(mask, grey, cg, light, ambient)
    lo, hi = np.percentile(grey[lab >= 1], [10.0, 90.0]) * 255.0
    if asked and hi - lo > SHARED_LEVELS:  # three distinct shades: not one shared
        raise MescherError(
            f"shared: expected two orientations of one shade (within {SHARED_LEVELS} "
            f"levels), found shades {lo:.0f} to {hi:.0f} read as one"
        )
    return Segmentation(mask, lab, sh, nr)


def _other_grouping(cshade, size, big, centre, k: int, min_share: float, line_step: float):
    """The ``k``-th grouping of the ``big`` faces' shades (by variance) unlike the one of
    ``centre`` (:func:`segment_picture`'s ``alternative``): the group of every face, the
    big faces' as grouped, the others' the nearest group's (mean shades weighted by size)."""
    order = big[np.argsort(cshade[big])]
    v, w = cshade[order], size[order].astype(np.float64)
    plain = np.argmin(np.abs(v[:, None] - np.nan_to_num(centre, nan=9.0)[None]), axis=1)
    min_w = min_share * size.sum()
    found = 0
    for g in _three_means_ranked(v, w, min_w, line_step):
        if not np.array_equal(g, plain):
            found += 1
            if found == k:
                ratio = _spread(v, w, g) / max(_spread(v, w, plain), 1e-300)
                if not ratio <= REGROUP_SPREAD:
                    raise MescherError(
                        f"alternative: expected a grouping of the shades nearly as tight as the "
                        f"best (spread within {REGROUP_SPREAD} times), found {ratio:.3g} times"
                    )
                mean = np.array([np.average(v[g == j], weights=w[g == j]) for j in range(3)])
                grp = np.argmin(np.abs(cshade[:, None] - mean[None]), axis=1)
                grp[order] = g
                return grp
    raise MescherError(f"alternative: expected a grouping of the shades, found {found} other(s)")


def _faces_between_lines(grey: np.ndarray, mask: np.ndarray, line_step: float):
    """The figure's pieces that no line crosses (4-neighbours whose grey levels differ by at
    most ``line_step`` are joined): per figure pixel its piece, and per piece its size and mean
    grey level."""
    import scipy.sparse.csgraph as csgraph

    H, W = grey.shape
    idx = np.arange(H * W).reshape(H, W)
    pairs = []
    for a, b, ga, gb in (
        (idx[:, :-1], idx[:, 1:], grey[:, :-1], grey[:, 1:]),
        (idx[:-1], idx[1:], grey[:-1], grey[1:]),
    ):
        same = mask.ravel()[a] & mask.ravel()[b] & (np.abs(ga - gb) <= line_step)
        pairs.append(np.stack([a[same], b[same]], axis=1))
    pr = np.concatenate(pairs)
    G = sp.coo_matrix((np.ones(len(pr)), (pr[:, 0], pr[:, 1])), shape=(H * W, H * W))
    _, comp = csgraph.connected_components(G, directed=False)
    _, cinv, size = np.unique(comp[mask.ravel()], return_inverse=True, return_counts=True)
    cshade = np.bincount(cinv, weights=grey[mask]) / size
    return cinv, size, cshade


def triangulate_regions(
    polygons, region, lines, pixel: float, max_area_px: float = 12.0, min_angle: float = 25.0
):
    """Constrained Delaunay triangulation of the region pieces (``triangle``).

    Parameters
    ----------
    polygons : list of shapely Polygon
        Pieces of the figure (:func:`region_polygons`), screen units.
    region : (P,) int
        Region of each piece.
    lines : list of shapely LineString
        Boundaries, the triangulation's constraints.
    pixel : float
        A pixel's size in screen units.
    max_area_px : float
        Largest triangle area, in pixels.
    min_angle : float
        Smallest angle in degrees (quality refinement).

    Returns
    -------
    xy : (#V, 2) float64
    F : (#F, 3) int64
        Counter-clockwise triangles covering the pieces, none straddling two regions.
    face_region : (#F,) int64
    """
    import shapely
    import triangle

    if not polygons:
        raise MescherError("polygons: expected at least one non-empty region, found none")
    union = shapely.union_all(polygons)
    chains = _split_near_outline([np.asarray(g.coords) for g in lines], union.boundary, pixel)
    # a planar straight-line graph: Triangle's refinement may crash the process on a vertex a
    # rounding error off a foreign segment (regions.node_constraints)
    verts, segs = node_constraints(chains, NODE_GRID_PX * pixel)
    # the figure's holes; an interior under half a pixel is a gap the pieces' rounding left
    # (pieces split by hidden lines), gone once noded: a seed there would eat the triangles
    # around it up to the next constraints
    holes = []
    for p in getattr(union, "geoms", [union]):
        for r in p.interiors:
            if shapely.Polygon(r).area > 0.5 * pixel * pixel:
                holes.append(np.asarray(shapely.Polygon(r).representative_point().coords)[0])
    spec = {"vertices": verts, "segments": segs}
    if holes:
        spec["holes"] = np.asarray(holes)
    area = f"a{max_area_px * pixel * pixel:.3e}"
    tri = None
    # Triangle's quality refinement gives up where constraints nearly touch (a frame of bars
    # two pixels wide): milder settings then
    for opts in (f"pq{min_angle:g}{area}", f"pq10{area}", f"p{area}", "p"):
        try:
            tri = triangle.triangulate(spec, opts)
        except RuntimeError:
            continue
        # out of precision, Triangle may also return overlapping triangles: an edge of three
        T = np.sort(np.asarray(tri["triangles"], dtype=np.int64), axis=1)
        e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [0, 2]]])
        if np.unique(e, axis=0, return_counts=True)[1].max(initial=0) <= 2:
            break
        tri = None
    if tri is None:
        raise MescherError(
            "polygons: expected region boundaries Triangle can triangulate, found boundaries it "
            "rejects at every quality setting (lines closer than floating point can separate)"
        )
    xy = np.asarray(tri["vertices"], dtype=np.float64)
    F = np.asarray(tri["triangles"], dtype=np.int64)
    # region of each triangle: the piece holding its centroid (none: outside the figure)
    cent = shapely.points(xy[F].mean(axis=1))
    face_region = np.full(len(F), -1, dtype=np.int64)
    tree = shapely.STRtree(polygons)
    fi, pi = tree.query(cent, predicate="within")
    face_region[fi] = np.asarray(region)[pi]
    # Triangle removed the holes' and the outside's triangles (segments bound them); what lies
    # in no piece now is a gap under half a pixel the pieces' rounding left: its triangles
    # take the nearest piece's region (dropped, they would leave a pinhole in the mesh, a
    # boundary loop that the cuts would take for a hole)
    gap = np.flatnonzero(face_region < 0)
    if gap.size:
        (gi, pj), dist = tree.query_nearest(cent[gap], return_distance=True)
        near = dist < pixel
        face_region[gap[gi[near]]] = np.asarray(region)[pj[near]]
    keep = face_region >= 0
    F, face_region = F[keep], face_region[keep]
    used = np.unique(F)
    remap = np.full(len(xy), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return xy[used], remap[F], face_region


def region_boundaries(F: np.ndarray, n_vertices: int, xy: np.ndarray, region: np.ndarray):
    """Mesh edges with a different region on each side.

    Returns
    -------
    edges : (#E, 2) int64
        All edges of ``F`` (:func:`meschers_igl.topology.edge_topology`).
    ids : (B,) int64
        The boundary edges between two regions.
    dirs : (B, 2) float64
        Their screen vectors.
    pairs : (B, 2) int64
        The two regions.
    lengths : (B,) float64
    """
    from ..topology import edge_faces, edge_topology

    edges, face_edges, _ = edge_topology(F, n_vertices)
    ef = edge_faces(face_edges, len(edges))
    two = ef[:, 1] >= 0
    ra = np.where(two, region[ef[:, 0]], -1)
    rb = np.where(two, region[np.maximum(ef[:, 1], 0)], -1)
    ids = np.nonzero(two & (ra != rb))[0]
    d = xy[edges[ids, 1]] - xy[edges[ids, 0]]
    return edges, ids, d, np.stack([ra[ids], rb[ids]], axis=1), np.linalg.norm(d, axis=1)


def crease_misalignment(normals: np.ndarray, dirs: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """``|sin|`` of the angle between boundary vectors and their creases' screen projections.

    The crease of two planes with normals ``n_i, n_j`` runs along ``n_i x n_j``; a boundary
    between their regions that does not follow its projection is an occlusion, not a crease.
    """
    return np.abs(crease_sines(normals, dirs, pairs))


def _occlusions(xy, ends, dirs, pairs, normals, occlusion_deg: float, pixel: float):
    """(B,) which region boundaries are occlusions: those more than ``occlusion_deg`` off
    their crease (:func:`crease_misalignment`), and the crossbars of T-junctions run on past
    the stem (:func:`.occlusion.crossbar_occlusions`)."""
    max_sin = math.sin(math.radians(occlusion_deg))
    occl = crease_misalignment(normals, dirs, pairs) > max_sin
    return crossbar_occlusions(xy, ends, pairs, occl, normals, max_sin, pixel)


def _hidden_constraints(hidden: list, pixel: float, past_px: float = 1.5):
    """The hidden lines as constraints (shapely lines) and as the stretches to cut.

    Each starts a quarter pixel back so that it crosses the boundary it starts on (noding; the
    stub outside is not cut); one that ends on another hidden line crosses it by a quarter
    pixel (not cut either), the others run ``past_px`` pixels past the last figure pixel,
    across the straightened outline.  With fitted outlines (``past_px = 0``) a line ending at
    a notch ends on the outline's vertex, and run on it would follow the outline's edge there
    (the same edge of the figure, so nearly along it): noded a hair off the vertex, it would
    touch the outline twice and its cut would be left short of it.
    """
    import shapely

    ext, ident = [], []
    for k, seg_ in enumerate(hidden):
        u = (seg_[1] - seg_[0]) / np.linalg.norm(seg_[1] - seg_[0])
        on = any(_ends_on(seg_[1], s_, 1e-6 * pixel) for j, s_ in enumerate(hidden) if j != k)
        end = seg_[1] + (0.0 if on else past_px) * pixel * u
        ext.append(shapely.LineString([seg_[0] - 0.25 * pixel * u, end + 0.25 * on * pixel * u]))
        ident.append(np.stack([seg_[0], end]))
    return ext, ident


def _segment(q, name: str) -> np.ndarray:
    """``q`` as a (2, 2) float64 segment of two distinct finite points, or a MescherError."""
    a = as_points(q, name, 2, 2)
    if np.allclose(a[0], a[1]):
        raise MescherError(f"{name}: expected segments of two distinct points, found {a.tolist()}")
    return a


def _ends_on(p: np.ndarray, seg: np.ndarray, tol: float) -> bool:
    """Whether the point ``p`` lies on the segment ``seg`` ((2, 2)), within ``tol``."""
    d = seg[1] - seg[0]
    t = float(np.clip((p - seg[0]) @ d / (d @ d), 0.0, 1.0))
    return bool(np.linalg.norm(seg[0] + t * d - p) < tol)


def _piece_weights(
    xy: np.ndarray, F: np.ndarray, region: np.ndarray, small: float, weight: float = 1e-3
) -> np.ndarray:
    """(#F,) ``weight`` for the faces of pieces (faces of one region joined across edges)
    smaller than ``small`` (screen area), 1 for the others."""
    import scipy.sparse.csgraph as csgraph

    from ..topology import edge_faces, edge_topology

    edges, fe, _ = edge_topology(F, len(xy))
    ef = edge_faces(fe, len(edges))
    ok = np.nonzero(ef[:, 1] >= 0)[0]
    ok = ok[region[ef[ok, 0]] == region[ef[ok, 1]]]
    G = sp.coo_matrix((np.ones(len(ok)), (ef[ok, 0], ef[ok, 1])), shape=(len(F),) * 2)
    _, piece = csgraph.connected_components(G, directed=False)
    P = xy[F]
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return np.where(np.bincount(piece, weights=area)[piece] < small, weight, 1.0)


def _edges_on_lines(xy: np.ndarray, edges: np.ndarray, segments, tol: float) -> np.ndarray:
    """Indices of the edges lying on any of the segments (both ends and the midpoint within tol)."""
    import shapely

    if not segments:
        return np.zeros(0, dtype=np.int64)
    ml = shapely.MultiLineString([np.asarray(s_) for s_ in segments])
    pts = np.concatenate(
        [xy[edges[:, 0]], xy[edges[:, 1]], 0.5 * (xy[edges[:, 0]] + xy[edges[:, 1]])]
    )
    near = shapely.dwithin(shapely.points(pts), ml, tol).reshape(3, -1).all(axis=0)
    return np.nonzero(near)[0]


def lift(
    xy: np.ndarray,
    F: np.ndarray,
    face_normals: np.ndarray,
    weights: np.ndarray | None = None,
    climbs: np.ndarray | None = None,
) -> Mescher:
    """The mescher on ``(F, xy)`` whose faces best take the planes of ``face_normals``.

    Each face ``f`` wishes its half-edges ``i -> j`` to climb ``g_f . (xy_j - xy_i)`` with
    ``g_f = -(n_x, n_y) / n_z``.  ``zeta = d01 z + H c`` minimizes the (weighted) squared misfit
    over ``z`` and the periods ``c``: every wish consistent with its neighbours is met exactly
    and ``d12 zeta = 0`` by construction.

    Parameters
    ----------
    xy : (#V, 2) float
    F : (#F, 3) int
    face_normals : (#F, 3) float
        Unit normals with ``n_z > 0``.
    weights : (#F,) float, optional
    climbs : (#F, 3) float, optional
        Added to the wishes of the half-edges opposite each corner: a step the faces climb in
        place (:func:`.occlusion.hidden_steps`).

    Returns
    -------
    Mescher
    """
    from .sobolev import closed_harmonic_basis

    n = np.asarray(face_normals, dtype=np.float64)
    if n.shape != (len(F), 3) or np.any(n[:, 2] <= 0):
        raise MescherError(f"face_normals: expected ({len(F)}, 3) with n_z > 0, found {n.shape}")
    m0 = Mescher.from_corner_depths(F, xy, np.zeros((len(F), 3)))
    B, wish = _slope_wishes(m0, n)
    if climbs is not None:
        wish = wish + np.asarray(climbs, dtype=np.float64).reshape(-1)
    H = closed_harmonic_basis(m0)
    A = sp.hstack([B @ m0.d01, sp.csr_matrix(B @ H)]).tocsr()
    sol = _weighted_least_squares(A, wish, weights)
    nv = m0.n_vertices
    zeta = m0.d01 @ sol[:nv] + H @ sol[nv:]
    return m0.with_zeta(zeta)


def _reading_light(light, shades, ambient: float, d, pairs, lens, labels=None) -> np.ndarray:
    """The unit light: the one given, or :func:`estimate_light` on the frame the creases give
    (sharpened on the ``labels``; of the two Necker readings, which light the picture alike
    from ``(lx, ly, lz)`` and ``(-lx, -ly, lz)``, the one lit from above, as a person reads
    it)."""
    if light is None:
        frames = frames_from_creases(crease_directions(d, pairs, lens, labels))
        lights = [estimate_light(shades, N, ambient) for N in frames]
        light = lights[0] if lights[0][1] >= lights[1][1] else lights[1]
    light = np.asarray(light, dtype=np.float64)
    return light / np.linalg.norm(light)


#: A frame's misfit to the region boundaries (weighted mean ``sin^2``, :func:`crease_misfit`)
#: over which the picture is read the other ways it allows and the reading whose frame fits
#: its lines best is kept: the shades grouped the next best way (``segment_picture(
#: alternative=1)``: two orientations a few levels apart beside a small face of a fourth
#: shade) and, with the light given, two orientations sharing a shade
#: (``segment_picture(shared=True)``: two faces two levels apart near the ambient shade, one
#: lit at a grazing angle; a lit orientation whose faces vary by a few levels split in two).
#: Three shades that fit come before a shade shared by two orientations (which fits its
#: lines by construction).  Right readings of the benchmark's pictures measure at most 0.025;
#: those the retries mend 0.028-0.059.
RETRY_MISFIT = 0.025


def _faces_and_frame(target, background, light, ambient, tolerance_px, straighten, max_area_px):
    """Segmentation, triangulated regions and their frame: ``(seg, xy, F, region, (edges, ids,
    d, pairs, lens), light, normals, misfit, exposure, other)``, ``other`` the reading with the
    picture's 2 x 2 checkerboards resolved the other way, where it has any (its lines misfit
    the frame more, or its frame none, ``other[-1]`` None).  Three lit shades of a figure that
    is not white (:func:`.shading.estimate_exposure`) are read as the white figure's, the
    shades over ``exposure``.  A frame misfitting the lines by more than :data:`RETRY_MISFIT`
    (or no frame at all) is tried against the other readings the picture allows, in turn
    until one fits, and the one fitting its lines best is kept."""
    given = light is not None

    def read(seg):  # with 2 x 2 checkerboards made whole or not: the lines' better fit first
        out = read_once(seg)
        every = _tips_through_corners(seg.labels, every=True)
        if np.any(every != _tips_through_corners(seg.labels)):
            try:
                other = read_once(replace(seg, labels=every))
            except MescherError:
                return out
            return (*other[:-1], out) if other[7] < out[7] else (*out[:-1], other)
        return out

    def read_once(seg):
        polys, preg, lines = _pieces(seg.labels, tolerance_px, straighten=straighten)
        pixel = 2.0 / seg.labels.shape[1]
        xy, F, region = triangulate_regions(polys, preg, lines, pixel, max_area_px)
        _, _, d, pairs, lens = bounds = region_boundaries(F, len(xy), xy, region)
        exposure = 1.0 if seg.normals is not None else estimate_exposure(seg.shades, ambient)
        shades = seg.shades / exposure
        light_used = _reading_light(light, shades, ambient, d, pairs, lens, seg.labels)
        if seg.normals is not None:
            misfit = crease_misfit(seg.normals, d, pairs, lens)
            return seg, xy, F, region, bounds, light_used, seg.normals, misfit, 1.0, None
        normals, misfit = normals_from_shading(shades, light_used, ambient, d, pairs, lens)
        return seg, xy, F, region, bounds, light_used, normals, misfit, exposure, None

    kw = {"light": light, "ambient": ambient}
    seg = segment_picture(target, background, **kw)
    try:
        out, failed = read(seg), None
    except MescherError as e:  # no frame fits the lines: perhaps another reading's
        out, failed = None, e
    if out is not None and (seg.normals is not None or not out[7] > RETRY_MISFIT):
        return out
    if seg.normals is not None:  # two shades, read once: no other reading to try
        raise failed
    for retry in ({"alternative": 1}, {"shared": True}):
        if "shared" in retry and not given:
            continue
        try:
            other = read(segment_picture(target, background, **kw, **retry))
        except MescherError:
            continue
        if out is None or other[7] < out[7]:
            out = other
        if not out[7] > RETRY_MISFIT:  # three shades that fit before one shared by two
            break
    if out is None:
        raise failed
    return out


def mescher_from_picture(
    target: np.ndarray,
    light=None,
    ambient: float = 0.2,
    background=(1.0, 1.0, 1.0),
    max_area_px: float = 12.0,
    tolerance_px: float | None = None,
    occlusion_deg: float = 15.0,
    complete: bool = True,
    small_px: float = 8.0,
    reach_px: float = 3.0,
    straighten: str = "douglas-peucker",
    steps=None,
) -> tuple[Mescher, np.ndarray, dict]:
    """The initialization from a picture: segment, triangulate with holes, lift from shading.

    Boundaries between two shade regions that do not run along their crease (more than
    ``occlusion_deg`` off) are occlusions: one surface passes in front of the other there, so the
    mesh is cut open along them before the lift (each side keeps its own depth), and along the
    crossbars of T-junctions past their stems (:func:`.occlusion.crossbar_occlusions`).

    Parameters
    ----------
    target : (N, N, 3) float in [0, 1]
        Spans the screen square ``[-1, 1]^2``.
    light : (3,) float, optional
        Direction toward the (one, white) light, camera frame.  None: estimated
        (:func:`_reading_light`).
    ambient : float
    background : (3,) float
    max_area_px, tolerance_px : float
        Triangle size and boundary straightening, in pixels (``tolerance_px`` None: the
        ``straighten`` method's default, :func:`.regions.region_polygons`).
    occlusion_deg : float
    complete : bool, default: True
        Also cut along the occlusion lines the picture cannot show, between faces of one shade
        (:func:`.occlusion.hidden_occlusions`; a stair's tread over the one below), on to the
        outline, a hole or another hidden line; no piece of the cut touches the boundary twice
        (:func:`_one_contact`), so the loop that carries the period stays whole.  Read from jogs
        a few pixels long (the Penrose stairs at 128 px, rises of 3.5 px: all eight steps).
    small_px : float
        Pieces (faces of one region joined across edges) under this many square pixels weigh
        ``1e-3`` in the lift (a sliver of an end face under a stair's wall): it makes up for lost
        steps; where a turn climbs its step (:func:`.occlusion.hidden_steps`) it overshoots 0-5%.
    reach_px : float
        A slit of the cut this many pixels (along mesh edges) from a hole runs on to it
        (:func:`_to_holes`).
    straighten : {"douglas-peucker", "fit"}
        How region boundaries become straight (:func:`.regions.region_polygons`).
    steps : sequence of (2, 2) float, optional
        Known occlusion lines between faces of one shade (screen units; a drawing's lines
        between parallel faces, ``DrawingReading.steps``): cut along these, not ``complete``'s.

    Returns
    -------
    m : Mescher
    region : (#F,) int64
        Shade region of each face.
    info : dict
        ``normals`` (3, 3) per region, ``shades`` (3,), ``misfit`` (frame fit),
        ``occlusion_length`` (screen units of cut boundary), ``labels`` (H, W),
        ``hidden_lines`` (list of (2, 2) segments, :func:`hidden_occlusions`), ``light``
        (3,) the unit light used (given or estimated), ``unseen_turn`` (two orientations both
        at the ambient shade: the picture does not show how their faces turn), ``flattened``
        (the picture was not flat and was read as :func:`.flatten.flatten_picture` made it),
        ``antialiased`` (:func:`.flatten.is_antialiased`: the fit averages samples over each
        pixel, :func:`fit_options`), ``exposure`` (:func:`.shading.estimate_exposure`: the
        figure's brightness, 1 for a white one; :func:`picture_shading` renders with it),
        ``outlines`` (H, W) bool: dark lines drawn along the edges, read as the faces beside
        them (:func:`.flatten.drop_outlines`).
    """
    if steps is not None:
        steps = [_segment(q, "steps") for q in steps]
    target, kind = as_read(target, background)
    reading = _faces_and_frame(
        target, background, light, ambient, tolerance_px, straighten, max_area_px
    )
    opts = (steps, complete, tolerance_px, straighten, max_area_px, occlusion_deg, reach_px)
    m, region, hidden, occl_len = _cut_and_lift(reading, *opts, small_px)
    if reading[-1] is not None:
        # a checkerboard made whole where two surfaces part pins them together, and the lift
        # bends part of the climb away: of the two readings, the one that climbs more
        m2, region2, hidden2, occl_len2 = _cut_and_lift(reading[-1], *opts, small_px)
        if figure_period(m2) > (1.0 + CLIMB_MARGIN) * figure_period(m):
            reading, m, region, hidden, occl_len = reading[-1], m2, region2, hidden2, occl_len2
    seg, _, _, _, _, light, normals, misfit, exposure, _ = reading
    unseen = (
        seg.normals is not None and int(np.sum(seg.shades - ambient < AMBIENT_LEVELS / 255)) >= 2
    )
    info = {
        "normals": normals,
        "shades": seg.shades,
        "misfit": misfit,
        "occlusion_length": occl_len,
        "labels": seg.labels,
        "hidden_lines": hidden,
        "light": light,
        "unseen_turn": unseen,
        "exposure": exposure,
        **kind,
    }
    return m, region, info


#: The checkerboards' other reading is kept where it climbs more than this share over the
#: first (the two differ by a fifth or more where one pins the loop; 0-2% otherwise).
CLIMB_MARGIN = 0.05


def _cut_and_lift(
    reading, steps, complete, tolerance_px, straighten, max_area, occl_deg, reach_px, small_px
):
    """A reading of :func:`_faces_and_frame` cut open along its occlusions and lifted
    (:func:`mescher_from_picture`): the mescher, its faces' regions, the hidden lines and the
    length of the occluding boundary."""
    seg, xy, F, region, bounds, _, normals, _, _, _ = reading
    edges, ids, d, pairs, lens = bounds
    pixel = 2.0 / seg.labels.shape[1]
    occl = _occlusions(xy, edges[ids], d, pairs, normals, occl_deg, pixel)
    hidden = list(steps) if steps is not None else []
    if steps is None and complete:
        hidden = hidden_occlusions(seg.labels, xy, F, region, edges, ids, pairs, occl, normals)
    hidden_edges = []
    if hidden:
        ext, ident = _hidden_constraints(hidden, pixel, 0.0 if straighten == "fit" else 1.5)
        polys, preg, lines = _pieces(seg.labels, tolerance_px, ext, straighten)
        xy, F, region = triangulate_regions(polys, preg, lines, pixel, max_area)
        edges, ids, d, pairs, lens = region_boundaries(F, len(xy), xy, region)
        occl = _occlusions(xy, edges[ids], d, pairs, normals, occl_deg, pixel)
        hidden_edges = [_edges_on_lines(xy, edges, [i_], 1e-3 * pixel) for i_ in ident]
    # visible occlusions stop short of the outline, hidden ones run on to it unless their cut
    # touches the boundary already; slits short of a hole run on to it; junctions held whole
    seen = _off_outline(F, xy, edges, ids[occl])
    cut = _one_contact(F, edges, seen, hidden_edges)
    cut = _one_contact(F, edges, cut, _to_holes(F, xy, edges, cut, seen, reach_px * pixel))
    xy, F, region, edges, cut = keep_junctions(xy, F, region, edges, cut, seen, ids, pairs, pixel)
    climbs = hidden_steps(xy, F, edges, cut, hidden, hidden_edges, normals, region)
    xy, F = cut_along(xy, F, edges, cut)
    # pieces of a few pixels (a sliver of an end face under a stair's wall) follow their
    # neighbours instead of voting (:func:`_piece_weights`)
    m = lift(xy, F, normals[region], _piece_weights(xy, F, region, small_px * pixel**2), climbs)
    return m, region, hidden, float(lens[occl].sum())


def picture_shading(info: dict, ambient: float = 0.2) -> dict:
    """The shading a picture-made mescher is fitted and rendered with.

    ``lights`` (the one the picture was read under), ``light_colors`` and ``ambient`` scaled
    by the picture's ``exposure``: a grey figure renders ``exposure * (ambient + (1 -
    ambient) max(0, n dot l))``; for :func:`.optimize.fit_mescher` and
    :func:`.rasterizer.render_mescher`.

    Parameters
    ----------
    info : dict
        Of :func:`mescher_from_picture`.
    ambient : float
        The ambient share the picture was read with.
    """
    e = float(info.get("exposure", 1.0))
    grey = e * (1.0 - float(ambient))
    return {
        "lights": [tuple(float(v) for v in info["light"])],
        "light_colors": [(grey, grey, grey)],
        "ambient": e * float(ambient),
    }


def fit_options(iters: int = 300, power: int = 1, info: dict | None = None, **overrides):
    """:class:`.optimize.InverseOptions` for refining a picture-made mescher.

    The start already has the right faces, so the SoftRas blur stays within a pixel or two
    (``sigma`` from ``2e-4`` for xy, ``1e-4`` for zeta, a pixel being ``2.4e-4`` at 128 x 128)
    and both schedules end at :data:`HARD_SIGMA`, the sharpness of the returned render and of
    the PSNR checks: the picture is sampled at pixel centres with no anti-aliasing, so the last
    steps minimize the error of the nearly hard render that is measured and kept.  A
    blurrier end (``1e-5``: a soft border 0.4 pixel deep on either side of every edge at
    128 x 128) minimizes an error that weighs every pixel centre within that border: the
    edges balance them, and on a short stretch of staircase pass on the far side of a centre
    near the line, single wrong pixels along every edge (the impossible cube of
    ``bench_inverse_real`` under its light 2: 29.2 dB and 274 pixels off by more than 0.1 at
    ``1e-5``, 38.5 dB and 64 at :data:`HARD_SIGMA`).  The steps are small, the offsets stay
    (the figure does not overlap itself where it was not cut), ``lambda = 1`` with the
    uniform Laplacian (largesteps' choice) and the best nearly-hard PSNR seen every 20 steps
    is kept; with :func:`.optimize.fit_mescher`'s
    ``face_normals`` (``info["normals"][region]``) each face's normal is held to its shade
    region's by a small penalty (:data:`.turn.PICTURE_TURN`).  The periods move at ``1e-2``
    depth units per step: where the lift met a step it could not see, the faces it bent shade
    wrongly, and the image pulls the periods toward the picture's.  Where ``info`` (of
    :func:`mescher_from_picture`) says two orientations are both turned away from the light,
    any turn of their faces shades them alike, the image cannot hold the periods and they stay
    as the lines gave them (``lr_periods = 0``); so they do where the lift cut hidden lines
    (``info["hidden_lines"]``): the steps no picture shows are then cut, not bent, and the
    image has nothing to say about their height (Penrose stairs seen from (1, 1, 2), light
    (0.19, -0.2, 0.96), before its turn climbed its step: 1.32 from the picture against the
    true 1.39, 1.28 after 300 steps at ``1e-2``).  An antialiased picture
    (``info["antialiased"]``) is compared with a render that averages 4 x 4 samples per pixel
    (``supersample``), as its renderer made it; a JPEG of a picture sampled at pixel centres
    is not (bench_inverse_real's JPEG pictures: 34 of 60 pass sampled at centres, 24 averaged).
    """
    from .optimize import InverseOptions

    kw = dict(
        iters=iters,
        power=power,
        lam=1.0,
        laplacian="uniform",
        lr_xy=3e-3,
        lr_z=3e-3,
        lr_periods=1e-2,
        lr_offsets=0.0,
        sigma_xy=(2e-4, HARD_SIGMA),
        sigma_zeta=(1e-4, HARD_SIGMA),
        final_sigma=HARD_SIGMA,
        eval_every=20,
        turn=PICTURE_TURN,
    )
    if info is not None and (info.get("unseen_turn") or len(info.get("hidden_lines", ())) > 0):
        kw["lr_periods"] = 0.0
    if info is not None and info.get("antialiased"):
        kw["supersample"] = 4
    kw.update(overrides)
    return InverseOptions(**kw)
