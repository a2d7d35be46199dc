"""The ``meschers`` command line: the comparison study and everyday work on meschers.

``meschers study`` runs every operation of the paper on the built-in gallery (or on your own
models) and writes an HTML report; the other subcommands each wrap one library call::

    meschers study --quick --out study        # report in study/index.html
    meschers study my_models/ --jobs 2        # a folder of models on two worker processes
    meschers info penrose_triangle            # counts, genus, periods
    meschers convert paradox:penrose_triangle penrose.ply   # a shipped model, written out
    meschers convert model.obj model.ply --view 1,1,1 --up 0,0,1
    meschers render model.ply -o model.png --light 1,1,1 --light -1,0,1
    meschers draw penrose_triangle -o penrose.svg --hidden dashed   # line art
    meschers geodesic model.ply --source 0 --target 10 -o distance.png
    meschers smooth model.ply -o smooth.ply --t-xy 0.01 --t-zeta 0.01
    meschers subdivide model.ply -o fine.ply --levels 2
    meschers view model.ply                   # interactive (needs a display)
    meschers inverse target.png --light 0,0,1 --out fit

A model is named as in :mod:`meschers.inputs`: a gallery name, ``paradox:NAME``, a saved
``.ply``/``.npz`` mescher or a mesh with a sidecar JSON view.

A user error (missing or corrupt file, unknown model, bad option, a request too big for the
memory without ``--force``) prints one line
``meschers: error: ...`` on stderr and exits with status 2 (1 for a failed step); genuine bugs
keep their traceback.  pyvista, pymeshlab and torch are imported only inside the subcommands that
need them (``import meschers_igl`` never imports pyvista).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import FORCE_HINT

from .cli_args import (
    PROG,
    add,
    add_force,
    add_input,
    add_mescher_output,
    budget,
    examples,
    headless_views,
    load_input,
    nonnegative,
    out_path,
    save_png,
    size,
    subdivide,
    vector,
)
from .describe import describe, format_info

__all__ = ["build_parser", "describe", "load_input", "main"]


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (no usage block) and no exit inside :func:`main`."""

    def error(self, message: str):  # type: ignore[override]
        raise _UsageError(f"{message} (see '{self.prog} --help')")


class _UsageError(Exception):
    pass


# ------------------------------------------------------------------------------------------------
# helpers
# ------------------------------------------------------------------------------------------------
def _print_info(info: dict, label: str) -> None:
    print(format_info(info, label))


# ------------------------------------------------------------------------------------------------
# subcommands
# ------------------------------------------------------------------------------------------------
def _split_names(chunks: Sequence[str] | None) -> list[str]:
    return [n.strip() for chunk in chunks or () for n in chunk.split(",") if n.strip()]


def _cmd_study(args: argparse.Namespace) -> int:
    from meschers_igl.validate import as_count

    from .study import run_study

    jobs = as_count(args.jobs, "--jobs", minimum=1) if args.jobs is not None else _default_jobs()
    names = [*args.inputs, *_split_names(args.models)]
    result = run_study(
        names or None,
        out=args.out,
        quick=args.quick,
        progress=not args.no_progress,
        other_tools=not args.no_other_tools,
        jobs=jobs,
        scheduler=args.scheduler,
    )
    print(f"wrote {result.index} ({result.metrics['runtime_s']:.1f} s)")
    for err in result.errors:
        print(f"{PROG}: step failed: {err}", file=sys.stderr)
    return 1 if result.errors else 0


def _default_jobs() -> int:
    """Worker processes of a study by default: the cores this process may use, at most 4."""
    from .warmup import available_cores

    return max(1, min(available_cores(), 4))


def _cmd_info(args: argparse.Namespace) -> int:
    m, order, label = load_input(args.input)
    info = describe(m, order)
    if args.json:
        print(json.dumps(info))
    else:
        _print_info(info, label)
    return 0


def _cmd_convert(args: argparse.Namespace) -> int:
    from meschers_igl import io

    from .inputs import ModelSpec, resolve

    out = out_path(args.output, (".ply", ".npz"))
    src = Path(args.input)
    if src.is_file() and src.with_suffix(".json").is_file() or not src.exists():
        model = resolve(args.input, "INPUT")  # a named model, or a mesh with its sidecar view
    else:
        if not src.is_file():
            raise MescherError(f"INPUT: expected a mesh file, found a folder at '{src}'")
        model = ModelSpec("artist", src.stem, str(src), source=args.input)
    if model.kind != "artist":  # a gallery model or a saved mescher: written as it is
        from .inputs import load_mescher

        m, order = load_mescher(model)
    else:
        from meshlab_filters import model_to_mescher  # one door: it picks the route, says why

        view = args.view or model.view or (0.0, 0.0, 1.0)
        up = args.up or model.up or (0.0, 1.0, 0.0)
        m, order, report = model_to_mescher(
            model.path,
            view=view,
            up=up,
            perceive=args.perceive,
            merge_tol=args.merge_tol,
            tol=args.tol,
            route="seen" if args.visible else "auto",
            view_start=args.view_start,
        )
        print(report)
    io.save(m, out, order=order)
    _print_info(describe(m, order), f"wrote {out}")
    return 0


def _cmd_render(args: argparse.Namespace) -> int:
    from meschers_igl.validate import as_count

    out = out_path(args.output, (".png",), "-o")
    levels = as_count(args.subdivide, "--subdivide")
    m, order, _ = load_input(
        args.input, lambda m: budget(m, levels, args.force, f"render --subdivide {levels}")
    )
    if levels:
        m, order = subdivide(m, order, levels, force=args.force)
    pvv = headless_views()
    image = pvv.render(
        m,
        order=order if args.representation == "mescher" else None,
        lights=args.light or [(1.0, 1.0, 1.0)],
        shading=args.shading,
        env_map=args.env,
        window_size=args.size,
        representation=args.representation,
        anti_aliasing=True,
    )
    if np.all(image == image[:1, :1]):
        raise MescherError(
            f"-o: expected a picture of the model, found a render of one colour (the model is "
            f"degenerate or outside the view); nothing written to {out}"
        )
    save_png(image, out)
    print(f"wrote {out} ({image.shape[1]} x {image.shape[0]})")
    return 0


def _cmd_geodesic(args: argparse.Namespace) -> int:
    from meschers_igl.geodesic import geodesic_solver
    from meschers_igl.validate import as_index_array

    m, order, _ = load_input(args.input)
    # vertices checked before the field is computed
    as_index_array(args.source, "--source", m.n_vertices)
    if args.target is not None:
        as_index_array(args.target, "--target", m.n_vertices)
    d = geodesic_solver(m, args.method or "auto").distance(args.source)
    finite = np.isfinite(d)
    print(
        f"distance from vertex(es) {', '.join(map(str, args.source))}: max {d[finite].max():.6g}, "
        f"mean {d[finite].mean():.6g}, unreachable vertices {int((~finite).sum())}"
    )
    path = None
    if args.target is not None:
        path = m.shortest_path(args.source[0], args.target)
        print(
            f"shortest path {args.source[0]} -> {args.target}: length {path.length:.6g}, "
            f"{path.n_points} points (distance field: {d[args.target]:.6g})"
        )
    if args.save:
        out = out_path(args.save, (".npy",), "--save")
        np.save(out, d)
        print(f"wrote {out}")
    if args.output:
        out = out_path(args.output, (".png",), "-o")
        from .figures import geodesic_picture

        image = geodesic_picture(
            m,
            order,
            d,
            path,
            None if path is None else (args.source[0], args.target),
            args.size,
            args.isolines,
        )
        save_png(image, out)
        print(f"wrote {out}")
    return 0


def _cmd_smooth(args: argparse.Namespace) -> int:
    from meschers_igl import io
    from meschers_igl.validate import as_count

    m, order, _ = load_input(args.input)
    out = out_path(args.output, (".ply", ".npz"), "-o")
    iterations = as_count(args.iterations, "--iterations", minimum=1)
    ms = m.smooth(t_xy=args.t_xy, t_zeta=args.t_zeta, iterations=iterations, order=order)
    if order is not None:  # smoothing moved xy: the order follows (overlaps come and go)
        ms, order = ms
    p0, p1 = np.asarray(m.periods()), np.asarray(ms.periods())
    io.save(ms, out, order=order)
    print(
        f"wrote {out}: t_xy {args.t_xy:g}, t_zeta {args.t_zeta:g}, {iterations} iteration(s); "
        f"largest period change {np.abs(p1 - p0).max(initial=0.0):.2e}"
    )
    return 0


def _cmd_subdivide(args: argparse.Namespace) -> int:
    from meschers_igl import io
    from meschers_igl.validate import as_count

    levels = as_count(args.levels, "--levels")
    out = out_path(args.output, (".ply", ".npz"), "-o")
    m, order, _ = load_input(
        args.input, lambda m: budget(m, levels, args.force, f"subdivide --levels {levels}")
    )
    ms, order_s = subdivide(m, order, levels, args.scheme, force=args.force)
    io.save(ms, out, order=order_s)
    print(f"wrote {out}: {m.n_faces} -> {ms.n_faces} faces ({args.scheme}, {levels} level(s))")
    return 0


def _cmd_view(args: argparse.Namespace) -> int:
    m, order, _ = load_input(args.input)
    from pyvista_views.headless import has_display

    if not has_display():
        raise MescherError(
            "view: expected a display for an interactive window, found none (DISPLAY and "
            "WAYLAND_DISPLAY are unset); use 'meschers render' for a PNG instead"
        )
    import pyvista_views

    pyvista_views.plot(
        m, order=order, shading=args.shading, window_size=args.size, off_screen=False
    )
    return 0


def _cmd_inverse(args: argparse.Namespace) -> int:
    try:
        from .inverse_cli import inverse_main
    except ModuleNotFoundError as exc:
        if exc.name != f"{__package__}.inverse_cli":
            raise  # a missing dependency (torch): its own message says how to install it
        raise MescherError(
            "inverse: expected the inverse-rendering module meschers.inverse_cli, found it "
            "missing from this installation"
        ) from None

    return int(inverse_main(list(args.rest)) or 0)


def _cmd_info_or_list(args: argparse.Namespace) -> int:
    if args.list or args.input is None:
        from meschers_igl.gallery import get_model, list_models
        from meschers_igl.paradox import list_paradox_models

        if args.input is None and not args.list:
            raise MescherError("INPUT: expected a model name or a .ply/.npz file, found nothing")
        print("gallery models:")
        for name in list_models():
            print(f"  {name:30s} {get_model(name).description}")
        print("shipped ParadoxToolkit cut models (GPL-3.0 data):")
        for name in list_paradox_models():
            print(f"  paradox:{name}")
        from .inputs import list_solids

        print("shipped solid models (closed solids, separate blocks, seen from their view):")
        for name in list_solids():
            print(f"  solid:{name}")
        return 0
    return _cmd_info(args)


# ------------------------------------------------------------------------------------------------
# parser
# ------------------------------------------------------------------------------------------------
_RAW = argparse.RawDescriptionHelpFormatter
_SIZE_HELP = "image size in pixels, WIDTH,HEIGHT or N for a square (default %(default)s)"


def build_parser() -> argparse.ArgumentParser:
    """The ``meschers`` argument parser (one subparser per subcommand)."""
    parser = _Parser(
        prog=PROG,
        description="Geometry processing of impossible objects (meschers; Dodik et al., ACM TOG 2025).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=examples("study --quick --out study", "info penrose_triangle"),
    )
    from meschers_igl import __version__

    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    _parser_study(sub)
    _parser_info(sub)
    _parser_convert(sub)
    _parser_render(sub)
    from .draw_cli import add_draw_parser  # line art: meschers/draw_cli.py

    add_draw_parser(sub)
    _parser_geodesic(sub)
    _parser_smooth(sub)
    _parser_subdivide(sub)
    _parser_view(sub)
    from .studio import add_parser as add_studio_parser  # a studio in the browser (trame)

    add_studio_parser(
        sub, formatter_class=_RAW, epilog=examples("studio", "studio penrose_triangle --port 8090")
    )
    _parser_inverse(sub)
    return parser


def _parser_study(sub: Any) -> None:
    """The ``study`` subcommand and its options."""
    p = sub.add_parser(
        "study",
        help="run the comparison study; write one HTML page",
        formatter_class=_RAW,
        description="Every operation of the paper on each model, mescher vs cut vs bent, written "
        "to OUT/index.html (one file, figures embedded) with the PNGs and metrics.json. Default: "
        "the gallery and the shipped ParadoxToolkit and solid models.",
        epilog=examples(
            "study",
            "study --quick --models penrose_triangle,impossibagel --out study",
            "study 'my_models/*.obj' saved.ply --jobs 2 --out mine",
            "study --scheduler tcp://10.0.0.5:8786",
        ),
    )
    add(
        p,
        "inputs",
        nargs="*",
        metavar="MODEL",
        help="models to study, exactly these: gallery names, paradox:NAME, solid:NAME, .ply/.npz meschers, meshes "
        "with a sidecar .json view ({'view': [x,y,z], 'up': [x,y,z]}), folders, glob patterns "
        "(quoted); default: the gallery and the shipped ParadoxToolkit and solid models "
        "(meschers info --list)",
    )
    add(
        p,
        "--models",
        action="append",
        metavar="NAMES",
        help="comma-separated models, like MODEL (repeatable); only these are run",
    )
    add(
        p,
        "--out",
        default="meschers_study",
        metavar="DIR",
        help="output folder (default: meschers_study)",
    )
    add(
        p,
        "--quick",
        action="store_true",
        help="192-pixel panels and one subdivision level instead of 320 and two",
    )
    add(
        p,
        "--jobs",
        type=int,
        default=None,
        metavar="N",
        help="worker processes of a local Dask cluster, one model per task; 1 runs here, one model "
        "after another (default: the cores available, at most 4)",
    )
    add(
        p,
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (its workers need meschers "
        "installed); --jobs is then ignored",
    )
    add(p, "--no-progress", action="store_true", help="no progress bar")
    add(
        p,
        "--no-other-tools",
        action="store_true",
        help="without MODEL/--models: leave out the ParadoxToolkit section",
    )
    p.set_defaults(func=_cmd_study)


def _parser_info(sub: Any) -> None:
    """The ``info`` subcommand and its options."""
    p = sub.add_parser(
        "info",
        help="counts, genus, components, impossible?, periods",
        formatter_class=_RAW,
        description="Describe a mescher: counts, Euler characteristic, genus, boundary loops, "
        "whether it is impossible, its periods and its depth order.",
        epilog=examples(
            "info penrose_triangle", "info paradox:penrose_triangle --json", "info --list"
        ),
    )
    add_input(p, nargs="?")
    add(p, "--json", action="store_true", help="print one JSON object")
    add(p, "--list", action="store_true", help="list the gallery and shipped ParadoxToolkit models")
    p.set_defaults(func=_cmd_info_or_list)


def _parser_convert(sub: Any) -> None:
    """The ``convert`` subcommand and its options."""
    p = sub.add_parser(
        "convert",
        help="a model (artist cut model, paradox:NAME, gallery) -> .ply mescher",
        formatter_class=_RAW,
        description="Write a mescher file. An artist's cut model (OBJ, PLY, STL, ... any format "
        "PyMeshLab reads) is cleaned with PyMeshLab and its seam glued into a mescher seen from "
        "--view (default: its sidecar .json view, else 0,0,1); a shipped model "
        "(paradox:NAME) uses its own camera; a gallery model is written as it is. The depth "
        "order is saved with it; the clean-up report is printed.",
        epilog=examples(
            "convert paradox:penrose_triangle penrose.ply",
            "convert penrose_triangle.obj penrose.ply --view 0.577,-0.577,0.577 --up -0.408,0.408,0.816",
        ),
    )
    add(
        p,
        "input",
        metavar="INPUT",
        help="a mesh file PyMeshLab reads (OBJ, PLY, STL, OFF, ...), paradox:NAME or a gallery model",
    )
    add(p, "output", metavar="OUT", help="the mescher file to write (.ply or .npz)")
    add(
        p,
        "--view",
        type=lambda s: s if s == "auto" else vector(s, "--view"),
        default=None,
        metavar="X,Y,Z|auto",
        help="direction from the model toward the camera (default: the sidecar "
        ".json's, else 0,0,1); 'auto': the view where the model's junctions line up",
    )
    add(
        p,
        "--up",
        type=lambda s: vector(s, "--up"),
        default=None,
        metavar="X,Y,Z",
        help="screen up (default: the sidecar .json's, else 0,1,0)",
    )
    add(
        p,
        "--view-start",
        type=lambda s: vector(s, "--view-start"),
        default=None,
        metavar="X,Y,Z",
        help="with --view auto: a view near the intended one (searched within 10 degrees of it)",
    )
    add(
        p,
        "--tol",
        type=float,
        default=None,
        metavar="T",
        help="gluing tolerance relative to the model's size (default: automatic)",
    )
    add(
        p,
        "--visible",
        action="store_true",
        help="take the seen-from-the-view route even for a cut model (by default the route is "
        "picked from the model: an open seam whose loops glue is glued there; anything else is "
        "seen from the view, false edges glued, hidden gaps bridged)",
    )
    add(
        p,
        "--perceive",
        choices=["manhattan"],
        default=None,
        help="'manhattan': snap normals to the perceived right angles (sheared tricks, reliefs)",
    )
    add(
        p,
        "--merge-tol",
        type=nonnegative,
        default=0.0,
        metavar="D",
        help="3D distance under which the clean-up merges duplicate vertices (default 0: exact)",
    )
    p.set_defaults(func=_cmd_convert)


def _parser_render(sub: Any) -> None:
    """The ``render`` subcommand and its options."""
    p = sub.add_parser(
        "render",
        help="render a mescher head-on to a PNG",
        formatter_class=_RAW,
        description="Render a mescher in its depth order (or its cut/bent embedding) under "
        "directional lights and an optional environment map.",
        epilog=examples(
            "render penrose_triangle -o penrose.png --light 1,1,1 --light -1,0,1 --shading smooth",
            "render paradox:penrose_triangle -o bent.png --representation bent --env studio",
        ),
    )
    add_input(p)
    add(p, "-o", "--output", required=True, metavar="PNG", help="the image to write (.png)")
    add(
        p,
        "--light",
        action="append",
        type=lambda s: vector(s, "--light"),
        metavar="X,Y,Z",
        help="direction toward a directional light, camera frame (repeatable; default 1,1,1)",
    )
    add(
        p,
        "--shading",
        choices=("flat", "smooth"),
        default="flat",
        help="per-face or interpolated normals (default %(default)s)",
    )
    add(
        p,
        "--env",
        default=None,
        metavar="MAP",
        help="environment map: studio, sky, uniform or a lat-long image",
    )
    add(
        p,
        "--representation",
        choices=("mescher", "cut", "bent"),
        default="mescher",
        help="draw the mescher in its depth order, or its cut or bent 3D embedding (default %(default)s)",
    )
    add(
        p,
        "--subdivide",
        type=int,
        default=0,
        metavar="N",
        help="midpoint subdivision levels before rendering (each level: 4x the faces; default 0)",
    )
    add(p, "--size", type=size, default=(800, 800), metavar="W,H", help=_SIZE_HELP)
    add_force(p)
    p.set_defaults(func=_cmd_render)


def _parser_geodesic(sub: Any) -> None:
    """The ``geodesic`` subcommand and its options."""
    from meschers_igl.geodesic import methods

    p = sub.add_parser(
        "geodesic",
        help="geodesic distance (heat method or exact) and a shortest path",
        formatter_class=_RAW,
        description="Geodesic distance from source vertices (heat method, or exact), optionally a shortest "
        "path to a target, a PNG with isolines and the path, and the distances as .npy.",
        epilog=examples("geodesic penrose_triangle --source 0 --target 35 -o distance.png"),
    )
    add_input(p)
    add(
        p,
        "--source",
        type=int,
        nargs="+",
        required=True,
        metavar="V",
        help="source vertex index (or several: distance to the nearest)",
    )
    add(
        p,
        "--target",
        type=int,
        default=None,
        metavar="V",
        help="draw and report a shortest path from the first source to this vertex",
    )
    add(
        p,
        "--method",
        default=None,
        metavar="NAME",
        help=f"one of the registry meschers_igl.geodesic.SOLVERS: {', '.join(methods())} "
        "(exact: window propagation; covering: MMP on a covering; the others: heat-method "
        "presets); default: auto, the library's heat method",
    )
    add(p, "-o", "--output", metavar="PNG", help="render the distance with isolines (and the path)")
    add(p, "--save", metavar="NPY", help="save the (#V,) distances as a .npy file")
    add(
        p,
        "--isolines",
        type=int,
        default=12,
        metavar="K",
        help="isolines in the PNG (default %(default)s)",
    )
    add(p, "--size", type=size, default=(800, 800), metavar="W,H", help=_SIZE_HELP)
    p.set_defaults(func=_cmd_geodesic)


def _parser_smooth(sub: Any) -> None:
    """The ``smooth`` subcommand and its options."""
    p = sub.add_parser(
        "smooth",
        help="Laplacian smoothing of xy and/or zeta (periods kept)",
        formatter_class=_RAW,
        description="Implicit Laplacian smoothing of screen positions and of the exact part of the "
        "depths (paper Sec. 4.4); the harmonic part and every period are kept.",
        epilog=examples("smooth penrose_triangle -o smooth.ply --t-xy 0.05 --t-zeta 0.05"),
    )
    add_input(p)
    add_mescher_output(p)
    add(
        p,
        "--t-xy",
        type=nonnegative,
        default=0.0,
        metavar="T",
        help="diffusion time for the screen positions, in squared screen units (default 0: kept)",
    )
    add(
        p,
        "--t-zeta",
        type=nonnegative,
        default=0.0,
        metavar="T",
        help="diffusion time for the exact part of the depths (default 0: kept)",
    )
    add(
        p,
        "--iterations",
        type=int,
        default=1,
        metavar="N",
        help="repeat, rebuilding the operators each time (default %(default)s)",
    )
    p.set_defaults(func=_cmd_smooth)


def _parser_subdivide(sub: Any) -> None:
    """The ``subdivide`` subcommand and its options."""
    p = sub.add_parser(
        "subdivide",
        help="1-to-4 subdivision (midpoint or Loop), depth order kept",
        formatter_class=_RAW,
        description="Subdivide a mescher; periods and local integrability are kept. A request whose "
        "result would not fit in memory is refused at once unless --force is given.",
        epilog=examples("subdivide penrose_triangle -o fine.ply --levels 2 --scheme loop"),
    )
    add_input(p)
    add_mescher_output(p)
    add(
        p,
        "--levels",
        type=int,
        default=1,
        metavar="N",
        help="subdivision levels; each multiplies the faces by 4 (default %(default)s)",
    )
    add(
        p,
        "--scheme",
        choices=("midpoint", "loop"),
        default="midpoint",
        help="midpoint split (the surface is unchanged) or Loop subdivision of the covering "
        "(default %(default)s)",
    )
    add_force(p)
    p.set_defaults(func=_cmd_subdivide)


def _parser_view(sub: Any) -> None:
    """The ``view`` subcommand and its options."""
    p = sub.add_parser(
        "view",
        help="interactive view (needs a display)",
        formatter_class=_RAW,
        description="Open an interactive window: sliders move the light, 's' cycles scalars, "
        "'f' toggles flat/smooth, 'r' selects faces to put in front.",
        epilog=examples("view penrose_triangle"),
    )
    add_input(p)
    add(
        p,
        "--shading",
        choices=("flat", "smooth"),
        default="flat",
        help="per-face or interpolated normals (default %(default)s)",
    )
    add(
        p,
        "--size",
        type=size,
        default=(900, 900),
        metavar="W,H",
        help="window size in pixels (default 900,900)",
    )
    p.set_defaults(func=_cmd_view)


def _parser_inverse(sub: Any) -> None:
    """The ``inverse`` subcommand and its options."""
    p = sub.add_parser(
        "inverse",
        help="recover a mescher from a picture (needs torch)",
        formatter_class=_RAW,
        add_help=False,
        description="Inverse rendering (paper Sec. 4.5); arguments go to "
        "meschers.inverse_cli ('meschers inverse --help' for them).",
        epilog=examples("inverse target.png --light 0,0,1 --out fit --init torus --iters 300"),
    )
    add(p, "rest", nargs=argparse.REMAINDER, help="arguments of the inverse command")
    p.set_defaults(func=_cmd_inverse)


_VECTOR_OPTIONS = ("--view", "--up", "--light")

#: The compiled kernel groups (:mod:`meschers.warmup`) each command uses: compiled as the command
#: reaches them, with a notice the first time (the study compiles them up front, in parallel).
_KERNELS = {
    "render": ("order", "render"),
    "geodesic": ("order", "geodesic", "render"),
    "smooth": ("order",),
    "subdivide": ("order",),
    "convert": ("order",),
}


def _compile_first(args: argparse.Namespace) -> None:
    groups = _KERNELS.get(getattr(args, "command", None) or "", ())
    if groups:
        from .warmup import announce_compilation

        announce_compilation(lambda line: print(line, file=sys.stderr), groups)


def _join_negative_vectors(argv: list[str]) -> list[str]:
    """``--up -0.4,0.4,0.8`` -> ``--up=-0.4,0.4,0.8``: argparse would take the leading minus of
    a comma-separated vector for an option."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        tok = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else ""
        if (
            tok in _VECTOR_OPTIONS
            and len(nxt) > 1
            and nxt[0] == "-"
            and (nxt[1].isdigit() or nxt[1] == ".")
        ):
            out.append(f"{tok}={nxt}")
            i += 2
        else:
            out.append(tok)
            i += 1
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``meschers`` with ``argv`` (default ``sys.argv[1:]``); returns the exit status.

    User errors (:class:`MescherError`, a missing file, a bad option) print one line
    ``meschers: error: ...`` on stderr and return 2; other exceptions propagate.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        argv = _join_negative_vectors(argv)
        if argv[:1] == ["inverse"]:  # hand everything after 'inverse' over, '--help' included
            args = argparse.Namespace(rest=argv[1:], func=_cmd_inverse, command="inverse")
        else:
            args = parser.parse_args(argv)
        _compile_first(args)
        token = FORCE_HINT.set("add --force")  # size guards speak of the option, not the keyword
        try:
            return int(args.func(args) or 0)
        finally:
            FORCE_HINT.reset(token)
    except _UsageError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except SystemExit as exc:  # --help / --version, or a delegated parser's exit
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    except (MescherError, FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"{PROG}: error: {msg}", file=sys.stderr)
        return 2
    except ImportError as exc:  # an optional dependency (torch, a display backend) is missing
        msg = str(exc).splitlines()[0] if str(exc) else repr(exc)
        print(f"{PROG}: error: {msg}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # 'meschers info x | head': the reader left, nothing to report
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
