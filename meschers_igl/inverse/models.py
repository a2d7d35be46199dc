"""Real (possible) 3D models whose pictures look impossible: the acceptance targets.

Each model is a union of axis-aligned boxes, a closed triangle mesh, seen orthographically along
``view``.  From that one view two parts that are far apart in depth project onto each other
exactly, so a z-buffered picture of the model *is* the impossible figure, while the model itself
is an ordinary 3D object.  The depth between those two parts is the figure's true period:
the depth a mescher fitted to the picture must gain going once around the figure.

Nothing here renders: pictures are made outside ``meschers_igl`` by PyVista's z-buffer
(``meschers.inverse_cli.zbuffer_picture``), so the code under test never renders its own target.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import MescherError

#: the six faces of the box [0, 1]^3 as quads (outward, counter-clockwise seen from outside)
_CUBE_V = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=np.float64,
)
_CUBE_Q = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
)


@dataclass(frozen=True)
class BoxModel:
    """A union of boxes seen from one view, with what a fit to its picture should recover.

    Attributes
    ----------
    name : str
    V : (#V, 3) float64
    F : (#F, 3) int64
        Closed, outward-oriented triangles (each box is its own closed component).
    view : (3,) float64
        Unit direction from the model toward the viewer (orthographic camera).
    up : (3,) float64
        Unit screen-up direction (orthogonal to ``view``).
    gap : float
        Depth between the two parts that coincide on screen where the figure closes, model
        units: the depth step the illusion hides (tribar: the two corner cubes), which a
        mescher of the picture must climb going once around the figure.
    """

    name: str
    V: np.ndarray
    F: np.ndarray
    view: np.ndarray
    up: np.ndarray
    gap: float

    def camera_frame(self) -> np.ndarray:
        """(3, 3) rows ``right, up, view``: camera coordinates are ``V @ R.T``."""
        right = np.cross(self.up, self.view)
        return np.stack([right / np.linalg.norm(right), self.up, self.view])

    def axes_in_camera(self) -> np.ndarray:
        """(3, 3) the model's axis directions x, y, z (rows) in the camera frame."""
        return self.camera_frame().T.copy()


def boxes_mesh(boxes) -> tuple[np.ndarray, np.ndarray]:
    """Triangle meshes of axis-aligned boxes, concatenated (each box closed and outward).

    Parameters
    ----------
    boxes : (B, 2, 3) array_like
        ``(lo, hi)`` corners.

    Returns
    -------
    V : (8B, 3) float64
    F : (12B, 3) int64
    """
    b = np.asarray(boxes, dtype=np.float64)
    if b.ndim != 3 or b.shape[1:] != (2, 3) or np.any(b[:, 1] <= b[:, 0]):
        raise MescherError(f"boxes: expected (B, 2, 3) with lo < hi, found shape {b.shape}")
    lo, size = b[:, 0], b[:, 1] - b[:, 0]
    V = (lo[:, None, :] + _CUBE_V[None] * size[:, None, :]).reshape(-1, 3)
    tri = np.concatenate([_CUBE_Q[:, [0, 1, 2]], _CUBE_Q[:, [0, 2, 3]]])
    F = (tri[None] + 8 * np.arange(len(b))[:, None, None]).reshape(-1, 3)
    return V, F.astype(np.int64)


def _iso_view(up_axis=(0.0, 0.0, 1.0)) -> tuple[np.ndarray, np.ndarray]:
    view = np.ones(3) / math.sqrt(3.0)
    u = np.asarray(up_axis, dtype=np.float64)
    up = u - (u @ view) * view
    return view, up / np.linalg.norm(up)


def penrose_tribar(length: float = 5.0, width: float = 1.0) -> BoxModel:
    """Three bars along x, y and z (an open path) whose ends coincide seen along (1, 1, 1).

    ``X = [0, L] x [0, w]^2``, ``Y = [L-w, L] x [w, L] x [0, w]``,
    ``Z = [L-w, L] x [L-w, L] x [w, L]``: the last cube of Z is the first cube of X moved by
    ``(L - w)(1, 1, 1)``, so the two project onto the same hexagon and the picture is the closed
    Penrose triangle.  The two cubes are ``sqrt(3) (L - w)`` apart in depth (``gap``).  (The
    picture's occlusion line from the cap to the hole hides a step that shrinks from ``gap`` to
    ``sqrt(3) (L - 2w)`` at the hole; the step is ``gap`` all along the seam where X's faces
    meet the cap's, which is what a loop around the whole figure crosses.)
    """
    L, w = float(length), float(width)
    if not L > 2 * w > 0:
        raise MescherError(f"length, width: expected length > 2 width > 0, found {L}, {w}")
    boxes = [((0, 0, 0), (L, w, w)), ((L - w, w, 0), (L, L, w)), ((L - w, L - w, w), (L, L, L))]
    V, F = boxes_mesh(boxes)
    view, up = _iso_view()
    return BoxModel("tribar", V, F, view, up, math.sqrt(3.0) * (L - w))


def penrose_stairs(
    flights=(4, 4, 2, 2), rise: float = 2.0, width: float = 1.0, thickness: float = 0.6
) -> BoxModel:
    """Penrose stairs: steps that climb all the way round and meet their own start.

    Four flights of unit-cell steps along +x, +y, -x, -y (``flights`` cells each) climbing
    ``rise`` in total, ``s = rise / N`` per step.  The return flights are shorter, so the real
    path is an open spiral whose end is the start moved by ``rise (1, 1, 1)``: seen along
    (1, 1, 1) that move is invisible and the picture is a closed ring of steps that climbs for
    ever (each step a block ``thickness`` deep under its tread).  Going once around the ring
    climbs ``sqrt(3) rise`` in depth: the period.  Needs ``flights[0] - flights[2] =
    flights[1] - flights[3] = rise / width``.
    """
    a, b, c, d = (int(f) for f in flights)
    w, T = float(width), float(thickness)
    N = a + b + c + d
    if min(a, b, c, d) < 1 or not (a - c == b - d) or abs((a - c) * w - rise) > 1e-9:
        raise MescherError(
            f"flights, rise: expected flights[0] - flights[2] = flights[1] - flights[3] = "
            f"rise / width, found {flights}, rise {rise}, width {w}"
        )
    s = float(rise) / N
    moves = [(1, 0)] * a + [(0, 1)] * b + [(-1, 0)] * c + [(0, -1)] * d
    boxes, x, y = [], 0.0, 0.0
    for k, (dx, dy) in enumerate(moves):
        h = k * s
        boxes.append(((x, y, h - T), (x + w, y + w, h)))
        x, y = x + dx * w, y + dy * w
    V, F = boxes_mesh(boxes)
    view, up = _iso_view()
    return BoxModel("stairs", V, F, view, up, math.sqrt(3.0) * float(rise))


def impossible_cube(size: float = 4.0, width: float = 0.7, view=(1.0, 0.75, 0.55)) -> BoxModel:
    """An impossible cube frame: a cube's twelve bars, one bar's upper half moved to the front.

    The back vertical bar (through the corner farthest from the viewer) crosses a front bar on
    screen.  It is split at the crossing and its upper half is moved *toward the viewer* along
    the view direction by ``gap`` -- a move along the view leaves its picture where it was --
    until it lies in front of the bar it crossed behind.  The picture then shows the back bar
    passing behind and in front of the same front bar: the impossible cube (Escher's
    Belvedere).  The figure has several holes.  ``gap`` is the move (``2 size``); note that a
    move along the view is invisible, so the picture does not determine it: any move that
    clears the front bar gives the same picture.
    """
    a, w = float(size), float(width)
    if not a > 3 * w > 0:
        raise MescherError(f"size, width: expected size > 3 width > 0, found {a}, {w}")
    v = np.asarray(view, dtype=np.float64)
    v = v / np.linalg.norm(v)
    up = np.array([0.0, 0.0, 1.0]) - v[2] * v
    up /= np.linalg.norm(up)
    right = np.cross(up, v)
    P = np.stack([right, up])  # screen projection
    lo, hi = 0.0, a - w
    bars = []
    for axis in range(3):
        o1, o2 = (axis + 1) % 3, (axis + 2) % 3
        for p_ in (lo, hi):
            for q in (lo, hi):
                b0, b1 = np.zeros(3), np.zeros(3)
                b0[axis], b1[axis] = 0.0, a
                b0[o1], b1[o1] = p_, p_ + w
                b0[o2], b1[o2] = q, q + w
                bars.append((axis, b0, b1))
    # the back vertical bar (x = y = lo) and the front bars it crosses on screen
    back = next(i for i, (ax, b0, _) in enumerate(bars) if ax == 2 and b0[0] == lo and b0[1] == lo)
    c0 = np.array([w / 2, w / 2, 0.0])
    best = None
    for i, (ax, b0, b1) in enumerate(bars):
        if ax == 2 or (b0 + b1) @ v / 2 <= (c0 + [0, 0, a / 2]) @ v:
            continue  # only bars nearer the viewer than the back bar's middle
        m0 = (b0 + b1) / 2
        d0 = np.zeros(3)
        d0[ax] = 1.0
        # screen intersection of c0 + s e_z and m0 + t d0
        A = np.column_stack([P @ np.array([0, 0, 1.0]), -(P @ d0)])
        if abs(np.linalg.det(A)) < 1e-9:
            continue
        s_, t_ = np.linalg.solve(A, P @ (m0 - c0))
        if 2 * w < s_ < a - 2 * w and abs(t_) < a / 2 - w:
            best = (s_, i)
            break
    if best is None:
        raise MescherError("view: expected a view where a front bar crosses the back bar")
    zc = best[0]
    _, b0, b1 = bars[back]
    lower = (b0.copy(), np.r_[b1[:2], zc])
    upper = (np.r_[b0[:2], zc], b1.copy())
    gap = 2.0 * a  # toward the viewer: far enough to clear every other bar
    boxes = [(b0_, b1_) for i, (_, b0_, b1_) in enumerate(bars) if i != back]
    boxes += [lower, (upper[0] + gap * v, upper[1] + gap * v)]
    V, F = boxes_mesh(boxes)
    return BoxModel("cube", V, F, v, up, gap)
