"""Laplacian smoothing of meschers (paper Sec. 4.4).

Screen positions are smoothed like any 0-form; ``zeta`` is split by its Hodge decomposition
``zeta = d01 z + omega`` and only the exact part is smoothed -- ``omega`` spans the kernel of the
1-form Laplacian, so it (and with it every period) is left unchanged::

    xy'   = (M - t_xy L)^-1 M xy
    zeta' = omega + d01 (M - t_zeta L)^-1 M z

(mass-weighted backward Euler, ``L`` the negative semi-definite cotangent matrix).  The paper
prints ``omega + d01((I + tL)^-1 z - z)``; the ``- z`` would cancel the exact part it smooths, so
we read it as the update above, which is what its figures show.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp

from .errors import MescherError, MescherWarning
from .progress import track
from .solvers import factorize_spd
from .validate import as_count, as_positive


def heat_operator(m, t: float):
    """Factor ``M - t L`` once for mescher ``m``; returns ``u -> (M - tL)^-1 M u``."""
    M = m.massmatrix()
    solve = factorize_spd(sp.csc_matrix(M - t * m.cotmatrix()))

    def apply(u: np.ndarray) -> np.ndarray:
        return solve(M @ u)

    return apply


#: smoothed screen extent / original below which the shape is gone (a point, up to round-off)
COLLAPSED = 1e-6
#: ... and below which a warning says how much it shrank
SHRUNK = 0.05


def _kept_shape(xy: np.ndarray, new: np.ndarray, t: float) -> np.ndarray:
    """``new``, refused when smoothing for time ``t`` shrank the figure to a point and warned
    about when it shrank below ``SHRUNK`` of its size (backward Euler divides each mode by
    ``1 + lambda t``: a time far above ``size^2`` leaves only the mean)."""
    size = float(np.ptp(xy, axis=0).max())
    ratio = float(np.ptp(new, axis=0).max()) / size if size > 0 else 1.0
    if not np.all(np.isfinite(new)) or ratio < COLLAPSED:
        raise MescherError(
            f"t_xy: expected a smoothing time that keeps the figure (about size^2 = {size**2:.3g} "
            f"or less), found {t:g}: every vertex moved to one point"
        )
    if ratio < SHRUNK:
        warnings.warn(
            f"t_xy = {t:g} shrank the figure to {ratio:.2%} of its size (size^2 = {size**2:.3g})",
            MescherWarning,
            stacklevel=3,
        )
    return new


def smooth(m, t_xy: float = 0.0, t_zeta: float = 0.0, iterations: int = 1):
    """Smooth screen positions and/or the exact part of the depths (see module docstring).

    Parameters
    ----------
    m : Mescher
    t_xy, t_zeta : float >= 0
        Diffusion times; 0 leaves that part unchanged.  With equal times the joint smoothing
        uses one factorization.
    iterations : int, default: 1
        Repeat, rebuilding the operators from the smoothed mescher each time (as for curvature
        flow); the periods stay fixed throughout.

    Returns
    -------
    Mescher
    """
    t_xy = as_positive(t_xy, "t_xy", allow_zero=True)
    t_zeta = as_positive(t_zeta, "t_zeta", allow_zero=True)
    iterations = as_count(iterations, "iterations")
    # each iteration factors a #V x #V system: ~1 s per iteration at 1M faces
    for _ in track(range(iterations), "smooth", total=iterations, work=m.n_faces * iterations):
        if t_xy == 0 and t_zeta == 0:
            return m
        xy, zeta = np.asarray(m.xy), np.asarray(m.zeta)
        ops = {t: heat_operator(m, t) for t in {t_xy, t_zeta} if t > 0}
        if t_xy > 0:
            xy = _kept_shape(xy, ops[t_xy](xy), t_xy)
        if t_zeta > 0:
            h = m.hodge()
            zeta = h.omega + m.d01 @ ops[t_zeta](np.asarray(h.z))
        m = m.with_xy(xy) if t_xy > 0 else m  # both keep the homology basis
        m = m.with_zeta(zeta) if t_zeta > 0 else m
    return m
