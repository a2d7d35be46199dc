"""Deprecated alias of :mod:`pyvista_views.headless` (kept until every caller has moved)."""

from .headless import configure_headless, gl_available, has_display, is_offscreen, new_plotter

__all__ = ["configure_headless", "gl_available", "has_display", "is_offscreen", "new_plotter"]
