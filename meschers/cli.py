"""The ``meschers`` command line: the comparison study and everyday work on meschers.

``meschers study`` runs every operation of the paper on the built-in gallery and writes an HTML
report; the other subcommands each wrap one library call::

    meschers study --quick --out study        # report in study/index.html
    meschers info penrose_triangle            # counts, genus, periods
    meschers convert model.obj model.ply --view 1,1,1 --up 0,0,1
    meschers render model.ply -o model.png --light 1,1,1 --light -1,0,1
    meschers geodesic model.ply --source 0 --target 10 -o distance.png
    meschers smooth model.ply -o smooth.ply --t-xy 0.01 --t-zeta 0.01
    meschers subdivide model.ply -o fine.ply --levels 2
    meschers view model.ply                   # interactive (needs a display)
    meschers inverse target.png --light 0,0,1 --out fit

A user error (missing or corrupt file, unknown model, bad option) prints one line
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

__all__ = ["describe", "load_input", "main"]

PROG = "meschers"


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (no usage block) and no exit inside :func:`main`."""

    def error(self, message: str):  # type: ignore[override]
        raise _UsageError(f"{message} (see '{self.prog} --help')")


class _UsageError(Exception):
    pass


# ------------------------------------------------------------------------------------------------
# helpers
# ------------------------------------------------------------------------------------------------
def _vector(text: str, name: str = "vector", n: int = 3) -> tuple[float, ...]:
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


def _size(text: str) -> tuple[int, int]:
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


def _nonnegative(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = -1.0
    if not np.isfinite(v) or v < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, found {text!r}")
    return v


def describe(m: Any, order: Any = None) -> dict:
    """Counts, topology, impossibility and periods of a mescher (``meschers info``).

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional

    Returns
    -------
    dict
        ``vertices``, ``edges``, ``faces``, ``euler_characteristic`` (V - E + F), ``components``,
        ``boundary_loops``, ``genus`` (sum over components of ``(2 - chi_i - b_i) / 2``, the
        surface being orientable), ``impossible``, ``periods``, ``max_integrability_residual``
        and, with an order, ``depth_arcs`` and ``depth_cycles``.
    """
    from meschers_igl import topology

    F = np.asarray(m.F)
    n = int(m.n_vertices)
    n_comp, label = topology.connected_components(F, n)
    loops = topology.boundary_loops(F)
    chi = int(m.n_vertices) - int(m.n_edges) + int(m.n_faces)
    # genus summed over components: 2 - 2 g_i - b_i = chi_i, so sum g_i = (2c - chi - b) / 2
    used = np.zeros(n, dtype=bool)
    used[F.ravel()] = True
    n_comp_used = int(np.unique(np.asarray(label)[used]).size)
    genus2 = 2 * n_comp_used - chi - len(loops)
    periods = np.asarray(m.periods(), dtype=np.float64)
    info = {
        "vertices": n,
        "edges": int(m.n_edges),
        "faces": int(m.n_faces),
        "euler_characteristic": chi,
        "components": n_comp_used,
        "boundary_loops": len(loops),
        "genus": genus2 // 2 if genus2 % 2 == 0 else genus2 / 2,
        "impossible": bool(m.is_impossible()),
        "periods": periods.tolist(),
        "max_integrability_residual": float(np.abs(m.integrability_residual()).max(initial=0.0)),
    }
    if order is not None:
        info["depth_arcs"] = int(order.n_arcs)
        info["depth_cycles"] = len(order.cycles(warn=False))
    return info


def load_input(spec: str) -> tuple[Any, Any, str]:
    """A mescher from a gallery model name or a ``.ply`` / ``.npz`` mescher file.

    Returns
    -------
    (Mescher, DepthOrder or None, label)
    """
    from meschers_igl import io

    path = Path(spec)
    if path.suffix.lower() in (".ply", ".npz") or path.exists():
        if not path.is_file():
            raise MescherError(
                f"INPUT: expected an existing .ply or .npz mescher file, found nothing at '{spec}'"
            )
        if path.suffix.lower() not in (".ply", ".npz"):
            raise MescherError(
                f"INPUT: expected a .ply or .npz mescher file, found '{path.name}' "
                f"(convert an artist model first: meschers convert {spec} OUT.ply --view X,Y,Z)"
            )
        m, order = io.load(path, return_order=True)
        return m, order, str(path)
    from meschers_igl.gallery import get_model, list_models

    if spec not in list_models():
        raise MescherError(
            f"INPUT: expected a .ply/.npz mescher file or a gallery model "
            f"({', '.join(list_models())}), found {spec!r}"
        )
    g = get_model(spec)
    return g.mescher, g.order, spec


def _out_path(text: str, suffixes: Sequence[str], name: str = "OUT") -> Path:
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


def _headless_views():
    """Import pyvista_views for an off-screen render (EGL without a display)."""
    import pyvista

    import pyvista_views
    from pyvista_views._offscreen import has_display

    if not has_display():
        pyvista.OFF_SCREEN = True
    return pyvista_views


def _save_png(image: np.ndarray, path: Path) -> None:
    from PIL import Image

    Image.fromarray(np.ascontiguousarray(image)).save(path)


def _print_info(info: dict, label: str) -> None:
    periods = info["periods"]
    print(f"{label}")
    print(f"  vertices {info['vertices']}, edges {info['edges']}, faces {info['faces']}")
    print(
        f"  Euler characteristic {info['euler_characteristic']}, components {info['components']}, "
        f"boundary loops {info['boundary_loops']}, genus {info['genus']}"
    )
    print(f"  impossible: {'yes' if info['impossible'] else 'no'}")
    print(
        "  periods: " + (", ".join(f"{p:.6g}" for p in periods) if periods else "none (no loops)")
    )
    if "depth_arcs" in info:
        print(f"  depth order: {info['depth_arcs']} arcs, {info['depth_cycles']} cycles")


# ------------------------------------------------------------------------------------------------
# subcommands
# ------------------------------------------------------------------------------------------------
def _cmd_study(args: argparse.Namespace) -> int:
    from .study import run_study

    _headless_views()
    models = None
    if args.models:
        models = [n.strip() for chunk in args.models for n in chunk.split(",") if n.strip()]
    result = run_study(models, out=args.out, quick=args.quick, progress=not args.no_progress,
                       other_tools=not args.no_other_tools)  # fmt: skip
    print(f"wrote {result.index} ({result.metrics['runtime_s']:.1f} s)")
    for err in result.errors:
        print(f"{PROG}: step failed: {err}", file=sys.stderr)
    return 1 if result.errors else 0


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

    src = Path(args.input)
    if not src.is_file():
        raise MescherError(f"INPUT: expected an existing mesh file, found nothing at '{src}'")
    out = _out_path(args.output, (".ply", ".npz"))
    from meshlab_filters import cut_model_to_mescher, load_artist_model

    V, F, report = load_artist_model(src, merge_tol=args.merge_tol)
    print(report)
    m, order = cut_model_to_mescher((V, F), view=args.view, up=args.up, tol=args.tol)
    io.save(m, out, order=order)
    _print_info(describe(m, order), f"wrote {out}")
    return 0


def _cmd_render(args: argparse.Namespace) -> int:
    m, order, _ = load_input(args.input)
    out = _out_path(args.output, (".png",), "-o")
    if args.subdivide:
        m, order = _subdivide(m, order, args.subdivide)
    pvv = _headless_views()
    image = pvv.render(
        m, order=order if args.representation == "mescher" else None,
        lights=args.light or [(1.0, 1.0, 1.0)], shading=args.shading, env_map=args.env,
        window_size=args.size, representation=args.representation, anti_aliasing=True,
    )  # fmt: skip
    _save_png(image, out)
    print(f"wrote {out} ({image.shape[1]} x {image.shape[0]})")
    return 0


def _subdivide(m: Any, order: Any, levels: int, scheme: str = "midpoint") -> tuple:
    if order is None:
        return m.subdivide(levels, scheme=scheme), None
    return m.subdivide(levels, scheme=scheme, order=order)


def _cmd_geodesic(args: argparse.Namespace) -> int:
    from meschers_igl.heat import HeatGeodesicSolver

    m, order, _ = load_input(args.input)
    solver = HeatGeodesicSolver(m, method=args.method)
    d = solver.distance(args.source)
    finite = np.isfinite(d)
    print(f"distance from vertex(es) {', '.join(map(str, args.source))}: max {d[finite].max():.6g}, "
          f"mean {d[finite].mean():.6g}, unreachable vertices {int((~finite).sum())}")  # fmt: skip
    path = None
    if args.target is not None:
        path = m.shortest_path(args.source[0], args.target)
        print(f"shortest path {args.source[0]} -> {args.target}: length {path.length:.6g}, "
              f"{path.n_points} points (distance field: {d[args.target]:.6g})")  # fmt: skip
    if args.save:
        out = _out_path(args.save, (".npy",), "--save")
        np.save(out, d)
        print(f"wrote {out}")
    if args.output:
        out = _out_path(args.output, (".png",), "-o")
        pvv = _headless_views()
        size = args.size
        from pyvista_views.render import _xy_box, default_bounds

        from .study import _overlay

        bounds = default_bounds(_xy_box(np.asarray(m.xy)), size)
        image = pvv.render(m, order=order, shading="smooth", scalars=d, isolines=args.isolines,
                           window_size=size, bounds=bounds, anti_aliasing=True)  # fmt: skip
        if path is not None:
            P = np.asarray(path.xy)
            image = _overlay(image, bounds, segments=[(np.stack([P[:-1], P[1:]], 1), "#ff2020", 3)],
                             points=[(P[[0]], "white", 5), (P[[-1]], "#ff2020", 5)])  # fmt: skip
        _save_png(image, out)
        print(f"wrote {out}")
    return 0


def _cmd_smooth(args: argparse.Namespace) -> int:
    from meschers_igl import io

    m, order, _ = load_input(args.input)
    out = _out_path(args.output, (".ply", ".npz"), "-o")
    ms = m.smooth(t_xy=args.t_xy, t_zeta=args.t_zeta, iterations=args.iterations)
    p0, p1 = np.asarray(m.periods()), np.asarray(ms.periods())
    io.save(ms, out, order=order)
    print(f"wrote {out}: t_xy {args.t_xy:g}, t_zeta {args.t_zeta:g}, {args.iterations} iteration(s); "
          f"largest period change {np.abs(p1 - p0).max(initial=0.0):.2e}")  # fmt: skip
    return 0


def _cmd_subdivide(args: argparse.Namespace) -> int:
    from meschers_igl import io

    m, order, _ = load_input(args.input)
    out = _out_path(args.output, (".ply", ".npz"), "-o")
    ms, order_s = _subdivide(m, order, args.levels, args.scheme)
    io.save(ms, out, order=order_s)
    print(f"wrote {out}: {m.n_faces} -> {ms.n_faces} faces ({args.scheme}, {args.levels} level(s))")
    return 0


def _cmd_view(args: argparse.Namespace) -> int:
    m, order, _ = load_input(args.input)
    from pyvista_views._offscreen import has_display

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


# ------------------------------------------------------------------------------------------------
# parser
# ------------------------------------------------------------------------------------------------
def _examples(*lines: str) -> str:
    return "example:\n" + "\n".join(f"  {PROG} {ln}" for ln in lines)


def build_parser() -> argparse.ArgumentParser:
    """The ``meschers`` argument parser (one subparser per subcommand)."""
    parser = _Parser(
        prog=PROG,
        description="Geometry processing of impossible objects (meschers; Dodik et al., ACM TOG 2025).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=_examples("study --quick --out study", "info penrose_triangle"),
    )
    from meschers_igl import __version__

    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    raw = argparse.RawDescriptionHelpFormatter
    inp = "a gallery model name (see 'meschers info --list') or a .ply/.npz mescher file"

    p = sub.add_parser("study", help="run the comparison study on the gallery; write an HTML report",
                       formatter_class=raw, description="Every operation of the paper on the built-in gallery, "
                       "mescher vs cut vs bent, written to OUT/index.html with PNGs and metrics.json.",
                       epilog=_examples("study", "study --quick --models penrose_triangle,impossibagel --out study"))  # fmt: skip
    p.add_argument(
        "--models",
        action="append",
        metavar="NAMES",
        help="comma-separated gallery models (default: all)",
    )
    p.add_argument(
        "--out",
        default="meschers_study",
        metavar="DIR",
        help="output folder (default: meschers_study)",
    )
    p.add_argument(
        "--quick", action="store_true", help="small renders, one subdivision level (<= 2 minutes)"
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument(
        "--no-other-tools", action="store_true", help="leave out the ParadoxToolkit section"
    )
    p.set_defaults(func=_cmd_study)

    p = sub.add_parser("info", help="counts, genus, components, impossible?, periods", formatter_class=raw,
                       description="Describe a mescher.", epilog=_examples("info penrose_triangle", "info model.ply --json"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", nargs="?", help=inp)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--list", action="store_true", help="list the gallery models")
    p.set_defaults(func=_cmd_info_or_list)

    p = sub.add_parser("convert", help="artist cut model (OBJ, PLY, ...) -> .ply mescher", formatter_class=raw,
                       description="Load and clean an artist's cut model with PyMeshLab, glue its seam into a mescher "
                       "seen from --view, and save it with its depth order. Prints the clean-up report.",
                       epilog=_examples("convert penrose_triangle.obj penrose.ply --view 0.577,-0.577,0.577 --up -0.408,0.408,0.816"))  # fmt: skip
    p.add_argument(
        "input", metavar="INPUT", help="mesh file PyMeshLab reads (OBJ, PLY, STL, OFF, ...)"
    )
    p.add_argument("output", metavar="OUT", help="the mescher file (.ply or .npz)")
    p.add_argument("--view", type=lambda s: _vector(s, "--view"), default=(0.0, 0.0, 1.0), metavar="X,Y,Z",
                   help="direction from the model toward the camera (default 0,0,1)")  # fmt: skip
    p.add_argument("--up", type=lambda s: _vector(s, "--up"), default=(0.0, 1.0, 0.0), metavar="X,Y,Z",
                   help="screen up (default 0,1,0)")  # fmt: skip
    p.add_argument(
        "--tol", type=float, default=None, help="gluing tolerance relative to the model's size"
    )
    p.add_argument(
        "--merge-tol",
        type=_nonnegative,
        default=0.0,
        help="3D duplicate-vertex distance of the clean-up",
    )
    p.set_defaults(func=_cmd_convert)

    p = sub.add_parser("render", help="render a mescher head-on to a PNG", formatter_class=raw,
                       description="Render a mescher in its depth order (or its cut/bent embedding) under "
                       "directional lights and an optional environment map.",
                       epilog=_examples("render penrose_triangle -o penrose.png --light 1,1,1 --light -1,0,1 --shading smooth",
                                        "render model.ply -o bent.png --representation bent --env studio"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", help=inp)
    p.add_argument("-o", "--output", required=True, metavar="PNG")
    p.add_argument("--light", action="append", type=lambda s: _vector(s, "--light"), metavar="X,Y,Z",
                   help="direction toward a directional light, camera frame (repeatable; default 1,1,1)")  # fmt: skip
    p.add_argument("--shading", choices=("flat", "smooth"), default="flat")
    p.add_argument(
        "--env",
        default=None,
        metavar="MAP",
        help="environment map: studio, sky, uniform or a lat-long image",
    )
    p.add_argument("--representation", choices=("mescher", "cut", "bent"), default="mescher")
    p.add_argument(
        "--subdivide", type=int, default=0, metavar="N", help="midpoint subdivision levels first"
    )
    p.add_argument("--size", type=_size, default=(800, 800), metavar="W,H")
    p.set_defaults(func=_cmd_render)

    p = sub.add_parser("geodesic", help="heat-method geodesic distance and a shortest path", formatter_class=raw,
                       description="Geodesic distance from source vertices (heat method), optionally a shortest "
                       "path to a target, a PNG with isolines and the path, and the distances as .npy.",
                       epilog=_examples("geodesic penrose_triangle --source 0 --target 30 -o distance.png"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", help=inp)
    p.add_argument("--source", type=int, nargs="+", required=True, metavar="V")
    p.add_argument(
        "--target", type=int, default=None, metavar="V", help="draw and report a shortest path"
    )
    p.add_argument("--method", choices=("standard", "accurate"), default="standard")
    p.add_argument("-o", "--output", metavar="PNG", help="render the distance")
    p.add_argument("--save", metavar="NPY", help="save the (#V,) distances")
    p.add_argument("--isolines", type=int, default=12)
    p.add_argument("--size", type=_size, default=(800, 800), metavar="W,H")
    p.set_defaults(func=_cmd_geodesic)

    p = sub.add_parser("smooth", help="Laplacian smoothing of xy and/or zeta (periods kept)", formatter_class=raw,
                       description="Implicit Laplacian smoothing of screen positions and of the exact part of the "
                       "depths (paper Sec. 4.4); the harmonic part and every period are kept.",
                       epilog=_examples("smooth penrose_triangle -o smooth.ply --t-xy 0.05 --t-zeta 0.05"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", help=inp)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help=".ply or .npz")
    p.add_argument(
        "--t-xy", type=_nonnegative, default=0.0, help="diffusion time for xy (length^2)"
    )
    p.add_argument("--t-zeta", type=_nonnegative, default=0.0, help="diffusion time for the depths")
    p.add_argument("--iterations", type=int, default=1)
    p.set_defaults(func=_cmd_smooth)

    p = sub.add_parser("subdivide", help="1-to-4 subdivision (midpoint or Loop), depth order kept", formatter_class=raw,
                       description="Subdivide a mescher; periods and local integrability are kept.",
                       epilog=_examples("subdivide penrose_triangle -o fine.ply --levels 2 --scheme loop"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", help=inp)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help=".ply or .npz")
    p.add_argument("--levels", type=int, default=1)
    p.add_argument("--scheme", choices=("midpoint", "loop"), default="midpoint")
    p.set_defaults(func=_cmd_subdivide)

    p = sub.add_parser("view", help="interactive view (needs a display)", formatter_class=raw,
                       description="Open an interactive window: sliders move the light, 's' cycles scalars, "
                       "'f' toggles flat/smooth, 'r' selects faces to put in front.",
                       epilog=_examples("view penrose_triangle"))  # fmt: skip
    p.add_argument("input", metavar="INPUT", help=inp)
    p.add_argument("--shading", choices=("flat", "smooth"), default="flat")
    p.add_argument("--size", type=_size, default=(900, 900), metavar="W,H")
    p.set_defaults(func=_cmd_view)

    p = sub.add_parser("inverse", help="recover a mescher from a picture (needs torch)", formatter_class=raw,
                       add_help=False, description="Inverse rendering (paper Sec. 4.5); arguments go to "
                       "meschers.inverse_cli ('meschers inverse --help' for them).",
                       epilog=_examples("inverse target.png --light 0,0,1 --out fit --init torus --iters 300"))  # fmt: skip
    p.add_argument("rest", nargs=argparse.REMAINDER, help="arguments of the inverse command")
    p.set_defaults(func=_cmd_inverse)
    return parser


def _cmd_info_or_list(args: argparse.Namespace) -> int:
    if args.list or args.input is None:
        from meschers_igl.gallery import get_model, list_models

        if args.input is None and not args.list:
            raise MescherError("INPUT: expected a gallery model or a .ply/.npz file, found nothing")
        for name in list_models():
            print(f"{name:22s} {get_model(name).description}")
        return 0
    return _cmd_info(args)


_VECTOR_OPTIONS = ("--view", "--up", "--light")


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
        if argv[:1] == ["inverse"]:  # hand everything after 'inverse' over, '--help' included
            args = argparse.Namespace(rest=argv[1:], func=_cmd_inverse)
        else:
            args = parser.parse_args(_join_negative_vectors(argv))
        return int(args.func(args) or 0)
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
        print(f"{PROG}: error: {str(exc).splitlines()[0] if str(exc) else exc!r}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
