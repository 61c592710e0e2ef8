"""The in-page C-space and A* of the live explorers, timed in headless Chromium.

Run from the repository root:  python benchmarks/bench_live.py

The goal of issue 26: a 180 x 180 C-space with five obstacles recomputed in <= 30 ms, and A* on
it in <= 30 ms, in headless Chromium on this machine (so a drag redraws within two frames). The
scene is the benchmark's three discs plus a fourth disc and a rotated rectangle (four discs and
one convex polygon); A* runs between two far cells whose shortest path crosses the seam. Each is
timed as the explorer runs it (``rappLive.occupancyOf`` with one layer per obstacle, as drawn,
and ``rappLive.Search`` run to the end), after warm-up, and the median, the worst
and the 95th percentile are recorded with the path length (checked equal to ``rapp.astar``'s) in
rapp/recorded/live.json.

Issue 37.4, side by side in CPU time: the page's A* (``rappLive.Search`` under node, the V8 of
Chromium) against rapp's numba A* (:func:`rapp.astar`) on the same 360 x 360 C-space grid, the
same start and goal, interleaved in rounds (a node process answers each round on its stdin while
this process waits, then this process times its own). The search's set-up alone
(``new Search``) is timed too: it must grow with the cells the search touches, not the grid.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import shutil
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import rapp  # noqa: E402
from rapp import live  # noqa: E402

SCENE = {
    "arm": {"link_lengths": [1.0, 1.0], "joint_limits": None},
    "obstacles": [
        {"type": "circle", "center": [1.75, 0.75], "radius": 0.6},
        {"type": "circle", "center": [0.55, 1.5], "radius": 0.5},
        {"type": "circle", "center": [0.0, -1.0], "radius": 0.25},
        {"type": "circle", "center": [-1.3, -0.9], "radius": 0.3},
        {"type": "rectangle", "corner": [-1.6, 0.6], "width": 0.5, "height": 0.3, "angle": 0.4},
    ],
}
M = 180
RUNS = 50

TIMING = """([scene, M, runs, start, goal]) => {
  const R = window.rappLive, parsed = R.parseScenario(scene);
  const occ = new Uint8Array(M * M);
  const occT = [], astarT = [];
  let path = 0;
  for (let k = 0; k < runs + 10; k++) {
    let t0 = performance.now();
    const layers = R.occupancyOf(R.parseScenario(scene), M, true);
    occ.fill(0);
    for (const lay of layers) for (let i = 0; i < occ.length; i++) occ[i] |= lay[i];
    let t1 = performance.now();
    const S = new R.Search(occ, [M, M], start, goal, {});
    S.step(Infinity);
    let t2 = performance.now();
    if (k >= 10) { occT.push(t1 - t0); astarT.push(t2 - t1); }
    path = S.path.length - 1;
  }
  return {occ: occT, astar: astarT, path: path};
}"""


def _stats(ms) -> dict:
    """Median, 95th percentile and worst: the worst run on a shared 2-core machine is the
    scheduler's, the median is the page's."""
    return {k: round(float(f(ms)), 2) for k, f in
            (("median", np.median), ("p95", lambda a: np.percentile(a, 95)), ("max", np.max))}


NODE_DRIVER = r"""
const vm = require("vm"), fs = require("fs"), readline = require("readline");
const [core, occPath, M, s0, s1, g0, g1] = process.argv.slice(1);
vm.runInThisContext(fs.readFileSync(core, "utf8"));
const R = globalThis.rappLive, occ = new Uint8Array(fs.readFileSync(occPath));
const shape = [+M, +M], start = [+s0, +s1], goal = [+g0, +g1];
const buf = R.searchBuffers ? R.searchBuffers() : undefined;
const cpu = () => { const u = process.cpuUsage(); return u.user + u.system; };
const rl = readline.createInterface({input: process.stdin});
rl.on("line", (line) => {
  const runs = +line, total = [], setup = [];
  let steps = 0;
  for (let k = 0; k < runs; k++) {
    const t0 = cpu();
    const S = new R.Search(occ, shape, start, goal, {buffers: buf});
    const t1 = cpu();
    S.step(Infinity);
    const t2 = cpu();
    total.push(t2 - t0); setup.push(t1 - t0); steps = S.path.length - 1;
  }
  process.stdout.write(JSON.stringify({total, setup, steps}) + "\n");
});
"""
NODE_M = 360


def node_vs_numba(rounds: int = 12, per_round: int = 20, warm_up: int = 200) -> dict:
    """The page's A* under node against rapp.astar (numba), CPU time per search, interleaved.

    Both are timed warm: node after ``warm_up`` searches (V8 compiles the loop once it is hot, as
    it is after a reader's first drags), rapp.astar with its compiled kernel loaded."""
    import subprocess
    import tempfile
    import time

    node = shutil.which("node")
    if node is None:
        raise SystemExit("bench_live: no node on PATH")
    s = rapp.load_scenario({**SCENE, "start": [0.0, 0.0], "goal": {"joints": [0.0, 0.0]}})
    grid = rapp.JointGrid(s.arm, NODE_M)
    occ = rapp.occupancy(s.arm, s.obstacles, grid)
    start = tuple(grid.index([0.0, 0.0]).tolist())
    goal = tuple(grid.index([2.4, 2.6]).tolist())
    want = len(rapp.astar(occ, start, goal)) - 1  # also loads the compiled kernel
    with tempfile.TemporaryDirectory() as tmp:
        core, occ_path = Path(tmp) / "core.js", Path(tmp) / "occ.bin"
        core.write_text(live.core_js(), encoding="utf-8")
        occ_path.write_bytes(occ.astype(np.uint8).tobytes())
        proc = subprocess.Popen([node, "-e", NODE_DRIVER, str(core), str(occ_path), str(NODE_M), *map(str, start),
                                 *map(str, goal)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        try:
            def ask(n):
                proc.stdin.write(f"{n}\n")
                proc.stdin.flush()
                return json.loads(proc.stdout.readline())
            ask(warm_up)  # warm-up: V8 compiles the hot loops
            node_us, setup_us, numba_us = [], [], []
            for _ in range(rounds):
                got = ask(per_round)
                assert got["steps"] == want, (got["steps"], want)
                node_us += got["total"]
                setup_us += got["setup"]
                for _ in range(per_round):
                    t0 = time.process_time_ns()
                    rapp.astar(occ, start, goal)
                    numba_us.append((time.process_time_ns() - t0) / 1e3)
        finally:
            proc.stdin.close()
            proc.wait(30)
    med = {k: float(np.median(v)) for k, v in (("node", node_us), ("setup", setup_us), ("numba", numba_us))}
    return {
        "what": f"A* on the {NODE_M} x {NODE_M} C-space of the scene above, {want} steps, CPU time per search",
        "runs": rounds * per_round,
        "node_warm_up_runs": warm_up,
        "node_us_median": round(med["node"], 1),
        "node_setup_us_median": round(med["setup"], 1),
        "numba_us_median": round(med["numba"], 1),
        "ratio_node_over_numba": round(med["node"] / med["numba"], 2),
        "goal_ratio": 2.0,
    }


def main() -> int:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        print("bench_live: no chromium on PATH", file=sys.stderr)
        return 1
    s = rapp.load_scenario({**SCENE, "start": [0.0, 0.0], "goal": {"joints": [0.0, 0.0]}})
    grid = rapp.JointGrid(s.arm, M)
    occ = rapp.occupancy(s.arm, s.obstacles, grid)
    start = tuple(grid.index([0.0, 0.0]).tolist())
    goal = tuple(grid.index([2.4, 2.6]).tolist())
    want = len(rapp.astar(occ, start, goal)) - 1
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, args=["--no-sandbox", "--disable-gpu"])
        page = browser.new_page()
        page.set_content("<html><body></body></html>")
        page.add_script_tag(content=live.core_js())
        got = page.evaluate(TIMING, [SCENE, M, RUNS, list(start), list(goal)])
        version = browser.version
        browser.close()
    versus = node_vs_numba()
    if got["path"] != want:
        print(f"bench_live: the page's path has {got['path']} steps, rapp.astar's {want}", file=sys.stderr)
        return 1
    occ_ms, astar_ms = np.array(got["occ"]), np.array(got["astar"])
    result = {
        "what": "in-page C-space (180 x 180, 4 discs + 1 rectangle) and A* on it, headless Chromium",
        "date": datetime.date.today().isoformat(),
        "machine": platform.platform(),
        "load_average_1min": round(os.getloadavg()[0], 2),
        "cpu_count": os.cpu_count(),
        "chromium": version,
        "cells": [M, M],
        "runs": RUNS,
        "occupancy_ms": _stats(occ_ms),
        "astar_ms": _stats(astar_ms),
        "astar_path_steps": got["path"],
        "rapp_astar_path_steps": want,
        "goal_ms": 30,
        "astar_node_vs_numba": versus,
    }
    out = ROOT / "rapp" / "recorded" / "live.json"
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    tmp.replace(out)
    print(f"occupancy 180x180, 5 obstacles: median {result['occupancy_ms']['median']} ms, "
          f"95th percentile {result['occupancy_ms']['p95']} ms, worst {result['occupancy_ms']['max']} ms")
    print(f"A* ({got['path']} steps): median {result['astar_ms']['median']} ms, 95th percentile {result['astar_ms']['p95']} ms, worst {result['astar_ms']['max']} ms")
    print(f"A* at {NODE_M} x {NODE_M}, CPU time: node {versus['node_us_median']} us "
          f"(set-up {versus['node_setup_us_median']} us), numba {versus['numba_us_median']} us: "
          f"{versus['ratio_node_over_numba']}x (goal <= 2x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
