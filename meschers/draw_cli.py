"""``meschers draw``: line art of a mescher as SVG, PDF or PNG.

::

    meschers draw penrose_triangle -o penrose.svg
    meschers draw impossibagel -o bagel.pdf --subdivide 2 --hidden dashed
    meschers draw paradox:impossible_cube -o cube.png --overlay --light 1,1,1

The lines (outlines, occlusion lines with their T-junctions, creases, occluding contours) and
their visibility come from :func:`meschers_igl.lines.line_drawing`, the file from
:func:`pyvista_views.draw`; ``--overlay`` draws them over the shaded render instead
(:func:`pyvista_views.lineart.overlay`, PNG only).
"""

from __future__ import annotations

import argparse
from typing import Any

from . import cli_args as ca

__all__ = ["add_draw_parser", "cmd_draw"]


def add_draw_parser(sub: Any) -> None:
    """Register ``draw`` on the ``meschers`` subparsers ``sub``."""
    p = sub.add_parser(
        "draw",
        help="line art (SVG/PDF/PNG): outlines, occlusion lines, creases, contours",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Vector line art of a mescher: the lines a person draws, their visibility "
        "from the depth order (exact T-junctions where a line passes behind a face), thick "
        "outlines, medium occlusion lines, thin creases; joined polylines in groups by kind.",
        epilog=ca.examples(
            "draw penrose_triangle -o penrose.svg",
            "draw impossibagel -o bagel.pdf --subdivide 2 --hidden dashed",
            "draw paradox:impossible_cube -o cube.png --overlay",
        ),
    )
    ca.add_input(p)
    ca.add(
        p,
        "-o",
        "--output",
        required=True,
        metavar="FILE",
        help="the drawing to write: .svg, .pdf or .png (PDF and PNG need cairosvg)",
    )
    ca.add(
        p,
        "--hidden",
        choices=("omit", "dashed"),
        default="omit",
        help="hidden lines left out or drawn dashed and grey (default %(default)s)",
    )
    ca.add(
        p,
        "--crease-angle",
        type=ca.nonnegative,
        default=30.0,
        metavar="A",
        help="dihedral angle in degrees above which an edge is a crease (default %(default)s)",
    )
    ca.add(
        p,
        "--contours",
        choices=("auto", "mesh", "interpolated"),
        default="auto",
        help="occluding contours along mesh edges or interpolated inside faces; auto: "
        "interpolated on meschers without creases (default %(default)s)",
    )
    ca.add(
        p,
        "--subdivide",
        type=int,
        default=0,
        metavar="N",
        help="Loop subdivision levels first (smooth silhouettes; each level 4x the faces; default 0)",
    )
    ca.add(
        p,
        "--size",
        type=ca.size,
        default=(800, 800),
        metavar="W,H",
        help="picture size in pixels (SVG units, PDF points), WIDTH,HEIGHT or N (default 800,800)",
    )
    ca.add(
        p,
        "--overlay",
        action="store_true",
        help="draw the lines over the shaded render (PNG output)",
    )
    ca.add(
        p,
        "--light",
        action="append",
        type=lambda s: ca.vector(s, "--light"),
        metavar="X,Y,Z",
        help="with --overlay: direction toward a directional light (repeatable; default 1,1,1)",
    )
    ca.add_force(p)
    p.set_defaults(func=cmd_draw)


def cmd_draw(args: argparse.Namespace) -> int:
    """Run ``meschers draw``; returns the exit status."""
    from meschers_igl.lines import KINDS, line_drawing
    from meschers_igl.validate import as_count

    suffixes = (".png",) if args.overlay else (".svg", ".pdf", ".png")
    out = ca.out_path(args.output, suffixes, "-o")
    levels = as_count(args.subdivide, "--subdivide")
    m, order, _ = ca.load_input(
        args.input, lambda m: ca.budget(m, levels, args.force, f"draw --subdivide {levels}")
    )
    if levels:
        m, order = ca.subdivide(m, order, levels, scheme="loop", force=args.force)
    lines = line_drawing(
        m,
        order,
        crease_angle=args.crease_angle,
        contours=args.contours,
        hidden=args.hidden == "dashed",
    )
    pvv = ca.headless_views()
    if args.overlay:
        from pyvista_views.lineart import overlay

        image = overlay(
            m,
            order,
            window_size=args.size,
            hidden=args.hidden,
            lines=lines,
            lights=args.light or [(1.0, 1.0, 1.0)],
            anti_aliasing=True,
        )
        ca.save_png(image, out)
    else:
        pvv.draw(m, order, out, window_size=args.size, hidden=args.hidden, lines=lines)
    counts = ", ".join(
        f"{int((lines.visible & (lines.kind == k)).sum())} {name}" for k, name in enumerate(KINDS)
    )
    print(f"wrote {out} ({args.size[0]} x {args.size[1]}; visible lines: {counts})")
    return 0
