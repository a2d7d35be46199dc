"""Reading artist models (OBJ, PLY, STL, OFF and every other format PyMeshLab reads).

Files are checked before PyMeshLab sees them (exists, is a file, is not empty) and the loaded mesh
is checked before any filter runs (faces present, finite coordinates, face indices in range:
PyMeshLab's OFF reader keeps out-of-range indices).  Every failure is a
:class:`meschers_igl.MescherError` naming the path and what was found.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pymeshlab

from meschers_igl import MescherError

from .cleanup import CleanupReport, clean_meshset


def _as_path(path) -> Path:
    if not isinstance(path, (str, os.PathLike)):
        raise MescherError(f"path: expected a file path (str or os.PathLike), found {type(path)}")
    return Path(path)


def read_meshset(path: str | os.PathLike) -> pymeshlab.MeshSet:
    """Load a mesh file into a new ``pymeshlab.MeshSet`` (no clean-up), after sanity checks.

    Parameters
    ----------
    path : str or os.PathLike
        Any format PyMeshLab reads (by extension: .obj, .ply, .stl, .off, ...).

    Returns
    -------
    pymeshlab.MeshSet
        One mesh, current, labelled with the file's stem.  Polygons are already triangulated.

    Raises
    ------
    MescherError
        Missing file, a directory, an empty file, or a file PyMeshLab cannot read (its reason
        included).
    """
    p = _as_path(path)
    if not p.exists():
        raise MescherError(f"path: expected an existing mesh file, found nothing at '{p}'")
    if not p.is_file():
        raise MescherError(f"path: expected a mesh file, found a directory or special file '{p}'")
    if p.stat().st_size == 0:
        raise MescherError(f"path: expected a mesh file with content, found an empty file '{p}'")
    ms = pymeshlab.MeshSet()
    try:
        ms.load_new_mesh(str(p))
    except pymeshlab.PyMeshLabException as exc:
        reason = " ".join(str(exc).split())
        raise MescherError(
            f"path: expected a mesh file PyMeshLab can read, found an unreadable or corrupt "
            f"file '{p}' ({reason})"
        ) from None
    if ms.mesh_number() != 1:  # e.g. a project file with several layers
        raise MescherError(
            f"path: expected a file holding one mesh, found {ms.mesh_number()} meshes in '{p}'"
        )
    return ms


def load_artist_model(
    path: str | os.PathLike, merge_tol: float = 0.0
) -> tuple[np.ndarray, np.ndarray, CleanupReport]:
    """Load an artist's mesh file and clean it for :class:`meschers_igl.Mescher`.

    Polygons are triangulated; exact duplicate and unreferenced vertices, duplicate and
    zero-area faces are removed; non-manifold edges are repaired (fewest faces removed) and
    non-manifold vertices split; each connected component is oriented coherently, keeping the
    orientation most of its faces had.  See :mod:`meshlab_filters.cleanup`.

    Parameters
    ----------
    path : str or os.PathLike
        OBJ, PLY, STL, OFF or any other format PyMeshLab reads.
    merge_tol : float, default: 0.0
        3D distance below which vertices merge.  The default merges bit-identical positions only:
        a *cut* model of an impossible object has front/back vertex pairs that coincide on screen
        but not in 3D, and they must survive to be glued by
        :meth:`meschers_igl.Mescher.from_cut_mesh`.  A positive value must stay far below every
        depth gap of the model.

    Returns
    -------
    V : (n, 3) float64
        Vertex positions (as in the file, in the file's frame).
    F : (m, 3) int64
        Coherently oriented triangles.
    report : CleanupReport
        What was changed and how many; ``print(report)`` for a summary, ``report.as_dict()``
        for the counts, ``report.vertex_map`` for input -> cleaned vertex indices.

    Raises
    ------
    MescherError
        Missing, empty, unreadable or corrupt file; no faces; non-finite coordinates; face
        indices out of range; nothing left after clean-up.

    Examples
    --------
    >>> V, F, report = load_artist_model("penrose_triangle.obj")  # doctest: +SKIP
    >>> print(report)  # doctest: +SKIP
    """
    p = _as_path(path)
    ms = read_meshset(p)
    return clean_meshset(ms, merge_tol=merge_tol, source=str(p))
