"""Sparse factorizations for the symmetric positive definite systems of geometry processing.

Heat diffusion, the heat method and smoothing all solve ``A x = b`` with ``A`` symmetric positive
definite (``M - t L``, a pinned ``-L``) many times with one matrix, so the factorization is the
hot path.  :func:`factorize_spd` factors once and returns a callable that solves for one or many
right-hand sides.

Which library: cholespy (CHOLMOD) when it is installed -- the solve is what users repeat (one
per geodesic query, two per heat-method source), and it solves fastest, blocks of right-hand
sides too, in the least memory, and detects a matrix that is not positive definite -- else
SuperLU with the ``MMD_AT_PLUS_A`` ordering, solving blocks column by column.  The
measurements behind the choice are in the docs (:doc:`/results`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from .errors import MescherError

try:  # optional at import time so that a pure-scipy install still works
    import cholespy as _cholespy
except ImportError:  # pragma: no cover - exercised only where cholespy is missing
    _cholespy = None

__all__ = ["SPDFactor", "factorize_spd", "BACKENDS"]

#: Factorization backends in order of preference.
BACKENDS = ("cholespy", "splu")


class SPDFactor:
    """A factored symmetric positive definite matrix; call it to solve.

    Parameters
    ----------
    A : (n, n) scipy.sparse matrix
        Symmetric positive definite.
    backend : {"auto", "cholespy", "splu"}
        ``"auto"`` takes cholespy (CHOLMOD) when it imports, else SuperLU.

    Attributes
    ----------
    n : int
        Size of the system.
    backend : str
        The backend actually used.
    """

    def __init__(self, A: sp.spmatrix, backend: str = "auto") -> None:
        if not sp.issparse(A):
            raise MescherError(f"A: expected a scipy.sparse matrix, found {type(A).__name__}")
        if A.ndim != 2 or A.shape[0] != A.shape[1]:
            raise MescherError(f"A: expected a square matrix, found shape {A.shape}")
        if backend not in ("auto", *BACKENDS):
            raise MescherError(
                f"backend: expected one of auto, {', '.join(BACKENDS)}; found {backend!r}"
            )
        if backend == "auto":
            backend = "cholespy" if _cholespy is not None else "splu"
        if backend == "cholespy" and _cholespy is None:
            raise MescherError(
                "backend: 'cholespy' requested but cholespy is not installed (pip install cholespy)"
            )
        A = sp.csr_matrix(A, dtype=np.float64)
        if not np.all(np.isfinite(A.data)):
            raise MescherError("A: expected finite entries, found NaN or inf")
        self.n = A.shape[0]
        self.backend = backend
        if backend == "cholespy":
            A.sum_duplicates()
            try:
                self._chol = _cholespy.CholeskySolverD(
                    self.n,
                    A.indptr.astype(np.int32),
                    A.indices.astype(np.int32),
                    np.ascontiguousarray(A.data),
                    _cholespy.MatrixType.CSR,
                )
            except ValueError as exc:  # CHOLMOD: "Matrix is not positive definite!"
                raise MescherError(
                    f"A: expected a symmetric positive definite matrix; CHOLMOD says: {exc}"
                ) from exc
        else:
            # MMD on A^T + A: 3x faster than COLAMD on Laplacians (see module docstring).
            try:
                self._lu = sla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A")
            except RuntimeError as exc:  # "Factor is exactly singular"
                raise MescherError(
                    f"A: expected a nonsingular matrix; SuperLU says: {exc}"
                ) from exc

    def __call__(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``.

        Parameters
        ----------
        b : (n,) or (n, k) array_like

        Returns
        -------
        x : (n,) or (n, k) float64
        """
        b = np.asarray(b, dtype=np.float64)
        if b.ndim not in (1, 2) or b.shape[0] != self.n:
            raise MescherError(f"b: expected shape ({self.n},) or ({self.n}, k), found {b.shape}")
        if self.backend == "cholespy":
            b = np.ascontiguousarray(b)
            x = np.zeros_like(b)
            if b.size:
                self._chol.solve(b, x)
            return x
        if b.ndim == 1:
            return self._lu.solve(b)
        # SuperLU's block solve is slower than column by column here (module docstring).
        x = np.empty_like(b)
        for k in range(b.shape[1]):
            x[:, k] = self._lu.solve(np.ascontiguousarray(b[:, k]))
        return x

    solve = __call__


def factorize_spd(A: sp.spmatrix, backend: str = "auto") -> Callable[[np.ndarray], np.ndarray]:
    """Factor a sparse symmetric positive definite matrix once; return a solver.

    Parameters
    ----------
    A : (n, n) scipy.sparse matrix
        Symmetric positive definite (e.g. ``M - t L`` with ``L`` libigl's negative semi-definite
        cotangent matrix).
    backend : {"auto", "cholespy", "splu"}, default: "auto"
        ``"auto"``: cholespy (CHOLMOD) if importable, else SuperLU with ``MMD_AT_PLUS_A``.

    Returns
    -------
    solve : SPDFactor
        ``solve(b)`` returns ``x`` with ``A x = b`` for ``b`` of shape (n,) or (n, k).

    Raises
    ------
    MescherError
        If ``A`` is not a square sparse matrix, has non-finite entries, or (cholespy) is not
        positive definite, or (SuperLU) is singular.
    """
    return SPDFactor(A, backend=backend)
