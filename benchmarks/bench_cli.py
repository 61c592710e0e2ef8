"""The command line's own costs: planning stages, and what --plot adds.

Three measurements, each side by side in one run:

* ``python -m rapp plan`` against ``python -m rapp plan --plot fig.png`` on the embedded default
  scenario (fresh interpreters, interleaved, best of 5). A PNG is drawn by ``rapp.raster`` with
  Pillow; ``--plot fig.svg`` (matplotlib, as every format but PNG) is timed in the same rounds for
  comparison. The parts of the PNG's cost are measured in one process: importing Pillow and
  ``rapp.raster``, drawing the image, writing the PNG; and, for comparison, the parts of the same
  PNG made by matplotlib, as ``--plot`` made it before ``rapp.raster``: importing matplotlib and
  ``rapp.plotting``, drawing the figure, writing the PNG.
* The stages of ``rapp.plan`` (``Plan.timings``) on the embedded three-link scenario, and the
  certified cells (``certified_free``) against the previous implementation
  (``rapp.reference.certified_free``: link clearances on every prefix cell) on the same grid.

Run: ``python benchmarks/bench_cli.py``; rewrites ``benchmarks/results/cli.json`` (atomically;
keys of the file this script does not write are kept).
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


def cli_times(repeat: int = 5) -> tuple:
    """Best times of plan, plan --plot f.png (rapp.raster) and plan --plot f.svg (matplotlib)."""
    with tempfile.TemporaryDirectory() as tmp:
        base = [sys.executable, "-m", "rapp", "plan", "--quiet", "--out", os.path.join(tmp, "r.json")]
        run = lambda extra: subprocess.run(base + extra, check=True, cwd=tmp, capture_output=True)  # noqa: E731
        plan_s, png_s, svg_s = [], [], []
        for _ in range(repeat):  # interleaved, so a change of load hits all alike
            plan_s.append(best_of(1, lambda: run([])))
            png_s.append(best_of(1, lambda: run(["--plot", os.path.join(tmp, "f.png")])))
            svg_s.append(best_of(1, lambda: run(["--plot", os.path.join(tmp, "f.svg")])))
    png = {"plan_s": min(plan_s), "plan_plot_s": min(png_s), "ratio": min(png_s) / min(plan_s),
           "goal": "ratio <= 1.6", "plot": "f.png, drawn by rapp.raster (Pillow)"}
    svg = {"plan_s": min(plan_s), "plan_plot_s": min(svg_s), "ratio": min(svg_s) / min(plan_s),
           "plot": "f.svg, drawn by rapp.plotting (matplotlib)"}
    return png, svg


_PARTS = r"""
import time, json, sys, tempfile, os
t0 = time.perf_counter(); import rapp; t1 = time.perf_counter()
p = rapp.plan("default"); t2 = time.perf_counter()
d = tempfile.mkdtemp()
if sys.argv[1] == "raster":
    from PIL import Image; from rapp import raster; t3 = time.perf_counter()
    image = raster.render_plan(p, p.scenario); t4 = time.perf_counter()
    image.save(os.path.join(d, "f.png"), format="PNG", compress_level=1); t5 = time.perf_counter()
    names = ("import_pil_raster_s", "render_s", "save_png_s")
else:
    import matplotlib; matplotlib.use("Agg"); from rapp import plotting; t3 = time.perf_counter()
    fig = plotting.plot_plan(p, p.scenario); t4 = time.perf_counter()
    fig.savefig(os.path.join(d, "f.png"), dpi=100, pil_kwargs={"compress_level": 1})
    t5 = time.perf_counter()
    names = ("import_matplotlib_plotting_s", "figure_s", "save_png_s")
os.remove(os.path.join(d, "f.png")); os.rmdir(d)
assert "matplotlib" not in sys.modules or sys.argv[1] != "raster"
print(json.dumps({"import_rapp_s": t1 - t0, "plan_s": t2 - t1, names[0]: t3 - t2,
                  names[1]: t4 - t3, names[2]: t5 - t4}))
"""


def plot_parts(renderer: str, repeat: int = 3) -> dict:
    """Best time of each part of making the PNG in one process: "raster" or "matplotlib"."""
    runs = [json.loads(subprocess.run([sys.executable, "-c", _PARTS, renderer], check=True,
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
    out = Path(__file__).parent / "results" / "cli.json"
    result = json.loads(out.read_text()) if out.exists() else {}  # keep keys not written here
    png, svg = cli_times()
    result.update({
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "load_1min": os.getloadavg()[0],
                    "platform": platform.platform(), "python": platform.python_version()},
        "cli": png, "cli_matplotlib": svg,
        "plot_parts": plot_parts("raster"), "plot_parts_matplotlib": plot_parts("matplotlib"),
        "stages": stages()})
    print(json.dumps(result, indent=2))
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
