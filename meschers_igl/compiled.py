"""The compiled (numba) kernels of the core: which are compiled on this machine, and warming them.

numba compiles a kernel the first time it is called and, with ``cache=True``, keeps the machine
code beside the module (``__pycache__``) for every later process.  A fresh installation
therefore pays the compilation once, inside whatever runs first; a parallel run whose workers
start together would pay it once per worker.  This module lets the application pay it once, up
front and visibly: :func:`cold_kernels` says which kernels have no machine code cached for this
CPU, and :func:`warm` runs a tiny representative call of each group of kernels (the public
functions with the argument types real work uses, so the cached signatures are the ones later
calls look up).

Every kernel is declared with :func:`meschers_igl.jit.kernel`, which owns the compile policy.

Groups (each can be warmed in its own process, in parallel):

``"order"``
    overlap tests, depth orders, topological sorts, refinement, line drawings
    (:mod:`.overlap`, :mod:`.order_graph`, :mod:`.lines`).
``"paths"``
    closed geodesics (funnel unfolding), intrinsic Delaunay flips, the heap
    (:mod:`.geodesic.unfold`, :mod:`.intrinsic`, :mod:`.heap`): what homology loops and the heat
    method use.
``"geodesic"``
    exact geodesics by window propagation (:mod:`.geodesic.windows`): exact distances and
    shortest paths; the longest single kernel to compile, so a group of its own.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable

__all__ = [
    "GROUPS",
    "cold_kernels",
    "is_cached",
    "kernels",
    "tiny_mescher",
    "warm",
]

# module names of each group's kernels
GROUPS: dict[str, tuple[str, ...]] = {
    "order": ("meschers_igl.overlap", "meschers_igl.order_graph", "meschers_igl.lines"),
    "paths": ("meschers_igl.geodesic.unfold", "meschers_igl.intrinsic", "meschers_igl.heap"),
    "geodesic": ("meschers_igl.geodesic.windows",),
}


def kernels(modules: Iterable[str]) -> list:
    """The numba dispatchers defined at the top level of ``modules`` (imported here).

    Parameters
    ----------
    modules : iterable of str
        Importable module names.

    Returns
    -------
    list of numba dispatchers
    """
    from numba.core.registry import CPUDispatcher

    out = []
    for name in modules:
        try:
            mod = importlib.import_module(name)
        except ImportError:  # a module of an optional extra: its kernels are not used here
            continue
        for value in vars(mod).values():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                out.append(value)
    return out


def is_cached(dispatcher) -> bool:
    """Does ``dispatcher``'s on-disk cache hold machine code for this CPU and this source?

    Reads numba's cache index (private API: any surprise counts as "not cached", so the worst a
    numba change can do is an unneeded message).
    """
    try:
        cache = dispatcher._cache
        overloads = cache._cache_file._load_index()
        magic = dispatcher.targetctx.codegen().magic_tuple()
    except Exception:  # noqa: BLE001 -- numba internals; see the docstring
        return False
    return any(key[1] == magic for key in overloads)


def cold_kernels(modules: Iterable[str]) -> list[str]:
    """Names (``module.function``) of the kernels of ``modules`` with no cached machine code.

    Kernels inlined into their callers (``inline="always"``) are compiled inside them and never
    have a cache of their own, so they are not counted.

    Parameters
    ----------
    modules : iterable of str
        Module names, e.g. ``GROUPS["order"]``.

    Returns
    -------
    list of str
    """
    return [
        f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        for d in kernels(modules)
        if d.targetoptions.get("inline", "never") == "never" and not is_cached(d)
    ]


def warm(group: str) -> None:
    """Compile (or load from the cache) the kernels of ``group`` with a tiny representative call.

    Parameters
    ----------
    group : str
        A key of :data:`GROUPS`.
    """
    from .errors import MescherError

    if group not in GROUPS:
        raise MescherError(f"group: expected one of {sorted(GROUPS)}, found {group!r}")
    {"order": _warm_order, "paths": _warm_paths, "geodesic": _warm_geodesic}[group]()


def tiny_mescher():
    """The small impossible mescher every warm-up call uses (an impossible torus, 144 faces):
    the argument types of real work at almost no cost."""
    from . import shapes

    return shapes.impossible_torus(12, 6, climb=1.0)


def _warm_order() -> None:
    import numpy as np

    from .geometry2d import candidate_pairs, intersection_centroids, triangles_overlap
    from .lines import line_drawing
    from .order import DepthOrder

    m = tiny_mescher()
    o = DepthOrder.from_local_depth(m)
    o.linear_extension()
    o.put_in_front(np.arange(4), np.arange(4, 8))
    fine, _ = m.subdivide(1, order=o)
    T = m.xy[m.F]
    intersection_centroids(T[:2], T[2:4])
    triangles_overlap(T[:2], T[2:4])
    candidate_pairs(T.min(axis=1), T.max(axis=1))
    DepthOrder.from_embedding(m, m.corner_depths())
    line_drawing(m, o, hidden=True)
    del fine


def _warm_paths() -> None:
    from .geodesic import geodesic_distance, shortest_loops

    m = tiny_mescher()
    for method in ("auto", "refined", "geometry_central"):
        geodesic_distance(m, [0], method=method)
    shortest_loops(m)


def _warm_geodesic() -> None:
    from .geodesic import geodesic_distance

    m = tiny_mescher()
    geodesic_distance(m, [0], method="exact")
    m.shortest_path(0, m.n_vertices // 2)
