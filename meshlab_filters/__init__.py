"""meshlab_filters: artist models through PyMeshLab, and meschers back out to MeshLab.

* :func:`load_artist_model` reads any format PyMeshLab reads and cleans it
  (:mod:`meshlab_filters.cleanup` lists the steps), reporting what changed.
* :func:`cut_model_to_mescher` turns a cut 3D model of an impossible object into a mescher and
  its depth order; :func:`model_to_mescher` does it for any model (closed solids, separate
  blocks, soups) seen from a view, with a conversion report.
* :func:`export_cut_embedding`, :func:`export_bent_embedding` and :func:`export_render_mesh`
  write files MeshLab opens, with scalar fields as vertex colours.
* :func:`mescher_to_meshset` / :func:`meshset_to_mescher` convert without touching disk.

Every PyMeshLab filter used is listed in :data:`meshlab_filters._filters.FILTERS` and checked
to exist at import.
"""

from __future__ import annotations

from ._filters import FILTERS, check_filters
from .cleanup import CleanupReport, clean_mesh, clean_meshset
from .convert import (
    cut_model_to_mescher,
    export_bent_embedding,
    export_cut_embedding,
    export_render_mesh,
    model_to_mescher,
    scalars_to_colors,
)
from .load import load_artist_model, read_meshset
from .meshset import mescher_to_meshset, meshset_metadata, meshset_to_mescher

__all__ = [
    "FILTERS",
    "CleanupReport",
    "check_filters",
    "clean_mesh",
    "clean_meshset",
    "cut_model_to_mescher",
    "export_bent_embedding",
    "export_cut_embedding",
    "export_render_mesh",
    "load_artist_model",
    "mescher_to_meshset",
    "meshset_metadata",
    "meshset_to_mescher",
    "model_to_mescher",
    "read_meshset",
    "scalars_to_colors",
]
