"""Naming models: gallery names, shipped models, files with sidecar views, folders and globs."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from meschers.inputs import expand_models, load_artist, load_mescher, resolve
from meschers_igl import MescherError, save
from meschers_igl.gallery import get_model
from meschers_igl.paradox import paradox_model


def test_gallery_and_shipped_names():
    assert (resolve("penrose_triangle").kind, resolve("gallery:window").name) == (
        "gallery",
        "window",
    )
    spec = resolve("paradox:penrose_triangle")
    pm = paradox_model("penrose_triangle")
    assert spec.kind == "artist" and spec.view == pm.view and spec.up == pm.up
    with pytest.raises(MescherError, match="INPUT: expected .*penrose_triangle.*found 'nope'"):
        resolve("nope")
    with pytest.raises(MescherError, match="penrose_triangle"):
        resolve("paradox:nope")


def test_files_folders_and_globs(tmp_path):
    pm = paradox_model("penrose_triangle")
    shutil.copy(pm.obj, tmp_path / "tri.obj")
    (tmp_path / "tri.json").write_text(json.dumps({"view": list(pm.view), "up": list(pm.up)}))
    g = get_model("impossibagel")
    save(g.mescher, tmp_path / "bagel.npz", order=g.order)
    (tmp_path / "notes.txt").write_text("not a model")
    specs = expand_models([str(tmp_path)])
    assert [(s.kind, s.name) for s in specs] == [("mescher", "bagel"), ("artist", "tri")]
    assert specs[1].view == pm.view  # the simple sidecar layout
    # a glob, a file named twice, and a name: each model once, in the order given
    again = expand_models([str(tmp_path / "*.obj"), str(tmp_path / "tri.obj"), "window"])
    assert [(s.kind, s.name) for s in again] == [("artist", "tri"), ("gallery", "window")]
    m, order = load_mescher(specs[0])
    np.testing.assert_allclose(m.periods(), g.mescher.periods(), atol=1e-12)
    assert order is not None and order.n_arcs == g.order.n_arcs


def test_artist_file_needs_a_view(tmp_path):
    pm = paradox_model("penrose_triangle")
    shutil.copy(pm.obj, tmp_path / "tri.obj")
    with pytest.raises(MescherError, match="sidecar 'tri.json'.*meschers convert"):
        resolve(str(tmp_path / "tri.obj"))
    (tmp_path / "tri.json").write_text('{"camera": {}}')
    with pytest.raises(MescherError, match="tri.json: expected a view"):
        resolve(str(tmp_path / "tri.obj"))
    with pytest.raises(MescherError, match="expected model files in"):
        expand_models([str(tmp_path / "*.stl")])
    with pytest.raises(MescherError, match="found nothing at"):
        resolve(str(tmp_path / "absent.ply"))


def test_shipped_model_converts_like_its_metadata_says():
    pytest.importorskip("pymeshlab")
    spec = resolve("paradox:penrose_triangle")
    m, order, Vcam, F, report = load_artist(spec)
    gap = max(spec.meta["verification"]["depth_gaps"])
    assert np.abs(m.periods()).max() == pytest.approx(gap, rel=1e-4)
    assert m.euler_characteristic() == spec.meta["verification"]["glued_chi"]
    # the model in camera coordinates lies on the mescher's screen positions
    np.testing.assert_allclose(
        Vcam[F][..., :2].reshape(-1, 2).min(0), np.asarray(m.xy).min(0), atol=1e-6
    )
