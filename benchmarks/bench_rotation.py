"""How long the illusion holds when a mescher turns (``Mescher.rotated``).

For each gallery figure turned by a few degrees about screen x and screen y, prints:

* ``resid``: the relative projection residual (the share of the turned screen-space edge
  vectors that no single-valued ``xy`` can hold: the harmonic part of the depth leaking into
  the screen, dropped by the Poisson re-projection);
* ``back``: the share of the figure's pixels that show a back face (clockwise on screen), in
  the depth order carried by ``DepthOrder.follow``;
* ``crack``: pixels of the mescher's render left empty although a face covers their centre
  (a crack between triangles; the painter's test of :func:`meschers_igl.painter.visible_faces`
  decides coverage), and the crack the turned *cut model* opens at its seam (``meschers.metrics.seam_gap``, in % of the figure's size): a cut
  model is a real 3D object, so turning it pulls the two sides of its seam apart by the
  screen part of the period;
* ``impossible``: what still makes the turned figure impossible (``is_impossible(order=)``:
  "zeta" for a period, "order" for a depth order no 3D model has, "possible" when the
  illusion is gone);
* ``other face than cut``: the share of the figure's pixels where the order carried by
  ``DepthOrder.follow`` shows another face than the order of the turned cut model's depths
  (figures with a period only): where the mescher reads differently from its cut model at
  0 degrees (the impossibagel's crossing) and, after a turn, faces of a hidden layer that
  poke through near an impossible crossing;
* ``dL``: how far the mescher's render departs from the turned cut model's z-buffered render
  outside the seam (mean luminance difference 0-1 over pixels covered by either, pixels of
  faces touching the seam masked in both), and the silhouette IoU there.

The cut model is the figure cut as an artist cuts a bar (``straight_cut``) when it has a
period, its own 3D embedding otherwise; it is turned about the mescher's centroid and moved
on screen onto the turned mescher by the mean offset of corresponding vertices.  With
``--strips DIR`` it also writes ``DIR/turntable_<figure>.png``: the mescher and the turned cut
model from -15 to 15 degrees about y and about x.

    python benchmarks/bench_rotation.py [--size 256] [--angles 1,2,5,10,20] [--strips docs/images]
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "2")
os.environ.setdefault("OMP_NUM_THREADS", "2")

import numpy as np  # noqa: E402
from scipy import ndimage  # noqa: E402

from meschers.metrics import seam_gap  # noqa: E402
from meschers_igl import DepthOrder  # noqa: E402
from meschers_igl.embedding import straight_cut  # noqa: E402
from meschers_igl.gallery import get_model, list_models  # noqa: E402
from meschers_igl.painter import backface_share, visible_faces  # noqa: E402
from meschers_igl.rotation import rotate  # noqa: E402
from pyvista_views import render  # noqa: E402
from pyvista_views.compare import image_agreement, image_difference  # noqa: E402

LIGHTS = [(0.4, 0.6, 1.0)]
STRIP_ANGLES = (-15, -10, -5, 0, 5, 10, 15)


class Figure:
    """A gallery figure, its cut model and a fixed frame for every angle."""

    def __init__(self, name: str, size: int):
        gm = get_model(name)
        m, order = gm.mescher, gm.order
        self.name, self.size = name, size
        self.has_period = m.is_impossible()
        if self.has_period:
            cut = straight_cut(m, order)
            self.m = cut.mescher
            self.order = order.follow(cut.mescher, cut.face_parent)
            self.Vc, self.Fc, self.vmap = cut.mescher.cut_embedding(cut.cut_edges)
        else:
            self.m, self.order = m, order
            self.Vc, self.Fc, self.vmap = m.cut_embedding()
        w = self.m.star0.diagonal()
        z = self.m.hodge().z
        # the cut model's depth matches the mescher's potential up to a constant: the mean
        self.Vc = self.Vc.copy()
        first = np.unique(self.vmap, return_index=True)[1]
        self.Vc[:, 2] += (w @ z - w @ self.Vc[first, 2]) / w.sum()
        copies = np.bincount(self.vmap)[self.vmap] > 1
        self.seam_faces = np.flatnonzero(copies[self.Fc].any(axis=1))
        lo, hi = self.m.xy.min(0), self.m.xy.max(0)
        c, r = (lo + hi) / 2, 0.62 * (hi - lo).max()
        self.bounds = (c[0] - r, c[0] + r, c[1] - r, c[1] + r)
        self.scale = self.m.scale()
        self.base_cracks = {}

    def turned_cut(self, turn) -> np.ndarray:
        """The cut model turned like ``turn``, moved on screen onto the turned mescher."""
        w = self.m.star0.diagonal()
        P = np.column_stack([self.m.xy, self.m.hodge().z])
        centre = (w @ P) / w.sum()
        V = (self.Vc - centre) @ turn.matrix.T + centre
        V[:, :2] += (turn.mescher.xy[self.vmap] - V[:, :2]).mean(axis=0)
        return V

    def pixel_centres(self) -> np.ndarray:
        x0, x1, y0, y1 = self.bounds
        n = self.size
        s = (np.arange(n) + 0.5) / n
        X, Y = np.meshgrid(x0 + s * (x1 - x0), y1 - s * (y1 - y0))
        return np.column_stack([X.ravel(), Y.ravel()])

    def seam_band(self, tri_sets) -> np.ndarray:
        """(size, size) bool: pixels inside any of the given screen triangles, dilated 2 px."""
        p = self.pixel_centres()
        inside = np.zeros(p.shape[0], dtype=bool)
        for T in tri_sets:  # (k, 3, 2) triangles, k small (faces touching the seam)
            a, b, c = T[:, 0, None], T[:, 1, None], T[:, 2, None]
            d = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
                c[..., 0] - a[..., 0]
            )
            d = np.where(np.abs(d) < 1e-300, 1e-300, d)
            q = p[None]
            u = (
                (b[..., 0] - q[..., 0]) * (c[..., 1] - q[..., 1])
                - (b[..., 1] - q[..., 1]) * (c[..., 0] - q[..., 0])
            ) / d
            v = (
                (c[..., 0] - q[..., 0]) * (a[..., 1] - q[..., 1])
                - (c[..., 1] - q[..., 1]) * (a[..., 0] - q[..., 0])
            ) / d
            inside |= ((u >= 0) & (v >= 0) & (u + v <= 1)).any(axis=0)
        mask = inside.reshape(self.size, self.size)
        return ndimage.binary_dilation(mask, iterations=2)

    def render_pair(self, turn):
        V = self.turned_cut(turn)
        win = (self.size, self.size)
        img_m = render(turn.mescher, turn.order, lights=LIGHTS, window_size=win, bounds=self.bounds)
        img_c = render((V, self.Fc), lights=LIGHTS, window_size=win, bounds=self.bounds)
        return img_m, img_c, V


def holes(fig: Figure, m, order, img: np.ndarray) -> int:
    """Pixels inside the figure (all 8 neighbours covered too) whose centre some face covers
    but the render leaves background: cracks between triangles."""
    covered = visible_faces(m, order, size=fig.size, bounds=fig.bounds) >= 0
    inner = ndimage.binary_erosion(covered, structure=np.ones((3, 3)))  # not the silhouette
    return int(np.count_nonzero(inner & np.all(img == 255, axis=-1)))


def order_defect(fig: Figure, turn, V: np.ndarray) -> float:
    """Share of the figure's pixels whose visible face differs between the followed order and
    the order of the turned cut model's depths (``DepthOrder.from_embedding``); NaN for
    figures impossible through their order alone (no cut model has their order)."""
    if not fig.has_period:
        return float("nan")
    ref = DepthOrder.from_embedding(turn.mescher, V[:, 2][fig.Fc])
    a = visible_faces(turn.mescher, turn.order, size=fig.size, bounds=fig.bounds)
    b = visible_faces(turn.mescher, ref, size=fig.size, bounds=fig.bounds)
    hit = (a >= 0) | (b >= 0)
    return float(np.mean(a[hit] != b[hit])) if hit.any() else 0.0


def measure(fig: Figure, degrees: float, axis: str) -> dict:
    t0 = time.perf_counter()
    turn = rotate(fig.m, degrees, axis, order=fig.order)
    t_turn = time.perf_counter() - t0
    img_m, img_c, V = fig.render_pair(turn)
    band = fig.seam_band(
        [turn.mescher.xy[fig.m.F[fig.seam_faces]], V[:, :2][fig.Fc[fig.seam_faces]]]
    )
    a, b = img_m.copy(), img_c.copy()
    a[band], b[band] = 255, 255
    agree = image_agreement(a, b)
    px = (fig.bounds[1] - fig.bounds[0]) / fig.size
    return {
        "resid": turn.residual,
        "back": backface_share(turn.mescher, turn.order, size=fig.size, bounds=fig.bounds),
        "crack_px": holes(fig, turn.mescher, turn.order, img_m),
        "cut_crack": seam_gap(V[:, :2], fig.vmap) / fig.scale,
        "cut_crack_px": seam_gap(V[:, :2], fig.vmap) / px,
        "dL": image_difference(a, b),
        "iou": agree["iou"],
        "periods": turn.mescher.periods(),
        "kind": turn.mescher.is_impossible(order=turn.order).kind or "possible",
        "order_defect": order_defect(fig, turn, V),
        "t_turn": t_turn,
        "images": (img_m, img_c),
    }


def strip(fig: Figure, path: str) -> None:
    from meschers.figures import compose

    rows, labels, notes = [], [], []
    for axis in ("y", "x"):
        row_m, row_c, note_m, note_c = [], [], [], []
        for deg in STRIP_ANGLES:
            r = measure(fig, float(deg), axis)
            row_m.append(r["images"][0])
            row_c.append(r["images"][1])
            note_m.append(f"back {r['back']:.1%}  res {r['resid']:.3f}")
            note_c.append(f"crack {r['cut_crack']:.1%}  dL {r['dL']:.3f}")
        rows += [row_m, row_c]
        notes += [note_m, note_c]
        labels += [f"mescher, {axis}", f"cut model, {axis}"]
    cols = [f"{d:+d} deg" if d else "0 deg" for d in STRIP_ANGLES]
    compose(rows, col_labels=cols, row_labels=labels, notes=notes).save(path)
    print(f"wrote {path}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--angles", default="1,2,5,10,20")
    ap.add_argument("--models", default=",".join(list_models()))
    ap.add_argument("--strips", default=None, help="folder for turntable_<figure>.png")
    ap.add_argument("--strip-size", type=int, default=180)
    args = ap.parse_args(argv)
    angles = [float(a) for a in args.angles.split(",")]
    print(
        "| figure | axis | deg | resid | back | crack px (mescher) | cut crack (% size, px) "
        "| dL outside seam | IoU | period / period(0) | impossible | other face than cut | turn s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.models.split(","):
        fig = Figure(name, args.size)
        p0 = fig.m.periods()
        k = int(np.argmax(np.abs(p0))) if p0.size else 0
        for axis in ("y", "x"):
            for deg in [0.0, *angles]:
                r = measure(fig, deg, axis)
                ratio = f"{r['periods'][k] / p0[k]:.4f}" if fig.has_period else "-"
                od = f"{r['order_defect']:.2%}" if fig.has_period else "-"
                print(
                    f"| {name} | {axis} | {deg:g} | {r['resid']:.2e} | {r['back']:.2%} | "
                    f"{r['crack_px']:d} | {r['cut_crack']:.2%}, "
                    f"{r['cut_crack_px']:.1f} | {r['dL']:.4f} | {r['iou']:.3f} | "
                    f"{ratio} | {r['kind']} | {od} | {r['t_turn']:.3f} |",
                    flush=True,
                )
        if args.strips:
            small = Figure(name, args.strip_size)
            strip(small, os.path.join(args.strips, f"turntable_{name}.png"))


if __name__ == "__main__":
    main()
