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
