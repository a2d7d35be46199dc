"""``meschers inverse TARGET.png --light X,Y,Z --out DIR [--init torus] [--iters N]``.

Recovers a mescher from a picture (paper Section 4.5): the target image spans the screen square
``[-1, 1]^2`` (pixel centres, y up), lit by the given directional lights.  Writes into ``DIR``:

- ``mescher.ply``: the recovered mescher with its extracted depth order (``meschers_igl.save``);
- ``render.png``: its final render; ``target.png``: the target as fitted; ``loss.png``: the
  loss curve;
- ``before_after.png``: target, initialization and result side by side;
- ``metrics.json``: silhouette IoU, PSNR, periods and ``max |period| / size``.

``TARGET`` may be the word ``penrose``: the built-in Penrose-triangle picture
(:func:`meschers_igl.inverse.optimize.penrose_target`), rendered under the same lights.
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from meschers_igl.errors import MescherError
from meschers_igl.validate import as_count

DEFAULT_LIGHT = "0.4,0.25,1"


def zbuffer_picture(
    model,
    resolution: int = 128,
    light=(0.4, 0.25, 1.0),
    ambient: float = 0.2,
    extent: float = 0.8,
    background=(1.0, 1.0, 1.0),
) -> tuple[np.ndarray, float]:
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

    Returns
    -------
    image : (resolution, resolution, 3) float64 in [0, 1]
    scale : float
        Screen units per model unit (depths scale the same way).
    """
    import pyvista as pv

    res = as_count(resolution, "resolution", minimum=8)
    R = model.camera_frame()
    C = model.V @ R.T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    scale = 2.0 * extent / float((hi - lo).max())
    centre_cam = np.r_[0.5 * (lo + hi), C[:, 2].mean()]
    centre = centre_cam @ R  # back to model coordinates
    faces = np.hstack([np.full((len(model.F), 1), 3), model.F]).ravel()
    mesh = pv.PolyData(model.V, faces)
    pl = pv.Plotter(off_screen=True, window_size=(res, res), lighting="none")
    try:
        pl.disable_anti_aliasing()
        pl.set_background(tuple(background))
        pl.add_mesh(mesh, color="white", ambient=ambient, diffuse=1.0 - ambient, specular=0.0,
                    smooth_shading=False, lighting=True)  # fmt: skip
        lw = np.asarray(light, dtype=np.float64) @ R  # toward the light, model coordinates
        lw = lw / np.linalg.norm(lw)
        pl.add_light(pv.Light(position=tuple(centre + lw), focal_point=tuple(centre),
                              light_type="scene light", positional=False, intensity=1.0))  # fmt: skip
        span = float(np.ptp(C, axis=0).max()) + 1.0
        pl.camera.enable_parallel_projection()
        pl.camera.focal_point = tuple(centre)
        pl.camera.position = tuple(centre + span * 4.0 * model.view)
        pl.camera.up = tuple(model.up)
        pl.camera.parallel_scale = 1.0 / scale  # half the screen height, model units
        pl.camera.clipping_range = (span, span * 8.0)
        img = pl.screenshot(return_img=True)
    finally:
        pl.close()
    return np.asarray(img[..., :3], dtype=np.float64) / 255.0, scale


def _triple(text: str, name: str) -> tuple[float, float, float]:
    try:
        vals = tuple(float(t) for t in str(text).split(","))
    except ValueError:
        vals = ()
    if len(vals) != 3 or not all(math.isfinite(v) for v in vals):
        raise MescherError(f"{name}: expected three comma-separated numbers X,Y,Z, found {text!r}")
    return vals  # type: ignore[return-value]


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``meschers inverse`` arguments to ``parser`` (returned)."""
    parser.add_argument("target", help="target PNG spanning the screen square, or 'penrose'")
    parser.add_argument("--light", action="append", default=None, metavar="X,Y,Z",
                        help=f"direction toward a light, camera frame; repeat for several "
                        f"(default {DEFAULT_LIGHT})")  # fmt: skip
    parser.add_argument("--light-color", action="append", default=None, metavar="R,G,B",
                        help="RGB intensity of each --light, in the same order "
                        "(default white, (1 - ambient) / #lights each)")  # fmt: skip
    parser.add_argument("--ambient", type=float, default=0.2, help="ambient light (default 0.2)")
    parser.add_argument("--out", required=True, help="output folder (created)")
    parser.add_argument("--init", choices=["torus"], default="torus",
                        help="initialization (default torus)")  # fmt: skip
    parser.add_argument("--iters", type=int, default=1200, help="steps (default 1200)")
    parser.add_argument("--resolution", type=int, default=128,
                        help="working resolution; the target is resampled (default 128)")  # fmt: skip
    parser.add_argument("--torus", default="96,24", metavar="N_MAJOR,N_MINOR",
                        help="torus resolution (default 96,24)")  # fmt: skip
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="meschers inverse",
        description="Recover a mescher from a picture by soft-rasterized inverse rendering.",
    )
    return add_arguments(p)


def _load_target(path: str, resolution: int) -> np.ndarray:
    from PIL import Image

    try:
        img = Image.open(path).convert("RGB")
    except (OSError, ValueError) as exc:
        raise MescherError(
            f"TARGET: expected a readable image file, found {path!r} ({exc})"
        ) from exc
    if img.width != img.height:
        raise MescherError(
            f"TARGET: expected a square image (it spans [-1, 1]^2), found {img.width}x{img.height}"
        )
    if img.width != resolution:
        img = img.resize((resolution, resolution), Image.Resampling.BOX)
    return np.asarray(img, dtype=np.float64) / 255.0


def _background(target: np.ndarray) -> np.ndarray:
    # the corners are background in any picture of an object that fits the screen square
    c = np.stack([target[0, 0], target[0, -1], target[-1, 0], target[-1, -1]])
    return np.median(c, axis=0)


def _save_png(path: Path, image: np.ndarray) -> None:
    from PIL import Image

    Image.fromarray((np.clip(image, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)).save(path)


def _figures(out: Path, target, before, after, losses) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.2), dpi=120)
    steps = np.arange(len(losses))
    # the two kinds of step render with different sigma: their losses are two curves
    ax.semilogy(steps[0::2], losses[0::2], lw=0.8, label="xy steps")
    ax.semilogy(steps[1::2], losses[1::2], lw=0.8, label="zeta steps")
    ax.legend()
    ax.set_xlabel("step")
    ax.set_ylabel("loss")
    ax.set_title("inverse rendering loss")
    fig.tight_layout()
    fig.savefig(out / "loss.png")
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(9, 3.3), dpi=120)
    for ax, img, title in zip(axes, (target, before, after), ("target", "torus init", "result")):
        ax.imshow(np.clip(img, 0, 1), interpolation="nearest")
        ax.set_title(title)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out / "before_after.png")
    plt.close(fig)


def inverse_main(args: Sequence[str] | argparse.Namespace | None = None) -> int:
    """Run ``meschers inverse``; ``args`` is an argv list (parsed here) or a parsed namespace.

    Returns
    -------
    int
        Exit status 0; bad input raises :class:`MescherError`.
    """
    if args is None or not isinstance(args, argparse.Namespace):
        args = _parser().parse_args(None if args is None else list(args))
    from meschers_igl import save
    from meschers_igl.inverse.metrics import image_psnr, max_period_ratio, silhouette_iou
    from meschers_igl.inverse.optimize import InverseOptions, extract_order, fit_mescher
    from meschers_igl.inverse.rasterizer import render_mescher
    from meschers_igl.inverse.targets import penrose_target, target_mask, torus_for_target

    lights = [_triple(t, "--light") for t in (args.light or [DEFAULT_LIGHT])]
    colors = None
    if args.light_color:
        colors = [_triple(t, "--light-color") for t in args.light_color]
        if len(colors) != len(lights):
            raise MescherError(
                f"--light-color: expected one per --light ({len(lights)}), found {len(colors)}"
            )
    if args.iters < 1 or args.resolution < 8:
        raise MescherError(
            f"--iters, --resolution: expected >= 1 and >= 8, found {args.iters}, {args.resolution}"
        )
    n_major, n_minor = (int(v) for v in _triple(args.torus + ",0", "--torus")[:2])
    res = int(args.resolution)
    if args.target == "penrose":
        target = penrose_target(res, lights=lights, light_colors=colors, ambient=args.ambient)
    else:
        target = _load_target(args.target, res)
    bg = _background(target)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    m0, off0 = torus_for_target(target, bg, n_major=n_major, n_minor=n_minor)
    shade = dict(lights=lights, light_colors=colors, ambient=args.ambient)
    before = render_mescher(m0, off0, resolution=res, background=bg, **shade)
    opts = InverseOptions(iters=int(args.iters), resolution=res)

    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(
        TextColumn("[bold]inverse[/] {task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(),
        disable=bool(args.no_progress),
    ) as progress:
        task = progress.add_task("loss -", total=opts.iters)

        def tick(it: int, state: dict) -> None:
            progress.update(task, advance=1, description=f"loss {state['loss']:.5f}")

        result = fit_mescher(target, m0, off0, background=bg, options=opts, callback=tick, **shade)

    m = result.mescher
    order = extract_order(m, result.offsets)
    save(m, out / "mescher.ply", order=order)
    _save_png(out / "target.png", target)
    _save_png(out / "render.png", result.image)
    _figures(out, target, before, result.image, result.losses)
    metrics = {
        "silhouette_iou": silhouette_iou(result.alpha > 0.5, target_mask(target, bg)),
        "psnr_db": image_psnr(result.image, target),
        "periods": [float(p) for p in m.periods()],
        "max_period_over_size": max_period_ratio(m),
        "max_abs_d12_zeta": result.max_residual,
        "order_arcs": int(order.n_arcs),
        "seconds": result.seconds,
        "faces": int(m.n_faces),
        "iters": opts.iters,
    }
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2))
    print(
        f"silhouette IoU {metrics['silhouette_iou']:.4f}  PSNR {metrics['psnr_db']:.2f} dB  "
        f"max |period| / size {metrics['max_period_over_size']:.3f}  "
        f"max |d12 zeta| {result.max_residual:.1e}  {result.seconds:.0f} s  -> {out}"
    )
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(inverse_main())
