"""Fit a mescher to a picture: inverse rendering of impossible objects (paper Section 4.5).

The unknowns and their Sobolev preconditioner are :mod:`.sobolev`; the image loss is the mean
squared error against the target, rendered by the soft rasterizer of :mod:`.rasterizer` under
fixed lights.  As in the paper, xy steps and zeta steps alternate and use separate SoftRas
``sigma``; the depth offsets (which only decide the soft z-ordering) and the periods move with
the zeta steps.  Afterwards the partial depth order is extracted from the faces that overlap on
screen (:func:`extract_order`).  Starting shapes: :mod:`.picture` (from the picture itself) or
:mod:`.targets` (a torus).
"""

from __future__ import annotations

import contextlib
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from ._torch import require_largesteps, require_torch

torch = require_torch()
require_largesteps()

from largesteps.optimize import AdamUniform  # noqa: E402

from ..errors import MescherError  # noqa: E402
from ..mescher import Mescher  # noqa: E402
from ..validate import check_budget  # noqa: E402
from .flatten import figure_mask  # noqa: E402
from .metrics import image_psnr  # noqa: E402
from .rasterizer import lambertian, soft_rasterize  # noqa: E402
from .sobolev import MescherParametrization  # noqa: E402
from .turn import FaceTurn, turn_faces  # noqa: E402


@dataclass
class InverseOptions:
    """Settings of :func:`fit_mescher` (defaults: the Penrose demonstration at 128 x 128).

    Attributes
    ----------
    iters : int, default: 1200
        Steps; even steps move xy, odd steps move z, the periods and the offsets (paper 4.5).
    resolution : int, default: 128
        Informative; the target's size is what is rendered.
    lam : float, default: 10.0
        Sobolev diffusion parameter lambda of ``I + lambda L`` for xy.
    lam_z : float or None, default: None
        Its own lambda for the depths (None: ``lam``).
    laplacian : {"cotan", "uniform"}, default: "cotan"
        ``L`` of :func:`.sobolev.sobolev_matrix`.
    power : {2, 1}, default: 2
        Preconditioner ``(I + lambda L)^-power``: 2 is largesteps' parametrization, 1 the
        Sobolev gradient as the paper writes it (:mod:`.sobolev`).
    lr_xy, lr_z : float, default: 1e-2, 2e-2
        ``largesteps.optimize.AdamUniform`` rates.
    lr_periods, lr_offsets : float
        Adam rates of the periods ``c`` (depth units) and of the offsets.
    lr_final : float, default: 0.05
        All rates decay by a cosine to this fraction of their start.
    sigma_xy, sigma_zeta : (float, float)
        SoftRas sharpness (squared screen units, a pixel is ``(2 / 128)^2 = 2.4e-4``) of the xy
        and of the zeta steps, decayed geometrically from the first to the second value.
    gamma : float, default: 1e-2
        Softness of the z-ordering by offsets.
    silhouette_weight : float, default: 1.0
        Weight of ``mean (alpha - mask)^2`` added to the image MSE.
    threads : int or None, default: 1
        ``torch.set_num_threads`` during the fit (None: leave it).
    final_sigma : float, default: 1e-6
        Sharpness of the returned render (and of the PSNR checks).
    supersample : int, default: 1
        The returned render and the PSNR checks take the mean of ``supersample x
        supersample`` samples spread evenly over each pixel: an antialiased picture (a pixel
        the mean over its area) is compared with a render made the same way, not with one
        sampled at pixel centres, which differs from it along every edge.
    eval_every : int, default: 0
        Every so many steps, render nearly hard and measure the PSNR; with ``keep_best`` the
        iterate with the best one is returned (0: never; the last iterate is returned).
    keep_best : bool, default: True
        With ``eval_every``: return the iterate of the best PSNR seen, the start included.
    turn : (int, float), default: (0, 0.0)
        With :func:`fit_mescher`'s ``face_normals`` (:class:`.turn.FaceTurn`): ``(every,
        weight)``.  Every ``every`` steps the faces are turned back to them
        (:func:`.turn.turn_parametrization`) and the fit goes on from there, before that
        step's PSNR check (0: only once, after the fit; negative: never).  ``weight``: of
        the penalty ``mean_f (1 - n_f . face_normals[f])`` added to every step's loss (0:
        none).  Pictures of boxes at 200 steps: ``(-1, 0.03)``, the penalty alone, keeps the
        PSNR (often raises it) and puts more faces on the regions' orientations; turning the
        faces back, once or every 20 steps, costs 0.5-3 dB.
    """

    iters: int = 1200
    resolution: int = 128
    lam: float = 10.0
    lam_z: float | None = None
    laplacian: str = "cotan"
    power: int = 2
    lr_xy: float = 1e-2
    lr_z: float = 2e-2
    lr_periods: float = 2e-2
    lr_offsets: float = 1e-3
    lr_final: float = 0.05
    sigma_xy: tuple[float, float] = (3e-3, 2e-5)
    sigma_zeta: tuple[float, float] = (3e-4, 1e-6)
    gamma: float = 1e-2
    silhouette_weight: float = 1.0
    threads: int | None = 1
    final_sigma: float = 1e-6
    supersample: int = 1
    eval_every: int = 0
    keep_best: bool = True
    turn: tuple[int, float] = (0, 0.0)


@dataclass
class InverseResult:
    """What :func:`fit_mescher` returns.

    Attributes
    ----------
    mescher : Mescher
    offsets : (#F,) float64
        Depth offsets (larger nearer).
    image : (H, W, 3) float64
        Nearly hard render of the result (``final_sigma``).
    alpha : (H, W) float64
    losses : list of float
        Training loss per step (xy and zeta steps alternate and use different sigma).
    psnr : list of (step, dB)
        The nearly hard PSNR every ``eval_every`` steps.
    max_residual : float
        Largest ``|d12 zeta|`` over all iterates.
    seconds, cpu_seconds : float
        Wall and process CPU time.
    snapshots : list of (step, (H, W, 3) image)
        The renders of the PSNR checks.
    """

    mescher: Mescher
    offsets: np.ndarray
    image: np.ndarray
    alpha: np.ndarray
    losses: list = field(default_factory=list)
    psnr: list = field(default_factory=list)
    max_residual: float = 0.0
    seconds: float = 0.0
    cpu_seconds: float = 0.0
    snapshots: list = field(default_factory=list, repr=False)


def _schedule(pair: tuple[float, float], t: float) -> float:
    a, b = pair
    return a * (b / a) ** t


def fit_mescher(
    target: np.ndarray,
    init: Mescher,
    offsets=None,
    lights=((0.0, 0.0, 1.0),),
    light_colors=None,
    ambient=0.2,
    background=(1.0, 1.0, 1.0),
    options: InverseOptions | None = None,
    callback: Callable[[int, dict], None] | None = None,
    progress: bool | None = False,
    device=None,
    force: bool = False,
    face_normals=None,
) -> InverseResult:
    """Optimize a mescher so that its soft rendering matches ``target`` (paper Section 4.5).

    Minimizes ``|I(xy, zeta, o) - target|^2`` (mean over pixels and channels) plus
    ``silhouette_weight * |alpha - mask|^2``, with xy steps and zeta/offset steps alternating.

    Parameters
    ----------
    target : (H, W, 3) float in [0, 1]
        Spans the screen square ``[-1, 1]^2`` (row 0 at the top).
    init : Mescher
        Initialization (:func:`.picture.mescher_from_picture` or
        :func:`.targets.torus_for_target`); its connectivity is kept.
    offsets : (#F,) array_like, optional
        Initial depth offsets (larger nearer).
    lights, light_colors, ambient, background
        Fixed shading, see :func:`.rasterizer.lambertian`.
    options : InverseOptions, optional
    callback : callable(iteration, state), optional
        The progress callback, called after every step with ``state = {"loss", "zeta" (#E,)
        float64 ndarray, "step": "xy" | "zeta", "iters"}`` and, on PSNR checks, ``"psnr"``.
    progress : bool or None, default: False
        A progress bar on stderr (rich); None: only when stderr is a terminal.
    device : str or torch.device, optional
        Where to compute, e.g. ``"cuda"`` when ``torch.cuda.is_available()``; default CPU (the
        tested path).
    force : bool, default: False
        Skip the memory guard (:func:`meschers_igl.validate.check_budget`) on the resolution.
    face_normals : (#F, 3) array_like, optional
        The orientation each face of ``init`` stands for (a picture's region normals,
        ``info["normals"][region]`` of :func:`.picture.mescher_from_picture`).  Given, the
        fit holds the faces to them as ``options.turn`` says (a penalty on each face's
        normal, turns back during the fit, and, unless ``options.turn[0] < 0``, the returned
        mescher turned back once more, :func:`.turn.turn_faces`: the fitted screen
        positions and periods kept): the image only holds each face's shade, ``n . l``, and
        the fit turns faces about the light as freely as it bends them where it moves their
        vertices.  ``image`` and ``alpha`` are then its render.

    Returns
    -------
    InverseResult
    """
    opt = options or InverseOptions()
    if not isinstance(init, Mescher):
        raise MescherError(f"init: expected a Mescher, found {type(init).__name__}")
    if face_normals is not None:
        face_normals = np.asarray(face_normals, dtype=np.float64)
        if face_normals.shape != (init.n_faces, 3):
            raise MescherError(
                f"face_normals: expected ({init.n_faces}, 3), found {face_normals.shape}"
            )
    target = np.asarray(target, dtype=np.float64)
    if target.ndim != 3 or target.shape[2] != 3 or target.shape[0] != target.shape[1]:
        raise MescherError(f"target: expected an (N, N, 3) image, found shape {target.shape}")
    res = target.shape[0]
    if isinstance(opt.supersample, bool) or not isinstance(opt.supersample, (int, np.integer)):
        raise MescherError(
            f"options.supersample: expected an integer >= 1, found {opt.supersample!r}"
        )
    if not 1 <= opt.supersample <= 8:
        raise MescherError(f"options.supersample: expected 1 to 8, found {opt.supersample}")
    # the soft rasterizer holds a few (face, pixel) pairs per pixel: ~2 kB per pixel
    check_budget(
        float(res) * res, bytes_per_face=2048.0, what=f"fit_mescher at {res}^2", force=force
    )
    if not np.all(np.isfinite(target)):
        raise MescherError("target: expected finite values in [0, 1], found non-finite values")
    if device is not None and torch.device(device).type == "cuda" and not torch.cuda.is_available():
        raise MescherError(f"device: expected a device torch can use, found {device!r} (no CUDA)")
    if progress is None:
        progress = sys.stderr.isatty()
    old_threads = torch.get_num_threads()
    if opt.threads:
        # several engineers share two cores: oversubscribed BLAS threads are 10x slower here
        torch.set_num_threads(opt.threads)
    ctx, step_callback = _with_progress(progress, opt.iters, callback)
    try:
        with ctx:
            result = _fit(
                target,
                res,
                init,
                offsets,
                (lights, light_colors, ambient, background),
                opt,
                step_callback,
                device,
                None if face_normals is None else FaceTurn(face_normals, *opt.turn),
            )
            if face_normals is not None and opt.turn[0] >= 0:
                _turn_faces_back(
                    result, face_normals, lights, light_colors, ambient, background, opt.final_sigma
                )
            return result
    finally:
        torch.set_num_threads(old_threads)


def _turn_faces_back(
    result, face_normals, lights, light_colors, ambient, background, sigma: float
) -> None:
    """``result`` with its mescher's faces turned to ``face_normals`` and its render redone."""
    from .rasterizer import render_mescher

    m = turn_faces(result.mescher, face_normals)
    result.image, result.alpha = render_mescher(
        m,
        result.offsets,
        lights,
        light_colors,
        ambient,
        resolution=result.image.shape[0],
        sigma=sigma,
        background=background,
        return_alpha=True,
    )
    result.mescher = m


def _with_progress(progress: bool, total: int, callback):
    """The context and the step callback :func:`fit_mescher` runs :func:`_fit` with.

    Without ``progress``: :func:`contextlib.nullcontext` and ``callback`` itself.  With it: a
    rich progress bar on stderr (stdout stays for results) of ``total`` steps, and a callback
    that advances it once per step, shows the loss and the last PSNR check, then calls
    ``callback``.
    """
    if not progress:
        return contextlib.nullcontext(), callback
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("[bold]inverse[/] {task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        transient=False,
    )
    task = bar.add_task("loss -", total=total)

    def tick(it: int, state: dict) -> None:
        text = f"loss {state['loss']:.5f}"
        if "psnr" in state:
            text += f" PSNR {state['psnr']:.1f} dB"
        bar.update(task, advance=1, description=text)
        if callback is not None:
            callback(it, state)

    return bar, tick


def _supersampled(draw, xy, zeta, k: int, res: int):
    """``draw(xy, zeta) -> (image, alpha)`` averaged over ``k x k`` samples spread evenly over
    each pixel, as ``k^2`` draws of the figure shifted by the samples' offsets from the pixel
    centre (one draw's memory, not ``k^2``); numpy ``(H, W, 3)``, ``(H, W)``."""
    shifts = ((np.arange(k) + 0.5) / k - 0.5) * (2.0 / res)
    img = alpha = 0.0
    for dx in shifts:
        for dy in shifts:
            i, a = draw(xy + torch.tensor([dx, dy], dtype=xy.dtype, device=xy.device), zeta)
            img, alpha = img + i / k**2, alpha + a / k**2
    return img.cpu().numpy(), alpha.cpu().numpy()


def _fit(target, res, init, offsets, shading, opt, callback, device, turn=None):
    """The fit of :func:`fit_mescher`; ``shading`` is ``(lights, light_colors, ambient,
    background)``; ``turn`` (a :class:`.turn.FaceTurn` or None) adds its penalty to the loss
    and turns the faces back after the steps it says."""
    lights, light_colors, ambient, background = shading
    t0, c0 = time.perf_counter(), time.process_time()
    f32 = torch.float32
    par = MescherParametrization(
        init, offsets, opt.lam, opt.laplacian, opt.power, opt.lam_z, device=device
    )
    dev = par.device
    d12 = init.d12
    tgt = torch.as_tensor(target, dtype=f32, device=dev)
    mask = torch.as_tensor(figure_mask(target, background), dtype=f32, device=dev)
    opt_xy = AdamUniform([par.xy_leaf.leaf], lr=opt.lr_xy)
    opt_z = AdamUniform([par.z_leaf.leaf], lr=opt.lr_z)
    opt_rest = torch.optim.Adam(
        [{"params": [par.c], "lr": opt.lr_periods}, {"params": [par.offsets], "lr": opt.lr_offsets}]
    )
    losses: list[float] = []
    psnrs: list[tuple[int, float]] = []
    snapshots: list = []
    max_res = 0.0
    best = (-math.inf, None)

    def render(xy, zeta, sigma, gamma=opt.gamma, dtype=f32):
        colors = lambertian(par.normals(xy, zeta), lights, light_colors, ambient).to(dtype)
        rest = (par.offsets.to(dtype), res, sigma, gamma, background)
        return soft_rasterize(par.F, xy.to(dtype), colors, *rest, return_alpha=True)

    def hard():
        with torch.no_grad():
            draw = partial(render, sigma=opt.final_sigma, gamma=1e-3, dtype=torch.float64)
            return _supersampled(draw, par.xy().double(), par.zeta(), int(opt.supersample), res)

    leaves = (par.xy_leaf.leaf, par.z_leaf.leaf, par.c, par.offsets)

    def snapshot():
        with torch.no_grad():
            return tuple(x.clone() for x in leaves)

    base_lr = [[g["lr"] for g in o.param_groups] for o in (opt_xy, opt_z, opt_rest)]
    if opt.eval_every and opt.keep_best:
        # the start is a candidate too: a fit that only loses (a frame of bars a few pixels
        # wide) returns its start
        img_h, _ = hard()
        best = (image_psnr(img_h, target), snapshot())
    for it in range(opt.iters):
        t = it / max(opt.iters - 1, 1)
        # cosine decay to lr_final: large early steps, then settle the per-face noise
        decay = opt.lr_final + (1.0 - opt.lr_final) * 0.5 * (1.0 + math.cos(math.pi * t))
        for o, lrs in zip((opt_xy, opt_z, opt_rest), base_lr):
            for g, lr in zip(o.param_groups, lrs):
                g["lr"] = lr * decay
        xy_step = it % 2 == 0
        if xy_step:
            xy = par.xy()
            with torch.no_grad():
                zeta = par.zeta()
            img, alpha = render(xy, zeta, _schedule(opt.sigma_xy, t))
        else:
            with torch.no_grad():
                xy = par.xy()
            zeta = par.zeta()
            img, alpha = render(xy, zeta, _schedule(opt.sigma_zeta, t))
        loss = ((img - tgt) ** 2).mean() + (turn.penalty(par, xy, zeta) if turn else 0.0)
        if opt.silhouette_weight:
            loss = loss + opt.silhouette_weight * ((alpha - mask) ** 2).mean()
        for o in (opt_xy, opt_z, opt_rest):
            o.zero_grad()
        loss.backward()
        if xy_step:
            par.xy_leaf.precondition()
            opt_xy.step()
        else:
            par.z_leaf.precondition()
            opt_z.step()
            opt_rest.step()
        if turn is not None:
            turn.after_step(par, it)
        losses.append(float(loss.detach()))
        zeta_np = zeta.detach().cpu().numpy()
        max_res = max(max_res, float(np.abs(d12 @ zeta_np).max(initial=0.0)))
        state = {
            "loss": losses[-1],
            "zeta": zeta_np,
            "step": "xy" if xy_step else "zeta",
            "iters": opt.iters,
        }
        if opt.eval_every and ((it + 1) % opt.eval_every == 0 or it + 1 == opt.iters):
            img_h, _ = hard()
            state["psnr"] = image_psnr(img_h, target)
            psnrs.append((it + 1, state["psnr"]))
            snapshots.append((it + 1, img_h))
            if opt.keep_best and state["psnr"] > best[0]:
                best = (state["psnr"], snapshot())
        if callback is not None:
            callback(it, state)

    if opt.keep_best and best[1] is not None:
        with torch.no_grad():
            for dst, src in zip(leaves, best[1]):
                dst.copy_(src)
    m = par.mescher()
    fitted_offsets = par.offsets.detach().double().cpu().numpy()
    img, alpha = hard()
    max_res = max(max_res, float(np.abs(d12 @ np.asarray(m.zeta)).max(initial=0.0)))
    return InverseResult(
        mescher=m,
        offsets=fitted_offsets,
        image=img,
        alpha=alpha,
        losses=losses,
        psnr=psnrs,
        max_residual=max_res,
        seconds=time.perf_counter() - t0,
        cpu_seconds=time.process_time() - c0,
        snapshots=snapshots,
    )


# ---------------------------------------------------------------------------------------------
# The partial depth order
# ---------------------------------------------------------------------------------------------


def extract_order(m: Mescher, offsets: np.ndarray):
    """The partial depth order of a fitted mescher: overlapping faces compared by offset.

    Parameters
    ----------
    m : Mescher
    offsets : (#F,) float
        Depth offsets from the fit (larger nearer).

    Returns
    -------
    DepthOrder
        Arc ``i -> j`` (i behind j) for each pair of faces that overlap on screen with positive
        area (:func:`meschers_igl.geometry2d.overlapping_pairs`) and have
        ``offsets[i] < offsets[j]``; equal offsets give no arc.
    """
    from ..geometry2d import overlapping_pairs
    from ..order import DepthOrder

    o = np.asarray(offsets, dtype=np.float64)
    if o.shape != (m.n_faces,):
        raise MescherError(f"offsets: expected shape ({m.n_faces},), found {o.shape}")
    pairs, _ = overlapping_pairs(np.asarray(m.xy)[np.asarray(m.F)])
    i, j = pairs[:, 0], pairs[:, 1]
    back = np.where(o[i] < o[j], i, j)
    front = np.where(o[i] < o[j], j, i)
    arcs = np.stack([back, front], axis=1)[o[i] != o[j]]
    return DepthOrder(m.n_faces, arcs, m=m)
