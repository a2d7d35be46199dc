"""Ordinary test meshes for the benchmarks (a torus grid of any size, seeded and rotated)."""

from __future__ import annotations

import numpy as np


def torus(n_u: int, n_v: int, R: float = 2.0, r: float = 1.0, seed: int = 0):
    """A (2 * n_u * n_v)-face torus, randomly rotated so nothing is axis-aligned."""
    u, v = np.meshgrid(
        np.linspace(0, 2 * np.pi, n_u, endpoint=False),
        np.linspace(0, 2 * np.pi, n_v, endpoint=False),
        indexing="ij",
    )
    V = np.c_[((R + r * np.cos(v)) * np.cos(u)).ravel(), ((R + r * np.cos(v)) * np.sin(u)).ravel(),
              (r * np.sin(v)).ravel()]  # fmt: skip
    i, j = np.meshgrid(np.arange(n_u), np.arange(n_v), indexing="ij")
    a = i * n_v + j
    b = ((i + 1) % n_u) * n_v + j
    c = ((i + 1) % n_u) * n_v + (j + 1) % n_v
    d = i * n_v + (j + 1) % n_v
    F = np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]]
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    return np.ascontiguousarray(V @ q.T), F.astype(np.int64)


def torus_with_faces(n_faces: int, seed: int = 0):
    """A torus with about ``n_faces`` faces and aspect 2:1 in its grid."""
    n_v = max(3, int(round(np.sqrt(n_faces / 4))))
    n_u = max(3, int(round(n_faces / (2 * n_v))))
    return torus(n_u, n_v, seed=seed)
