"""The impossibagel: an ordinary torus made impossible with :meth:`Mescher.with_periods`."""

from __future__ import annotations

import numpy as np

from ..errors import MescherError
from ..operators import view_frame
from ..validate import as_count, as_positive

BAGEL_VIEW = (0.0, -0.5, 1.0)
BAGEL_UP = (0.0, 1.0, 0.0)


def torus_grid(R: float, r: float, n_u: int, n_v: int, seam: bool):
    """A torus around the z axis on an ``n_u x n_v`` grid, outward triangles.

    With ``seam`` the column ``u = 2 pi`` is a copy of ``u = 0`` (vertices ``n_u n_v`` onward),
    so the surface is an annulus cut open along one meridian; faces are the same either way.

    Returns
    -------
    V : (#V, 3), F : (2 n_u n_v, 3), u : (#V,) the angle around the axis of each vertex.
    """
    cols = n_u + 1 if seam else n_u
    u = np.arange(cols) * (2 * np.pi / n_u)
    v = np.arange(n_v) * (2 * np.pi / n_v)
    U, Vv = np.meshgrid(u, v, indexing="ij")
    rho = R + r * np.cos(Vv)
    X = np.stack([rho * np.cos(U), rho * np.sin(U), r * np.sin(Vv)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_u), np.arange(n_v), indexing="ij")
    i1 = i + 1 if seam else (i + 1) % n_u
    j1 = (j + 1) % n_v
    a, b = i * n_v + j, i1 * n_v + j
    c, d = i1 * n_v + j1, i * n_v + j1
    # (u, v) is counter-clockwise seen from outside: d/du x d/dv points outward
    F = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return X, F.astype(np.int64), U.reshape(-1)


def screen_winding(xy: np.ndarray, edges: np.ndarray, loop: tuple[np.ndarray, np.ndarray]) -> int:
    """How many times a closed edge loop turns around the screen origin (counter-clockwise > 0)."""
    e, s = loop
    tail = np.where(s > 0, edges[e, 0], edges[e, 1])
    head = np.where(s > 0, edges[e, 1], edges[e, 0])
    ang = np.arctan2(xy[:, 1], xy[:, 0])
    d = np.angle(np.exp(1j * (ang[head] - ang[tail])))  # wrapped to (-pi, pi]
    return int(np.round(d.sum() / (2 * np.pi)))


def impossibagel(
    major_radius: float = 2.0, minor_radius: float = 0.6, climb: float = 2.5, resolution: int = 8
):
    """A torus that climbs by ``climb`` each time around its hole.

    The mescher is the ordinary torus seen along ``(0, -0.5, 1)`` with its harmonic part set by
    ``with_periods``: ``climb`` on every homology generator per turn around the hole (counted
    by screen winding), 0 around the tube.  The cut model is the same torus cut along one
    meridian and sheared along the view by ``climb * u / 2 pi``: its two ends coincide on
    screen, ``climb`` apart in depth.

    Returns
    -------
    V, F (cut model), view, up, expected_period (``climb``), and a builder of the mescher
    """
    R = as_positive(major_radius, "major_radius")
    r = as_positive(minor_radius, "minor_radius")
    c = as_positive(climb, "climb")
    n = as_count(resolution, "resolution", minimum=3)
    if not r < R:
        raise MescherError(f"minor_radius: expected less than major_radius {R}, found {r}")
    n_u, n_v = 4 * n, n
    Vt, F, _ = torus_grid(R, r, n_u, n_v, seam=False)
    Vc, Fc, u = torus_grid(R, r, n_u, n_v, seam=True)
    vdir = view_frame(BAGEL_VIEW, BAGEL_UP)[2]
    Vc = Vc + (c * u / (2 * np.pi))[:, None] * vdir

    def build():
        from ..mescher import Mescher

        m0 = Mescher.from_mesh(Vt, F, view=BAGEL_VIEW, up=BAGEL_UP)
        xy, edges = np.asarray(m0.xy), np.asarray(m0.edges)
        values = [c * screen_winding(xy, edges, g) for g in m0.homology_generators()]
        # vertices 0..n_u n_v - 1 of the cut model are the torus's; the seam copies follow
        vmap = np.concatenate([np.arange(n_u * n_v), np.arange(n_v)])
        return m0.with_periods(values), vmap

    return Vc, Fc, BAGEL_VIEW, BAGEL_UP, c, build
