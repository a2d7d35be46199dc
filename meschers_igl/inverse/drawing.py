"""A black-on-white line drawing of a figure of boxes read as a shaded picture.

A person reads a drawing of a Penrose triangle, a Reutersvärd triangle or an impossible cube
as faces of three orientations: the closed regions between the lines are the faces, the three
directions the lines run in are the screen projections of three right-angled directions
(a Manhattan reading), and a face is spanned by the two directions its edges follow.  This
module makes that reading into the flat-shaded picture the rest of the pipeline takes
(:func:`meschers_igl.inverse.picture.mescher_from_picture`):

1. :func:`is_line_drawing`: dark lines on a light ground, nearly nothing in between.
2. :func:`shade_drawing`: the regions of paper no line crosses; the one touching the border is
   the ground.  The lines' directions (length-weighted orientation histogram of the regions'
   straightened outlines) give three directions and, by :func:`.picture.frames_from_creases`,
   the right-angled frame (of its two Necker readings, the one seen from above).  A region
   whose edges follow two of the directions is a face of the third direction's orientation;
   a region with edges along all three (the hole of a tribar) or along none is a hole, and so
   is one a heavier outline closes all round where the drawing's outline is heavier than its
   inner lines (:func:`_outlined`: the outline runs round a hole as round the figure).  A
   face's own edges leave out the crossbars of the T-junctions it ends at (:func:`_crossbars`:
   a post's edge is not the edge of the bar behind it).  A face whose edges allow two
   orientations takes the one under which its lines with its neighbours are creases
   (:func:`_by_creases`); two such faces side by side along their one direction are a bar's
   two faces seen from above (:func:`_bars_from_above`).  Each face is painted with the
   Lambertian shade of its normal under a light that gives the three orientations three
   distinct shades, and each line pixel takes the colour of the nearest face or hole, so that
   the figure's outline runs along the middle of its outer lines.  The lines between two faces
   of one orientation, which the shaded picture cannot show, are kept as ``steps`` for the
   lift to cut along.

Darkness is measured against the paper (``1 - grey / paper``): a drawing on cream paper, saved
as JPEG, scanned, blurred or resized reads as the clean one (:data:`NOISE_DARKNESS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import MescherError
from .faces import _segments, line_directions
from .regions import labels_at

#: the frame's Lambertian terms n_k . l of the light painting a drawing: three distinct shades
DRAWING_SHADES = np.array([0.42, 0.63, 0.93])


@dataclass
class DrawingReading:
    """What :func:`shade_drawing` reads.

    Attributes
    ----------
    picture : (N, N, 3) float64
        The drawing as a flat-shaded picture on the drawing's ground colour.
    faces : (N, N) int64
        Face region per pixel (line pixels given to the nearest region), -1 on the ground and
        in holes.
    orientation : (R,) int64
        Orientation (0, 1, 2) of each face region, -1 for holes.
    normals : (3, 3) float64
        Row ``k``: the normal of orientation ``k`` (camera frame, ``n_z > 0``).
    directions : (3, 2) float64
        Unit screen direction of the lines along axis ``k`` (the projection of ``normals[k]``).
    light : (3,) float64
        The light that paints ``picture``.
    steps : list of (2, 2) float64
        The lines drawn between two faces of one orientation (screen units, the drawing
        spanning ``[-1, 1]^2``): one face passes in front of a parallel one there (a stair's
        tread over the one below), which the shaded picture cannot show.
    """

    picture: np.ndarray
    faces: np.ndarray
    orientation: np.ndarray
    normals: np.ndarray
    directions: np.ndarray
    light: np.ndarray
    steps: list


#: a bar's band seen between two posts (:func:`_bars_from_above`) follows one direction
#: with all but this share of its outline: besides its long edges it keeps short pieces of
#: its ends that are not read as the posts' edges (a pixel's jog where a scan's noise moved
#: the line), up to a fifth of it
BAND_SHARE = 0.2

#: a faint line's pixels (a slanted line thinner than a pixel) are over this darkness, and
#: so is the darkness smoothed over :data:`FAINT_SMOOTH_PX` along their ridge
FAINT_DARKNESS = 0.1
FAINT_SMOOTH_PX = 1.0

#: darkness against the paper (``1 - grey / paper``) a line pixel exceeds: a scan's or a
#: JPEG's noise and ringing stay under it
NOISE_DARKNESS = 0.25


def is_line_drawing(
    target: np.ndarray,
    background=(1.0, 1.0, 1.0),
    black: float = 0.5,
    thin_px: int | None = None,
    ink: float = NOISE_DARKNESS,
) -> bool:
    """Whether a picture is dark lines on a light ground rather than shaded faces.

    Darkness is measured against the paper: ``1 - grey / paper`` (a cream paper, a scan's
    grey ground).  True when the ground is light, the ink (pixels over ``ink`` dark: not the
    paper's noise or a JPEG's ringing) is dark at the lines' middles (the median of the ink
    pixels that are the darkest of their 3 x 3 neighbourhood over ``black``: an antialiased,
    blurred or downsampled line's flanks are grey, its middle is not), thin (an erosion by
    ``thin_px`` pixels, default one per 256 pixels of the picture's size and two at least,
    leaves under 15% of it: lines, not faces) and encloses paper inside the figure's outline.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
    background : (3,) float
    black : float
    thin_px : int, optional
    ink : float
    """
    from scipy import ndimage

    t = np.asarray(target, dtype=np.float64)
    paper = float(np.mean(background))
    if t.ndim != 3 or paper < 0.75:
        return False
    grey = t.mean(axis=-1)
    dark = _darkness(t, background)
    mask = dark > ink
    if mask.sum() < 16:
        return False
    middle = mask & (grey <= ndimage.minimum_filter(grey, size=3))
    if float(np.median(dark[middle])) < black:
        return False
    if thin_px is None:
        thin_px = max(2, round(max(t.shape[:2]) / 256))
    if ndimage.binary_erosion(mask, iterations=thin_px).sum() > 0.15 * mask.sum():
        return False
    filled = ndimage.binary_fill_holes(mask)
    return bool((filled & ~mask).sum() > 0.5 * mask.sum())


def narrowest_face_px(faces: np.ndarray, min_share: float = 0.002) -> float:
    """Width in pixels of the narrowest face of a drawing: the diameter of the largest disc
    inside each face (twice the largest distance from one of its pixels to the face's border,
    half a pixel past its edge pixels' centres), least over the faces covering at least
    ``min_share`` of the figure.

    A mesh read from a picture resolves a face some pixels wide; a bar drawn two or three
    pixels wide comes out in slivers and wedges.  The working size a drawing is read at
    follows from this width (``meschers inverse``).

    Parameters
    ----------
    faces : (N, N) int
        Face region per pixel, -1 off the figure (:attr:`DrawingReading.faces`).
    min_share : float
        Faces smaller than this share of the figure's pixels (a corner's sliver) are left out.

    Returns
    -------
    float
        Pixels of ``faces``; ``inf`` without a face.
    """
    import scipy.ndimage as ndi

    f = np.asarray(faces)
    if f.ndim != 2:
        raise MescherError(f"faces: expected an (N, N) label image, found shape {f.shape}")
    # pixels next to another region (or the ground) are each face's boundary
    edge = np.zeros(f.shape, dtype=bool)
    for a, b in ((f[:-1], f[1:]), (f[:, :-1], f[:, 1:])):
        differ = a != b
        edge[: differ.shape[0], : differ.shape[1]] |= differ
        edge[f.shape[0] - differ.shape[0] :, f.shape[1] - differ.shape[1] :] |= differ
    dist = ndi.distance_transform_edt(~edge)
    labs = np.unique(f[f >= 0])
    if labs.size == 0:
        return math.inf
    area = np.bincount(f[f >= 0], minlength=int(labs.max()) + 1)[labs]
    width = 2.0 * np.asarray(ndi.maximum(dist, f, labs), dtype=np.float64) + 1.0
    big = area >= min_share * area.sum()
    return float(width[big].min()) if big.any() else math.inf


def _darkness(t: np.ndarray, background) -> np.ndarray:
    """(H, W) darkness against the paper, ``1 - grey / paper`` (the paper's grey: the mean of
    ``background``)."""
    return 1.0 - t.mean(axis=-1) / float(np.mean(background))


def _line_pixels(dark: np.ndarray, ink: float) -> np.ndarray:
    """(N, N) bool: a drawing's line pixels, from its darkness against the paper.

    A line pixel is over ``ink`` times as dark as the darkest pixel near it (a blurred or
    downsampled line is grey at its middle) or a line's middle (:func:`_ridges`: a faint line
    where it meets a dark one), and darker than the paper's noise (:data:`NOISE_DARKNESS`).
    A line thinner than a pixel drawn at a slant spreads its ink over two pixels of each
    column or row, both under the noise's darkness in places: dashed, and the paper leaks
    through.  Smoothed over :data:`FAINT_SMOOTH_PX` it is a ridge again, far over the noise
    smoothed (a scan's 0.03 becomes 0.01); its pixels with ink on that ridge are line pixels
    too.
    """
    from scipy import ndimage

    N = dark.shape[0]
    peak = ndimage.maximum_filter(dark, size=3 + 2 * (N // 512))
    line = ((dark > ink * peak) | _ridges(dark)) & (dark > NOISE_DARKNESS)
    smooth = ndimage.gaussian_filter(dark, FAINT_SMOOTH_PX)
    return line | (_ridges(smooth) & (smooth > FAINT_DARKNESS) & (dark > FAINT_DARKNESS))


def _ridges(dark: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels darker than both their neighbours across one of the four pixel
    directions, a line's middle (also where a faint line meets a dark one, whose darkness
    the faint line's pixels next to it are not half of), and the pairs of pixels darker than
    the two either side of the pair (a line under two pixels wide whose ink two pixels
    share: where such a line meets a heavy one, neither is half as dark as the heavy one nor
    darker than both its neighbours, and the faces either side of the line met there)."""
    H, W = dark.shape
    p = np.pad(dark, 2, mode="edge")
    c = p[2:-2, 2:-2]

    def at(di, dj):  # the neighbours ``(di, dj)`` pixels off
        return p[2 + di : 2 + di + H, 2 + dj : 2 + dj + W]

    out = np.zeros((H, W), dtype=bool)
    for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
        a, b = at(-di, -dj), at(di, dj)
        out |= (c > a) & (c > b)
        # a line a pixel wide or less whose ink falls on two pixels (a downscaled drawing's):
        # the pair darker than the pixels either side of it
        out |= (c > a) & (c >= b) & (b > at(2 * di, 2 * dj))
        out |= (c > b) & (c >= a) & (a > at(-2 * di, -2 * dj))
    return out


def _frame_directions(
    lines, polys, piece_region, n_regions: int, pixel: float, tolerance_px: float
):
    """The three main directions of a drawing's lines, and each region's outline along each.

    The directions are read from the ``lines`` simplified over their pixel steps (a pixel's
    tolerance at least, or ``tolerance_px``; :func:`.faces._segments`), from segments 3
    pixels long at least: a shallow line's staircase of flat runs and diagonal steps is
    neither direction, and along a long line the steps outweigh a figure's short edges.  They
    are ranked as the ``lines`` as traced rank them (a drawing's shades follow the rank).

    Parameters
    ----------
    lines : list of shapely LineString
        Straightened boundaries (:func:`.picture.region_polygons`), screen units.
    polys : list of shapely Polygon
        The pieces; ``piece_region`` their region.
    n_regions : int
    pixel : float
        A pixel's size (screen units).
    tolerance_px : float

    Returns
    -------
    dirs : (3, 2) float64
        Unit directions (:func:`.faces.line_directions`).
    along : (R, 3) float64
        Length of each region's outline within 10 degrees of each direction.
    total : (R,) float64
        Length of each region's outline.
    """

    def directions(tolerance):  # two orientations are at least 20 degrees apart
        a, b = _segments(lines, tolerance)
        return line_directions(a, b, k=3, apart_deg=20.0, min_length=3.0 * pixel)

    dirs = directions(max(1.0, tolerance_px) * pixel)
    rank = np.argmax(np.abs(directions(0.0) @ dirs.T), axis=1)
    if np.unique(rank).size == 3:
        dirs = dirs[rank]
    return (dirs, *_outline_shares(polys, piece_region, n_regions, dirs))


def _outline_shares(polys, piece_region, n_regions: int, dirs: np.ndarray):
    """``along`` (R, 3): the length of each region's outline within 10 degrees of each of the
    directions ``dirs`` (3, 2); ``total`` (R,): the length of its outline."""
    along = np.zeros((n_regions, 3))
    total = np.zeros(n_regions)
    cos10 = math.cos(math.radians(10.0))
    for poly, r in zip(polys, piece_region):  # a handful of pieces
        for ring in [poly.exterior, *poly.interiors]:
            v = np.diff(np.asarray(ring.coords), axis=0)
            lv = np.linalg.norm(v, axis=1)
            u = v / np.maximum(lv[:, None], 1e-300)
            along[r] += ((np.abs(u @ dirs.T) > cos10) * lv[:, None]).sum(axis=0)
            total[r] += lv.sum()
    return along, total


def _outlined(
    t: np.ndarray,
    line: np.ndarray,
    ground: np.ndarray,
    reg: np.ndarray,
    n_regions: int,
    heavier: float = 1.5,
    radius: int = 3,
) -> np.ndarray:
    """Which regions a heavier outline closes all round: the holes of a drawing whose outline
    is drawn heavier than its inner lines (the drafting convention, and the project's own line
    art), as the outline runs round a hole as round the figure.

    A line's width is its ink across it: the ink ``1 - grey`` within ``radius`` pixels of a line
    pixel over the disc's diameter, so antialiased flanks count as the part of a pixel they
    cover.  The outline's width is the median over the line pixels next to the ground; the
    drawing is weighted when 15% of the other line pixels are ``heavier`` times thinner (the
    heavy lines have the most pixels, so a median would not tell).
    A region is outlined when nine in ten of the line pixels within two pixels of its paper
    are over 0.8 of the outline's width, and none of its paper is within the outline's width
    and two pixels of the ground (a face on the figure's rim is closed by the outline too).

    Returns
    -------
    (R,) bool
    """
    from scipy import ndimage

    ink = np.clip(1.0 - t.mean(axis=-1), 0.0, 1.0)
    yy, xx = np.mgrid[-radius : radius + 1, -radius : radius + 1]
    disc = (xx**2 + yy**2 <= radius * radius).astype(np.float64)
    width = ndimage.convolve(ink, disc, mode="constant") / (2.0 * radius)
    near_ground = ndimage.binary_dilation(ground, iterations=2)
    rim = line & near_ground
    inner = line & ~near_ground
    out = np.zeros(n_regions, dtype=bool)
    if not rim.any() or not inner.any():
        return out
    w_out = float(np.median(width[rim]))
    if np.mean(width[inner] < w_out / heavier) < 0.15:  # one weight for every line
        return out
    # per region: its line pixels (within two pixels of its paper), and how many are heavy
    paper = np.where(~line & (reg >= 0), reg, -1)
    heavy = width > 0.8 * w_out
    count = np.zeros(n_regions)
    thick = np.zeros(n_regions)
    for step in range(1, 3):  # pixels one and two steps from a region's paper
        grown = ndimage.grey_dilation(paper + 1, size=2 * step + 1) - 1
        on = line & (grown >= 0)
        count += np.bincount(grown[on], minlength=n_regions)
        thick += np.bincount(grown[on & heavy], minlength=n_regions)
    # a face on the figure's rim: its paper within the outline's width (and two pixels) of the
    # ground
    rim_reach = ndimage.binary_dilation(ground, iterations=int(np.ceil(w_out)) + 2)
    touches = np.zeros(n_regions, dtype=bool)
    touches[np.unique(paper[rim_reach & (paper >= 0)])] = True
    return (count > 0) & (thick >= 0.9 * count) & ~touches


def shade_drawing(
    target: np.ndarray,
    background=(1.0, 1.0, 1.0),
    light=None,
    ambient: float = 0.2,
    ink: float = 0.5,
    min_face_px: int = 6,
    third_share: float = 0.15,
) -> DrawingReading:
    """Read a black-on-white line drawing of boxes as a flat-shaded picture.

    Parameters
    ----------
    target : (N, N, 3) float in [0, 1]
    background : (3,) float
        The paper's colour.
    light : (3,) float, optional
        The light to paint with (camera frame); default: the one giving the three orientations
        the Lambertian terms :data:`DRAWING_SHADES`.
    ambient : float
    ink : float
        A pixel is a line where it is over this share as dark as the darkest pixel near it
        (darkness ``1 - grey / paper``; with black lines on white: under this grey).
    min_face_px : int
        Regions of paper smaller than this are gaps between lines (given to the lines).
    third_share : float
        A face's edges along its own normal's direction stay under this share of its outline;
        a region over it along all three directions is a hole.

    Returns
    -------
    DrawingReading

    Raises
    ------
    MescherError
        No lines, lines along fewer than three directions, or no right-angled reading of them.
    """
    from scipy import ndimage

    from .regions import region_polygons
    from .shading import frames_from_creases

    t = np.asarray(target, dtype=np.float64)
    if t.ndim != 3 or t.shape[2] != 3 or t.shape[0] != t.shape[1]:
        raise MescherError(f"target: expected an (N, N, 3) image, found shape {t.shape}")
    N = t.shape[0]
    dark = _darkness(t, background)
    line = _line_pixels(dark, ink)
    if line.sum() < 16:
        raise MescherError(
            f"target: expected a drawing (dark lines), found {int(line.sum())} dark pixels"
        )
    lab, n = ndimage.label(~line)  # 4-connected regions of paper
    border = np.unique(np.r_[lab[0], lab[-1], lab[:, 0], lab[:, -1]])
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    regions = [
        r for r in range(1, n + 1) if r not in set(border.tolist()) and sizes[r] >= min_face_px
    ]
    if not regions:
        raise MescherError("target: expected closed regions between the lines, found none")
    # every pixel of the figure: its region, line pixels the nearest region's (face or hole)
    region_of = np.full(n + 1, -1, dtype=np.int64)
    region_of[np.asarray(regions)] = np.arange(len(regions))
    ground = np.isin(lab, border) & ~line
    seeds = ((lab > 0) & ~line & (region_of[lab] >= 0)) | ground
    _, (ii, jj) = ndimage.distance_transform_edt(~seeds, return_indices=True)
    near = np.where(seeds, lab, lab[ii, jj])
    reg = np.where(np.isin(near, border), -1, region_of[near])
    # a thick line (an upscaled drawing's: its staircases two pixels a step) is straightened
    # with a tolerance near half its width (the usual 0.75 pixels up to lines 4 pixels wide)
    half = float(np.percentile(ndimage.distance_transform_edt(line)[line], 90))
    polys, preg, lines = region_polygons(reg, tolerance_px=max(0.75, half - 1.25))
    dirs, along, total = _frame_directions(lines, polys, preg, len(regions), 2.0 / N, half - 1.25)
    share = along / np.maximum(total[:, None], 1e-300)
    k_min = np.argmin(share, axis=1)
    own = share[np.arange(len(regions)), k_min]
    # a face: its edges follow the two other directions, hardly its own
    face_like = (own < third_share) & (share.sum(axis=1) - own > 0.6)
    # a region whose outline follows one direction only is a bar's face seen between others,
    # not an opening, heavy as its lines may be (an opening shows two directions at least)
    outlined = _outlined(t, line, ground, reg, len(regions))
    outlined &= ~_one_direction(share, third_share)
    orient = np.where(face_like & ~outlined, k_min, -1)
    pieces = _sides(lines, reg)
    share = _own_shares(lines, reg, pieces, orient, share, total, dirs)
    orient = _by_creases(pieces, orient, share, dirs, third_share)
    orient = _bars_from_above(pieces, orient, share, dirs, BAND_SHARE)
    if np.unique(orient[orient >= 0]).size < 3:
        raise MescherError(
            "target: expected faces of three orientations between the lines, found "
            f"{np.unique(orient[orient >= 0]).size}"
        )
    frames = frames_from_creases(dirs)
    # of the two Necker readings, a person sees boxes from above: the most vertical normal up
    k_up = int(np.argmax(np.abs(frames[0][:, 1])))
    normals = frames[0] if frames[0][k_up, 1] > 0 else frames[1]
    if light is None:
        lvec = normals.T @ (DRAWING_SHADES / np.linalg.norm(DRAWING_SHADES))
    else:
        lvec = np.asarray(light, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    shade = ambient + (1.0 - ambient) * np.maximum(normals @ lvec, 0.0)
    face = np.where(reg >= 0, orient[np.maximum(reg, 0)], -1)
    picture = np.empty((N, N, 3))
    picture[:] = np.asarray(background, dtype=np.float64)
    on = face >= 0
    picture[on] = shade[face[on]][:, None]
    faces = np.where(on, reg, -1)
    steps = _steps(lines, faces, orient)
    return DrawingReading(picture, faces, orient, normals, dirs, lvec, steps)


def _sides(lines, labels: np.ndarray, side_px: float = 1.0):
    """The pieces of the straightened ``lines`` (screen units) and the labels ``side_px`` pixels
    to either side of their middles: ``a, b`` (S, 2), ``length`` (S,), ``f, g`` (S,)."""
    pts = [np.asarray(g.coords) for g in lines]
    if not pts:
        z = np.zeros((0, 2))
        return z, z, np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    px = 2.0 / labels.shape[0]
    a = np.concatenate([c[:-1] for c in pts])
    b = np.concatenate([c[1:] for c in pts])
    d = b - a
    length = np.linalg.norm(d, axis=1)
    n = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.maximum(length, 1e-300)[:, None]
    mid = 0.5 * (a + b)
    f, g = labels_at(labels, mid + side_px * px * n), labels_at(labels, mid - side_px * px * n)
    return a, b, length, f, g


def _piece_axes(a, b, length, dirs):
    """Unit directions ``u`` (S, 2) of the pieces ``a -> b`` and the direction (row of
    ``dirs``) each runs along within 10 degrees, -1 for none (``axis``, (S,))."""
    u = (b - a) / np.maximum(length, 1e-300)[:, None]
    cos = np.abs(u @ dirs.T)
    axis = np.where(cos.max(axis=1) > math.cos(math.radians(10.0)), np.argmax(cos, axis=1), -1)
    return u, axis


def _one_direction(share: np.ndarray, third_share: float) -> np.ndarray:
    """(R,) bool: the regions whose outline follows one direction only (both others' shares
    under ``third_share``)."""
    return np.sort(share, axis=1)[:, 1] < third_share


def _steps(lines, faces: np.ndarray, orient: np.ndarray) -> list:
    """The pieces of the straightened ``lines`` (screen units) with two different faces of one
    orientation on their two sides, over two pixels long: (2, 2) arrays."""
    a, b, length, f, g = _sides(lines, faces)
    o_f = np.where(f >= 0, orient[np.maximum(f, 0)], -1)
    o_g = np.where(g >= 0, orient[np.maximum(g, 0)], -2)
    keep = (f != g) & (o_f == o_g) & (length > 4.0 / faces.shape[0])
    return [np.stack([a[k], b[k]]) for k in np.flatnonzero(keep)]


def _by_creases(pieces, orient, share, dirs, third_share: float) -> np.ndarray:
    """Orientations of the faces whose edges allow two (both other directions' shares under
    ``third_share``: a wall under a flight shows the treads' edges in front of it): the one
    under which more of its boundary with faces of one reading is a crease, a line along the
    third direction between faces of the two others."""
    two = (orient >= 0) & _one_direction(share, third_share)
    if not two.any():
        return orient
    a, b, length, f, g = pieces
    _, axis = _piece_axes(a, b, length, dirs)
    score = np.zeros((len(orient), 3))
    for r, q in ((f, g), (g, f)):  # each side of each piece
        sel = (r >= 0) & (q >= 0) & (r != q) & (axis >= 0)
        sel[sel] &= two[r[sel]] & ~two[q[sel]] & (orient[q[sel]] >= 0)
        r_, kq, ax, ln = r[sel], orient[q[sel]], axis[sel], length[sel]
        for k in range(3):
            ok = (k != kq) & (ax != k) & (ax != kq)
            np.add.at(score[:, k], r_[ok], ln[ok])
    score[share >= third_share] = -1.0
    best = np.argmax(score, axis=1)
    decided = two & (score[np.arange(len(orient)), best] > 0)
    return np.where(decided, best, orient)


def _crossbars(lines, labels: np.ndarray, pieces, reach_px: float = 3.0, chord_px: float = 10.0):
    """Which pieces of the straightened ``lines`` are the crossbar of a T-junction for the region
    on each side: that region ends at an end of the line while the region across runs on
    straight past it and a third region takes the first one's place (a bar passing behind a
    post: the post's edge is not the bar's).

    Each end of a line is looked past along its last ``chord_px`` pixels' chord (the
    straightened lines round their corners by a pixel or two), ``reach_px`` pixels on, a pixel
    and a half to either side.  The flag goes to the line's pieces along that chord.

    ``pieces`` are the lines' pieces and the regions on their two sides (:func:`_sides` of
    ``lines`` and ``labels``).

    Returns
    -------
    stem_f, stem_g : (S,) bool
        The region ``f`` (``g``) ends where the region across runs on.
    """
    a, b, length, f, g = pieces
    stem_f = np.zeros(len(a), dtype=bool)
    stem_g = np.zeros(len(a), dtype=bool)
    px = 2.0 / labels.shape[0]
    u_piece = (b - a) / np.maximum(length, 1e-300)[:, None]
    k0 = 0
    for ln in lines:  # a few dozen lines
        c = np.asarray(ln.coords)
        k1 = k0 + len(c) - 1
        fl, gl = f[k0:k1], g[k0:k1]
        for end, back in ((c[-1], max(ln.length - chord_px * px, 0.0)), (c[0], chord_px * px)):
            u = end - np.asarray(ln.interpolate(min(back, ln.length)).coords)[0]
            if np.linalg.norm(u) < 0.5 * px:
                continue
            u = u / np.linalg.norm(u)
            n = np.array([-u[1], u[0]])
            beyond = end + reach_px * px * u
            left, right = labels_at(
                labels, np.stack([beyond + 1.5 * px * n, beyond - 1.5 * px * n])
            )
            run = np.abs(u_piece[k0:k1] @ u) > math.cos(math.radians(15.0))
            f_left = u_piece[k0:k1] @ u > 0.0  # f lies left of its piece (:func:`_sides`)
            lf, lg = np.where(f_left, left, right), np.where(f_left, right, left)
            stem_f[k0:k1] |= run & (lf != fl) & (lf != gl) & (lg == gl)
            stem_g[k0:k1] |= run & (lg != gl) & (lg != fl) & (lf == fl)
        k0 = k1
    return stem_f, stem_g


def _own_shares(lines, reg, pieces, orient, share, total, dirs) -> np.ndarray:
    """The faces' shares of outline along each direction without the crossbars of the
    T-junctions they end at (:func:`_crossbars`; the region running on a face, not the ground
    or a hole): a bar seen between two posts has edges along one direction only, where its
    ends' lines (the posts') made it a face of another orientation.  Faces whose outline would
    lose over 70% keep their shares."""
    a, b, length, f, g = pieces
    stem_f, stem_g = _crossbars(lines, reg, pieces)
    _, axis = _piece_axes(a, b, length, dirs)
    along = share * total[:, None]
    tot = total.copy()
    face = np.r_[orient >= 0, False]  # label -1 (the ground): index -1
    for r, stem, other in ((f, stem_f, g), (g, stem_g, f)):
        sel = stem & (r >= 0) & face[other]  # only a face runs on in front
        np.subtract.at(tot, r[sel], length[sel])
        sel &= axis >= 0
        np.subtract.at(along, (r[sel], axis[sel]), length[sel])
    keep = (orient >= 0) & (tot > 0.3 * total)
    own = np.maximum(along, 0.0) / np.maximum(tot[:, None], 1e-300)
    return np.where(keep[:, None], own, share)


def _bars_from_above(pieces, orient, share, dirs, third_share) -> np.ndarray:
    """Orientations of two faces whose edges follow one direction only, side by side along
    it: the two faces of a bar whose ends are hidden, which either of the two orientations
    holding that direction could be.  Seen from above a bar's edge is convex: each face lies
    on the side of the edge its normal's screen projection points to (the top above the edge,
    a wall below it).  Each such face takes the orientation the length of its edges with such
    a neighbour votes for."""
    one = (orient >= 0) & _one_direction(share, third_share)
    if not one.any():
        return orient
    d_of = np.argmax(share, axis=1)
    # the normals' screen projections seen from above: the most vertical one up, the others
    # down (the Necker reading :func:`shade_drawing` takes)
    k_up = int(np.argmax(np.abs(dirs[:, 1])))
    proj = (
        dirs * np.sign(dirs[:, 1:2] + 1e-300) * np.where(np.arange(3) == k_up, 1.0, -1.0)[:, None]
    )
    a, b, length, f, g = pieces
    u, axis = _piece_axes(a, b, length, dirs)
    toward_f = np.stack([-u[:, 1], u[:, 0]], axis=1)  # f lies left of its piece
    votes = np.zeros((len(orient), 3))
    ok = (f >= 0) & (g >= 0) & (f != g)
    ok[ok] &= one[f[ok]] & one[g[ok]] & (d_of[f[ok]] == d_of[g[ok]])
    for k in np.flatnonzero(ok):  # the pieces between two such faces: a handful
        d = d_of[f[k]]
        if axis[k] != d:
            continue
        c0, c1 = [c for c in range(3) if c != d]
        s0, s1 = float(proj[c0] @ toward_f[k]), float(proj[c1] @ toward_f[k])
        if s0 * s1 >= 0.0:
            continue
        on_f, on_g = (c0, c1) if s0 > 0.0 else (c1, c0)
        votes[f[k], on_f] += length[k]
        votes[g[k], on_g] += length[k]
    voted = votes.max(axis=1) > 0.0
    return np.where(voted, np.argmax(votes, axis=1), orient)
