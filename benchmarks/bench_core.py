"""Side-by-side timing of rapp's C-space grid and A* against the naive baseline.

Run from the repository root:  python benchmarks/bench_core.py
Prints a table and writes benchmarks/results/core.json. Times are best-of-k
wall-clock seconds (time.perf_counter); ratios are baseline / rapp, measured in
the same run on the same machine.
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
import baseline  # noqa: E402

import rapp  # noqa: E402

HERE = Path(__file__).resolve().parent
LINKS = [1.0, 1.0]
CIRCLES = [(1.75, 0.75, 0.6), (0.55, 1.5, 0.5), (0.0, -1.0, 0.25)]
START_Q = (0.0, 0.0)           # arm along +x, below the first circle
GOAL_Q = (np.pi / 2, 0.0)      # arm straight up, between the circles: the way round is long
LINKS3 = [1.0, 0.8, 0.5]
OBSTACLES3 = [
    rapp.Circle((1.4, 0.9), 0.35),
    rapp.Circle((-0.4, 1.5), 0.3),
    rapp.Circle((0.2, -1.3), 0.3),
    rapp.Circle((1.0, -1.0), 0.3),
    rapp.Polygon.rectangle((-1.9, -0.6), 0.5, 1.0),
]
START3, GOAL3 = (0.0, 0.0, 0.0), (-2.0, 0.5, 0.5)


def best_of(k, fn):
    best, out = np.inf, None
    for _ in range(k):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run():
    rows, results = [], {}
    arm = rapp.Arm(LINKS)
    obstacles = [rapp.Circle((cx, cy), r) for cx, cy, r in CIRCLES]
    for M in (100, 360):
        grid = rapp.JointGrid(arm, M)
        t_fast, occ = best_of(7, lambda: rapp.occupancy(arm, obstacles, grid))
        t_naive, occ_naive = best_of(3 if M <= 100 else 1,
                                     lambda: baseline.naive_occupancy(LINKS, CIRCLES, M))
        diff = occ != occ_naive
        mismatch = int(diff.sum())
        # Cells where the two disagree must be ones where the arm just touches an obstacle.
        worst = float(np.abs(rapp.clearance(arm, rapp.grid_q(grid)[diff], obstacles)).max()
                      ) if mismatch else 0.0
        start, goal = tuple(grid.index(START_Q).tolist()), tuple(grid.index(GOAL_Q).tolist())
        t_astar, path = best_of(5, lambda: rapp.astar(occ, start, goal))
        t_greedy, gpath = best_of(3 if M <= 100 else 1,
                                  lambda: baseline.naive_greedy(occ_naive, start, goal))
        res = {
            "cells": M * M,
            "grid_rapp_s": t_fast, "grid_naive_s": t_naive, "grid_ratio": t_naive / t_fast,
            "grid_mismatched_cells": mismatch,
            "mismatched_max_abs_clearance": worst, "occupied_fraction": float(occ.mean()),
            "start": start, "goal": goal,
            "astar_s": t_astar, "astar_path_steps": len(path) - 1,
            "greedy_naive_s": t_greedy, "greedy_path_steps": len(gpath) - 1,
            "pipeline_rapp_s": t_fast + t_astar, "pipeline_naive_s": t_naive + t_greedy,
            "pipeline_ratio": (t_naive + t_greedy) / (t_fast + t_astar),
        }
        results[f"2link_M{M}"] = res
        rows += [
            (f"2-link grid M={M}", t_naive, t_fast),
            (f"2-link grid+search M={M}", t_naive + t_greedy, t_fast + t_astar),
        ]

    arm3 = rapp.Arm(LINKS3)
    grid3 = rapp.JointGrid(arm3, 64)
    t_g3, occ3 = best_of(7, lambda: rapp.occupancy(arm3, OBSTACLES3, grid3))
    s3, g3 = tuple(grid3.index(START3).tolist()), tuple(grid3.index(GOAL3).tolist())
    t_a3, path3 = best_of(3, lambda: rapp.astar(occ3, s3, g3))
    results["3link_M64"] = {
        "cells": 64**3, "grid_rapp_s": t_g3, "occupied_fraction": float(occ3.mean()),
        "start": s3, "goal": g3, "astar_s": t_a3, "astar_path_steps": len(path3) - 1,
        "manhattan_lower_bound": int(sum(min(abs(a - b), 64 - abs(a - b)) for a, b in zip(s3, g3))),
        "targets": {"grid_s_max": 0.1, "astar_s_max": 2.0},
    }
    rows += [("3-link grid 64^3", None, t_g3), ("3-link A* 64^3", None, t_a3)]
    results["2link_M360"]["targets"] = {"grid_ratio_min": 300, "pipeline_ratio_min": 40}

    info = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu_count": os.cpu_count(),
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "machine": platform.machine(), "platform": platform.platform(),
        "python": platform.python_version(), "numpy": np.__version__,
        "scenario": {"links": LINKS, "circles": CIRCLES, "start_q": START_Q, "goal_q": GOAL_Q,
                     "links3": LINKS3, "obstacles3": [repr(o) for o in OBSTACLES3],
                     "start3_q": START3, "goal3_q": GOAL3},
        "timing": "best-of-k time.perf_counter seconds; k=7 rapp grid, 5 A*, 1-3 naive",
    }
    out = {"machine": info, "results": results}
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "core.json").write_text(json.dumps(out, indent=2) + "\n")

    print(f"{'case':28s} {'naive [s]':>11s} {'rapp [s]':>11s} {'ratio':>9s}")
    for name, slow, fast in rows:
        s = f"{slow:11.4f}" if slow is not None else f"{'-':>11s}"
        r = f"{slow / fast:8.0f}x" if slow is not None else f"{'-':>9s}"
        print(f"{name:28s} {s} {fast:11.4f} {r}")
    for key, res in results.items():
        extra = {k: v for k, v in res.items() if "steps" in k or "mismatch" in k or "bound" in k}
        print(key, extra)
    print(f"cpu_count={info['cpu_count']} python={info['python']} numpy={info['numpy']}"
          f" load={info['load_average_1min']}")


if __name__ == "__main__":
    run()
