"""Hand-made models for the meshlab_filters tests (no files outside the repository)."""

from __future__ import annotations

import numpy as np


def write_obj(path, V, faces):
    """OBJ with polygons of any size (1-based indices), written by hand like an artist's tool."""
    lines = ["v " + " ".join(repr(float(c)) for c in row) for row in np.asarray(V, dtype=float)]
    lines += ["f " + " ".join(str(int(i) + 1) for i in f) for f in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def grid(n=2):
    """(n+1)^2 vertices in the plane z=0 and n^2 counter-clockwise quads."""
    x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0), indexing="xy")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    a = (j * (n + 1) + i).ravel()
    Q = np.column_stack([a, a + 1, a + n + 2, a + n + 1])
    return V, Q


def tris(Q):
    """Split quads (a, b, c, d) into (a, b, c), (a, c, d)."""
    return np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])


def ramp_ring(N=12, gap=0.9, radii=(1.0, 1.5, 2.0)):
    """A flat annulus seen from +z, cut open along one radius, whose depth climbs by ``gap``
    once around: the simplest cut model of an impossible object (its period is ``gap``).

    Returns
    -------
    V : ((N+1) * len(radii), 3) float64
        Column k (angle 2 pi k / N) at depth gap * k / N; column N repeats column 0 on screen.
    Q : (N * (len(radii) - 1), 4) int64
        Counter-clockwise quads seen from +z.
    cut : (len(radii), 2) int64
        The vertex pairs of the cut (column 0, column N): equal on screen, ``gap`` apart in depth.
    """
    k = np.arange(N + 1)
    th = 2 * np.pi * k / N
    c, s = np.cos(th), np.sin(th)
    c[-1], s[-1] = c[0], s[0]  # the cut's two sides coincide exactly on screen
    R = np.asarray(radii, dtype=float)
    V = np.stack(
        [np.outer(c, R), np.outer(s, R), np.outer(gap * k / N, np.ones(R.size))], axis=-1
    ).reshape(-1, 3)
    idx = np.arange(V.shape[0]).reshape(N + 1, R.size)
    Q = np.column_stack(
        [idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()]
    )
    return V, Q, np.column_stack([idx[0], idx[-1]])
