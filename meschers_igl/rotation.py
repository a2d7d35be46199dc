"""Turning a mescher a little: rotation that keeps the illusion (paper Sec. 6, future work).

A locally integrable ``zeta`` gives every edge a well-defined 3D vector
``e = (dx, dy, zeta)`` with ``(dx, dy) = d01 xy`` (both faces of an edge agree on it), so a
rotation ``R`` turns every triangle's local shape by turning the edge vectors::

    (a, b, c) = R (dx, dy, zeta)        per edge, (#E, 3).

With ``zeta = d01 z + omega`` (Hodge decomposition), ``a = d01 (R00 x + R01 y + R02 z) +
R02 omega``: the harmonic part of the depth leaks into the screen coordinates, which must stay
one value per vertex.  So ``x'`` and ``y'`` are the least-squares (``star1``) potentials of
``a`` and ``b`` -- a Poisson solve ``d01^T star1 d01 x' = d01^T star1 a`` -- which drops
exactly ``R02 omega`` and ``R12 omega`` (harmonic forms are ``star1``-orthogonal to exact
ones).  The new depth ``c`` is closed already (a combination of closed forms); it is
projected onto the locally integrable forms when round-off left more than a trace.  The
periods keep their meaning -- the depth gained around each loop of the same homology basis -- and become
``R22 * periods``: the depth component of the turned jump ``R (0, 0, p)``; its screen
component is what the projection cannot keep.

A mescher that embeds (``omega = 0``) is turned exactly like its 3D mesh; at 0 degrees the
turn is the identity.  The screen position of the turned figure is the turn of each
connected part's centroid about the figure's centroid (area-weighted, ``star0``), so a
turntable keeps the figure centred.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from .errors import MescherError
from .validate import as_float_array, as_vector

#: Integrability residual (times the model's size) above which the turned depths are projected.
ROUND_OFF_RTOL = 1e-12
#: Named rotation axes in the camera frame (x right, y up, z toward the viewer).
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class Turn:
    """A turned mescher and what the turn could not keep.

    Attributes
    ----------
    mescher : Mescher
        The turned mescher (same faces, edges and homology basis).
    order : DepthOrder or None
        The depth order carried to it (``order.follow``), when one was given.
    matrix : (3, 3) float64
        The rotation ``R`` in the camera frame.
    residual : float
        Relative projection residual ``||(a, b) - d01 (x', y')|| / ||(a, b)||`` (norms
        weighted by ``|star1|``):
        the share of the turned screen-space edge vectors that no single-valued ``xy`` can
        hold (0 for a mescher that embeds, ``|R[:2, 2]| ||omega|| / ||(a, b)||`` otherwise).
    lost : (#E, 2) float64
        The dropped screen 1-forms ``(a, b) - d01 (x', y')``: harmonic, equal to
        ``R[:2, 2] * omega``.
    """

    mescher: Any
    order: Any
    matrix: np.ndarray
    residual: float
    lost: np.ndarray


def rotation_matrix(degrees: float, axis: Any = "y") -> np.ndarray:
    """The (3, 3) rotation by ``degrees`` about ``axis`` (right-handed, camera frame).

    Parameters
    ----------
    degrees : float
        Angle; positive turns counter-clockwise seen from the tip of ``axis``.
    axis : {"x", "y", "z"} or (3,) array_like
        Screen x (right), screen y (up), the view direction z, or any non-zero direction.

    Returns
    -------
    (3, 3) float64
        ``R`` with ``R @ p`` the turned point; ``R == I`` exactly at 0 degrees.
    """
    try:
        angle = float(degrees)
    except (TypeError, ValueError):
        raise MescherError(f"degrees: expected a number, found {degrees!r}") from None
    if not np.isfinite(angle):
        raise MescherError(f"degrees: expected a finite number, found {angle}")
    if isinstance(axis, str):
        if axis.lower() not in AXES:
            raise MescherError(f"axis: expected 'x', 'y', 'z' or a (3,) direction, found {axis!r}")
        u = np.asarray(AXES[axis.lower()])
    else:
        u = as_float_array(axis, "axis", (3,))
        n = float(np.linalg.norm(u))
        if n == 0.0:
            raise MescherError(f"axis: expected a non-zero direction, found {u.tolist()}")
        u = u / n
    if angle == 0.0:  # exactly the identity (scipy's matrix carries 1 - cos(0) round-off)
        return np.eye(3)
    return Rotation.from_rotvec(np.deg2rad(angle) * u).as_matrix()


def _component_centroids(m: Any, z: np.ndarray, w: np.ndarray, labels, ncomp: int) -> np.ndarray:
    """(ncomp, 3) area-weighted centroids of (x, y, z) per connected part."""
    P = np.column_stack([m.xy, z])
    wsum = np.bincount(labels, weights=w, minlength=ncomp)
    return np.column_stack(
        [np.bincount(labels, weights=w * P[:, k], minlength=ncomp) / wsum for k in range(3)]
    )


def rotate(
    m: Any, degrees: float, axis: Any = "y", order: Any = None, depth_offsets: Any = None
) -> Turn:
    """Turn a mescher by ``degrees`` about ``axis`` (see the module notes for the math).

    Parameters
    ----------
    m : Mescher
    degrees : float
    axis : {"x", "y", "z"} or (3,) array_like
        In the camera frame, right-handed: a positive turn about ``"x"`` brings the top toward
        the viewer; about ``"y"`` it takes the right side away from the viewer.
    order : DepthOrder, optional
        Carried to the turned mescher with ``order.follow`` (arcs kept where faces still
        overlap, new overlaps ordered from local depth).
    depth_offsets : (k,) array_like, optional
        Depth of each connected part's centroid (parts as numbered by
        ``m.exact_part_solver().labels``); a mescher stores no depth between its parts, so by
        default all centroids are at one depth.  Only where parts sit on screen after the turn
        depends on it.

    Returns
    -------
    Turn
        ``mescher``, ``order``, ``matrix``, ``residual``, ``lost``.

    Notes
    -----
    Cost: one Poisson solve with the factorization the Hodge decomposition already uses (two
    right-hand sides) and one projection onto closed forms.
    """
    R = rotation_matrix(degrees, axis)
    solver = m.exact_part_solver()
    labels, ncomp = solver.labels, solver.ncomp
    offsets = (
        np.zeros(ncomp)
        if depth_offsets is None
        else as_vector(depth_offsets, "depth_offsets", ncomp)
    )
    w = np.asarray(m.star0.diagonal(), dtype=np.float64)
    E = np.asarray(m.edges)
    dxy = m.xy[E[:, 1]] - m.xy[E[:, 0]]
    e3 = np.column_stack([dxy, m.zeta])  # the 3D vector of each edge, shared by its faces
    turned = e3 @ R.T
    z = m.hodge().z + offsets[labels]
    P = np.column_stack([m.xy, z])
    centre = (w @ P) / w.sum()
    s1 = np.abs(np.asarray(m.star1.diagonal(), dtype=np.float64))  # a norm: |cot weights|
    if R[0, 2] == 0.0 and R[1, 2] == 0.0:
        # no depth enters the screen (a turn about the view axis): the turn is exact on screen
        xy_new = (P[:, :2] - centre[:2]) @ R[:2, :2].T + centre[:2]
        lost = np.zeros((m.n_edges, 2))
        residual = 0.0
    else:
        # Poisson: the star1-nearest exact forms to the turned screen 1-forms (zero weighted
        # mean per part), each part then placed where its turned centroid falls.
        xy_new = solver.potential(np.ascontiguousarray(turned[:, :2]), w)
        c_new = centre + (_component_centroids(m, z, w, labels, ncomp) - centre) @ R.T
        xy_new = xy_new + c_new[labels, :2]
        lost = turned[:, :2] - (xy_new[E[:, 1]] - xy_new[E[:, 0]])
        denom = float(np.sqrt(np.sum(s1[:, None] * turned[:, :2] ** 2)))
        residual = float(np.sqrt(np.sum(s1[:, None] * lost**2))) / denom if denom > 0 else 0.0
    # c = R20 d01 x + R21 d01 y + R22 zeta is closed; projected onto the closed forms only when
    # round-off left more than a trace (the projection's factorization costs more than the turn)
    zeta_new = np.ascontiguousarray(turned[:, 2])
    if np.abs(m.d12 @ zeta_new).max(initial=0.0) > ROUND_OFF_RTOL * m.scale():
        zeta_new = m._closed_projector(zeta_new)
    out = m.with_xy(xy_new).with_zeta(zeta_new)
    new_order = None if order is None else order.follow(out)
    return Turn(out, new_order, R, residual, lost)
