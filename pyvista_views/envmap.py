"""Environment maps: distant illumination evaluated per normal.

Besides directional lights, an environment map is the only illumination compatible with a
mescher (paper Section 4.1): its radiance ``L(w)`` depends on the direction ``w`` alone, so shading
is invariant to the unknown absolute depth.  For a Lambertian (matte) surface only the irradiance

    E(n) = (1 / pi) * integral over the sphere of L(w) max(0, n . w) dw

matters.  We use the order-2 spherical-harmonic irradiance of Ramamoorthi and Hanrahan,
"An Efficient Representation for Irradiance Environment Maps" (SIGGRAPH 2001): 9 coefficients per
colour channel, exact for environments that are quadratic in ``w`` and within a few percent of the
true irradiance otherwise.  It is written here with numpy because neither VTK nor PyVista expose a
CPU irradiance evaluation (VTK's image-based lighting is a GPU PBR path with a specular lobe, which
is not a matte material).  The normalisation divides by pi, so a constant environment of radiance
``c`` gives ``E = c`` for every normal.

Lat-long (equirectangular) convention, camera frame (x right, y up, z toward the viewer): row 0 is
straight up (+y), the last row straight down; the middle column is the direction the camera looks
(-z), columns to its right turn toward +x, and the left and right edges are behind the camera (+z),
which is what faces turned toward the viewer mostly see.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from meschers_igl.errors import MescherError

# Ramamoorthi-Hanrahan convolution constants A_l for l = 0, 1, 2 (Lambert kernel, divided by pi).
_A_OVER_PI = np.array([1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25])


def sh9(directions: np.ndarray) -> np.ndarray:
    """Real spherical harmonics of order <= 2.

    Parameters
    ----------
    directions : (n, 3) float64
        Unit vectors.

    Returns
    -------
    (n, 9) float64
        ``Y00, Y1-1 (y), Y10 (z), Y11 (x), Y2-2 (xy), Y2-1 (yz), Y20 (3z^2-1), Y21 (xz),
        Y22 (x^2-y^2)`` with the usual orthonormal constants.
    """
    x, y, z = directions[:, 0], directions[:, 1], directions[:, 2]
    return np.stack(
        [
            np.full_like(x, 0.282095),
            0.488603 * y,
            0.488603 * z,
            0.488603 * x,
            1.092548 * x * y,
            1.092548 * y * z,
            0.315392 * (3.0 * z * z - 1.0),
            1.092548 * x * z,
            0.546274 * (x * x - y * y),
        ],
        axis=1,
    )


def latlong_directions(height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Pixel-centre directions and solid angles of a ``height x width`` lat-long image.

    Returns
    -------
    directions : (height, width, 3) float64
        Unit vectors (module docstring for the convention).
    solid_angle : (height, 1) float64
        ``sin(theta) dtheta dphi`` of each row (midpoint rule); sums to ~4 pi.
    """
    theta = (np.arange(height) + 0.5) * np.pi / height  # polar angle from +y
    phi = ((np.arange(width) + 0.5) / width - 0.5) * 2.0 * np.pi  # 0 at the middle column: -z
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    d = np.empty((height, width, 3))
    d[..., 0] = st * np.sin(phi)[None, :]
    d[..., 1] = np.broadcast_to(ct, (height, width))
    d[..., 2] = -st * np.cos(phi)[None, :]
    solid_angle = st * (np.pi / height) * (2.0 * np.pi / width)
    return d, solid_angle


class EnvironmentMap:
    """Irradiance of a distant environment, stored as 9 SH coefficients per channel.

    Parameters
    ----------
    coefficients : (9, 3) float64
        SH coefficients ``L_lm`` of the radiance (linear RGB), in :func:`sh9` order.
    name : str
        For messages and figure captions.
    """

    def __init__(self, coefficients: np.ndarray, name: str = "environment") -> None:
        c = np.asarray(coefficients, dtype=np.float64)
        if c.shape != (9, 3) or not np.all(np.isfinite(c)):
            raise MescherError(f"coefficients: expected a finite (9, 3) array, found {c.shape}")
        self.coefficients = c
        self.name = name

    @classmethod
    def from_latlong(cls, image: np.ndarray, name: str = "image") -> EnvironmentMap:
        """Project a lat-long radiance image (H, W, 3) or (H, W), linear units, onto SH."""
        img = np.asarray(image, dtype=np.float64)
        if img.ndim == 2:
            img = np.repeat(img[..., None], 3, axis=2)
        if img.ndim != 3 or img.shape[2] not in (3, 4) or min(img.shape[:2]) < 2:
            raise MescherError(
                f"env_map: expected a lat-long image of shape (H, W, 3), found {img.shape}"
            )
        img = img[..., :3]
        if not np.all(np.isfinite(img)):
            raise MescherError("env_map: expected finite radiance values, found NaN or inf")
        d, dw = latlong_directions(*img.shape[:2])
        basis = sh9(d.reshape(-1, 3)) * np.broadcast_to(dw, img.shape[:2]).reshape(-1, 1)
        return cls(basis.T @ img.reshape(-1, 3), name)

    @classmethod
    def from_function(
        cls, radiance: Callable[[np.ndarray], np.ndarray], name: str, resolution: int = 128
    ) -> EnvironmentMap:
        """Project ``radiance(directions (n, 3)) -> (n, 3)`` sampled on a lat-long grid."""
        d, _ = latlong_directions(resolution, 2 * resolution)
        values = np.asarray(radiance(d.reshape(-1, 3)), dtype=np.float64)
        return cls.from_latlong(values.reshape(resolution, 2 * resolution, -1), name)

    @classmethod
    def from_file(cls, path: str | Path) -> EnvironmentMap:
        """Load a lat-long image: 8-bit formats (PNG, JPEG, ...) are sRGB, ``.hdr`` is linear."""
        path = Path(path)
        if not path.is_file():
            raise MescherError(f"env_map: expected an existing image file, found {str(path)!r}")
        if path.suffix.lower() == ".hdr":
            import pyvista as pv  # VTK's Radiance reader: linear float radiance

            data = pv.read(str(path))
            nx, ny = data.dimensions[:2]
            arr = np.asarray(data.point_data.active_scalars, dtype=np.float64)
            img = arr.reshape(ny, nx, -1)[::-1]  # VTK images start at the bottom row
        else:
            from PIL import Image

            with Image.open(path) as im:
                srgb = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
            img = np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
        return cls.from_latlong(img, path.name)

    def irradiance(self, normals: np.ndarray) -> np.ndarray:
        """``E(n)`` (module docstring) for each unit normal.

        Parameters
        ----------
        normals : (n, 3) float64

        Returns
        -------
        (n, 3) float64
            Linear RGB irradiance divided by pi (constant environment ``c`` gives ``c``).
        """
        return sh9(normals) @ (self.coefficients * _A_OVER_PI[:, None])


def _studio(d: np.ndarray) -> np.ndarray:
    # Soft key light above-left in front of the object, a dimmer fill on the right, a neutral
    # ceiling-to-floor gradient: a portrait-studio look that reads shape well on matte surfaces.
    key = np.array([-0.5, 0.6, 0.62])
    fill = np.array([0.7, 0.1, 0.7])
    k = np.clip(d @ (key / np.linalg.norm(key)), 0.0, None) ** 8
    f = np.clip(d @ (fill / np.linalg.norm(fill)), 0.0, None) ** 4
    base = 0.25 + 0.15 * d[:, 1]
    value = base + 2.2 * k + 0.6 * f
    return value[:, None] * np.array([[1.0, 0.98, 0.95]])


def _sky(d: np.ndarray) -> np.ndarray:
    up = np.clip(d[:, 1], 0.0, None)[:, None]
    down = np.clip(-d[:, 1], 0.0, None)[:, None]
    horizon = np.array([[0.9, 0.9, 0.95]])
    zenith = np.array([[0.35, 0.55, 1.0]])
    ground = np.array([[0.35, 0.3, 0.25]])
    return horizon * (1 - up - down) + zenith * up + ground * down


def _uniform(d: np.ndarray) -> np.ndarray:
    return np.ones((d.shape[0], 3))


BUILTIN = {"studio": _studio, "sky": _sky, "uniform": _uniform}


def as_env_map(env_map: object) -> EnvironmentMap | None:
    """``None``, a built-in name (``"studio"``, ``"sky"``, ``"uniform"``), an image path, a
    lat-long array (H, W, 3) in linear radiance, or an :class:`EnvironmentMap`."""
    if env_map is None or isinstance(env_map, EnvironmentMap):
        return env_map
    if isinstance(env_map, str) and env_map.lower() in BUILTIN:
        return EnvironmentMap.from_function(BUILTIN[env_map.lower()], env_map.lower())
    if isinstance(env_map, (str, Path)):
        if not Path(env_map).is_file():
            raise MescherError(
                f"env_map: expected one of {sorted(BUILTIN)} or an image file, "
                f"found {str(env_map)!r}"
            )
        return EnvironmentMap.from_file(env_map)
    if isinstance(env_map, np.ndarray):
        return EnvironmentMap.from_latlong(env_map)
    raise MescherError(
        f"env_map: expected a name in {sorted(BUILTIN)}, an image path, an (H, W, 3) array or an "
        f"EnvironmentMap, found {type(env_map).__name__}"
    )
