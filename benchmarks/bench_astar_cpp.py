"""rapp.astar (numba) against pyastar2d (A* in C++) on the 2-link grids, in one run.

The 2-link torus grids of ``bench_search.py`` (M = 360 and 720, the three discs of
``bench_core.py``). rapp searches the torus (every joint wraps, the toroidal Manhattan
heuristic); pyastar2d knows no wrap, so it is given the same grid unrolled: the occupancy
tiled 3 x 3 with the start in the middle tile and the goal's nearest copy as its goal, which
makes its shortest path the torus's (also timed on the plain grid without wrap, as the issue
measured it: a different problem whose path is longer). Both 4-connected, unit steps (pyastar2d's weights 1 on
free cells, inf on blocked ones); path lengths must be equal. Interleaved rounds, best of 7;
the machine's load is recorded. Writes ``rapp/recorded/astar_cpp.json``; without
pyastar2d only rapp is timed.

Run from the repository root: ``PYTHONPATH=$PWD python benchmarks/bench_astar_cpp.py``.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import CIRCLES, GOAL_Q, LINKS, START_Q  # noqa: E402  the problem, defined once

import rapp  # noqa: E402

HERE = Path(__file__).resolve().parent
ROUNDS = 7


def unrolled(occ, start, goal):
    """The torus as a 3 x 3 tiling for a planner without wrap: weights, start, goal."""
    M0, M1 = occ.shape
    w = np.where(np.tile(occ, (3, 3)), np.inf, 1.0).astype(np.float32)
    s = (start[0] + M0, start[1] + M1)
    g = tuple(min((goal[a] + k * m for k in range(3)), key=lambda x: abs(x - s[a]))
              for a, m in enumerate((M0, M1)))
    return w, s, g


def main() -> None:
    try:
        import pyastar2d
    except ImportError:
        pyastar2d = None
        print("pyastar2d is not installed (pip install -r benchmarks/requirements.txt): timing rapp only")
    arm = rapp.Arm(LINKS)
    obstacles = [rapp.Circle((cx, cy), r) for cx, cy, r in CIRCLES]
    load_before = os.getloadavg()
    out = {}
    for M in (360, 720):
        grid = rapp.JointGrid(arm, M)
        occ = rapp.occupancy(arm, obstacles, grid)
        s, g = tuple(grid.index(START_Q).tolist()), tuple(grid.index(GOAL_Q).tolist())
        rapp.astar(occ, s, g)  # load the compiled kernel
        fns = {"rapp": lambda: rapp.astar(occ, s, g)}
        if pyastar2d is not None:
            w, s3, g3 = unrolled(occ, s, g)
            fns["pyastar2d"] = lambda: pyastar2d.astar_path(w, s3, g3, allow_diagonal=False)
            # As the issue measured it: the plain grid, no wrap (a different, longer problem).
            w1 = np.where(occ, np.inf, 1.0).astype(np.float32)
            fns["pyastar2d_no_wrap"] = lambda: pyastar2d.astar_path(w1, s, g, allow_diagonal=False)
        best, paths = {k: np.inf for k in fns}, {}
        for _ in range(ROUNDS):
            for k, fn in fns.items():
                t0 = time.perf_counter()
                paths[k] = fn()
                best[k] = min(best[k], time.perf_counter() - t0)
        row = {"rapp_s": best["rapp"], "rapp_path_cells": len(paths["rapp"])}
        if pyastar2d is not None:
            assert len(paths["pyastar2d"]) == len(paths["rapp"]), "the path lengths differ"
            row.update(pyastar2d_s=best["pyastar2d"],
                       rapp_over_pyastar2d=best["rapp"] / best["pyastar2d"],
                       pyastar2d_no_wrap_s=best["pyastar2d_no_wrap"],
                       pyastar2d_no_wrap_path_cells=len(paths["pyastar2d_no_wrap"]),
                       rapp_over_pyastar2d_no_wrap=best["rapp"] / best["pyastar2d_no_wrap"])
        out[f"2link_M{M}"] = row
    result = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "load_before": load_before,
                    "load_after": os.getloadavg()},
        "rounds": ROUNDS,
        "grids": out,
    }
    print(json.dumps(result, indent=2))
    (HERE.parent / "rapp" / "recorded" / "astar_cpp.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
