"""Fit a mescher to a picture: inverse rendering of impossible objects (paper Section 4.5).

The unknowns are screen positions ``xy`` (#V, 2), relative depths and one depth offset per face.
Depths are parametrized on the space of meschers,

    zeta = d01 z + H c,

with ``z`` (#V,) a per-vertex depth and ``H`` (#E, k) the harmonic basis dual to the homology
generators (``m.harmonic_basis()``: the period of ``h_j`` around generator ``i`` is
``delta_ij``), so ``c`` *are* the periods and ``d12 zeta = d12 d01 z + d12 H c = 0`` holds for
every iterate, to round-off.  The image loss is the mean squared error against the target,
rendered by the soft rasterizer of :mod:`.rasterizer` under fixed lights.

Following Nicolet et al. 2021 ("Large Steps in Inverse Rendering"), ``xy`` and ``z`` are
optimized in differential coordinates ``u = (I + lambda L) x`` with the uniform-scaled Adam of
``largesteps``; a gradient step in ``u`` is the Sobolev step ``(I + lambda L)^-1 g`` in ``x``.
``L = -m.cotmatrix()`` is the mescher's own (intrinsic) Laplacian, which is what makes the
method apply to meschers.  ``largesteps.geometry.compute_matrix`` hard-codes ``device='cuda'``,
so ``I + lambda L`` is built here with scipy; its ``parameterize`` and ``optimize`` modules are
device-agnostic and are used as they are (cholespy solves on the CPU).

As in the paper, xy steps and zeta steps alternate and use separate SoftRas ``sigma``; the
depth offsets (which only decide the soft z-ordering) move with the zeta steps.  Afterwards the
partial depth order is extracted from the faces that overlap on screen (:func:`extract_order`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ._torch import require_largesteps, require_torch

torch = require_torch()
require_largesteps()

from largesteps.optimize import AdamUniform  # noqa: E402
from largesteps.parameterize import from_differential, to_differential  # noqa: E402

from ..errors import MescherError  # noqa: E402
from ..mescher import Mescher  # noqa: E402
from .rasterizer import face_normals_from_zeta, lambertian, soft_rasterize  # noqa: E402

# ---------------------------------------------------------------------------------------------
# Initialization: a torus seen from the view
# ---------------------------------------------------------------------------------------------


def torus_mesh(
    major: float = 0.6, minor: float = 0.2, n_major: int = 64, n_minor: int = 16, center=(0, 0)
) -> tuple[np.ndarray, np.ndarray]:
    """A torus lying in the screen plane (axis along z, toward the viewer), outward oriented.

    Parameters
    ----------
    major, minor : float
        Radius of the centre circle and of the tube.
    n_major, n_minor : int
        Vertices around the hole and around the tube (``2 n_major n_minor`` faces).
    center : (2,) float
        Screen position of the centre.

    Returns
    -------
    V : (n_major n_minor, 3) float64
        ``((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`` plus ``center``.
    F : (2 n_major n_minor, 3) int64
    """
    if not (major > minor > 0) or n_major < 3 or n_minor < 3:
        raise MescherError(
            "torus: expected major > minor > 0 and n_major, n_minor >= 3, found "
            f"major={major}, minor={minor}, n_major={n_major}, n_minor={n_minor}"
        )
    u = 2 * np.pi * np.arange(n_major) / n_major
    v = 2 * np.pi * np.arange(n_minor) / n_minor
    U, W = np.meshgrid(u, v, indexing="ij")
    ring = major + minor * np.cos(W)
    V = np.stack([ring * np.cos(U), ring * np.sin(U), minor * np.sin(W)], axis=-1).reshape(-1, 3)
    V[:, :2] += np.asarray(center, dtype=np.float64)
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a = i * n_minor + j
    b = ((i + 1) % n_major) * n_minor + j
    c = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor
    d = i * n_minor + (j + 1) % n_minor
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1)
                        .reshape(-1, 3)])  # fmt: skip
    return V, F.astype(np.int64)


def torus_mescher(
    major: float = 0.6, minor: float = 0.2, n_major: int = 64, n_minor: int = 16, center=(0, 0)
) -> tuple[Mescher, np.ndarray]:
    """The torus of :func:`torus_mesh` as a (possible) mescher, and its face depth offsets.

    Returns
    -------
    m : Mescher
        ``Mescher.from_mesh`` of the torus, viewed along z.
    offsets : (#F,) float64
        Face centroid depths mapped affinely to [0.25, 0.75] (larger nearer): the torus's own
        occlusion, as the initial soft z-ordering.
    """
    V, F = torus_mesh(major, minor, n_major, n_minor, center)
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


# ---------------------------------------------------------------------------------------------
# Figures of merit
# ---------------------------------------------------------------------------------------------


def silhouette_iou(mask_a: np.ndarray, mask_b: np.ndarray) -> float:
    """Intersection over union of two (H, W) boolean masks (1.0 when both are empty)."""
    a, b = np.asarray(mask_a, bool), np.asarray(mask_b, bool)
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else float(np.logical_and(a, b).sum() / union)


def psnr(image: np.ndarray, target: np.ndarray) -> float:
    """Peak signal-to-noise ratio in dB of images with values in [0, 1]: ``-10 log10(MSE)``."""
    mse = float(np.mean((np.asarray(image, float) - np.asarray(target, float)) ** 2))
    return math.inf if mse == 0 else -10.0 * math.log10(mse)


def max_period_ratio(m: Mescher) -> float:
    """Largest ``|period|`` of ``m`` over its size (the longer side of its screen bounding box)."""
    p = m.periods()
    size = float(np.ptp(np.asarray(m.xy), axis=0).max())
    return 0.0 if p.size == 0 or size == 0 else float(np.abs(p).max() / size)


# ---------------------------------------------------------------------------------------------
# The parametrization and the fit
# ---------------------------------------------------------------------------------------------


def _sparse_to_torch(A: sp.spmatrix, dtype) -> torch.Tensor:
    A = sp.coo_matrix(A)
    idx = torch.as_tensor(np.vstack([A.row, A.col]).astype(np.int64))
    val = torch.as_tensor(A.data, dtype=dtype)
    return torch.sparse_coo_tensor(idx, val, A.shape, check_invariants=False).coalesce()


def sobolev_matrix(m: Mescher, lam: float, laplacian: str = "cotan") -> sp.csc_matrix:
    """``I + lambda L`` of Nicolet et al. 2021, ``L`` positive semi-definite.

    Parameters
    ----------
    m : Mescher
    lam : float
        Diffusion parameter lambda (>= 0).
    laplacian : {"cotan", "uniform"}
        ``-m.cotmatrix()`` (intrinsic, from xy and zeta: the mescher's Laplacian) or the
        combinatorial graph Laplacian ``d01^T d01`` used by ``largesteps`` by default.

    Returns
    -------
    (#V, #V) scipy.sparse.csc_matrix, symmetric positive definite.
    """
    if not lam >= 0:
        raise MescherError(f"lam: expected a non-negative number, found {lam}")
    if laplacian == "cotan":
        L = -m.cotmatrix()
    elif laplacian == "uniform":
        L = m.d01.T @ m.d01
    else:
        raise MescherError(f"laplacian: expected 'cotan' or 'uniform', found {laplacian!r}")
    return sp.csc_matrix(sp.identity(m.n_vertices) + lam * L)


def closed_harmonic_basis(m: Mescher, tol: float = 1e-14) -> np.ndarray:
    """``m.harmonic_basis()`` with its closedness refined to round-off.

    The harmonic basis comes from a linear solve, so ``d12 H`` is small but not round-off small
    (about 1e-10 on a 2k-face torus); with periods of order one that would break
    ``d12 zeta = 0`` to 1e-10.  Each column gets the least-norm correction ``delta`` with
    ``d12 delta = d12 h`` (LSQR), which moves it by about that residual and leaves it closed to
    round-off; its periods change by as little.

    Returns
    -------
    (#E, k) float64
    """
    from scipy.sparse.linalg import lsqr

    H = np.array(m.harmonic_basis(), dtype=np.float64, copy=True)
    d12 = sp.csr_matrix(m.d12, dtype=np.float64)
    for k in range(H.shape[1]):  # k = 2g + b - 1 columns: a handful
        r = d12 @ H[:, k]
        if np.abs(r).max(initial=0.0) > 0:
            H[:, k] -= lsqr(d12, r, atol=tol, btol=tol, iter_lim=10 * d12.shape[1])[0]
    return H


class MescherParametrization:
    """``xy``, ``zeta = d01 z + H c`` and face offsets of a mescher as PyTorch leaves.

    ``u_xy = M xy`` and ``u_z = M z`` (differential coordinates, ``M = I + lambda L``, float32
    for cholespy), the periods ``c`` (k,) and the offsets (#F,) are the optimized tensors.
    ``zeta`` is assembled in float64 so that ``d12 zeta = 0`` to round-off.

    Parameters
    ----------
    m : Mescher
        Initial mescher; its connectivity, Laplacian and harmonic basis are kept.
    offsets : (#F,) array_like, optional
        Initial depth offsets (default zeros).
    lam : float, default: 10.0
        Sobolev diffusion parameter.
    laplacian : {"cotan", "uniform"}
        See :func:`sobolev_matrix`.
    """

    def __init__(self, m: Mescher, offsets=None, lam: float = 10.0, laplacian: str = "cotan"):
        self.m0 = m
        self.F = torch.tensor(np.asarray(m.F), dtype=torch.long)
        edges = np.array(m.edges)
        self.tail = torch.as_tensor(edges[:, 0], dtype=torch.long)
        self.head = torch.as_tensor(edges[:, 1], dtype=torch.long)
        self.face_edges = torch.tensor(np.asarray(m.face_edges), dtype=torch.long)
        self.face_edge_signs = torch.tensor(np.asarray(m.face_edge_signs), dtype=torch.float64)
        self.H = torch.as_tensor(closed_harmonic_basis(m), dtype=torch.float64)
        h = m.hodge()
        self.M = _sparse_to_torch(sobolev_matrix(m, lam, laplacian), torch.float32)
        f32 = torch.float32
        xy0 = torch.tensor(np.asarray(m.xy), dtype=f32)
        z0 = torch.tensor(np.asarray(h.z), dtype=f32)[:, None]
        # omega = H @ periods exactly for the dual basis: start from the given periods
        self.u_xy = to_differential(self.M, xy0).detach().requires_grad_(True)
        self.u_z = to_differential(self.M, z0).detach().requires_grad_(True)
        self.c = torch.as_tensor(m.periods(), dtype=torch.float64).clone().requires_grad_(True)
        o = np.zeros(m.n_faces) if offsets is None else np.asarray(offsets, dtype=np.float64)
        if o.shape != (m.n_faces,):
            raise MescherError(f"offsets: expected shape ({m.n_faces},), found {o.shape}")
        self.offsets = torch.as_tensor(o, dtype=f32).clone().requires_grad_(True)

    def xy(self) -> torch.Tensor:
        """(#V, 2) float32 screen positions, ``M^-1 u_xy``."""
        return from_differential(self.M, self.u_xy)

    def z(self) -> torch.Tensor:
        """(#V,) float32 exact-part depths, ``M^-1 u_z``."""
        return from_differential(self.M, self.u_z)[:, 0]

    def zeta(self) -> torch.Tensor:
        """(#E,) float64 ``d01 z + H c``: closed by construction."""
        z = self.z().double()
        return z[self.head] - z[self.tail] + self.H @ self.c

    def normals(self, xy: torch.Tensor, zeta: torch.Tensor) -> torch.Tensor:
        """(#F, 3) unit face normals of the local corners (float64)."""
        return face_normals_from_zeta(
            self.F, xy.double(), zeta, self.face_edges, self.face_edge_signs
        )

    def mescher(self) -> Mescher:
        """The current iterate as a :class:`Mescher` (validated: ``d12 zeta = 0``)."""
        with torch.no_grad():
            xy = self.xy().double().numpy()
            zeta = self.zeta().numpy()
        return self.m0.with_xy(xy).with_zeta(zeta)


@dataclass
class InverseOptions:
    """Settings of :func:`fit_mescher` (defaults: the Penrose demonstration at 128 x 128).

    Attributes
    ----------
    iters : int, default: 1200
        Steps; even steps move xy, odd steps move z, the periods and the offsets (paper 4.5).
    resolution : int, default: 128
        Informative; the target's size is what is rendered.
    lam : float, default: 10.0
        Sobolev diffusion parameter lambda of ``I + lambda L``.
    laplacian : {"cotan", "uniform"}, default: "cotan"
        ``L`` of :func:`sobolev_matrix`.
    lr_xy, lr_z : float, default: 1e-2, 2e-2
        ``largesteps.optimize.AdamUniform`` rates in differential coordinates.
    lr_periods, lr_offsets : float
        Adam rates of the periods ``c`` (depth units) and of the offsets.
    lr_final : float, default: 0.05
        All rates decay by a cosine to this fraction of their start.
    sigma_xy, sigma_zeta : (float, float)
        SoftRas sharpness (squared screen units, a pixel is ``(2 / 128)^2 = 2.4e-4``) of the xy
        and of the zeta steps, decayed geometrically from the first to the second value.  xy
        needs wide blur early (silhouette gradients reach far), zeta ends nearly hard so that
        the flat-shaded faces are fitted as the final render shows them.
    gamma : float, default: 1e-2
        Softness of the z-ordering by offsets.
    silhouette_weight : float, default: 1.0
        Weight of ``mean (alpha - mask)^2`` added to the image MSE.
    threads : int or None, default: 1
        ``torch.set_num_threads`` during the fit (None: leave it).
    final_sigma : float, default: 1e-6
        Sharpness of the returned render.
    """

    iters: int = 1200
    resolution: int = 128
    lam: float = 10.0
    laplacian: str = "cotan"
    lr_xy: float = 1e-2
    lr_z: float = 2e-2
    lr_periods: float = 2e-2
    lr_offsets: float = 1e-3
    lr_final: float = 0.05
    sigma_xy: tuple[float, float] = (3e-3, 2e-5)
    sigma_zeta: tuple[float, float] = (3e-4, 1e-6)
    gamma: float = 1e-2
    silhouette_weight: float = 1.0
    threads: int | None = 1
    final_sigma: float = 1e-6


@dataclass
class InverseResult:
    """What :func:`fit_mescher` returns."""

    mescher: Mescher
    offsets: np.ndarray
    image: np.ndarray
    alpha: np.ndarray
    losses: list = field(default_factory=list)
    max_residual: float = 0.0
    seconds: float = 0.0


def _schedule(pair: tuple[float, float], t: float) -> float:
    a, b = pair
    return a * (b / a) ** t


def fit_mescher(
    target: np.ndarray,
    init: Mescher,
    offsets=None,
    lights=((0.0, 0.0, 1.0),),
    light_colors=None,
    ambient=0.2,
    background=(1.0, 1.0, 1.0),
    options: InverseOptions | None = None,
    callback: Callable[[int, dict], None] | None = None,
) -> InverseResult:
    """Optimize a mescher so that its soft rendering matches ``target`` (paper Section 4.5).

    Minimizes ``|I(xy, zeta, o) - target|^2`` (mean over pixels and channels) plus
    ``silhouette_weight * |alpha - mask|^2``, with xy steps and zeta/offset steps alternating.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
        Spans the screen square ``[-1, 1]^2`` (row 0 at the top).
    init : Mescher
        Initialization (e.g. :func:`torus_for_target`); its connectivity is kept.
    offsets : (#F,) array_like, optional
        Initial depth offsets (larger nearer).
    lights, light_colors, ambient, background
        Fixed shading, see :func:`.rasterizer.lambertian`.
    options : InverseOptions, optional
    callback : callable(iteration, state), optional
        Called after every step with ``state = {"loss", "zeta" (#E,) float64 ndarray,
        "step": "xy" | "zeta"}``.

    Returns
    -------
    InverseResult
        ``mescher`` (a :class:`Mescher`), ``offsets``, the final hard-ish render ``image``
        (H, W, 3) and ``alpha`` (H, W), per-step ``losses``, the largest ``|d12 zeta|`` seen
        over all iterates (``max_residual``) and the wall time.
    """
    opt = options or InverseOptions()
    if not isinstance(init, Mescher):
        raise MescherError(f"init: expected a Mescher, found {type(init).__name__}")
    target = np.asarray(target, dtype=np.float64)
    if target.ndim != 3 or target.shape[2] != 3 or target.shape[0] != target.shape[1]:
        raise MescherError(f"target: expected an (N, N, 3) image, found shape {target.shape}")
    if not np.all(np.isfinite(target)):
        raise MescherError("target: expected finite values in [0, 1], found non-finite values")
    res = target.shape[0]
    old_threads = torch.get_num_threads()
    if opt.threads:
        # several engineers share two cores: oversubscribed BLAS threads are 10x slower here
        torch.set_num_threads(opt.threads)
    try:
        return _fit(target, res, init, offsets, lights, light_colors, ambient, background, opt,
                    callback)  # fmt: skip
    finally:
        torch.set_num_threads(old_threads)


def _fit(target, res, init, offsets, lights, light_colors, ambient, background, opt, callback):
    t0 = time.perf_counter()
    f32 = torch.float32
    par = MescherParametrization(init, offsets, opt.lam, opt.laplacian)
    d12 = init.d12
    tgt = torch.as_tensor(target, dtype=f32)
    mask = torch.as_tensor(target_mask(target, background), dtype=f32)
    opt_xy = AdamUniform([par.u_xy], lr=opt.lr_xy)
    opt_z = AdamUniform([par.u_z], lr=opt.lr_z)
    opt_rest = torch.optim.Adam(
        [{"params": [par.c], "lr": opt.lr_periods}, {"params": [par.offsets], "lr": opt.lr_offsets}]
    )
    losses: list[float] = []
    max_res = 0.0

    def render(xy, zeta, sigma):
        colors = lambertian(par.normals(xy, zeta), lights, light_colors, ambient).to(f32)
        return soft_rasterize(
            par.F, xy, colors, par.offsets, res, sigma, opt.gamma, background, return_alpha=True
        )

    base_lr = [[g["lr"] for g in o.param_groups] for o in (opt_xy, opt_z, opt_rest)]
    for it in range(opt.iters):
        t = it / max(opt.iters - 1, 1)
        # cosine decay to lr_final: large early steps, then settle the per-face noise
        decay = opt.lr_final + (1.0 - opt.lr_final) * 0.5 * (1.0 + math.cos(math.pi * t))
        for o, lrs in zip((opt_xy, opt_z, opt_rest), base_lr):
            for g, lr in zip(o.param_groups, lrs):
                g["lr"] = lr * decay
        xy_step = it % 2 == 0
        if xy_step:
            xy = par.xy()
            with torch.no_grad():
                zeta = par.zeta()
            img, alpha = render(xy, zeta, _schedule(opt.sigma_xy, t))
        else:
            with torch.no_grad():
                xy = par.xy()
            zeta = par.zeta()
            img, alpha = render(xy, zeta, _schedule(opt.sigma_zeta, t))
        loss = ((img - tgt) ** 2).mean()
        if opt.silhouette_weight:
            loss = loss + opt.silhouette_weight * ((alpha - mask) ** 2).mean()
        for o in (opt_xy, opt_z, opt_rest):
            o.zero_grad()
        loss.backward()
        if xy_step:
            opt_xy.step()
        else:
            opt_z.step()
            opt_rest.step()
        losses.append(float(loss.detach()))
        zeta_np = zeta.detach().numpy()
        max_res = max(max_res, float(np.abs(d12 @ zeta_np).max(initial=0.0)))
        if callback is not None:
            callback(it, {"loss": losses[-1], "zeta": zeta_np, "step": "xy" if xy_step else "zeta"})

    m = par.mescher()
    fitted_offsets = par.offsets.detach().double().numpy()
    with torch.no_grad():
        xy = par.xy()
        zeta = par.zeta()
        colors = lambertian(par.normals(xy, zeta), lights, light_colors, ambient)
        img, alpha = soft_rasterize(
            par.F, xy.double(), colors, par.offsets.double(), res, opt.final_sigma, 1e-3,
            background, return_alpha=True,
        )  # fmt: skip
    max_res = max(max_res, float(np.abs(d12 @ np.asarray(m.zeta)).max(initial=0.0)))
    return InverseResult(
        mescher=m,
        offsets=fitted_offsets,
        image=img.numpy(),
        alpha=alpha.numpy(),
        losses=losses,
        max_residual=max_res,
        seconds=time.perf_counter() - t0,
    )


# ---------------------------------------------------------------------------------------------
# The partial depth order
# ---------------------------------------------------------------------------------------------


def extract_order(m: Mescher, offsets: np.ndarray):
    """The partial depth order of a fitted mescher: overlapping faces compared by offset.

    Parameters
    ----------
    m : Mescher
    offsets : (#F,) float
        Depth offsets from the fit (larger nearer).

    Returns
    -------
    DepthOrder
        Arc ``i -> j`` (i behind j) for each pair of faces that overlap on screen with positive
        area (:func:`meschers_igl.geometry2d.overlapping_pairs`) and have
        ``offsets[i] < offsets[j]``; equal offsets give no arc.
    """
    from ..geometry2d import overlapping_pairs
    from ..order import DepthOrder

    o = np.asarray(offsets, dtype=np.float64)
    if o.shape != (m.n_faces,):
        raise MescherError(f"offsets: expected shape ({m.n_faces},), found {o.shape}")
    pairs, _ = overlapping_pairs(np.asarray(m.xy)[np.asarray(m.F)])
    i, j = pairs[:, 0], pairs[:, 1]
    back = np.where(o[i] < o[j], i, j)
    front = np.where(o[i] < o[j], j, i)
    arcs = np.stack([back, front], axis=1)[o[i] != o[j]]
    return DepthOrder(m.n_faces, arcs, m=m)
