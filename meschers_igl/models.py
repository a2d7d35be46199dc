"""Artist models seen from a view, as (mescher, depth order) pairs: the one door,
:mod:`meschers_igl.obtain.route`."""

from __future__ import annotations

from .obtain.choose import PERIOD_RTOL, ROUTES, drop_small_periods
from .obtain.route import cut_model_to_mescher, model_to_mescher

__all__ = [
    "PERIOD_RTOL",
    "ROUTES",
    "cut_model_to_mescher",
    "drop_small_periods",
    "model_to_mescher",
]
