"""Inverse rendering of pictures of real models under random lights: the acceptance table.

Models: the development set of real files (a folder of models with a ``views.json`` giving each
file's orthographic view, up vector and the depth gaps between vertices that coincide on
screen; skipped when absent) and the project's own box models (``tribar``, ``cube``,
``stairs`` of :mod:`meschers_igl.inverse.models`).  Each is rendered by PyVista's z-buffer
(``meschers.inverse_cli.zbuffer_picture``, flat Lambertian, ambient 0.2) under ``--lights``
directions drawn uniformly on the upper hemisphere (toward the viewer, seeded), on a pale blue
ground: no grey face can take its colour, where on white a face turned to the light vanishes.
``--picture antialiased`` renders 4x larger and averages 4 x 4 blocks (a renderer's
supersampling; what ``meschers inverse`` makes of a larger picture), ``--picture jpeg`` saves
each picture as a JPEG of quality 90 and reads it back, ``--picture outlined`` draws black lines
3 pixels wide over every edge of the 4x larger picture, drops them as ``meschers inverse``
does (``inverse.flatten.drop_outlines``) and averages it down (:func:`published_picture`).

Per picture: :func:`meschers_igl.inverse.picture.mescher_from_picture` with the light given,
then :func:`meschers_igl.inverse.optimize.fit_mescher` (``fit_options``) with the regions'
normals as ``face_normals`` and ``turn = TURN``: a penalty of weight 0.03 on each face's normal
against its region's during the fit (the image holds only ``n . l``; the fit tilts faces about
the light).  At 200 steps, against the plain fit (``--no-turn-faces``): ImpossibleTriangle
0 -> 1, EscherCube 3 -> 5, PenroseStairs2 5 -> 5, cube 3 -> 4 passes of 6 (weight 0.1: 3, 5, 3,
4; turning the faces back once after the fit or every 20 steps costs 0.5-3 dB).
``--turn-every K`` also turns the faces back every ``K`` steps (0: once after the fit, -1:
never), ``--turn-weight W`` sets the penalty's weight.  Also the light
*estimated* from the picture alone (no light given) and its angle to the true light, and to
the true light's Necker mirror ``(-x, -y, z)`` (which lights the mirrored reading the same).

Columns (median and worst over the lights, per model), against the bar:
PSNR >= 30 dB, silhouette IoU >= 0.98, share of figure pixels on faces within 10 degrees of
the three face directions the model's picture shows (:func:`model_axes`: the most projected
area, not the most area) >= 90%, impossible, period
(around the outline or a hole) within 5% of the true depth gap (the box model's ``gap``; for a
file, the largest gap among the junctions a drawn line runs through (:func:`junction_gaps`): the
coincident pairs of ``views.json`` and the picture's invisible edges (:func:`invisible_gaps`)
that run on as a line the picture draws; times the picture's scale; "-" where none is
known: models without coincident pairs, and physically possible models a person reads as
right-angled, whose physical gaps are not the period read), and wall seconds.  A picture
refused with a ``MescherError`` counts as failing every column.

Run:  python benchmarks/bench_inverse_real.py [--models PATH] [--lights 6] [--iters 300]
      [--no-turn-faces] [--turn-every K] [--turn-weight W]
      [--resolution 128] [--only NAME,NAME] [--cases NAME:K,...] [--figures DIR] [--seed 0]
      [--picture zbuffer|antialiased|jpeg|outlined] [--ground R,G,B]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from meschers_igl.inverse.turn import PICTURE_TURN
from meschers_igl.obtain.caps import unit_normals

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

AMBIENT = 0.2
GROUND = (0.55, 0.7, 0.9)
TURN = PICTURE_TURN  # what fit_options uses: the normal penalty of weight 0.03, never turned back
DEFAULT_MODELS = Path(__file__).resolve().parents[2] / "shared" / "real_models"


def hemisphere_lights(n: int, seed: int) -> np.ndarray:
    """``n`` unit directions uniform on the hemisphere ``z > 0`` (seeded)."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v


def model_axes(model) -> np.ndarray:
    """(3, 3) the three face directions the model's picture shows (model frame, either sign).

    :func:`meschers_igl.inverse.metrics.picture_axes` from ``model.view``: each face weighs its
    projected area ``A |n . view|``, not its area.  A sheared model hides its sheared faces
    edge-on: PenroseTriangle2's third most area lies on faces seen edge-on (45 degrees from two
    axes), and against those directions the model's own z-buffered picture scores 65% (96% on
    the three directions the picture shows, at right angles, which a person reads).
    """
    from meschers_igl.inverse.metrics import picture_axes

    return picture_axes(model.V, model.F, model.view)


def face_ids(model, res: int, extent: float = 0.8) -> np.ndarray:
    """(res, res) int64: the face of ``model.F`` seen at each pixel, -1 on the background.

    PyVista's z-buffer with the camera of ``meschers.inverse_cli.zbuffer_picture`` (the same
    view, up, centre and scale), each face drawn unlit in a colour that encodes its index.
    """
    import pyvista as pv

    from meschers.inverse_cli import aim_camera, picture_frame
    from pyvista_views.headless import configure_headless

    configure_headless()
    C, scale, centre = picture_frame(model, extent)
    F = np.asarray(model.F)
    mesh = pv.PolyData(model.V, np.hstack([np.full((len(F), 1), 3), F]).ravel())
    k = np.arange(1, len(F) + 1)
    mesh.cell_data["id"] = np.stack([k & 255, (k >> 8) & 255, (k >> 16) & 255], 1).astype(np.uint8)
    pl = pv.Plotter(off_screen=True, window_size=(res, res), lighting="none")
    try:
        pl.disable_anti_aliasing()
        pl.set_background((0.0, 0.0, 0.0))
        pl.add_mesh(mesh, scalars="id", rgb=True, lighting=False, preference="cell")
        aim_camera(pl, model, C, scale, centre)
        img = np.asarray(pl.screenshot(return_img=True)[..., :3], dtype=np.int64)
    finally:
        pl.close()
    return img[..., 0] + (img[..., 1] << 8) + (img[..., 2] << 16) - 1


def invisible_gaps(model, res: int, min_pairs: int = 2, max_deg: float = 0.5) -> np.ndarray:
    """Depth gaps (model units) across the invisible edges of the model's picture, ascending.

    An invisible edge is an occlusion between two parallel faces (normals within ``max_deg``):
    under any directional light both have one shade, so the picture shows no line there and a
    person reads one surface running on (the impossible cube's front bar joined to a back bar;
    a staircase's riser to a wall behind it).  Its gap is exact: the planes' distance over
    ``|n . view|``.  Counted where ``min_pairs`` pairs of neighbouring pixels of
    :func:`face_ids` show it; gaps under ``1e-6`` of the model's size are one plane split.
    """
    V = np.asarray(model.V, dtype=np.float64)
    size = float(np.ptp(V, axis=0).max())
    _, _, g = _invisible_pixels(model, res, max_deg)
    _, inv, cnt = np.unique(np.round(g / size, 9), return_inverse=True, return_counts=True)
    gap = np.bincount(inv.ravel(), g) / cnt  # one value per plane pair, not rounded
    return gap[cnt >= min_pairs]


def _invisible_pixels(model, res: int, max_deg: float = 0.5):
    """:func:`face_ids` (``res``), and each pair of neighbouring pixels across an invisible
    edge: the point between them (pixel-centre row, column) and its gap (model units)."""
    V = np.asarray(model.V, dtype=np.float64)
    F = np.asarray(model.F)
    ids = face_ids(model, res)
    ids[ids >= len(F)] = -1  # a colour no face has: not a face
    n = unit_normals(V, F)
    v = np.asarray(model.view, dtype=np.float64)
    size = float(np.ptp(V, axis=0).max())
    pts, gaps = [], []
    for a, b, dr, dc in ((ids[:, :-1], ids[:, 1:], 0, 1), (ids[:-1, :], ids[1:, :], 1, 0)):
        ok = (a >= 0) & (b >= 0) & (a != b)
        r, c = np.nonzero(ok)
        fa, fb = a[ok], b[ok]
        par = np.abs((n[fa] * n[fb]).sum(axis=1)) > math.cos(math.radians(max_deg))
        g = np.abs(((V[F[fb, 0]] - V[F[fa, 0]]) * n[fa]).sum(axis=1))
        g = g / np.maximum(np.abs(n[fa] @ v), 1e-300)
        keep = par & (g > 1e-6 * size)  # under that: one plane split
        pts.append(np.stack([r[keep] + 0.5 * dr, c[keep] + 0.5 * dc], axis=1))
        gaps.append(g[keep])
    return ids, np.concatenate(pts), np.concatenate(gaps)


def drawn(ids: np.ndarray, n: np.ndarray, points: np.ndarray, u: np.ndarray, max_deg: float = 0.5):
    """(P,) bool: whether the picture draws a line across ``u`` at each of ``points``.

    ``points`` (P, 2) and ``u`` (2,) are (row, column) pixel-centre coordinates of
    :func:`face_ids`' image ``ids``; the two pixels half a pixel on either side of the point,
    across ``u``, are compared.  A line is drawn where they show faces that are not parallel
    (normals ``n`` more than ``max_deg`` apart: every light but one along their crease shades
    them apart) or one face and the background; out of the image, none is.
    """
    res = ids.shape[0]
    w = np.array([-u[1], u[0]]) / np.linalg.norm(u)
    a = np.floor(points + 0.5 * w + 0.5).astype(np.int64)
    b = np.floor(points - 0.5 * w + 0.5).astype(np.int64)
    inside = ((a >= 0) & (a < res) & (b >= 0) & (b < res)).all(axis=1)
    fa = np.where(inside, ids[np.clip(a[:, 0], 0, res - 1), np.clip(a[:, 1], 0, res - 1)], -1)
    fb = np.where(inside, ids[np.clip(b[:, 0], 0, res - 1), np.clip(b[:, 1], 0, res - 1)], -1)
    par = np.abs((n[np.maximum(fa, 0)] * n[np.maximum(fb, 0)]).sum(axis=1))
    both = (fa >= 0) & (fb >= 0)
    apart = both & (par < math.cos(math.radians(max_deg)))
    return inside & (((fa >= 0) != (fb >= 0)) | apart)


def continues_drawn_line(ids, n, points: np.ndarray, beyond=(2, 3, 4, 5), need: int = 3) -> bool:
    """Whether the straight piece of boundary through ``points`` (pixel-centre (row, column),
    three at least) runs on, past one of its ends, as a line the picture draws.

    The piece's direction is its points' principal axis; past each end, ``beyond`` pixels on,
    ``need`` of the samples must lie on a drawn line across it (:func:`drawn`).
    """
    c = points.mean(axis=0)
    _, U = np.linalg.eigh(np.cov((points - c).T))
    u = U[:, -1]
    t = (points - c) @ u
    k = np.asarray(beyond, dtype=np.float64)
    for end, sign in ((t.max(), 1.0), (t.min(), -1.0)):
        q = c[None] + (end + sign * k)[:, None] * u[None]
        if int(drawn(ids, n, q, u).sum()) >= need:
            return True
    return False


def _pieces(points: np.ndarray, gaps: np.ndarray, size: float):
    """Pieces of invisible edge: points of one gap (to 1e-9 of ``size``) within 1.5 pixels."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    key = np.round(gaps / size, 9)
    for g in np.unique(key):
        P = points[key == g]
        pr = cKDTree(P).query_pairs(1.5, output_type="ndarray")
        G = sp.coo_matrix((np.ones(len(pr)), (pr[:, 0], pr[:, 1])), shape=(len(P),) * 2)
        _, lab = connected_components(G, directed=False)
        for k in np.unique(lab):
            yield float(gaps[key == g].mean()), P[lab == k]


def junction_gaps(model, listed=(), res: int = 512, max_deg: float = 0.5, tol: float = 1e-3):
    """The depth gaps (model units) of the junctions a person reads as one line running on.

    A junction joins two surfaces far apart in depth where they meet on screen.  Two kinds
    are counted, each only where the picture draws a line that runs through it, for there a
    person reads the near edge and the far one as one edge of one surface:

    - an invisible edge (an occlusion between parallel faces, :func:`invisible_gaps`) whose
      straight piece runs on past one of its ends as a drawn line (:func:`continues_drawn_line`):
      the impossible cube's front bar edge running on into a back bar's; a staircase's top
      riser whose end lies on a wall's edge behind it.  One that ends over the middle of the
      face behind (a riser's end over a wall, the wall going on around it) joins nothing a
      line shows and is an occlusion the picture happens not to draw;
    - a listed coincident gap (``views.json``) where some pair of vertices that coincide on
      screen (to ``tol`` of the figure's size) with that gap (to ``tol`` of it) has an edge
      seen as a drawn line from the point that runs on, straight, past it (the tribar's inner
      edges).  A corner of a hidden floor under a tread's corner is no junction.

    Returns
    -------
    (G,) float64, ascending, each gap once.
    """
    V = np.asarray(model.V, dtype=np.float64)
    F = np.asarray(model.F)
    ids, pts, gaps = _invisible_pixels(model, res, max_deg)
    n = unit_normals(V, F)
    size = float(np.ptp(V, axis=0).max())
    out = [
        g for g, P in _pieces(pts, gaps, size) if len(P) >= 3 and continues_drawn_line(ids, n, P)
    ]
    # coincident pairs: screen position (pixel-centre row, column) of each vertex, framed as
    # face_ids frames it
    from meschers.inverse_cli import picture_frame

    C, scale, _ = picture_frame(model)
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    xy = (C[:, :2] - 0.5 * (lo + hi)) * scale
    rc = np.stack([(1.0 - xy[:, 1]) * res / 2 - 0.5, (xy[:, 0] + 1.0) * res / 2 - 0.5], axis=1)
    E = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), 1), axis=0)
    px = 2.0 / res
    d = np.linalg.norm(xy[:, None] - xy[None], axis=2) < tol * 2.0 * float(np.ptp(xy, axis=0).max())
    for gap in listed:
        dz = np.abs(np.abs(C[:, None, 2] - C[None, :, 2]) - gap) < tol * gap
        for i, j in zip(*np.nonzero(np.triu(d & dz, 1))):  # a handful of pairs
            if any(_runs_through(ids, n, rc[i], xy[w] - xy[p], px) for p, w in _edges_of(E, i, j)):
                out.append(float(gap))
                break
    return np.unique(np.round(out, 9))


def _edges_of(E: np.ndarray, i: int, j: int):
    """(vertex, neighbour) for each edge of ``E`` at vertex ``i`` or ``j``."""
    for a, b in E[(E == i).any(axis=1) | (E == j).any(axis=1)]:
        yield (a, b) if a in (i, j) else (b, a)


def _runs_through(ids, n, at, d, px: float) -> bool:
    """Whether the edge leaving the pixel point ``at`` along screen vector ``d`` is drawn (2 to
    5 pixels on, as far as it goes) and the line runs on past ``at`` (3 of 4 samples)."""
    L = float(np.linalg.norm(d)) / px
    if L < 3.0:
        return False
    u = np.array([-d[1], d[0]]) / np.linalg.norm(d)  # screen (x, y) to (row, column)
    along = np.arange(2.0, min(5.0, L - 1.0) + 1e-9)
    back = np.arange(2.0, 6.0)
    return bool(
        drawn(ids, n, at[None] + along[:, None] * u[None], u).all()
        and drawn(ids, n, at[None] - back[:, None] * u[None], u).sum() >= 3
    )


def load_models(folder: Path | None, only: set | None):
    from meschers_igl.inverse import models
    from meschers_igl.inverse.models import BoxModel

    out = []
    if folder is not None and (folder / "views.json").is_file():
        from meshlab_filters.load import load_artist_model

        views = json.loads((folder / "views.json").read_text())
        for name, v in views.items():
            if name.startswith("_") or (only and name not in only):
                continue
            V, F, _ = load_artist_model(folder / name)
            view = np.asarray(v["view"], float)
            view /= np.linalg.norm(view)
            up = np.asarray(v["up"], float)
            up -= (up @ view) * view
            up /= np.linalg.norm(up)
            # a physically possible model (a sheared torus, a relief) is read as right-angled
            # bars: its physical gaps are not the period a person reads.  A file with a junction
            # from its view (coincident pairs) is checked against the largest gap among the
            # junctions a drawn line runs through (:func:`junction_gaps`): such pairs and the
            # picture's invisible edges (a cube frame's front bar running on, with no line,
            # into a back bar behind it is a junction too; a riser's end over a wall is not)
            gaps = v.get("coincident_depth_gaps") or []
            m = BoxModel(name, V, np.asarray(F), view, up, math.nan)
            if gaps and "perceive" not in v:
                junctions = junction_gaps(m, gaps)
                m = replace(m, gap=float(junctions.max()) if junctions.size else math.nan)
            out.append((m, model_axes(m)))
    for name, make in (
        ("tribar", models.penrose_tribar),
        ("cube", models.impossible_cube),
        ("stairs", models.penrose_stairs),
    ):
        if only and name not in only:
            continue
        m = make()
        out.append((m, model_axes(m)))
    return out


def published_picture(model, res: int, light, how: str = "zbuffer"):
    """The model's z-buffer picture (:func:`meschers.inverse_cli.zbuffer_picture`) as it is
    published: ``"zbuffer"`` as rendered; ``"antialiased"`` rendered 4x larger and averaged
    over 4 x 4 blocks (a renderer's supersampling, or ``meschers inverse`` on a larger
    picture); ``"jpeg"`` saved as a JPEG of quality 90 and read back.  Returns it and the
    scale."""
    import io

    from PIL import Image

    from meschers.inverse_cli import zbuffer_picture

    if how in ("antialiased", "outlined"):
        big, scale = zbuffer_picture(
            model, 4 * res, light=light, ambient=AMBIENT, background=GROUND
        )
        if how == "outlined":  # black lines 3 px wide over every edge, dropped as the CLI does
            from meschers_igl.inverse.flatten import drop_outlines
            from meschers_igl.inverse.targets import outlined

            big = drop_outlines(outlined(big, 3), GROUND)[0]
        return big.reshape(res, 4, res, 4, 3).mean(axis=(1, 3)), scale
    image, scale = zbuffer_picture(model, res, light=light, ambient=AMBIENT, background=GROUND)
    if how == "jpeg":
        buf = io.BytesIO()
        Image.fromarray((image * 255.0).round().astype(np.uint8)).save(buf, "JPEG", quality=90)
        buf.seek(0)
        image = np.asarray(Image.open(buf).convert("RGB"), dtype=np.float64) / 255.0
    return image, scale


def run_case(
    model, axes, light, res: int, iters: int, turn_faces: bool = True, turn=TURN, how="zbuffer"
) -> dict:
    from meschers_igl.errors import MescherError
    from meschers_igl.inverse.flatten import figure_mask
    from meschers_igl.inverse.metrics import (
        axis_aligned_share,
        figure_period,
        image_psnr,
        silhouette_iou,
    )
    from meschers_igl.inverse.optimize import extract_order, fit_mescher
    from meschers_igl.inverse.picture import fit_options, mescher_from_picture, picture_shading
    from meschers_igl.inverse.rasterizer import render_mescher
    from meschers_igl.painter import visible_faces

    target, scale = published_picture(model, res, light, how)
    R = model.camera_frame()
    out = {"model": model.name, "light": [float(v) for v in light], "target_img": target}
    t0 = time.perf_counter()
    try:
        m0, region, info = mescher_from_picture(target, light, AMBIENT, background=GROUND)
    except MescherError as exc:
        out["error"] = str(exc)
        return out
    try:
        _, _, est = mescher_from_picture(target, None, AMBIENT, background=GROUND)
        le = est["light"]
        out["light_err"] = math.degrees(math.acos(np.clip(le @ light, -1, 1)))
        mir = light * np.array([-1.0, -1.0, 1.0])
        out["light_err_mirror"] = math.degrees(math.acos(np.clip(le @ mir, -1, 1)))
    except MescherError as exc:
        out["light_error"] = str(exc)
    shade = picture_shading(info, AMBIENT)  # the light given; a grey figure's exposure
    init_img = render_mescher(m0, None, resolution=res, sigma=1e-6, background=GROUND, **shade)
    r = fit_mescher(
        target,
        m0,
        None,
        background=GROUND,
        **shade,
        options=fit_options(iters=iters, info=info, turn=turn),
        face_normals=info["normals"][region] if turn_faces else None,
    )
    m = r.mescher
    order = extract_order(m, r.offsets)
    vis = visible_faces(m, order, size=res, bounds=(-1.0, 1.0, -1.0, 1.0))
    gap = model.gap * scale
    period = figure_period(m)
    out.update(
        psnr=image_psnr(r.image, target),
        psnr_init=image_psnr(init_img, target),
        iou=silhouette_iou(r.alpha > 0.5, figure_mask(target, GROUND)),
        axis=axis_aligned_share(vis, m.face_normals(), axes @ R.T, 10.0),
        impossible=bool(m.is_impossible()),
        period=period,
        gap=gap,
        period_err=abs(period - gap) / gap if math.isfinite(gap) else math.nan,
        wall=time.perf_counter() - t0,
        faces=m.n_faces,
        init_img=init_img,
        fit_img=r.image,
    )
    return out


def passes(r: dict) -> bool:
    if "error" in r:
        return False
    per = r["period_err"]
    return (
        r["psnr"] >= 30
        and r["iou"] >= 0.98
        and r["axis"] >= 0.9
        and r["impossible"]
        and (not math.isfinite(per) or per <= 0.05)
    )


def save_panel(path: Path, r: dict) -> None:
    from PIL import Image

    imgs = [r["target_img"]] + ([r["init_img"], r["fit_img"]] if "fit_img" in r else [])
    row = np.concatenate([np.clip(i, 0, 1) for i in imgs], axis=1)
    Image.fromarray((row * 255 + 0.5).astype(np.uint8)).save(path)


def _median_worst(ok: list, n: int, key: str, worst=min, fmt: str = "{:.2f}") -> str:
    if not ok:
        return "refused"
    v = np.array([r[key] for r in ok], dtype=float)
    if np.all(~np.isfinite(v)):
        return "-"
    w = worst(v[np.isfinite(v)])
    if len(ok) < n:  # a refused picture is the worst
        return f"{fmt.format(np.nanmedian(v))}/refused"
    return f"{fmt.format(np.nanmedian(v))}/{fmt.format(w)}"


def table(rows: list[dict]) -> str:
    lines = [
        f"{'model':22s} {'pass':>5s} {'PSNR med/worst':>15s} {'IoU med/worst':>14s} "
        f"{'axis10 med/worst':>17s} {'imposs':>7s} {'period err med/worst':>21s} "
        f"{'light est err':>14s} {'wall s':>7s}"
    ]
    names = list(dict.fromkeys(r["model"] for r in rows))
    for name in names:
        rs = [r for r in rows if r["model"] == name]
        ok = [r for r in rs if "error" not in r]
        npass = sum(passes(r) for r in rs)

        le = [min(r.get("light_err", np.inf), r.get("light_err_mirror", np.inf)) for r in ok]
        le_s = f"{np.median(le):.1f} deg" if le and np.isfinite(np.median(le)) else "-"
        n = len(rs)
        lines.append(
            f"{name:22s} {npass:>2d}/{n:<2d} {_median_worst(ok, n, 'psnr'):>15s} "
            f"{_median_worst(ok, n, 'iou', fmt='{:.3f}'):>14s} "
            f"{_median_worst(ok, n, 'axis', fmt='{:.0%}'):>17s} "
            f"{sum(r.get('impossible', False) for r in rs):>3d}/{n:<3d} "
            f"{_median_worst(ok, n, 'period_err', worst=max, fmt='{:.1%}'):>21s} {le_s:>14s} "
            f"{(np.median([r['wall'] for r in ok]) if ok else float('nan')):7.1f}"
        )
    return "\n".join(lines)


def main(argv=None) -> int:
    global GROUND  # --ground: the ground of every picture and reading of this run
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", default=str(DEFAULT_MODELS), help="folder with views.json")
    ap.add_argument("--only", default=None, help="comma-separated model names")
    ap.add_argument("--lights", type=int, default=6)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--cases",
        default=None,
        metavar="NAME:K,...",
        help="only these (model, light index) pairs, e.g. tribar:3,cube:5 (rerun failures)",
    )
    ap.add_argument(
        "--picture",
        choices=("zbuffer", "antialiased", "jpeg", "outlined"),
        default="zbuffer",
        help="the pictures as rendered, antialiased (4x4 supersampled), JPEG (quality 90) or "
        "outlined (4x larger with 3 px black lines on every edge, the lines dropped as "
        "meschers inverse drops them, averaged down)",
    )
    ap.add_argument("--iters", type=int, default=300)
    ap.add_argument("--resolution", type=int, default=128)
    ap.add_argument(
        "--figures",
        default=None,
        metavar="DIR",
        help="save target | start | fit strips as DIR/<model>_<k>.png",
    )
    ap.add_argument(
        "--no-turn-faces",
        dest="turn_faces",
        action="store_false",
        help="fit without the regions' normals (no fit_mescher face_normals)",
    )
    ap.add_argument(
        "--turn-every",
        type=int,
        default=TURN[0],
        help="turn the faces back every K steps (0: once after the fit, -1: never)",
    )
    ap.add_argument(
        "--turn-weight", type=float, default=TURN[1], help="the normal penalty's weight"
    )
    ap.add_argument(
        "--ground",
        default=",".join(str(c) for c in GROUND),
        metavar="R,G,B",
        help="the pictures' ground colour in [0, 1] (default pale blue; 1,1,1: white, on which "
        "a face lit toward the light comes within a few levels of the ground)",
    )
    ap.add_argument("--log", default=None, help="append one JSON line per picture")
    ap.add_argument(
        "--table-from", default=None, metavar="LOG", help="only print the table of a --log file"
    )
    args = ap.parse_args(argv)
    GROUND = tuple(float(c) for c in args.ground.split(","))
    if args.table_from:
        rows = [json.loads(t) for t in Path(args.table_from).read_text().splitlines() if t]
        print(table(rows))
        return 0
    cases = None
    if args.cases:
        cases = {(c.rsplit(":", 1)[0], int(c.rsplit(":", 1)[1])) for c in args.cases.split(",")}
    only = set(args.only.split(",")) if args.only else None
    if cases:
        only = (only or set()) | {name for name, _ in cases}
    folder = Path(args.models)
    lights = hemisphere_lights(args.lights, args.seed)
    print(
        f"{args.resolution}^2 ({args.picture}), {args.iters} steps, {args.lights} lights "
        f"(seed {args.seed}), "
        f"ambient {AMBIENT}, ground {GROUND}, torch 1 thread"
        + (
            f", region normals (turned back every {args.turn_every}, weight {args.turn_weight})"
            if args.turn_faces
            else ""
        )
    )
    turn = (args.turn_every, args.turn_weight)
    rows = []
    for model, axes in load_models(folder if folder.is_dir() else None, only):
        for k, light in enumerate(lights):
            if cases is not None and (model.name, k) not in cases:
                continue
            try:
                r = run_case(
                    model,
                    axes,
                    light,
                    args.resolution,
                    args.iters,
                    turn_faces=args.turn_faces,
                    turn=turn,
                    how=args.picture,
                )
            except Exception as exc:  # a crash is a result too: it fails every column
                r = {
                    "model": model.name,
                    "light": [float(v) for v in light],
                    "error": f"{type(exc).__name__}: {exc}",
                    "target_img": np.ones((8, 8, 3)),
                }
            rows.append(r)
            if args.figures:
                Path(args.figures).mkdir(parents=True, exist_ok=True)
                save_panel(Path(args.figures) / f"{Path(model.name).stem}_{k}.png", r)
            brief = {k_: v for k_, v in r.items() if not k_.endswith("_img")}
            print(json.dumps(brief), flush=True)
            if args.log:
                with open(args.log, "a") as fh:
                    fh.write(json.dumps(brief) + "\n")
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
