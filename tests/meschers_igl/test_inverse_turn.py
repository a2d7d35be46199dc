"""Faces turned back to their shade regions' normals during the fit (inverse.turn)."""

from __future__ import annotations

import numpy as np
import pytest
from test_inverse_faces import AMBIENT, GROUND, _angles_deg, _cube_picture, _frame

from meschers_igl import MescherError
from meschers_igl.inverse import picture as pic

pytest.importorskip("torch")
pytest.importorskip("largesteps")


def _about(v: np.ndarray, axis: np.ndarray, deg: float) -> np.ndarray:
    """Rows of ``v`` turned by ``deg`` about the unit ``axis`` (Rodrigues)."""
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return v * c + np.cross(axis, v) * s + np.outer(v @ axis, axis) * (1 - c)


def _cube(res: int, seed: int = 7):
    N = _frame(seed)
    light = np.array([0.3, 0.4, 0.87])
    light /= np.linalg.norm(light)
    image, _ = _cube_picture(N, light, res=res)
    m0, region, info = pic.mescher_from_picture(image, light, AMBIENT, background=GROUND)
    return image, light, m0, region, info


@pytest.mark.parametrize("power", [1, 2])
def test_turn_parametrization_adds_turn_faces_exact_form(power):
    from meschers_igl.inverse.sobolev import MescherParametrization
    from meschers_igl.inverse.turn import turn_depths, turn_faces, turn_parametrization

    _, _, m0, region, info = _cube(40)
    want = info["normals"][region]
    rng = np.random.default_rng(1)
    bent = m0.with_zeta(np.asarray(m0.zeta) + m0.d01 @ rng.normal(0, 0.05, m0.n_vertices))
    par = MescherParametrization(bent, None, 1.0, "uniform", power)
    before = par.mescher()
    assert _angles_deg(before.face_normals(), info["normals"]).max() > 5.0
    turn_parametrization(par, want)
    after = par.mescher()
    # the oracle: turn_faces of the iterate (float32 leaves: depths to ~1e-6)
    oracle = turn_faces(before, want)
    np.testing.assert_allclose(np.asarray(after.zeta), np.asarray(oracle.zeta), atol=2e-5)
    np.testing.assert_allclose(after.face_normals(), m0.face_normals(), atol=1e-3)
    np.testing.assert_array_equal(np.asarray(after.xy), np.asarray(before.xy))
    np.testing.assert_allclose(after.periods(), before.periods(), atol=1e-12)
    # turn_depths is that exact form
    dz = turn_depths(before, want)
    np.testing.assert_allclose(
        np.asarray(before.zeta) + before.d01 @ dz, np.asarray(oracle.zeta), atol=1e-12
    )
    with pytest.raises(MescherError, match="face_normals"):
        turn_depths(before, want[:-1])


def test_penalty_is_half_the_mean_squared_normal_distance():
    import torch

    from meschers_igl.inverse.sobolev import MescherParametrization
    from meschers_igl.inverse.turn import FaceTurn

    _, light, m0, region, info = _cube(40)
    want = _about(info["normals"], light, 12.0)[region]
    par = MescherParametrization(m0, None, 1.0, "uniform", 1)
    with torch.no_grad():
        got = float(FaceTurn(want, 0, 0.3).penalty(par, par.xy(), par.zeta()))
    n = par.mescher().face_normals()
    expect = 0.3 * 0.5 * np.mean(np.sum((n - want) ** 2, axis=1))
    assert got == pytest.approx(expect, rel=1e-5)
    assert FaceTurn(want, 0, 0.0).penalty(par, par.xy(), par.zeta()) == 0.0


def test_penalty_turns_faces_tilted_about_the_light_back_and_the_fit_still_gains():
    from meschers_igl.inverse import optimize as opt
    from meschers_igl.inverse.metrics import image_psnr

    image, light, m0, region, info = _cube(40)
    want = info["normals"][region]
    # every face turned 12 degrees about the light: the same shades, the picture cannot tell
    tilt = _about(info["normals"], light, 12.0)[region]
    tilted = pic.lift(np.asarray(m0.xy), np.asarray(m0.F), tilt)
    kw = dict(lights=[light], ambient=AMBIENT, background=GROUND)
    start = opt.fit_mescher(image, tilted, None, options=pic.fit_options(iters=0), **kw)
    o = pic.fit_options(iters=60, info=info, turn=(-1, 1.0))
    free = opt.fit_mescher(image, tilted, None, options=o, **kw)
    held = opt.fit_mescher(image, tilted, None, options=o, face_normals=want, **kw)
    a_start, a_free, a_held = (
        np.median(_angles_deg(r.mescher.face_normals(), info["normals"]))
        for r in (start, free, held)
    )
    # the image alone leaves the tilt (its shades are right); the penalty turns faces back
    assert a_free > 0.7 * a_start
    assert a_held < a_free - 1.0
    # and the fit still gains on the picture (the start is a lift: its creases are rough)
    assert image_psnr(held.image, image) > image_psnr(start.image, image) + 2.0
    # negative turn[0]: the penalty alone, the returned mescher is the fit's iterate (no
    # turn after the fit): its render is the image returned
    from meschers_igl.inverse import rasterizer as ras

    img = ras.render_mescher(
        held.mescher,
        held.offsets,
        [light],
        None,
        AMBIENT,
        resolution=40,
        sigma=o.final_sigma,
        background=GROUND,
    )
    np.testing.assert_allclose(held.image, img, atol=1e-12)
