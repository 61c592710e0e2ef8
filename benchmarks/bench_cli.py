"""The command line's own costs: planning stages, and what --plot adds.

Two measurements, each side by side in one run:

* ``python -m rapp plan`` against ``python -m rapp plan --plot fig.png`` on the embedded default
  scenario (fresh interpreters, best of 5), and the parts of the difference measured in one
  process: importing matplotlib and ``rapp.plotting``, drawing the figure, writing the PNG.
* The stages of ``rapp.plan`` (``Plan.timings``) on the embedded three-link scenario, and the
  certified cells (``certified_free``) against the previous implementation
  (``_certified_free_reference``: link clearances on every prefix cell) on the same grid.

Run: ``python benchmarks/bench_cli.py``; writes ``benchmarks/results/cli.json``.
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
    with tempfile.TemporaryDirectory() as tmp:
        base = [sys.executable, "-m", "rapp", "plan", "--quiet", "--out", os.path.join(tmp, "r.json")]
        run = lambda extra: subprocess.run(base + extra, check=True, cwd=tmp, capture_output=True)  # noqa: E731
        plan_s, plot_s = [], []
        for _ in range(repeat):  # interleaved, so a change of load hits both alike
            plan_s.append(best_of(1, lambda: run([])))
            plot_s.append(best_of(1, lambda: run(["--plot", os.path.join(tmp, "f.png")])))
    return {"plan_s": min(plan_s), "plan_plot_s": min(plot_s), "ratio": min(plot_s) / min(plan_s),
            "goal": "ratio <= 1.6"}


def plot_parts() -> dict:
    code = r"""
import time, json
t0 = time.perf_counter(); import rapp; t1 = time.perf_counter()
p = rapp.plan("default"); t2 = time.perf_counter()
import matplotlib; matplotlib.use("Agg"); from rapp import plotting; t3 = time.perf_counter()
fig = plotting.plot_plan(p, p.scenario); t4 = time.perf_counter()
import tempfile, os
with tempfile.TemporaryDirectory() as d:
    fig.savefig(os.path.join(d, "f.png"), dpi=100, pil_kwargs={"compress_level": 1})
t5 = time.perf_counter()
print(json.dumps({"import_rapp_s": t1 - t0, "plan_s": t2 - t1, "import_matplotlib_plotting_s": t3 - t2,
                  "figure_s": t4 - t3, "save_png_s": t5 - t4}))
"""
    runs = [json.loads(subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                                      text=True).stdout) for _ in range(3)]
    return {k: min(r[k] for r in runs) for k in runs[0]}


def stages() -> dict:
    import rapp
    from rapp.cspace import JointGrid, _certified_free_reference, certified_free

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
    result = {"date": date.today().isoformat(),
              "machine": {"cpus": os.cpu_count(), "load_1min": os.getloadavg()[0],
                          "platform": platform.platform(), "python": platform.python_version()},
              "cli": cli_times(), "plot_parts": plot_parts(), "stages": stages()}
    print(json.dumps(result, indent=2))
    out = Path(__file__).parent / "results" / "cli.json"
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
