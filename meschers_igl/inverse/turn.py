"""Turning a fit's faces back to their shade regions' normals, during the fit.

A picture holds each face's shade, ``n . l``: the image loss lets a face tilt about the light
as freely as it lets it keep its plane.  :func:`turn_faces` adds the exact form
``d01 dz`` that best turns every face back to its region's normal (periods and screen
positions kept).  Done once after the fit, the fitted screen positions no longer match the
turned faces and the picture's PSNR drops; done every few steps inside the fit
(:func:`turn_parametrization`, ``InverseOptions.turn_every``), the optimizer moves the screen
positions and depths on from the turned faces, and the best PSNR kept is that of a turned
iterate.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import MescherError
from ..mescher import Mescher

#: ``InverseOptions.turn`` for refining a picture-made mescher (:func:`.picture.fit_options`):
#: never turned back, a penalty of weight 0.03 on each face's normal against its shade region's.
#: Measured over the development set and the project's models under 6 random lights each at 200
#: steps: 27 of 60 cases pass the acceptance against 23 of 60 without it, no model losing one;
#: weight 0.1 drops the Penrose stairs' PSNR under 30 dB, turning back costs PSNR.
PICTURE_TURN = (-1, 0.03)


def _slope_wishes(m: Mescher, n: np.ndarray):
    """Per half-edge, the climb its face's plane of normal ``n[f]`` asks for.

    Returns the (3 #F, #E) signed map ``B`` from edge values to half-edges (stored edge sign
    ``s``: ``zeta_e = s * value``) and the wishes ``g_f . (xy_j - xy_i)``,
    ``g_f = -(n_x, n_y) / n_z``, in the same (3 #F,) order.
    """
    g = -n[:, :2] / n[:, 2:3]
    P = np.asarray(m.xy)[np.asarray(m.F)]
    # half-edge opposite corner i runs i+1 -> i+2
    dxy = P[:, [2, 0, 1]] - P[:, [1, 2, 0]]
    wish = np.einsum("fk,fik->fi", g, dxy).reshape(-1)
    fe = np.asarray(m.face_edges)
    sg = np.asarray(m.face_edge_signs)
    rows = np.arange(fe.size)
    B = sp.csr_matrix((sg.reshape(-1), (rows, fe.reshape(-1))), shape=(fe.size, m.n_edges))
    return B, wish


def _weighted_least_squares(A, b: np.ndarray, weights) -> np.ndarray:
    """``argmin |A x - b|^2`` with per-face weights on the rows (three half-edges a face)."""
    from scipy.sparse.linalg import spsolve

    nf = A.shape[0] // 3
    wv = np.ones(nf) if weights is None else np.asarray(weights, dtype=np.float64)
    W = sp.diags(np.repeat(wv, 3))
    # normal equations; z is defined up to a constant per piece: pin it with a tiny ridge
    N = (A.T @ W @ A).tocsc()
    N = N + 1e-12 * float(np.abs(N.diagonal()).max()) * sp.identity(A.shape[1])
    return spsolve(N, A.T @ (W @ b))


def turn_depths(m: Mescher, face_normals: np.ndarray, weights: np.ndarray | None = None):
    """The vertex depths ``dz`` whose exact form turns ``m``'s faces toward ``face_normals``.

    ``m.with_zeta(m.zeta + m.d01 @ dz)`` is :func:`turn_faces` of ``m``: ``dz`` minimizes, in
    (per-face weighted) least squares over the half-edges, the misfit of the climbs
    ``zeta + d01 dz`` to the slopes the planes of ``face_normals`` ask for at the screen
    positions of ``m``.  ``dz`` is defined up to a constant per connected piece.

    Parameters
    ----------
    m : Mescher
    face_normals : (#F, 3) float
        Unit normals with ``n_z > 0``.
    weights : (#F,) float, optional

    Returns
    -------
    (#V,) float64
    """
    if not isinstance(m, Mescher):
        raise MescherError(f"m: expected a Mescher, found {type(m).__name__}")
    n = np.asarray(face_normals, dtype=np.float64)
    if n.shape != (m.n_faces, 3) or not np.all(np.isfinite(n)) or np.any(n[:, 2] <= 0):
        raise MescherError(
            f"face_normals: expected ({m.n_faces}, 3) finite with n_z > 0, found {n.shape}"
            + ("" if n.shape != (m.n_faces, 3) else " with n_z <= 0 or non-finite values")
        )
    B, wish = _slope_wishes(m, n)
    zeta = np.asarray(m.zeta, dtype=np.float64)
    return _weighted_least_squares((B @ m.d01).tocsr(), wish - B @ zeta, weights)


def turn_faces(m: Mescher, face_normals: np.ndarray, weights: np.ndarray | None = None) -> Mescher:
    """``m`` with its periods and screen positions kept and its faces turned toward
    ``face_normals``.

    A fit against the image moves vertices on screen and bends faces as it goes; a picture of
    boxes, though, has flat faces in the orientations their shades gave.  This adds the exact
    form ``d01 dz`` (which changes no period, so ``d12 zeta`` stays 0 and the figure's climb
    stays the fitted one) that best meets the faces' slope wishes (:func:`lift`), in least
    squares: every face whose plane its neighbours allow takes its normal exactly.

    Parameters
    ----------
    m : Mescher
    face_normals : (#F, 3) float
        Unit normals with ``n_z > 0`` (e.g. the region normals of
        :func:`mescher_from_picture`, ``info["normals"][region]``).
    weights : (#F,) float, optional

    Returns
    -------
    Mescher
    """
    zeta = np.asarray(m.zeta, dtype=np.float64)
    return m.with_zeta(zeta + m.d01 @ turn_depths(m, face_normals, weights))


class FaceTurn:
    """What :func:`.optimize.fit_mescher` does with ``face_normals`` during the fit.

    Parameters
    ----------
    face_normals : (#F, 3) float
        Unit normals with ``n_z > 0``.
    every : int
        Turn the faces back (:func:`turn_parametrization`) after every so many steps; 0: never.
    weight : float
        Weight of the penalty ``mean_f (1 - n_f . face_normals[f])`` added to the loss of
        every step (0: none): half the mean squared distance of the faces' normals to theirs.
    """

    def __init__(self, face_normals: np.ndarray, every: int = 0, weight: float = 0.0):
        self.face_normals = np.asarray(face_normals, dtype=np.float64)
        self.every, self.weight = int(every), float(weight)
        self._want = None

    def penalty(self, par, xy, zeta):
        """The penalty term (a scalar tensor, or 0.0 without a weight)."""
        if not self.weight:
            return 0.0
        import torch

        if self._want is None:
            self._want = torch.as_tensor(self.face_normals, dtype=torch.float64, device=xy.device)
        n = par.normals(xy, zeta)
        return self.weight * (1.0 - (n * self._want).sum(dim=1)).mean()

    def after_step(self, par, it: int) -> None:
        """After step ``it`` (from 0): turn the faces back every ``every`` steps."""
        if self.every > 0 and (it + 1) % self.every == 0:
            turn_parametrization(par, self.face_normals)


def turn_parametrization(par, face_normals: np.ndarray, weights=None) -> None:
    """Turn the faces of a fit's current iterate toward ``face_normals``, in place.

    Adds :func:`turn_depths` of ``par.mescher()`` to the depth leaf of ``par`` (a
    :class:`.sobolev.MescherParametrization`): ``z`` itself under ``power=1``, its
    differential ``(I + lambda L) z`` under ``power=2``.  The periods, screen positions and
    offsets stay, and so does the optimizers' state.
    """
    import torch
    from largesteps.parameterize import to_differential

    dz = turn_depths(par.mescher(), face_normals, weights)
    leaf = par.z_leaf.leaf
    with torch.no_grad():
        step = torch.as_tensor(dz, dtype=leaf.dtype, device=leaf.device)[:, None]
        if par.z_leaf.power == 2:
            step = to_differential(par.z_leaf.M, step)
        leaf.add_(step)
