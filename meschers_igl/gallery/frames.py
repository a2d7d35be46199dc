"""Frames of square bars: the impossible cube and the "Window".

Both are made impossible-looking by moving parts of a real frame *along the view direction*,
which changes depths but not the picture.  The impossible cube moves a piece of one bar rigidly
between two cuts (the jumps cancel: no period, impossible through its depth order; an opt-in
variant with one cut and a sheared stretch carries a period); the Window moves a bar
continuously (no period: a real 3D object that looks impossible only because of which bar is in
front where).
"""

from __future__ import annotations

import itertools

import numpy as np

from ..errors import MescherError
from ..operators import view_frame
from ..validate import as_count, as_positive
from .cutmodel import CutModel
from .polycube import box_union_surface, slant_cut

CUBE_VIEW = (1.0, 0.8, 0.4)
CUBE_UP = (0.0, 0.0, 1.0)
WINDOW_VIEW = (0.25, 0.2, 1.0)
WINDOW_UP = (0.0, 1.0, 0.0)


def cube_frame_boxes(L: float, w: float) -> list:
    """The 12 bars of the frame of the cube [0, L]^3 (square section ``w``, corners filled)."""
    boxes = []
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        for c0, c1 in itertools.product((0.0, L), repeat=2):
            lo, hi = np.empty(3), np.empty(3)
            lo[axis], hi[axis] = -w / 2, L + w / 2
            lo[others], hi[others] = np.array([c0, c1]) - w / 2, np.array([c0, c1]) + w / 2
            boxes.append((lo, hi))
    return boxes


def _crossing(L: float, view, up) -> tuple[float, float]:
    """Height ``z`` on the back vertical bar ``(0, 0, z)`` where the front top bar ``(L, y, L)``
    crosses it on screen, and how much nearer the front bar is there (centre lines)."""
    R = view_frame(view, up)
    e0, e1 = R @ np.zeros(3), R @ np.array([0.0, 0.0, L])
    f0, f1 = R @ np.array([L, 0.0, L]), R @ np.array([L, L, L])
    A = np.stack([(e1 - e0)[:2], -(f1 - f0)[:2]], axis=1)
    t, u = np.linalg.solve(A, (f0 - e0)[:2])
    return float(t * L), float((f0 + u * (f1 - f0))[2] - (e0 + t * (e1 - e0))[2])


def impossible_cube(
    size: float = 10.0, bar_width: float = 1.0, resolution: int = 10, straight_bars: bool = True
):
    """Escher's impossible cube (the one held in *Belvedere*, 1958).

    Seen along ``(1, 0.8, 0.4)``, the back vertical bar at the origin crosses the front top bar
    ``(L,0,L)-(L,L,L)`` at about 60% of its height, ``d`` behind it.  The back bar is cut just
    above the crossing and again just above the bottom corner, and the piece between the two
    cuts is moved toward the viewer by ``a = d + 2.5 w`` along the view direction, *rigidly*:
    at the crossing the back bar passes in front of the front bar.  Both cuts lie in planes
    containing the view (seen edge-on, nothing drawn over them) and every face keeps its bar's
    normal, as a person sees the figure (straight, evenly shaded bars).  The two depth jumps
    (``+a`` and ``-a``) cancel around every loop, so this mescher has no period: like the Window
    it is impossible through its depth order (the back bar drawn in front of the front top bar,
    while the frame its zeta integrates to has it behind), ``is_impossible(order=...)`` of kind
    ``"order"``.  With axis-aligned bars every face loop integrates to zero anyway: Escher's
    cube is impossible through its order, not through its depths.

    ``straight_bars=False`` gives the period-carrying variant: one cut above the crossing, the
    part below it moved by ``a`` and eased back to 0 at the bottom corner, so the depth jumps by
    ``a`` at the cut (the mescher's period, one period class).  The easing is a shear along the
    view: the eased stretch's faces turn toward the camera and shade darker than the bar (a
    visible dark sheared band near the crossing).  It cannot hide: a period needs the depth to
    climb by ``a`` on every path from one side of the cut to the other, and in this view the
    path through the bottom x bar crosses no other bar, so some visible stretch must shear.

    Returns
    -------
    V, F, view, up, expected_period (0; ``a`` with ``straight_bars=False``)
    """
    L = as_positive(size, "size")
    w = as_positive(bar_width, "bar_width")
    n = as_count(resolution, "resolution", minimum=1)
    if not 8 * w <= L:
        raise MescherError(f"bar_width: expected at most size / 8 = {L / 8}, found {w}")
    zc, d = _crossing(L, CUBE_VIEW, CUBE_UP)
    P = zc + 2.5 * w  # the cut, above the crossing
    bottom = w / 2  # junction with the bottom corner
    flat_start = zc - 2.0 * w
    a = d + 2.5 * w
    r = (-w / 2, -w / 2), (w / 2, w / 2)
    if straight_bars:
        return _rigid_back_bar(L, w, n, P, a)
    V, F, side = box_union_surface(cube_frame_boxes(L, w), L / n, splits=[(2, P, *r)])
    in_bar = (np.abs(V[:, 0]) <= w / 2 + 1e-12) & (np.abs(V[:, 1]) <= w / 2 + 1e-12)
    z = V[:, 2]
    # the cut in a plane containing the view: seen edge-on it shows no inside (a horizontal cut
    # opens upward, toward the camera, at the top of the moved part). Each side of the split
    # tilts its own copy of the cut's vertices.
    upper = in_bar & ((z > P + 1e-12) | (side == 1))
    lower = in_bar & (z <= P + 1e-12) & (side == 0)
    V = np.where(
        upper[:, None],
        slant_cut(V, 2, P, *r, +1, w, CUBE_VIEW),
        np.where(lower[:, None], slant_cut(V, 2, P, *r, -1, w, CUBE_VIEW), V),
    )
    lower = in_bar & (z <= P + 1e-12) & (side == 0)  # the moved part, up to the cut
    phi = np.where(z >= flat_start, a, a * (z - bottom) / (flat_start - bottom))
    phi = np.where(lower, np.clip(phi, 0.0, a), 0.0)
    v = view_frame(CUBE_VIEW, CUBE_UP)[2]
    return CutModel(V + phi[:, None] * v, F, CUBE_VIEW, CUBE_UP, a)


def _rigid_back_bar(L: float, w: float, n: int, P: float, a: float):
    """The impossible cube whose back bar piece between heights ``Pb`` and ``P`` is moved by
    ``a`` along the view, rigidly (see :func:`impossible_cube`, ``straight_bars``)."""
    Pb = 1.5 * w  # a bar's width above the bottom corner's top (w / 2)
    r = (-w / 2, -w / 2), (w / 2, w / 2)
    V, F, side = box_union_surface(cube_frame_boxes(L, w), L / n, splits=[(2, P, *r), (2, Pb, *r)])
    in_bar = (np.abs(V[:, 0]) <= w / 2 + 1e-12) & (np.abs(V[:, 1]) <= w / 2 + 1e-12)
    z, eps = V[:, 2], 1e-12
    # the piece: below the upper cut (its lower copy) and above the lower cut (its upper copy)
    piece = in_bar & (
        ((z > Pb + eps) & (z < P - eps))
        | ((np.abs(z - P) <= eps) & (side == 0))
        | ((np.abs(z - Pb) <= eps) & (side == 2))
    )
    above = in_bar & ((z > P + eps) | (side == 1))
    below = in_bar & ((z < Pb - eps) | ((np.abs(z - Pb) <= eps) & (side == 0)))
    # every cut in a plane containing the view (seen edge-on): each side tilts its own copy,
    # fading within w (the piece's ends within w of each cut, the bottom stub down to the corner)
    tilt = [
        (above, slant_cut(V, 2, P, *r, +1, w, CUBE_VIEW)),
        (piece & (z > 0.5 * (P + Pb)), slant_cut(V, 2, P, *r, -1, w, CUBE_VIEW)),
        (piece & (z <= 0.5 * (P + Pb)), slant_cut(V, 2, Pb, *r, +1, w, CUBE_VIEW)),
        (below, slant_cut(V, 2, Pb, *r, -1, w / 2, CUBE_VIEW)),
    ]
    out = V.copy()
    for mask, moved in tilt:
        out[mask] = moved[mask]
    v = view_frame(CUBE_VIEW, CUBE_UP)[2]
    out[piece] += a * v  # rigid: the faces keep their normals
    return CutModel(out, F, CUBE_VIEW, CUBE_UP, 0.0)


def window(width: float = 12.0, height: float = 8.0, bar_width: float = 1.0, resolution: int = 12):
    """An impossible window frame that is a real 3D object.

    A rectangular frame with two vertical mullions, and a horizontal transom joined to the side
    bars by short posts.  The transom passes in front of the left mullion; between the mullions
    it slides back along the view direction (invisible on screen) and passes behind the right
    mullion: that slid model gives the depth order. The mescher is the frame a person sees,
    with a straight transom in front of both mullions: its zeta integrates (no period), and no
    depth offset per part realises the order (``is_impossible(order=...)``, kind ``"order"``).

    Returns
    -------
    V, F (the slid model), view, up, expected_period (0), builder of the perceived mescher
    """
    W = as_positive(width, "width")
    H = as_positive(height, "height")
    w = as_positive(bar_width, "bar_width")
    n = as_count(resolution, "resolution", minimum=1)
    if not (12 * w <= W and 6 * w <= H):
        raise MescherError(
            f"bar_width: expected at most width / 12 and height / 6 ({min(W / 12, H / 6)}), "
            f"found {w}"
        )
    m1, m2 = W / 3, 2 * W / 3
    y0, y1 = H / 2 - w / 2, H / 2 + w / 2

    def box(x0, x1, ya, yb, z0, z1):
        return np.array([x0, ya, z0]), np.array([x1, yb, z1])

    boxes = [
        box(0, w, 0, H, 0, w),
        box(W - w, W, 0, H, 0, w),
        box(0, W, 0, w, 0, w),
        box(0, W, H - w, H, 0, w),
        box(m1 - w / 2, m1 + w / 2, 0, H, 0, w),
        box(m2 - w / 2, m2 + w / 2, 0, H, 0, w),
        box(0, W, y0, y1, 2 * w, 3 * w),  # transom, in front of the frame
        box(0, w, y0, y1, w, 2 * w),  # posts joining it to the side bars
        box(W - w, W, y0, y1, w, 2 * w),
    ]
    V, F, _ = box_union_surface(boxes, W / n, [])
    D = 5.0 * w  # how far the transom slides back behind the right mullion
    knots = [m1 + w, m1 + 2.5 * w, m2 + 1.75 * w, W - 1.25 * w]
    g = np.interp(V[:, 0], knots, [0.0, -D, -D, 0.0], left=0.0, right=0.0)
    s = np.clip((V[:, 2] - w) / w, 0.0, 1.0)  # 0 on the frame, 1 on the transom
    v = view_frame(WINDOW_VIEW, WINDOW_UP)[2]
    flat = V

    def build():
        # what a person perceives: a straight transom in front of the frame (the slide along
        # the view is invisible on screen, and its sheared faces would shade as dark and
        # light squares); the depth order comes from the slid model
        from ..mescher import Mescher

        return Mescher.from_mesh(flat, F, view=WINDOW_VIEW, up=WINDOW_UP), np.arange(len(V))

    return CutModel(V + (g * s)[:, None] * v, F, WINDOW_VIEW, WINDOW_UP, 0.0, build)
