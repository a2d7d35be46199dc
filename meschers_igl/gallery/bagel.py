"""The impossibagel: an ordinary torus made impossible with :meth:`Mescher.with_periods`.

Seen at a grazing angle (72 degrees from its axis), the front of the ring overlaps its back near
the two ends of the hole.  At the left end the front passes in front of the back, as in any
ring; at the right end the back passes *in front of* the front: no single ring shows both.
Two things make it impossible:

- its depth climbs by ``climb`` once around the hole (``with_periods`` on the ordinary torus;
  the cut model is the torus cut along the meridian at the back of the ring, seen edge-on, and
  sheared along the view by ``climb * u / 2 pi``), and
- its depth order puts the back of the right half (its faces that face the viewer) in front of
  the front of the right half, where they overlap on screen (``front_back``, as for
  Reutersvard's triangle).

Why not the climb alone: a lift of the ring
along the view is locally a shear ``depth += a_x x + a_y y`` (``y`` toward the back of the
ring).  It keeps the depth order along every ray iff ``1 - a_y sin(tilt) > 0`` (the Jacobian
of ``(y, z) -> (screen y, depth)``; ``a_x`` never matters), so where it is locally affine it
cannot change which surface is in front.  Near the ends of the hole, where front and back are
one bent tube, a flip needs ``a_y > 1 / sin(tilt)``: the tube turns inside out (a linear climb
``1.3 * 2 pi R sin(tilt)`` has ``a_y sin(tilt) = 1.18`` at 72 degrees; 8% of the pixels showed
back faces, a see-through blob).  Lifts that rise faster in the middle of the overlap flip only
a small hook and let the front and back tubes pass through each other at its end (a jagged
intersection; the cut model self-intersects, so its order disagrees with its z-buffer).  So the
climb gives the period and the edited order gives the picture.
"""

from __future__ import annotations

import numpy as np

from ..errors import MescherError
from ..operators import view_frame
from ..shapes import torus
from ..validate import as_count, as_positive
from .cutmodel import CutModel


def screen_winding(xy: np.ndarray, edges: np.ndarray, loop: tuple[np.ndarray, np.ndarray]) -> int:
    """How many times a closed edge loop turns around the screen origin (counter-clockwise > 0)."""
    e, s = loop
    tail = np.where(s > 0, edges[e, 0], edges[e, 1])
    head = np.where(s > 0, edges[e, 1], edges[e, 0])
    ang = np.arctan2(xy[:, 1], xy[:, 0])
    d = np.angle(np.exp(1j * (ang[head] - ang[tail])))  # wrapped to (-pi, pi]
    return int(np.round(d.sum() / (2 * np.pi)))


def bagel_view(tilt: float = 72.0) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """``(view, up)`` of a ring around the z axis seen from the front (-y), ``tilt`` degrees
    from its axis (0: from above, 90: edge-on); the back of the ring (+y) is up on screen."""
    t = np.radians(float(tilt))
    return (0.0, -float(np.sin(t)), float(np.cos(t))), (0.0, float(np.cos(t)), float(np.sin(t)))


def impossibagel(
    major_radius: float = 2.0,
    minor_radius: float = 0.6,
    climb: float = 4.0,
    tilt: float = 72.0,
    resolution: int = 16,
):
    """A torus that climbs by ``climb`` each time around its hole, seen so that its back passes
    in front of its front at the right end of the hole.

    The mescher is the ordinary torus ``shapes.torus(4 n, n, R, r)``, turned a quarter turn
    about its axis (the meridian ``u = 0`` to the back of the ring, +y), seen from
    :func:`bagel_view` with its harmonic part set by ``with_periods``: ``climb`` on every
    homology generator per turn around the hole (counted by screen winding), 0 around the tube.
    The cut model is the same torus cut along that meridian (in the plane of the view, so seen
    edge-on) and sheared along the view by ``climb * u / 2 pi``: its two ends coincide on
    screen, ``climb`` apart in depth.  ``front_back`` puts the right half's back faces that face
    the viewer in front of the right half's front (and of the back's own faces that face away).

    Parameters
    ----------
    major_radius, minor_radius : float, ``0 < r < R``
        With the default tilt, ``r`` a little below ``R cos(tilt)`` leaves a thin hole in the
        middle (the edited order changes where nothing overlaps) and long overlaps at its ends.
    climb : float > 0
        Depth gained once around the hole; keep it below ``2 pi R sin(tilt)`` (a steeper shear
        turns the tube inside out, see the module notes).
    tilt : float in (0, 90)
        Degrees between the view and the ring's axis.
    resolution : int >= 3
        ``n``: ``4 n`` segments around the hole, ``n`` around the tube.

    Returns
    -------
    V, F (cut model), view, up, expected_period (``climb``), a builder of the mescher, and
    ``(front_faces, back_faces)`` for :meth:`DepthOrder.put_in_front`
    """
    R = as_positive(major_radius, "major_radius")
    r = as_positive(minor_radius, "minor_radius")
    c = as_positive(climb, "climb")
    n = as_count(resolution, "resolution", minimum=3)
    if not r < R:
        raise MescherError(f"minor_radius: expected less than major_radius {R}, found {r}")
    t = float(tilt)
    if not 0.0 < t < 90.0:
        raise MescherError(f"tilt: expected degrees in (0, 90), found {tilt!r}")
    view, up = bagel_view(t)
    frame = view_frame(view, up)
    n_u, n_v = 4 * n, n
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # u = 0 to +y
    Vt, F = torus(n_u, n_v, R, r)
    Vt = Vt @ quarter.T
    Vc, Fc, u = torus(n_u, n_v, R, r, seam=True, return_angles=True)
    Vc = Vc @ quarter.T
    centre = Vc[Fc].mean(axis=1)  # the unsheared torus: which half each face is in
    xy = (Vc @ frame.T)[:, :2]
    e1, e2 = xy[Fc[:, 1]] - xy[Fc[:, 0]], xy[Fc[:, 2]] - xy[Fc[:, 0]]
    faces_viewer = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0  # screen area > 0: n_z > 0
    right, back = centre[:, 0] > 0, centre[:, 1] > 0
    front_back = (
        np.flatnonzero(right & back & faces_viewer),
        np.flatnonzero(right & ~(back & faces_viewer)),
    )
    Vc = Vc + (c * u / (2 * np.pi))[:, None] * frame[2]

    def build():
        from ..mescher import Mescher

        m0 = Mescher.from_mesh(Vt, F, view=view, up=up)
        xy0, edges = np.asarray(m0.xy), np.asarray(m0.edges)
        values = [c * screen_winding(xy0, edges, g) for g in m0.homology_generators()]
        # vertices 0..n_u n_v - 1 of the cut model are the torus's; the seam copies follow
        vmap = np.concatenate([np.arange(n_u * n_v), np.arange(n_v)])
        return m0.with_periods(values), vmap

    return CutModel(Vc, Fc, view, up, c, build, front_back)
