"""``meschers inverse TARGET [--light X,Y,Z] --out DIR [--init picture|torus] [--iters N]``.

Recovers a mescher from a picture (paper Section 4.5): the target image spans the
screen square ``[-1, 1]^2`` (pixel centres, y up), lit by the given directional lights; an
oblong one is centred in a square of its longer side, the margins its ground's colour.  The
default initialization starts from the picture itself
(:func:`meschers_igl.inverse.picture.mescher_from_picture`); ``--init torus`` is the paper's.
Writes into ``DIR``:

- ``mescher.ply``: the recovered mescher with its extracted depth order (``meschers_igl.save``);
- ``target.png``, ``init.png``, ``render.png``: the target as fitted, the initialization and
  the result; ``renders/step_NNNNN.png``: intermediate renders every ``--every`` steps;
- ``loss.png``: the loss curve and the PSNR curve; ``before_after.png``: the three side by side;
- ``metrics.json``: silhouette IoU, PSNR (start, end, curve), periods, the period around the
  outline (``figure_period``), the light used (``light``; ``light_estimated`` when no
  ``--light`` was given and the picture's creases and shades fixed it), CPU and wall time.

``TARGET`` may also be a black-on-white line drawing of a figure of boxes (told apart by
:func:`meschers_igl.inverse.drawing.is_line_drawing`): its closed regions become faces shaded by
their Manhattan reading (:func:`meschers_igl.inverse.drawing.shade_drawing`, saved as
``drawing_shaded.png``), which is then fitted as a picture.

``TARGET`` may be a built-in: ``penrose`` (the Penrose triangle drawn by this package's own
rasterizer) or ``tribar``, ``cube``, ``stairs``: real 3D box models
(:mod:`meschers_igl.inverse.models`) rendered by PyVista's z-buffer (:func:`zbuffer_picture`).
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_count, as_vector

DEFAULT_LIGHT = "0.6,-0.1,1"

#: the working resolution when ``--resolution`` is not given
DEFAULT_RESOLUTION = 128

#: a drawing whose narrowest face would come under this many pixels wide at the default
#: resolution is read at twice it: a bar two or three pixels wide meshes into slivers and
#: wedges that the fit cannot smooth away
DRAWING_FACE_PX = 4.0
#: built-in targets: the soft-rasterized Penrose triangle and z-buffered box models
BUILTIN = ("penrose", "tribar", "cube", "stairs")


def picture_frame(model, extent: float = 0.8) -> tuple[np.ndarray, float, np.ndarray]:
    """Where :func:`zbuffer_picture` puts ``model``: its screen box centred, the longer side
    spanning ``2 extent`` of the screen square ``[-1, 1]^2``.

    Returns
    -------
    C : (#V, 3) float64
        The vertices in the camera frame (right, up, toward the viewer), model units.
    scale : float
        Screen units per model unit: screen ``xy = (C[:, :2] - box centre) * scale``.
    centre : (3,) float64
        The box's centre at the model's mean depth, in model coordinates.
    """
    R = model.camera_frame()
    C = model.V @ R.T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    scale = 2.0 * extent / float((hi - lo).max())
    centre = np.r_[0.5 * (lo + hi), C[:, 2].mean()] @ R  # back to model coordinates
    return C, scale, centre


def aim_camera(pl, model, C: np.ndarray, scale: float, centre: np.ndarray) -> None:
    """Point the plotter ``pl``'s orthographic camera as :func:`zbuffer_picture` does
    (``C, scale, centre`` from :func:`picture_frame`), its clipping range around the model."""
    span = float(np.ptp(C, axis=0).max()) + 1.0
    pl.camera.enable_parallel_projection()
    pl.camera.focal_point = tuple(centre)
    pl.camera.position = tuple(centre + span * 4.0 * model.view)
    pl.camera.up = tuple(model.up)
    pl.camera.parallel_scale = 1.0 / scale  # half the screen height, model units
    pl.camera.clipping_range = (span, span * 8.0)


def zbuffer_picture(
    model,
    resolution: int = 128,
    light=(0.4, 0.25, 1.0),
    ambient: float = 0.2,
    extent: float = 0.8,
    background=(1.0, 1.0, 1.0),
    return_depth: bool = False,
):
    """A picture of a real 3D model by PyVista's z-buffer (not by the code under test).

    Orthographic camera along ``model.view`` with ``model.up`` up; the model's screen box is
    centred and its longer side spans ``2 extent`` of the screen square ``[-1, 1]^2``; one
    directional light toward ``light`` (camera frame) with flat Lambertian shading
    ``ambient + (1 - ambient) max(0, n . l)``, no specular, no anti-aliasing (pixel centres are
    sampled, as :func:`meschers_igl.inverse.rasterizer.soft_rasterize` does at small sigma).

    Parameters
    ----------
    model : meschers_igl.inverse.models.BoxModel
    resolution : int
    light : (3,) float
        Direction toward the light in the camera frame (right, up, toward the viewer).
    ambient : float
    extent : float
    background : (3,) float
        The ground's colour, each channel in [0, 1] (integers too: ``(1, 1, 1)`` is white).

    Returns
    -------
    image : (resolution, resolution, 3) float64 in [0, 1]
    scale : float
        Screen units per model unit (depths scale the same way).
    depth : (resolution, resolution) float64, only with ``return_depth``
        The z-buffer in screen units, larger nearer the viewer (NaN on the background).
    """
    import pyvista as pv

    from pyvista_views.headless import configure_headless

    configure_headless()  # EGL/OSMesa without a display, before the first window
    res = as_count(resolution, "resolution", minimum=8)
    ground = as_vector(background, "background", 3)
    if not np.all((ground >= 0.0) & (ground <= 1.0)):
        raise MescherError(
            f"background: expected an RGB colour of three numbers in [0, 1], found {background!r}"
        )
    R = model.camera_frame()
    C, scale, centre = picture_frame(model, extent)
    faces = np.hstack([np.full((len(model.F), 1), 3), model.F]).ravel()
    mesh = pv.PolyData(model.V, faces)
    pl = pv.Plotter(off_screen=True, window_size=(res, res), lighting="none")
    try:
        pl.disable_anti_aliasing()
        # floats in [0, 1], as the returned picture: PyVista reads integers as 0-255
        pl.set_background(tuple(float(c) for c in ground))
        pl.add_mesh(
            mesh,
            color="white",
            ambient=ambient,
            diffuse=1.0 - ambient,
            specular=0.0,
            smooth_shading=False,
            lighting=True,
        )
        lw = np.asarray(light, dtype=np.float64) @ R  # toward the light, model coordinates
        lw = lw / np.linalg.norm(lw)
        pl.add_light(
            pv.Light(
                position=tuple(centre + lw),
                focal_point=tuple(centre),
                light_type="scene light",
                positional=False,
                intensity=1.0,
            )
        )
        aim_camera(pl, model, C, scale, centre)
        img = pl.screenshot(return_img=True)
        # PyVista's depth is the (negative) distance from the camera: toward the viewer is up
        depth = (
            np.asarray(pl.get_image_depth(reset_camera_clipping_range=False), dtype=np.float64)
            * scale
            if return_depth
            else None
        )
    finally:
        pl.close()
    image = np.asarray(img[..., :3], dtype=np.float64) / 255.0
    return (image, scale, depth) if return_depth else (image, scale)


def _triple(text: str, name: str) -> tuple[float, float, float]:
    try:
        vals = tuple(float(t) for t in str(text).split(","))
    except ValueError:
        vals = ()
    if len(vals) != 3 or not all(math.isfinite(v) for v in vals):
        raise MescherError(f"{name}: expected three comma-separated numbers X,Y,Z, found {text!r}")
    return vals  # type: ignore[return-value]


def _join_negative_values(argv: list[str]) -> list[str]:
    """``--light -0.5,0.35,1`` as ``--light=-0.5,0.35,1``: argparse takes a value that starts
    with a dash and is not a plain number for an option."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in ("--light", "--light-color") and i + 1 < len(argv) and argv[i + 1][:1] == "-":
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``meschers inverse`` arguments to ``parser`` (returned)."""
    parser.add_argument(
        "target",
        help="target image spanning the screen square (an oblong one is centred in a square of "
        f"its ground's colour), or a built-in: {', '.join(BUILTIN)}",
    )
    parser.add_argument(
        "--light",
        action="append",
        default=None,
        metavar="X,Y,Z",
        help="direction toward a light, camera frame (negative components are "
        "fine: --light -0.5,0.35,1); repeat for several; default: estimated "
        f"from the picture with --init picture, else {DEFAULT_LIGHT}",
    )
    parser.add_argument(
        "--light-color",
        action="append",
        default=None,
        metavar="R,G,B",
        help="RGB intensity of each --light, in the same order "
        "(default white, (1 - ambient) / #lights each)",
    )
    parser.add_argument("--ambient", type=float, default=0.2, help="ambient light (default 0.2)")
    parser.add_argument("--out", required=True, help="output folder (created)")
    parser.add_argument(
        "--init",
        choices=["picture", "torus"],
        default="picture",
        help="initialization: from the picture (segment, triangulate, lift; "
        "needs one white light) or a torus (default picture)",
    )
    parser.add_argument("--iters", type=int, default=300, help="steps (default 300)")
    parser.add_argument(
        "--resolution",
        type=int,
        default=None,
        help=f"working resolution; the target is resampled (default {DEFAULT_RESOLUTION}; a "
        f"drawing whose narrowest face would come under {DRAWING_FACE_PX:g} px wide at "
        f"{DEFAULT_RESOLUTION}: {2 * DEFAULT_RESOLUTION})",
    )
    parser.add_argument(
        "--torus",
        default="96,24",
        metavar="N_MAJOR,N_MINOR",
        help="torus resolution for --init torus (default 96,24)",
    )
    parser.add_argument(
        "--power",
        type=int,
        choices=[1, 2],
        default=1,
        help="Sobolev preconditioner (I + lambda L)^-power (default 1)",
    )
    parser.add_argument("--device", default=None, help="torch device, e.g. cuda (default cpu)")
    parser.add_argument(
        "--every", type=int, default=50, help="save a render every so many steps (default 50)"
    )
    parser.add_argument("--force", action="store_true", help="skip the memory-size guard")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


def _check_resolution(res: int, force) -> None:
    """Refuse a working resolution whose fit would not fit in memory (unless forced)."""
    from meschers_igl.validate import check_budget

    # a soft rasterizer keeps per (face, pixel) pairs: about 2 kB per pixel at 128^2
    check_budget(
        float(res) * res,
        bytes_per_face=2048.0,
        what=f"inverse --resolution {res}",
        force=bool(force),
    )


def _drawing_resolution(faces: np.ndarray) -> int:
    """The working resolution for a drawing whose face regions are ``faces`` ((N, N), its
    own size): :data:`DEFAULT_RESOLUTION`, or twice it where the narrowest face would come
    under :data:`DRAWING_FACE_PX` wide (the impossible cube's bars, a stair's risers)."""
    from meschers_igl.inverse.drawing import narrowest_face_px

    width = narrowest_face_px(faces) * DEFAULT_RESOLUTION / faces.shape[0]
    return DEFAULT_RESOLUTION if width >= DRAWING_FACE_PX else 2 * DEFAULT_RESOLUTION


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="meschers inverse",
        description="Recover a mescher from a picture (or a black-on-white line drawing) by "
        "soft-rasterized inverse rendering.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="example:\n"
        "  meschers inverse penrose --out fit --resolution 64 --iters 100\n"
        "  meschers inverse picture.png --light -0.5,0.35,1 --out fit\n"
        "  meschers inverse drawing.png --out fit    # a line drawing; the light is estimated",
    )
    return add_arguments(p)


def _load_target(path: str, resolution: int) -> np.ndarray:
    from PIL import Image

    try:
        img = Image.open(path)
        img.load()
    except (OSError, ValueError) as exc:
        raise MescherError(
            f"TARGET: expected a readable image file, found {path!r} ({exc})"
        ) from exc
    return _box_resize(_squared(_as_rgb(img)), resolution)


def _squared(rgb: np.ndarray) -> np.ndarray:
    """``rgb`` (H, W, 3) centred in a square of side ``max(H, W)``, the margins filled with
    its corners' colour (the ground of a picture of an object that fits it): the screen
    square ``[-1, 1]^2`` a picture spans is that square."""
    H, W = rgb.shape[:2]
    if H == W:
        return rgb
    n = max(H, W)
    out = np.empty((n, n, 3))
    out[:] = _background(rgb)
    top, left = (n - H) // 2, (n - W) // 2
    out[top : top + H, left : left + W] = rgb
    return out


def _box_resize(rgb: np.ndarray, resolution: int) -> np.ndarray:
    """``rgb`` (N, N, 3) averaged over each new pixel's area (box filter) to ``resolution``
    (0: as it is), in 8-bit levels as a picture file holds them (a flat picture stays flat)."""
    from PIL import Image

    if rgb.shape[0] != resolution and resolution > 0:
        rgb = np.stack(
            [
                np.asarray(
                    Image.fromarray(rgb[..., c].astype(np.float32), "F").resize(
                        (resolution, resolution), Image.Resampling.BOX
                    ),
                    dtype=np.float64,
                )
                for c in range(3)
            ],
            axis=-1,
        )
    return np.clip(np.round(rgb * 255.0), 0.0, 255.0) / 255.0


def _as_rgb(img) -> np.ndarray:
    """(H, W, 3) float in [0, 1] of a PIL image of any mode: 16-bit and float grey scaled by
    their range (``convert("RGB")`` clips them to white), transparent pixels laid over white
    as on a page (their stored colour, often black, is not what anybody sees)."""
    mode = img.mode
    if mode.startswith("I") or mode == "F":
        a = np.asarray(img, dtype=np.float64)
        top = 65535.0 if (mode.startswith("I;16") or a.max() > 255.0) else 255.0
        if mode == "F" and a.max() <= 1.0:
            top = 1.0
        return np.repeat(np.clip(a / top, 0.0, 1.0)[..., None], 3, axis=2)
    if "A" in mode or "transparency" in img.info:
        rgba = np.asarray(img.convert("RGBA"), dtype=np.float64) / 255.0
        alpha = rgba[..., 3:]
        return rgba[..., :3] * alpha + (1.0 - alpha)
    return np.asarray(img.convert("RGB"), dtype=np.float64) / 255.0


def _no_outlines(target: np.ndarray, bg: np.ndarray) -> np.ndarray:
    """The picture the fit compares with: dark lines an illustrator drew along the edges
    (:func:`meschers_igl.inverse.flatten.drop_outlines`) are no shading a mescher renders, so
    a picture with them is fitted flat and without them; marks beside the figure (a caption:
    :func:`~meschers_igl.inverse.flatten.drop_specks`) are ground; any other picture as it
    is."""
    from meschers_igl.inverse import flatten as fl

    # flattened once: the figure's mask of the picture and of its flat version are one
    flat = target if fl.is_flat(target) else fl.flatten_picture(target)
    fig = fl.figure_mask(flat, bg)
    clean, lines = fl.drop_outlines(target, bg, figure=fig)  # 1 px lines look like blends
    if not lines.any():
        clean, lines = fl.drop_outlines(flat, bg, figure=fig)
    if lines.any():
        return fl.drop_specks(clean, bg)[0]
    return fl.drop_specks(target, bg, figure=fig)[0]


def _resize_flat(image: np.ndarray, resolution: int) -> np.ndarray:
    """A flat-shaded picture at another size, nearest pixel (no new shades at the edges)."""
    n = image.shape[0]
    if n == resolution:
        return image
    idx = np.minimum(((np.arange(resolution) + 0.5) * n / resolution).astype(np.int64), n - 1)
    return image[idx][:, idx]


def _background(target: np.ndarray) -> np.ndarray:
    # the corners are background in any picture of an object that fits the screen square
    c = np.stack([target[0, 0], target[0, -1], target[-1, 0], target[-1, -1]])
    return np.median(c, axis=0)


def _save_png(path: Path, image: np.ndarray) -> None:
    from PIL import Image

    Image.fromarray((np.clip(image, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)).save(path)


#: Least side, in pixels, of each picture in ``before_after.png``: the start and the fitted
#: mescher are rendered again at this size (the working resolution when larger), and the target,
#: a picture of the working resolution, is enlarged by a whole factor, each pixel a block (no
#: new shades), and labelled so.
FIGURE_PIXELS = 256


def enlarge_nearest(image: np.ndarray, size: int) -> tuple[np.ndarray, int]:
    """``image`` enlarged by the least whole factor ``k`` that makes its shorter side at least
    ``size`` pixels, each pixel repeated as a ``k x k`` block (nearest neighbour), and ``k``.

    Returns
    -------
    (k H, k W, ...) ndarray and int
        ``image`` itself and 1 when it is large enough.
    """
    k = max(1, -(-int(size) // int(min(image.shape[:2]))))
    if k == 1:
        return image, 1
    return np.repeat(np.repeat(image, k, axis=0), k, axis=1), k


def figure_panels(target, m0, off0, result, background, shade: dict, init_name: str):
    """The three pictures of ``before_after.png`` and their titles: the target (enlarged by
    :func:`enlarge_nearest` when smaller than :data:`FIGURE_PIXELS`), the start and the result
    rendered at the enlarged target's size (nearly hard, ``sigma = 1e-6``), so no panel is
    a low-resolution render scaled up.

    Returns
    -------
    list of three (n, n, 3) float arrays in [0, 1], list of three str
    """
    from meschers_igl.inverse.rasterizer import render_mescher

    shown, k = enlarge_nearest(np.asarray(target, dtype=np.float64), FIGURE_PIXELS)
    n = int(shown.shape[0])
    pictures = [
        render_mescher(m, off, resolution=n, background=background, sigma=1e-6, **shade)
        for m, off in ((m0, off0), (result.mescher, result.offsets))
    ]
    side = int(np.asarray(target).shape[0])
    titles = [
        f"target ({side} px" + (f", shown {k}x, nearest)" if k > 1 else ")"),
        f"{init_name} init ({n} px)",
        f"result ({n} px)",
    ]
    return [shown, *pictures], titles


def _figures(out: Path, panels, titles, losses, psnrs) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .figures import compose

    fig, ax = plt.subplots(figsize=(5.5, 3.2), dpi=120)
    steps = np.arange(len(losses))
    # the two kinds of step render with different sigma: their losses are two curves
    ax.semilogy(steps[0::2], losses[0::2], lw=0.8, label="loss, xy steps")
    ax.semilogy(steps[1::2], losses[1::2], lw=0.8, label="loss, zeta steps")
    ax.set_xlabel("step")
    ax.set_ylabel("loss")
    if psnrs:
        ax2 = ax.twinx()
        ax2.plot([p[0] for p in psnrs], [p[1] for p in psnrs], "k.-", lw=0.8, label="PSNR")
        ax2.set_ylabel("PSNR of the nearly hard render (dB)")
        ax2.legend(loc="center right")
    ax.legend(loc="upper right")
    ax.set_title("inverse rendering")
    fig.tight_layout()
    fig.savefig(out / "loss.png")
    plt.close(fig)

    # the pictures pixel for pixel, side by side (no resampling by a plotting library)
    cells = [(np.clip(p, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8) for p in panels]
    compose([cells], col_labels=titles).save(out / "before_after.png")


def _builtin_target(name: str, res: int, lights, colors, ambient: float):
    """A built-in target image and, for the box models, the model (else None)."""
    from meschers_igl.inverse import models
    from meschers_igl.inverse.targets import penrose_target

    if name == "penrose":
        return penrose_target(res, lights=lights, light_colors=colors, ambient=ambient), None
    if len(lights) != 1 or colors is not None:
        raise MescherError(f"--light: expected one white light for {name!r}, found {len(lights)}")
    model = {
        "tribar": models.penrose_tribar,
        "cube": models.impossible_cube,
        "stairs": models.penrose_stairs,
    }[name]()
    image, scale = zbuffer_picture(model, res, light=lights[0], ambient=ambient)
    return image, (model, scale)


def _save_fit(
    out, args, target, bg, before, result, shade, drawing, model, iters, given, start
) -> dict:
    """Write the fitted mescher (with its order), the pictures and the snapshots; the metrics."""
    from meschers_igl import save
    from meschers_igl.inverse.flatten import figure_mask
    from meschers_igl.inverse.metrics import (
        figure_period,
        image_psnr,
        max_period_ratio,
        silhouette_iou,
    )
    from meschers_igl.inverse.optimize import extract_order

    m = result.mescher
    order = extract_order(m, result.offsets)
    save(m, out / "mescher.ply", order=order)
    _save_png(out / "target.png", target)
    _save_png(out / "init.png", before)
    _save_png(out / "render.png", result.image)
    renders = out / "renders"
    renders.mkdir(exist_ok=True)
    for step, img in result.snapshots:
        _save_png(renders / f"step_{step:05d}.png", img)
    panels, titles = figure_panels(target, *start, result, bg, shade, args.init)
    _figures(out, panels, titles, result.losses, result.psnr)
    metrics = {
        "silhouette_iou": silhouette_iou(result.alpha > 0.5, figure_mask(target, bg)),
        "psnr_db": image_psnr(result.image, target),
        "psnr_init_db": image_psnr(before, target),
        "psnr_curve": [[int(s_), float(p)] for s_, p in result.psnr],
        "periods": [float(p) for p in m.periods()],
        "figure_period": figure_period(m),
        "impossible": bool(m.is_impossible()),
        "max_period_over_size": max_period_ratio(m),
        "max_abs_d12_zeta": result.max_residual,
        "order_arcs": int(order.n_arcs),
        "seconds": result.seconds,
        "cpu_seconds": result.cpu_seconds,
        "faces": int(m.n_faces),
        "iters": iters,
        "init": args.init,
        "light": [list(v) for v in shade["lights"]],
        "light_estimated": drawing is None and not given and args.init == "picture",
        "drawing": drawing is not None,
        "resolution": int(target.shape[0]),
    }
    if drawing is not None:
        _save_png(out / "drawing_shaded.png", drawing.picture)
    if model is not None:
        metrics["true_gap"] = float(model[0].gap * model[1])
    return metrics


def inverse_main(args: Sequence[str] | argparse.Namespace | None = None) -> int:
    """Run ``meschers inverse``; ``args`` is an argv list (parsed here) or a parsed namespace.

    Returns
    -------
    int
        Exit status 0; bad input raises :class:`MescherError`.
    """
    import sys

    if args is None or not isinstance(args, argparse.Namespace):
        argv = sys.argv[1:] if args is None else list(args)
        args = _parser().parse_args(_join_negative_values(argv))
    from meschers_igl.inverse.drawing import is_line_drawing, shade_drawing
    from meschers_igl.inverse.optimize import InverseOptions, fit_mescher
    from meschers_igl.inverse.picture import fit_options, mescher_from_picture, picture_shading
    from meschers_igl.inverse.rasterizer import render_mescher
    from meschers_igl.inverse.targets import target_mask, torus_for_target

    given = bool(args.light)
    lights = [_triple(t, "--light") for t in (args.light or [DEFAULT_LIGHT])]
    colors = None
    if args.light_color:
        colors = [_triple(t, "--light-color") for t in args.light_color]
        if len(colors) != len(lights):
            raise MescherError(
                f"--light-color: expected one per --light ({len(lights)}), found {len(colors)}"
            )
    iters = as_count(args.iters, "--iters", minimum=1)
    chosen = args.resolution is not None
    res = as_count(args.resolution if chosen else DEFAULT_RESOLUTION, "--resolution", minimum=8)
    every = as_count(args.every, "--every", minimum=1)
    _check_resolution(res, args.force)
    n_major, n_minor = (int(v) for v in _triple(args.torus + ",0", "--torus")[:2])
    model = None
    if args.target in BUILTIN:
        target, model = _builtin_target(args.target, res, lights, colors, args.ambient)
    else:
        target = _load_target(args.target, 0)  # the file's own size: thin lines stay dark
    bg = _background(target)
    drawing = None
    if model is None and is_line_drawing(target, bg):
        # a line drawing: faces between the lines, shaded by their Manhattan reading
        drawing = shade_drawing(
            target, bg, light=lights[0] if given else None, ambient=args.ambient
        )
        if not chosen:
            res = _drawing_resolution(drawing.faces)
            _check_resolution(res, args.force)
        target = _resize_flat(drawing.picture, res)
        lights, given = [tuple(float(v) for v in drawing.light)], True
    elif model is None:  # edge lines dropped at the file's own size, then averaged down
        target = _box_resize(_no_outlines(target, bg), res)
    if int(target_mask(target, bg).sum()) < 16:
        raise MescherError(
            f"TARGET: expected a figure on a plain background, found {args.target!r} with no "
            "pixels unlike its corners"
        )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    shade = dict(lights=lights, light_colors=colors, ambient=args.ambient)
    if args.init == "picture":
        if len(lights) != 1 or colors is not None:
            raise MescherError(
                f"--init picture: expected one white --light, found {len(lights)} lights"
                + (" with colours" if colors is not None else "")
            )
        # a drawing shows the steps between parallel faces its shaded reading cannot
        m0, region, info = mescher_from_picture(
            target,
            lights[0] if given else None,
            args.ambient,
            background=bg,
            steps=None if drawing is None else drawing.steps,
        )
        # the fit holds each face to its shade region's normal (fit_options' turn); a grey
        # figure is rendered grey (picture_shading: the exposure the picture was read with)
        face_normals = info["normals"][region]
        shade = picture_shading(info, args.ambient)
        lights = shade["lights"]
        off0 = None
        opts = fit_options(iters=iters, power=args.power, info=info, eval_every=every)
    else:
        m0, off0 = torus_for_target(target, bg, n_major=n_major, n_minor=n_minor)
        face_normals = None
        opts = InverseOptions(iters=iters, resolution=res, power=args.power, eval_every=every)
    before = render_mescher(m0, off0, resolution=res, background=bg, sigma=1e-6, **shade)
    progress = (not args.no_progress) and sys.stderr.isatty()
    result = fit_mescher(
        target,
        m0,
        off0,
        background=bg,
        options=opts,
        progress=progress,
        device=args.device,
        face_normals=face_normals,
        **shade,
    )

    metrics = _save_fit(
        out, args, target, bg, before, result, shade, drawing, model, iters, given, (m0, off0)
    )
    if args.init == "picture":  # the figure's brightness the picture was read with, 1: white
        metrics["exposure"] = float(info["exposure"])
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2))
    print(
        f"silhouette IoU {metrics['silhouette_iou']:.4f}  PSNR {metrics['psnr_init_db']:.2f} -> "
        f"{metrics['psnr_db']:.2f} dB  period {metrics['figure_period']:.3f}  "
        f"max |d12 zeta| {result.max_residual:.1e}  light "
        f"{','.join(f'{v:.3f}' for v in lights[0])}"
        f"{' (estimated)' if metrics['light_estimated'] else ''}  {res} px  "
        f"{result.seconds:.0f} s  -> {out}"
    )
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(inverse_main())
