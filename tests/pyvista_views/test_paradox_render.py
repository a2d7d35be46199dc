"""Issue 8: meschers made from the ParadoxToolkit cut models render like the models themselves.

For each of the 18 shipped files: the mescher (glued with only the JSON's camera) drawn back to
front in the order taken from the cut model matches a z-buffered render of the cut model under
the same orthographic camera, for several directional lights -- including the stair boxes whose
faces touch face to face and the back faces of the tubes -- and again after one midpoint
subdivision with the order carried to the children.
"""

from __future__ import annotations

import numpy as np
import pytest
from pvv_helpers import requires_gl

from meschers_igl.operators import view_frame
from meschers_igl.paradox import list_paradox_models, paradox_model
from pyvista_views import MescherScene
from pyvista_views.compare import image_agreement

pytestmark = [requires_gl, pytest.mark.render]

LIGHTS = [(1.0, 1.0, 1.0), (-1.0, 0.4, 0.8), (0.3, -1.0, 0.6)]
SIZE = 160


def _renders(scene, add, bounds):
    scene.clear()
    add()
    scene.view(bounds)
    out = []
    for light in LIGHTS:
        scene.relight([light])
        out.append(scene.screenshot())
    return out


@pytest.fixture(scope="module")
def scene():
    return MescherScene(window_size=(SIZE, SIZE))


@pytest.mark.parametrize("name", list_paradox_models())
def test_mescher_renders_like_the_cut_model(scene, name):
    from meshlab_filters import cut_model_to_mescher, load_artist_model

    pm = paradox_model(name)
    V, F, _ = load_artist_model(pm.obj)
    m, order = cut_model_to_mescher((V, F), view=pm.view, up=pm.up)
    Vc = V @ view_frame(pm.view, pm.up).T
    lo, hi = Vc[:, :2].min(axis=0), Vc[:, :2].max(axis=0)
    pad = 0.05 * float(np.max(hi - lo))
    bounds = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
    ref = _renders(scene, lambda: scene.add_embedding(Vc, F, shading="flat"), bounds)
    fine, fine_order = m.subdivide(1, "midpoint", order=order)
    for mm, oo in ((m, order), (fine, fine_order)):
        got = _renders(scene, lambda mm=mm, oo=oo: scene.add(mm, order=oo, shading="flat"), bounds)
        for a, b in zip(got, ref):
            g = image_agreement(a, b)
            assert g["iou"] >= 0.98, (name, mm.n_faces, g)
            assert g["luminance_corr"] >= 0.97, (name, mm.n_faces, g)
