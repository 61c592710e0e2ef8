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


# ------------------------------------------------------------------ the explorers on a phone

HARNESS = """async ([esm, state]) => {
  const url = URL.createObjectURL(new Blob([esm], {type: "text/javascript"}));
  const mod = await import(url);
  const model = {s: state, get(k) { return this.s[k]; }, set(k, v) { this.s[k] = v; }, save_changes() {}, on() {}};
  const host = document.createElement("div");
  document.body.appendChild(host);
  mod.default.render({model, el: host});
}"""
STATE = ["scenario", "cells", "q", "search", "source", "start", "goal", "weight", "walls", "paint_cells", "sweep"]


@pytest.fixture()
def phone(pw):
    """A 390 x 844 touch screen (device pixel ratio 3), as issue 33 measured the book."""
    browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
    pg = browser.new_page(viewport={"width": 390, "height": 844}, device_scale_factor=3, has_touch=True, is_mobile=True)
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.set_content("<html><head><meta name=viewport content='width=device-width'></head><body style='margin:8px'></body></html>")

    def show(widget):
        pg.evaluate(HARNESS, [live.explorer_js(), {k: getattr(widget, k) for k in STATE}])
        root = pg.locator("[data-rapp-live]").last
        pg.wait_for_function("r => +r.dataset.rappFrame >= 1", arg=root.element_handle())
        pg.wait_for_timeout(100)  # handles are placed on the frame after the first drawing
        return root

    pg.show = show
    yield pg
    browser.close()
    assert not errors, errors


def touch_drag(pg, x0, y0, x1, y1, steps=8):
    """A finger's drag: touch events through the DevTools protocol (Chromium makes them pointer events)."""
    cdp = pg.context.new_cdp_session(pg)
    cdp.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": [{"x": x0, "y": y0}]})
    for k in range(1, steps + 1):
        x, y = x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps
        cdp.send("Input.dispatchTouchEvent", {"type": "touchMove", "touchPoints": [{"x": x, "y": y}]})
        pg.wait_for_timeout(20)
    cdp.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
    pg.wait_for_timeout(150)


def centre(box):
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2


def test_on_a_phone_both_panels_fit_and_handles_take_a_finger(phone):
    root = phone.show(live.astar_explorer("default", cells=100, goal=(-2.9, -1.5)))
    root.scroll_into_view_if_needed()
    ws, cs = (root.locator(f'canvas[data-rapp-drag="{n}"]').bounding_box() for n in ("workspace", "cspace"))
    assert ws["x"] + ws["width"] <= cs["x"] and cs["x"] + cs["width"] <= 390  # side by side
    assert abs(ws["y"] - cs["y"]) < 40 and root.bounding_box()["height"] <= 844
    handles = root.locator('[role="slider"][data-rapp-drag]')
    assert handles.count() == 3 + 2 + 2  # obstacles, elbow and tip, start and goal
    for k in range(handles.count()):
        box = handles.nth(k).bounding_box()
        assert box["width"] >= 32 and box["height"] >= 32
    ticks = root.locator(".rl-xt").inner_text() + root.locator(".rl-yt").inner_text()
    assert all(t in ticks for t in ("−π", "0", "π"))


def test_a_finger_drags_an_obstacle_and_it_stays_on_the_canvas(phone):
    root = phone.show(live.cspace_explorer(cells=60))
    h = root.locator('[data-rapp-drag="obstacle-0"]')
    before = h.get_attribute("aria-valuetext")
    frame = int(root.get_attribute("data-rapp-frame"))
    x, y = centre(h.bounding_box())
    touch_drag(phone, x, y, 389, y - 400)  # far beyond the canvas's top right corner
    assert int(root.get_attribute("data-rapp-frame")) > frame
    after = h.get_attribute("aria-valuetext")
    assert after != before and "obstacle 1 at" in after
    cx, cy = (float(v.replace("−", "-")) for v in after.split("(")[1].split(")")[0].split(", "))
    half = 1.0 + 1.0 + 0.35  # the canvas shows the reach plus a margin
    assert abs(cx) + 0.6 <= half + 1e-9 and abs(cy) + 0.6 <= half + 1e-9  # the disc (radius 0.6) inside
    canvas = root.locator('canvas[data-rapp-drag="workspace"]').bounding_box()
    hx, hy = centre(h.bounding_box())
    assert canvas["x"] <= hx <= canvas["x"] + canvas["width"] and canvas["y"] <= hy <= canvas["y"] + canvas["height"]
    assert "Obstacle 1 is at" in root.locator(".rl-status").inner_text()


def test_every_handle_by_keyboard_announces_its_value(phone):
    root = phone.show(live.cspace_explorer(cells=60, q=(0.45, 0.2)))
    status = root.locator(".rl-status")
    assert status.get_attribute("aria-live") == "polite"
    assert "% of the cells collide" in status.inner_text()
    names = []
    phone.locator("body").focus()
    for _ in range(12):  # Tab through the page: the sliders, then every handle
        phone.keyboard.press("Tab")
        names.append(phone.evaluate("() => document.activeElement.dataset.rappDrag || ''"))
    assert {"obstacle-0", "obstacle-1", "obstacle-2", "elbow", "tip", "configuration"} <= set(names)
    elbow = root.locator('[data-rapp-drag="elbow"]')
    assert elbow.get_attribute("aria-valuetext") == "θ₁ 0.45 rad" and elbow.get_attribute("aria-valuenow") == "0.45"
    elbow.focus()
    phone.keyboard.press("ArrowRight")
    phone.wait_for_timeout(100)
    assert elbow.get_attribute("aria-valuetext") == "θ₁ 0.50 rad"
    ob = root.locator('[data-rapp-drag="obstacle-0"]')
    ob.focus()
    phone.keyboard.press("ArrowUp")
    phone.wait_for_timeout(100)
    assert ob.get_attribute("aria-valuetext") == "obstacle 1 at (1.75, 0.80) m"
    text = status.inner_text()
    assert "Obstacle 1 is at (1.75, 0.80) m" in text and ("is free." in text or "collides." in text)


def test_the_arm_moves_along_the_path_it_found(phone):
    sc = rapp.load_scenario("default")
    grid = rapp.JointGrid(sc.arm, 100)
    root = phone.show(live.astar_explorer("default", cells=100, goal=(-2.9, -1.5)))
    want = len(rapp.astar(rapp.occupancy(sc.arm, sc.obstacles, grid), tuple(grid.index([0.0, 0.0])),
                          tuple(grid.index([-2.9, -1.5])))) - 1
    assert f"path of {want} steps" in root.locator(".rl-status").inner_text()
    assert root.get_attribute("data-rapp-motion") == "-1"
    caption = root.locator(".rl-cap").first
    assert "the arm at the start" in caption.inner_text()
    root.get_by_role("button", name="▶ move the arm").click()
    phone.wait_for_function("r => +r.dataset.rappMotion > 5", arg=root.element_handle())
    assert root.locator('[data-rapp-drag="elbow"]').is_hidden()  # the start's handles wait
    assert "at the start" not in caption.inner_text() and f" of {want})" in caption.inner_text()
    phone.wait_for_function(f"r => +r.dataset.rappMotion === {want}", arg=root.element_handle(), timeout=20_000)
    assert "moved along it to the goal" in root.locator(".rl-status").inner_text()
    assert "the arm at the goal" in caption.inner_text()


def test_the_menu_keeps_each_grids_start_and_goal(phone):
    root = phone.show(live.astar_explorer("default", cells=100, goal=(-2.9, -1.5)))
    goal = root.locator('[data-rapp-drag="goal"]')
    goal.focus()
    phone.keyboard.press("ArrowUp")
    phone.wait_for_timeout(100)
    moved = goal.get_attribute("aria-valuetext")
    sel = root.locator("select")
    sel.select_option("paint")
    phone.wait_for_timeout(100)
    assert "cell (20, 12)" in goal.get_attribute("aria-valuetext")  # the painted grid's own goal
    sel.select_option("cspace")
    phone.wait_for_timeout(100)
    assert goal.get_attribute("aria-valuetext") == moved
    assert "A* found a path" in root.locator(".rl-status").inner_text()


def test_the_sweep_builds_one_obstacle_column_by_column(phone):
    sc = rapp.load_scenario("default")
    M = 60
    layer = rapp.occupancy(sc.arm, sc.obstacles[:1], rapp.JointGrid(sc.arm, M))
    root = phone.show(live.sweep_explorer(obstacle=0, cells=M))
    root.get_by_role("button", name="▶ sweep θ₁").click()
    phone.wait_for_function("r => +r.dataset.rappSweep >= 10", arg=root.element_handle())
    root.get_by_role("button", name="❚❚ pause").click()
    col = int(root.get_attribute("data-rapp-sweep"))
    slider = root.locator("input[aria-label='θ₁ column']")
    assert f"column {col + 1} of {M}" in root.locator(".rl-status").inner_text()
    assert slider.input_value() == str(col + 1)  # the slider shows the column the status names
    for c in (1, 17, 45, M):
        slider.fill(str(c))
        phone.wait_for_timeout(80)
        text = root.locator(".rl-status").inner_text()
        shown = slider.evaluate("(s) => s.nextSibling.textContent")
        assert shown == str(c) and f"column {c} of {M}" in text, (shown, text)
        assert f"at {int(layer[c - 1].sum())} of the {M} values" in text, text


def test_the_cspace_tick_labels_sit_at_their_angles(phone):
    """The C-space's "0" is centred on the canvas's middle (θ = 0) on both axes, "−π" and "π"
    at its ends (within the canvas's 1 px border and a rounding)."""
    root = phone.show(live.cspace_explorer(cells=60))
    cv = root.locator('canvas[data-rapp-drag="cspace"]').bounding_box()
    ticks = {ax: {s.inner_text(): s.bounding_box() for s in root.locator(f".{ax} span").all()}
             for ax in ("rl-xt", "rl-yt")}
    x0 = ticks["rl-xt"]["0"]
    assert abs(x0["x"] + x0["width"] / 2 - (cv["x"] + cv["width"] / 2)) <= 2.5
    y0 = ticks["rl-yt"]["0"]
    assert abs(y0["y"] + y0["height"] / 2 - (cv["y"] + cv["height"] / 2)) <= 2.5
    lo, hi = ticks["rl-xt"]["−π"], ticks["rl-xt"]["π"]
    assert abs(lo["x"] - cv["x"]) <= 2.5 and abs(hi["x"] + hi["width"] - (cv["x"] + cv["width"])) <= 2.5
    top, bottom = ticks["rl-yt"]["π"], ticks["rl-yt"]["−π"]
    assert abs(top["y"] - cv["y"]) <= 2.5 and abs(bottom["y"] + bottom["height"] - (cv["y"] + cv["height"])) <= 2.5


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
