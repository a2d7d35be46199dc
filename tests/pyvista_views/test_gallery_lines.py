"""The gallery figure's stairs show every step: where a tread meets the next step's tread of the
same shade, only a line tells them apart, and :func:`pyvista_views.lineart.overlay` draws it.

Measured against the CPU painter's visible-face map: the boundary pixels between two visible
faces of one orientation that lie on different planar patches (the treads of neighbouring steps)
are dark in the overlay and not in the plain render.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import binary_dilation

from meschers_igl.gallery import get_model
from meschers_igl.painter import visible_faces

pytest.importorskip("cairosvg")

SIZE = 320
LIGHT = (0.4, 0.6, 1.0)


def tread_heights(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normal and plane offset of each face of the 3D (cut) model."""
    P = V[F]
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return n, np.einsum("ij,ij->i", n, P[:, 0])


def step_edge_pixels(g, face_map: np.ndarray) -> np.ndarray:
    """Pixels where the visible surface passes from one tread to a parallel one a few risers
    away that is not joined to it in the mescher: a step.

    Left out: faces joined in the mescher (the cut model's seam, where its heights jump by the
    period) and the impossible junction, where the top flight meets the bottom one at a height
    the picture does not show (no line there in Penrose's drawing either).
    """
    n, off = tread_heights(g.V, g.F)
    F = g.mescher.F
    out = np.zeros(face_map.shape, bool)
    for a, b, sa, sb in (
        (face_map[:, :-1], face_map[:, 1:], np.s_[:, :-1], np.s_[:, 1:]),
        (face_map[:-1], face_map[1:], np.s_[:-1], np.s_[1:]),
    ):
        ok = (a >= 0) & (b >= 0) & (a != b)
        aa, bb = np.where(ok, a, 0), np.where(ok, b, 0)
        parallel = np.einsum("...i,...i->...", n[aa], n[bb]) > 1 - 1e-9
        joined = (F[aa][..., :, None] == F[bb][..., None, :]).any(axis=(-1, -2))
        rise = np.abs(off[aa] - off[bb])
        hit = ok & parallel & ~joined & (rise > 1e-9)
        riser = rise[hit].min()
        hit &= rise < 4 * riser
        out[sa] |= hit
        out[sb] |= hit
    return out


def dark_share(image: np.ndarray, where: np.ndarray) -> float:
    lum = image[..., :3].astype(float).mean(axis=2)
    dark = binary_dilation(lum < 60, iterations=1)
    return float(dark[where].mean())


def test_every_step_of_the_stairs_is_drawn():
    from pyvista_views import render
    from pyvista_views.camera import default_bounds
    from pyvista_views.lineart import overlay

    g = get_model("penrose_stairs")
    m, order = g.mescher, g.order
    lo, hi = m.xy.min(axis=0), m.xy.max(axis=0)
    b = default_bounds((lo[0], hi[0], lo[1], hi[1]), (SIZE, SIZE))
    face_map = visible_faces(m, order, size=SIZE, bounds=b)
    steps = step_edge_pixels(g, face_map)
    assert steps.sum() > 100  # the treads of neighbouring steps meet along many pixels
    plain = render(m, order, lights=[LIGHT], window_size=(SIZE, SIZE), bounds=b)
    drawn = overlay(m, order, window_size=(SIZE, SIZE), bounds=b, lights=[LIGHT])
    assert dark_share(plain, steps) < 0.2  # the shading alone hides most steps
    assert dark_share(drawn, steps) > 0.95
