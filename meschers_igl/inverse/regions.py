"""Regions of a label image as polygons with straight boundaries that neighbours share.

The step between segmenting a picture and triangulating it (:mod:`.picture`): a region's pixels
become shapely boxes, the pixel boundaries between regions become lines made straight, and the
lines are polygonized again, so that two regions meet along one boundary.
"""

from __future__ import annotations

import numpy as np

from ..errors import MescherError

__all__ = ["node_constraints", "region_polygons"]


def pixel_to_screen(res: int) -> float:
    return 2.0 / res


def _pixel_boxes(mask: np.ndarray):
    """The pixels of a mask as shapely boxes, one per run along a row (screen units)."""
    import shapely

    H, W = mask.shape
    px = pixel_to_screen(W)
    ii, jj = np.nonzero(mask)
    start = np.r_[True, (np.diff(jj) != 1) | (np.diff(ii) != 0)]
    run_id = np.cumsum(start) - 1
    j0 = jj[start]
    j1 = np.bincount(run_id).astype(np.int64) + j0
    r = ii[start]
    return shapely.box(-1.0 + j0 * px, 1.0 - (r + 1) * px, -1.0 + j1 * px, 1.0 - r * px)


def region_polygons(labels: np.ndarray, tolerance_px: float = 0.75, extra_lines=()):
    """The regions of a label image as polygons with straight, shared boundaries.

    The pixel boundaries between regions (and the background) are merged into lines between
    junctions (``shapely.line_merge``), each line is simplified on its own with its ends kept
    (Douglas-Peucker, ``tolerance_px``: pixel staircases become straight), and the lines are
    polygonized again.  Neighbours thus share one simplified boundary.

    Parameters
    ----------
    labels : (H, W) int
        Region index per pixel, -1 for the background; the image spans ``[-1, 1]^2``.
    tolerance_px : float
    extra_lines : sequence of shapely LineString
        More boundaries inside regions (hidden occlusion lines, :func:`hidden_occlusions`):
        they split the pieces they cross and become constraints too.

    Returns
    -------
    polygons : list of shapely Polygon
        The pieces, each inside one region.
    region : (P,) int64
        Each piece's region: the majority label of the pixel centres it holds.
    lines : list of shapely LineString
        The simplified boundary lines (constraints of the triangulation).
    """
    import shapely

    H, W = labels.shape
    if H != W:
        raise MescherError(f"labels: expected a square image, found {labels.shape}")
    px = pixel_to_screen(W)
    K = int(labels.max()) + 1
    regions = [shapely.union_all(_pixel_boxes(labels == k)) for k in range(K)]
    edges = shapely.union_all([shapely.boundary(r) for r in regions])
    merged = shapely.line_merge(edges)
    lines = [g for g in getattr(merged, "geoms", [merged])]
    lines = [_straighten(g, px, tolerance_px) for g in lines] + list(extra_lines)
    # straightened neighbours may cross: node them again so that every piece closes
    lines = list(shapely.get_parts(shapely.union_all(lines)))
    pieces = list(shapely.get_parts(shapely.polygonize(lines)))
    # the label of each piece: majority of the pixel centres inside it
    c = -1.0 + (2.0 * np.arange(W) + 1.0) / W
    X, Y = np.meshgrid(c, -c)
    region = np.full(len(pieces), -1, dtype=np.int64)
    for i, poly in enumerate(pieces):
        x0, y0, x1, y1 = poly.bounds
        sel = (X >= x0) & (X <= x1) & (Y >= y0) & (Y <= y1)
        inside = shapely.contains_xy(poly, X[sel], Y[sel])
        lab = labels[sel][inside]
        if lab.size:  # background counts too: a hole stays a hole
            region[i] = np.bincount(lab + 1).argmax() - 1
    keep = region >= 0
    return [p for p, k in zip(pieces, keep) if k], region[keep], lines


def _straighten(line, px: float, tolerance_px: float):
    """A pixel staircase made straight: midpoints of its unit steps, then Douglas-Peucker.

    The corners of a digital line stray up to a pixel from it; the midpoints of its unit
    steps stray at most half a pixel and alternate around it, so a tolerance under a pixel
    leaves one segment per straight boundary.  The ends (junctions) are kept.
    """
    import shapely

    c = np.asarray(shapely.segmentize(line, px * 1.0001).coords)
    closed = bool(np.allclose(c[0], c[-1]))
    if len(c) > 3:
        mid = 0.5 * (c[1:] + c[:-1])
        c = np.vstack([mid, mid[:1]]) if closed else np.vstack([c[:1], mid, c[-1:]])
    return shapely.simplify(shapely.LineString(c), tolerance_px * px, preserve_topology=False)


def node_constraints(chains, grid: float) -> tuple[np.ndarray, np.ndarray]:
    """The vertices and segments of polylines, snap-rounded to ``grid`` and noded.

    A constrained triangulation needs a planar straight-line graph: segments that meet only at
    shared vertices.  Boundaries traced from a picture may leave a vertex a rounding error off
    another segment (a T-junction the segment does not know of), or two segments crossing;
    Triangle's quality refinement can then crash the process (a segfault, which no ``try``
    catches).  Snap rounding (GEOS through ``shapely.unary_union(..., grid_size=grid)``) moves
    every vertex to the grid, merges vertices of one grid cell and splits every segment at each
    vertex and crossing it passes within the grid: the result is a planar graph whose segments
    cover the input's to within ``grid``.

    Parameters
    ----------
    chains : sequence of (k_i, 2) array_like
        Polylines (screen units); those with fewer than two points are ignored.
    grid : float
        The snapping grid (``> 0``; e.g. a thousandth of a pixel).

    Returns
    -------
    verts : (#V, 2) float64
        Distinct vertices on the grid.
    segs : (#S, 2) int64
        Sorted vertex pairs, each once, no segment of length 0.
    """
    import shapely

    if not (np.isfinite(grid) and grid > 0):
        raise MescherError(f"grid: expected a positive number, found {grid}")
    lines = [shapely.linestrings(np.asarray(c, dtype=np.float64)) for c in chains if len(c) >= 2]
    if not lines:
        return np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64)
    noded = shapely.unary_union(shapely.multilinestrings(lines), grid_size=grid)
    coords, part = shapely.get_coordinates(shapely.get_parts(noded), return_index=True)
    within = part[1:] == part[:-1]  # consecutive points of one line: a segment
    a, b = coords[:-1][within], coords[1:][within]
    key = np.round(np.concatenate([a, b]) / grid).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inv = inv.reshape(-1)
    verts = np.concatenate([a, b])[first]
    segs = np.sort(np.stack([inv[: len(a)], inv[len(a) :]], axis=1), axis=1)
    segs = np.unique(segs[segs[:, 0] != segs[:, 1]], axis=0)
    return verts, segs.astype(np.int64)
