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


class Meter:
    """A bar for work whose size is not known in advance: it appears once the work has run
    ``after`` seconds (quick calls, and tests, stay silent), transient, on the standard error
    when that is a terminal.

    Use as a context manager; call :meth:`update` with the amount done so far.

    Parameters
    ----------
    description : str
    total : int
        The amount :meth:`update` counts towards (e.g. vertices reached).
    after : float, default: 2.0
        Seconds before the bar is drawn.
    """

    def __init__(self, description: str, total: int, after: float = 2.0) -> None:
        self.description = description
        self.total = max(int(total), 1)
        self.after = float(after)
        self._t0 = 0.0
        self._bar = None
        self._task = None

    def __enter__(self) -> Meter:
        import time

        self._t0 = time.perf_counter()
        return self

    def update(self, done: int) -> None:
        """Report ``done`` of ``total``; draws the bar once ``after`` seconds have passed."""
        import time

        if self._bar is None:
            if time.perf_counter() - self._t0 < self.after:
                return
            from rich.console import Console
            from rich.progress import Progress

            console = Console(stderr=True)
            if not console.is_terminal:  # a log or a pipe: a live bar would only add blank lines
                self.after = float("inf")
                return
            self._bar = Progress(console=console, transient=True)
            self._bar.start()
            self._task = self._bar.add_task(self.description, total=self.total)
        self._bar.update(self._task, completed=min(int(done), self.total))

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None
