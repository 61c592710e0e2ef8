"""Side-by-side timing of rapp's C-space grid and A* against the naive baseline.

The 3-link grids (64^3 and 128^3) are also timed against the previous rapp grid
(``rapp.reference.occupancy``: every link against every obstacle on
every cell) and both are checked cell by cell against ``rapp.collides``.

Run from the repository root:  python benchmarks/bench_core.py
Prints a table and writes rapp/recorded/core.json. Times are best-of-k
wall-clock seconds (time.perf_counter); ratios are baseline / rapp, measured in
the same run on the same machine.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import time
import tracemalloc
from pathlib import Path

import numpy as np

import rapp
from rapp import baseline
from rapp.reference import occupancy as _occupancy_reference  # (the previous rapp grid)

HERE = Path(__file__).resolve().parent
# The problem, defined once for the benchmarks and the tests (run from the repository root).
from tests.scenes import CIRCLES, GOAL3, GOAL_Q, LINKS, LINKS3, OBSTACLES3, START3, START_Q  # noqa: E402,F401


def best_of(k, fn):
    best, out = np.inf, None
    for _ in range(k):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def side_by_side(k, fns):
    """Best-of-k seconds of several functions, run alternately so that load hits them alike."""
    best, outs = [np.inf] * len(fns), [None] * len(fns)
    for _ in range(k):
        for j, fn in enumerate(fns):
            t0 = time.perf_counter()
            outs[j] = fn()
            best[j] = min(best[j], time.perf_counter() - t0)
    return best, outs


def peak_bytes(fn):
    """Peak memory traced while ``fn`` runs (numpy reports its buffers to tracemalloc)."""
    tracemalloc.start()
    tracemalloc.reset_peak()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def grid_vs_previous(arm, obstacles, M, k):
    """The interval-painting occupancy against the previous rapp grid, side by side."""
    grid = rapp.JointGrid(arm, M)
    (t_new, t_old), (occ, occ_old) = side_by_side(
        k, [lambda: rapp.occupancy(arm, obstacles, grid),
            lambda: _occupancy_reference(arm, obstacles, grid)])
    diff = occ != occ_old
    # Both against the exact per-configuration test, one slice of axis 0 at a time (memory).
    exact_diff, worst = 0, 0.0
    axes = grid.axes
    rest = np.stack(np.meshgrid(*axes[1:], indexing="ij"), axis=-1)
    for i0, a0 in enumerate(axes[0]):
        q = np.concatenate([np.full(rest.shape[:-1] + (1,), a0), rest], axis=-1)
        d = occ[i0] != rapp.collides(arm, q, obstacles)
        exact_diff += int(d.sum())
        bad = diff[i0] | d
        if bad.any():
            worst = max(worst, float(np.abs(rapp.clearance(arm, q[bad], obstacles)).max()))
    cells = occ.size
    return grid, occ, {
        "cells": cells, "grid_rapp_s": t_new, "grid_previous_rapp_s": t_old,
        "grid_ratio_previous_over_rapp": t_old / t_new,
        "mismatched_cells_vs_previous": int(diff.sum()),
        "mismatched_cells_vs_collides": exact_diff,
        "mismatched_max_abs_clearance": worst,
        "occupied_fraction": float(occ.mean()),
        "peak_bytes_per_cell_rapp": peak_bytes(lambda: rapp.occupancy(arm, obstacles, grid)) / cells,
        "peak_bytes_per_cell_previous": peak_bytes(
            lambda: _occupancy_reference(arm, obstacles, grid)) / cells,
    }


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
    for M3, k3 in ((64, 7), (128, 5)):
        grid3, occ3, res3 = grid_vs_previous(arm3, OBSTACLES3, M3, k3)
        s3, g3 = tuple(grid3.index(START3).tolist()), tuple(grid3.index(GOAL3).tolist())
        t_a3, path3 = best_of(3, lambda: rapp.astar(occ3, s3, g3))
        res3.update({
            "start": s3, "goal": g3, "astar_s": t_a3, "astar_path_steps": len(path3) - 1,
            "manhattan_lower_bound": int(sum(min(abs(a - b), M3 - abs(a - b))
                                             for a, b in zip(s3, g3))),
        })
        results[f"3link_M{M3}"] = res3
        rows += [(f"3-link grid {M3}^3 (previous)", res3["grid_previous_rapp_s"],
                  res3["grid_rapp_s"]),
                 (f"3-link A* {M3}^3", None, t_a3)]
    results["3link_M64"]["targets"] = {"grid_s_max": 0.1, "astar_s_max": 2.0}
    results["3link_M128"]["targets"] = {"grid_ratio_previous_over_rapp_min": 4}
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
        "timing": "best-of-k time.perf_counter seconds; k=7 rapp grid, 5 A*, 1-3 naive; "
                  "3-link grids: rapp and the previous rapp grid alternately, k=7 (64^3), 5 (128^3)",
        "memory": "peak_bytes_per_cell_*: tracemalloc peak during one occupancy call / cells",
    }
    out = {"machine": info, "results": results}
    (HERE.parent / "rapp" / "recorded" / "core.json").write_text(json.dumps(out, indent=2) + "\n")

    print(f"{'case':30s} {'baseline [s]':>12s} {'rapp [s]':>11s} {'ratio':>9s}")
    for name, slow, fast in rows:
        s = f"{slow:12.4f}" if slow is not None else f"{'-':>12s}"
        r = f"{slow / fast:8.1f}x" if slow is not None else f"{'-':>9s}"
        print(f"{name:30s} {s} {fast:11.4f} {r}")
    for key, res in results.items():
        extra = {k: v for k, v in res.items()
                 if "steps" in k or "mismatch" in k or "bound" in k or "per_cell" in k}
        print(key, extra)
    print(f"cpu_count={info['cpu_count']} python={info['python']} numpy={info['numpy']}"
          f" load={info['load_average_1min']}")


if __name__ == "__main__":
    run()
