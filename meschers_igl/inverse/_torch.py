"""Lazy PyTorch import for :mod:`meschers_igl.inverse` (an optional extra).

The rest of :mod:`meschers_igl` never needs PyTorch; only the modules of this package that
differentiate through a renderer import it, through :func:`require_torch`.
"""

from __future__ import annotations

from types import ModuleType

#: how to get PyTorch; the CPU wheel is enough for everything in this package
INSTALL_HINT = (
    "pip install torch==2.13.0 (the CPU build, first, so that nothing asks for a CUDA build), "
    "then pip install 'meschers[inverse]'"
)


def require_torch() -> ModuleType:
    """Import and return :mod:`torch`, or raise an ``ImportError`` saying how to install it.

    Returns
    -------
    module
        The :mod:`torch` module.

    Raises
    ------
    ImportError
        When PyTorch is not installed; the message gives the install command.
    """
    try:
        import torch
    except ImportError as exc:  # pragma: no cover - exercised only without torch
        raise ImportError(
            "meschers_igl.inverse needs PyTorch, which is not installed; expected an "
            f"importable 'torch', found none. Install it with: {INSTALL_HINT}"
        ) from exc
    return torch


def require_largesteps() -> ModuleType:
    """Import and return :mod:`largesteps` (Nicolet et al. 2021), or say how to install it."""
    try:
        import largesteps.optimize
        import largesteps.parameterize  # noqa: F401
    except ImportError as exc:  # pragma: no cover - exercised only without largesteps
        raise ImportError(
            "meschers_igl.inverse.optimize needs largesteps, which is not installed; expected an "
            f"importable 'largesteps', found none. Install it with: {INSTALL_HINT} "
            "(or: pip install largesteps)"
        ) from exc
    return largesteps
