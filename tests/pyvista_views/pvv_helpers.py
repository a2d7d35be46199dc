"""Small scenes and image measures shared by the pyvista_views tests (imported, not fixtures)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from pyvista_views.headless import gl_available

requires_gl = pytest.mark.skipif(not gl_available(), reason="no offscreen OpenGL context")


def sphere(resolution: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """A closed UV sphere (#V, 3), (#F, 3) whose faces overlap on screen (front and back)."""
    s = pv.Sphere(theta_resolution=resolution, phi_resolution=resolution)
    return np.asarray(s.points, dtype=np.float64), s.regular_faces.astype(np.int64)


def back_to_front(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Faces sorted by centroid depth: a valid painter's order for a convex closed surface."""
    return np.argsort(V[F][:, :, 2].mean(axis=1), kind="stable")


def ramp_ring(n_around: int = 48, n_across: int = 4, height: float = 0.6):
    """An impossible annulus: depth climbs ``height`` once around (a Penrose-stair-like ramp).

    Returns ``(F, xy, Z, V_cut, F_cut)``: faces and screen positions of the ring, per-face corner
    depths ``h * theta / 2 pi`` unwrapped inside each face (locally integrable, period ``height``),
    and the helix cut open at theta = pi as a real mesh (its cut embedding).
    """
    r = np.linspace(0.5, 1.0, n_across + 1)
    t = np.arange(n_around) * 2 * np.pi / n_around - np.pi + np.pi / n_around
    ii, jj = np.meshgrid(np.arange(n_around), np.arange(n_across), indexing="ij")
    a, b = ii * (n_across + 1) + jj, ((ii + 1) % n_around) * (n_across + 1) + jj
    F = np.concatenate(
        [np.stack([a, b, b + 1], -1).reshape(-1, 3), np.stack([a, b + 1, a + 1], -1).reshape(-1, 3)]
    )
    tt, rr = np.meshgrid(t, r, indexing="ij")
    xy = np.stack([rr * np.cos(tt), rr * np.sin(tt)], -1).reshape(-1, 2)
    theta = np.arctan2(xy[F][..., 1], xy[F][..., 0])
    theta = np.where(theta - theta[:, :1] > np.pi, theta - 2 * np.pi, theta)  # unwrap per face
    theta = np.where(theta - theta[:, :1] < -np.pi, theta + 2 * np.pi, theta)
    Z = height * theta / (2 * np.pi)
    # Cut embedding: one copy of each vertex per face corner, then merged except across the seam.
    Vc = np.concatenate([xy[F].reshape(-1, 2), Z.reshape(-1, 1)], axis=1)
    _, inverse = np.unique(np.round(Vc, 9), axis=0, return_inverse=True)
    Fc = inverse.reshape(-1, 3).astype(np.int64)
    Vcut = np.zeros((Fc.max() + 1, 3))
    Vcut[Fc.reshape(-1)] = Vc
    return F.astype(np.int64), xy, Z, Vcut, Fc


def luminance(image: np.ndarray) -> np.ndarray:
    return image.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])


def mask(image: np.ndarray, background=(255, 255, 255)) -> np.ndarray:
    return np.any(image != np.asarray(background, dtype=image.dtype), axis=-1)


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / max((a | b).sum(), 1))
