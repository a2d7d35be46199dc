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
from ..operators import view_frame
from ..validate import as_count, as_positive
from .cutmodel import CutModel
from .polycube import box_union_surface, slant_cut

VIEW = (1.0, 1.0, 1.0)
UP = (0.0, 0.0, 1.0)


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
    n = as_count(resolution, "resolution", minimum=1)
    if not 2 * w < L:
        raise MescherError(f"bar_width: expected less than bar_length / 2 = {L / 2}, found {w}")
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
    # cut in a plane containing the view, as artists do: seen edge-on, the cut hides nothing
    # and shows no inside (an axis-aligned cut would open toward the camera: a dark notch)
    fade = c - w / 2  # up to the corner cubes, which stay square
    V = slant_cut(V, 0, start[0], *cuts[0][2:], +1, fade, VIEW)
    V = slant_cut(V, 0, start[0] + L, *cuts[1][2:], -1, fade, VIEW)
    return CutModel(V, F, VIEW, UP, float(np.sqrt(3.0) * L))


def penrose_stairs(
    step: float = 1.0,
    thickness: float = 1.0,
    long_side: int = 5,
    short_side: int = 3,
    resolution: int = 2,
    steepness: float = 1.0,
):
    """A closed loop of steps (Penrose & Penrose 1958) as one solid ribbon of blocks.

    Square blocks of side ``step`` walk ``long_side`` steps along +x, ``long_side`` along +y,
    ``short_side`` along -x and ``short_side`` along -y, rising by ``s = m step / N`` each
    (``m = long_side - short_side``, ``N`` steps in all); block ``i`` spans depths
    ``[i s - thickness, i s]``.  After ``N`` steps the walk has moved by ``m step (1, 1, 1)``,
    along the view, so the last block hides exactly where the first one was.

    ``steepness`` ``c`` looks along ``(1, 1, c)`` instead: the walk then rises ``c m step`` per
    turn, ``s = c m step / N`` a step, and ends moved by ``m step (1, 1, c)``, again along the
    view.  Which flights show their risers is fixed by the climb, not by ``c``: a turn's net
    horizontal move is the view's horizontal part times ``m step``, toward the viewer, so the
    flights along +x and +y climb toward the viewer and their risers (normals -x, -y) face
    away, under any view along the period; on those two flights a step shows only as a jog of
    height ``s`` in the wall that faces the viewer (the near flight's outer wall, the far
    flight's courtyard wall), ``c`` times taller, relative to the step, in a steeper view.
    ``thickness`` must be a whole number of rises: the blocks' bottoms then lie on the levels
    of the treads, so the two cut ends (translates by the period) are meshed alike.

    Returns
    -------
    V, F, view, up, expected_period (``sqrt(2 + c^2) * m * step``)
    """
    p = as_positive(step, "step")
    n_long = as_count(long_side, "long_side", minimum=3)
    n_short = as_count(short_side, "short_side", minimum=1)
    res = as_count(resolution, "resolution", minimum=1)
    if n_long <= n_short:
        raise MescherError(
            f"long_side: expected more steps than short_side ({n_short}), found {n_long}"
        )
    N = 2 * (n_long + n_short)
    m = n_long - n_short
    c = as_positive(steepness, "steepness")
    view = (1.0, 1.0, c)
    s = c * m * p / N
    T = as_positive(thickness, "thickness")
    if not s < T < 3 * p + s:
        raise MescherError(
            f"thickness: expected more than the rise per step {s:.4g} and less than "
            f"3 step + rise {3 * p + s:.4g} (room for the slanted cut), found {T}"
        )
    if abs(T / s - round(T / s)) > 1e-9 * (T / s):
        raise MescherError(
            f"thickness: expected a whole number of rises ({s:.6g} each, steepness {c:g}), so "
            f"both cut ends are meshed alike, found {T} = {T / s:.4g} rises"
        )
    moves = np.repeat(
        np.array([[1, 0], [0, 1], [-1, 0], [0, -1]]), [n_long, n_long, n_short, n_short], axis=0
    )
    # the cut: between blocks j and j + 1, in the middle of the first long side, where the
    # walk runs straight on both sides of both cut blocks
    j = n_long // 2
    moves = np.concatenate([moves, moves[: j + 2]])  # the next period's first blocks
    pos = np.concatenate([[[0, 0]], np.cumsum(moves, axis=0)]) * p  # cell corners
    z = np.arange(pos.shape[0]) * s
    # blocks j + 1 .. j + N: block j + N is block j moved by m * step * (1, 1, 1)
    boxes = [
        (np.array([*pos[i], z[i] - T]), np.array([*(pos[i] + p), z[i]]))
        for i in range(j + 1, j + N + 1)
    ]

    def interface(i: int):
        """The shared face of blocks i and i + 1 (a rectangle on a plane x or y)."""
        d = moves[i]
        axis = 0 if d[0] != 0 else 1
        value = pos[i][axis] + (p if d[axis] > 0 else 0.0)
        other = pos[i][1 - axis]
        return (axis, value, (other, z[i + 1] - T), (other + p, z[i]))

    first, last = interface(j), interface(j + N)
    V, F, _ = box_union_surface(boxes, p / res, [first, last])
    # cut in a plane containing the view (seen edge-on: no inside shows), fading out within the
    # two cut blocks (their neighbours along the walk are straight on, so nothing else moves)
    for (axis, value, lo, hi), side, i in ((first, +1, j + 1), (last, -1, j + N)):
        block = ((lo[0], z[i] - T), (hi[0], z[i]))  # the cut block's whole end face
        V = slant_cut(V, axis, value, lo, hi, side, p, view, region=block)
    return CutModel(V, F, view, UP, float(np.sqrt(2.0 + c * c) * m * p))


def reutersvard_triangle(
    cube_size: float = 1.0, pitch: float = 1.55, cubes_per_side: int = 3, resolution: int = 1
):
    """Reutersvärd's triangle of cubes (1934): separate cubes on the Penrose path.

    ``cubes_per_side`` cubes of side ``cube_size`` every ``pitch`` along x, y and z: ``3
    cubes_per_side`` closed boxes, no cut and no period. Seen along (1, 1, 1) the path ends where
    it began: the last cube overlaps the first on screen and, being nearer, would hide it. The
    figure is impossible only through its depth order: the half of the first cube that faces
    the last one is put in front of it (:meth:`DepthOrder.put_in_front`), while its other half
    stays behind the second cube, as Reutersvärd drew it. (Cutting the first cube into two
    halves at the two ends of the path, as an earlier version did, shows its inside: an
    axis-aligned cut through a cube seen along its diagonal opens toward the camera, and no cut
    plane containing the view halves a cube without passing through its corners.)

    Parameters
    ----------
    cube_size, pitch : float
        Side of the cubes and distance between their centres; ``cube_size < pitch < 2
        cube_size`` so neighbours overlap on screen, and ``pitch > 1.5 cube_size`` so the second
        and the last cube do not both overlap the same part of the first (no cyclic pixel).
    cubes_per_side : int
    resolution : int
        Grid cells per *half* cube side (even cells, so every face lies on one side of the
        first cube's middle).

    Returns
    -------
    V, F, view, up, expected_period (0), builder (None), and ``(front, back)`` face groups
    """
    a = as_positive(cube_size, "cube_size")
    p = as_positive(pitch, "pitch")
    k = as_count(cubes_per_side, "cubes_per_side", minimum=2)
    res = as_count(resolution, "resolution", minimum=1)
    if not 1.5 * a < p < 2 * a:
        raise MescherError(
            f"pitch: expected between 1.5 and 2 times cube_size ({1.5 * a:g}, {2 * a:g}): "
            f"neighbours overlap on screen, no pixel sees three cubes; found {p}"
        )
    L = k * p
    steps = np.arange(k)[:, None] * p
    ex, ey, ez = np.eye(3)
    P0, P1, P2 = np.zeros(3), L * ex, L * (ex + ey)
    centers = np.concatenate([P0 + steps * ex, P1 + steps * ey, P2 + steps * ez])
    boxes = [(c - a / 2, c + a / 2) for c in centers]
    V, F, _ = box_union_surface(boxes, a / (2 * res), [])
    # which cube each face belongs to: the cubes are apart, so the nearest centre
    mid = V[F].mean(axis=1)
    cube = np.argmin(((mid[:, None, :] - centers[None]) ** 2).sum(-1), axis=1)
    # the half of the first cube nearer (on screen) to the last cube than to the second
    R = view_frame(VIEW, UP)[:2]
    s_mid, s_second, s_last = mid @ R.T, R @ centers[1], R @ centers[-1]
    near_last = ((s_mid - s_last) ** 2).sum(1) < ((s_mid - s_second) ** 2).sum(1)
    front = np.flatnonzero((cube == 0) & near_last)
    back = np.flatnonzero(cube == len(centers) - 1)
    return CutModel(V, F, VIEW, UP, 0.0, front_back=(front, back))
