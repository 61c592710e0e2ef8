"""Command line of the planner comparison (:mod:`rapp.compare`), with OMPL's planners where installed.

The harness itself, its scenarios and its statistics are :mod:`rapp.compare`; this script adds
OMPL's RRTConnect and RRT* (``benchmarks/requirements.txt``), with ``rapp.collides`` as their
validity checker and ``rapp.shortcut`` applied to their paths, so "after shortcutting" means the
same for all, and writes the result.

Usage, from the repository root::

    python benchmarks/compare_planners.py                   # 30 scenarios x 20 seeds, all cores
    python benchmarks/compare_planners.py --scenarios 4 --seeds 3 --out /tmp/small.json

Writes ``rapp/recorded/planners.json`` (package data, which chapter 14 reads through
:func:`rapp.compare.recorded_results`): one record per run, and per planner (overall and per
scenario class) the success rate with its Wilson 95 % interval, and the mean time to a solution
and path lengths with Student-t 95 % intervals over the successful runs.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import rapp
from rapp.compare import (RRT_STAR_BUDGET, STEP, TIME_BUDGET, Record, Task, run,
                          run_task as run_rapp_task)
from rapp.ik import free_ik_solutions
from rapp.paths import path_length, shortcut, unwrap_path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ompl_torus import path_of, state, torus_setup  # noqa: E402  OMPL's side, shared

OMPL_PLANNERS = ("ompl_rrt_connect", "ompl_rrt_star")
RECORDED = Path(__file__).resolve().parent.parent / "rapp" / "recorded" / "planners.json"


def ompl_available() -> bool:
    try:
        import ompl  # noqa: F401
    except ImportError:
        return False
    return True


def run_task(task: Task) -> Record:
    """One run: OMPL's planners here, rapp's through :func:`rapp.compare.run_task`."""
    if task.planner.startswith("ompl_"):
        return _run_ompl(task)
    return run_rapp_task(task)


def _run_ompl(task: Task) -> Record:
    from ompl import base as ob, geometric as og

    scenario = rapp.load_scenario(task.scenario)
    arm, obstacles = scenario.arm, scenario.obstacles
    if scenario.goal_q is not None:
        goals = np.array([scenario.goal_q], float)
    else:
        goals, _ = free_ik_solutions(arm, scenario.goal_xy, obstacles, q0=scenario.start_array)
    ss, space = torus_setup(arm, obstacles, task.seed)
    start = state(space, scenario.start_array)
    goal_states = ob.GoalStates(ss.getSpaceInformation())
    for g in goals:
        goal_states.addState(state(space, g))
    ss.addStartState(start)
    ss.setGoal(goal_states)
    planner = (og.RRTConnect if task.planner == "ompl_rrt_connect" else og.RRTstar)(ss.getSpaceInformation())
    planner.setRange(STEP)
    ss.setPlanner(planner)
    ss.setup()
    t0 = time.perf_counter()
    # OMPL's RRT* stops at its first solution unless told an optimization objective to meet.
    solved = ss.solve(RRT_STAR_BUDGET if task.planner == "ompl_rrt_star" else TIME_BUDGET)
    elapsed = time.perf_counter() - t0
    if not (solved and ss.haveExactSolutionPath()):
        return Record(task.scenario_index, task.planner, task.seed, False, "NoPathFound",
                      math.nan, elapsed, math.nan, math.nan)
    path = unwrap_path(arm, path_of(ss, arm.n))
    short = shortcut(arm, path, obstacles)
    return Record(task.scenario_index, task.planner, task.seed, True, "", elapsed, elapsed,
                  path_length(path), path_length(short))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", type=int, default=30)
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--planners", nargs="*", default=None, help="name prefixes, e.g. astar rrt_connect")
    ap.add_argument("--out", type=Path, default=RECORDED)
    args = ap.parse_args(argv)
    extra = OMPL_PLANNERS if ompl_available() else ()
    result = run(args.scenarios, args.seeds, planners=args.planners, runner=run_task, extra=extra)
    result["machine"]["ompl"] = ompl_available()
    tmp = args.out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(result, indent=1, allow_nan=True) + "\n")
    os.replace(tmp, args.out)  # atomic: a half-written file never replaces the last results
    for planner, by_class in result["summary"].items():
        a = by_class["all"]
        lo, hi = a["success_interval"]
        print(f"{planner:18s} success {a['success_rate']:6.1%} [{lo:.2f}, {hi:.2f}]  "
              f"time {a['time_s']['median']:.3f} s  length {a['length_rad']['mean']:.2f} -> "
              f"{a['shortcut_length_rad']['mean']:.2f} rad", file=sys.stderr)


if __name__ == "__main__":
    main()
