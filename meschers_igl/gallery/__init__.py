"""A gallery of classic impossible figures, built procedurally (paper Sections 3.5 and 5).

Each model is a *cut* 3D model (``V``, ``F``) with its view; the mescher (glued with
:meth:`Mescher.from_cut_mesh`) and its :class:`DepthOrder` (from the cut model's depths) are
built on first use.

>>> from meschers_igl.gallery import list_models, get_model
>>> list_models()  # doctest: +NORMALIZE_WHITESPACE
['impossibagel', 'impossible_cube', 'penrose_stairs', 'penrose_triangle',
 'reutersvard_triangle', 'window']
>>> g = get_model("penrose_triangle", bar_length=4.0, bar_width=1.0, resolution=4)
>>> round(float(abs(g.mescher.periods()).max()), 6)  # sqrt(3) * bar_length
6.928203
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import MescherError
from ..operators import view_frame
from . import bagel, frames, penrose
from .cutmodel import CutModel


@dataclass
class GalleryModel:
    """A cut model of an impossible figure, its view, and (lazily) its mescher and order.

    Attributes
    ----------
    name : str
    V : (#V, 3) float64
        The cut model (world frame).
    F : (#F, 3) int64
        Its outward-oriented triangles; face ``i`` of the mescher is face ``i`` here.
    view, up : (3,) tuple
        Direction toward the orthographic camera, and screen up.
    expected_period : float
        Depth gained once around the figure's loop (the cut's depth gap), 0 when the figure is
        impossible only through its depth order.
    description : str
    builder : callable, optional
        Builds ``(mescher, vmap)`` when the mescher is not the glued cut model.
    front_back : ((k,) int, (l,) int), optional
        Faces put in front of other faces after the order from the cut model's depths (the
        order no 3D model has, for figures impossible only through their order).
    """

    name: str
    V: np.ndarray
    F: np.ndarray
    view: tuple
    up: tuple
    expected_period: float
    description: str
    builder: Callable[[], tuple[Any, np.ndarray]] | None = field(default=None, repr=False)
    front_back: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)

    @cached_property
    def _built(self) -> tuple[Any, np.ndarray]:
        if self.builder is not None:
            return self.builder()
        from ..mescher import Mescher

        return Mescher.from_cut_mesh(self.V, self.F, view=self.view, up=self.up, return_map=True)

    @property
    def mescher(self):
        """The glued :class:`~meschers_igl.Mescher` (built on first use)."""
        return self._built[0]

    @property
    def vmap(self) -> np.ndarray:
        """(#V,) mescher vertex of each cut-model vertex."""
        return self._built[1]

    @property
    def corner_depths(self) -> np.ndarray:
        """(#F, 3) camera-space depth of each face corner of the cut model (the ``Zc`` of
        :meth:`DepthOrder.from_embedding`)."""
        return (self.V @ view_frame(self.view, self.up)[2])[self.F]

    @cached_property
    def order(self):
        """:class:`~meschers_igl.DepthOrder` of the mescher's faces from the cut model."""
        from ..order import DepthOrder

        order = DepthOrder.from_embedding(self.mescher, self.corner_depths)
        if self.front_back is not None:  # an order no 3D model has (impossible through order)
            order.put_in_front(*self.front_back, m=self.mescher)
        return order


_MODELS: dict[str, tuple[Callable, str]] = {
    "penrose_triangle": (
        penrose.penrose_triangle,
        "Penrose triangle: three square bars along x, y, z seen along (1, 1, 1); "
        "period sqrt(3) x bar length.",
    ),
    "penrose_stairs": (
        penrose.penrose_stairs,
        "Penrose stairs: a ribbon of steps that climbs forever around a square; one period.",
    ),
    "impossible_cube": (
        frames.impossible_cube,
        "Escher's impossible cube (Belvedere): a back bar passes in front of a front bar; "
        "straight bars, no period, impossible through the depth order; genus 5.",
    ),
    "reutersvard_triangle": (
        penrose.reutersvard_triangle,
        "Reutersvard's triangle of cubes: separate cubes on the Penrose path; no period, "
        "impossible through the depth order.",
    ),
    "window": (
        frames.window,
        "Window: a frame whose transom passes in front of one mullion and behind the other; "
        "a real 3D object (no period), impossible only through its depth order.",
    ),
    "impossibagel": (
        bagel.impossibagel,
        "Impossibagel: a torus given a period around its hole with Mescher.with_periods; seen at "
        "a grazing angle, its back passes in front of its front at the right end of the hole.",
    ),
}


def list_models() -> list[str]:
    """Names of the gallery's models, sorted."""
    return sorted(_MODELS)


def get_model(name: str, **params: Any) -> GalleryModel:
    """Build a gallery model.

    Parameters
    ----------
    name : str
        One of :func:`list_models`.
    **params
        Sizes and resolution of that model (see the builder in :mod:`.penrose`, :mod:`.frames`,
        :mod:`.bagel`; e.g. ``bar_length``, ``bar_width``, ``resolution``).

    Returns
    -------
    GalleryModel
    """
    if name not in _MODELS:
        raise MescherError(f"name: expected one of {', '.join(list_models())}, found {name!r}")
    fn, description = _MODELS[name]
    try:
        out = fn(**params)
    except TypeError as exc:  # unknown keyword: name the model and its parameters
        import inspect

        allowed = ", ".join(inspect.signature(fn).parameters)
        raise MescherError(
            f"params: expected parameters of {name!r} ({allowed}), found {sorted(params)} ({exc})"
        ) from None
    if not isinstance(out, CutModel):
        raise MescherError(
            f"name: the builder of {name!r} returned {type(out).__name__}, not a CutModel"
        )
    return GalleryModel(
        name=name,
        V=np.ascontiguousarray(out.V, dtype=np.float64),
        F=np.ascontiguousarray(out.F, dtype=np.int64),
        view=tuple(float(x) for x in out.view),
        up=tuple(float(x) for x in out.up),
        expected_period=float(out.period),
        description=description,
        builder=out.build,
        front_back=out.front_back,
    )


__all__ = ["CutModel", "GalleryModel", "get_model", "list_models"]
