"""The command line's own costs: planning stages, and what --plot adds.

Two measurements, each side by side in one run:

* ``python -m rapp plan`` against ``python -m rapp plan --plot fig.png`` on the embedded default
  scenario (fresh interpreters, interleaved, best of 5). The figure is drawn by matplotlib
  (``rapp.plotting.plot_plan`` on an Agg figure, as the command line does for every format); the
  ratio is recorded. No goal is set for it: the earlier goal of at most 1.6 times ``plan`` was
  met only by a second, Pillow-drawn copy of the figure, and was withdrawn with it (one
  renderer). The parts of the figure's cost are measured in one process: importing matplotlib
  and ``rapp.plotting``, drawing the figure, writing the PNG.
* The stages of ``rapp.plan`` (``Plan.timings``) on the embedded three-link scenario, and the
  certified cells (``certified_free``) against the previous implementation
  (``rapp.reference.certified_free``: link clearances on every prefix cell) on the same grid.

Run: ``python benchmarks/bench_cli.py``; rewrites ``rapp/recorded/cli.json`` (atomically).
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def best_of(k, fn):
    times = []
    for _ in range(k):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def cli_times(repeat: int = 5) -> dict:
    """Best times of plan and plan --plot f.png, interleaved in fresh interpreters."""
    with tempfile.TemporaryDirectory() as tmp:
        base = [sys.executable, "-m", "rapp", "plan", "--quiet", "--out", os.path.join(tmp, "r.json")]
        run = lambda extra: subprocess.run(base + extra, check=True, cwd=tmp, capture_output=True)  # noqa: E731
        plan_s, png_s = [], []
        for _ in range(repeat):  # interleaved, so a change of load hits both alike
            plan_s.append(best_of(1, lambda: run([])))
            png_s.append(best_of(1, lambda: run(["--plot", os.path.join(tmp, "f.png")])))
    return {"plan_s": min(plan_s), "plan_plot_s": min(png_s), "ratio": min(png_s) / min(plan_s),
            "goal": None, "plot": "f.png, drawn by rapp.plotting.plot_plan (matplotlib, Agg)"}


# The parts of --plot f.png as rapp.cli makes it: a Figure with an Agg canvas, no pyplot figure.
_PARTS = r"""
import time, json, sys, tempfile, os
t0 = time.perf_counter(); import rapp; t1 = time.perf_counter()
p = rapp.plan("default"); t2 = time.perf_counter()
d = tempfile.mkdtemp()
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from rapp import plotting; t3 = time.perf_counter()
fig = Figure(figsize=plotting.PLAN_FIGSIZE, layout="constrained"); FigureCanvasAgg(fig)
plotting.plot_plan(p, p.scenario, fig=fig); t4 = time.perf_counter()
fig.savefig(os.path.join(d, "f.png"), dpi=100, format="png"); t5 = time.perf_counter()
os.remove(os.path.join(d, "f.png")); os.rmdir(d)
print(json.dumps({"import_rapp_s": t1 - t0, "plan_s": t2 - t1,
                  "import_matplotlib_plotting_s": t3 - t2, "figure_s": t4 - t3,
                  "save_png_s": t5 - t4}))
"""


def plot_parts(repeat: int = 3) -> dict:
    """Best time of each part of making the PNG, each in its own fresh process."""
    runs = [json.loads(subprocess.run([sys.executable, "-c", _PARTS], check=True,
                                      capture_output=True, text=True).stdout)
            for _ in range(repeat)]
    return {k: min(r[k] for r in runs) for k in runs[0]}


def stages() -> dict:
    import rapp
    from rapp.cspace import JointGrid, certified_free
    from rapp.reference import certified_free as _certified_free_reference

    rapp.plan("three_link")
    runs = [rapp.plan("three_link").timings for _ in range(5)]
    timings = {k: min(r[k] for r in runs) for k in runs[0]}
    s = rapp.load_scenario("three_link")
    grid = JointGrid(s.arm, s.planner.cells)
    new = best_of(5, lambda: certified_free(s.arm, s.obstacles, grid))
    old = best_of(3, lambda: _certified_free_reference(s.arm, s.obstacles, grid))
    same = bool(np.array_equal(certified_free(s.arm, s.obstacles, grid),
                               _certified_free_reference(s.arm, s.obstacles, grid)))
    return {"scenario": "three_link", "cells": list(grid.shape), "stage_s": timings,
            "certified_free_s": new, "certified_free_previous_s": old, "ratio": old / new,
            "identical_cells": same}


def main() -> None:
    out = ROOT / "rapp" / "recorded" / "cli.json"
    load_before = os.getloadavg()[0]
    result = {"cli": cli_times(), "plot_parts": plot_parts(), "stages": stages()}
    result = {
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "load_1min": load_before,
                    "load_1min_end": os.getloadavg()[0],
                    "platform": platform.platform(), "python": platform.python_version()},
        **result}
    print(json.dumps(result, indent=2))
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
