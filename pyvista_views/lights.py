"""Directional lights: the only lights a mescher can be lit by (paper Section 4.1).

A mescher has no absolute depth, so radiance that depends on *where* a point is (point, spot and
area lights) is undefined for it; radiance that depends only on the *direction* it arrives from is
translation invariant and therefore well defined.  Directional lights and environment maps
(:mod:`.envmap`) are exactly those.  Everything here is in the camera frame of docs/conventions.rst: x right,
y up, z toward the viewer; a light is given by the unit direction *toward* it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pyvista as pv

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_direction, as_float_array, as_positive

_WHY_DIRECTIONAL = (
    "meschers have no absolute depth, so only directional lights and environment maps are "
    "defined for them (paper Section 4.1)"
)


@dataclass(frozen=True)
class DirectionalLight:
    """A light at infinity.

    Parameters
    ----------
    direction : (3,) float64
        Unit vector toward the light in the camera frame (x right, y up, z toward the viewer).
    intensity : float
        Scale of the light's colour (VTK's light intensity).
    color : (3,) float64
        Linear RGB in [0, 1].
    """

    direction: np.ndarray
    intensity: float = 1.0
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)

    @property
    def radiance(self) -> np.ndarray:
        """(3,) ``intensity * color``, what multiplies the Lambert cosine."""
        return self.intensity * np.asarray(self.color, dtype=np.float64)

    def to_vtk(self) -> pv.Light:
        """A non-positional scene light shining from ``direction`` toward the origin.

        The camera of every view looks down -z with y up, so scene and camera frames agree.
        """
        return pv.Light(
            position=tuple(self.direction),
            focal_point=(0.0, 0.0, 0.0),
            color=tuple(self.color),
            intensity=self.intensity,
            light_type="scene light",
            positional=False,
        )


def _from_pv_light(light: pv.Light, name: str) -> DirectionalLight:
    if light.positional:
        raise MescherError(
            f"{name}: expected a directional light, found a positional (point or spot) "
            f"pyvista.Light at {tuple(light.position)}; {_WHY_DIRECTIONAL}"
        )
    # Scene, camera and head lights alike: every view's camera looks down -z with y up, so the
    # camera frame is the scene frame up to a translation, which a direction ignores.
    direction = np.asarray(light.position, float) - np.asarray(light.focal_point, float)
    return DirectionalLight(
        as_direction(direction, name), float(light.intensity), tuple(light.diffuse_color)
    )


def _from_mapping(spec: dict, name: str) -> DirectionalLight:
    kind = str(spec.get("type", "directional")).lower()
    if kind != "directional" or "position" in spec:
        raise MescherError(
            f"{name}: expected a directional light, found type={kind!r}"
            + (f" with position {spec['position']}" if "position" in spec else "")
            + f"; {_WHY_DIRECTIONAL}"
        )
    if "direction" not in spec:
        raise MescherError(f"{name}: expected a 'direction' key, found keys {sorted(spec)}")
    color = as_float_array(spec.get("color", (1.0, 1.0, 1.0)), f"{name}['color']", (3,))
    return DirectionalLight(
        as_direction(spec["direction"], f"{name}['direction']"),
        as_positive(spec.get("intensity", 1.0), f"{name}['intensity']", allow_zero=True),
        tuple(float(c) for c in color),
    )


def as_lights(lights: object, name: str = "lights") -> list[DirectionalLight]:
    """Normalise a light specification to a list of :class:`DirectionalLight`.

    Parameters
    ----------
    lights : None, (3,) array_like, or sequence
        ``None`` or ``[]`` for no light; one direction ``(x, y, z)``; or a sequence whose items are
        directions, :class:`DirectionalLight`, non-positional :class:`pyvista.Light`, or dicts
        ``{"direction": ..., "intensity": 1.0, "color": (1, 1, 1)}``.
    name : str
        Argument name used in error messages.

    Raises
    ------
    MescherError
        For a point, spot or otherwise positional light (undefined on a mescher, paper Section 4.1),
        a zero direction, or anything that is not a light.
    """
    if lights is None:
        return []
    if isinstance(lights, (DirectionalLight, pv.Light, dict, str)):
        lights = [lights]
    elif isinstance(lights, np.ndarray) and lights.ndim == 1:
        lights = [lights]
    elif (
        isinstance(lights, Sequence)
        and len(lights) == 3
        and all(isinstance(c, (int, float, np.number)) for c in lights)
    ):
        lights = [lights]
    out = []
    for i, item in enumerate(lights):
        item_name = f"{name}[{i}]"
        if isinstance(item, DirectionalLight):
            out.append(item)
        elif isinstance(item, pv.Light):
            out.append(_from_pv_light(item, item_name))
        elif isinstance(item, dict):
            out.append(_from_mapping(item, item_name))
        elif isinstance(item, str):
            raise MescherError(
                f"{item_name}: expected a direction (x, y, z) toward a directional light, found "
                f"the string {item!r}; {_WHY_DIRECTIONAL}"
            )
        else:
            out.append(DirectionalLight(as_direction(item, item_name)))
    return out


def lambert(normals: np.ndarray, lights: Sequence[DirectionalLight]) -> np.ndarray:
    """Diffuse irradiance of directional lights, ``sum_i I_i c_i max(0, dot(n, l_i))``.

    Parameters
    ----------
    normals : (n, 3) float64
        Unit normals in the camera frame.
    lights : sequence of DirectionalLight

    Returns
    -------
    (n, 3) float64
        Linear RGB irradiance (what VTK's diffuse term multiplies by the material colour).
    """
    out = np.zeros((normals.shape[0], 3))
    for light in lights:
        cos = np.clip(normals @ light.direction, 0.0, None)
        out += cos[:, None] * light.radiance[None, :]
    return out


def set_vtk_lights(plotter: pv.Plotter, lights: Sequence[DirectionalLight]) -> None:
    """Replace every light of ``plotter`` (light kit and headlight included) by ``lights``."""
    plotter.remove_all_lights()
    # Otherwise VTK adds a headlight to a renderer left without lights.
    plotter.renderer.SetAutomaticLightCreation(False)
    # With no light at all VTK's shaders skip lighting and draw ambient + diffuse unlit; a black
    # light keeps the lit path, so "no light" means ambient only.
    for light in lights or [DirectionalLight(np.array([0.0, 0.0, 1.0]), 0.0)]:
        plotter.add_light(light.to_vtk())


def _visible_normals(count: int = 4096) -> np.ndarray:
    """Unit normals of the hemisphere facing the viewer (n_z >= 0), a Fibonacci lattice."""
    i = np.arange(count) + 0.5
    z = i / count  # uniform in z on [0, 1]: uniform in area on the hemisphere
    phi = np.pi * (1.0 + 5**0.5) * i
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def peak_irradiance(lights: Sequence[DirectionalLight], env_map: object = None) -> float:
    """Largest irradiance any visible normal receives, over the colour channels.

    ``max over n with n_z >= 0 of max_c (sum_i I_i c_i max(0, n . l_i) + E_env(n))_c``: what
    a matte surface seen head-on can be lit by at most (a visible face's normal points toward
    the viewer, as the renderer's two-sided lighting flips the others).  Evaluated on 4096
    normals of that hemisphere plus each light's direction (where a lone light peaks), so it is
    exact for one light and within a fraction of a percent otherwise.

    Parameters
    ----------
    lights : sequence of DirectionalLight
    env_map : EnvironmentMap, optional
        Anything with ``irradiance(normals (n, 3)) -> (n, 3)``.

    Returns
    -------
    float
    """
    n = _visible_normals()
    toward = [light.direction for light in lights if light.direction[2] >= 0]
    if toward:
        n = np.concatenate([n, np.asarray(toward, dtype=np.float64)])
    e = lambert(n, lights)
    if env_map is not None:
        e = e + env_map.irradiance(n)
    return float(e.max()) if e.size else 0.0


def exposure_scale(
    peak: float, ambient: float, diffuse: float, exposure: float = 1.0, normalize: bool = True
) -> float:
    """Factor on the irradiance so that the brightest visible normal is not washed out.

    A matte material shows ``albedo * (ambient + diffuse * s * E(n))``; with ``normalize`` the
    factor is ``s = exposure * min(1, (1 - ambient) / (diffuse * peak))``, so that
    ``ambient + diffuse * s * E <= 1`` everywhere when ``exposure == 1``: the lit colour never
    exceeds the albedo, whatever the number of lights and the environment (equivalently the
    light intensities, environment included, sum to at most ``(1 - ambient) / diffuse`` where
    they all meet).  One light of intensity 1 with the default material (0.2, 0.8) is left as
    it is.  ``exposure > 1`` brightens on purpose (see ``tone_map``).
    """
    s = float(exposure)
    if normalize and diffuse > 0 and peak > 0 and ambient < 1:
        s *= min(1.0, (1.0 - ambient) / (diffuse * peak))
    return s


TONE_MAPS = ("none", "reinhard")


def tone_map_curve(x: np.ndarray, white: float, kind: str = "reinhard") -> np.ndarray:
    """Map linear light ``x >= 0`` (what multiplies the albedo) for display.

    ``"none"``: unchanged (the colour is clipped at 1 afterwards, as OpenGL does).  ``"reinhard"``: the extended Reinhard operator
    ``x (1 + x / w^2) / (1 + x)`` with white point ``w`` (``white``), which maps ``w`` to 1,
    keeps dark values nearly linear and compresses highlights instead of clipping them.
    """
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, None)
    if kind == "none":
        return x
    w = max(float(white), 1e-12)
    return np.clip(x * (1.0 + x / (w * w)) / (1.0 + x), 0.0, 1.0)
