"""The compile policy of the project's numba kernels: :func:`kernel`, a ``numba.njit`` with it.

Every kernel of the project is declared with :func:`kernel`, which owns the compile policy:

* ``cache=True``: machine code kept for every later process;
* ``error_model="numpy"``: a float division by zero gives ``inf`` or ``nan`` as numpy does, with
  no check and no exception path compiled after each division (about 6% less compile time).
  Results are the same wherever no division by zero happens; where one did, a kernel raised
  ``ZeroDivisionError`` before, a fault in its guards either way;
* ``no_cfunc_wrapper=True``: no C-callable wrapper (``.ctypes``, ``cfunc`` addresses), which no
  caller uses; Python calls go through the CPython wrapper and kernels call each other
  directly (about 6% less compile time, measured on the four groups from an empty cache).

A module of its own that imports nothing of the package: every module with kernels imports it,
and :mod:`meschers_igl.compiled` (which warms the kernels) imports those modules.
"""

from __future__ import annotations

__all__ = ["POLICY", "kernel"]

#: the options every kernel is compiled with (:func:`kernel`)
POLICY = {"cache": True, "error_model": "numpy", "no_cfunc_wrapper": True}


def kernel(**options):
    """``numba.njit`` with the project's compile policy (see the module docstring).

    Parameters
    ----------
    **options
        Further numba options of this kernel (``nogil``, ``inline``, ``no_cpython_wrapper``,
        ``_nrt``).

    Returns
    -------
    callable
        The decorator: ``@kernel()`` or ``kernel(nogil=True)(function)``.

    Examples
    --------
    >>> from meschers_igl.jit import kernel
    >>> @kernel(cache=False)
    ... def twice(x):
    ...     return 2.0 * x
    >>> twice(1.5)
    3.0
    """
    import numba

    return numba.njit(**{**POLICY, **options})
