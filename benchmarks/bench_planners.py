"""rapp's RRT-Connect, PRM and RRT* against OMPL's RRTConnect, PRM and RRTstar, in one run.

Problem (issue "More planners"): links 1.0, 0.8, 0.5; the four discs and the rectangle of
``bench_core.py``; start (0, 0, 0), goal (-2, 0.5, 0.5); goal tolerance 0.05 rad.

What each side gets, so that the comparison is fair:

* **The same checker.** OMPL plans on SO(2)^3 (every joint wraps, as in rapp) and its state
  validity checker is a thin callable around rapp's compiled collision kernel
  (``ompl_torus.kernel_validity``: the angles copied into an array, one kernel call). rapp's
  planners call the same kernel from their compiled loops. OMPL checks an edge with its default
  motion validator (states along it, 1 % of the space's extent apart: a sampling resolution);
  rapp certifies every edge (a proof). How many of OMPL's paths rapp's certificate proves free
  is recorded (``certified``).
* **A comparable step.** OMPL measures SO(2)^3 by the sum of the joint distances (L1), rapp by
  the Euclidean norm of the wrapped difference. A random direction's L1 norm is on average 1.5
  times its Euclidean norm in three dimensions, so OMPL's range is 1.5 x rapp's step: the same
  mean Euclidean step. The run with OMPL's range equal to the step is recorded beside it
  (``ompl_same_range``): it only makes OMPL's steps shorter.
* **The same budget rules.** RRT-Connect and PRM stop at their first path (OMPL's PRM does by
  itself: its path-length objective is met by any path), within 30 s. RRT* is anytime: both
  run the same number of iterations (OMPL's stopped by a condition on its iteration counter),
  rewiring within a radius (OMPL's k-nearest variant off: it gives the same trees here, since
  OMPL joins no edge longer than its range either way).
* **RRT*'s rewiring radius.** OMPL caps its radius ``gamma (log m / m)^(1/d)`` at its range, the
  steering step; rapp caps it at ``radius``, here twice the step (``RRT_STAR_RADIUS``): parents
  and rewired edges up to two steps long, for straighter paths from the same samples. Two more
  rows keep that honest: rapp with the radius capped at the step like OMPL
  (``rapp_step_radius``), and OMPL with its range 1.5 x rapp's radius (``ompl_long_range``: its
  edges as long as rapp's longest, its steps longer too).
* **The same lengths.** Every path's length is measured in rapp's metric (Euclidean joint-space
  length of the unwrapped path), OMPL's raw path (no simplification) like rapp's; median and
  mean (lengths cluster by the way round the obstacles a path goes, so the median of one set of
  seeds can land in either cluster).

Seeds 0 to 29, rapp and OMPL in turn seed by seed (a change of load hits both alike); the
machine's load is recorded before and after. Ratios are OMPL's median time over rapp's (above
1: rapp faster). Run from the repository root, with OMPL installed
(``pip install -r benchmarks/requirements.txt``)::

    PYTHONPATH=$PWD python benchmarks/bench_planners.py

Writes ``rapp/recorded/planners_ompl_kernel.json`` (another file name may be given).
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
from rapp._kernels import collision as collision_backend
from rapp.paths import path_length, unwrap_path
from rapp.prm import prm
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import LINKS3, OBSTACLES3  # noqa: E402  the problem is defined once
from ompl_torus import kernel_validity, path_of, state, torus_setup  # noqa: E402  OMPL's side

START, GOAL, STEP, TOLERANCE, SEEDS = (0.0, 0.0, 0.0), (-2.0, 0.5, 0.5), 0.1, 0.05, 30
#: OMPL's range per unit of rapp's step: the mean L1 / L2 norm of a random direction in 3-D.
RANGE_FACTOR = 1.5
RRT_STAR_STEP, RRT_STAR_ITERATIONS = 0.2, 5000
#: rapp's largest rewiring radius (rad): two steps.
RRT_STAR_RADIUS = 2 * RRT_STAR_STEP
TIME_LIMIT = 30.0

RAPP = {
    "rrt_connect": lambda arm, obs, seed: rrt_connect(arm, START, GOAL, obs, step=STEP, seed=seed,
                                                      raise_on_failure=False),
    "prm": lambda arm, obs, seed: prm(arm, START, GOAL, obs, seed=seed, raise_on_failure=False),
    "rrt_star": lambda arm, obs, seed, radius=RRT_STAR_RADIUS: rrt_star(
        arm, START, GOAL, obs, step=RRT_STAR_STEP, radius=radius, seed=seed,
        max_iterations=RRT_STAR_ITERATIONS, raise_on_failure=False),
}


def run_rapp(name, arm, obstacles, seed, **options):
    t0 = time.perf_counter()
    res = RAPP[name](arm, obstacles, seed, **options)
    elapsed = time.perf_counter() - t0
    if not res.success:
        return elapsed, False, np.nan, False
    certified = bool(rapp.path_collision_free(arm, res.path, obstacles))
    assert certified, f"rapp's {name} returned a path its certificate refuses (seed {seed})"
    return elapsed, True, path_length(res.path), certified


def run_ompl(name, arm, obstacles, seed, factor=RANGE_FACTOR, rrt_star_range=RRT_STAR_STEP):
    from ompl import base as ob, geometric as og

    ss, space = torus_setup(arm, obstacles, seed, kernel_validity(arm, obstacles))
    ss.setStartAndGoalStates(state(space, START), state(space, GOAL), TOLERANCE)
    si = ss.getSpaceInformation()
    if name == "rrt_connect":
        planner = og.RRTConnect(si)
        planner.setRange(factor * STEP)
    elif name == "prm":
        planner = og.PRM(si)
    else:
        planner = og.RRTstar(si)
        planner.setRange(factor * rrt_star_range)
        planner.setKNearest(False)
    ss.setPlanner(planner)
    ss.setup()
    if name == "rrt_star":
        done = ob.PlannerTerminationCondition(
            lambda: planner.numIterations() >= RRT_STAR_ITERATIONS)
        limit = ob.plannerOrTerminationCondition(done, ob.timedPlannerTerminationCondition(TIME_LIMIT))
        t0 = time.perf_counter()
        solved = ss.solve(limit)
    else:
        t0 = time.perf_counter()
        solved = ss.solve(TIME_LIMIT)
    elapsed = time.perf_counter() - t0
    if not (solved and ss.haveExactSolutionPath()):
        return elapsed, False, np.nan, False
    path = unwrap_path(arm, path_of(ss, arm.n))
    return elapsed, True, path_length(path), bool(rapp.path_collision_free(arm, path, obstacles))


def summary(runs):
    t = [r[0] for r in runs]
    lengths = [r[2] for r in runs if r[1]]
    return {"median_s": float(np.median(t)), "max_s": float(max(t)),
            "solved": sum(r[1] for r in runs),
            "median_length": float(np.median(lengths)) if lengths else None,
            # Lengths cluster by the way round the obstacles a path goes: the mean moves less
            # than the median from one set of seeds to another.
            "mean_length": float(np.mean(lengths)) if lengths else None,
            "certified": sum(r[3] for r in runs)}


#: The rows of each planner (those it runs), in the order the table prints them.
SIDES = ("rapp", "ompl", "ompl_same_range", "rapp_step_radius", "ompl_long_range")


def compare(arm, obstacles):
    out = {}
    for name in RAPP:
        run_rapp(name, arm, obstacles, 0)  # load the compiled loops (numba's disk cache)
        run_ompl(name, arm, obstacles, 0)
        runs = {side: [] for side in SIDES}
        for seed in range(SEEDS):
            runs["rapp"].append(run_rapp(name, arm, obstacles, seed))
            runs["ompl"].append(run_ompl(name, arm, obstacles, seed))
            if name != "prm":  # PRM has no range
                runs["ompl_same_range"].append(run_ompl(name, arm, obstacles, seed, 1.0))
            if name == "rrt_star":
                runs["rapp_step_radius"].append(run_rapp(name, arm, obstacles, seed,
                                                         radius=RRT_STAR_STEP))
                runs["ompl_long_range"].append(run_ompl(name, arm, obstacles, seed,
                                                        rrt_star_range=RRT_STAR_RADIUS))
        out[name] = {side: summary(r) for side, r in runs.items() if r}
        out[name]["ratio_ompl_over_rapp"] = out[name]["ompl"]["median_s"] / out[name]["rapp"]["median_s"]
    return out


def main() -> None:
    try:
        import ompl  # noqa: F401
    except ImportError:
        sys.exit("OMPL is not installed: pip install -r benchmarks/requirements.txt")
    if collision_backend.kernels() is None:
        sys.exit("numba is not installed: OMPL would have no compiled checker")
    arm, obstacles = rapp.Arm(LINKS3), list(OBSTACLES3)
    load_before = os.getloadavg()
    q = np.zeros(arm.n)
    rapp.collides(arm, q, obstacles)
    k = 2000
    t0 = time.perf_counter()
    for _ in range(k):
        rapp.collides(arm, q, obstacles)
    collides_us = (time.perf_counter() - t0) / k * 1e6
    valid = kernel_validity(arm, obstacles)
    fake = [type("S", (), {"value": 0.0})() for _ in range(arm.n)]  # an OMPL state's interface
    t0 = time.perf_counter()
    for _ in range(k):
        valid(fake)
    validity_us = (time.perf_counter() - t0) / k * 1e6
    planners = compare(arm, obstacles)
    rc = planners["rrt_connect"]
    result = {
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "load_1min": load_before[0],
                    "load_before": load_before, "load_after": os.getloadavg(),
                    "platform": platform.platform(), "python": platform.python_version()},
        "problem": {"links": LINKS3, "start": START, "goal": GOAL, "step": STEP,
                    "goal_tolerance": TOLERANCE, "seeds": SEEDS,
                    "ompl_range": RANGE_FACTOR * STEP, "rrt_star_step": RRT_STAR_STEP,
                    "ompl_rrt_star_range": RANGE_FACTOR * RRT_STAR_STEP,
                    "rrt_star_radius": RRT_STAR_RADIUS,
                    "ompl_long_range": RANGE_FACTOR * RRT_STAR_RADIUS,
                    "rrt_star_iterations": RRT_STAR_ITERATIONS, "time_limit_s": TIME_LIMIT},
        "collides_single_us": collides_us,
        "ompl_validity_call_us": validity_us,
        # The keys of the first recording: RRT-Connect alone.
        "rapp_rrt_connect": rc["rapp"],
        "ompl_rrt_connect": rc["ompl"],
        "median_ratio_ompl_over_rapp": rc["ratio_ompl_over_rapp"],
        "planners": planners,
    }
    print(f"load {load_before[0]:.1f} -> {result['machine']['load_after'][0]:.1f}; "
          f"OMPL's checker {validity_us:.1f} us per call; {SEEDS} seeds")
    print(f"{'planner':12s} {'side':16s} {'median s':>9s} {'max s':>8s} {'solved':>6s} "
          f"{'length':>7s} {'mean':>6s} {'certified':>9s}")
    for name, sides in planners.items():
        for side in SIDES:
            if side in sides:
                s = sides[side]
                length, mean = ("-", "-") if s["median_length"] is None else (
                    f"{s['median_length']:.2f}", f"{s['mean_length']:.2f}")
                print(f"{name:12s} {side:16s} {s['median_s']:9.4f} {s['max_s']:8.3f} "
                      f"{s['solved']:6d} {length:>7s} {mean:>6s} {s['certified']:9d}")
        print(f"{name:12s} OMPL / rapp, median time: {sides['ratio_ompl_over_rapp']:.2f}x")
    name = sys.argv[1] if len(sys.argv) > 1 else "planners_ompl_kernel.json"
    (Path(__file__).resolve().parent.parent / "rapp" / "recorded" / name).write_text(
        json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
