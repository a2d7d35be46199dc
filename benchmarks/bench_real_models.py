"""Real models of impossible figures, as people publish them, through the one door.

For each model file in FOLDER (with its ``views.json``: view, up, the depth gaps between
vertices that coincide on screen) and each view -- the given one and ``view="auto"``, each
followed by a ``+mh`` row with ``perceive="manhattan"`` where the converter suggests it -- prints
the route taken, whether the mescher is impossible and how (``zeta``: a period; ``order``: the
depth order cannot be realised), its periods against the coincident-pair gaps, the silhouette
IoU and the least luminance correlation over four lights against PyVista's z-buffer of the
model from the same view (``pyvista_views.compare.image_agreement``), and the time of the
conversion (``meshlab_filters.model_to_mescher``: loading and clean-up included).  As a
yardstick measured in the same run, the z-buffer render of the model itself.

    python benchmarks/bench_real_models.py FOLDER [--size 160] [--save DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import time
import warnings
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "2")
os.environ.setdefault("OMP_NUM_THREADS", "2")

import numpy as np  # noqa: E402

LIGHTS = [(0.3, 0.5, 1.0), (-0.6, 0.2, 0.4), (0.5, -0.7, 0.6), (-0.2, -0.3, 1.0)]


def _model(path: Path):
    from meshlab_filters.load import read_meshset

    ms = read_meshset(path)  # the mesh lives in its MeshSet: keep it alive while reading
    mesh = ms.current_mesh()
    return np.asarray(mesh.vertex_matrix(), float), np.asarray(mesh.face_matrix(), np.int64)


def _agreement(m, order, V, F, report, size, save):
    """(IoU, least luminance correlation over LIGHTS, seconds of the z-buffer renders)."""
    from meschers_igl.operators import view_frame
    from pyvista_views import render
    from pyvista_views.compare import image_agreement

    C = V @ view_frame(report.view, report.up).T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    c, h = 0.5 * (lo + hi), 0.55 * float((hi - lo).max())
    kw = dict(window_size=(size, size), bounds=(c[0] - h, c[0] + h, c[1] - h, c[1] + h))
    iou, corr, t_ref, pics = 1.0, 1.0, 0.0, []
    for light in LIGHTS:  # four renders of each
        t = time.perf_counter()
        ref = render((C, F), lights=[light], **kw)
        t_ref += time.perf_counter() - t
        img = render(m, order=order, lights=[light], **kw)
        a = image_agreement(img, ref)
        iou, corr = min(iou, a["iou"]), min(corr, a["luminance_corr"])
        pics.append(np.hstack([ref, img]))
    if save:
        from PIL import Image

        Image.fromarray(np.vstack(pics[:2])).save(save)
    return iou, corr, t_ref


def _row(path, given, gaps, auto, size, save_dir, perceive=None):
    from meschers_igl import MescherError
    from meshlab_filters import model_to_mescher

    view, up = ("auto", None) if auto else given
    t = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            kw = {} if auto else {"up": up}
            m, order, report = model_to_mescher(path, view=view, perceive=perceive, **kw)
    except MescherError as err:
        return f"refused: {str(err)[:70]}", (None, False)
    dt = time.perf_counter() - t
    imp = m.is_impossible(order=order)
    p = np.abs(np.asarray(m.periods()))
    p = np.unique(np.round(p, 3))
    p = p[p > 0]
    match = [g for g in gaps if np.any(np.isclose(p, g, rtol=2e-3))]
    V, F = _model(path)
    save = None
    if save_dir:
        tag = ("auto" if auto else "given") + ("_manhattan" if perceive else "")
        save = str(Path(save_dir) / f"{path.name}_{tag}.png")
    iou, corr, t_ref = _agreement(m, order, V, F, report, size, save)
    kind = imp.kind or "no"
    per = ",".join(f"{x:g}" for x in p[:3]) + ("..." if p.size > 3 else "") or "-"
    return (
        f"{report.route:7s} {kind:5s} {per:>18s} {len(match)}/{len(gaps)} {iou:5.3f} {corr:5.3f} "
        f"{dt:5.2f}s (z-buffer x4 {t_ref:4.2f}s)"
    ), (imp.kind, any("perceive='manhattan'" in w for w in report.warnings))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "folder",
        nargs="?",
        default=os.environ.get("MESCHERS_REAL_MODELS", "."),
        help="a folder of model files with their views.json (default: "
        "$MESCHERS_REAL_MODELS, else the current folder)",
    )
    ap.add_argument("--size", type=int, default=160, help="render size in pixels")
    ap.add_argument("--save", default=None, help="folder for z-buffer | mescher pictures")
    a = ap.parse_args(argv)
    folder = Path(a.folder)
    if not (folder / "views.json").is_file():
        print(f"no views.json in {folder}: nothing to measure")
        return
    from pyvista_views.headless import configure_headless

    configure_headless()
    views = json.loads((folder / "views.json").read_text())
    if a.save:
        Path(a.save).mkdir(parents=True, exist_ok=True)
    print(
        f"{'file':22s} {'view':5s} {'route':7s} {'imp':5s} {'periods':>18s} gap  IoU   corr  time"
    )
    n_imp = {False: 0, True: 0}
    n_perceived = {False: 0, True: 0}
    n = 0
    for name, d in views.items():
        if name.startswith("_") or not (folder / name).is_file():
            continue
        n += 1
        gaps = [float(g) for g in d.get("coincident_depth_gaps", [])]
        for auto in (False, True):
            line, (kind, hint) = _row(
                folder / name, (d["view"], d["up"]), gaps, auto, a.size, a.save
            )
            n_imp[auto] += kind is not None
            print(f"{name[:22]:22s} {'auto' if auto else 'given':5s} {line}")
            if hint:  # the converter suggests perceived right angles: take it
                line, (kind, _) = _row(
                    folder / name,
                    (d["view"], d["up"]),
                    gaps,
                    auto,
                    a.size,
                    a.save,
                    perceive="manhattan",
                )
                # perceived depths against the model's own order: only a period counts
                n_perceived[auto] += kind == "zeta"
                print(f"{name[:22]:22s} {'+mh':5s} {line}")
    took = {
        a: f"{n_imp[a] + n_perceived[a]}/{n} taking the suggested perceive='manhattan'"
        for a in n_imp
    }
    print(
        f"impossible: {n_imp[False]}/{n} from the given view ({took[False]}), {n_imp[True]}/{n} "
        f"from view='auto' ({took[True]})"
    )


if __name__ == "__main__":
    main()
