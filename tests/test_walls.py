"""The walls between the packages, read from every module's imports (lazy ones inside functions too).

DESIGN.md: ``meschers_igl`` (the math) never imports pyvista, vtk, pymeshlab, ``pyvista_views``,
``meshlab_filters`` or the application ``meschers``; torch only inside ``meschers_igl/inverse/``;
``pyvista_views`` and ``meshlab_filters`` never import each other nor the application; no file
imports another that imports it back, directly or in a longer circle; no module takes another
package's private name or private module. The checks run on the source text (``ast``), so an
import that is never executed in the tests is checked too.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import networkx as nx
import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("meschers_igl", "pyvista_views", "meshlab_filters", "meschers")


@dataclass(frozen=True)
class Import:
    module: str  # importing module, dotted
    target: str  # imported module, dotted (resolved)
    names: tuple[str, ...]  # names taken with ``from target import ...``
    line: int


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _is_package(module: str, root: Path) -> bool:
    return (root / Path(*module.split(".")) / "__init__.py").exists()


def _exists(module: str, root: Path) -> bool:
    p = root / Path(*module.split("."))
    return p.with_suffix(".py").exists() or (p / "__init__.py").exists()


def imports_of(path: Path, root: Path = ROOT) -> list[Import]:
    """Every import statement of one file, relative imports resolved to dotted names."""
    module = _module_name(path, root)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [Import(module, a.name, (), node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = tuple(a.name for a in node.names)
            # ``from pkg import sub`` imports the submodule pkg.sub
            subs = [n for n in names if _exists(f"{target}.{n}", root)]
            for n in subs:
                out.append(Import(module, f"{target}.{n}", (), node.lineno))
            rest = tuple(n for n in names if n not in subs)
            if rest or not subs:
                out.append(Import(module, target, rest, node.lineno))
    return out


def all_imports(root: Path = ROOT) -> list[Import]:
    files = [p for pkg in PACKAGES for p in sorted((root / pkg).rglob("*.py"))]
    return [imp for p in files for imp in imports_of(p, root)]


def _top(name: str) -> str:
    return name.split(".")[0]


def wall_violations(imports: list[Import]) -> list[str]:
    """Each crossing of a wall, as 'module:line imports target (rule)'."""
    forbidden = {
        "meschers_igl": {
            "pyvista",
            "vtk",
            "vtkmodules",
            "pymeshlab",
            "pyvista_views",
            "meshlab_filters",
            "meschers",
        },
        "pyvista_views": {"meshlab_filters", "meschers", "pymeshlab"},
        "meshlab_filters": {"pyvista_views", "meschers", "pyvista", "vtk", "vtkmodules"},
    }
    bad = []
    for imp in imports:
        src, dst = _top(imp.module), _top(imp.target)
        where = f"{imp.module}:{imp.line} imports {imp.target}"
        if dst in forbidden.get(src, ()):
            bad.append(f"{where} ({src} must not import {dst})")
        if dst == "torch" and not imp.module.startswith("meschers_igl.inverse"):
            bad.append(f"{where} (torch only inside meschers_igl/inverse/)")
        if dst in PACKAGES and dst != src:
            private_mod = [p for p in imp.target.split(".")[1:] if p.startswith("_")]
            private = [n for n in imp.names if n.startswith("_") and n != "__version__"]
            if private_mod or private:
                bad.append(f"{where} (another package's private name {private_mod + private})")
    return bad


def import_cycles(imports: list[Import], root: Path = ROOT) -> list[list[str]]:
    """Circles of modules importing each other (a package imports its own ``__init__`` freely)."""
    g = nx.DiGraph()
    for imp in imports:
        if _top(imp.target) not in PACKAGES or imp.target == imp.module:
            continue
        # a module importing a name from its own package's __init__ (or an ancestor's) is not a
        # circle between files: __init__ only re-exports
        if imp.module.startswith(imp.target + ".") and _is_package(imp.target, root):
            continue
        g.add_edge(imp.module, imp.target)
    return [sorted(c) for c in nx.simple_cycles(g)]


def test_no_wall_is_crossed():
    assert wall_violations(all_imports()) == []


def test_no_import_circle():
    assert import_cycles(all_imports()) == []


# ------------------------------------------------------------------------------------------------
# the checker itself must catch a crossing (a rule that can never fail is no rule)
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("path", "source", "fragment"),
    [
        ("meschers_igl/bad.py", "def f():\n    import pyvista\n", "must not import pyvista"),
        ("meschers_igl/bad.py", "from pyvista_views import render\n", "must not import"),
        ("meschers_igl/bad.py", "import torch\n", "torch only"),
        ("pyvista_views/bad.py", "def f():\n    from meshlab_filters import x\n", "must not"),
        ("meshlab_filters/bad.py", "from meschers.cli import main\n", "must not import"),
        ("meschers/bad.py", "from pyvista_views.render import _xy_box\n", "private name"),
        ("meschers/bad.py", "from pyvista_views._offscreen import has_display\n", "private"),
    ],
)
def test_checker_catches_a_crossing(tmp_path, path, source, fragment):
    for pkg in PACKAGES:
        (tmp_path / pkg).mkdir()
        (tmp_path / pkg / "__init__.py").write_text("")
    (tmp_path / "pyvista_views" / "render.py").write_text("")
    (tmp_path / "pyvista_views" / "_offscreen.py").write_text("")
    (tmp_path / path).write_text(source)
    found = wall_violations(imports_of(tmp_path / path, tmp_path))
    assert any(fragment in v for v in found), found


def test_checker_catches_a_circle(tmp_path):
    pkg = tmp_path / "meschers_igl"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import g\n")
    (pkg / "b.py").write_text("def g():\n    from . import c\n")
    (pkg / "c.py").write_text("from meschers_igl.a import f\n")
    imps = [i for p in sorted(pkg.glob("*.py")) for i in imports_of(p, tmp_path)]
    cycles = import_cycles(imps, tmp_path)
    assert cycles == [["meschers_igl.a", "meschers_igl.b", "meschers_igl.c"]]
