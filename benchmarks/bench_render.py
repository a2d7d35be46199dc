"""Rendering cost of a mescher against PyVista rendering an ordinary mesh of the same size.

Measures, at ~1M faces and a 1024^2 image, offscreen:

- build + first frame: ``to_polydata`` (flattened, painter-ordered soup with zeta's normals) +
  plotter + lights + screenshot, vs ``pv.PolyData(V, F)`` + plotter + screenshot;
- a relit frame: new light + render + screenshot, vs the same on the ordinary mesh.

Prints both times and their ratios (targets: <= 1.5x and <= 1.2x).  The machine is shared: run it
once or twice, not in a loop.  ``python benchmarks/bench_render.py [--faces N] [--size S]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pyvista as pv

import pyvista_views  # noqa: F401  (EGL set-up before the first window)
from meschers_igl import Mescher
from pyvista_views import MescherScene
from pyvista_views._offscreen import new_plotter


def sphere_with_faces(n_faces: int) -> tuple[np.ndarray, np.ndarray]:
    res = max(int(np.sqrt(n_faces / 2)), 8)
    s = pv.Sphere(theta_resolution=res, phi_resolution=res + 2)
    return np.asarray(s.points, dtype=np.float64), s.regular_faces.astype(np.int64)


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, default=1_000_000)
    parser.add_argument("--size", type=int, default=1024)
    args = parser.parse_args(argv)
    pv.OFF_SCREEN = True
    size = (args.size, args.size)
    V, F = sphere_with_faces(args.faces)
    m = Mescher.from_mesh(V, F)
    order = np.argsort(V[F][:, :, 2].mean(axis=1), kind="stable")  # given, like a DepthOrder
    light_a, light_b = (1.0, 1.0, 1.0), (-1.0, 0.2, 0.5)
    print(f"{F.shape[0]} faces, {V.shape[0]} vertices, {args.size}^2 image")

    # Warm-up: the first GL context in a process pays for driver start-up; not ours to count.
    warm = new_plotter((64, 64))
    warm.add_mesh(pv.Sphere())
    warm.screenshot(return_img=True)
    warm.close()

    def peer_first():
        plotter = new_plotter(size)
        plotter.add_mesh(pv.PolyData.from_regular_faces(V, F), color="lightgray", specular=0.0)
        plotter.add_light(pv.Light(position=light_a, light_type="scene light", positional=False))
        plotter.view_xy()
        plotter.enable_parallel_projection()
        return plotter, plotter.screenshot(return_img=True)

    def peer_relight(plotter):
        plotter.remove_all_lights()
        plotter.add_light(pv.Light(position=light_b, light_type="scene light", positional=False))
        plotter.render()
        return plotter.screenshot(return_img=True)

    def ours_first():
        scene = MescherScene(window_size=size)
        scene.add(m, order=order, shading="flat")
        scene.view()
        scene.relight([light_a])
        return scene, scene.screenshot()

    def ours_relight(scene):
        scene.relight([light_b])
        return scene.screenshot()

    t_peer_first, (plotter, _) = timed(peer_first)
    t_peer_relit, _ = timed(lambda: peer_relight(plotter))
    plotter.close()
    t_first, (scene, _) = timed(ours_first)
    t_relit, _ = timed(lambda: ours_relight(scene))
    scene.close()

    print(f"{'':28s}{'mescher':>10s}{'pyvista':>10s}{'ratio':>8s}  target")
    print(
        f"{'build + first frame (s)':28s}{t_first:10.3f}{t_peer_first:10.3f}"
        f"{t_first / t_peer_first:8.2f}  <= 1.5"
    )
    print(
        f"{'relit frame (s)':28s}{t_relit:10.3f}{t_peer_relit:10.3f}"
        f"{t_relit / t_peer_relit:8.2f}  <= 1.2"
    )


if __name__ == "__main__":
    main()
