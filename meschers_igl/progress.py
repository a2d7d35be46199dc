"""Progress bars (rich) for work that may take more than a few seconds.

One helper, so every long loop of the library reports the same way: a transient bar on the
standard error, shown only when the estimated work is large (small calls, and tests, stay
silent).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")

#: Work (faces touched) above which a loop shows a bar: about a second of vectorised work.
SHOW_ABOVE = 2_000_000


def track(
    items: Iterable[T], description: str, total: int | None = None, work: float = 0.0
) -> Iterator[T]:
    """Iterate ``items`` with a rich progress bar when ``work`` exceeds :data:`SHOW_ABOVE`.

    Parameters
    ----------
    items : iterable
    description : str
        Shown left of the bar, e.g. ``"subdivide"``.
    total : int, optional
        Number of items (default ``len(items)``).
    work : float
        Estimated amount of work (e.g. output faces); below the threshold no bar is drawn.
    """
    if work <= SHOW_ABOVE:
        yield from items
        return
    from rich.console import Console  # rich is a dependency; loaded when needed
    from rich.progress import track as rich_track

    console = Console(stderr=True)  # stdout stays for results (the CLI prints JSON there)
    yield from rich_track(
        items, description=description, total=total, transient=True, console=console
    )
