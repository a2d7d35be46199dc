"""Figures on the Penrose path: triangle, stairs, Reutersvärd's triangle of cubes.

All three are one period of a periodic 3D structure whose period ``t`` points along the view
direction ``(1, 1, 1)``: the piece between a cross-section and its translate by ``t`` is the cut
model, its two open ends coincide on screen, and gluing them gives a mescher whose period is the
depth gap ``|t|`` (or a set of closed boxes with no period, impossible only through their
depth order, when the structure is made of separate blocks).
"""

from __future__ import annotations

import numpy as np

from ..errors import MescherError
from ..validate import as_positive
from .polycube import box_union_surface

VIEW = (1.0, 1.0, 1.0)
UP = (0.0, 0.0, 1.0)


def _count(x, name: str, least: int = 1) -> int:
    if not isinstance(x, (int, np.integer)) or x < least:
        raise MescherError(f"{name}: expected an integer >= {least}, found {x!r}")
    return int(x)


def _bar_box(p: np.ndarray, q: np.ndarray, w: float):
    """Box around the axis-aligned segment p-q, widened by w/2 (corners filled)."""
    return np.minimum(p, q) - w / 2, np.maximum(p, q) + w / 2


def penrose_triangle(bar_length: float = 4.0, bar_width: float = 1.0, resolution: int = 4):
    """Three square bars along x, y and z, seen along (1, 1, 1).

    The centre line runs ``(0,0,0) -> (L,0,0) -> (L,L,0) -> (L,L,L)``; the last corner is the
    first translated by ``(L, L, L)``, so the x bar is cut in its middle and its far half sits
    ``sqrt(3) L`` behind its near half.

    Returns
    -------
    V, F, view, up, expected_period (``sqrt(3) * bar_length``)
    """
    L = as_positive(bar_length, "bar_length")
    w = as_positive(bar_width, "bar_width")
    n = _count(resolution, "resolution")
    if not w < L:
        raise MescherError(f"bar_width: expected less than bar_length {L}, found {w}")
    P = np.array([[0, 0, 0], [L, 0, 0], [L, L, 0], [L, L, L]], dtype=float)
    c = L / 2  # the cut, in the middle of the x bar
    start = np.array([c, 0, 0])
    boxes = [
        (np.array([c, -w / 2, -w / 2]), P[1] + w / 2),
        _bar_box(P[1], P[2], w),
        _bar_box(P[2], P[3], w),
        (P[3] - w / 2, P[3] + np.array([c, w / 2, w / 2])),
    ]
    cuts = [
        (0, start[0], (-w / 2, -w / 2), (w / 2, w / 2)),
        (0, start[0] + L, (L - w / 2, L - w / 2), (L + w / 2, L + w / 2)),
    ]
    V, F, _ = box_union_surface(boxes, L / n, cuts)
    return V, F, VIEW, UP, float(np.sqrt(3.0) * L)


def penrose_stairs(
    step: float = 1.0,
    thickness: float = 1.0,
    long_side: int = 5,
    short_side: int = 3,
    resolution: int = 2,
):
    """A closed loop of steps (Penrose & Penrose 1958) as one solid ribbon of blocks.

    Square blocks of side ``step`` walk ``long_side`` steps along +x, ``long_side`` along +y,
    ``short_side`` along -x and ``short_side`` along -y, rising by ``s = m step / N`` each
    (``m = long_side - short_side``, ``N`` steps in all); block ``i`` spans depths
    ``[i s - thickness, i s]``.  After ``N`` steps the walk has moved by ``m step (1, 1, 1)``,
    along the view, so the last block hides exactly where the first one was.

    Returns
    -------
    V, F, view, up, expected_period (``sqrt(3) * m * step``)
    """
    p = as_positive(step, "step")
    n_long = _count(long_side, "long_side", 2)
    n_short = _count(short_side, "short_side", 1)
    res = _count(resolution, "resolution")
    if n_long <= n_short:
        raise MescherError(
            f"long_side: expected more steps than short_side ({n_short}), found {n_long}"
        )
    N = 2 * (n_long + n_short)
    m = n_long - n_short
    s = m * p / N
    T = as_positive(thickness, "thickness")
    if T <= s:
        raise MescherError(f"thickness: expected more than the rise per step {s:.4g}, found {T}")
    moves = np.repeat(
        np.array([[1, 0], [0, 1], [-1, 0], [0, -1]]), [n_long, n_long, n_short, n_short], axis=0
    )
    moves = np.concatenate([moves, moves[:2]])  # blocks N and N + 1 of the next period
    pos = np.concatenate([[[0, 0]], np.cumsum(moves, axis=0)]) * p  # cell corners, (N + 3, 2)
    z = np.arange(pos.shape[0]) * s
    # blocks 1..N: block N is block 0 moved by m * step * (1, 1, 1)
    boxes = [
        (np.array([*pos[i], z[i] - T]), np.array([*(pos[i] + p), z[i]])) for i in range(1, N + 1)
    ]

    def interface(i: int):
        """The shared face of blocks i and i + 1 (a rectangle on a plane x or y)."""
        d = moves[i]
        axis = 0 if d[0] != 0 else 1
        value = pos[i][axis] + (p if d[axis] > 0 else 0.0)
        other = pos[i][1 - axis]
        return (axis, value, (other, z[i + 1] - T), (other + p, z[i]))

    V, F, _ = box_union_surface(boxes, p / res, [interface(0), interface(N)])
    return V, F, VIEW, UP, float(np.sqrt(3.0) * m * p)


def reutersvard_triangle(
    cube_size: float = 1.0, pitch: float = 1.25, cubes_per_side: int = 3, resolution: int = 2
):
    """Reutersvärd's triangle of cubes (1934): separate cubes on the Penrose path.

    ``cubes_per_side`` cubes of side ``cube_size`` every ``pitch`` along x, y and z; the cube at
    the first corner is cut through its middle, its back half at the start of the path and its
    front half at the end.  Glued, the cubes are ``3 cubes_per_side`` closed boxes: no period,
    the figure is impossible only through its depth order.

    Returns
    -------
    V, F, view, up, expected_period (0)
    """
    a = as_positive(cube_size, "cube_size")
    p = as_positive(pitch, "pitch")
    k = _count(cubes_per_side, "cubes_per_side", 2)
    res = _count(resolution, "resolution")
    if not p > a:
        raise MescherError(f"pitch: expected more than cube_size {a} (cubes apart), found {p}")
    L = k * p
    steps = np.arange(k)[:, None] * p
    ex, ey, ez = np.eye(3)
    P0, P1, P2, P3 = np.zeros(3), L * ex, L * (ex + ey), L * (ex + ey + ez)
    centers = np.concatenate([P0 + steps * ex, P1 + steps * ey, P2 + steps * ez])[1:]
    boxes = [(c - a / 2, c + a / 2) for c in centers]
    boxes += [(P0 + np.array([0, -a / 2, -a / 2]), P0 + a / 2)]  # back half of the seam cube
    boxes += [(P3 - a / 2, P3 + np.array([0, a / 2, a / 2]))]  # front half
    r = (-a / 2, -a / 2), (a / 2, a / 2)
    cuts = [(0, 0.0, *r), (0, L, (L - a / 2, L - a / 2), (L + a / 2, L + a / 2))]
    V, F, _ = box_union_surface(boxes, a / res, cuts)
    return V, F, VIEW, UP, 0.0
