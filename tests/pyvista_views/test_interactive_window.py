"""The interactive window under a real X server (Xvfb): widgets and help beside the figure.

``meschers view`` opens :class:`pyvista_views.MescherViewer`'s window.  Here it is opened under
Xvfb in a child process and screenshotted with its widgets, then again with every widget, text
and colour bar hidden: the figure's columns must be identical (nothing drawn over the figure),
every widget must lie in the side panel and inside the window, and the text must be readable
(lines at least 14 pixels high at the default 800 x 800).  Skipped where Xvfb is absent
(``.ci/run`` installs Debian's ``xvfb``).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from pvv_helpers import requires_gl

pytestmark = [
    requires_gl,
    pytest.mark.render,
    pytest.mark.slow,
    pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="Xvfb (Debian xvfb) not installed"),
]

CHILD = textwrap.dedent(
    """
    import json, sys
    import numpy as np
    from PIL import Image
    from meschers_igl.gallery import get_model
    from pyvista_views import MescherViewer
    from pyvista_views.interactive import HELP_FONT_SIZE

    g = get_model("penrose_triangle")
    m = g.mescher
    viewer = MescherViewer(m, g.order, scalars={"x": np.asarray(m.xy)[:, 0]})
    assert not viewer.off_screen, "expected an on-screen window under Xvfb"
    viewer.show(interactive_update=True, auto_close=False)
    pl = viewer.scene.plotter
    ren = pl.renderer
    pl.render()
    shown = pl.screenshot(return_img=True)[..., :3]
    W, H = (int(v) for v in pl.window_size)
    boxes = {}
    for i, widget in enumerate(pl.slider_widgets):
        rep = widget.GetRepresentation()
        a = rep.GetPoint1Coordinate().GetComputedDisplayValue(ren)
        b = rep.GetPoint2Coordinate().GetComputedDisplayValue(ren)
        boxes[f"slider{i}"] = [min(a[0], b[0]), max(a[0], b[0]), min(a[1], b[1]), max(a[1], b[1])]
        boxes[f"slider{i}_title_px"] = rep.GetTitleHeight() * H
    help_actor = pl.actors["help"]
    bbox = [0.0] * 4
    help_actor.GetBoundingBox(ren, bbox)  # relative to the actor's position
    px, py = help_actor.GetPositionCoordinate().GetComputedDisplayValue(ren)
    boxes["help"] = [px + bbox[0], px + bbox[1], py + bbox[2], py + bbox[3]]
    boxes["help_lines"] = help_actor.GetInput().count(chr(10)) + 1
    for title, bar in pl.scalar_bars.items():
        lo = bar.GetPositionCoordinate().GetComputedDisplayValue(ren)
        hi = bar.GetPosition2Coordinate().GetComputedDisplayValue(ren)
        boxes["bar"] = [lo[0], hi[0], lo[1], hi[1]]
    # hide everything that is not the figure, render again
    for widget in pl.slider_widgets:
        widget.Off()
    help_actor.VisibilityOff()
    for bar in pl.scalar_bars.values():
        bar.VisibilityOff()
    pl.render()
    bare = pl.screenshot(return_img=True)[..., :3]
    Image.fromarray(shown).save(sys.argv[1] + "/shown.png")
    np.save(sys.argv[1] + "/bare.npy", bare)
    np.save(sys.argv[1] + "/shown.npy", shown)
    print(json.dumps({"W": W, "H": H, "panel": viewer._panel, "boxes": boxes}))
    """
)


@pytest.fixture(scope="module")
def window(tmp_path_factory):
    out = tmp_path_factory.mktemp("xvfb")
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("VTK_DEFAULT_OPENGL_WINDOW", "PYVISTA_OFF_SCREEN", "DISPLAY")
    }
    proc = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", sys.executable, "-c", CHILD, str(out)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    info = json.loads(proc.stdout.strip().splitlines()[-1])
    return info, np.load(out / "shown.npy"), np.load(out / "bare.npy")


def test_nothing_is_drawn_over_the_figure(window):
    info, shown, bare = window
    W, H, panel = info["W"], info["H"], info["panel"]
    w = W - panel
    assert (W, H) == (800 + panel, 800) and panel >= 300  # the figure keeps its 800 x 800
    figure = bare.min(axis=-1) < 250
    assert figure[:, :w].sum() > 0.2 * w * H and not figure[:, w:].any()  # figure left only
    np.testing.assert_array_equal(shown[:, :w], bare[:, :w])  # widgets changed no figure pixel
    assert (shown[:, w:] != bare[:, w:]).any(axis=-1).mean() > 0.05  # they are in the panel


def test_widgets_and_help_lie_in_the_panel_and_are_readable(window):
    info, *_ = window
    W, H, panel = info["W"], info["H"], info["panel"]
    w = W - panel
    b = info["boxes"]
    for name in ("slider0", "slider1", "help", "bar"):
        x0, x1, y0, y1 = b[name]
        assert w <= x0 and x1 <= W - 4, f"{name} x range {x0:.0f}-{x1:.0f} leaves [{w}, {W}]"
        assert 0 <= y0 and y1 <= H, f"{name} y range {y0:.0f}-{y1:.0f} leaves the window"
    # stacked, not overlapping: sliders above the help, the help above the colour bar
    assert b["slider1"][2] > b["help"][3] and b["help"][2] > b["bar"][3]
    assert (b["help"][3] - b["help"][2]) / b["help_lines"] >= 14  # line height in pixels
    assert b["slider0_title_px"] >= 14 and b["slider1_title_px"] >= 14
