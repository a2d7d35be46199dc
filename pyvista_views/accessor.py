"""``polydata.mescher``: meschers from and to PyVista meshes (a ``pyvista.accessors`` plugin).

Two kinds of :class:`pyvista.PolyData` meet a mescher:

- a **cut model** (paper Sections 3.4-3.5): an ordinary 3D triangle mesh, e.g. from
  ``pv.read("penrose.obj")``, whose cut boundaries coincide on screen when seen from ``view``;
  :meth:`MescherAccessor.to_mescher` glues it and orders its faces where they overlap on
  screen by the model's own depths (:func:`meschers_igl.obtain.cut_model_to_mescher`);
- a **flattened mescher**: what :meth:`MescherAccessor.to_polydata`,
  :func:`pyvista_views.to_polydata` (``embed=True``) and ``pv.read("x.mescher")`` give, which
  carries the mescher in its arrays (``cell_data["face_id"]``, ``point_data["vertex_id"]``,
  ``field_data["edges"]``, ``["zeta"]``, ``["depth_arcs"]``, ``["has_order"]``);
  :meth:`MescherAccessor.to_mescher` recovers that mescher and order exactly (bit for bit).

So ``poly.mescher.to_polydata(view=..., up=...)`` is the flattened view of a cut model and
``flat.mescher.to_mescher()`` its inverse.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyvista as pv

from meschers_igl import Mescher
from meschers_igl.errors import MescherError
from meschers_igl.obtain import cut_model_to_mescher
from meschers_igl.order import DepthOrder

from .polydata import (
    FIELD_ARCS,
    FIELD_EDGES,
    FIELD_HAS_ORDER,
    FIELD_ZETA,
    to_polydata,
)

NAME = "mescher"


class MescherAccessor:
    """The ``mescher`` namespace of a :class:`pyvista.PolyData`.

    Parameters
    ----------
    mesh : pyvista.PolyData
    """

    def __init__(self, mesh: pv.PolyData) -> None:
        self._mesh = mesh

    @property
    def is_flattened(self) -> bool:
        """Whether the mesh carries a mescher (``field_data`` ``"edges"`` and ``"zeta"``)."""
        fd = self._mesh.field_data
        return FIELD_ZETA in fd and FIELD_EDGES in fd

    def to_mescher(
        self,
        view: Any = (0.0, 0.0, 1.0),
        up: Any = (0.0, 1.0, 0.0),
        tol: float | None = None,
        merge: Any = None,
    ) -> tuple[Mescher, DepthOrder | None]:
        """The mescher of this mesh and its depth order.

        Parameters
        ----------
        view : (3,) array_like, default: (0, 0, 1)
            Cut model only: direction from the model toward the orthographic camera.
        up : (3,) array_like, default: (0, 1, 0)
            Cut model only: screen up.
        tol, merge
            Cut model only: gluing tolerance and explicit vertex pairs, as in
            :func:`meschers_igl.obtain.cut_model_to_mescher`.

        Returns
        -------
        m : meschers_igl.Mescher
            Cut model: face ``i`` is cell ``i`` (after triangulating non-triangular cells).
            Flattened mescher: exactly the stored one (``view``, ``up``, ``tol`` and ``merge`` do
            not apply and must be left at their defaults).
        order : DepthOrder or None
            Cut model: arc ``i -> j`` where face ``i`` is behind face ``j`` on screen.  Flattened
            mescher: the stored order, ``None`` when it was saved without one.
        """
        if self.is_flattened:
            defaults = (
                np.allclose(view, (0, 0, 1)) and np.allclose(up, (0, 1, 0)) and tol is None
            ) and merge is None
            if not defaults:
                raise MescherError(
                    "view: expected the defaults (view, up, tol, merge) for a mesh that already "
                    "carries a mescher (field data 'edges' and 'zeta'), found other values; "
                    "its screen positions are fixed"
                )
            return _recover(self._mesh)
        return _from_cut_model(self._mesh, view, up, tol, merge)

    def seen_from(
        self,
        view: Any = (0.0, 0.0, 1.0),
        up: Any = (0.0, 1.0, 0.0),
        perceive=None,
        **kwargs: Any,
    ):
        """Any 3D model (closed solids, separate blocks, soups) as seen from ``view``.

        :func:`meschers_igl.obtain.model_to_mescher` of the mesh's triangles: ``(m, order,
        report)`` with false edges glued crosswise and hidden gaps bridged (their depth gaps
        become periods); ``view="auto"``, ``perceive="manhattan"`` and the keywords
        (``hidden=``, ``view_start=``, ``tol=``) as there.
        """
        from meschers_igl.obtain import model_to_mescher

        mesh = _triangles(self._mesh)
        return model_to_mescher(
            mesh.points, mesh.regular_faces, view=view, up=up, perceive=perceive, **kwargs
        )

    def to_polydata(
        self,
        view: Any = (0.0, 0.0, 1.0),
        up: Any = (0.0, 1.0, 0.0),
        shading: str = "flat",
        scalars: object = None,
        layout: str = "indexed",
        tol: float | None = None,
        merge: Any = None,
    ) -> pv.PolyData:
        """The flattened, shaded mescher of this mesh, carrying the mescher and its order.

        ``to_polydata(m, order, shading, scalars, layout, embed=True)`` of :meth:`to_mescher`'s
        result: cells back to front (right under any renderer's default depth test), zeta's
        normals, ``field_data`` with ``edges``, ``zeta`` and the order's arcs, so that
        ``result.mescher.to_mescher()`` gives the same mescher and order back.
        """
        m, order = self.to_mescher(view, up, tol, merge)
        return to_polydata(m, order, shading=shading, scalars=scalars, layout=layout, embed=True)


def _triangles(mesh: pv.PolyData) -> pv.PolyData:
    if mesh.n_cells == 0 or mesh.n_points == 0:
        raise MescherError(
            f"mesh: expected a triangle mesh, found {mesh.n_points} points and {mesh.n_cells} cells"
        )
    if not mesh.is_all_triangles:
        mesh = mesh.triangulate()
        if not mesh.is_all_triangles:  # lines or vertices that triangulate cannot turn into faces
            raise MescherError("mesh: expected surface cells (polygons), found lines or vertices")
    return mesh


def _from_cut_model(mesh: pv.PolyData, view, up, tol, merge) -> tuple[Mescher, DepthOrder]:
    mesh = _triangles(mesh)
    # The one cut model -> (mescher, order) path (meshlab_filters and the CLI use it too).
    return cut_model_to_mescher(mesh.points, mesh.regular_faces, view, up, tol, merge)


def _recover(mesh: pv.PolyData) -> tuple[Mescher, DepthOrder | None]:
    """Invert :func:`~pyvista_views.polydata.to_polydata` (any layout, any drawing direction)."""
    fd, cd, pd = mesh.field_data, mesh.cell_data, mesh.point_data
    if "face_id" not in cd:
        raise MescherError(
            "mesh: expected cell_data['face_id'] beside the stored mescher (as to_polydata writes "
            f"it), found cell arrays {list(cd.keys())}"
        )
    if mesh.n_cells == 0 or not mesh.is_all_triangles:
        raise MescherError("mesh: expected the triangles of a flattened mescher, found other cells")
    cells = np.asarray(mesh.regular_faces, dtype=np.int64)
    face_id = np.asarray(cd["face_id"], dtype=np.int64)
    vertex_id = (
        np.asarray(pd["vertex_id"], dtype=np.int64)
        if "vertex_id" in pd
        else np.arange(mesh.n_points, dtype=np.int64)
    )
    edges = np.asarray(fd[FIELD_EDGES], dtype=np.int64).reshape(-1, 2)
    zeta = np.asarray(fd[FIELD_ZETA], dtype=np.float64).reshape(-1)
    n_faces = cells.shape[0]
    if np.sort(face_id).tolist() != list(range(n_faces)):
        raise MescherError(
            f"mesh: expected cell_data['face_id'] to be a permutation of the {n_faces} cells, "
            "found repeated or missing faces"
        )
    F = np.empty((n_faces, 3), dtype=np.int64)
    F[face_id] = vertex_id[cells]
    n_vertices = int(max(vertex_id.max(initial=-1), edges.max(initial=-1))) + 1
    xy = np.full((n_vertices, 2), np.nan)
    xy[vertex_id] = np.asarray(mesh.points, dtype=np.float64)[:, :2]
    m = Mescher(F, xy, edges, zeta)
    has_order = FIELD_HAS_ORDER in fd and bool(np.asarray(fd[FIELD_HAS_ORDER]).reshape(-1)[0])
    order = None
    if has_order:
        arcs = np.asarray(fd[FIELD_ARCS], dtype=np.int64) if FIELD_ARCS in fd else None
        order = DepthOrder(n_faces, np.zeros((0, 2), np.int64) if arcs is None else arcs, m=m)
    return m, order


pv.register_dataset_accessor(NAME, pv.PolyData)(MescherAccessor)
