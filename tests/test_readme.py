"""The README works as printed.

The Quick start is exactly two command lines and CI runs the second one; every Python block runs
by itself in an empty folder; the CLI section's lines run in order in an empty folder; and the
package carries its licence, citation and typing markers.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _quick_start_lines() -> list[str]:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Quick start", 1)[1]
    block = re.search(r"```(?:bash|sh)?\n(.*?)```", section, re.S).group(1)
    return [ln for ln in block.splitlines() if ln.strip() and not ln.strip().startswith("#")]


def test_quick_start_has_two_lines_and_ci_runs_the_test_line():
    lines = _quick_start_lines()
    assert len(lines) == 2
    assert "meschers study" in lines[0]
    assert "pytest" in lines[1]
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert lines[1].strip() in [c.strip() for c in ci]


def test_readme_images_exist():
    text = (ROOT / "README.md").read_text()
    for img in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text):
        assert (ROOT / img).is_file(), img


def test_readme_core_example_runs(tmp_path, monkeypatch):
    """The README's first Python example is complete and runs as printed."""
    text = (ROOT / "README.md").read_text()
    block = re.search(
        r"```python\n(import numpy as np\nfrom meschers_igl import Mescher.*?)```", text, re.S
    )
    assert block is not None
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(block.group(1), "README.md", "exec"), scope)
    m = scope["m"]
    assert m.is_impossible() and np.isclose(np.abs(m.periods()).max(), 1.0)
    assert (tmp_path / "torus.ply").is_file()


# --- every block works as printed -----------------------------------------------------------


def _python_blocks() -> list[str]:
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def _cli_lines() -> list[str]:
    """The command lines of the README's CLI section, comments stripped, in order."""
    text = (ROOT / "README.md").read_text()
    section = text.split("\n## CLI", 1)[1].split("\n## ", 1)[0]
    lines = []
    for block in re.findall(r"```(?:bash|sh)\n(.*?)```", section, re.S):
        for ln in block.splitlines():
            ln = ln.split("  #", 1)[0].strip()
            if ln and not ln.startswith("#"):
                lines.append(ln)
    return lines


def _env() -> dict:
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
    if not env.get("DISPLAY"):
        # nothing set by hand: pyvista_views picks EGL by itself (the README says so)
        env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    return env


def _has_torch() -> bool:
    return importlib.util.find_spec("torch") is not None


def test_readme_has_python_blocks_and_cli_lines():
    assert len(_python_blocks()) >= 6
    lines = _cli_lines()
    assert len(lines) >= 8 and all(ln.startswith("meschers ") for ln in lines), lines
    assert any(ln.startswith("meschers convert paradox:") for ln in lines), lines


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(_python_blocks())))
def test_each_python_block_runs_by_itself_in_an_empty_folder(index, tmp_path):
    code = _python_blocks()[index]
    if "meschers_igl.inverse" in code and not _has_torch():
        pytest.skip("the inverse-rendering block needs PyTorch")
    (tmp_path / "block.py").write_text(code)
    run = tmp_path / "run"
    run.mkdir()
    proc = subprocess.run(
        [sys.executable, str(tmp_path / "block.py")],
        cwd=run,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, f"README block {index}:\n{code}\n{proc.stderr[-4000:]}"
    assert "bad X server connection" not in proc.stderr


@pytest.mark.slow
def test_cli_lines_run_in_order_in_an_empty_folder(tmp_path):
    for line in _cli_lines():
        if line.startswith("meschers inverse") and not _has_torch():
            continue
        proc = subprocess.run(
            ["bash", "-c", line],
            cwd=tmp_path,
            env=_env(),
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert proc.returncode == 0, f"{line}\n{proc.stdout[-2000:]}\n{proc.stderr[-4000:]}"
        assert "bad X server connection" not in proc.stderr, line
        # what the line says it writes is there
        words = shlex.split(line)
        outputs = [w for w in words if re.search(r"\.(png|ply|npy|npz)$", w) and w != words[2]]
        if words[1] == "convert":
            outputs = [words[3]]
        for out in outputs:
            assert (tmp_path / out).is_file(), f"{line}: no {out}"
        if words[1] == "study":
            assert (tmp_path / words[words.index("--out") + 1] / "index.html").is_file()
        if words[1] == "inverse":
            assert any((tmp_path / words[words.index("--out") + 1]).iterdir())


# --- what the package carries ---------------------------------------------------------------


def test_licence_citation_and_typing_markers():
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    project = pyproject["project"]
    assert "MIT" in str(project["license"])
    licence = (ROOT / "LICENSE").read_text()
    assert licence.startswith("MIT License")
    # the ParadoxToolkit data ship under the GPL-3.0, and say so where they ship
    note = ROOT / "meschers_igl" / "data" / "paradox" / "LICENSE-NOTE.md"
    assert "GPL-3.0" in note.read_text() and "GPL-3.0" in licence
    import meschers_igl

    cff = (ROOT / "CITATION.cff").read_text()
    assert re.search(rf"^version: {re.escape(project['version'])}$", cff, re.M)
    assert project["version"] == meschers_igl.__version__
    assert 'doi: "10.1145/3731422"' in cff
    package_data = pyproject["tool"]["setuptools"]["package-data"]
    for pkg in ("meschers_igl", "pyvista_views", "meshlab_filters", "meschers"):
        assert (ROOT / pkg / "py.typed").is_file(), pkg
        assert "py.typed" in package_data[pkg], pkg


def test_the_docs_index_caption_names_every_row_of_its_gallery_figure():
    from meschers_igl.gallery import list_models

    text = (Path(__file__).resolve().parents[1] / "docs" / "index.rst").read_text()
    caption = text[text.index("images/gallery.png") :].split("\n\n", 2)[1]
    words = " ".join(caption.split()).lower()
    for name in list_models():
        first = name.replace("_", " ").split()[0]
        assert first.lower() in words.replace("ä", "a"), f"{name} missing from the caption"
