"""The in-page C-space and A* (rapp/live/core.js) held to rapp, in headless Chromium.

The explorers of chapters 4 and 5 recompute the occupancy grid and A* in the browser. Here the
page's `window.rappLive.occupancy` and `window.rappLive.astar` run on random scenarios (discs,
rectangles at any angle, convex polygons, random link lengths, grids of 24 to 180 cells per joint)
and are compared with the oracles `rapp.occupancy` and `rapp.astar`: the cells agree except at
tangency (at most 0.1 % of a grid, and only where the arm's clearance is within rounding of 0),
and the paths agree cell for cell (the same order of expansions gives the same path).
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

import rapp
from rapp import live
from rapp.collision import clearance
from rapp.cspace import grid_q

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
playwright = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH (apt-get install chromium)"),
]

N_SCENARIOS = 48


def random_scenario(rng: np.random.Generator) -> dict:
    """A scenario file's mapping: two random links, one to five obstacles of every type."""
    L = rng.uniform(0.4, 1.5, 2).round(3).tolist()
    reach = sum(L)
    obstacles = []
    for _ in range(int(rng.integers(1, 6))):
        kind = rng.choice(["circle", "rectangle", "polygon"])
        c = rng.uniform(-reach, reach, 2)
        if kind == "circle":
            obstacles.append({"type": "circle", "center": c.tolist(), "radius": float(rng.uniform(0.05, 0.6))})
        elif kind == "rectangle":
            obstacles.append({"type": "rectangle", "corner": c.tolist(), "width": float(rng.uniform(0.1, 0.8)),
                              "height": float(rng.uniform(0.1, 0.8)), "angle": float(rng.uniform(-np.pi, np.pi))})
        else:
            k = int(rng.integers(3, 8))
            t = np.linspace(0, 2 * np.pi, k, endpoint=False) + rng.uniform(0, 2 * np.pi / k / 2, k)
            r = rng.uniform(0.1, 0.5)
            v = c + r * np.c_[np.cos(t), np.sin(t)]
            obstacles.append({"type": "polygon", "vertices": (v if rng.random() < 0.5 else v[::-1]).tolist()})
    # A disc over the base or the elbow's circle now and then: the "every direction" cases.
    if rng.random() < 0.2:
        obstacles.append({"type": "circle", "center": [0.0, 0.0], "radius": float(rng.uniform(0.05, 0.3))})
    return {"arm": {"link_lengths": L, "joint_limits": None}, "obstacles": obstacles,
            "start": [0.0, 0.0], "goal": {"joints": [1.0, 1.0]}}


def objects(sc: dict):
    """The arm and obstacles of a scenario mapping, built with rapp's constructors."""
    obs = []
    for ob in sc["obstacles"]:
        if ob["type"] == "circle":
            obs.append(rapp.Circle(ob["center"], ob["radius"]))
        elif ob["type"] == "rectangle":
            obs.append(rapp.Polygon.rectangle(ob["corner"], ob["width"], ob["height"], ob.get("angle", 0.0)))
        else:
            obs.append(rapp.Polygon(ob["vertices"]))
    return rapp.Arm(sc["arm"]["link_lengths"]), obs


@pytest.fixture(scope="module")
def pw():
    """One Playwright for the module: a second sync_playwright() while one runs is refused."""
    with playwright.sync_playwright() as p:
        yield p


@pytest.fixture(scope="module")
def page(pw):
    browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
    pg = browser.new_page()
    pg.set_content("<html><body></body></html>")
    pg.add_script_tag(content=live.core_js())
    yield pg
    browser.close()


def _cases():
    rng = np.random.default_rng(2026)
    out = []
    for _ in range(N_SCENARIOS):
        sc = random_scenario(rng)
        M = int(rng.choice([24, 45, 90, 120, 180]))
        out.append((sc, M))
    return out


def test_occupancy_matches_rapp(page):
    cases = _cases()
    got = page.evaluate("cases => cases.map(([sc, M]) => window.rappLive.occupancy(sc, M))",
                        [[sc, M] for sc, M in cases])
    worst = 0.0
    for (sc, M), js in zip(cases, got):
        arm, obs = objects(sc)
        grid = rapp.JointGrid(arm, (M, M))
        want = rapp.occupancy(arm, obs, grid)
        js = np.array(js, dtype=bool).reshape(M, M)
        differ = js != want
        worst = max(worst, differ.mean())
        assert differ.mean() <= 0.001, (json.dumps(sc), M, int(differ.sum()))
        if differ.any():
            # Every disagreement is a tangent cell: the arm grazes an obstacle there.
            gap = clearance(arm, grid_q(grid)[differ], obs)
            assert np.all(np.abs(gap) < 1e-9), (json.dumps(sc), M, gap)
    assert 0.0 <= worst <= 0.001


def test_occupancy_of_the_benchmark_is_exact(page):
    sc = rapp.load_scenario("default").to_dict()
    js = np.array(page.evaluate("sc => window.rappLive.occupancy(sc, 180)", sc), bool).reshape(180, 180)
    s = rapp.load_scenario("default")
    assert (js == rapp.occupancy(s.arm, s.obstacles, rapp.JointGrid(s.arm, 180))).all()


def test_astar_matches_rapp(page):
    rng = np.random.default_rng(7)
    cases, want = [], []
    for sc, M in _cases():
        arm, obs = objects(sc)
        occ = rapp.occupancy(arm, obs, rapp.JointGrid(arm, (M, M)))
        free = np.argwhere(~occ)
        if len(free) < 2:
            continue
        for _ in range(2):
            a, b = free[rng.choice(len(free), 2, replace=False)]
            w = float(rng.choice([1.0, 1.0, 1.5, 2.0]))
            try:
                path = rapp.astar(occ, tuple(a), tuple(b), heuristic_weight=w)
            except rapp.NoPathFound:
                path = None
            cases.append([occ.ravel().astype(int).tolist(), [M, M], a.tolist(), b.tolist(), w])
            want.append(path)
    got = page.evaluate(
        """cases => cases.map(([occ, shape, a, b, w]) => {
             try { return window.rappLive.astar(occ, shape, a, b, {weight: w}); }
             catch (e) { return null; } })""", cases)
    assert len(cases) >= 60 and sum(p is not None for p in want) >= 40
    for case, js, py in zip(cases, got, want):
        if py is None:
            assert js is None, case[2:]
            continue
        assert js is not None and len(js) == len(py), case[2:]
        assert [tuple(c) for c in js] == py, case[2:]


def test_astar_crosses_the_seam_and_stops_at_walls(page):
    grid = np.zeros((20, 20), bool)
    path = page.evaluate("a => window.rappLive.astar(a, [20, 20], [1, 1], [18, 18])", grid.ravel().astype(int).tolist())
    assert [tuple(c) for c in path] == rapp.astar(grid, (1, 1), (18, 18))
    assert len(path) - 1 == 6  # 3 steps across each seam
    walled = grid.copy()
    walled[10, :] = True
    walled[:, 10] = True
    msg = page.evaluate("""a => { try { window.rappLive.astar(a, [20, 20], [1, 1], [15, 15], {wraps: false}); return "found"; }
                                  catch (e) { return e.message; } }""", walled.ravel().astype(int).tolist())
    assert "no path" in msg



# The 30 ms goal (180 x 180, five obstacles, and A* across it) is a speed goal: it is measured in
# benchmarks/bench_live.py (rapp/recorded/live.json), never in a timed unit test.


# ------------------------------------------------------------------ the same explorer in JupyterLab

def _lab_notebook(path) -> None:
    import nbformat
    from nbformat.v4 import new_code_cell, new_notebook

    nb = new_notebook(cells=[
        new_code_cell("from rapp import live\nw = live.cspace_explorer(cells=60)\nw"),
        new_code_cell("print('centre', [round(v, 2) for v in w.scenario['obstacles'][0]['center']])"),
    ])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, path)


def test_the_explorer_works_in_jupyterlab_and_tells_python(tmp_path, pw):
    """Lab renders the explorer with anywidget's own front end; a drag redraws it, and the
    kernel sees where the reader left the obstacle."""
    import os
    import socket
    import subprocess
    import sys
    import time
    from pathlib import Path

    _lab_notebook(tmp_path / "live.ipynb")
    settings = tmp_path / ".settings" / "@jupyterlab"
    (settings / "apputils-extension").mkdir(parents=True)
    (settings / "apputils-extension" / "notification.jupyterlab-settings").write_text('{"fetchNews": "false"}')
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    env = dict(os.environ, JUPYTERLAB_SETTINGS_DIR=str(tmp_path / ".settings"),
               JUPYTERLAB_WORKSPACES_DIR=str(tmp_path / ".workspaces"))
    server = subprocess.Popen(
        [str(Path(sys.executable).with_name("jupyter")), "lab", "--no-browser", "--allow-root",
         f"--port={port}", "--ServerApp.ip=127.0.0.1", f"--ServerApp.root_dir={tmp_path}",
         "--IdentityProvider.token=live"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        page = browser.new_page(viewport={"width": 1300, "height": 900})
        page.set_default_timeout(90_000)
        deadline = time.monotonic() + 60
        while True:
            try:
                page.goto(f"http://127.0.0.1:{port}/lab/tree/live.ipynb?token=live&reset")
                break
            except playwright.Error:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)
        page.wait_for_selector(".jp-Notebook .jp-Cell")
        page.wait_for_function("""() => [...document.querySelectorAll('.jp-StatusBar-TextItem')]
            .some(e => /\\|\\s*Idle/.test(e.textContent))""")
        page.locator(".jp-CodeCell").first.click()
        page.keyboard.press("Shift+Enter")
        root = page.locator("[data-rapp-live]")
        root.wait_for()
        page.wait_for_function("() => document.querySelector('[data-rapp-live]').dataset.rappFrame >= 1")
        page.wait_for_timeout(1000)  # handles are placed on the frame after the first drawing
        frame = int(root.get_attribute("data-rapp-frame"))
        box = root.locator('[data-rapp-drag="obstacle-0"]').bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x - 60, y + 20, steps=10)
        page.mouse.up()
        page.wait_for_function(f"() => +document.querySelector('[data-rapp-live]').dataset.rappFrame > {frame}",
                               timeout=15_000)
        page.keyboard.press("Escape")
        page.locator(".jp-CodeCell").nth(1).click()
        page.keyboard.press("Shift+Enter")
        out = page.locator(".jp-CodeCell").nth(1).locator(".jp-OutputArea-output")
        out.filter(has_text="centre").wait_for()
        text = out.inner_text()
        assert "centre" in text and "[1.75, 0.75]" not in text, text
        browser.close()
    finally:
        server.terminate()
        server.wait(30)
