"""Pictures and initial shapes for inverse rendering: what the fit is tested and started on.

- :func:`torus_mescher`, :func:`torus_for_target`: the paper's initialization (Section 4.5), a
  possible torus matched to a silhouette;
- :func:`target_mask`: the figure's pixels in a picture; :func:`outlined`: a picture with
  black lines over its edges, as a technical illustration draws it;
- :func:`penrose_soup`, :func:`penrose_target`: the Penrose triangle as flat ordered triangles,
  rendered by this package's own rasterizer (a self-consistency target only: acceptance runs on
  z-buffered pictures of real 3D models, :mod:`meschers_igl.inverse.models`).

Nothing here imports PyTorch at module level.
"""

from __future__ import annotations

import math

import numpy as np

from .. import shapes
from ..errors import MescherError
from ..mescher import Mescher

# ---------------------------------------------------------------------------------------------
# Initialization: a torus seen from the view
# ---------------------------------------------------------------------------------------------


def torus_mescher(
    major: float = 0.6, minor: float = 0.2, n_major: int = 64, n_minor: int = 16, center=(0, 0)
) -> tuple[Mescher, np.ndarray]:
    """A torus lying in the screen plane as a (possible) mescher, and its face depth offsets.

    The torus is :func:`meschers_igl.shapes.torus` (the project's one torus generator: axis
    along z, toward the viewer, outward oriented) moved to ``center``.

    Parameters
    ----------
    major, minor : float
        Radius of the centre circle and of the tube (``major > minor > 0``).
    n_major, n_minor : int
        Vertices around the hole and around the tube (``2 n_major n_minor`` faces).
    center : (2,) float
        Screen position of the centre.

    Returns
    -------
    m : Mescher
        ``Mescher.from_mesh`` of the torus, viewed along z.
    offsets : (#F,) float64
        Face centroid depths mapped affinely to [0.25, 0.75] (larger nearer): the torus's own
        occlusion, as the initial soft z-ordering.
    """
    if not (major > minor > 0):
        raise MescherError(f"major, minor: expected major > minor > 0, found {major}, {minor}")
    V, F = shapes.torus(n_major, n_minor, R=major, r=minor)
    V[:, :2] += np.asarray(center, dtype=np.float64)
    m = Mescher.from_mesh(V, F)
    zc = V[F, 2].mean(axis=1)
    offsets = 0.25 + 0.5 * (zc - zc.min()) / max(zc.max() - zc.min(), 1e-12)
    return m, offsets


def target_mask(target: np.ndarray, background=(1.0, 1.0, 1.0), tol: float = 0.05) -> np.ndarray:
    """Silhouette of a target image: pixels whose colour differs from the background.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
    background : (3,) float
    tol : float
        Largest per-channel difference still counted as background.

    Returns
    -------
    (H, W) bool
    """
    return np.abs(target - np.asarray(background, dtype=np.float64)).max(axis=-1) > tol


def outlined(image: np.ndarray, width: int = 3) -> np.ndarray:
    """``image`` with black lines ``width`` (odd) pixels wide over its colour edges.

    Parameters
    ----------
    image : (H, W, 3) float in [0, 1]
        A flat picture (its edges are where two neighbouring pixels' 8-bit colours differ).
    width : int

    Returns
    -------
    (H, W, 3) float64
        A copy, the lines' pixels black.
    """
    from scipy import ndimage

    q = np.round(np.asarray(image, dtype=np.float64) * 255.0).astype(np.int64)
    key = (q[..., 0] << 16) | (q[..., 1] << 8) | q[..., 2]
    edge = np.zeros(key.shape, dtype=bool)
    edge[:, 1:] |= key[:, 1:] != key[:, :-1]
    edge[1:] |= key[1:] != key[:-1]
    if width > 1:
        edge = ndimage.binary_dilation(edge, iterations=(width - 1) // 2)
    out = np.array(image, dtype=np.float64)
    out[edge] = 0.0
    return out


def torus_for_target(
    target: np.ndarray, background=(1.0, 1.0, 1.0), n_major: int = 64, n_minor: int = 16
) -> tuple[Mescher, np.ndarray]:
    """A torus initialization matched to a target's silhouette (area-equivalent circles).

    The outer radius ``R + r`` is that of the disc with the area of the silhouette with its holes
    filled, the inner radius ``R - r`` that of the disc with the area of the holes, and the
    centre is the filled silhouette's centroid (screen square ``[-1, 1]^2``, y up).

    Returns
    -------
    m : Mescher
    offsets : (#F,) float64
    """
    from scipy import ndimage

    mask = target_mask(target, background)
    if not mask.any():
        raise MescherError("target: expected an object on the background, found an empty image")
    H, W = mask.shape
    filled = ndimage.binary_fill_holes(mask)
    px = 4.0 / (H * W)  # area of a pixel in screen units
    r_out = math.sqrt(filled.sum() * px / math.pi)
    r_in = math.sqrt((filled & ~mask).sum() * px / math.pi)
    r_in = min(max(r_in, 0.25 * r_out), 0.8 * r_out)  # keep a sensible tube without a hole
    ii, jj = np.nonzero(filled)
    center = (-1.0 + (2.0 * jj.mean() + 1.0) / W, 1.0 - (2.0 * ii.mean() + 1.0) / H)
    return torus_mescher(0.5 * (r_out + r_in), 0.5 * (r_out - r_in), n_major, n_minor, center)


# ---------------------------------------------------------------------------------------------
# The demonstration target: a Penrose triangle
# ---------------------------------------------------------------------------------------------


def penrose_soup(length: float = 5.0, width: float = 1.0, extent: float = 0.8):
    """The Penrose triangle as flat, ordered triangles (three bars seen along (1, 1, 1)).

    Bars along x, y and z (Penrose's construction) project to a closed triangle when viewed
    along ``(1, 1, 1)``: ``X = [0, L] x [0, w]^2``, ``Y = [L-w, L] x [w, L] x [0, w]``,
    ``Z = [L-w, L] x [L-w, L] x [w, L]``.  Only the faces that face the viewer are kept
    (``+x, +y, +z``).  The X bar is split in two halves so that one offset per face can give the
    cyclic order of the illusion: X far half < Y < Z < X near half.

    Parameters
    ----------
    length, width : float
        Bar length ``L`` and width ``w``.
    extent : float
        Half-size of the screen box the drawing is scaled into.

    Returns
    -------
    xy : (#V, 2) float64
        Screen positions (bottom bar horizontal).
    F : (#F, 3) int64
    normals : (#F, 3) float64
        Unit normals in the camera frame.
    offsets : (#F,) float64
        Depth offsets for the soft z-ordering.
    scale : float
        Screen units per model unit (depths scale the same way).
    """
    L, w = float(length), float(width)
    boxes = [  # (lo, hi, offset, faces kept)
        ((L / 2, 0, 0), (L, w, w), 0.2, "xyz"),
        ((L - w, w, 0), (L, L, w), 0.4, "xyz"),
        ((L - w, L - w, w), (L, L, L), 0.6, "xyz"),
        ((0, 0, 0), (L / 2, w, w), 0.8, "yz"),  # its +x face is internal
    ]
    quads, quad_normals, quad_offsets = [], [], []
    for lo, hi, off, keep in boxes:
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        for axis, name in enumerate("xyz"):
            if name not in keep:
                continue
            a, b = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for sa, sb in ((0, 0), (1, 0), (1, 1), (0, 1)):  # counter-clockwise about +axis
                p = hi.copy()
                p[a] = (lo, hi)[sa][a]
                p[b] = (lo, hi)[sb][b]
                corners.append(p)
            quads.append(corners)
            n = np.zeros(3)
            n[axis] = 1.0
            quad_normals.append(n)
            quad_offsets.append(off)
    Q = np.asarray(quads)  # (#Q, 4, 3)
    # merge corners that coincide in 3D so that shared edges are not drawn as outlines
    Vq, qidx = np.unique(Q.reshape(-1, 3).round(9), axis=0, return_inverse=True)
    qidx = qidx.reshape(-1, 4)
    # camera frame: z toward the viewer along (1, 1, 1); screen axes rotated below
    view = np.ones(3) / math.sqrt(3.0)
    right = np.array([1.0, -1.0, 0.0]) / math.sqrt(2.0)
    up = np.cross(view, right)
    R = np.stack([right, up, view])
    C = Vq @ R.T
    N = np.asarray(quad_normals) @ R.T
    # rotate the screen so that the X bar (the bottom side) is horizontal
    dx = np.array([1.0, 0.0, 0.0]) @ R.T
    ang = -math.atan2(dx[1], dx[0])
    rot = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
    xy = C[:, :2] @ rot.T
    N[:, :2] = N[:, :2] @ rot.T
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    scale = 2.0 * extent / float((hi - lo).max())
    xy = (xy - 0.5 * (lo + hi)) * scale
    F = np.concatenate([qidx[:, [0, 1, 2]], qidx[:, [0, 2, 3]]]).astype(np.int64)
    # keep the counter-clockwise screen orientation of the quads (all face the viewer)
    normals = np.concatenate([N, N])
    offsets = np.concatenate([quad_offsets, quad_offsets]).astype(np.float64)
    return xy, F, normals, offsets, scale


def penrose_target(
    resolution: int = 128,
    lights=((0.0, 0.0, 1.0),),
    light_colors=None,
    ambient=0.2,
    background=(1.0, 1.0, 1.0),
    sigma: float = 1e-6,
) -> np.ndarray:
    """A Penrose-triangle picture rendered by :func:`.rasterizer.soft_rasterize`.

    Parameters
    ----------
    resolution : int, default: 128
    lights, light_colors, ambient
        See :func:`.rasterizer.lambertian`.
    background : (3,) float
    sigma : float, default: 1e-6
        A nearly hard rasterization (edges under a tenth of a pixel wide).

    Returns
    -------
    (resolution, resolution, 3) float64 in [0, 1]
    """
    from .rasterizer import lambertian, require_torch, soft_rasterize

    torch = require_torch()
    xy, F, normals, offsets, _ = penrose_soup()
    dt = torch.float64
    with torch.no_grad():
        colors = lambertian(torch.as_tensor(normals, dtype=dt), lights, light_colors, ambient)
        img = soft_rasterize(
            torch.as_tensor(F),
            torch.as_tensor(xy, dtype=dt),
            colors,
            torch.as_tensor(offsets, dtype=dt),
            resolution,
            sigma=sigma,
            gamma=1e-3,
            background=background,
        )
    return img.numpy()
