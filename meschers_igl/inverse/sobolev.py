"""The unknowns of the fit and their Sobolev preconditioner (Nicolet et al. 2021).

The unknowns are screen positions ``xy`` (#V, 2), relative depths and one depth offset per face.
Depths are parametrized on the space of meschers,

    zeta = d01 z + H c,

with ``z`` (#V,) a per-vertex depth and ``H`` (#E, k) the harmonic basis dual to the homology
generators (``m.harmonic_basis()``: the period of ``h_j`` around generator ``i`` is
``delta_ij``), so ``c`` *are* the periods and ``d12 zeta = d12 d01 z + d12 H c = 0`` holds for
every iterate, to round-off.

The preconditioner: what is computed, and why
---------------------------------------------
With ``M = I + lambda L`` (``L`` positive semi-definite), two steps are on offer
(``power`` below):

- ``power=2`` (default, what ``largesteps`` computes): the leaves are the *differential
  coordinates* ``u = M x`` and ``x = M^-1 u``.  The gradient in ``u`` is ``M^-1 g`` and the
  step in ``u`` moves ``x`` by ``M^-1`` of it, so a gradient step in ``x`` is
  ``(I + lambda L)^-2 g``.  This is the parametrization of Nicolet et al. 2021 (their Sec. 4-5:
  "we reparametrize ... and take steps on u"), combined with their uniformly scaled Adam
  (``largesteps.optimize.AdamUniform``), and it is what their ``lambda`` values are tuned for.
- ``power=1``: ``x`` itself is the leaf and its gradient is replaced by ``(I + lambda L)^-1 g``
  before the step (the Sobolev gradient as the mescher paper writes it, Sec. 4.5, Eq. for
  ``g-hat``).  It smooths less: a silhouette gradient reaches about ``sqrt(lambda)`` rings
  instead of twice as far.

``L`` is the combinatorial graph Laplacian ``d01^T d01`` (``laplacian="uniform"``, largesteps'
default, *not* mass-normalised: Nicolet et al.'s ``lambda`` is in "rings", independent of the
mesh's scale) or the mescher's own intrinsic cotangent Laplacian ``-m.cotmatrix()``
(``laplacian="cotan"``, computed from ``xy`` and ``zeta``: what makes the method apply to
meschers; also not divided by the mass matrix so that ``M`` stays symmetric for Cholesky).
``largesteps.geometry.compute_matrix`` hard-codes ``device='cuda'``, so ``M`` is built here with
scipy; the solves use ``largesteps``' cholespy solver (CPU or CUDA).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ._torch import require_largesteps, require_torch

torch = require_torch()
require_largesteps()

from largesteps.parameterize import from_differential, to_differential  # noqa: E402
from largesteps.solvers import CholeskySolver  # noqa: E402

from ..errors import MescherError  # noqa: E402
from ..mescher import Mescher  # noqa: E402
from .rasterizer import face_normals_from_zeta  # noqa: E402


def sparse_to_torch(A: sp.spmatrix, dtype, device=None) -> torch.Tensor:
    """A scipy sparse matrix as a coalesced ``torch.sparse_coo_tensor``."""
    A = sp.coo_matrix(A)
    idx = torch.as_tensor(np.vstack([A.row, A.col]).astype(np.int64))
    val = torch.as_tensor(A.data, dtype=dtype)
    out = torch.sparse_coo_tensor(idx, val, A.shape, check_invariants=False).coalesce()
    return out if device is None else out.to(device)


def sobolev_matrix(m: Mescher, lam: float, laplacian: str = "uniform") -> sp.csc_matrix:
    """``I + lambda L`` of Nicolet et al. 2021, ``L`` positive semi-definite.

    Parameters
    ----------
    m : Mescher
    lam : float
        Diffusion parameter lambda (>= 0).
    laplacian : {"uniform", "cotan"}
        The combinatorial graph Laplacian ``d01^T d01`` (largesteps' default) or
        ``-m.cotmatrix()`` (intrinsic, from xy and zeta: the mescher's Laplacian); neither is
        divided by a mass matrix (module docstring).

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
        raise MescherError(f"laplacian: expected 'uniform' or 'cotan', found {laplacian!r}")
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


class SobolevLeaf:
    """One optimized array ``x`` (#V, d) under the preconditioner ``(I + lambda L)^-power``.

    ``leaf`` is the tensor handed to the optimizer; :meth:`value` gives ``x`` (differentiable);
    :meth:`precondition` must be called between ``backward()`` and the optimizer's step (it
    does nothing for ``power=2``, where the reparametrization does the work).
    """

    def __init__(self, M: torch.Tensor, x0: torch.Tensor, power: int):
        if power not in (1, 2):
            raise MescherError(f"power: expected 1 or 2, found {power!r}")
        self.M, self.power = M, power
        if power == 2:
            self.leaf = to_differential(M, x0).detach().requires_grad_(True)
        else:
            self.solver = CholeskySolver(M)
            self.leaf = x0.detach().clone().requires_grad_(True)

    def value(self) -> torch.Tensor:
        return from_differential(self.M, self.leaf) if self.power == 2 else self.leaf

    @torch.no_grad()
    def precondition(self) -> None:
        if self.power == 1 and self.leaf.grad is not None:
            self.leaf.grad.copy_(self.solver.solve(self.leaf.grad.contiguous()))


class MescherParametrization:
    """``xy``, ``zeta = d01 z + H c`` and face offsets of a mescher as PyTorch leaves.

    ``xy`` and ``z`` are :class:`SobolevLeaf` (float32 for cholespy), the periods ``c`` (k,)
    and the offsets (#F,) are plain leaves.  ``zeta`` is assembled in float64 so that
    ``d12 zeta = 0`` to round-off.

    Parameters
    ----------
    m : Mescher
        Initial mescher; its connectivity, Laplacian and harmonic basis are kept.
    offsets : (#F,) array_like, optional
        Initial depth offsets (default zeros).
    lam : float, default: 10.0
        Sobolev diffusion parameter.
    laplacian : {"uniform", "cotan"}
        See :func:`sobolev_matrix`.
    power : {2, 1}
        ``(I + lambda L)^-power`` (module docstring).
    lam_z : float, optional
        Its own lambda for the depths (default ``lam``).
    device : str or torch.device, optional
        Where the tensors live (default CPU).
    """

    def __init__(
        self,
        m: Mescher,
        offsets=None,
        lam: float = 10.0,
        laplacian: str = "uniform",
        power: int = 2,
        lam_z: float | None = None,
        device=None,
    ):
        self.m0 = m
        self.device = torch.device("cpu") if device is None else torch.device(device)
        dev = self.device
        self.F = torch.tensor(np.asarray(m.F), dtype=torch.long, device=dev)
        edges = np.array(m.edges)
        self.tail = torch.as_tensor(edges[:, 0], dtype=torch.long, device=dev)
        self.head = torch.as_tensor(edges[:, 1], dtype=torch.long, device=dev)
        self.face_edges = torch.tensor(np.asarray(m.face_edges), dtype=torch.long, device=dev)
        self.face_edge_signs = torch.tensor(
            np.asarray(m.face_edge_signs), dtype=torch.float64, device=dev
        )
        self.H = torch.as_tensor(closed_harmonic_basis(m), dtype=torch.float64, device=dev)
        h = m.hodge()
        f32 = torch.float32
        M_xy = sparse_to_torch(sobolev_matrix(m, lam, laplacian), f32, dev)
        lz = lam if lam_z is None else lam_z
        M_z = M_xy if lz == lam else sparse_to_torch(sobolev_matrix(m, lz, laplacian), f32, dev)
        self.M = M_xy
        xy0 = torch.tensor(np.asarray(m.xy), dtype=f32, device=dev)
        z0 = torch.tensor(np.asarray(h.z), dtype=f32, device=dev)[:, None]
        self.xy_leaf = SobolevLeaf(M_xy, xy0, power)
        self.z_leaf = SobolevLeaf(M_z, z0, power)
        # omega = H @ periods exactly for the dual basis: start from the given periods
        self.c = torch.as_tensor(m.periods(), dtype=torch.float64, device=dev)
        self.c = self.c.clone().requires_grad_(True)
        o = np.zeros(m.n_faces) if offsets is None else np.asarray(offsets, dtype=np.float64)
        if o.shape != (m.n_faces,):
            raise MescherError(f"offsets: expected shape ({m.n_faces},), found {o.shape}")
        self.offsets = torch.as_tensor(o, dtype=f32, device=dev).clone().requires_grad_(True)

    def xy(self) -> torch.Tensor:
        """(#V, 2) float32 screen positions."""
        return self.xy_leaf.value()

    def z(self) -> torch.Tensor:
        """(#V,) float32 exact-part depths."""
        return self.z_leaf.value()[:, 0]

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
            xy = self.xy().double().cpu().numpy()
            zeta = self.zeta().cpu().numpy()
        return self.m0.with_xy(xy).with_zeta(zeta)
