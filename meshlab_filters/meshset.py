"""Meschers in a ``pymeshlab.MeshSet`` and back, without touching disk.

Layout (the documented metadata; PyMeshLab has no per-mesh or per-MeshSet attributes, so all of
it lives in meshes and their custom attributes, all float64, so every value is kept exactly):

``"mescher"`` -- the mescher, shown in MeshLab as its bent embedding:

* vertices ``(x, y, z)``: screen position and bent depth ``z`` (``m.bent_embedding()``);
* faces ``F`` (face i = mescher face i); edges ``m.edges`` (the mescher's own edge order and
  orientation) as the mesh's edge matrix;
* vertex attribute ``"mescher_exact_z"``: the potential ``z`` of zeta's exact part
  (``m.hodge().z``; ``d01 @ z`` is the exact part);
* vertex attribute ``"mescher_bent_z"``: the bent depth as written, to tell whether a filter
  moved the vertices;
* face point attribute ``"mescher_zeta"``: zeta around each face, column ``i`` the depth change
  along the face's edge opposite corner ``i`` (from corner ``i+1`` to corner ``i+2``), i.e.
  ``m.zeta[m.face_edges] * m.face_edge_signs``: zeta itself, harmonic part included.

``"mescher_order"`` (only with an order) -- a point cloud of the face centroids (bent
embedding), one vertex per face, with the order's arcs ``(behind, in front)`` as edges.

``"mescher_periods"`` (only when ``m.periods()`` is non-empty) -- one vertex per homology
generator, ``(period, 0, 0)``, also as vertex attribute ``"mescher_period"``.

Back from a MeshSet, xy comes from the vertices and zeta from ``"mescher_zeta"``; if a filter
moved the vertices, zeta gains the change of depth's differential (``zeta += d01 @ (z - z_bent)``),
which is closed, so the harmonic part and every period are kept.  A mesh without the attributes
(or whose faces no longer match them) becomes ``Mescher.from_mesh`` of its vertices, with a
:class:`~meschers_igl.MescherWarning` when the attributes were there but unusable.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import pymeshlab

from meschers_igl import Mescher, MescherError, MescherWarning
from meschers_igl.topology import edge_topology

MESCHER = "mescher"
ORDER = "mescher_order"
PERIODS = "mescher_periods"
EXACT_Z = "mescher_exact_z"
BENT_Z = "mescher_bent_z"
ZETA = "mescher_zeta"
PERIOD = "mescher_period"


def mescher_to_meshset(m: Mescher, order: Any = None) -> pymeshlab.MeshSet:
    """A new ``pymeshlab.MeshSet`` holding the mescher (and its depth order) exactly.

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional

    Returns
    -------
    pymeshlab.MeshSet
        Meshes ``"mescher"`` (current), ``"mescher_order"`` and ``"mescher_periods"`` as
        described in the module notes.
    """
    from meschers_igl.order import DepthOrder

    if not isinstance(m, Mescher):
        raise MescherError(f"m: expected a meschers_igl.Mescher, found {type(m).__name__}")
    if order is not None and not isinstance(order, DepthOrder):
        raise MescherError(f"order: expected a DepthOrder or None, found {type(order).__name__}")
    if order is not None and order.n_faces != m.n_faces:
        raise MescherError(
            f"order: expected a DepthOrder over {m.n_faces} faces, found {order.n_faces}"
        )
    F = np.asarray(m.F)
    Vb, _ = m.bent_embedding()
    Vb = np.ascontiguousarray(Vb, dtype=np.float64)
    mesh = pymeshlab.Mesh(Vb, F.astype(np.int32), np.asarray(m.edges).astype(np.int32))
    mesh.add_vertex_custom_scalar_attribute(np.asarray(m.hodge().z, dtype=np.float64), EXACT_Z)
    mesh.add_vertex_custom_scalar_attribute(Vb[:, 2].copy(), BENT_Z)
    H = np.asarray(m.zeta)[np.asarray(m.face_edges)] * np.asarray(m.face_edge_signs)
    mesh.add_face_custom_point_attribute(np.ascontiguousarray(H), ZETA)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(mesh, MESCHER)
    if order is not None:
        C = Vb[F].mean(axis=1)
        arcs = np.asarray(order.arcs, dtype=np.int32).reshape(-1, 2)
        ms.add_mesh(pymeshlab.Mesh(C, edge_matrix=arcs), ORDER, set_as_current=False)
    periods = np.asarray(m.periods(), dtype=np.float64).reshape(-1)
    if periods.size:
        P = np.zeros((periods.size, 3))
        P[:, 0] = periods
        pm = pymeshlab.Mesh(P, v_scalar_array=periods)
        pm.add_vertex_custom_scalar_attribute(periods.copy(), PERIOD)
        ms.add_mesh(pm, PERIODS, set_as_current=False)
    return ms


def _find(ms: pymeshlab.MeshSet, label: str) -> pymeshlab.Mesh | None:
    for mesh in ms:
        if mesh.label() == label:
            return mesh
    return None


def _vertex_attr(mesh: pymeshlab.Mesh, name: str) -> np.ndarray | None:
    try:
        return np.asarray(mesh.vertex_custom_scalar_attribute_array(name), dtype=np.float64)
    except pymeshlab.PyMeshLabException:
        return None


def _face_attr(mesh: pymeshlab.Mesh, name: str) -> np.ndarray | None:
    try:
        return np.asarray(mesh.face_custom_point_attribute_matrix(name), dtype=np.float64)
    except pymeshlab.PyMeshLabException:
        return None


def meshset_metadata(ms: pymeshlab.MeshSet) -> dict:
    """The metadata a MeshSet from :func:`mescher_to_meshset` carries.

    Returns
    -------
    dict
        ``"periods"``: (k,) float64 (empty when none were stored); ``"order_arcs"``: (a, 2)
        int64 or ``None``; ``"has_zeta"``: whether ``"mescher"`` carries ``"mescher_zeta"``.
    """
    _check_meshset(ms)
    mesh = _find(ms, MESCHER)
    pm = _find(ms, PERIODS)
    om = _find(ms, ORDER)
    periods = np.zeros(0) if pm is None else _vertex_attr(pm, PERIOD)
    if periods is None:
        periods = pm.vertex_matrix()[:, 0].copy()
    return {
        "periods": periods,
        "order_arcs": None if om is None else om.edge_matrix().astype(np.int64).reshape(-1, 2),
        "has_zeta": mesh is not None and _face_attr(mesh, ZETA) is not None,
    }


def _check_meshset(ms: Any) -> None:
    if not isinstance(ms, pymeshlab.MeshSet):
        raise MescherError(f"ms: expected a pymeshlab.MeshSet, found {type(ms).__name__}")
    if ms.mesh_number() == 0:
        raise MescherError("ms: expected a MeshSet with a mesh, found an empty MeshSet")


def _zeta_from_faces(
    F: np.ndarray, H: np.ndarray, edges: np.ndarray, n: int
) -> tuple[np.ndarray, float] | None:
    """Per-edge zeta from per-face half-edge values, and the largest disagreement.

    Edge ``e`` takes ``H[f, i] * s`` from every face side naming it (``s = +1`` where the face
    runs tail -> head); the values are averaged (equal when nothing changed, so the average is
    the value itself, bit for bit).  ``None`` when the faces use an edge missing from ``edges``.
    """
    tail = F[:, [1, 2, 0]].reshape(-1)
    head = F[:, [2, 0, 1]].reshape(-1)
    key = np.minimum(tail, head) * np.int64(n) + np.maximum(tail, head)
    ekey = np.minimum(edges[:, 0], edges[:, 1]) * np.int64(n) + np.maximum(edges[:, 0], edges[:, 1])
    srt = np.argsort(ekey, kind="stable")
    pos = np.searchsorted(ekey[srt], key)
    pos = np.minimum(pos, ekey.size - 1)
    if ekey.size == 0 or not np.array_equal(ekey[srt][pos], key):
        return None
    idx = srt[pos]
    vals = H.reshape(-1) * np.where(edges[idx, 0] == tail, 1.0, -1.0)
    ne = edges.shape[0]
    cnt = np.bincount(idx, minlength=ne)
    if np.any(cnt == 0):
        return None  # an edge no face uses
    first = np.empty(ne)
    first[idx[::-1]] = vals[::-1]  # the first face's value, kept exactly
    conflict = float(np.max(np.abs(vals - first[idx]), initial=0.0))
    return first, conflict


def meshset_to_mescher(ms: pymeshlab.MeshSet, rtol: float = 1e-9):
    """The mescher (and order) a MeshSet holds; the inverse of :func:`mescher_to_meshset`.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
        Uses the mesh labelled ``"mescher"`` (else the current mesh).  Filters may have run on it.
    rtol : float, default: 1e-9
        Two faces' values for one edge count as equal within ``rtol`` times the model's size.

    Returns
    -------
    m : Mescher
        Bit-equal to the original after an untouched round trip.  After filters that moved the
        vertices, zeta is updated by the depth change (periods kept); after filters that changed
        faces so the stored zeta no longer fits, ``Mescher.from_mesh`` of the vertices (the
        harmonic part is lost; a :class:`~meschers_igl.MescherWarning` says so).
    order : DepthOrder or None
        From ``"mescher_order"`` when its vertex count still equals the face count.

    Raises
    ------
    MescherError
        Not a MeshSet, no mesh, a mesh without faces.
    """
    from meschers_igl.order import DepthOrder

    _check_meshset(ms)
    mesh = _find(ms, MESCHER)
    if mesh is None:
        mesh = ms.current_mesh()
    V = np.ascontiguousarray(mesh.vertex_matrix(), dtype=np.float64)
    F = np.ascontiguousarray(mesh.face_matrix(), dtype=np.int64)
    if F.shape[0] == 0:
        raise MescherError(
            f"ms: expected a mesh with faces, found mesh {mesh.label()!r} with "
            f"{V.shape[0]} vertices and no faces"
        )
    m = _exact_mescher(mesh, V, F, rtol)
    if m is None:
        m = Mescher.from_mesh(V, F)
    order = None
    om = _find(ms, ORDER)
    if om is not None:
        if om.vertex_number() == m.n_faces:
            order = DepthOrder(m.n_faces, om.edge_matrix().astype(np.int64).reshape(-1, 2), m=m)
        else:
            warnings.warn(
                f"ms: mesh {ORDER!r} has {om.vertex_number()} vertices but the mescher has "
                f"{m.n_faces} faces (a filter changed the faces); the depth order is dropped",
                MescherWarning,
                stacklevel=2,
            )
    return m, order


def _exact_mescher(mesh: pymeshlab.Mesh, V: np.ndarray, F: np.ndarray, rtol: float):
    H = _face_attr(mesh, ZETA)
    if H is None:
        return None
    n = V.shape[0]
    scale = max(float(np.linalg.norm(V.max(axis=0) - V.min(axis=0))), 1e-300)
    E = np.asarray(mesh.edge_matrix(), dtype=np.int64).reshape(-1, 2)
    got = _zeta_from_faces(F, H, E, n) if E.size else None
    if got is None:  # edges missing or stale: the canonical edges of the faces
        E = edge_topology(F, n, check=False)[0]
        got = _zeta_from_faces(F, H, E, n)
    zeta, conflict = got
    if conflict > rtol * scale:
        warnings.warn(
            f"ms: the stored {ZETA!r} disagrees across edges by up to {conflict:.3g} (a filter "
            "changed the faces); rebuilding the mescher from the vertices, harmonic part lost",
            MescherWarning,
            stacklevel=3,
        )
        return None
    zb = _vertex_attr(mesh, BENT_Z)
    if zb is not None and not np.array_equal(zb, V[:, 2]):
        # A filter moved the vertices: add the change of depth's differential (closed, so the
        # harmonic part and the periods stay).
        dz = V[:, 2] - zb
        zeta = zeta + (dz[E[:, 1]] - dz[E[:, 0]])
    try:
        return Mescher(F, np.ascontiguousarray(V[:, :2]), E, zeta)
    except MescherError as exc:
        warnings.warn(
            f"ms: the stored {ZETA!r} does not give a valid mescher ({exc}); rebuilding from the "
            "vertices, harmonic part lost",
            MescherWarning,
            stacklevel=3,
        )
        return None
