"""The ParadoxToolkit cut models shipped with the package (``meschers_igl/data/paradox``).

Six classic impossible figures and 12 variants at other viewing angles, produced by an
independent tool (see ``data/paradox/README.md`` and ``LICENSE-NOTE.md``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from .errors import MescherError


def data_dir() -> Path:
    """Folder holding the OBJ/JSON pairs."""
    return Path(str(resources.files("meschers_igl") / "data" / "paradox"))


@dataclass(frozen=True)
class ParadoxModel:
    """One shipped cut model: its OBJ path and the JSON metadata (camera, verification)."""

    name: str
    obj: Path
    meta: dict

    @property
    def view(self) -> tuple[float, float, float]:
        return tuple(self.meta["camera"]["view_dir"])

    @property
    def up(self) -> tuple[float, float, float]:
        return tuple(self.meta["camera"]["up"])


def list_paradox_models(variants: bool = True) -> list[str]:
    """Names of the shipped models (``variants/`` ones as ``NAME__VARIANT``)."""
    d = data_dir()
    names = sorted(p.stem for p in d.glob("*.obj"))
    if variants:
        names += sorted(p.stem for p in (d / "variants").glob("*.obj"))
    return names


def paradox_model(name: str) -> ParadoxModel:
    """The model called ``name`` (see :func:`list_paradox_models`)."""
    d = data_dir()
    for folder in (d, d / "variants"):
        obj = folder / f"{name}.obj"
        if obj.is_file():
            return ParadoxModel(name, obj, json.loads((folder / f"{name}.json").read_text()))
    raise MescherError(f"name: expected one of {', '.join(list_paradox_models())}, found {name!r}")
