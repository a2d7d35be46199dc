"""Models as people publish them, perturbed: a mescher or one MescherError, never a traceback.

Every model of the test suites (and, when the development set of real files is present, each
of its files) is perturbed the ways real files differ from clean ones -- vertex jitter at 1e-6
and 1e-3 of the size, dropped faces, flipped faces, duplicated parts (moved, or left in
place), the model moved a thousand sizes away, quads split along the other diagonal -- and
converted through the one door from its view.  The outcome must be a
valid mescher whose verdict agrees with its periods, or a ``MescherError``.  A seeded subset
runs by default; ``MESCHERS_FUZZ=200`` runs 200 perturbations per model.

Scenes: many separate parts on a huge ground plane, thousands of faces, degenerate and
repeated-vertex faces.  Ordinary models stay possible from any view.
"""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path

import numpy as np
import pytest
from builders import box_mesh, merge_meshes, ordinary_stairs
from visible_models import ISO_UP, ISO_VIEW, block_stairs, hidden_gap_cube, triangulate, u_tribar

from meschers_igl import MescherError
from meschers_igl.obtain import PERIOD_RTOL, model_to_mescher

REAL = Path(__file__).resolve().parents[3] / "shared" / "real_models"
N_FUZZ = int(os.environ.get("MESCHERS_FUZZ", "6"))
KINDS = ("jitter6", "jitter3", "drop", "flip", "duplicate", "inplace", "far", "resplit")


def _suite():
    out = {}
    for name, make in (
        ("u_tribar", u_tribar),
        ("block_stairs", block_stairs),
        ("hidden_gap_cube", hidden_gap_cube),
    ):
        V, P, _ = make()
        out[name] = (V, triangulate(P), ISO_VIEW, ISO_UP)
    return out


def _real():
    pymeshlab = pytest.importorskip("pymeshlab")
    views = json.loads((REAL / "views.json").read_text())
    out = {}
    for name, d in views.items():
        if name.startswith("_"):
            continue
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(str(REAL / name))
        mesh = ms.current_mesh()
        V = np.asarray(mesh.vertex_matrix(), float)
        F = np.asarray(mesh.face_matrix(), np.int64)
        out[name] = (V, F, np.asarray(d["view"]), np.asarray(d["up"]))
    return out


def _resplit(V, F, rng):
    """Flip the diagonal of some quads (pairs of coplanar triangles sharing an edge)."""
    F = F.copy()
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    seen: dict = {}
    done = np.zeros(F.shape[0], dtype=bool)
    for f in rng.permutation(F.shape[0]).tolist():  # test code: small models
        for k in range(3):
            a, b = int(F[f, k]), int(F[f, (k + 1) % 3])
            g = seen.get((b, a))
            if g is not None and not done[f] and not done[g] and n[f] @ n[g] > 1 - 1e-12:
                c = int(F[f, (k + 2) % 3])
                d = int(next(x for x in F[g] if x not in (a, b)))
                F[f], F[g] = [c, a, d], [d, b, c]
                done[f] = done[g] = True
            seen[(a, b)] = f
    return F


def perturb(V, F, kind, seed):
    """One perturbation of the model (V, F) of the given kind."""
    rng = np.random.default_rng(seed)
    size = float(np.linalg.norm(np.ptp(V, axis=0)))
    if kind in ("jitter6", "jitter3"):
        eps = 1e-6 if kind == "jitter6" else 1e-3
        return V + eps * size * rng.uniform(-1, 1, V.shape), F
    if kind == "drop":
        keep = rng.random(F.shape[0]) > max(1.0 / F.shape[0], 0.03)
        return V, F[keep]
    if kind == "flip":
        F = F.copy()
        sel = rng.random(F.shape[0]) < 0.1
        F[sel] = F[sel][:, [0, 2, 1]]
        return V, F
    if kind == "duplicate":
        shift = rng.normal(size=3) * size
        return np.vstack([V, V + shift]), np.vstack([F, F + V.shape[0]])
    if kind == "inplace":  # a copy left where it was made
        return np.vstack([V, V]), np.vstack([F, F + V.shape[0]])
    if kind == "far":  # placed far out in the scene it was exported from
        return V + rng.normal(size=3) * 1e3 * size, F
    return V, _resplit(V, F, rng)


def _convert(V, F, view, up):
    """(mescher, report) or None when refused with a MescherError (any other error fails)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            m, order, report = model_to_mescher(V, F, view=view, up=up)
        except MescherError as err:
            assert str(err) and "\n" not in str(err).strip()
            return None
    p = np.abs(np.asarray(m.periods()))
    # the verdict agrees with the periods, and no period is gluing noise
    assert bool(m.is_impossible()) == bool(p.size and p.max() > 1e-6 * m.scale())
    assert not np.any((p > 1e-9 * m.scale()) & (p <= PERIOD_RTOL * m.scale()))
    assert report.route in ("cut", "closed", "visible") and report.reason
    return m, report


def _cases(models):
    n_seeds = max(1, N_FUZZ // len(KINDS))
    return [(name, kind, seed) for name in models for kind in KINDS for seed in range(n_seeds)]


SUITE = _suite()


@pytest.mark.parametrize("name, kind, seed", _cases(SUITE))
def test_perturbed_suite_models_convert_or_refuse(name, kind, seed):
    V, F, view, up = SUITE[name]
    Vp, Fp = perturb(V, F, kind, seed)
    out = _convert(Vp, Fp, view, up)
    if kind in ("inplace", "far"):  # the same picture: the same verdict and periods
        m0, _ = _convert(V, F, view, up)
        assert out is not None and bool(out[0].is_impossible()) == bool(m0.is_impossible())
        p0, p1 = np.abs(np.asarray(m0.periods())), np.abs(np.asarray(out[0].periods()))
        assert np.isclose(p1.max(initial=0.0), p0.max(initial=0.0), rtol=1e-6)


@pytest.mark.skipif(not REAL.is_dir(), reason="the development set of real models is absent")
def test_perturbed_real_models_convert_or_refuse():
    real = _real()
    for name, kind, seed in _cases(real):  # one test: the files are loaded once
        V, F, view, up = real[name]
        Vp, Fp = perturb(V, F, kind, seed)
        _convert(Vp, Fp, view, up)


@pytest.mark.skipif(not REAL.is_dir(), reason="the development set of real models is absent")
def test_tiny_jitter_keeps_the_junction_of_real_tribars():
    """At 1e-6 of the size the model is the same to a person: same period (the coincident
    pair's depth gap, to the jitter's order)."""
    real = _real()
    views = json.loads((REAL / "views.json").read_text())
    for name in ("PenroseTriangle.obj", "PenroseTriangle2.obj"):
        V, F, view, up = real[name]
        gaps = np.asarray(views[name]["coincident_depth_gaps"])
        for seed in range(3):
            m, _ = _convert(*perturb(V, F, "jitter6", seed), view, up)
            p = np.abs(np.asarray(m.periods()))
            p = p[p > PERIOD_RTOL * m.scale()]
            assert p.size >= 1
            assert np.min(np.abs(p[:, None] - gaps[None]), axis=1).max() <= 1e-3 * gaps.max()


def scene(n_boxes=60, seed=0):
    """A game level: a huge ground plane (a thin slab 1000 wide) and many boxes standing on it,
    some stacked, some touching."""
    rng = np.random.default_rng(seed)
    parts = [box_mesh([-500, -500, -1], [500, 500, 0])]
    for _ in range(n_boxes):  # test code
        c = rng.uniform(-20, 20, 2)
        s = rng.uniform(0.5, 3, 3)
        z0 = 0.0 if rng.random() < 0.8 else rng.uniform(0, 4)
        parts.append(box_mesh([c[0], c[1], z0], [c[0] + s[0], c[1] + s[1], z0 + s[2]]))
    return merge_meshes(parts)


def _views(k, seed):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(k, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.parametrize("make", [scene, ordinary_stairs])
def test_ordinary_models_stay_possible_from_any_view(make):
    V, F = make()
    views = list(_views(6, 1)) + [ISO_VIEW, np.array([1.0, -1.0, 1.0]) / np.sqrt(3)]
    for view in views:  # a few views, isometric ones included (edges line up there)
        out = _convert(V, F, view, None if abs(view[2]) > 0.99 else (0.0, 0.0, 1.0))
        assert out is not None and not out[0].is_impossible(), (view, out[1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            m, _, _ = model_to_mescher(V, F, view="auto")
        except MescherError:
            return  # "no view found" is a clear answer
    assert not m.is_impossible()


def test_degenerate_and_repeated_vertex_faces_are_refused_or_repaired():
    V, P, _ = u_tribar()
    F = triangulate(P)
    bad = np.vstack([F, [[0, 0, 1], [2, 2, 2], [3, 4, 3]], F[:5]])  # repeated vertices, repeats
    with pytest.raises(MescherError, match="F: expected three distinct corners"):
        model_to_mescher(V, bad, view=ISO_VIEW, up=ISO_UP)
    # zero-area slivers (collinear corners) on an edge of the model: a result or a refusal
    mid = V.shape[0]
    Vz = np.vstack([V, 0.5 * (V[F[0, 0]] + V[F[0, 1]])])
    Fz = np.vstack([F, [[F[0, 0], mid, F[0, 1]], [F[0, 1], mid, F[0, 0]]]])
    _convert(Vz, Fz, ISO_VIEW, ISO_UP)
    Vn = V.copy()
    Vn[0] = np.nan
    with pytest.raises(MescherError, match="V"):
        model_to_mescher(Vn, F, view=ISO_VIEW, up=ISO_UP)
    with pytest.raises(MescherError, match="F"):
        model_to_mescher(V, F + V.shape[0], view=ISO_VIEW, up=ISO_UP)
