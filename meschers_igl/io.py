"""Lossless files for meschers: ``.ply`` (MeshLab opens it as a flat mesh) and ``.npz``.

PLY layout (binary little-endian, so doubles round-trip bit-exactly)::

    element vertex  #V   property double x, y, z      (z = 0: the flattened mesh)
    element face    #F   property list uchar int vertex_indices
    element edge    #E   property int vertex1, vertex2; property double zeta
    element depth_arc #A property int back, front      (the depth order, optional)
    element homology_edge #H property int loop, edge; property char sign
                                                       (the loops periods() are measured on)

Any PLY reader (MeshLab, PyMeshLab, PyVista) opens the file as a flat triangle mesh and skips
the elements it does not know.  ``.npz`` stores the same arrays under their names.
"""

from __future__ import annotations

import os
import zipfile
from pathlib import Path

import numpy as np

from .errors import MescherError
from .mescher import Mescher
from .validate import as_choice

FORMAT_VERSION = 1
#: File formats :func:`save` and :func:`load` know.
FORMATS = ("ply", "npz")


def _format(path: Path, format: str | None, verb: str) -> str:
    """The explicit ``format``, or the one the suffix names."""
    if format is not None:
        return as_choice(format, "format", FORMATS)
    ext = path.suffix.lower().lstrip(".")
    if ext not in FORMATS:
        raise MescherError(
            f"path: expected a .ply or .npz file name (or format='ply'/'npz' to {verb} "
            f"any name), found {path.name!r}"
        )
    return ext


def _order_arrays(order, m: Mescher) -> np.ndarray:
    if order is None:
        return np.zeros((0, 2), dtype=np.int64)
    arcs = np.asarray(order.arcs, dtype=np.int64).reshape(-1, 2)
    if order.n_faces != m.n_faces:
        raise MescherError(
            f"order: expected a depth order over the mescher's {m.n_faces} faces, "
            f"found one over {order.n_faces}"
        )
    return arcs


def _generator_rows(m: Mescher) -> np.ndarray:
    """(#H, 3) int64 rows (loop, edge, sign) of the mescher's homology loops: stored so that a
    loaded mescher reports ``periods()`` in the same basis (a subdivided mescher's loops are
    its parent's, not the ones a fresh tree-cotree would pick)."""
    loops = m.homology_generators()
    if not loops:
        return np.zeros((0, 3), dtype=np.int64)
    rows = [
        np.stack([np.full(e.size, i), e, s.astype(np.int64)], 1) for i, (e, s) in enumerate(loops)
    ]
    return np.concatenate(rows).astype(np.int64)


def _loops_from_rows(rows: np.ndarray) -> list:
    rows = np.asarray(rows, dtype=np.int64).reshape(-1, 3)
    if rows.size == 0:
        return []
    if rows[:, 0].min() < 0 or np.any(np.diff(rows[:, 0]) < 0):
        raise MescherError("homology: expected rows sorted by loop, found a corrupt table")
    cut = np.searchsorted(rows[:, 0], np.arange(1, int(rows[:, 0].max()) + 1))
    return [(r[:, 1], r[:, 2].astype(np.float64)) for r in np.split(rows, cut)]


def save(m: Mescher, path: str | os.PathLike, order=None, *, format: str | None = None) -> Path:
    """Write ``m`` (and its depth order) to ``.ply`` or ``.npz``; returns the path.

    Parameters
    ----------
    m : Mescher
    path : str or PathLike
        Written as given (``np.savez`` adds no ``.npz`` suffix here).
    order : DepthOrder, optional
        Stored alongside; ``load(path, return_order=True)`` returns it.
    format : {"ply", "npz"}, optional
        Default: from the suffix of ``path``; give it to write any file name (``x.mescher``).
    """
    if not isinstance(m, Mescher):
        raise MescherError(f"m: expected a Mescher, found {type(m).__name__}")
    path = Path(path)
    fmt = _format(path, format, "write")
    arcs = _order_arrays(order, m)
    gens = _generator_rows(m)
    if fmt == "npz":
        with open(path, "wb") as fh:  # a file object: numpy adds no suffix to the name
            np.savez(
                fh,
                version=np.int64(FORMAT_VERSION),
                F=m.F,
                xy=m.xy,
                edges=m.edges,
                zeta=m.zeta,
                order_arcs=arcs,
                has_order=np.bool_(order is not None),
                homology=gens,
            )
    else:
        _write_ply(path, m, arcs, order is not None, gens)
    return path


def load(path: str | os.PathLike, *, format: str | None = None, return_order: bool = False):
    """Read a mescher written by :func:`save`.

    Parameters
    ----------
    path : str or PathLike
    format : {"ply", "npz"}, optional
        Default: from the suffix of ``path``; give it to read any file name.
    return_order : bool, default: False
        Return ``(m, order)``, ``order`` a :class:`~meschers_igl.order.DepthOrder` or ``None``
        when the file holds none.

    Returns
    -------
    Mescher, or always the pair ``(Mescher, DepthOrder | None)`` with ``return_order=True``:
    the shape of the result never depends on the file's content.

    Raises
    ------
    MescherError
        Missing, corrupt or truncated files, or a stored mescher that is invalid.
    """
    if not isinstance(return_order, (bool, np.bool_)):
        raise MescherError(f"return_order: expected True or False, found {return_order!r}")
    path = Path(path)
    if not path.is_file():
        raise MescherError(f"path: expected an existing file, found nothing at {str(path)!r}")
    fmt = _format(path, format, "read")
    if fmt == "npz":
        F, xy, edges, zeta, arcs, has_order, gens = _read_npz(path)
    else:
        F, xy, edges, zeta, arcs, has_order, gens = _read_ply(path)
    try:
        m = Mescher(F, xy, edges, zeta)
        if gens is not None:  # the loops periods() were measured on when saved
            m = m.with_generators(_loops_from_rows(gens))
    except MescherError as exc:
        raise MescherError(f"{path.name}: the stored mescher is invalid: {exc}") from exc
    if not return_order:
        return m
    order = None
    if has_order:
        from .order import DepthOrder

        order = DepthOrder(m.n_faces, arcs, m=m)
    return m, order


def _read_npz(path: Path):
    try:
        with np.load(path, allow_pickle=False) as z:
            F, xy, edges, zeta = z["F"], z["xy"], z["edges"], z["zeta"]
            arcs = z["order_arcs"] if "order_arcs" in z else np.zeros((0, 2), np.int64)
            has_order = bool(z["has_order"]) if "has_order" in z else False
            gens = z["homology"] if "homology" in z else None
    except (zipfile.BadZipFile, OSError, ValueError, KeyError, EOFError) as exc:
        raise MescherError(
            f"{path.name}: expected a mescher .npz (F, xy, edges, zeta), found a corrupt or "
            f"incomplete file ({type(exc).__name__}: {exc})"
        ) from None
    return F, xy, edges, zeta, arcs, has_order, gens


_VERTEX = np.dtype([("x", "<f8"), ("y", "<f8"), ("z", "<f8")])
_FACE = np.dtype([("n", "u1"), ("a", "<i4"), ("b", "<i4"), ("c", "<i4")])
_EDGE = np.dtype([("vertex1", "<i4"), ("vertex2", "<i4"), ("zeta", "<f8")])
_ARC = np.dtype([("back", "<i4"), ("front", "<i4")])
_HOMOLOGY = np.dtype([("loop", "<i4"), ("edge", "<i4"), ("sign", "i1")])
_ELEMENTS = {
    "vertex": _VERTEX,
    "face": _FACE,
    "edge": _EDGE,
    "depth_arc": _ARC,
    "homology_edge": _HOMOLOGY,
}


def _write_ply(path: Path, m: Mescher, arcs: np.ndarray, has_order: bool, gens: np.ndarray) -> None:
    header = [
        "ply",
        "format binary_little_endian 1.0",
        f"comment meschers mescher format {FORMAT_VERSION}: zeta[e] = depth(vertex2) - depth(vertex1)",
        f"element vertex {m.n_vertices}",
        "property double x",
        "property double y",
        "property double z",
        f"element face {m.n_faces}",
        "property list uchar int vertex_indices",
        f"element edge {m.n_edges}",
        "property int vertex1",
        "property int vertex2",
        "property double zeta",
    ]
    if has_order:
        header += [f"element depth_arc {arcs.shape[0]}", "property int back", "property int front"]
    header += [
        f"element homology_edge {gens.shape[0]}",
        "property int loop",
        "property int edge",
        "property char sign",
    ]
    header.append("end_header")
    v = np.zeros(m.n_vertices, _VERTEX)
    v["x"], v["y"] = m.xy[:, 0], m.xy[:, 1]
    f = np.zeros(m.n_faces, _FACE)
    f["n"] = 3
    f["a"], f["b"], f["c"] = m.F[:, 0], m.F[:, 1], m.F[:, 2]
    e = np.zeros(m.n_edges, _EDGE)
    e["vertex1"], e["vertex2"], e["zeta"] = m.edges[:, 0], m.edges[:, 1], m.zeta
    with open(path, "wb") as fh:
        fh.write(("\n".join(header) + "\n").encode("ascii"))
        fh.write(v.tobytes())
        fh.write(f.tobytes())
        fh.write(e.tobytes())
        if has_order:
            a = np.zeros(arcs.shape[0], _ARC)
            a["back"], a["front"] = arcs[:, 0], arcs[:, 1]
            fh.write(a.tobytes())
        h = np.zeros(gens.shape[0], _HOMOLOGY)
        h["loop"], h["edge"], h["sign"] = gens[:, 0], gens[:, 1], gens[:, 2]
        fh.write(h.tobytes())


def _read_ply(path: Path):
    data = path.read_bytes()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply") or end < 0:
        raise MescherError(f"{path.name}: expected a PLY header ending in end_header, found none")
    lines = data[:end].decode("ascii", errors="replace").splitlines()
    if "format binary_little_endian 1.0" not in lines:
        raise MescherError(
            f"{path.name}: expected a binary little-endian mescher PLY written by meschers.save, "
            f"found {next((ln for ln in lines if ln.startswith('format')), 'no format line')!r}"
        )
    counts, names = {}, []
    for ln in lines:
        parts = ln.split()
        if len(parts) == 3 and parts[0] == "element":
            try:
                counts[parts[1]] = int(parts[2])
            except ValueError:
                raise MescherError(f"{path.name}: malformed header line {ln!r}") from None
            names.append(parts[1])
    for need in ("vertex", "face", "edge"):
        if need not in counts:
            raise MescherError(
                f"{path.name}: expected a mescher PLY with a {need!r} element, found elements "
                f"{sorted(counts)} (a plain mesh? convert it with Mescher.from_mesh)"
            )
    body = memoryview(data)[end + len(b"end_header\n") :]
    unknown = [k for k in names if k not in _ELEMENTS]
    if unknown:
        raise MescherError(
            f"{path.name}: expected the elements of a mescher PLY ({', '.join(_ELEMENTS)}), "
            f"found {unknown}"
        )
    layout = [(k, _ELEMENTS[k]) for k in names]  # in the file's order
    need_bytes = sum(counts[k] * dt.itemsize for k, dt in layout)
    if len(body) != need_bytes:
        raise MescherError(
            f"{path.name}: expected {need_bytes} bytes of data for the header's counts, found "
            f"{len(body)} (truncated or corrupt file)"
        )
    arrays, off = {}, 0
    for k, dt in layout:
        arrays[k] = np.frombuffer(body, dtype=dt, count=counts[k], offset=off)
        off += counts[k] * dt.itemsize
    f = arrays["face"]
    if np.any(f["n"] != 3):
        raise MescherError(
            f"{path.name}: expected triangles, found faces with {set(f['n'])} corners"
        )
    v, e = arrays["vertex"], arrays["edge"]
    xy = np.stack([v["x"], v["y"]], axis=1)
    F = np.stack([f["a"], f["b"], f["c"]], axis=1).astype(np.int64)
    edges = np.stack([e["vertex1"], e["vertex2"]], axis=1).astype(np.int64)
    zeta = np.array(e["zeta"], dtype=np.float64)
    has_order = "depth_arc" in counts
    arcs = (
        np.stack([arrays["depth_arc"]["back"], arrays["depth_arc"]["front"]], axis=1).astype(
            np.int64
        )
        if has_order
        else np.zeros((0, 2), np.int64)
    )
    gens = None
    if "homology_edge" in counts:
        h = arrays["homology_edge"]
        gens = np.stack([h["loop"], h["edge"], h["sign"]], axis=1).astype(np.int64)
    return F, xy, edges, zeta, arcs, has_order, gens
