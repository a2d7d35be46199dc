"""The application's tests render offscreen like the pyvista_views tests."""

from __future__ import annotations

import pyvista as pv

from pyvista_views.headless import configure_headless

configure_headless()
pv.OFF_SCREEN = True
