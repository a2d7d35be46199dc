"""Pictures as people publish them, made flat again: antialiased edges and JPEG noise.

The picture reader (:func:`.picture.segment_picture`) takes a flat-shaded picture: each face of a
figure of boxes under one light one exact colour, a line wherever two neighbouring pixels
differ.  A renderer that antialiases blends the colours of the faces meeting at each edge
pixel (a pixel half on a dark face and half on a light one takes the middle shade, which may
be a third face's), and JPEG adds a few levels of noise everywhere and ringing along the edges.
:func:`flatten_picture` restores the flat picture, comparing colours by their grey and a third
of their departure from it (JPEG keeps the grey within a few levels but samples colour at half
resolution) within a noise radius read from the faces' insides (:func:`noise_radius`: 1.5
levels for any render, so faces three levels apart stay two):

1. the picture's *modes*: colours held by many pixels, each gathering the colours within the
   radius of it (greedily from the most frequent), that are not thin colours between two
   others (a blend along a long straight edge is a run of one colour too, and so is JPEG's
   ringing along one: one pixel wide, under a quarter of its pixels survive a 2 x 2 opening;
   the darkest or lightest colour blends none, and the risers of a flight seen nearly
   edge-on are thin faces);
2. each pixel takes the nearest mode within the radius, except a run one pixel wide of a
   mode's colour lying between two others' colours next to both (an edge's blend that
   matches a third face's colour);
3. the others (edge blends, ringing) take, of the modes present within two pixels, the
   nearest in colour: a pixel mostly on one face is nearest that face's colour;
4. specks of a few pixels (noise past the radius) take the colour around them, and where the
   radius says JPEG, a Potts model (:func:`_potts_smooth`) smooths the edges the noise left
   ragged and keeps the corners of a staircase's steps.

:func:`is_flat` tells a flat picture (nearly every pixel's exact colour shared by many) from
one to restore; a flat picture is left as it is, so faces a few grey levels apart, which
noise would merge, stay apart there.
"""

from __future__ import annotations

import numpy as np

from ..errors import MescherError

__all__ = [
    "drop_outlines",
    "drop_specks",
    "figure_mask",
    "flatten_picture",
    "is_antialiased",
    "is_flat",
    "noise_radius",
]


#: Cost of a 4-neighbour of another label, in squared noise radii of colour distance
#: (:func:`_potts_smooth`): over the benchmark's JPEG pictures (quality 90, 128 px) 2 left 3 to
#: 8 times fewer pixels off their face's colour than a 3 x 3 majority; 1 left more, 4 as few.
POTTS_WEIGHT = 2.0

#: JPEG's ringing overshoots a face's colour by up to this many noise radii: a thin colour
#: that near another is ringing even where it lies between no two colours.
RING = 3.0

#: A colour is one pixel wide where under this share of its pixels lie in a 2 x 2 block of it.
WIDE = 0.25


def _colour_keys(target: np.ndarray) -> np.ndarray:
    """(H, W) int64: each pixel's colour rounded to 8-bit levels, packed in one integer."""
    q = np.clip(np.round(np.asarray(target, dtype=np.float64) * 255.0), 0, 255).astype(np.int64)
    return (q[..., 0] << 16) | (q[..., 1] << 8) | q[..., 2]


def is_flat(
    target: np.ndarray, min_run: int = 16, share: float = 0.995, max_thin: float = 0.05
) -> bool:
    """Whether ``share`` of the pixels have an 8-bit colour that ``min_run`` pixels share and
    at most ``max_thin`` of the pixels along colour edges have a one-wide colour.

    A z-buffered picture of boxes under one light (every pixel one of a few exact colours) is
    flat (the acceptance benchmark's: at most 0.4% of pixels in rarer colours, tiny faces); a
    JPEG (noise everywhere) is not.  An antialiased one has a blend along every edge, 1.6-5.6%
    of its pixels at 128 px but fewer, and repeated along straight edges, at 256-512 px: its
    blends are colours one pixel wide (:func:`_thin_on_edges`: 20-41% of the edge pixels of
    the benchmark's pictures at 128, 256 and 512 px, at most 1% of a z-buffer's).
    """
    keys = _colour_keys(target)
    _, inv, cnt = np.unique(keys.ravel(), return_inverse=True, return_counts=True)
    if np.mean(cnt[inv] >= min_run) < share:
        return False
    return _thin_on_edges(keys) <= max_thin


def _thin_on_edges(keys: np.ndarray) -> float:
    """Share of the edge pixels (a 4-neighbour of another colour) whose colour is one pixel
    wide: under :data:`WIDE` of its pixels lie in a 2 x 2 block of it (a blend along an edge;
    a face, however thin in places, has an inside)."""
    _, inv = np.unique(keys.ravel(), return_inverse=True)
    inv = inv.reshape(keys.shape)
    block = (keys[:-1, :-1] == keys[1:, :-1]) & (keys[:-1, :-1] == keys[:-1, 1:])
    block &= keys[:-1, :-1] == keys[1:, 1:]
    inside = np.zeros(keys.shape, dtype=bool)
    for di in (0, 1):
        for dj in (0, 1):
            inside[di : di + block.shape[0], dj : dj + block.shape[1]] |= block
    n = np.bincount(inv.ravel())
    thin = (np.bincount(inv.ravel(), weights=inside.ravel(), minlength=len(n)) < WIDE * n)[inv]
    edge = np.zeros(keys.shape, dtype=bool)
    d = keys[:, 1:] != keys[:, :-1]
    edge[:, 1:] |= d
    edge[:, :-1] |= d
    d = keys[1:] != keys[:-1]
    edge[1:] |= d
    edge[:-1] |= d
    return float(thin[edge].mean()) if edge.any() else 0.0


def figure_mask(target: np.ndarray, background=(1.0, 1.0, 1.0), tol: float = 0.05) -> np.ndarray:
    """(H, W) bool: the figure's pixels as a renderer that samples pixel centres sees them.

    :func:`.targets.target_mask` of the flat picture (:func:`flatten_picture`) where the
    picture is not flat: an antialiased edge pixel is the figure's where most of it is, not
    wherever a little of the figure tints it (which puts the silhouette half a pixel out).
    Of the colours within ``tol`` of ``background``, only those the picture's border shows are
    ground: a face lit almost as light as a white ground (a few levels under it) is inside
    the figure, which fits the screen square.
    """
    from .targets import target_mask

    t = np.asarray(target, dtype=np.float64)
    t = t if is_flat(t) else flatten_picture(t)
    near = ~target_mask(t, background, tol)
    keys = _colour_keys(t)
    rim = np.zeros(keys.shape, dtype=bool)
    rim[[0, -1], :] = True
    rim[:, [0, -1]] = True
    if not np.any(rim & near):  # no ground on the border (a figure filling it): by colour
        return ~near
    return ~(near & np.isin(keys, keys[rim & near]))


def noise_radius(target: np.ndarray) -> float:
    """How far (per channel, in [0, 1] units) a pixel strays from its face's colour: one and
    a half 8-bit levels (rounding) plus four times the 95th percentile of the grey's distance
    to its 5 x 5 median, over pixels whose windows are mostly within a level of their median
    (the faces' insides, a few edge pixels among them: hence not a higher percentile); at
    most eight levels.  A render, antialiased or not: 1.5 levels, so faces a few levels apart
    stay apart; JPEG at quality 75-95 (95th percentile 0.7-1.3 levels): 4-7 levels."""
    from scipy import ndimage

    g = np.asarray(target, dtype=np.float64).mean(axis=-1) * 255.0
    dev = np.abs(g - ndimage.median_filter(g, size=5))
    inside = ndimage.uniform_filter((dev <= 1.0).astype(np.float64), size=5) >= 0.6
    noise = float(np.percentile(dev[inside], 95)) if inside.any() else 0.0
    return min(1.5 + 4.0 * noise, 8.0) / 255.0


def is_antialiased(target: np.ndarray) -> bool:
    """Whether a picture that is not flat (:func:`is_flat`) is a render's antialiasing: its
    faces flat inside (:func:`noise_radius` at most 2 levels), only its edges blended.  A
    JPEG's faces are noisy inside (4-7 levels): its edges are a picture sampled at pixel
    centres, blurred by the compression, not pixels averaged over their area."""
    return not is_flat(target) and noise_radius(target) <= 2.0 / 255.0


def flatten_picture(
    target: np.ndarray, radius: float | None = None, min_share: float = 0.002, min_speck: int = 3
) -> np.ndarray:
    """The flat-shaded picture an antialiased or JPEG-compressed picture was made from.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
    radius : float, optional
        Largest per-channel difference of a pixel to its face's colour (noise); colours closer
        than this are one.  Default: :func:`noise_radius`.
    min_share : float
        Smallest share of the picture a colour must hold to be a face's (or the ground's).
    min_speck : int
        Pieces of one colour smaller than this (pixels, 4-connected) take the colour of the
        nearest pixel outside them.

    Returns
    -------
    (H, W, 3) float64
        Each pixel one of the modes' colours (their pixel-weighted mean colours).

    Raises
    ------
    MescherError
        ``target`` not an (H, W, 3) image, or no colour held by ``min_share`` of it.
    """
    from scipy import ndimage

    t = np.asarray(target, dtype=np.float64)
    if t.ndim != 3 or t.shape[2] != 3:
        raise MescherError(f"target: expected an (H, W, 3) image, found shape {t.shape}")
    H, W, _ = t.shape
    rgb = np.clip(t.reshape(-1, 3), 0.0, 1.0) * 255.0
    feat = _features(rgb)
    rows, inv, cnt = np.unique(
        np.round(feat).astype(np.int64), axis=0, return_inverse=True, return_counts=True
    )
    inv = inv.ravel()
    cols = rows.astype(np.float64)
    r = (noise_radius(t) if radius is None else float(radius)) * 255.0
    need = max(8.0, min_share * H * W)
    taken = np.zeros(len(rows), dtype=bool)
    modes = []
    for u in np.argsort(-cnt, kind="stable"):  # the few seeds of the modes, most frequent first
        if cnt[u] < 0.25 * need:
            break
        if taken[u]:
            continue
        near = ~taken & (np.abs(cols - cols[u]).max(axis=1) <= r)
        taken |= near
        if cnt[near].sum() >= need:
            modes.append(np.flatnonzero(near))
    if not modes:
        raise MescherError(
            f"target: expected faces of flat colours (some colour on {min_share:.1%} of the "
            "picture), found none"
        )
    # each mode's mean colour and mean feature, over its pixels
    member = np.full(len(rows), -1, dtype=np.int64)
    for k, idx in enumerate(modes):
        member[idx] = k
    of = member[inv]
    on = of >= 0
    n_k = np.bincount(of[on], minlength=len(modes)).astype(np.float64)
    RGB = np.stack([np.bincount(of[on], rgb[on, c], len(modes)) for c in range(3)], 1)
    RGB /= n_k[:, None]
    M = _features(RGB)
    dist = np.abs(feat[:, None, :] - M[None]).max(axis=-1).reshape(H, W, len(M))
    label = np.argmin(dist, axis=-1)
    sure = np.take_along_axis(dist, label[..., None], axis=-1)[..., 0] <= r
    keep = _faces_not_blends(M, r, label, sure)
    sure &= keep[label]
    # the rest: of the modes seen within two pixels, the nearest in colour
    cost = np.where(keep[None, None], dist, np.inf)
    for k in np.flatnonzero(keep):
        near_k = ndimage.binary_dilation(sure & (label == k), iterations=2)
        cost[..., k] = np.where(near_k, cost[..., k], np.inf)
    fill = np.argmin(cost, axis=-1)
    none = ~np.isfinite(np.min(cost, axis=-1)) & ~sure
    if none.any():  # far from every face's sure pixels: the nearest sure pixel's mode
        _, (ii, jj) = ndimage.distance_transform_edt(~sure, return_indices=True)
        fill = np.where(none, label[ii, jj], fill)
    out = np.where(sure, label, fill)
    # specks (a few pixels of one mode inside another's face: noise past ``radius``) join the
    # face around them
    speck = np.zeros((H, W), dtype=bool)
    for k in np.flatnonzero(keep):  # a handful of modes
        comp, n = ndimage.label(out == k)
        size = np.bincount(comp.ravel(), minlength=n + 1)
        speck |= (comp > 0) & (size[comp] < min_speck)
    if speck.any() and not speck.all():
        _, (ii, jj) = ndimage.distance_transform_edt(speck, return_indices=True)
        out = out[ii, jj]
    if r > 2.0:  # noisy (JPEG): edges ragged by the noise, smoothed by a Potts model
        out = _potts_smooth(out, np.where(keep[None, None], dist / r, np.inf))
    return RGB[out] / 255.0


def _potts_smooth(labels: np.ndarray, dist: np.ndarray, sweeps: int = 10) -> np.ndarray:
    r"""``labels`` (H, W) relabelled to a local minimum of a Potts energy.

    .. math:: E = \sum_p d_p(\ell_p)^2 + \lambda \sum_{p \sim q} [\ell_p \neq \ell_q]

    over 4-neighbour pairs, with ``dist`` (H, W, K) each pixel's colour distance to each
    mode in noise radii (inf for modes that are no face's) and :data:`POTTS_WEIGHT` as
    :math:`\lambda`.  Iterated conditional modes on the two colours of a checkerboard (each
    half's pixels have no neighbour in it, so every sweep lowers ``E``) until no pixel
    changes.  A pixel of JPEG's ragged edges (a bump of one pixel: three neighbours of the
    other label) changes wherever its colour is within ``sqrt(2 lambda)`` radii of the
    other's, a step's corner (two neighbours of each) only where its colour is nearer the
    other's, where a 3 x 3 majority would round every corner off and cut the one-pixel
    teeth of a staircase's outline, which are its steps.  Written here: a handful of labels
    on a grid, where a few vectorized sweeps reach what a graph-cut library would add a
    dependency for.
    """
    H, W, K = dist.shape
    data = dist**2
    white = (np.add.outer(np.arange(H), np.arange(W)) % 2).astype(bool)
    out = labels.copy()
    for _ in range(sweeps):
        changed = False
        for half in (white, ~white):
            pad = np.pad(out, 1, constant_values=-1)  # outside the picture: no label
            nb = (pad[1:-1, 2:], pad[1:-1, :-2], pad[2:, 1:-1], pad[:-2, 1:-1])
            same = np.stack([sum(n == k for n in nb) for k in range(K)], axis=-1)
            best = np.argmin(data + POTTS_WEIGHT * (4 - same), axis=-1)
            move = half & (best != out)
            changed |= bool(move.any())
            out = np.where(move, best, out)
        if not changed:
            break
    return out


def _features(rgb: np.ndarray, chroma: float = 0.3) -> np.ndarray:
    """(P, 4): the grey (channels' mean) and ``chroma`` times each channel's departure from it
    (8-bit levels).  JPEG keeps the grey within a few levels but blurs and coarsens colour
    (sampled at half resolution): its colour noise, weighed down, stays within the grey's
    noise, while a coloured ground stays far from grey faces."""
    g = rgb.mean(axis=-1, keepdims=True)
    return np.concatenate([g, chroma * (rgb - g)], axis=-1)


def _faces_not_blends(M: np.ndarray, r: float, label: np.ndarray, sure: np.ndarray) -> np.ndarray:
    """(K,) bool: which modes are faces' colours; ``sure`` loses the pixels a blend matched.

    A colour between two others (within ``r`` of the segment joining them) is a blend where
    its pixels lie one wide (a colour between no two is a face however thin it lies): a
    whole mode so (a long straight edge), or single runs of a face's colour that a blend
    happens to match.  Where the picture is noisy (``r`` over two levels: JPEG) a colour
    between the ground and a face along the outline is one too (:func:`_ground_band`).
    """
    from scipy import ndimage

    between = _between(M, r)  # (K, K, K): k between i and j
    keep = np.ones(len(M), dtype=bool)
    two = np.ones((2, 2), dtype=bool)
    mks = [sure & (label == k) for k in range(len(M))]
    near3 = [ndimage.binary_dilation(mk) for mk in mks]
    ground = _ground_mode(label) if r > 2.0 else None
    five = np.ones((5, 5), dtype=bool)
    near5 = None if ground is None else ndimage.binary_dilation(label == ground, five)
    wides = [ndimage.binary_opening(mk, structure=two) for mk in mks]
    one_wide = np.array([w.sum() < WIDE * mk.sum() for w, mk in zip(wides, mks)])
    # each colour's distance to the nearest colour of a face that is not one wide
    gap = np.abs(M[:, None] - M[None]).max(axis=-1)
    gap[:, one_wide] = np.inf
    np.fill_diagonal(gap, np.inf)
    near = gap.min(axis=1)
    for k in range(len(M)):  # a handful of modes
        mk, wide = mks[k], wides[k]
        # one wide: a blend, or JPEG's ringing along an edge (past a wide face's colour,
        # within a few radii of it); a colour between no two others and far from each
        # blends none, and a thin face (a flight's risers seen edge-on) is one wide too
        if one_wide[k] and (between[:, :, k].any() or near[k] <= RING * r):
            keep[k] = False
            continue
        if ground is not None and k != ground and _ground_band(mk, near5, between[ground, :, k]):
            keep[k] = False  # JPEG's colour (subsampled 2 x 2) bled along the outline
            continue
        thin = mk & ~wide
        for i, j in zip(*np.nonzero(between[:, :, k])):
            sure[thin & near3[i] & near3[j]] = False
    return keep


def drop_outlines(
    target: np.ndarray,
    background=(1.0, 1.0, 1.0),
    thin: float = 0.25,
    darker: float = 10 / 255,
    black: float = 0.1,
    figure: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """A flat picture without the dark lines an illustrator draws along its edges.

    Shaded pictures are often drawn with black outlines on every edge (a "toon" or technical
    illustration style).  Two to four pixels wide, such lines are a colour of their own that
    the reader took for a face orientation.  A line colour is near black (grey at most
    ``black``: a face turned away from the light shows the ambient shade, 0.2 of its colour),
    darker by ``darker`` than every other colour of the figure covering a hundredth of it,
    and mostly thin (under ``thin`` of its pixels survive a 5 x 5 opening: no face's inside);
    its pixels take the colour of the nearest pixel of another colour (the faces on either
    side meet along the line's middle; the outline's line is shared with the ground).

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
        A flat picture (:func:`is_flat`, or :func:`flatten_picture`'s result).
    background : (3,) float
    thin, darker, black : float
    figure : (H, W) bool, optional
        ``figure_mask(target, background)`` where the caller has it (it flattens a picture
        that is not flat: seconds at 1024 px).

    Returns
    -------
    picture : (H, W, 3) float64
        ``target`` with the lines' pixels recoloured (``target`` itself where there are none).
    lines : (H, W) bool
        The pixels that were lines.
    """
    from scipy import ndimage

    t = np.asarray(target, dtype=np.float64)
    keys = _colour_keys(t)
    u, inv, cnt = np.unique(keys.ravel(), return_inverse=True, return_counts=True)
    inv = inv.reshape(keys.shape)
    grey = np.bincount(inv.ravel(), weights=t.mean(axis=-1).ravel()) / cnt
    figure = figure_mask(t, background) if figure is None else figure
    big = np.bincount(inv[figure], minlength=len(u)) >= 0.01 * max(int(figure.sum()), 1)
    lines = np.zeros(keys.shape, dtype=bool)
    five = np.ones((5, 5), dtype=bool)
    for k in np.flatnonzero(big & (grey <= black)):  # at most a few colours
        others = big.copy()
        others[k] = False
        if not others.any() or grey[k] > grey[others].min() - darker:
            continue
        mk = inv == k
        if ndimage.binary_opening(mk, structure=five).sum() < thin * cnt[k]:
            lines |= mk
    if not lines.any():
        return t, lines
    _, (ii, jj) = ndimage.distance_transform_edt(lines, return_indices=True)
    return t[ii, jj], lines


def drop_specks(
    target: np.ndarray,
    background=(1.0, 1.0, 1.0),
    share: float = 0.02,
    figure: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """A picture without the marks beside its figure: a caption, a signature, a speck of dirt.

    Pieces of the figure (:func:`figure_mask`, 8-connected) under ``share`` of the largest
    piece's pixels become ground: a figure of boxes is one piece or a few large ones, and a
    label read as faces gave the mesh shards of its own.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
    background : (3,) float
    share : float
    figure : (H, W) bool, optional
        ``figure_mask(target, background)`` where the caller has it.

    Returns
    -------
    picture : (H, W, 3) float64
        ``target`` with the specks' pixels in the ``background`` colour.
    specks : (H, W) bool
    """
    from scipy import ndimage

    t = np.asarray(target, dtype=np.float64)
    figure = figure_mask(t, background) if figure is None else figure
    comp, n = ndimage.label(figure, structure=np.ones((3, 3), dtype=bool))
    if n < 2:
        return t, np.zeros(t.shape[:2], dtype=bool)
    size = np.bincount(comp.ravel(), minlength=n + 1)
    size[0] = 0
    specks = (comp > 0) & (size[comp] < share * size.max())
    if not specks.any():
        return t, specks
    # with their antialiased fringe, which the figure's mask leaves to the ground's side
    keep = (comp > 0) & ~specks
    specks = ndimage.binary_dilation(specks, structure=np.ones((3, 3), dtype=bool)) & ~keep
    t = t.copy()
    t[specks] = np.asarray(background, dtype=np.float64)
    return t, specks


def _ground_mode(label: np.ndarray) -> int | None:
    """The mode most of the picture's border holds (the ground around a figure that fits the
    screen square), where it holds more than half of it; None otherwise."""
    border = np.concatenate([label[0], label[-1], label[1:-1, 0], label[1:-1, -1]])
    counts = np.bincount(border)
    k = int(np.argmax(counts))
    return k if counts[k] > 0.5 * border.size else None


def _ground_band(mk: np.ndarray, near_ground: np.ndarray, sides: np.ndarray) -> bool:
    """Whether the sure pixels ``mk`` of a colour between the ground and a face's colour
    (``sides``: the faces it lies between the ground and) are a band along the outline: 90%
    of them within two pixels of the ground.  A JPEG keeps colour at half resolution, so
    along the outline the ground's hue bleeds two pixels into the figure, a band wider than
    the blends a 2 x 2 opening takes out; a face of the figure has an inside."""
    if not sides.any() or not mk.any():
        return False
    return bool(np.count_nonzero(mk & near_ground) >= 0.9 * np.count_nonzero(mk))


def _between(M: np.ndarray, r: float) -> np.ndarray:
    """(K, K, K) bool: ``[i, j, k]`` where colour ``M[k]`` lies within ``r`` (per channel) of
    the segment from ``M[i]`` to ``M[j]``, strictly inside it (``i != j``, both ``!= k``)."""
    K = len(M)
    a, b = M[:, None, None, :], M[None, :, None, :]
    c = M[None, None, :, :]
    d = b - a
    t = ((c - a) * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-300)
    off = np.abs(a + np.clip(t, 0.0, 1.0)[..., None] * d - c).max(-1)
    idx = np.arange(K)
    distinct = (idx[:, None, None] != idx[None, :, None]) & (
        idx[:, None, None] != idx[None, None, :]
    )
    distinct &= idx[None, :, None] != idx[None, None, :]
    return distinct & (off <= r) & (t > 0.0) & (t < 1.0)


def as_read(target: np.ndarray, background) -> tuple[np.ndarray, dict]:
    """The flat picture a reader reads, and how it was made from ``target``.

    An antialiased or JPEG picture is made flat (:func:`flatten_picture`), an illustrator's
    dark edge lines are taken for the faces beside them (:func:`drop_outlines`), and marks
    beside the figure for ground (:func:`drop_specks`).

    Parameters
    ----------
    target : (N, N, 3) float in [0, 1]
    background : (3,) float
        The ground's colour.

    Returns
    -------
    flat : (N, N, 3) float64
    info : dict
        ``flattened`` (bool: the picture was not flat), ``antialiased`` (bool,
        :func:`is_antialiased`), ``outlines`` ((N, N) bool: the line pixels dropped) and
        ``specks`` ((N, N) bool: the pixels :func:`drop_specks` took for ground).
    """
    # flattened once where no lines are found: the figure's mask drop_outlines needs is the
    # flat picture's, and that flat picture is the one read
    flat = target if is_flat(target) else flatten_picture(target)
    fig = figure_mask(flat, background)
    clean, outlines = drop_outlines(target, background, figure=fig)  # 1 px lines look like blends
    if outlines.any():
        target = clean
        flat = target if is_flat(target) else flatten_picture(target)
    flattened = flat is not target
    antialiased = is_antialiased(target)
    target = flat
    if not outlines.any():  # a line's colour made exact by the flattening
        target, outlines = drop_outlines(target, background)
    target, specks = drop_specks(target, background)  # a caption beside the figure
    kind = {"flattened": flattened, "antialiased": antialiased, "outlines": outlines}
    return target, {**kind, "specks": specks}
