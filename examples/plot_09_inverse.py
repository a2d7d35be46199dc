"""
Inverse rendering
=================

Fit a mescher to a picture (paper Sec. 4.5): a soft rasterizer renders the flattened mescher,
and PyTorch moves ``xy`` and ``zeta = d01 z + H c`` in alternating steps, so every iterate is
a mescher (``d12 zeta = 0``). Starting from an ordinary torus, the fit has to *learn* a period to
draw a Penrose triangle. This example is tiny (32 x 32 pixels, 100 steps) to stay fast: the
torus only starts to turn into the triangle. ``meschers inverse penrose --init torus`` runs the
full fit from a torus; the default start, ``mescher_from_picture``, reads the faces, holes and
depths from the picture itself (README, "Inverse rendering": ``meschers inverse tribar``).

PyTorch is optional (``pip install "meschers[inverse]"``); without it this example says so and
stops.
"""

import importlib.util

import matplotlib.pyplot as plt
import numpy as np

if importlib.util.find_spec("torch") is None:
    print("PyTorch is not installed: pip install 'meschers[inverse]' to run this example.")
    fig, ax = plt.subplots(figsize=(6, 2))
    ax.text(0.5, 0.5, "needs PyTorch: pip install 'meschers[inverse]'", ha="center", va="center")
    ax.axis("off")
    plt.show()
else:
    from meschers_igl.inverse import (
        InverseOptions,
        fit_mescher,
        penrose_target,
        silhouette_iou,
        target_mask,
        torus_for_target,
    )

    lights = [(0.4, 0.25, 1.0)]  # direction toward the light, camera frame
    target = penrose_target(32, lights=lights)  # (32, 32, 3) in [0, 1], spans [-1, 1]^2
    init, offsets = torus_for_target(target)  # an ordinary torus covering the target
    options = InverseOptions(iters=100)
    result = fit_mescher(target, init, offsets, lights=lights, options=options)
    iou = silhouette_iou(target_mask(result.image), target_mask(target))
    print(f"{options.iters} steps in {result.seconds:.1f} s; silhouette IoU {iou:.3f}")
    print("largest |d12 zeta| over all iterates:", result.max_residual)
    print(
        "periods of the torus, of the result:",
        np.round(init.periods(), 3),
        np.round(result.mescher.periods(), 3),
    )

    # %%
    # Target, the fitted render, and the loss per step. The fit is rendered again at 256 x 256
    # (not its 32-pixel working render enlarged); the 32-pixel target is shown enlarged by whole
    # pixels (nearest neighbour), as its title says.
    from meschers.inverse_cli import enlarge_nearest
    from meschers_igl.inverse import render_mescher

    shown, k = enlarge_nearest(target, 256)
    fitted = render_mescher(
        result.mescher, result.offsets, lights=lights, resolution=256, sigma=1e-6
    )
    fig, axes = plt.subplots(1, 3, figsize=(12, 4))
    axes[0].imshow(shown, interpolation="nearest")
    axes[0].set_title(f"target ({target.shape[0]} px, shown {k}x, nearest)")
    axes[1].imshow(np.clip(fitted, 0, 1))
    axes[1].set_title(f"fit after {options.iters} steps (256 px)")
    for ax in axes[:2]:
        ax.axis("off")
    axes[2].semilogy(result.losses)
    axes[2].set(title="loss", xlabel="step")
    fig.tight_layout()
    plt.show()

    # %%
    # From a line drawing. The black lines of a drawing enclose the faces; the three directions
    # the lines run in are read as three right angles (the frame follows from their screen
    # angles alone), each face takes the orientation whose direction its edges avoid, and the
    # drawing becomes a shaded picture, lifted to a mescher whose period comes from the loop.
    # ``meschers inverse drawing.png --out fit`` does this when it is given a drawing.
    from scipy import ndimage

    from meschers_igl.inverse import mescher_from_picture, shade_drawing

    picture = penrose_target(256, lights=lights)
    grey = np.round(picture.mean(axis=-1) * 255)
    edge = np.zeros(grey.shape, dtype=bool)  # a drawing: black where the shade changes
    edge[:, 1:] |= np.abs(np.diff(grey, axis=1)) > 2
    edge[1:] |= np.abs(np.diff(grey, axis=0)) > 2
    drawing = np.where(ndimage.binary_dilation(edge)[..., None], 0.0, 1.0) * np.ones(3)
    reading = shade_drawing(drawing)  # faces, their orientations, a light, the shaded picture
    m, _, _ = mescher_from_picture(reading.picture, reading.light)
    lifted = render_mescher(m, None, lights=[reading.light], resolution=256, sigma=1e-6)
    print("from the drawing: impossible", m.is_impossible(), "period", np.round(m.periods(), 3))
    fig, axes = plt.subplots(1, 3, figsize=(12, 4))
    for ax, img, title in zip(
        axes, (drawing, reading.picture, lifted), ("drawing", "its reading", "mescher")
    ):
        ax.imshow(np.clip(img, 0, 1))
        ax.set_title(title)
        ax.axis("off")
    fig.tight_layout()
    plt.show()

# %%
# The full fit, ``meschers inverse penrose --out fit`` (1200 steps at 128 x 128), ends with a
# Penrose triangle: target, torus initialization and recovered mescher.
#
# .. image:: /images/inverse_penrose.png
#    :alt: Inverse rendering: target, torus initialization, recovered mescher
