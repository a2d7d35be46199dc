"""Riser bands of hidden steps, once glued, are narrowed to BAND_DRAWN of their width: the
picture of the mescher nears the z-buffer's along the step fronts, and nothing else changes
(topology, periods, the bands' corners on their two treads)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_obtain_hidden_riser import penrose_columns, straight_flight

import meschers_igl.obtain.see as see_mod
from meschers_igl.errors import MescherWarning
from meschers_igl.obtain import model_to_mescher, see_model
from meschers_igl.obtain.glue import BAND_DRAWN, STEP_BAND, narrow_step_bands
from meschers_igl.operators import view_frame


def _see(V, F, view, up=(0.0, 0.0, 1.0)):
    v = np.asarray(view, float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        return see_model(V, F, v / np.linalg.norm(v), up, snap=False)


def _widths(vm):
    """Screen width (twice the area over the longest edge) of each band face."""
    T = vm.xy[vm.F[vm.report.source_face < 0]]
    a = np.abs(
        (T[:, 1, 0] - T[:, 0, 0]) * (T[:, 2, 1] - T[:, 0, 1])
        - (T[:, 2, 0] - T[:, 0, 0]) * (T[:, 1, 1] - T[:, 0, 1])
    )
    L = np.linalg.norm(T - T[:, [1, 2, 0]], axis=2).max(axis=1)
    return a / L


@pytest.mark.parametrize("s", [4, 5])
def test_bands_are_narrowed_and_nothing_else_changes(s, monkeypatch):
    """The narrowed bands are at most BAND_DRAWN of STEP_BAND of the size wide; the periods
    and the mescher's faces are those of the wide bands (narrow_step_bands with shrink 1)."""
    V, F, w = penrose_columns(s)
    vm = _see(V, F, w)
    diag = float(np.linalg.norm(np.ptp(V, axis=0)))
    width = _widths(vm)
    assert width.size > 0
    assert width.max() <= STEP_BAND * BAND_DRAWN * diag * (1.0 + 1e-6)

    def wide(*args, **kw):
        return narrow_step_bands(*args, shrink=1.0, **kw)

    monkeypatch.setattr(see_mod, "narrow_step_bands", wide)
    vw = _see(V, F, w)
    assert _widths(vw).max() > 10.0 * width.max()  # the wide bands, as glued
    np.testing.assert_array_equal(vm.F, vw.F)
    from meschers_igl import Mescher

    p1 = np.sort(np.abs(Mescher.from_corner_depths(vm.F, vm.xy, vm.Z).periods()))
    p2 = np.sort(np.abs(Mescher.from_corner_depths(vw.F, vw.xy, vw.Z).periods()))
    np.testing.assert_allclose(p1, p2, atol=1e-9 * diag)
    np.testing.assert_allclose(p1.max(), np.linalg.norm(w), rtol=1e-6)


def test_narrowed_band_corners_stay_on_their_treads():
    """Each band corner, read back in 3D from its screen position and depth, lies on a tread:
    world height a whole number of rises, the two ends one rise apart."""
    rise = 0.25
    V, F = straight_flight(n=4, rise=rise)
    vm = _see(V, F, (2.0, 1.0, 2.0))
    band = vm.report.source_face < 0
    assert band.any()
    R = view_frame(vm.report.view, vm.report.up)
    P = np.concatenate([vm.xy[vm.F[band]], vm.Z[band][..., None]], axis=2)
    height = (P @ R)[..., 2] / rise
    np.testing.assert_allclose(height, np.round(height), atol=1e-6)
    k = np.round(height)
    np.testing.assert_array_equal(k.max(axis=1) - k.min(axis=1), 1.0)


def _differing_pixels(V, F, w):
    from pyvista_views import render

    v = w / np.linalg.norm(w)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        m, order, report = model_to_mescher(V, F, view=v, up=(0.0, 0.0, 1.0))
    C = V @ view_frame(report.view, report.up).T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    kw = dict(
        window_size=(480, 480),
        bounds=(c[0] - h, c[0] + h, c[1] - h, c[1] + h),
        lights=[(0.3, 0.5, 1.0)],
        anti_aliasing=False,
    )
    ref = render((C, F), **kw).astype(int)
    img = render(m, order=order, **kw).astype(int)
    return int((np.abs(ref - img).max(axis=2) > 8).sum())


def test_picture_along_the_step_fronts_nears_the_z_buffer(monkeypatch):
    """Rendered beside the z-buffer of the model (one light, no anti-aliasing), the mescher of
    a Penrose ring differs in at most a tenth of the pixels the wide bands showed as dotted
    lines along the step fronts (over 100 at this size)."""
    pytest.importorskip("pyvista")
    from pyvista_views.headless import configure_headless

    configure_headless()
    V, F, w = penrose_columns(4)
    narrow = _differing_pixels(V, F, w)

    def wide(*args, **kw):
        return narrow_step_bands(*args, shrink=1.0, **kw)

    monkeypatch.setattr(see_mod, "narrow_step_bands", wide)
    before = _differing_pixels(V, F, w)
    assert before > 100
    assert narrow <= 0.1 * before
