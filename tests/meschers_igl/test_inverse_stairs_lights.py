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

The climb then hangs on single pixels: with the true labels, every wall's unseen top edge one
pixel row higher gives +9.6% and +9.1%, one row lower -5.8% and -6.2%, and one 3 x 3 majority
pass over the two faces of the shade (what :func:`.faces.split_shared_shade` does to its own
labels) -23.3% and -23.8%: the strip's teeth are one to three pixels wide.  A rule must read
the strip to the pixel, and leave it unsmoothed.
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


def _picture(k: int):
    """The benchmark's picture of the stairs under light ``k``: image, light, depth gap."""
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_stairs()
    light = _bench_lights()[k]
    image, scale = zbuffer_picture(model, 128, light=light, ambient=AMBIENT, background=GROUND)
    return image, light, model.gap * scale


def _period_error(k: int) -> float:
    image, light, gap = _picture(k)
    m, _, _ = pic.mescher_from_picture(image, light, AMBIENT, background=GROUND)
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


@pytest.mark.render
@pytest.mark.parametrize("k", [3, 5])
def test_stairs_climb_of_two_shades_with_the_three_shade_labels(k, monkeypatch):
    """The orientations are all the two-shade pictures lack: read with the labels of the same
    figure under light 0 (three shades, pixel for pixel the same outline; each region matched
    to the two-shade reading's normal it lies along), the start climbs within 5% (+2.0%,
    +1.5%): the hidden step edges, the cuts and the lift need nothing else."""
    pytest.importorskip("pyvista")
    image, light, gap = _picture(k)
    image0, light0, _ = _picture(0)
    _, _, info0 = pic.mescher_from_picture(image0, light0, AMBIENT, background=GROUND)
    two = pic.segment_picture(image, GROUND, light=light, ambient=AMBIENT)
    assert two.normals is not None  # two shades: the lines told the orientations apart
    match = np.abs(info0["normals"] @ two.normals.T)  # (3, 3) |cos| between the readings
    perm = np.argmax(match, axis=1)
    assert sorted(perm.tolist()) == [0, 1, 2] and match.max(axis=1).min() > 0.99, match
    labels = np.where(info0["labels"] >= 0, perm[np.maximum(info0["labels"], 0)], -1)
    np.testing.assert_array_equal(labels >= 0, two.mask)
    grey = image.mean(axis=-1)
    shades = np.array([grey[labels == r].mean() for r in range(3)])
    monkeypatch.setattr(
        pic,
        "segment_picture",
        lambda *a, **kw: pic.Segmentation(two.mask, labels, shades, two.normals),
    )
    m, _, info = pic.mescher_from_picture(image, light, AMBIENT, background=GROUND)
    err = (met.figure_period(m) - gap) / gap
    assert len(info["hidden_lines"]) >= 8, len(info["hidden_lines"])
    assert abs(err) < 0.05, err
