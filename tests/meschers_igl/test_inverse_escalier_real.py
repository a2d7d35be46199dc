"""Escher's ascending and descending stairs (IllusionEscalier) under the benchmark's lights.

The development model is a block with four flights of stairs around a well whose walls fill
the picture's middle: the figure has no hole, and the climb around the stairs (75 sqrt 3 in
the model, the depth gap where the top riser ends on the edge of the well's wall) can only be
read where the mesh is cut along the step edges.  At 128 x 128 the right flight shows its
risers, but the back and front-left flights turn theirs away from the viewer: each step is
then an occlusion of a tread over the tread below, one shade on both sides, and the picture
shows it only as a tooth a pixel or three long where the step edge meets each side of the
flight (on the outline or the wall below, and on the edge of the well).  A person pairs the
teeth across the flight, along the flight's cross direction, and reads the step edges there.

:func:`meschers_igl.inverse.picture.mescher_from_picture` does not yet: under lights 0, 1, 2
and 4 (three shades) the start's period is 0.01-0.04 against the climb 1.14 (the start's slits
hold pieces of it the outline does not: the fitted period of the benchmark is -65%).  What
stands in the way, on light 0:

- the teeth are pixel staircases: a tooth on the outer side is a 2-3 px occlusion whose front
  face its direction does not tell (``occlusion_chains`` drops it), or one along the cross
  direction whose line must end on the well's edge, where no notch of the outline is;
- a tooth on the well's side runs along the crease direction of the tread and the well's wall
  and is read as a crease: the onward rule then runs a hidden line from it along the flight,
  through the treads, instead of across;
- pairing reflex corners of the treads' region across it, along one of its edge directions
  (mutually best aligned, within 3 px, treads' pixels between and on both sides, the two
  corners far apart along the region's boundary, the line at their mean offset run 2 px past
  both) finds the six front-left steps and three of the five back ones: -21 to -23%; with
  the onward rays parallel to those steps run on to the outline, all five back ones: -18%
  on light 0 (the back lines lie about a pixel off the true edges; set at the inner
  corner's offset instead of the mean: -73%).

With the model's own invisible step edges (its z-buffer's face ids) cut instead, run 2 px past
both ends, the start comes to -4.3, -5.4, -6.3 and -6.9%: the step lines alone do not reach 5%
under lights 1, 2 and 4 (cut 1 px past: -13%, not past: -30%), and each moved a quarter pixel
across itself: -6 to -10%, half a pixel: -9 to -28%.  The climb hangs on where, to a fraction
of a pixel, the cuts meet the teeth, which the picture gives to a pixel at best.

The test pins the failure (strict: a rule that reads the steps turns it into a pass, and the
marker must go).  It skips without the development set.
"""

from __future__ import annotations

import numpy as np
import pytest

NAME = "IllusionEscalier.obj"


@pytest.fixture(scope="module")
def escalier(development_model):
    return development_model(NAME)


@pytest.mark.render
def test_escalier_climb_is_the_top_riser_over_the_well_wall(escalier):
    # 75 sqrt 3 in the model: the benchmark's period (tests/test_inverse_periods.py says why)
    np.testing.assert_allclose(escalier.gap, 75.0 * np.sqrt(3.0), rtol=1e-9)


@pytest.mark.render
@pytest.mark.xfail(
    strict=True,
    reason="step edges seen only as teeth on both sides of the flights are not paired",
)
@pytest.mark.parametrize("k", [0, 1, 2, 4])
def test_escalier_start_climbs_the_stairs(bench_start, escalier, k):
    """Three shades: the start's period (around the outline, the loop the fit keeps) within
    the benchmark's 5% of the climb."""
    from meschers_igl.inverse.metrics import figure_period

    m0, _, gap = bench_start(escalier, k)
    err = figure_period(m0) / gap - 1.0
    assert abs(err) < 0.05, err
