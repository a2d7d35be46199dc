"""The studio: its model (turn, light, picks, periods, files), its manners, and the page
driven in a real headless Chromium (Playwright, the system browser)."""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from meschers.cli import main
from meschers.studio import (
    StudioModel,
    check_port,
    default_torus,
    light_from_pointer,
    load_model,
)
from meschers_igl import MescherError, load
from meschers_igl.painter import visible_faces
from meschers_igl.rotation import rotate, rotation_matrix

needs_trame = pytest.mark.skipif(
    importlib.util.find_spec("trame") is None, reason="trame not installed (meschers[studio])"
)


@pytest.fixture(scope="module")
def torus():
    return default_torus()


@pytest.fixture
def studio(torus):
    return StudioModel(*torus, label="torus", size=200)


def test_light_follows_the_pointer():
    np.testing.assert_allclose(light_from_pointer(0.0, 0.0), [0, 0, 1])
    d = light_from_pointer(0.6, -0.3)
    np.testing.assert_allclose(d, [0.6, -0.3, np.sqrt(1 - 0.45)])
    rim = light_from_pointer(3.0, 4.0)  # outside the disc: on the rim, still toward the viewer
    assert np.isclose(np.linalg.norm(rim), 1.0) and rim[2] > 0
    np.testing.assert_allclose(rim[:2] / np.linalg.norm(rim[:2]), [0.6, 0.8])


def test_drag_relights_without_changing_the_mescher(studio):
    m0 = studio.current()[0]
    studio.drag("light", (0, 0), (150, 50), (200, 200))
    np.testing.assert_allclose(studio.light, light_from_pointer(0.5, 0.5))
    assert studio.current()[0] is m0


def test_turning_is_the_rotation_and_turns_back_exactly(studio, torus):
    m, order = torus
    studio.drag("turn", (100, 100), (140, 80), (200, 200))  # 40 px right, 20 px up
    ax, ay = studio.turn
    k = 0.15 * studio.size / 200
    assert np.isclose(ay, 40 * k) and np.isclose(ax, -20 * k)
    R = rotation_matrix(ay, "y") @ rotation_matrix(ax, "x")
    turned, _ = studio.current()
    # the same turn done at once about its own axis
    w, v = np.linalg.eig(R)
    axis = np.real(v[:, np.argmin(np.abs(w - 1))])
    angle = np.degrees(np.arccos((np.trace(R) - 1) / 2))
    ref = rotate(m, angle, axis).mescher
    if not np.allclose(ref.xy, turned.xy, atol=1e-9):
        ref = rotate(m, -angle, axis).mescher
    np.testing.assert_allclose(turned.xy, ref.xy, atol=1e-9)
    np.testing.assert_allclose(turned.face_normals(), m.face_normals() @ R.T, atol=1e-9)
    studio.drag("turn", (0, 0), (10_000, 0), (200, 200))
    assert studio.turn[1] == 45.0  # turns stay within a few tens of degrees
    studio.set_turn([0.0, 0.0])
    assert studio.current()[0] is m


def test_drag_previews_follow_the_pointer_and_release_commits(studio):
    """While the button is held each preview is measured from where the drag began."""
    for x in (110, 130, 150):
        studio.drag("turn", (100, 100), (x, 100), (200, 200), final=False)
    k = 0.15 * studio.size / 200
    assert np.isclose(studio.turn[1], 50 * k) and studio.turn_base == [0.0, 0.0]
    studio.drag("turn", (100, 100), (150, 100), (200, 200))  # release: committed
    assert studio.turn_base == studio.turn
    studio.drag("turn", (0, 0), (20, 0), (200, 200), final=False)  # the next drag adds to it
    assert np.isclose(studio.turn[1], 70 * k)
    assert studio.drag("path", (0, 0), (100, 100), (200, 200), final=False) == ""
    assert studio.picks == []  # a pick happens on release only


def test_paint_a_period_on_a_possible_torus(studio, torus):
    m, _ = torus
    assert not m.is_impossible() and studio.n_loops == 2
    # the page starts on the loop around the hole (64 edges), not around the tube (24)
    assert [len(e) for e, _ in m.homology_generators()][studio.loop] == 64
    np.testing.assert_array_equal(studio.base_periods, [0.0, 0.0])
    msg = studio.set_period(1, 0.75)
    assert "impossible" in msg
    painted, _ = studio.current()
    np.testing.assert_allclose(painted.periods(), [0.0, 0.75], atol=1e-12)
    np.testing.assert_allclose(painted.xy, m.xy)  # the picture's outline is kept
    # only the harmonic part changes (in the torus's metric): exact part kept
    expect = m.d01 @ m.hodge().z + m.harmonic_basis() @ [0.0, 0.75]
    np.testing.assert_allclose(painted.zeta, expect, atol=1e-12)
    studio.set_smoothing(0.002, 0.01)  # smoothing keeps the painted period
    np.testing.assert_allclose(studio.current()[0].periods(), [0.0, 0.75], atol=1e-10)
    with pytest.raises(MescherError, match="loop: expected 0..1"):
        studio.set_period(2, 1.0)
    with pytest.raises(MescherError, match="period: expected a finite number"):
        studio.set_period(0, float("inf"))


def test_two_picks_give_the_geodesic(studio):
    m, order = studio.current()
    faces = visible_faces(m, order, size=studio.size, bounds=studio.bounds)
    rows, cols = np.nonzero(faces >= 0)
    assert "no surface" in studio.pick(0.0, 0.0)  # a corner of the frame is background
    a, b = (rows.min() + 10, cols.mean()), (rows.max() - 10, cols.mean())
    studio.pick((a[1] + 0.5) / studio.size, (a[0] + 0.5) / studio.size)
    msg = studio.pick((b[1] + 0.5) / studio.size, (b[0] + 0.5) / studio.size)
    assert msg.startswith("geodesic")
    s, t = studio.picks
    # each pick is a corner of the face seen under the pointer
    assert s in m.F[faces[int(a[0]), int(a[1])]] and t in m.F[faces[int(b[0]), int(b[1])]]
    path = studio.path()
    assert np.isclose(path.length, m.shortest_path(s, t).length)
    img = studio.image()
    red = (img[..., 0] > 200) & (img[..., 1] < 60) & (img[..., 2] < 90)
    assert red.sum() > 50  # the path is drawn


def test_strokes_are_drawn_only_where_their_faces_are_seen(studio):
    """The orange loop goes round the tube; its half behind the torus stays hidden."""
    m, order = studio.current()
    edges, _ = m.homology_generators()[studio.loop]
    img = studio.image()
    orange = (img[..., 0] > 200) & (np.abs(img[..., 1].astype(int) - 140) < 40) & (img[..., 2] < 60)
    assert orange.sum() > 20
    seen = visible_faces(m, order, size=studio.size, bounds=studio.bounds)
    on = np.isin(np.asarray(m.face_edges), np.asarray(edges)).any(axis=1)
    F = np.asarray(m.F)
    near = np.isin(F, F[on]).any(axis=1)
    assert np.all(seen[orange] >= 0) and np.all(near[seen[orange]])
    # drawn without the rule, the loop's hidden half would cover other faces
    from meschers.figures import overlay

    E = np.asarray(m.edges)[np.asarray(edges)]
    all_drawn = overlay(np.full_like(img, 255), studio.bounds, segments=[(m.xy[E], "#ff8c00", 3)])
    hidden = np.any(all_drawn != 255, axis=-1) & (seen >= 0) & ~near[np.maximum(seen, 0)]
    assert hidden.sum() > 0


def test_save_and_load_keep_the_painted_periods(studio, tmp_path):
    studio.set_period(1, -0.5)
    with pytest.raises(MescherError, match="save path: expected a .ply or .npz"):
        studio.save(str(tmp_path / "x.obj"))
    with pytest.raises(MescherError, match="save path: expected an existing folder"):
        studio.save(str(tmp_path / "nope" / "x.ply"))
    assert list(tmp_path.iterdir()) == []
    for name in ("painted.ply", "painted.npz"):
        studio.save(str(tmp_path / name))
        m, order = load(tmp_path / name, return_order=True)
        np.testing.assert_allclose(m.periods(), [0.0, -0.5], atol=1e-12)
        assert order is not None and m.is_impossible()
    studio.load(str(tmp_path / "painted.npz"))
    np.testing.assert_allclose(studio.base_periods, [0.0, -0.5], atol=1e-12)


def test_gallery_models_load(studio):
    m, order, label = load_model("penrose_triangle")
    assert label == "penrose_triangle" and m.is_impossible() and order is not None
    with pytest.raises(MescherError, match="MODEL"):
        load_model("no_such_model_anywhere")


def test_a_taken_port_is_refused_clearly():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        with pytest.raises(
            MescherError, match=f"--port: expected a free port.*found {port} in use"
        ):
            check_port("127.0.0.1", port)
        assert main(["studio", "--port", str(port)]) == 2
    assert 0 < check_port("127.0.0.1", 0) < 65536


def _free_port() -> int:
    return check_port("127.0.0.1", 0)


def _start(cwd: Path, *args: str) -> tuple[subprocess.Popen, int]:
    port = _free_port()
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    # output to a file, not a pipe nobody reads while the page is driven (a full pipe blocks)
    log = tempfile.TemporaryFile("w+")  # outside cwd, where nothing may be written; closed by _stop
    proc = subprocess.Popen(
        [sys.executable, "-m", "meschers", "studio", *args, "--port", str(port)],
        cwd=cwd,
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        text=True,
    )
    proc.log = log
    deadline = time.time() + 600  # an empty kernel cache compiles first (a minute or more)
    while time.time() < deadline:
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return proc, port
        if proc.poll() is not None:
            raise AssertionError(f"studio exited: {_output(proc)}")
        time.sleep(0.3)
    proc.kill()
    raise AssertionError("studio did not start within 600 s")


def _output(proc: subprocess.Popen) -> str:
    proc.log.flush()
    proc.log.seek(0)
    return proc.log.read()


def _stop(proc: subprocess.Popen) -> str:
    proc.send_signal(signal.SIGINT)  # Ctrl-C
    proc.wait(timeout=30)
    out = _output(proc)
    proc.log.close()
    assert proc.returncode == 0, out
    assert "stopped" in out and "Traceback" not in out
    return out


@needs_trame
def test_ctrl_c_stops_cleanly_and_nothing_is_written(tmp_path):
    proc, port = _start(tmp_path)
    out = _stop(proc)
    assert f"http://127.0.0.1:{port}/" in out
    assert list(tmp_path.iterdir()) == []


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _figure_pixels(page) -> np.ndarray:
    from io import BytesIO

    from PIL import Image

    return np.asarray(Image.open(BytesIO(page.locator("#figure").screenshot())).convert("RGB"))


@needs_trame
@pytest.mark.skipif(
    _chromium() is None, reason="no Chromium on this machine (apt-get install chromium)"
)
def test_page_in_headless_chromium(tmp_path):
    """Load the page, relight and turn by dragging, pick a geodesic, paint a period, save."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="pip install playwright")
    work, shots = tmp_path / "cwd", tmp_path / "shots"
    work.mkdir()
    shots.mkdir()
    proc, port = _start(work)
    try:
        with sync_api.sync_playwright() as p:
            browser = p.chromium.launch(
                executable_path=_chromium(),
                args=[
                    "--no-sandbox",
                    "--disable-gpu",
                    "--disable-background-networking",
                    "--disable-component-update",
                    "--disable-sync",
                ],
            )
            page = browser.new_page(viewport={"width": 1000, "height": 780})
            page.goto(f"http://127.0.0.1:{port}/")
            page.wait_for_function(
                "document.querySelector('#figure') && document.querySelector('#figure').naturalWidth > 0",
                timeout=180_000,
                polling=250,  # a timer: requestAnimationFrame stalls while a headless page is idle
            )
            page.screenshot(path=str(shots / "0_loaded.png"))
            status = page.locator("#status")

            def wait_status(text: str, seconds: float = 180) -> str:
                # a headless page that paints no frame can hold back its pending events and
                # messages: a screenshot makes it paint, as a person's screen would
                deadline = time.time() + seconds
                while text not in (status.text_content() or "") and time.time() < deadline:
                    page.screenshot()
                    page.wait_for_timeout(250)
                assert text in (status.text_content() or ""), status.text_content()
                page.wait_for_timeout(300)  # the new picture arrives with the status
                return status.text_content()

            box = page.locator("#figure").bounding_box()
            cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2

            def drag(dx: float, dy: float, x=cx, y=cy) -> None:
                page.mouse.move(x, y)
                page.mouse.down()
                page.mouse.move(x + dx, y + dy, steps=6)
                page.mouse.up()

            before = _figure_pixels(page)
            drag(-150, -120)  # light mode: the light moves to the upper left
            assert "light toward (-" in wait_status("light toward")
            relit = _figure_pixels(page)
            assert np.mean(np.any(relit != before, axis=-1)) > 0.05
            page.screenshot(path=str(shots / "1_relit.png"))

            page.click("#mode-turn")
            # the mode reaches the server asynchronously: on a loaded machine a drag begun at
            # once can still be read in the old mode, so wait for the button to show the mode
            page.wait_for_function(
                "document.querySelector('#mode-turn').className.includes('active')"
                " || document.querySelector('#mode-turn').getAttribute('aria-pressed') == 'true'",
                timeout=30_000,
                polling=200,
            )
            turned = False
            for _ in range(3):  # a drag whose events a busy server dropped is made again
                page.mouse.move(cx, cy)
                page.mouse.down()
                page.mouse.move(cx + 80, cy + 40, steps=6)
                try:
                    turned = "about y" in wait_status("turned", seconds=60)
                except AssertionError:
                    page.mouse.up()
                    continue
                break
            assert turned, status.text_content()  # the figure turns while the button is held
            page.screenshot(path=str(shots / "2_turning.png"))
            page.mouse.up()
            page.wait_for_timeout(500)
            assert "about y" in status.text_content()
            page.click("#reset-turn")
            wait_status("turn reset")

            page.click("#mode-path")
            page.mouse.click(cx - 0.22 * box["width"], cy)
            wait_status("pick a second point")
            page.mouse.click(cx + 0.25 * box["width"], cy + 0.05 * box["height"])
            assert "length" in wait_status("geodesic")
            page.screenshot(path=str(shots / "3_geodesic.png"))

            page.locator("input#period, #period input").first.fill("1.25")
            page.locator("input#period, #period input").first.press("Tab")
            assert "impossible" in wait_status("set to 1.25")
            page.screenshot(path=str(shots / "4_period.png"))
            assert list(work.iterdir()) == []  # nothing written before Save

            page.locator("input#save-path, #save-path input").first.fill(
                str(tmp_path / "painted.npz")
            )
            page.click("#save")
            wait_status("saved")
            page.screenshot(path=str(shots / "5_saved.png"))
            browser.close()
    finally:
        _stop(proc)
    m = load(tmp_path / "painted.npz")
    torus, order = default_torus()
    expect = np.zeros(2)
    expect[StudioModel(torus, order, size=64).loop] = 1.25  # the loop the page starts on
    np.testing.assert_allclose(m.periods(), expect, atol=1e-12)
    np.testing.assert_allclose(m.xy, torus.xy, atol=1e-12)  # turned back to 0 deg: unchanged
    assert list(work.iterdir()) == []
    for shot in sorted(shots.iterdir()):  # each screenshot shows the page and the figure
        img = np.asarray(__import__("PIL.Image").Image.open(shot).convert("RGB"))
        assert img.shape[:2] == (780, 1000)
        assert np.mean(img.min(axis=-1) < 200) > 0.05, shot.name
    keep = os.environ.get("MESCHERS_STUDIO_SHOTS")
    if keep:
        shutil.copytree(shots, keep, dirs_exist_ok=True)


@needs_trame
def test_same_page_from_a_notebook():
    """In a real kernel, ``notebook()`` serves the page and displays it in an iframe."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    import re
    import urllib.request

    nb = nbformat.v4.new_notebook()
    src = (
        "import os\nos.environ['TRAME_IPYWIDGETS_DISABLE'] = '1'  # plain HTML output\n"
        "from meschers.studio import notebook\nui = notebook(None, size=200)\nawait ui.ready\nui"
    )
    nb.cells = [nbformat.v4.new_code_cell(src)]
    client = nbclient.NotebookClient(nb, timeout=180, kernel_name="python3")
    with client.setup_kernel():
        client.execute_cell(nb.cells[0], 0)
        html = " ".join(o.get("data", {}).get("text/html", "") for o in nb.cells[0].outputs)
        url = re.search(r'<iframe[^>]*src="(http[^"]+)"', html).group(1)
        page = urllib.request.urlopen(url, timeout=30).read().decode()
        assert "trame" in page
        if _chromium() is not None and importlib.util.find_spec("playwright"):
            from playwright.sync_api import sync_playwright

            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=_chromium(), args=["--no-sandbox"])
                tab = browser.new_page()
                tab.goto(url)
                tab.wait_for_function(
                    "document.querySelector('#figure') && document.querySelector('#figure').naturalWidth > 0",
                    timeout=180_000,
                    polling=250,  # a timer: requestAnimationFrame stalls while a headless page is idle
                )
                assert "torus" in tab.text_content("#summary")
                browser.close()
