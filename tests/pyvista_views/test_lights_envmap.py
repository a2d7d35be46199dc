"""Lights and environment maps: validation and the irradiance math (no GL needed)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from meschers_igl import MescherError
from pyvista_views.envmap import EnvironmentMap, as_env_map, latlong_directions, sh9
from pyvista_views.lights import DirectionalLight, as_lights, lambert

RNG = np.random.default_rng(7)


def unit(n: int) -> np.ndarray:
    v = RNG.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


# -- lights ---------------------------------------------------------------------------------


def test_single_direction_and_lists_normalise_to_unit_directional_lights():
    (light,) = as_lights((0, 0, 2))
    np.testing.assert_allclose(light.direction, [0, 0, 1])
    lights = as_lights([(1, 0, 0), DirectionalLight(np.array([0.0, 1.0, 0.0]), 0.5)])
    assert [lt.intensity for lt in lights] == [1.0, 0.5]
    assert as_lights(None) == [] and as_lights([]) == []
    (d,) = as_lights({"direction": (0, 3, 4), "intensity": 2.0, "color": (1, 0, 0)})
    np.testing.assert_allclose(d.direction, [0, 0.6, 0.8])
    np.testing.assert_allclose(d.radiance, [2, 0, 0])


def test_pyvista_directional_light_keeps_its_direction():
    (light,) = as_lights([pv.Light(position=(1, 2, 2), focal_point=(0, 0, 0), positional=False)])
    np.testing.assert_allclose(light.direction, np.array([1, 2, 2]) / 3)


@pytest.mark.parametrize(
    "spec, words",
    [
        (pv.Light(position=(0, 0, 5), positional=True), "positional"),
        ({"type": "point", "direction": (0, 0, 1)}, "type='point'"),
        ({"position": (0, 0, 5)}, "position"),
        ("point", "string"),
        ((0, 0, 0), "non-zero"),
        ([(1, 0)], "shape"),
    ],
)
def test_point_lights_and_bad_directions_are_refused_with_a_named_reason(spec, words):
    with pytest.raises(MescherError, match="lights") as info:
        as_lights(spec)
    assert words in str(info.value)
    if "positional" in words or "point" in words or "position" in words:
        assert "Section 4.1" in str(info.value)


def test_lambert_is_clamped_cosine_times_radiance_summed_over_lights():
    n = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    lights = as_lights([(0, 0, 1), {"direction": (1, 0, 1), "intensity": 2.0}])
    c = np.sqrt(0.5)
    expected = np.array([1 + 2 * c, 2 * c, 0.0])
    np.testing.assert_allclose(lambert(n, lights), np.repeat(expected[:, None], 3, 1))


# -- environment maps -------------------------------------------------------------------------


def test_sh_basis_is_orthonormal_on_the_latlong_quadrature():
    d, dw = latlong_directions(128, 256)
    Y = sh9(d.reshape(-1, 3))
    w = np.broadcast_to(dw, d.shape[:2]).reshape(-1)
    np.testing.assert_allclose((Y * w[:, None]).T @ Y, np.eye(9), atol=2e-4)


def test_latlong_convention_middle_is_forward_top_is_up_right_is_plus_x():
    d, _ = latlong_directions(4, 8)
    np.testing.assert_allclose(d[0, 0, 1], np.cos(np.pi / 8))  # top row points up
    mid = 0.5 * (d[1, 3] + d[1, 4] + d[2, 3] + d[2, 4])
    assert mid[2] < -0.9 * np.linalg.norm(mid)  # middle: the way the camera looks (-z)
    assert d[2, 6, 0] > 0.5 and d[2, 1, 0] < -0.5  # right half +x, left half -x


def test_uniform_environment_gives_its_radiance_for_every_normal():
    env = as_env_map("uniform")
    np.testing.assert_allclose(env.irradiance(unit(50)), 1.0, atol=1e-3)


@pytest.mark.parametrize("a, b", [(0.5, 0.3), (1.0, -0.7)])
def test_linear_environment_irradiance_is_exact(a, b):
    """L(w) = a + b w.z  =>  E(n) = (1/pi) int L max(0, n.w) dw = a + (2/3) b n.z (hand-derived)."""
    env = EnvironmentMap.from_function(
        lambda w: np.repeat((a + b * w[:, 2])[:, None], 3, 1), "linear", 256
    )
    n = unit(40)
    np.testing.assert_allclose(env.irradiance(n)[:, 0], a + 2 / 3 * b * n[:, 2], atol=2e-4)


def test_quadratic_environment_irradiance_is_exact():
    """L(w) = w.y^2  =>  E(n) = 1/4 + n.y^2 / 4 (the l=2 band is scaled by A2/pi = 1/4)."""
    env = EnvironmentMap.from_function(lambda w: np.repeat(w[:, 1:2] ** 2, 3, 1), "quad", 256)
    n = unit(40)
    np.testing.assert_allclose(env.irradiance(n)[:, 1], 0.25 + 0.25 * n[:, 1] ** 2, atol=2e-4)


def test_sun_environment_approximates_lambert_within_sh_error():
    """A small bright disc behaves like a directional light (order-2 SH: a few % of the peak)."""
    s = np.array([0.3, 0.5, 0.81])
    s /= np.linalg.norm(s)
    cap = 1 - np.cos(0.1)

    def sun(w):
        return np.repeat(((w @ s) > np.cos(0.1))[:, None] / (2 * np.pi * cap), 3, 1) * np.pi

    env = EnvironmentMap.from_function(sun, "sun", 512)
    n = unit(200)
    exact = np.clip(n @ s, 0, None)
    assert np.abs(env.irradiance(n)[:, 0] - exact).max() < 0.1


def test_image_file_round_trip_is_srgb_decoded(tmp_path):
    from PIL import Image

    Image.fromarray(np.full((16, 32, 3), 128, np.uint8)).save(tmp_path / "grey.png")
    env = as_env_map(tmp_path / "grey.png")
    linear = ((128 / 255 + 0.055) / 1.055) ** 2.4
    np.testing.assert_allclose(env.irradiance(unit(5)), linear, atol=2e-3)
    np.testing.assert_allclose(
        as_env_map(np.full((16, 32, 3), linear)).coefficients, env.coefficients, atol=1e-9
    )


@pytest.mark.parametrize(
    "bad, words",
    [
        ("nowhere.hdr", "image file"),
        (np.zeros((4,)), "lat-long"),
        (np.full((8, 16, 3), np.nan), "finite"),
        (3.0, "float"),
    ],
)
def test_bad_environment_maps_are_refused(bad, words):
    with pytest.raises(MescherError, match="env_map") as info:
        as_env_map(bad)
    assert words in str(info.value)
