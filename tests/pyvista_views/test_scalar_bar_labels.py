"""Colour-bar labels print the values they stand for, with round-off shown as 0 (issue 17.5)."""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import requires_gl

from meschers_igl import shapes
from pyvista_views import MescherScene

pytestmark = [requires_gl, pytest.mark.render]


def test_symmetric_range_labels_its_middle_zero():
    m = shapes.impossible_torus(24, 8, climb=1.0)
    z = m.xy[:, 0] - m.xy[:, 0].mean()
    z = z - 0.5 * (z.max() + z.min()) + 1e-13  # symmetric up to round-off
    with MescherScene(window_size=(300, 300)) as scene:
        scene.add(m, scalars=z)
        actor = scene.add_scalar_bar("x")
        labels = actor.GetCustomLabels()
        values = np.array([labels.GetValue(i) for i in range(labels.GetNumberOfTuples())])
    assert actor.GetUseCustomLabels()
    lo, hi = z.min(), z.max()
    np.testing.assert_allclose(values[[0, -1]], [lo, hi], rtol=1e-12)
    assert values[len(values) // 2] == 0.0  # not 1e-13
    np.testing.assert_allclose(np.diff(values), (hi - lo) / (len(values) - 1), rtol=1e-9)


def test_inner_bar_labels_are_rounded_to_a_hundredth_of_the_range():
    """(-0.582, 0.578): the middle label reads 0 (not -0.00178), the quarter ones +-0.29; the
    ends stay the data's range."""
    from pyvista_views.scene import _exact_zero_labels

    class Bar:
        def SetCustomLabels(self, labels):  # noqa: N802 (VTK's name)
            self.values = [labels.GetValue(i) for i in range(labels.GetNumberOfTuples())]

        def SetUseCustomLabels(self, on):  # noqa: N802
            self.on = on

    bar = Bar()
    _exact_zero_labels(bar, (-0.582, 0.578), 5)
    assert bar.values == [-0.582, -0.29, 0.0, 0.29, 0.578]
    assert str(bar.values[2]) == "0.0"  # not "-0.0"
