"""The study's measurements on fields and meshes, on hand-made cases."""

from __future__ import annotations

import numpy as np
import pytest

from meschers.metrics import exact_distance
from meschers_igl.gallery import get_model


def test_exact_distance_at_some_vertices_equals_the_full_field():
    g = get_model("penrose_triangle")
    m = g.mescher.subdivide(1)
    full, how = exact_distance(m, [3])
    coarse = g.mescher.n_vertices  # midpoint subdivision keeps the old vertices first
    part, how_part = exact_distance(m, [3], at=np.arange(coarse))
    np.testing.assert_allclose(part[:coarse], full[:coarse], rtol=1e-12)
    assert np.isinf(part[coarse:]).all() and f"at {coarse} of {m.n_vertices}" in how_part
    # midpoint subdivision keeps the surface: exact distances at the old vertices do not move
    coarse_d, _ = exact_distance(g.mescher, [3])
    np.testing.assert_allclose(part[:coarse], coarse_d, rtol=1e-9, atol=1e-9)
    assert np.isfinite(full).all() and full[3] == pytest.approx(0.0, abs=1e-12)


def test_subdivision_levels_keep_to_the_face_budget():
    from meschers.steps import subdivision_levels

    assert subdivision_levels(1408, 2, 24_000) == 2  # 22 528 faces
    assert subdivision_levels(2048, 2, 24_000) == 1  # 32 768 would be too many: 8 192
    assert subdivision_levels(30_000, 2, 24_000) == 0
    assert subdivision_levels(100, 0, 24_000) == 0
