"""rapp.rrt_connect against OMPL's RRTConnect on the 3-link benchmark problem, in one run.

Problem (issue "More planners"): links 1.0, 0.8, 0.5; the four discs and the rectangle of
``bench_core.py``; start (0, 0, 0), goal (-2, 0.5, 0.5); step (OMPL's range) 0.1 rad; goal
tolerance 0.05 rad. OMPL plans on SO(2)^3 (every joint wraps, as in rapp) with ``rapp.collides``
as its state validity checker and its default motion validator (states along each edge at its
default resolution). rapp certifies every edge (``rapp.segment_collision_free``): a proof, where
OMPL's check is a sampling resolution. Both: 20 seeds, time to a solution, median and max.

Run from the repository root, with OMPL installed (``pip install -r benchmarks/requirements.txt``):
``python benchmarks/bench_planners.py``. Writes ``rapp/recorded/planners_ompl.json``.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np

import rapp
from rapp import collision_kernel
from rapp.rrt_connect import rrt_connect

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import LINKS3, OBSTACLES3  # noqa: E402  the problem is defined once
from ompl_torus import state, torus_setup  # noqa: E402  OMPL's side, shared with compare_planners

START, GOAL, STEP, TOLERANCE, SEEDS = (0.0, 0.0, 0.0), (-2.0, 0.5, 0.5), 0.1, 0.05, 20


def problem():
    arm = rapp.Arm(LINKS3)
    return arm, list(OBSTACLES3)


def time_rapp(arm, obstacles):
    times, ok = [], 0
    for seed in range(SEEDS):
        t0 = time.perf_counter()
        res = rrt_connect(arm, START, GOAL, obstacles, step=STEP, seed=seed,
                          raise_on_failure=False)
        times.append(time.perf_counter() - t0)
        if res.success:
            ok += 1
            assert rapp.path_collision_free(arm, res.path, obstacles)
    return times, ok


def time_ompl(arm, obstacles):
    from ompl import geometric as og

    times, ok = [], 0
    for seed in range(SEEDS):
        ss, space = torus_setup(arm, obstacles, seed)
        start, goal = state(space, START), state(space, GOAL)
        ss.setStartAndGoalStates(start, goal, TOLERANCE)
        planner = og.RRTConnect(ss.getSpaceInformation())
        planner.setRange(STEP)
        ss.setPlanner(planner)
        ss.setup()
        t0 = time.perf_counter()
        solved = ss.solve(30.0)
        times.append(time.perf_counter() - t0)
        ok += bool(solved) and ss.haveExactSolutionPath()
    return times, ok


def main() -> None:
    arm, obstacles = problem()
    q = np.zeros(arm.n)
    collision_kernel.kernels()  # OMPL's checker is rapp.collides, compiled: load it first
    rapp.collides(arm, q, obstacles)
    k = 2000
    t0 = time.perf_counter()
    for _ in range(k):
        rapp.collides(arm, q, obstacles)
    collides_us = (time.perf_counter() - t0) / k * 1e6
    r_times, r_ok = time_rapp(arm, obstacles)
    try:
        o_times, o_ok = time_ompl(arm, obstacles)
    except ImportError:
        sys.exit("OMPL is not installed: pip install -r benchmarks/requirements.txt")
    result = {
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "load_1min": os.getloadavg()[0],
                    "platform": platform.platform(), "python": platform.python_version()},
        "problem": {"links": LINKS3, "start": START, "goal": GOAL, "step": STEP,
                    "goal_tolerance": TOLERANCE, "seeds": SEEDS},
        "collides_single_us": collides_us,
        "rapp_rrt_connect": {"median_s": float(np.median(r_times)), "max_s": float(max(r_times)),
                             "solved": r_ok},
        "ompl_rrt_connect": {"median_s": float(np.median(o_times)), "max_s": float(max(o_times)),
                             "solved": o_ok},
    }
    result["median_ratio_ompl_over_rapp"] = (result["ompl_rrt_connect"]["median_s"]
                                             / result["rapp_rrt_connect"]["median_s"])
    print(json.dumps(result, indent=2))
    # An optional file name: planners_ompl_kernel.json holds the run with the compiled checker
    # until chapter 10 reads it (the chapter checks that its recordings share one day).
    name = sys.argv[1] if len(sys.argv) > 1 else "planners_ompl.json"
    (Path(__file__).resolve().parent.parent / "rapp" / "recorded" / name).write_text(
        json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
