"""Every PyMeshLab filter this package uses, named in one place and checked at import.

PyMeshLab renames filters between releases (``pymeshlab.replace_pymeshlab_filter_names`` exists
for that reason), so a name that the installed version lacks must fail loudly at import with the
name, not deep inside a clean-up run.  :func:`apply` is the only way the package calls a filter:
it turns PyMeshLab's exceptions into :class:`meschers_igl.MescherError`.
"""

from __future__ import annotations

from typing import Any

import pymeshlab

from meschers_igl import MescherError

#: The filters ``meshlab_filters`` calls, by PyMeshLab (2022.2+) name, with what each does here.
FILTERS: dict[str, str] = {
    "meshing_remove_duplicate_vertices": "merge vertices with bit-identical 3D positions",
    "meshing_merge_close_vertices": "merge vertices closer than an absolute 3D distance",
    "meshing_remove_unreferenced_vertices": "drop vertices no face uses",
    "meshing_remove_duplicate_faces": "drop faces with the same three vertices as another",
    "meshing_remove_null_faces": "drop faces of zero area",
    "meshing_repair_non_manifold_edges": "drop the fewest faces that make edges manifold",
    "meshing_repair_non_manifold_vertices": "split vertices whose faces form several fans",
    "meshing_re_orient_faces_coherently": "orient each connected component coherently",
    "compute_color_from_scalar_per_vertex": "map per-vertex quality to colour (a colormap)",
    "compute_normal_by_function_per_vertex": "set vertex normals (Mesh() recomputes given ones)",
    "get_topological_measures": "count non-manifold edges and vertices",
}


def missing_filters(names=None) -> list[str]:
    """Names in ``names`` (default :data:`FILTERS`) that the installed PyMeshLab lacks.

    Parameters
    ----------
    names : iterable of str, optional

    Returns
    -------
    list of str
        Sorted missing names (empty when all exist).
    """
    available = set(pymeshlab.filter_list())
    return sorted(set(FILTERS if names is None else names) - available)


def check_filters(names=None) -> None:
    """Raise :class:`MescherError` naming each filter the installed PyMeshLab lacks."""
    missing = missing_filters(names)
    if missing:
        raise MescherError(
            f"pymeshlab: expected the filters {missing} (used by meshlab_filters), found them "
            f"missing in the installed PyMeshLab {_version()}; install a PyMeshLab release that "
            "has them (pip install -U pymeshlab)"
        )


def _version() -> str:
    try:
        from importlib.metadata import version

        return version("pymeshlab")
    except Exception:  # noqa: BLE001 - only decorates an error message
        return "(unknown version)"


def apply(ms: pymeshlab.MeshSet, name: str, **params: Any) -> dict:
    """Apply the filter ``name`` (one of :data:`FILTERS`) to the current mesh of ``ms``.

    Returns
    -------
    dict
        What the filter returned (PyMeshLab returns a dict of measures, or nothing).

    Raises
    ------
    MescherError
        ``name`` is not listed in :data:`FILTERS`, or PyMeshLab failed (its message included).
    """
    if name not in FILTERS:
        raise MescherError(f"name: expected a filter listed in FILTERS, found {name!r}")
    try:
        out = ms.apply_filter(name, **params)
    except pymeshlab.PyMeshLabException as exc:
        msg = " ".join(str(exc).split())
        raise MescherError(f"PyMeshLab filter {name!r} failed: {msg}") from None
    return out if isinstance(out, dict) else {}


check_filters()
