"""``python -m rapp compare`` with OMPL's planners added, where ``ompl`` is installed.

The command is rapp's (:mod:`rapp.compare_command`: scenarios, seeds, ``--workers``,
``--scheduler``, the resumable ``--out`` journal, ``--summary``); this script adds OMPL's
RRTConnect and RRT* (``benchmarks/requirements.txt``), with ``rapp.collides`` as their
validity checker and ``rapp.shortcut`` applied to their paths, so "after shortcutting" means the
same for all. It takes the same options::

    python benchmarks/compare_planners.py --random 4 --seeds 3 --out /tmp/small.jsonl

The recorded comparison the book reads (``rapp/recorded/planners.json``) is a ``--summary``
of such a run (``benchmarks/README.md`` gives the command).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

import rapp
from rapp import cli, compare_command
from rapp.compare import RRT_STAR_BUDGET, STEP, TIME_BUDGET, Record, Task, run_task as run_rapp_task
from rapp.ik import free_ik_solutions
from rapp.paths import path_length, shortcut, unwrap_path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ompl_torus import path_of, state, torus_setup  # noqa: E402  OMPL's side, shared

OMPL_PLANNERS = ("ompl_rrt_connect", "ompl_rrt_star")


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


def main(argv=None) -> int:
    """``python -m rapp compare`` (same options, exit codes and one-line errors), with
    :data:`OMPL_PLANNERS` where OMPL is installed."""
    extra = OMPL_PLANNERS if ompl_available() else ()
    cli.COMMANDS["compare"] = lambda args, out, err, caught: compare_command.run(
        args, out, err, say=lambda stream, text: print(cli.printable(text), file=stream),
        runner=run_task, extra=extra)
    return cli.main(["compare", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
