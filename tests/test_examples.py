"""Every gallery example in ``examples/`` runs by itself in an empty folder and makes its figure.

Each script runs in a fresh interpreter whose working directory is an empty folder (what a user
who downloads one example has), with matplotlib's Agg backend. The test then checks what the
sphinx-gallery page will show: at least one figure, with a picture in it (not one flat colour),
and that the script left nothing behind in the folder it ran in (files it writes go to a
temporary folder of its own).
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))

# Runs the example as `python plot_x.py` would, then saves every open figure outside the cwd.
RUNNER = """
import runpy, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
plt.show = lambda *args, **kwargs: None
runpy.run_path(sys.argv[1], run_name="__main__")
for i in plt.get_fignums():
    plt.figure(i).savefig(f"{sys.argv[2]}/figure_{i}.png", dpi=50)
print("FIGURES", len(plt.get_fignums()))
"""


def test_there_are_at_least_eight_examples_each_with_a_title():
    assert len(EXAMPLES) >= 8, [p.name for p in EXAMPLES]
    for path in EXAMPLES:
        doc = ast.get_docstring(ast.parse(path.read_text()))
        assert doc, f"{path.name}: sphinx-gallery needs a docstring with a title"
        title, underline = doc.strip().splitlines()[:2]
        assert set(underline) == {"="} and len(underline) >= len(title), path.name


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_in_an_empty_folder_and_makes_its_figure(path, tmp_path):
    cwd = tmp_path / "empty"
    figures = tmp_path / "figures"
    cwd.mkdir()
    figures.mkdir()
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
    if not env.get("DISPLAY"):
        # nothing set by hand: pyvista_views picks EGL by itself (the README says so)
        env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    proc = subprocess.run(
        [sys.executable, "-c", RUNNER, str(path), str(figures)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    assert "bad X server connection" not in proc.stderr, proc.stderr[-2000:]
    assert list(cwd.iterdir()) == [], "the example wrote into the folder it ran in"
    pngs = sorted(figures.glob("figure_*.png"))
    assert pngs, f"{path.name} made no figure"
    import matplotlib.image as mpimg

    for png in pngs:
        img = mpimg.imread(png)[..., :3]
        # a picture, not a blank canvas: many distinct grey levels and real contrast
        assert img.std() > 0.05, f"{png.name} of {path.name} is (nearly) one colour"
        assert len(np.unique(np.round(img.mean(axis=2), 2))) > 20, png.name


NOTEBOOK = ROOT / "notebooks" / "meschers_trame.ipynb"

# The notebook's code cells, run as one script off screen (no Jupyter server here): the trame
# backend call is recorded instead of made, every plotter renders off screen.
NOTEBOOK_RUNNER = """
import json, sys
import pyvista as pv
pv.OFF_SCREEN = True
backends = []
pv.set_jupyter_backend = lambda name, *args, **kwargs: backends.append(name)
cells = json.load(open(sys.argv[1]))["cells"]
code = "\\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
scope = {}
exec(compile(code, sys.argv[1], "exec"), scope)
image = scope["plot"](scope["m"], order=scope["order"], window_size=(200, 200))
print("BACKENDS", backends, "IMAGE", image.shape, int(image.std() > 10))
"""


def test_notebook_uses_trame_and_its_cells_run(tmp_path):
    nb = json.loads(NOTEBOOK.read_text())
    assert nb["nbformat"] == 4 and nb["metadata"]["kernelspec"]["language"] == "python"
    code = "".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code")
    assert 'set_jupyter_backend("trame")' in code and 'jupyter_backend="trame"' in code
    assert all(c.get("outputs", []) == [] for c in nb["cells"]), (
        "commit the notebook without outputs"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    if not env.get("DISPLAY"):
        # nothing set by hand: pyvista_views picks EGL by itself (the README says so)
        env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    proc = subprocess.run(
        [sys.executable, "-c", NOTEBOOK_RUNNER, str(NOTEBOOK)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert "BACKENDS ['trame'] IMAGE (200, 200, 3) 1" in proc.stdout, proc.stdout[-2000:]


@pytest.mark.slow
def test_notebook_runs_in_a_jupyter_kernel(tmp_path):
    """The notebook as a user runs it: every cell in a real ``python3`` kernel (the ``[jupyter]``
    extra installs the kernel; the ``[test]`` extra the client), no error, a trame widget shown."""
    nbformat = pytest.importorskip("nbformat", reason="the [test] extra installs nbclient")
    nbclient = pytest.importorskip("nbclient", reason="the [test] extra installs nbclient")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()  # raises CellExecutionError, naming the cell, on any error
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    widgets = [
        o for o in outputs if "application/vnd.jupyter.widget-view+json" in o.get("data", {})
    ]
    assert len(widgets) >= 2, "plot(...) and pl.show(...) each show a trame widget"
    text = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    assert "vertices," in text and "periods" in text


def _rst_python(path: Path) -> str:
    """The ``.. code-block:: python`` blocks of a documentation page, in order, dedented."""
    code, lines, i = [], path.read_text().splitlines(), 0
    while i < len(lines):
        if lines[i].strip() == ".. code-block:: python":
            i += 1
            block = []
            while i < len(lines) and (not lines[i].strip() or lines[i].startswith("   ")):
                block.append(lines[i][3:])
                i += 1
            code.append("\n".join(block))
        else:
            i += 1
    return "\n".join(code)


@pytest.mark.parametrize("page", ["index.rst", "getting_started.rst"])
def test_documentation_code_runs_in_an_empty_folder(page, tmp_path):
    code = _rst_python(ROOT / "docs" / page)
    assert "import" in code
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
    if not env.get("DISPLAY"):
        # nothing set by hand: pyvista_views picks EGL by itself (the README says so)
        env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    proc = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, f"{page}:\n{code}\n{proc.stderr[-4000:]}"
