"""The in-page C-space and A* (rapp/live/core.js) held to rapp under node, in the fast tier.

One node process runs ``rappLive.occupancy`` and ``rappLive.astar`` on random scenes (discs,
rectangles at any angle, convex polygons in either winding, random link lengths, joints that
turn freely or are limited, square and oblong grids of 12 to 120 cells per joint) and on random
A* problems (grids of random walls and C-space grids, every combination of wrapping axes,
heuristic weights 1 to 2). The oracles are :func:`rapp.occupancy` and :func:`rapp.astar`: the
cells agree except at tangency (at most 0.1 % of a grid, only where the arm's clearance is within
rounding of 0), and the paths agree cell for cell, including "no path". tests/test_live.py runs
the same core in headless Chromium (slow tier).
"""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

import rapp
from rapp import live
from rapp.collision import clearance
from rapp.cspace import grid_q

NODE = shutil.which("node")
pytestmark = pytest.mark.skipif(NODE is None, reason="no node on PATH (apt-get install nodejs)")

# Reads the cases on stdin, answers on stdout: one node process for every case.
DRIVER = r"""
const vm = require("vm");
let text = "";
process.stdin.on("data", (d) => (text += d));
process.stdin.on("end", () => {
  const {core, occupancy, astar} = JSON.parse(text);
  vm.runInThisContext(core);
  const R = globalThis.rappLive;
  const occ = occupancy.map(([sc, M]) => R.occupancy(sc, M));
  const paths = astar.map(([grid, shape, a, b, w, wraps]) => {
    try { return R.astar(grid, shape, a, b, {weight: w, wraps: wraps}); }
    catch (e) { return String(e.message); }
  });
  process.stdout.write(JSON.stringify({occ, paths}));
});
"""


def random_scenario(rng: np.random.Generator, limited: bool) -> dict:
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
            v = c + rng.uniform(0.1, 0.5) * np.c_[np.cos(t), np.sin(t)]
            obstacles.append({"type": "polygon", "vertices": (v if rng.random() < 0.5 else v[::-1]).tolist()})
    if rng.random() < 0.2:  # a disc over the base: the "every direction" case
        obstacles.append({"type": "circle", "center": [0.0, 0.0], "radius": float(rng.uniform(0.05, 0.3))})
    limits = None
    if limited:
        lo = rng.uniform(-3.0, 0.0, 2)
        limits = [[float(a), float(a + rng.uniform(0.5, 3.0))] for a in lo]
    return {"arm": {"link_lengths": L, "joint_limits": limits}, "obstacles": obstacles}


def objects(sc: dict):
    """The arm and obstacles of a scenario mapping, built with rapp's constructors."""
    obs = []
    for ob in sc["obstacles"]:
        if ob["type"] == "circle":
            obs.append(rapp.Circle(ob["center"], ob["radius"]))
        elif ob["type"] == "rectangle":
            obs.append(rapp.Polygon.rectangle(ob["corner"], ob["width"], ob["height"], ob["angle"]))
        else:
            obs.append(rapp.Polygon(ob["vertices"]))
    lim = sc["arm"]["joint_limits"]
    return rapp.Arm(sc["arm"]["link_lengths"], None if lim is None else [tuple(x) for x in lim]), obs


def run_node(occupancy_cases, astar_cases) -> dict:
    payload = json.dumps({"core": live.core_js(), "occupancy": occupancy_cases, "astar": astar_cases})
    done = subprocess.run([NODE, "-e", DRIVER], input=payload, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def cases():
    rng = np.random.default_rng(36_5)
    occ_cases = []
    for k in range(40):
        sc = random_scenario(rng, limited=k % 4 == 3)
        M = [int(m) for m in rng.choice([12, 24, 45, 60, 90, 120], 2)] if k % 3 == 0 else int(rng.choice([24, 45, 90, 120]))
        occ_cases.append([sc, M])
    astar_cases, want = [], []
    for k in range(80):
        shape = [int(v) for v in rng.integers(5, 60, 2)]
        if k % 2:  # a C-space grid of one of the scenes above
            sc, M = occ_cases[k % len(occ_cases)]
            arm, obs = objects({**sc, "arm": {**sc["arm"], "joint_limits": None}})
            grid = rapp.occupancy(arm, obs, rapp.JointGrid(arm, tuple(shape)))
        else:  # random walls, sometimes dense enough to cut the start from the goal
            grid = rng.random(shape) < rng.uniform(0.0, 0.35)
        free = np.argwhere(~grid)
        ends = free[rng.choice(len(free), 2, replace=False)] if len(free) >= 2 else rng.integers(0, 5, (2, 2))
        if rng.random() < 0.1:
            ends[1] = np.argwhere(grid)[0] if grid.any() else ends[1]  # a blocked goal
        wraps = [bool(v) for v in rng.integers(0, 2, 2)]
        w = float(rng.choice([1.0, 1.0, 1.25, 1.5, 2.0, 1.1, 2.7]))  # 1.1 and 2.7: the unpacked heap
        try:
            path = rapp.astar(grid, tuple(ends[0]), tuple(ends[1]), wraps=wraps, heuristic_weight=w)
        except rapp.NoPathFound:
            path = None
        astar_cases.append([grid.ravel().astype(int).tolist(), shape, ends[0].tolist(), ends[1].tolist(), w, wraps])
        want.append(path)
    return occ_cases, astar_cases, want, run_node(occ_cases, astar_cases)


def test_occupancy_under_node_matches_rapp(cases):
    occ_cases, _, _, got = cases
    assert len(got["occ"]) == len(occ_cases) == 40
    for (sc, M), js in zip(occ_cases, got["occ"]):
        arm, obs = objects(sc)
        shape = tuple(M) if isinstance(M, list) else (M, M)
        grid = rapp.JointGrid(arm, shape)
        want = rapp.occupancy(arm, obs, grid)
        js = np.array(js, dtype=bool).reshape(shape)
        differ = js != want
        assert differ.mean() <= 0.001, (json.dumps(sc), M, int(differ.sum()))
        if differ.any():  # every disagreement is a cell where the arm grazes an obstacle
            gap = clearance(arm, grid_q(grid)[differ], obs)
            assert np.all(np.abs(gap) < 1e-9), (json.dumps(sc), M, gap)


def test_astar_under_node_matches_rapp(cases):
    _, astar_cases, want, got = cases
    assert sum(p is None for p in want) >= 5 and sum(p is not None for p in want) >= 40
    for case, js, py in zip(astar_cases, got["paths"], want):
        if py is None:
            assert isinstance(js, str) and ("no path" in js or "blocked" in js), (case[1:], js)
        else:
            assert [tuple(c) for c in js] == py, case[1:]


def test_a_search_can_be_resumed_and_reused():
    """The explorer steps a search a few expansions at a time and starts a new one on every
    drag, reusing its buffers: each gives rapp.astar's path, on a grid of any previous size, and
    its closed set and open list (drawn by the explorer) hold as many cells as it counts."""
    rng = np.random.default_rng(5)
    grids = [rng.random((int(a), int(b))) < 0.25 for a, b in rng.integers(8, 40, (6, 2))]
    probs = []
    for g in grids:
        free = np.argwhere(~g)
        a, b = free[rng.choice(len(free), 2, replace=False)]
        try:
            want = rapp.astar(g, tuple(a), tuple(b))
        except rapp.NoPathFound:
            want = None
        probs.append(([g.ravel().astype(int).tolist(), list(g.shape), a.tolist(), b.tolist()], want))
    script = r"""
const vm = require("vm"); let t = ""; process.stdin.on("data", (d) => (t += d));
process.stdin.on("end", () => {
  const {core, probs} = JSON.parse(t); vm.runInThisContext(core); const R = globalThis.rappLive;
  const buf = R.searchBuffers(), out = [];
  for (const [g, shape, a, b] of probs) {
    const S = new R.Search(g, shape, a, b, {buffers: buf});
    let n = 0; while (S.step(3) === "running") n++;
    let closed = 0;
    for (let k = 0; k < shape[0] * shape[1]; k++) closed += S.isClosed(k);
    if (closed !== S.expansions || S.openCells().length !== S.openCount()) throw new Error("counts");
    out.push([S.status, S.path ? R.toCells(S.path, shape[1]) : null, S.expansions, S.openCount()]);
  }
  process.stdout.write(JSON.stringify(out));
});"""
    payload = json.dumps({"core": live.core_js(), "probs": [p for p, _ in probs]})
    done = subprocess.run([NODE, "-e", script], input=payload, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    for (status, path, expansions, open_), (_, want) in zip(json.loads(done.stdout), probs):
        assert (status == "found") == (want is not None)
        if want is not None:
            assert [tuple(c) for c in path] == want and expansions >= len(want) - 1 and open_ >= 1


def test_a_search_reads_only_the_cells_it_touches():
    """The set-up costs the cells the search touches, not the grid (issue 37.4): on a 1000 x 1000
    grid a short search reads a few dozen cells of `occupied`, and a search on reused buffers
    writes none of the grid's cells before it starts."""
    script = r"""
const vm = require("vm"); let t = ""; process.stdin.on("data", (d) => (t += d));
process.stdin.on("end", () => {
  vm.runInThisContext(JSON.parse(t).core); const R = globalThis.rappLive;
  const M = 1000, grid = new Uint8Array(M * M);
  let reads = 0;
  const occ = new Proxy(grid, {get: (a, k) => { if (typeof k === "string" && /^\d+$/.test(k)) reads++; return a[k]; }});
  const buf = R.searchBuffers(), out = [];
  for (const [a, b] of [[[500, 500], [500, 507]], [[10, 10], [13, 12]], [[999, 0], [0, 999]]]) {
    reads = 0;
    const S = new R.Search(occ, [M, M], a, b, {buffers: buf});
    const setup = reads;
    S.step(Infinity);
    out.push([setup, reads, S.reached, S.expansions, S.path.length - 1]);
  }
  process.stdout.write(JSON.stringify(out));
});"""
    done = subprocess.run([NODE, "-e", script], input=json.dumps({"core": live.core_js()}), capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    for (setup, reads, reached, expansions, steps), want in zip(json.loads(done.stdout), (7, 5, 2)):
        assert steps == want  # the last pair is 2 steps apart across both seams
        assert setup == 2  # the start's cell and the goal's
        assert reads <= 2 + 4 * expansions and reached <= 1 + 4 * expansions <= 4 * 1000


# The explorer's state part (explorer_state.js) after core.js, in one script, then the checks.
EXPLORER_DRIVER = r"""
const vm = require("vm"); let t = ""; process.stdin.on("data", (d) => (t += d));
process.stdin.on("end", () => {
  const {src, check, widgets} = JSON.parse(t);
  vm.runInThisContext(src + "\n;globalThis.__check = (" + check + ");");
  process.stdout.write(JSON.stringify(globalThis.__check(widgets)));
});
"""


def _run_state(check: str, widgets: list[dict]):
    """Run ``check(widgets)`` (a JS function's text) with explorer_state.js loaded; its result."""
    from rapp.live import _read

    src = _read("core.js") + "\n" + _read("explorer_state.js")
    done = subprocess.run([NODE, "-e", EXPLORER_DRIVER], input=json.dumps({"src": src, "check": check, "widgets": widgets}),
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _state(widget) -> dict:
    keys = ["scenario", "cells", "q", "search", "source", "start", "goal", "weight", "walls", "paint_cells", "sweep"]
    return {k: getattr(widget, k) for k in keys}


def test_the_cspace_axis_labels_sit_at_their_angles():
    """Each tick label of the C-space's axes sits where the canvas shows its angle (the drag's
    map G.pxToQ): "0" at the middle of both axes, "−π" and "π" at the ends, θ₁ left to right and
    θ₂ bottom to top; the axis names sit between their 0 and π."""
    got = _run_state("""(ws) => {
      const S = makeState({get: (k) => ws[0][k]}), G = makeGeometry(S);
      return {x: X_TICKS.map(([t, a]) => [t, a, G.pxToQ(tickAt(a) * W, 0)[0]]),
              y: Y_TICKS.map(([t, a]) => [t, a, G.pxToQ(0, tickAt(a, true) * W)[1]])};
    }""", [_state(live.cspace_explorer(cells=60))])
    value = {"−π": -np.pi, "0": 0.0, "π": np.pi}
    for axis, name in (("x", "θ₁"), ("y", "θ₂")):
        labels = [t for t, _, _ in got[axis]]
        assert {"−π", "0", "π", name} <= set(labels)
        for text, angle, shown in got[axis]:
            assert shown == pytest.approx(angle, abs=1e-12)
            if text in value:
                assert angle == pytest.approx(value[text])
            else:  # the axis name, between 0 and π
                assert 0 < angle < np.pi


def test_the_sweep_slider_and_status_name_the_same_column():
    """Chapter 4's sweep: the column the slider shows is the column the status line names, at
    every slider position, and the slider shows the column the sweep is at."""
    M = 40
    got = _run_state("""(ws) => {
      const S = makeState({get: (k) => ws[0][k]}), G = makeGeometry(S);
      S.layers = R.occupancyOf(R.parseScenario(S.scenario), S.M, true);
      const out = [];
      for (let v = 1; v <= S.M; v++) {
        S.sweep = sweepFromSlider(v);
        out.push([v, sweepSliderValue(S), statusText(S, G, [0, 0])]);
      }
      return out;
    }""", [_state(live.sweep_explorer(obstacle=0, cells=M))])
    assert len(got) == M
    for v, shown, status in got:
        assert shown == v and f"(column {v} of {M})" in status, (v, shown, status)


def test_the_astar_caption_says_where_the_arm_is():
    """Chapter 5: the workspace's caption says the arm is at the start before it moves, where on
    its path it is while "move the arm" plays, and at the goal once it arrived."""
    got = _run_state("""(ws) => {
      const S = makeState({get: (k) => ws[0][k]}), G = makeGeometry(S), M = S.M;
      S.layers = R.occupancyOf(R.parseScenario(S.scenario), M, true);
      S.occ = new Uint8Array(M * M);
      for (const lay of S.layers) for (let i = 0; i < S.occ.length; i++) S.occ[i] |= lay[i];
      S.run = new R.Search(S.occ, [M, M], S.start, S.goal, {wraps: [true, true]});
      S.run.step(Infinity);
      const n = S.run.path.length - 1, out = [[-1, workspaceCaption(S, G)]];
      for (const k of [0, 1, Math.floor(n / 2), n]) { S.motion = k; out.push([k, workspaceCaption(S, G)]); }
      return {n, out};
    }""", [_state(live.astar_explorer("default", cells=60, goal=(-2.9, -1.5)))])
    n = got["n"]
    assert n > 3
    captions = dict(got["out"])
    assert "at the start" in captions[-1]
    for k in (0, 1, n // 2):
        assert f"step {k} of {n}" in captions[k] and "at the start" not in captions[k]
    assert "at the goal" in captions[n] and "at the start" not in captions[n]
