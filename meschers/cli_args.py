"""Argument types, option helpers and input/output helpers shared by the ``meschers`` subcommands.

Each subcommand module (:mod:`meschers.cli`, :mod:`meschers.draw_cli`, :mod:`meschers.studio`)
builds its options with :func:`add` (every option has a help text) and reads models with
:func:`load_input`; none of them imports another.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError

PROG = "meschers"

__all__ = [
    "PROG",
    "add",
    "add_force",
    "add_input",
    "add_mescher_output",
    "budget",
    "examples",
    "headless_views",
    "load_input",
    "nonnegative",
    "out_path",
    "save_png",
    "size",
    "subdivide",
    "vector",
]


def vector(text: str, name: str = "vector", n: int = 3) -> tuple[float, ...]:
    """Parse ``"x,y,z"``; an argparse type, so a bad value is a one-line usage error."""
    try:
        values = tuple(float(v) for v in text.replace(" ", "").split(","))
    except ValueError:
        values = ()
    if len(values) != n or not np.all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(
            f"{name}: expected {n} comma-separated numbers like {','.join(['1'] * n)}, found {text!r}"
        )
    return values


def size(text: str) -> tuple[int, int]:
    parts = text.lower().replace("x", ",").split(",")
    try:
        w, h = (int(p) for p in parts) if len(parts) == 2 else (int(parts[0]),) * 2
    except ValueError:
        w = h = 0
    if w <= 0 or h <= 0:
        raise argparse.ArgumentTypeError(
            f"size: expected WIDTH,HEIGHT or N (pixels), found {text!r}"
        )
    return w, h


def nonnegative(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = -1.0
    if not np.isfinite(v) or v < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, found {text!r}")
    return v


def load_input(spec: str, check: Callable[[Any], None] | None = None) -> tuple[Any, Any, str]:
    """A mescher from a model name (:mod:`meschers.inputs`): a gallery model, ``paradox:NAME``,
    a ``.ply`` / ``.npz`` mescher file, or a mesh with a sidecar JSON view.  ``check(mescher)``
    runs before the depth order is computed (:func:`meschers.inputs.load_mescher`).

    Returns
    -------
    (Mescher, DepthOrder or None, label)
    """
    from .inputs import load_mescher, resolve

    model = resolve(spec, "INPUT")
    m, order = load_mescher(model, check)
    return m, order, model.label


def out_path(text: str, suffixes: Sequence[str], name: str = "OUT") -> Path:
    p = Path(text)
    if p.suffix.lower() not in suffixes:
        raise MescherError(
            f"{name}: expected a file name ending in {' or '.join(suffixes)}, found '{text}'"
        )
    if p.parent and not p.parent.exists():
        raise MescherError(
            f"{name}: expected an existing folder for '{text}', found no '{p.parent}'"
        )
    return p


def headless_views():
    """Import pyvista_views for an off-screen render (EGL without a display)."""
    import pyvista

    import pyvista_views
    from pyvista_views.headless import has_display

    if not has_display():
        pyvista.OFF_SCREEN = True
    return pyvista_views


def save_png(image: np.ndarray, path: Path) -> None:
    from PIL import Image

    Image.fromarray(np.ascontiguousarray(image)).save(path)


def budget(m: Any, levels: int, force: bool, what: str) -> None:
    """Refuse (exit 2, before any work) a subdivision whose result would not fit in memory."""
    from meschers_igl.validate import check_budget

    check_budget(float(m.n_faces) * 4.0 ** min(levels, 200), what=what, force=force)


def subdivide(m: Any, order: Any, levels: int, scheme: str = "midpoint", force: bool = False):
    if order is None:
        return m.subdivide(levels, scheme=scheme, force=force), None
    return m.subdivide(levels, scheme=scheme, order=order, force=force)


def examples(*lines: str) -> str:
    return "example:\n" + "\n".join(f"  {PROG} {ln}" for ln in lines)


def add(p: argparse.ArgumentParser, *names: str, **kw: Any) -> None:
    """``add_argument`` that insists on a help text (every option documents itself)."""
    if not kw.get("help"):
        raise ValueError(f"option {names[0]} has no help text")  # a programming error
    p.add_argument(*names, **kw)


def add_input(p: argparse.ArgumentParser, nargs: str | None = None) -> None:
    add(
        p,
        "input",
        metavar="INPUT",
        nargs=nargs,
        help="a gallery model (e.g. penrose_triangle), paradox:NAME (a shipped ParadoxToolkit "
        "model), solid:NAME (a shipped closed solid), a .ply/.npz mescher file, or a mesh with a sidecar .json view; "
        "'meschers info --list' lists the names",
    )


def add_mescher_output(p: argparse.ArgumentParser) -> None:
    add(
        p,
        "-o",
        "--output",
        required=True,
        metavar="OUT",
        help="the mescher file to write (.ply or .npz)",
    )


def add_force(p: argparse.ArgumentParser) -> None:
    add(
        p,
        "--force",
        action="store_true",
        help="do it even when the estimated result does not fit in the memory available "
        "(otherwise refused at once, exit status 2)",
    )
