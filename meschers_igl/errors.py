"""The one exception type users see."""

from __future__ import annotations


class MescherError(ValueError):
    """Bad input to a mescher operation.

    The message names the argument, what was expected and what was found.  It is a
    ``ValueError`` so that generic input-error handlers catch it too.
    """


class MescherWarning(UserWarning):
    """Something the user should know that does not stop the computation (e.g. order cycles)."""
