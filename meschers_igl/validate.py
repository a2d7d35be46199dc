"""Shared validators: convert user input once at the boundary, or raise a clear error.

Every validator names the argument, what was expected and what was found
(PyVista ``core/_validation/check.py`` style).  Outputs are C-contiguous float64 / int64
arrays, the dtypes libigl's bindings take without copying.
"""

from __future__ import annotations

from contextvars import ContextVar
from typing import Any

import numpy as np

from .errors import MescherError


def _describe(x: Any) -> str:
    if isinstance(x, np.ndarray):
        return f"array of shape {x.shape} and dtype {x.dtype}"
    return f"{type(x).__name__}"


def _as_array(x: Any, name: str) -> np.ndarray:
    if x is None:
        raise MescherError(f"{name}: expected an array, found None")
    try:
        return np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise MescherError(f"{name}: expected an array, found {_describe(x)} ({exc})") from None


def as_float_array(x: Any, name: str, shape: tuple) -> np.ndarray:
    """Convert ``x`` to a finite float64 array of ``shape`` (``-1`` entries match any length)."""
    a = _as_array(x, name)
    if a.dtype == object or not (
        np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer) or a.dtype == bool
    ):
        raise MescherError(f"{name}: expected real numbers, found dtype {a.dtype}")
    if a.ndim != len(shape) or any(s not in (-1, t) for s, t in zip(shape, a.shape)):
        dims = ["n" if s == -1 else str(s) for s in shape]
        want = f"({dims[0]},)" if len(dims) == 1 else "(" + ", ".join(dims) + ")"
        raise MescherError(f"{name}: expected shape {want}, found {a.shape}")
    a = np.ascontiguousarray(a, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        bad = np.flatnonzero(~np.isfinite(a).reshape(-1))
        raise MescherError(
            f"{name}: expected finite values, found {bad.size} non-finite "
            f"(first at flat index {int(bad[0])}: {a.reshape(-1)[bad[0]]})"
        )
    return a


def as_points(X: Any, name: str, dim: int, n: int | None = None) -> np.ndarray:
    """(n, dim) finite float64 points."""
    a = as_float_array(X, name, (-1 if n is None else n, dim))
    return a


def as_vector(x: Any, name: str, n: int) -> np.ndarray:
    """(n,) finite float64 vector."""
    return as_float_array(x, name, (n,))


def as_int_array(x: Any, name: str, ndim: int, cols: int | None = None) -> np.ndarray:
    """Integer array with ``ndim`` dimensions (and ``cols`` columns); floats must be integral."""
    a = _as_array(x, name)
    if a.ndim != ndim or (cols is not None and a.shape[1] != cols):
        want = "(n,)" if ndim == 1 else f"(n, {cols if cols is not None else 'k'})"
        raise MescherError(f"{name}: expected an integer array of shape {want}, found {a.shape}")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        if a.dtype == bool or not np.issubdtype(a.dtype, np.floating):
            raise MescherError(f"{name}: expected integers, found dtype {a.dtype}")
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise MescherError(f"{name}: expected integer values, found non-integers ({a.dtype})")
    return np.ascontiguousarray(a, dtype=np.int64)


def as_faces(F: Any, name: str = "F", n_vertices: int | None = None) -> np.ndarray:
    """(#F, 3) int64 triangles with indices in ``[0, n_vertices)`` and three distinct corners."""
    F = as_int_array(F, name, 2, 3)
    if F.shape[0] == 0:
        raise MescherError(f"{name}: expected at least one triangle, found an empty array")
    if F.min() < 0:
        raise MescherError(f"{name}: expected indices >= 0, found {int(F.min())}")
    if n_vertices is not None and F.max() >= n_vertices:
        raise MescherError(
            f"{name}: expected indices < {n_vertices} (the number of vertices), "
            f"found {int(F.max())}"
        )
    degenerate = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    if degenerate.any():
        f = int(np.flatnonzero(degenerate)[0])
        raise MescherError(
            f"{name}: expected three distinct corners per face, found {int(degenerate.sum())} "
            f"face(s) with a repeated index (first: face {f} = {F[f].tolist()})"
        )
    return F


def as_index_array(idx: Any, name: str, n: int) -> np.ndarray:
    """(k,) int64 indices, each in ``[0, n)``; a scalar becomes a length-1 array."""
    a = _as_array(idx, name)
    a = as_int_array(a.reshape(-1) if a.ndim == 0 else a, name, 1)
    if a.size == 0:
        raise MescherError(f"{name}: expected at least one index, found none")
    if a.min() < 0 or a.max() >= n:
        bad = a[(a < 0) | (a >= n)][0]
        raise MescherError(f"{name}: expected indices in [0, {n}), found {int(bad)}")
    return a


def as_direction(v: Any, name: str, dim: int = 3) -> np.ndarray:
    """A unit (dim,) direction; a zero vector is an error."""
    a = as_float_array(v, name, (dim,))
    nrm = float(np.linalg.norm(a))
    if nrm == 0.0:
        raise MescherError(f"{name}: expected a non-zero direction, found {a.tolist()}")
    return a / nrm


def as_positive(x: Any, name: str, allow_zero: bool = False) -> float:
    """A finite positive (or non-negative) float."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise MescherError(f"{name}: expected a number, found {_describe(x)}") from None
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        want = ">= 0" if allow_zero else "> 0"
        raise MescherError(f"{name}: expected a finite number {want}, found {v}")
    return v


def as_choice(x: Any, name: str, choices: tuple[str, ...]) -> str:
    """One of a fixed set of strings."""
    if not isinstance(x, str) or x.lower() not in choices:
        raise MescherError(f"{name}: expected one of {', '.join(map(repr, choices))}, found {x!r}")
    return x.lower()


def as_count(x: Any, name: str, minimum: int = 0, maximum: int | None = None) -> int:
    """An integer count in ``[minimum, maximum]`` (a ``bool`` or a float is refused).

    The shared integer-argument check (levels, steps, iterations, sheets, sizes).
    """
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise MescherError(f"{name}: expected an integer >= {minimum}, found {x!r}")
    v = int(x)
    if v < minimum or (maximum is not None and v > maximum):
        want = f">= {minimum}" if maximum is None else f"in [{minimum}, {maximum}]"
        raise MescherError(f"{name}: expected an integer {want}, found {v}")
    return v


#: Share of the available memory an operation may claim before :func:`check_budget` refuses.
MEMORY_FRACTION = 0.5
#: Hard cap on the estimated output size whatever the machine (bytes): 64 GiB.
MAX_BYTES = 64 * 2**30


def available_memory() -> int:
    """Bytes of memory available to a new allocation (``psutil``, else ``/proc/meminfo``).

    Falls back to 4 GiB when neither source can be read.
    """
    try:
        import psutil

        return int(psutil.virtual_memory().available)
    except Exception:  # psutil missing or unusable: read the kernel's estimate
        pass
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 4 * 2**30


def _human(nbytes: float) -> str:
    for unit in ("B", "KB", "MB", "GB", "TB", "PB"):
        if abs(nbytes) < 1024 or unit == "PB":
            return f"{nbytes:.3g} {unit}"
        nbytes /= 1024
    return f"{nbytes:.3g} PB"  # pragma: no cover


#: How :func:`check_budget`'s message says to override it; the command line sets "add --force".
FORCE_HINT: ContextVar[str] = ContextVar("FORCE_HINT", default="pass force=True")


def check_budget(
    n_faces: float,
    bytes_per_face: float = 400.0,
    what: str = "the result",
    force: bool = False,
    available: int | None = None,
    unit: str = "faces",
) -> float:
    """Refuse work whose estimated output would not fit in memory, before doing any of it.

    The estimate is ``n_faces * bytes_per_face``; it is refused when above
    ``MEMORY_FRACTION`` of the memory available now (:func:`available_memory`) or above
    ``MAX_BYTES``.  ``n_faces`` may be a float (``4.0 ** 1000`` overflows no integer).

    Parameters
    ----------
    n_faces : float
        Estimated number of faces (or pixels, or elements) of the output.
    bytes_per_face : float, default: 400
        Peak working memory per face (a mescher with its edges, operators and caches needs
        a few hundred bytes per face).
    what : str
        Named in the message, e.g. ``"subdivide(levels=30)"``.
    force : bool, default: False
        Skip the check (for people who mean it).
    available : int, optional
        Memory available in bytes (default: measured).
    unit : str, default: "faces"
        What ``n_faces`` counts, for the message (``"pixels"`` for an image).

    Returns
    -------
    float
        The estimated number of bytes.

    Raises
    ------
    MescherError
        Giving the estimated faces and bytes, and the limit.
    """
    est = float(n_faces) * float(bytes_per_face)
    if force:
        return est
    avail = available_memory() if available is None else int(available)
    limit = min(MEMORY_FRACTION * avail, MAX_BYTES)
    if not np.isfinite(est) or est > limit:
        raise MescherError(
            f"{what}: expected an output that fits in memory (at most {_human(limit)}, "
            f"{MEMORY_FRACTION:.0%} of the {_human(avail)} available), found an estimated "
            f"{float(n_faces):.3g} {unit} and {_human(est)}; {FORCE_HINT.get()} if you mean it"
        )
    return est


def check_referenced(F: np.ndarray, n_vertices: int, name: str = "xy") -> None:
    """Refuse vertices that no face uses (a mescher's operators are sized by #V, and such a
    vertex would get a zero row: no area, no neighbours, a singular heat or Poisson system).

    Raises
    ------
    MescherError
        Naming the unreferenced vertices (the first ten) and how many there are.
    """
    used = np.zeros(int(n_vertices), dtype=bool)
    used[F.reshape(-1)] = True
    if not used.all():
        bad = np.flatnonzero(~used)
        more = "..." if bad.size > 10 else ""
        raise MescherError(
            f"{name}: expected every vertex to be a corner of some face, found {bad.size} "
            f"unreferenced vertex(es) {bad[:10].tolist()}{more}; remove them first (e.g. "
            "igl.remove_unreferenced(V, F))"
        )
