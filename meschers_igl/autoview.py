"""The view from which a model's junctions line up: :mod:`meschers_igl.obtain.view`."""

from __future__ import annotations

from .obtain.view import MAX_EDGE_ON, MAX_VOTERS, VOTE_ANGLE, find_view, up_for_view

__all__ = ["MAX_EDGE_ON", "MAX_VOTERS", "VOTE_ANGLE", "find_view", "up_for_view"]
