"""Naming models on the command line and in the study: one place that turns words into models.

A model is named by

=============================== ===================================================================
``penrose_triangle``            a gallery model (:func:`meschers_igl.gallery.list_models`); also
                                ``gallery:penrose_triangle``
``paradox:penrose_triangle``    a ParadoxToolkit cut model shipped with the package
                                (:mod:`meschers_igl.paradox`), seen from its own camera
``model.ply``, ``x.npz``        a saved mescher (:func:`meschers_igl.io.save`), depth order included
``model.obj`` + ``model.json``  an artist's cut model with its view in a sidecar JSON: either the
                                ParadoxToolkit layout ``{"camera": {"view_dir": [..], "up": [..]}}``
                                or ``{"view": [..], "up": [..]}``; any format PyMeshLab reads
``folder/``                     every model file in the folder (sidecar JSONs are not models)
``"models/*.obj"``              a glob pattern, expanded here (quote it for the shell)
=============================== ===================================================================

A ``.ply`` or ``.npz`` file with a sidecar JSON is an artist model; without one it is a saved
mescher.  :class:`ModelSpec` is small and picklable, so a study can send it to a Dask worker,
which loads the model itself.
"""

from __future__ import annotations

import glob
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from meschers_igl.errors import MescherError

__all__ = [
    "ModelSpec",
    "expand_models",
    "load_artist",
    "load_mescher",
    "load_solid",
    "list_solids",
    "resolve",
    "solid_path",
]

#: Suffixes of saved meschers.
MESCHER_SUFFIXES = (".ply", ".npz")
#: Suffixes of mesh files an artist model may come in (what PyMeshLab reads, commonly).
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf", ".3ds", ".dae", ".npz")
_GLOB = set("*?[")


@dataclass(frozen=True)
class ModelSpec:
    """A named model, not loaded yet.

    Attributes
    ----------
    kind : {"gallery", "artist", "solid", "mescher"}
        ``"solid"``: any 3D model (closed solids, separate blocks) seen from its sidecar view
        (``"seen_as": "solid"``), converted by ``meshlab_filters.model_to_mescher``.
    name : str
        Used for section titles and file names.
    path : str, optional
        The model file (``artist`` and ``mescher``).
    view, up : (3,) tuple, optional
        The camera of an artist model (from its sidecar JSON or the ParadoxToolkit metadata).
    meta : dict
        The sidecar JSON (``verification`` of a ParadoxToolkit model is checked by the study).
    source : str
        How the user named it (for messages).
    """

    kind: str
    name: str
    path: str | None = None
    view: tuple | None = None
    up: tuple | None = None
    meta: dict = field(default_factory=dict, compare=False, hash=False)
    source: str = ""

    @property
    def label(self) -> str:
        return self.source or self.name


def _camera(meta: dict) -> tuple[tuple, tuple] | None:
    cam = meta.get("camera", {}) if isinstance(meta.get("camera"), dict) else {}
    view = cam.get("view_dir", meta.get("view"))
    up = cam.get("up", meta.get("up"))
    if view is None or up is None:
        return None
    try:
        view, up = tuple(float(v) for v in view), tuple(float(v) for v in up)
    except (TypeError, ValueError):
        return None
    return (view, up) if len(view) == 3 and len(up) == 3 else None


def _sidecar(path: Path) -> Path | None:
    side = path.with_suffix(".json")
    return side if side.is_file() and side != path else None


def _file_spec(path: Path, source: str) -> ModelSpec:
    side = _sidecar(path)
    if side is not None:
        try:
            meta = json.loads(side.read_text())
        except (OSError, ValueError) as exc:
            raise MescherError(
                f"{side}: expected a JSON view sidecar, found unreadable JSON ({exc})"
            ) from None
        cam = _camera(meta) if isinstance(meta, dict) else None
        if cam is None:
            raise MescherError(
                f"{side.name}: expected a view in the sidecar JSON ({{'view': [x, y, z], "
                f"'up': [x, y, z]}} or ParadoxToolkit's camera.view_dir/up), found none"
            )
        kind = "solid" if isinstance(meta, dict) and meta.get("seen_as") == "solid" else "artist"
        return ModelSpec(kind, path.stem, str(path), cam[0], cam[1], meta, source)
    if path.suffix.lower() in MESCHER_SUFFIXES:
        return ModelSpec("mescher", path.stem, str(path), source=source)
    raise MescherError(
        f"{source}: expected a .ply/.npz mescher file or a mesh with a sidecar "
        f"'{path.with_suffix('.json').name}' giving its view, found '{path.name}' without one "
        f"(or convert it first: meschers convert {source} OUT.ply --view X,Y,Z --up X,Y,Z)"
    )


def list_solids() -> list[str]:
    """Names of the shipped artist-style solid models (``solid:NAME``)."""
    import importlib.resources

    root = importlib.resources.files("meschers_igl") / "data" / "solids"
    return sorted(p.name[:-4] for p in root.iterdir() if p.name.endswith(".obj"))


def solid_path(name: str) -> Path:
    """The OBJ file of the shipped solid model ``name`` (its view is in the sidecar JSON)."""
    import importlib.resources

    if name not in list_solids():
        raise MescherError(
            f"name: expected one of the shipped solids {', '.join(list_solids())}, found {name!r}"
        )
    return Path(str(importlib.resources.files("meschers_igl") / "data" / "solids" / f"{name}.obj"))


def _named(spec: str) -> ModelSpec | None:
    """A gallery or shipped ParadoxToolkit model named ``spec``, else None."""
    from meschers_igl.gallery import list_models

    prefix, _, rest = spec.partition(":")
    if prefix == "paradox" and rest:
        from meschers_igl.paradox import paradox_model

        pm = paradox_model(rest)
        return ModelSpec("artist", rest, str(pm.obj), pm.view, pm.up, pm.meta, spec)
    if prefix == "solid" and rest:
        return _file_spec(solid_path(rest), spec)
    if prefix == "gallery" and rest:
        spec = rest
    if spec in list_models():
        return ModelSpec("gallery", spec, source=spec)
    return None


def _hint() -> str:
    from meschers_igl.gallery import list_models

    return (
        f"a gallery model ({', '.join(list_models())}), paradox:NAME or solid:NAME "
        "(meschers info --list), a .ply/.npz mescher, a mesh with a sidecar .json view, a folder "
        "or a glob"
    )


def resolve(spec: str, name: str = "INPUT") -> ModelSpec:
    """One model from one name (see the module docstring); ``name`` is the argument named in
    the error.

    Raises
    ------
    MescherError
        Nothing of that name; a folder or glob (use :func:`expand_models`).
    """
    named = _named(spec) if ":" in spec or not Path(spec).exists() else None
    if named is not None:
        return named
    path = Path(spec)
    if path.is_file():
        return _file_spec(path, spec)
    if path.suffix.lower() in MESH_SUFFIXES or path.is_dir() or _GLOB & set(spec):
        what = "a folder" if path.is_dir() else "a pattern" if _GLOB & set(spec) else "nothing"
        raise MescherError(f"{name}: expected one model file, found {what} at '{spec}'")
    raise MescherError(f"{name}: expected {_hint()}, found {spec!r}")


def expand_models(specs: list[str], name: str = "models") -> list[ModelSpec]:
    """Models named by ``specs``: names, files, folders and glob patterns, in the order given
    (a folder's and a pattern's files sorted), each file once.

    Raises
    ------
    MescherError
        A spec that names nothing, or a folder / pattern without a model file.
    """
    out: list[ModelSpec] = []
    seen: set[str] = set()
    for spec in specs:
        path = Path(spec)
        if path.is_dir() or (_GLOB & set(spec) and not path.exists()):
            files = sorted(path.iterdir()) if path.is_dir() else sorted(map(Path, glob.glob(spec)))
            models = [p for p in files if p.is_file() and p.suffix.lower() in MESH_SUFFIXES]
            if not models:
                raise MescherError(f"{name}: expected model files in '{spec}', found none")
            for p in models:
                if str(p.resolve()) not in seen:
                    seen.add(str(p.resolve()))
                    out.append(_file_spec(p, str(p)))
            continue
        one = resolve(spec, name)
        key = str(Path(one.path).resolve()) if one.path else f"{one.kind}:{one.name}"
        if key not in seen:
            seen.add(key)
            out.append(one)
    return out


def load_mescher(spec: ModelSpec, check: Callable[[Any], None] | None = None) -> tuple[Any, Any]:
    """``(mescher, order or None)`` of a gallery model or a saved mescher.

    ``check(mescher)``, when given, runs as soon as the mescher exists and before its depth
    order is computed (a gallery model's order is the costly part), so a refusal such as a size
    guard comes at once.
    """
    if spec.kind == "gallery":
        from meschers_igl.gallery import get_model

        g = get_model(spec.name)
        if check is not None:
            check(g.mescher)
        return g.mescher, g.order
    if spec.kind == "mescher":
        from meschers_igl import io

        m, order = io.load(spec.path, return_order=True)
    else:
        load = load_solid if spec.kind == "solid" else load_artist
        m, order, _, _, _ = load(spec)
    if check is not None:
        check(m)
    return m, order


def load_artist(spec: ModelSpec, merge_tol: float = 0.0, tol: float | None = None) -> tuple:
    """An artist's cut model, cleaned with PyMeshLab and glued into a mescher from its view.

    Returns
    -------
    (m, order, Vcam, F, report)
        The mescher and depth order; the cleaned model in camera coordinates (x right, y up,
        z toward the viewer) and its faces (face ``i`` is mescher face ``i``); the clean-up
        report.
    """
    from meschers_igl.cutmesh import camera_coordinates
    from meshlab_filters import cut_model_to_mescher, load_artist_model

    V, F, report = load_artist_model(spec.path, merge_tol=merge_tol)
    m, order = cut_model_to_mescher((V, F), view=spec.view, up=spec.up, tol=tol)
    return m, order, camera_coordinates(V, spec.view, spec.up), F, report


def load_solid(spec: ModelSpec) -> tuple:
    """Any 3D model (closed solids, separate blocks, soups) seen from its view, as a mescher.

    Returns
    -------
    (m, order, Vcam, F, report)
        The mescher of what the viewer sees and its depth order (false edges glued, occlusions
        ordered, hidden gaps bridged: :func:`meshlab_filters.model_to_mescher`); the model in
        camera coordinates and its triangles (for a z-buffered reference); the conversion report.
    """
    import pymeshlab

    from meschers_igl.cutmesh import camera_coordinates
    from meshlab_filters import model_to_mescher

    perceive = spec.meta.get("perceive") if isinstance(spec.meta, dict) else None
    m, order, report = model_to_mescher(spec.path, view=spec.view, up=spec.up, perceive=perceive)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(spec.path)
    mesh = ms.current_mesh()
    V, F = mesh.vertex_matrix(), mesh.face_matrix().astype("int64")
    return m, order, camera_coordinates(V, spec.view, spec.up), F, report
