"""Figures of merit of a fitted picture and mescher (numpy).

These are the inverse-rendering acceptance numbers.  The image comparison of the application
(``pyvista_views.compare``) measures a mean luminance difference in 0-255 on rendered uint8
images and lives outside ``meschers_igl`` (which may not import it); what is needed here is
PSNR on float images in [0, 1], silhouette IoU and quantities of the mescher itself, so they are
kept here under their own names (``image_psnr``, ``silhouette_iou``), not as a second copy of
the luminance scale.
"""

from __future__ import annotations

import math

import numpy as np

from ..mescher import Mescher


def silhouette_iou(mask_a: np.ndarray, mask_b: np.ndarray) -> float:
    """Intersection over union of two (H, W) boolean masks (1.0 when both are empty)."""
    a, b = np.asarray(mask_a, bool), np.asarray(mask_b, bool)
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else float(np.logical_and(a, b).sum() / union)


def image_psnr(image: np.ndarray, target: np.ndarray) -> float:
    """Peak signal-to-noise ratio in dB of images with values in [0, 1]: ``-10 log10(MSE)``."""
    mse = float(np.mean((np.asarray(image, float) - np.asarray(target, float)) ** 2))
    return math.inf if mse == 0 else -10.0 * math.log10(mse)


def max_period_ratio(m: Mescher) -> float:
    """Largest ``|period|`` of ``m`` over its size (the longer side of its screen bounding box)."""
    p = m.periods()
    size = float(np.ptp(np.asarray(m.xy), axis=0).max())
    return 0.0 if p.size == 0 or size == 0 else float(np.abs(p).max() / size)


def boundary_loop_periods(m: Mescher) -> tuple[np.ndarray, np.ndarray]:
    """Depth gained once around each boundary loop of ``m``, and the area each loop encloses.

    The period around a hole of the picture is measured on the hole's own boundary: the sum of
    ``zeta`` along the loop (a closed 1-form has the same sum on every loop homologous to it).
    Loops follow the faces' orientation, so the outer boundary runs counter-clockwise and holes
    clockwise on screen.

    Returns
    -------
    periods : (B,) float64
        ``sum zeta`` along each loop of :func:`meschers_igl.topology.boundary_loops`.
    areas : (B,) float64
        Signed screen area enclosed (positive: counter-clockwise, the outer boundary).
    """
    from ..topology import boundary_loops, edge_lookup

    xy = np.asarray(m.xy)
    zeta = np.asarray(m.zeta)
    periods, areas = [], []
    for loop in boundary_loops(np.asarray(m.F)):
        tail, head = loop, np.roll(loop, -1)
        e, sign = edge_lookup(np.asarray(m.edges), m.n_vertices, tail, head)
        periods.append(float((sign * zeta[e]).sum()))
        p, q = xy[tail], xy[head]
        areas.append(0.5 * float((p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]).sum()))
    return np.asarray(periods), np.asarray(areas)


def figure_period(m: Mescher) -> float:
    """The largest ``|period|`` going once around the figure's outline or one of its holes.

    Measured on the boundary loops (:func:`boundary_loop_periods`) that enclose area: the
    outline (counter-clockwise) and the holes; slits cut along occlusions enclose none.  A
    figure with one hole (a Penrose triangle) climbs its period around the outline, which
    :func:`.picture.mescher_from_picture` keeps one closed loop.  0.0 without such loops.
    """
    periods, areas = boundary_loop_periods(m)
    size = np.abs(areas).max(initial=0.0)
    real = np.abs(areas) > 1e-6 * size
    return float(np.abs(periods[real]).max(initial=0.0))


def axis_aligned_share(
    visible: np.ndarray, face_normals: np.ndarray, axes: np.ndarray, max_deg: float = 10.0
) -> float:
    """Share of figure pixels whose visible face's normal is within ``max_deg`` of an axis.

    Parameters
    ----------
    visible : (H, W) int
        Face seen at each pixel, -1 on the background
        (e.g. :func:`meschers_igl.painter.visible_faces`).
    face_normals : (#F, 3) float
        Unit normals, camera frame.
    axes : (A, 3) float
        The figure's axis directions, camera frame (either sign counts).
    max_deg : float

    Returns
    -------
    float in [0, 1]
    """
    v = np.asarray(visible)
    f = v[v >= 0]
    if f.size == 0:
        return 0.0
    a = np.asarray(axes, dtype=np.float64)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    cos = np.abs(np.asarray(face_normals)[f] @ a.T).max(axis=1)
    return float(np.mean(cos >= np.cos(np.radians(max_deg))))


def picture_axes(V, F, view, max_deg: float = 10.0) -> np.ndarray:
    """(3, 3) the three main face directions a picture of a 3D model shows (either sign).

    Greedy over the face normals: the direction with the most projected area within
    ``max_deg`` of it, then the one with the most of what remains (more than ``max_deg`` from
    the first), then from both.  A face of area ``A`` and unit normal ``n`` covers
    ``A |n . view|`` of an orthographic picture (before occlusion); a face seen edge-on is not in
    the picture whatever its area.  The absolute value takes either orientation (files are not
    always outward).  For a model of boxes these are its axes; for a sheared model (a tribar
    made a real torus by shearing the bars a picture shows edge-on) the directions of the faces
    seen, which a person reads; for a relief, its real (not quite right-angled) face directions.

    Parameters
    ----------
    V : (#V, 3) float
    F : (#F, 3) int
    view : (3,) float
        Direction from the model toward the viewer (any length but zero).
    max_deg : float

    Returns
    -------
    (3, 3) float64
        Unit directions, rows in order of projected area, in the frame of ``V``.

    Raises
    ------
    MescherError
        Malformed ``V``, ``F`` or ``view``, or no face seen from ``view``.
    """
    from ..errors import MescherError

    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    v = np.asarray(view, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] != 3:
        raise MescherError(f"V: expected (#V, 3) vertex positions, found shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3 or not np.issubdtype(F.dtype, np.integer):
        raise MescherError(f"F: expected (#F, 3) integer triangles, found {F.dtype} {F.shape}")
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise MescherError(f"view: expected a nonzero (3,) direction, found {v!r}")
    v = v / np.linalg.norm(v)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    area = np.linalg.norm(n, axis=1)
    ok = area > 1e-12 * area.max(initial=0.0)
    n = n[ok] / area[ok, None]
    seen = area[ok] * np.abs(n @ v)
    if seen.sum() <= 0:
        raise MescherError("view: expected some face seen from it, found every face edge-on")
    # faces of one orientation (a box model's) vote once; the rest in blocks of rows, so that
    # many distinct normals (a relief) need no #F x #F matrix
    n, inv = np.unique(np.round(n, 9), axis=0, return_inverse=True)
    seen = np.bincount(inv.ravel(), seen, minlength=len(n))
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    cos = math.cos(math.radians(max_deg))
    score = np.concatenate(
        [(np.abs(n[i : i + 2048] @ n.T) > cos) @ seen for i in range(0, len(n), 2048)]
    )
    taken = np.zeros(len(n), dtype=bool)
    axes = []
    for _ in range(3):
        k = int(np.argmax(np.where(taken, -1.0, score)))
        axes.append(n[k])
        taken |= np.abs(n @ n[k]) > cos
    return np.stack(axes)
