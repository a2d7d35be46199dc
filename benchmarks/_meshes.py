"""Ordinary test meshes for the benchmarks: tori of any size, randomly rotated."""

from __future__ import annotations

import numpy as np

from meschers_igl import shapes


def torus_with_faces(n_faces: int, seed: int = 0):
    """A torus with about ``n_faces`` faces (grid aspect 2:1), rotated so nothing is axis-aligned."""
    n_v = max(3, int(round(np.sqrt(n_faces / 4))))
    n_u = max(3, int(round(n_faces / (2 * n_v))))
    V, F = shapes.torus(n_u, n_v)
    return np.ascontiguousarray(V @ shapes.random_rotation(seed).T), F
