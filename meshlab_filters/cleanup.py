"""Clean-up of artist meshes with PyMeshLab, and the report that says what changed.

The filters run in a fixed order on the current mesh of a ``pymeshlab.MeshSet``; each one's effect
is measured by comparing vertex and face counts before and after it (PyMeshLab's filters return
no counts of their own):

1. merge duplicate vertices -- **exact** 3D duplicates only by default (``merge_tol=0``);
2. remove unreferenced vertices;
3. remove duplicate faces (same three vertices, either orientation);
4. remove zero-area faces (exactly zero area, e.g. a quad with a repeated corner);
5. repair non-manifold edges (remove the fewest faces, or split their vertices);
6. split non-manifold vertices (repeated until none is left);
7. orient every connected component coherently, keeping the orientation most of its faces had.

Why merging must be exact for cut models of impossible objects: the two sides of a cut (the front
and back copies of one perceived vertex) coincide *on screen* but not in 3D; only
``meschers_igl.Mescher.from_cut_mesh`` may glue them, knowing the view.  Merging by a 3D
tolerance larger than the cut's depth gap would glue them here, in the wrong place; pass a
positive ``merge_tol`` only for float noise far below every depth gap of the model.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
import pymeshlab
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from meschers_igl import MescherError
from meschers_igl.topology import edge_topology

from ._filters import apply

#: Name of the temporary per-vertex attribute that carries input vertex indices through filters.
_INPUT_INDEX = "meschers_input_vertex"
#: Safety bound on repeated non-manifold vertex repair passes (one pass splits most fans).
_MAX_VERTEX_REPAIRS = 8


@dataclass
class CleanupReport:
    """What :func:`clean_meshset` (and :func:`~meshlab_filters.load_artist_model`) changed.

    All counts are exact differences of PyMeshLab's vertex and face counts before and after each
    filter.  ``polygons`` and ``polygons_triangulated`` are ``None`` when the input's polygons
    could not be recovered (PyMeshLab cannot walk the polygons of a non-manifold input).

    Attributes
    ----------
    source : str
        The file (or ``"<arrays>"`` / ``"<MeshSet>"``).
    vertices_in, faces_in : int
        Counts as loaded (faces are triangles: PyMeshLab triangulates polygons when it reads).
    polygons : int or None
        Faces in the input before triangulation.
    polygons_triangulated : int or None
        Input faces with more than three corners (each split into ``corners - 2`` triangles).
    duplicate_vertices_merged, unreferenced_vertices_removed, duplicate_faces_removed,
    zero_area_faces_removed, non_manifold_faces_removed, non_manifold_edges_split,
    non_manifold_vertices_split, faces_flipped : int
        What each step changed (``non_manifold_edges_split`` and
        ``non_manifold_vertices_split`` count vertices *added*).
    vertices_out, faces_out : int
        Counts of the cleaned mesh.
    components : int
        Edge-connected components of the cleaned mesh.
    orientable : bool
        Every interior edge is traversed in opposite directions by its two faces afterwards.
    merge_tol : float
        The 3D merge distance used (0: bit-identical positions only).
    vertex_map : (vertices_in,) int64 ndarray
        Cleaned vertex of each input vertex, ``-1`` where it was removed (unreferenced, or on a
        face that was removed).  A split non-manifold vertex maps to one of its copies.  Not part
        of :meth:`as_dict`.
    """

    source: str
    vertices_in: int
    faces_in: int
    polygons: int | None
    polygons_triangulated: int | None
    duplicate_vertices_merged: int = 0
    unreferenced_vertices_removed: int = 0
    duplicate_faces_removed: int = 0
    zero_area_faces_removed: int = 0
    non_manifold_faces_removed: int = 0
    non_manifold_edges_split: int = 0
    non_manifold_vertices_split: int = 0
    faces_flipped: int = 0
    vertices_out: int = 0
    faces_out: int = 0
    components: int = 0
    orientable: bool = True
    merge_tol: float = 0.0
    vertex_map: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64), repr=False)

    _CHANGES = (
        "polygons_triangulated",
        "duplicate_vertices_merged",
        "unreferenced_vertices_removed",
        "duplicate_faces_removed",
        "zero_area_faces_removed",
        "non_manifold_faces_removed",
        "non_manifold_edges_split",
        "non_manifold_vertices_split",
        "faces_flipped",
    )

    def changes(self) -> dict[str, int]:
        """The steps that changed something, with their counts (empty for a clean mesh)."""
        out = {}
        for name in self._CHANGES:
            v = getattr(self, name)
            if v:
                out[name] = int(v)
        return out

    @property
    def changed(self) -> bool:
        """Whether clean-up changed anything besides triangulating polygons."""
        return any(k != "polygons_triangulated" for k in self.changes())

    def as_dict(self) -> dict:
        """Plain ``dict`` of every count and flag (``vertex_map`` left out)."""
        d = asdict(self)
        d.pop("vertex_map")
        return d

    def __str__(self) -> str:
        poly = "?" if self.polygons is None else str(self.polygons)
        lines = [
            f"Clean-up of {self.source}",
            f"  in:  {self.vertices_in} vertices, {self.faces_in} triangles ({poly} polygons)",
        ]
        changes = self.changes()
        if not changes:
            lines.append("  nothing to change")
        for name, v in changes.items():
            lines.append(f"  {name.replace('_', ' ')}: {v}")
        lines.append(
            f"  out: {self.vertices_out} vertices, {self.faces_out} triangles, "
            f"{self.components} component(s), {'orientable' if self.orientable else 'NOT orientable'}"
        )
        return "\n".join(lines)


def _counts(ms: pymeshlab.MeshSet) -> tuple[int, int]:
    m = ms.current_mesh()
    return m.vertex_number(), m.face_number()


def _step(ms: pymeshlab.MeshSet, name: str, **params) -> tuple[int, int]:
    """Apply one filter; return (vertices removed, faces removed) (negative: added)."""
    nv, nf = _counts(ms)
    apply(ms, name, **params)
    nv2, nf2 = _counts(ms)
    return nv - nv2, nf - nf2


def _non_manifold_vertices(ms: pymeshlab.MeshSet) -> int:
    return int(apply(ms, "get_topological_measures").get("non_two_manifold_vertices", 0))


def _non_manifold_edges(ms: pymeshlab.MeshSet) -> int:
    return int(apply(ms, "get_topological_measures").get("non_two_manifold_edges", 0))


def count_polygons(ms: pymeshlab.MeshSet) -> tuple[int | None, int | None]:
    """(polygons, polygons with more than 3 corners) of the current mesh as loaded, or Nones.

    PyMeshLab keeps the polygons a file had as "faux" edges between the triangles it made;
    ``Mesh.polygonal_face_list`` walks them but fails (``std::bad_alloc``) on non-manifold edges,
    so it is only asked when there are none.
    """
    measures = apply(ms, "get_topological_measures")
    if measures.get("non_two_manifold_edges", 1) != 0:
        return None, None
    try:
        polys = ms.current_mesh().polygonal_face_list()
    except (MemoryError, pymeshlab.PyMeshLabException):
        return None, None
    sizes = np.fromiter((len(p) for p in polys), dtype=np.int64, count=len(polys))
    return int(sizes.size), int(np.count_nonzero(sizes > 3))


def check_current_mesh(ms: pymeshlab.MeshSet, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Validate the current mesh before any filter touches it; return its (V, F).

    PyMeshLab's OFF reader keeps out-of-range face indices, which later filters would follow
    into foreign memory; non-finite coordinates break every geometric filter.

    Raises
    ------
    MescherError
        No faces, non-finite coordinates or face indices out of range (naming ``source``).
    """
    m = ms.current_mesh()
    V = m.vertex_matrix()
    F = m.face_matrix().astype(np.int64)
    source = _label(source)
    if F.shape[0] == 0:
        raise MescherError(
            f"{source}: expected a surface mesh with faces, found {V.shape[0]} vertices and no "
            "faces (a point cloud, or every face referred to a missing vertex)"
        )
    if not np.all(np.isfinite(V)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(V), axis=1)))
        raise MescherError(
            f"{source}: expected finite vertex coordinates, found {bad} vertices with NaN or inf"
        )
    if F.min() < 0 or F.max() >= V.shape[0]:
        raise MescherError(
            f"{source}: expected face indices in [0, {V.shape[0]}), found indices from "
            f"{int(F.min())} to {int(F.max())}"
        )
    return V, F


def _label(source: str) -> str:
    """How messages name the input: a file as ``path '...'``, arrays or MeshSets as they are."""
    return source if source.startswith("<") else f"path '{source}'"


def _face_components(F: np.ndarray, n_vertices: int) -> tuple[int, np.ndarray]:
    """Edge-connected components of faces (faces sharing an edge), via the face-edge incidence."""
    edges, fe, _ = edge_topology(F, n_vertices, check=False)
    nf = F.shape[0]
    inc = sp.csr_matrix(
        (np.ones(fe.size), (np.repeat(np.arange(nf), 3), fe.reshape(-1))),
        shape=(nf, edges.shape[0]),
    )
    return connected_components(inc @ inc.T, directed=False)


def _same_orientation(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """(m,) bool: row ``B[f]`` is a cyclic rotation of row ``A[f]`` (same oriented triangle)."""
    return np.any([np.all(np.roll(A, k, axis=1) == B, axis=1) for k in range(3)], axis=0)


def _orient_like_majority(F_before: np.ndarray, F_after: np.ndarray, labels: np.ndarray):
    """Coherent orientation that keeps, per component, the orientation most faces had.

    MeshLab's coherent orientation keeps the seed face of each component, so one flipped input
    face chosen as the seed flips all the others; no PyMeshLab filter chooses by majority, so
    this is done here on arrays.  Faces keep their input corner order when their orientation is
    kept, and get corners 1 and 2 swapped when flipped.

    Returns
    -------
    F : (m, 3) int64
    flipped : (m,) bool
        Faces whose orientation differs from the input.
    """
    flipped = ~_same_orientation(F_before, F_after)
    n = int(labels.max()) + 1 if labels.size else 0
    n_flipped = np.bincount(labels, weights=flipped, minlength=n)
    n_total = np.bincount(labels, minlength=n)
    flipped ^= (2 * n_flipped > n_total)[labels]
    F = np.where(flipped[:, None], F_before[:, [0, 2, 1]], F_before)
    return F, flipped


def _is_coherent(F: np.ndarray, n_vertices: int) -> bool:
    """No directed half-edge appears twice (each edge used at most once per direction)."""
    key = F.reshape(-1) * np.int64(n_vertices) + np.roll(F, -1, axis=1).reshape(-1)
    key.sort()
    return not np.any(key[1:] == key[:-1])


def _replace_current_mesh(ms: pymeshlab.MeshSet, V: np.ndarray, F: np.ndarray) -> None:
    old = ms.current_mesh_id()
    label = ms.current_mesh().label()
    ms.add_mesh(pymeshlab.Mesh(V, F), label, set_as_current=False)
    new = max(m.id() for m in ms)
    ms.set_current_mesh(old)
    ms.delete_current_mesh()
    ms.set_current_mesh(new)


def clean_meshset(
    ms: pymeshlab.MeshSet,
    merge_tol: float = 0.0,
    source: str = "<MeshSet>",
    non_manifold_edges: str = "remove",
) -> tuple[np.ndarray, np.ndarray, CleanupReport]:
    """Clean the current mesh of ``ms`` in place and report what changed.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
        Its current mesh is cleaned (replaced by the cleaned mesh; custom attributes are kept by
        the filters but not by the final re-orientation when it has to undo MeshLab's choice).
    merge_tol : float, default: 0.0
        3D distance below which vertices merge; 0 merges bit-identical positions only (the only
        safe choice for cut models, see the module notes).
    source : str
        Name used in messages and in the report.
    non_manifold_edges : {"remove", "split"}, default: "remove"
        Repair an edge shared by more than two faces by removing the fewest faces (a manifold
        surface, some of the input lost), or by splitting its vertices so that each face keeps
        its own copy (nothing lost; the copies coincide in 3D: blocks that touch along an edge
        stay separate blocks).

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64
    report : CleanupReport
    """
    if non_manifold_edges not in ("remove", "split"):
        raise MescherError(
            f"non_manifold_edges: expected 'remove' or 'split', found {non_manifold_edges!r}"
        )
    merge_tol = float(merge_tol)
    if not np.isfinite(merge_tol) or merge_tol < 0:
        raise MescherError(f"merge_tol: expected a finite distance >= 0, found {merge_tol}")
    V0, F0 = check_current_mesh(ms, source)
    polygons, triangulated = count_polygons(ms)
    rep = CleanupReport(
        source=source,
        vertices_in=V0.shape[0],
        faces_in=F0.shape[0],
        polygons=polygons,
        polygons_triangulated=triangulated,
        merge_tol=merge_tol,
    )
    ms.current_mesh().add_vertex_custom_scalar_attribute(
        np.arange(V0.shape[0], dtype=np.float64), _INPUT_INDEX
    )

    if merge_tol > 0:
        dv, _ = _step(ms, "meshing_merge_close_vertices", threshold=pymeshlab.PureValue(merge_tol))
    else:
        dv, _ = _step(ms, "meshing_remove_duplicate_vertices")
    rep.duplicate_vertices_merged = dv
    rep.unreferenced_vertices_removed, _ = _step(ms, "meshing_remove_unreferenced_vertices")
    _, rep.duplicate_faces_removed = _step(ms, "meshing_remove_duplicate_faces")
    _, rep.zero_area_faces_removed = _step(ms, "meshing_remove_null_faces")
    if non_manifold_edges == "remove":
        _, rep.non_manifold_faces_removed = _step(ms, "meshing_repair_non_manifold_edges")
    elif _non_manifold_edges(ms):
        # the filter gives every face of the mesh fresh vertices; the unused ones go at once,
        # so the count is the copies added
        dv, _ = _step(ms, "meshing_repair_non_manifold_edges", method="Split Vertices")
        du, _ = _step(ms, "meshing_remove_unreferenced_vertices")
        rep.non_manifold_edges_split = -(dv + du)
    split = 0
    for _ in range(_MAX_VERTEX_REPAIRS):
        if _non_manifold_vertices(ms) == 0:
            break
        dv, _ = _step(ms, "meshing_repair_non_manifold_vertices")
        if dv == 0:
            break
        split -= dv
    rep.non_manifold_vertices_split = split
    # Faces removed by the repairs can leave vertices unused.
    dv, _ = _step(ms, "meshing_remove_unreferenced_vertices")
    rep.unreferenced_vertices_removed += dv
    if ms.current_mesh().face_number() == 0:
        raise MescherError(f"{_label(source)}: expected faces after clean-up, found none left")

    mesh = ms.current_mesh()
    F_before = mesh.face_matrix().astype(np.int64)
    apply(ms, "meshing_re_orient_faces_coherently")
    mesh = ms.current_mesh()
    V = np.ascontiguousarray(mesh.vertex_matrix(), dtype=np.float64)
    F_after = mesh.face_matrix().astype(np.int64)
    orig = np.rint(mesh.vertex_custom_scalar_attribute_array(_INPUT_INDEX)).astype(np.int64)
    n_comp, labels = _face_components(F_after, V.shape[0])
    F, flipped = _orient_like_majority(F_before, F_after, labels)
    rep.faces_flipped = int(np.count_nonzero(flipped))
    if not np.array_equal(F, F_after):
        _replace_current_mesh(ms, V, F)
    rep.components = int(n_comp)
    rep.orientable = _is_coherent(F, V.shape[0])
    rep.vertices_out, rep.faces_out = V.shape[0], F.shape[0]
    rep.vertex_map = _vertex_map(V0, F0, orig, V, merge_tol)
    return V, np.ascontiguousarray(F), rep


def _vertex_map(
    V0: np.ndarray, F0: np.ndarray, orig: np.ndarray, V: np.ndarray, merge_tol: float
) -> np.ndarray:
    """Cleaned vertex of each input vertex (-1: removed), given each survivor's input index.

    A vertex merged into another is found by position: bit-equal (``merge_tol == 0``) or the
    nearest cleaned vertex within ``merge_tol``.
    """
    vmap = np.full(V0.shape[0], -1, dtype=np.int64)
    vmap[orig[::-1]] = np.arange(V.shape[0])[::-1]  # a split vertex maps to its first copy
    used = np.zeros(V0.shape[0], dtype=bool)
    used[F0.reshape(-1)] = True
    todo = np.flatnonzero(used & (vmap < 0))
    if todo.size == 0:
        return vmap
    if merge_tol == 0:
        _, group = np.unique(V0, axis=0, return_inverse=True)
        group = group.reshape(-1)
        best = np.full(int(group.max()) + 1, -1, dtype=np.int64)
        np.maximum.at(best, group, vmap)
        vmap[todo] = best[group[todo]]
    else:
        from scipy.spatial import cKDTree

        dist, idx = cKDTree(V).query(V0[todo], distance_upper_bound=merge_tol * (1 + 1e-9))
        vmap[todo] = np.where(np.isfinite(dist), idx, -1)
    return vmap


def clean_mesh(
    V: np.ndarray, F: np.ndarray, merge_tol: float = 0.0, non_manifold_edges: str = "remove"
) -> tuple[np.ndarray, np.ndarray, CleanupReport]:
    """:func:`clean_meshset` on arrays: ``(V (n,3) float64, F (m,3) int64, report)``."""
    from meschers_igl.validate import as_faces, as_points

    V = as_points(V, "V", 3)
    F = as_faces(F, "F", V.shape[0])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F), "artist_model")
    return clean_meshset(
        ms, merge_tol=merge_tol, source="<arrays>", non_manifold_edges=non_manifold_edges
    )
