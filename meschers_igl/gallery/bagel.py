"""The impossibagel: an ordinary torus made impossible with :meth:`Mescher.with_periods`."""

from __future__ import annotations

import numpy as np

from ..errors import MescherError
from ..operators import view_frame
from ..shapes import torus
from ..validate import as_count, as_positive

BAGEL_VIEW = (0.0, -0.5, 1.0)
BAGEL_UP = (0.0, 1.0, 0.0)


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
    Vt, F = torus(n_u, n_v, R, r)
    Vc, Fc, u = torus(n_u, n_v, R, r, seam=True, return_angles=True)
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
