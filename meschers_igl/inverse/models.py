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
    return hexahedra_mesh(lo[:, None, :] + _CUBE_V[None] * size[:, None, :])


def hexahedra_mesh(corners) -> tuple[np.ndarray, np.ndarray]:
    """Triangle meshes of convex hexahedra given by their corners in the unit cube's order.

    A box with some faces cut by planes (a bar whose end is cut obliquely) keeps the box's
    connectivity: corner ``k`` is the image of the unit cube's corner ``k``
    (``_CUBE_V``), so faces stay outward when the map keeps the orientation.

    Parameters
    ----------
    corners : (B, 8, 3) array_like

    Returns
    -------
    V : (8B, 3) float64
    F : (12B, 3) int64
    """
    c = np.asarray(corners, dtype=np.float64)
    if c.ndim != 3 or c.shape[1:] != (8, 3):
        raise MescherError(f"corners: expected (B, 8, 3), found shape {c.shape}")
    tri = np.concatenate([_CUBE_Q[:, [0, 1, 2]], _CUBE_Q[:, [0, 2, 3]]])
    F = (tri[None] + 8 * np.arange(len(c))[:, None, None]).reshape(-1, 3)
    return c.reshape(-1, 3), F.astype(np.int64)


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
    flights=(4, 4, 2, 2), width: float = 1.0, thickness: float = 0.6, steep: float = 2.0
) -> BoxModel:
    """Penrose stairs: steps that climb all the way round and meet their own start.

    Four flights of unit-cell steps along +x, +y, -x, -y (``flights`` cells each, ``N`` in all,
    ``a - c = b - d`` with ``flights = (a, b, c, d)``), each step ``s`` higher than the one
    before.  The return flights are shorter, so the real path is an open spiral whose end is
    the start moved by ``D = (a - c) width (1, 1, steep)``; seen along ``D`` (the view
    ``(1, 1, steep)``) that move is invisible and the picture is a closed ring of steps that
    climbs for ever (each step a block ``thickness`` deep under its tread).  The height gained
    per turn is ``N s = steep (a - c) width``; the depth gained going once around the ring is
    ``|D| = (a - c) width sqrt(2 + steep^2)``: the period (``gap``).  ``steep = 1`` is the
    isometric view; a steeper view gives taller steps (``s = steep (a - c) width / N``).

    On the two flights that climb toward the viewer (+x, +y) the risers face away: each such
    step shows only as a notch of the outline and a jog of the tread's edge, where the next
    tread passes in front of the one below (both one shade).
    """
    a, b, c, d = (int(f) for f in flights)
    w, T, t = float(width), float(thickness), float(steep)
    N = a + b + c + d
    if min(a, b, c, d) < 1 or not (a - c == b - d) or a <= c:
        raise MescherError(
            f"flights: expected flights[0] - flights[2] = flights[1] - flights[3] > 0, found "
            f"{flights}"
        )
    if not t > 0:
        raise MescherError(f"steep: expected a positive number, found {steep}")
    s = t * (a - c) * w / N
    moves = [(1, 0)] * a + [(0, 1)] * b + [(-1, 0)] * c + [(0, -1)] * d
    boxes, x, y = [], 0.0, 0.0
    for k, (dx, dy) in enumerate(moves):
        h = k * s
        boxes.append(((x, y, h - T), (x + w, y + w, h)))
        x, y = x + dx * w, y + dy * w
    V, F = boxes_mesh(boxes)
    view = np.array([1.0, 1.0, t]) / math.sqrt(2.0 + t * t)
    up = np.array([0.0, 0.0, 1.0]) - view[2] * view
    gap = (a - c) * w * math.sqrt(2.0 + t * t)
    return BoxModel("stairs", V, F, view, up / np.linalg.norm(up), gap)


def impossible_cube(size: float = 10.0, width: float = 2.0) -> BoxModel:
    """An impossible cube frame built as an artist builds it (ParadoxToolkit's construction).

    The bars of the cube ``[-h, h]^3`` (``h = (size + width) / 2``, bars ``width`` thick,
    ``size`` apart centre to centre) seen along ``v = (1, -1, 1) / sqrt(3)``, where the nearest
    corner ``(h, -h, h)`` and the farthest corner land on the same screen point.  The nearest
    corner keeps only its bar along y (ten bars in all), and two bars along y are changed, both
    straight and axis-aligned:

    - the *back* bar ``x, z in [-h, -h + width]`` keeps only its half from the cut plane to
      the rim corner ``(-h, -h, -h)``;
    - the *front* bar ``x, z in [h - width, h]`` is extended beyond the nearest corner up to
      the same cut plane.

    The cut plane ``x + 2 y + z = width - 2 h`` contains ``v``, so both cut faces are seen
    edge-on, and the two pieces are collinear on screen: the front bar seems to go on as the
    back bar (the picture is one straight bar through the middle of the frame).  Their axes are
    ``size`` apart in x and in z; being collinear on screen forces a y offset of ``size`` too,
    so the hidden depth step where they meet is fixed by the cube:
    ``gap = |size (1, -1, 1)| = sqrt(3) size`` (17.32 for the defaults, as the shipped
    ``paradox/impossible_cube`` model measures).  Glued there, the frame is one closed
    surface of genus 3 with one period class equal to ``gap``.
    """
    a, w = float(size), float(width)
    if not a > 2 * w > 0:
        raise MescherError(f"size, width: expected size > 2 width > 0, found {a}, {w}")
    h = 0.5 * (a + w)
    lo, hi = (-h, -h + w), (h - w, h)
    c = w - 2.0 * h  # the cut plane x + 2y + z = c goes through the back bar's middle

    def y_cut(x, z):
        return 0.5 * (c - x - z)

    corners = []
    for axis in range(3):
        o1, o2 = (axis + 1) % 3, (axis + 2) % 3
        for p_ in (lo, hi):
            for q in (lo, hi):
                # the nearest corner's bars along x (y low, z high) and z (x high, y low)
                if (axis == 0 and p_ == lo and q == hi) or (axis == 2 and p_ == hi and q == lo):
                    continue
                b0, b1 = np.zeros(3), np.zeros(3)
                b0[axis], b1[axis] = -h, h
                b0[o1], b1[o1] = p_
                b0[o2], b1[o2] = q
                C = b0 + _CUBE_V * (b1 - b0)
                if axis == 1 and p_ == lo and q == lo:  # back bar (x, z low): rim half
                    top = C[:, 1] > 0
                    C[top, 1] = y_cut(C[top, 2], C[top, 0])
                elif axis == 1 and p_ == hi and q == hi:  # front bar (x, z high): extended
                    bot = C[:, 1] < 0
                    C[bot, 1] = y_cut(C[bot, 2], C[bot, 0])
                corners.append(C)
    V, F = hexahedra_mesh(corners)
    view = np.array([1.0, -1.0, 1.0]) / math.sqrt(3.0)
    up = np.array([0.0, 0.0, 1.0]) - view[2] * view
    return BoxModel("cube", V, F, view, up / np.linalg.norm(up), math.sqrt(3.0) * a)
