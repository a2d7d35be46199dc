"""Ordinary meshes for examples, tests and benchmarks: tori, spheres, grids, annuli, boxes.

Each returns ``(V (#V, 3) float64, F (#F, 3) int64)``, outward oriented.
"""

from __future__ import annotations

import igl
import numpy as np

from .errors import MescherError
from .validate import as_count, as_positive, check_budget


def _grid_faces(n_u: int, n_v: int, wrap_u: bool, wrap_v: bool) -> np.ndarray:
    nu = n_u if wrap_u else n_u - 1
    nv = n_v if wrap_v else n_v - 1
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * n_v + j
    b = ((i + 1) % n_u) * n_v + j
    c = ((i + 1) % n_u) * n_v + (j + 1) % n_v
    d = i * n_v + (j + 1) % n_v
    return np.r_[
        np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]
    ].astype(np.int64)


def torus(
    n_u: int = 48,
    n_v: int = 16,
    R: float = 2.0,
    r: float = 1.0,
    seam: bool = False,
    return_angles: bool = False,
):
    """Torus around the z axis: ``n_u`` segments around the hole, ``n_v`` around the tube.

    The project's one torus generator (the gallery's bagel and inverse rendering use it).
    Vertex ``i n_v + j`` sits at ``u = 2 pi i / n_u`` around the axis and ``v = 2 pi j / n_v``
    around the tube: ``((R + r cos v) cos u, (R + r cos v) sin u, r sin v)``; faces
    ``[a, b, c], [a, c, d]`` of each grid quad are outward (counter-clockwise from outside).

    Parameters
    ----------
    n_u, n_v : int >= 3
    R, r : float > 0
        Radius of the centre circle and of the tube.
    seam : bool, default: False
        Cut open along the meridian ``u = 0``: the column ``u = 2 pi`` is a copy of ``u = 0``
        (vertices ``n_u n_v`` onward), so the surface is an annulus; faces have the same
        corners' positions either way.
    return_angles : bool, default: False
        Also return ``u`` (#V,), each vertex's angle around the axis (``2 pi`` on the seam).

    Returns
    -------
    V : (n_u n_v, 3) float64 (``(n_u + 1) n_v`` with ``seam``)
    F : (2 n_u n_v, 3) int64
    u : (#V,) float64, only with ``return_angles``
    """
    n_u, n_v = as_count(n_u, "n_u", 3), as_count(n_v, "n_v", 3)
    R, r = as_positive(R, "R"), as_positive(r, "r")
    check_budget(2.0 * n_u * n_v, 100.0, what=f"torus({n_u}, {n_v})")
    cols = n_u + 1 if seam else n_u
    u, v = np.meshgrid(
        np.arange(cols) * (2 * np.pi / n_u), np.arange(n_v) * (2 * np.pi / n_v), indexing="ij"
    )
    V = np.c_[
        ((R + r * np.cos(v)) * np.cos(u)).ravel(),
        ((R + r * np.cos(v)) * np.sin(u)).ravel(),
        (r * np.sin(v)).ravel(),
    ]
    F = _grid_faces(cols, n_v, not seam, True)
    return (V, F, u.ravel()) if return_angles else (V, F)


def grid(n_x: int = 10, n_y: int = 10, size: float = 1.0):
    """A flat square ``[0, size]^2`` in the z = 0 plane, triangulated (a disc: one boundary)."""
    n_x, n_y = as_count(n_x, "n_x", 2), as_count(n_y, "n_y", 2)
    check_budget(2.0 * n_x * n_y, 100.0, what=f"grid({n_x}, {n_y})")
    x, y = np.meshgrid(np.linspace(0, size, n_x), np.linspace(0, size, n_y), indexing="ij")
    V = np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]
    return V, _grid_faces(n_x, n_y, False, False)


#: The 12 outward faces of a box whose 8 corners are listed x fastest, then y, then z.
BOX_FACES = np.array(
    [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ],
    dtype=np.int64,
)


def boxes(lo: np.ndarray, hi: np.ndarray):
    """Separate axis-aligned boxes ``[lo_k, hi_k]`` as one soup of closed solids (the way a
    modeller lays out blocks): 8 vertices and 12 faces each.

    Parameters
    ----------
    lo, hi : (k, 3) float64
        Opposite corners, ``lo < hi`` componentwise.

    Returns
    -------
    V : (8k, 3) float64
    F : (12k, 3) int64
    """
    lo, hi = np.atleast_2d(np.asarray(lo, np.float64)), np.atleast_2d(np.asarray(hi, np.float64))
    if lo.shape != hi.shape or lo.shape[1:] != (3,) or not np.all(hi > lo):
        raise MescherError(
            f"lo, hi: expected two (k, 3) arrays with lo < hi, found shapes {lo.shape}, {hi.shape}"
        )
    bits = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], np.float64)
    V = lo[:, None, :] + bits[None] * (hi - lo)[:, None, :]
    F = BOX_FACES[None] + 8 * np.arange(lo.shape[0])[:, None, None]
    return V.reshape(-1, 3), F.reshape(-1, 3)


def block_grid(n: int, ground: float = 0.0, heights: np.ndarray | None = None):
    """A scene of ``n x n`` separate 2 x 2 boxes, 1 apart (a city block), of unit height (or
    ``heights``, one per box, row by row); with ``ground > 0`` a ground quad of half-width
    ``ground`` under them (an open sheet), as scenes come from modelling tools.

    Returns
    -------
    V : (8 n^2 (+ 4), 3) float64
    F : (12 n^2 (+ 2), 3) int64
    """
    n = as_count(n, "n", 1)
    check_budget(12.0 * n * n, 100.0, what=f"block_grid({n})")
    h = np.ones(n * n) if heights is None else np.asarray(heights, np.float64).reshape(-1)
    if h.shape != (n * n,):
        raise MescherError(f"heights: expected {n * n} values, found {h.size}")
    ij = 3.0 * np.stack(np.divmod(np.arange(n * n), n), axis=1)
    V, F = boxes(np.c_[ij, np.zeros(n * n)], np.c_[ij + 2.0, h])
    if ground > 0:
        c = 1.5 * n - 0.5
        G = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]) * [ground, ground, 0]
        k = V.shape[0]
        V = np.vstack([V, G + [c, c, 0.0]])
        F = np.vstack([F, [[k, k + 1, k + 2], [k, k + 2, k + 3]]])
    return V, F


def annulus(n_u: int = 32, n_r: int = 4, r0: float = 1.0, r1: float = 2.0):
    """A flat ring in the z = 0 plane (two boundary loops)."""
    n_u, n_r = as_count(n_u, "n_u", 3), as_count(n_r, "n_r", 2)
    check_budget(2.0 * n_u * n_r, 100.0, what=f"annulus({n_u}, {n_r})")
    u, s = np.meshgrid(
        np.linspace(0, 2 * np.pi, n_u, endpoint=False), np.linspace(r0, r1, n_r), indexing="ij"
    )
    V = np.c_[(s * np.cos(u)).ravel(), (s * np.sin(u)).ravel(), np.zeros(u.size)]
    F = _grid_faces(n_u, n_r, True, False)
    return V, F[:, [0, 2, 1]]  # counter-clockwise seen from +z


def icosphere(level: int = 2, radius: float = 1.0):
    """Sphere by ``level`` midpoint subdivisions (``igl.upsample``) of an icosahedron."""
    level = as_count(level, "level", 0, 9)  # level 9: 5.2M faces
    t = (1 + 5**0.5) / 2
    # the icosahedron: vertices (+-1, +-t, 0) and their cyclic shifts, 20 faces (data, not code)
    V = np.array(
        [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t]]
        + [[0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]],
        dtype=float,
    )
    F = np.array(
        (
            "0 11 5  0 5 1  0 1 7  0 7 10  0 10 11  1 5 9  5 11 4  11 10 2  10 7 6  7 1 8  "
            "3 9 4  3 4 2  3 2 6  3 6 8  3 8 9  4 9 5  2 4 11  6 2 10  8 6 7  9 8 1"
        ).split(),
        dtype=np.int64,
    ).reshape(-1, 3)
    if level > 0:
        V, F = igl.upsample(V, F, level)
    V = radius * V / np.linalg.norm(V, axis=1, keepdims=True)
    return V, F


def random_rotation(seed: int = 0) -> np.ndarray:
    """A seeded random rotation matrix (3, 3), determinant +1."""
    q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def impossible_torus(
    n_u: int = 48, n_v: int = 16, climb: float = 1.0, R: float = 2.0, r: float = 1.0
):
    """A torus seen from above whose depth climbs by ``climb`` per turn around the hole.

    Built from an ordinary torus with ``with_periods``; returns the Mescher.
    """
    from .mescher import Mescher

    V, F = torus(n_u, n_v, R, r)
    m = Mescher.from_mesh(V, F)
    # the generator loop whose screen path winds around the hole gets the climb
    gens = m.homology_generators()
    winding = []
    for e, s in gens:
        E = m.edges[e]
        a = np.where(s > 0, E[:, 0], E[:, 1])
        b = np.where(s > 0, E[:, 1], E[:, 0])
        ang = np.arctan2(m.xy[:, 1], m.xy[:, 0])
        d = np.angle(np.exp(1j * (ang[b] - ang[a])))
        winding.append(round(float(d.sum()) / (2 * np.pi)))
    values = np.array([climb * w for w in winding], dtype=float)
    return m.with_periods(values)
