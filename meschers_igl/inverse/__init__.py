"""Inverse rendering of impossible objects (paper Section 4.5), on PyTorch.

Importing this package is cheap and never imports PyTorch; the names below load their module
(and PyTorch) on first access, and a missing PyTorch raises an ``ImportError`` that says how to
install it (``pip install 'meschers[inverse]'``).

- :mod:`~meschers_igl.inverse.rasterizer`: a SoftRas-style soft rasterizer (Liu et al. 2019)
  for flattened meschers with flat Lambertian shading and per-face depth offsets.
- :mod:`~meschers_igl.inverse.sobolev`: the unknowns ``xy``, ``zeta = d01 z + H c`` (every
  iterate is a mescher) and offsets, and the Sobolev preconditioner (Nicolet et al. 2021).
- :mod:`~meschers_igl.inverse.optimize`: the fit of a mescher to a target image.
- :mod:`~meschers_igl.inverse.targets`: test pictures and the torus initialization;
  :mod:`~meschers_igl.inverse.metrics`: PSNR, silhouette IoU and period figures of merit.
- :mod:`~meschers_igl.inverse.picture`: the start from the picture itself (segment, triangulate
  the silhouette with its holes, lift from shading); :mod:`~meschers_igl.inverse.models`: real
  3D box models of impossible figures whose z-buffered pictures are the acceptance targets;
  :mod:`~meschers_igl.inverse.drawing`: a black-on-white line drawing read as a shaded picture;
  :mod:`~meschers_igl.inverse.flatten`: an antialiased or JPEG picture made flat again;
  :mod:`~meschers_igl.inverse.cuts`: the mesh cut open along occlusions before the lift.
- the command line ``meschers inverse`` lives in the application, :mod:`meschers.inverse_cli`.
"""

from __future__ import annotations

import importlib
from typing import Any

from ._torch import INSTALL_HINT, require_torch

_LAZY = {
    "soft_rasterize": "rasterizer",
    "lambertian": "rasterizer",
    "face_normals_from_zeta": "rasterizer",
    "local_face_normals": "rasterizer",
    "corner_depths_from_zeta": "rasterizer",
    "pixel_centers": "rasterizer",
    "render_mescher": "rasterizer",
    "silhouette_edges": "rasterizer",
    "InverseOptions": "optimize",
    "InverseResult": "optimize",
    "fit_mescher": "optimize",
    "extract_order": "optimize",
    "MescherParametrization": "sobolev",
    "closed_harmonic_basis": "sobolev",
    "sobolev_matrix": "sobolev",
    "torus_mescher": "targets",
    "torus_for_target": "targets",
    "penrose_target": "targets",
    "penrose_soup": "targets",
    "target_mask": "targets",
    "silhouette_iou": "metrics",
    "image_psnr": "metrics",
    "max_period_ratio": "metrics",
    "boundary_loop_periods": "metrics",
    "figure_period": "metrics",
    "axis_aligned_share": "metrics",
    "picture_axes": "metrics",
    "mescher_from_picture": "picture",
    "fit_options": "picture",
    "picture_shading": "picture",
    "segment_picture": "picture",
    "frames_from_creases": "shading",
    "estimate_light": "shading",
    "estimate_exposure": "shading",
    "is_line_drawing": "drawing",
    "shade_drawing": "drawing",
    "narrowest_face_px": "drawing",
    "flatten_picture": "flatten",
    "figure_mask": "flatten",
    "is_flat": "flatten",
    "is_antialiased": "flatten",
    "penrose_tribar": "models",
    "impossible_cube": "models",
    "penrose_stairs": "models",
}

__all__ = ["INSTALL_HINT", "require_torch", *_LAZY]


def __getattr__(name: str) -> Any:
    # PEP 562: load the heavy module only when one of its names is asked for
    if name in _LAZY:
        module = importlib.import_module(f"{__name__}.{_LAZY[name]}")
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
