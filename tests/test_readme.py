"""The README's Quick start is exactly two command lines, and CI runs the second one."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

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
