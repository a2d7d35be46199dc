"""The box Penrose stairs under the acceptance benchmark's six lights: the climb of the start.

``benchmarks/bench_inverse_real.py`` draws six lights uniformly on the upper hemisphere
(seed 0) and renders each model with PyVista's z-buffer (flat Lambertian, ambient 0.2) on a
pale blue ground.  The period of the mescher read from the picture
(:func:`meschers_igl.inverse.picture.mescher_from_picture`) is the period of the fit (the
fit leaves it), so the benchmark's period column is checked here in a fraction of a second
per light.

Under lights 3 and 5 the treads and the inner walls are both turned away from the light (one
shade, the ambient), and the walls of the upper-left flight are a thin strip along the
courtyard whose steps (its teeth, where a wall ends under the next tread) no line shows.
Chords along the walls' direction run the strip's length and end, past unseen edges, on
tread lines: the strip is read as treads, no step of that flight is cut (3 hidden step edges
instead of 9) and the climb comes out 41% short.  The teeth lie where the tread edges from
the notches of the outer outline (along ``d_B1``) cross the wall edges from the jogs of the
courtyard's outline (along ``d_B2``); the true labels give +2.0% and +1.5%.
"""

from __future__ import annotations

import numpy as np
import pytest

from meschers_igl.inverse import metrics as met
from meschers_igl.inverse import models as mdl
from meschers_igl.inverse import picture as pic

AMBIENT = 0.2
GROUND = (0.55, 0.7, 0.9)


def _bench_lights(n: int = 6, seed: int = 0) -> np.ndarray:
    """The benchmark's lights: ``n`` unit directions uniform on the hemisphere ``z > 0``."""
    v = np.random.default_rng(seed).normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v


def _period_error(k: int) -> float:
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_stairs()
    light = _bench_lights()[k]
    image, scale = zbuffer_picture(model, 128, light=light, ambient=AMBIENT, background=GROUND)
    m, _, _ = pic.mescher_from_picture(image, light, AMBIENT, background=GROUND)
    gap = model.gap * scale
    return (met.figure_period(m) - gap) / gap


def test_bench_lights_are_the_benchmarks():
    """Lights 3 and 5 come from the left, nearly level (3) or 19 degrees up (5)."""
    L = _bench_lights()
    np.testing.assert_allclose(L[3], [-0.8967022761, -0.4416644114, 0.0292843931], atol=1e-9)
    np.testing.assert_allclose(L[5], [-0.7583158230, -0.5636195521, 0.3275516952], atol=1e-9)


@pytest.mark.render
@pytest.mark.parametrize("k", [0, 1, 2, 4])
def test_stairs_climb_under_three_shades(k):
    """Three shades: within the benchmark's 5% (+3.1, +4.8, +4.0, +2.2%)."""
    pytest.importorskip("pyvista")
    err = _period_error(k)
    assert abs(err) < 0.05, err


@pytest.mark.render
@pytest.mark.xfail(
    strict=True,
    reason="walls and treads of one shade: the wall strip's teeth are not read, -41%",
)
@pytest.mark.parametrize("k", [3, 5])
def test_stairs_climb_with_walls_and_treads_of_one_shade(k):
    """Two shades, the walls of the upper-left flight told from its treads by lines no
    picture draws: the climb must still be within 5%."""
    pytest.importorskip("pyvista")
    err = _period_error(k)
    assert abs(err) < 0.05, err
