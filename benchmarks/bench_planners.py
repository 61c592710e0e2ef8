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
  mean Euclidean step. (The earlier wall-time recording, ``planners_ompl_kernel.json``, also
  ran OMPL with its range equal to the step, ``ompl_same_range``: it only made OMPL's steps
  shorter.)
* **The same budget rules.** RRT-Connect and PRM stop at their first path (OMPL's PRM does by
  itself: its path-length objective is met by any path), within 30 s. RRT* is anytime: both
  run the same number of iterations (OMPL's stopped by a condition on its iteration counter),
  rewiring within a radius (OMPL's k-nearest variant off: it gives the same trees here, since
  OMPL joins no edge longer than its range either way).
* **RRT*'s rewiring radius.** OMPL caps its radius ``gamma (log m / m)^(1/d)`` at its range, the
  steering step; rapp caps it at ``radius``, here twice the step (``RRT_STAR_RADIUS``): parents
  and rewired edges up to two steps long, for straighter paths from the same samples. The
  earlier wall-time recording (``planners_ompl_kernel.json``) keeps that honest with two more
  rows: rapp with the radius capped at the step like OMPL (``rapp_step_radius``), and OMPL with
  its range 1.5 x rapp's radius (``ompl_long_range``).
* **The same lengths.** Every path's length is measured in rapp's metric (Euclidean joint-space
  length of the unwrapped path), OMPL's raw path (no simplification) like rapp's; median and
  mean (lengths cluster by the way round the obstacles a path goes, so the median of one set of
  seeds can land in either cluster).
* **CPU time, not wall time.** Every run is timed with ``time.process_time`` (the CPU time of
  every thread of the process): on a shared machine a descheduled run is not slower, and OMPL's
  PRM, which grows its roadmap in one thread while another checks for a solution every
  millisecond, is charged the CPU both threads spend, not the wall time between them.
* **What OMPL pays that rapp does not: a Python callback.** OMPL 2's bindings (nanobind) take
  a state validity checker only as a Python callable or a Python subclass of
  ``StateValidityChecker``: no C function pointer, so a compiled checker cannot be handed over.
  Every one of OMPL's checks therefore crosses from C++ into Python and back. The benchmark
  counts OMPL's checker calls per run and measures the callback's cost per call: ``si.isValid``
  on real OMPL states with the Python callback, minus the same with OMPL's compiled
  ``AllValidStateValidityChecker`` (the C++ call itself), against the compiled kernel's cost
  per configuration inside one batched call (what a checker compiled into OMPL would cost). The
  *callback-corrected* time is OMPL's CPU time minus calls x (callback cost - compiled cost):
  OMPL as it would run with its checks as cheap as rapp's. Both ratios are recorded.

Seeds 0 to SEEDS - 1, rapp and OMPL in turn seed by seed (a change of load hits both alike);
the machine's load is recorded before and after. Ratios are OMPL's median CPU time over rapp's
(above 1: rapp faster). Every run must be solved (the success counts are recorded). Run from the
repository root, with OMPL installed (``pip install -r benchmarks/requirements.txt``)::

    PYTHONPATH=$PWD python benchmarks/bench_planners.py

Writes ``rapp/recorded/planners_cpu.json`` (another file name may be given). The earlier
wall-time recording ``planners_ompl_kernel.json`` (with the range and radius variants) is
kept as it was.
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
from rapp.kernels import collision as collision_backend
from rapp.paths import path_length, unwrap_path
from rapp.prm import prm
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import LINKS3, OBSTACLES3  # noqa: E402  the problem is defined once
from ompl_torus import path_of, state, torus_setup  # noqa: E402  OMPL's side

START, GOAL, STEP, TOLERANCE = (0.0, 0.0, 0.0), (-2.0, 0.5, 0.5), 0.1, 0.05
SEEDS = int(os.environ.get("RAPP_BENCH_SEEDS", 15))
#: OMPL's range per unit of rapp's step: the mean L1 / L2 norm of a random direction in 3-D.
RANGE_FACTOR = 1.5
RRT_STAR_STEP, RRT_STAR_ITERATIONS = 0.2, 5000
#: rapp's largest rewiring radius (rad): two steps.
RRT_STAR_RADIUS = 2 * RRT_STAR_STEP
TIME_LIMIT = 30.0
#: rapp's PRM first batch in the ``prm_small`` row, given explicitly: the median vertex count
#: of OMPL's roadmap at its first path on this problem (10, recorded as ``median_vertices``);
#: rapp's default since its PRM doubles its roadmap after the first batch.
PRM_SMALL_SAMPLES = 10
#: Only these rows are measured (RAPP_BENCH_PLANNERS=prm,prm_small); the others stay as
#: recorded.
ONLY = [x for x in os.environ.get("RAPP_BENCH_PLANNERS", "").split(",") if x]

RAPP = {
    "rrt_connect": lambda arm, obs, seed: rrt_connect(arm, START, GOAL, obs, step=STEP, seed=seed,
                                                      raise_on_failure=False),
    "prm": lambda arm, obs, seed: prm(arm, START, GOAL, obs, seed=seed, raise_on_failure=False),
    # rapp's PRM grows from a first batch of ``samples`` (10 by default), doubling, OMPL's one
    # sample at a time until it holds a path: this row gives rapp a first batch of the size of
    # the roadmap OMPL ends with here (``median_vertices``), explicitly; the default's now.
    "prm_small": lambda arm, obs, seed: prm(arm, START, GOAL, obs, seed=seed,
                                            samples=PRM_SMALL_SAMPLES, raise_on_failure=False),
    "rrt_star": lambda arm, obs, seed, radius=RRT_STAR_RADIUS: rrt_star(
        arm, START, GOAL, obs, step=RRT_STAR_STEP, radius=radius, seed=seed,
        max_iterations=RRT_STAR_ITERATIONS, raise_on_failure=False),
}


def run_rapp(name, arm, obstacles, seed, **options):
    t0 = time.process_time()
    res = RAPP[name](arm, obstacles, seed, **options)
    elapsed = time.process_time() - t0
    if not res.success:
        return elapsed, False, np.nan, False, 0
    certified = bool(rapp.path_collision_free(arm, res.path, obstacles))
    assert certified, f"rapp's {name} returned a path its certificate refuses (seed {seed})"
    return elapsed, True, path_length(res.path), certified, 0


def counted_validity(arm, obstacles):
    """``ompl_torus.kernel_validity``'s checker with a call counter (``valid.calls[0]``).

    The counter is one list-element increment inside the same Python function: the callback
    whose cost per call :func:`callback_cost` measures is this very one.
    """
    from rapp.arm import MAX_ANGLE

    kernel = collision_backend.kernels()
    packed, lengths, n = collision_backend.pack(list(obstacles)), arm.lengths, arm.n
    q = np.zeros((1, n))
    row = q[0]
    collides = kernel.collides
    calls = [0]

    def valid(state):
        calls[0] += 1
        for i in range(n):
            row[i] = state[i].value
        return not collides(lengths, q, *packed, MAX_ANGLE)[0][0]

    valid.calls = calls
    return valid


def run_ompl(name, arm, obstacles, seed, factor=RANGE_FACTOR, rrt_star_range=RRT_STAR_STEP):
    from ompl import base as ob, geometric as og

    valid = counted_validity(arm, obstacles)
    ss, space = torus_setup(arm, obstacles, seed, valid)
    ss.setStartAndGoalStates(state(space, START), state(space, GOAL), TOLERANCE)
    si = ss.getSpaceInformation()
    if name == "rrt_connect":
        planner = og.RRTConnect(si)
        planner.setRange(factor * STEP)
    elif name.startswith("prm"):
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
        t0 = time.process_time()
        solved = ss.solve(limit)
    else:
        t0 = time.process_time()
        solved = ss.solve(TIME_LIMIT)
    elapsed = time.process_time() - t0
    calls = valid.calls[0]
    data = ob.PlannerData(si)
    planner.getPlannerData(data)
    VERTICES.append(data.numVertices())
    if not (solved and ss.haveExactSolutionPath()):
        return elapsed, False, np.nan, False, calls
    path = unwrap_path(arm, path_of(ss, arm.n))
    return (elapsed, True, path_length(path), bool(rapp.path_collision_free(arm, path, obstacles)),
            calls)


#: The vertex count of OMPL's roadmap or tree at the end of each run (of the last planner).
VERTICES: list = []


def summary(runs):
    t = [r[0] for r in runs]
    lengths = [r[2] for r in runs if r[1]]
    calls = [r[4] for r in runs]
    return {"median_cpu_s": float(np.median(t)), "max_cpu_s": float(max(t)),
            "min_cpu_s": float(min(t)), "runs": len(runs),
            "solved": sum(r[1] for r in runs),
            "median_length": float(np.median(lengths)) if lengths else None,
            # Lengths cluster by the way round the obstacles a path goes: the mean moves less
            # than the median from one set of seeds to another.
            "mean_length": float(np.mean(lengths)) if lengths else None,
            "certified": sum(r[3] for r in runs),
            "median_checker_calls": float(np.median(calls))}


def corrected(runs, excess_us):
    """Median over runs of OMPL's CPU time with each checker call costed as a compiled one."""
    return float(np.median([r[0] - r[4] * excess_us * 1e-6 for r in runs]))


def callback_cost(arm, obstacles, k=1000, repeats=20, rounds=5):
    """The Python callback's cost per call as OMPL pays it, and the compiled check's.

    Returns ``(callback_us, compiled_us, single_us)``: ``si.isValid`` on ``k`` uniformly random
    OMPL states (``repeats`` times over: few enough to stay in cache, as a planner's recent
    states do) with the benchmark's Python callback minus the same with OMPL's compiled
    ``AllValidStateValidityChecker`` (the Python-to-C++ call both pay, removed); the compiled
    kernel's cost per configuration inside one batched call over the same configurations (what a
    checker compiled into OMPL would cost); and one call of the compiled kernel from Python.
    Best of ``rounds``, CPU time, the three interleaved.
    """
    from ompl import base as ob
    from rapp.arm import MAX_ANGLE

    rng = np.random.default_rng(0)
    qs = rng.uniform(-np.pi, np.pi, (k, arm.n))
    ss, space = torus_setup(arm, obstacles, 0, counted_validity(arm, obstacles))
    si = ss.getSpaceInformation()
    states = [state(space, q) for q in qs]
    python_checker = si.getStateValidityChecker()
    all_valid = ob.AllValidStateValidityChecker(si)
    kernel = collision_backend.kernels()
    packed, lengths = collision_backend.pack(list(obstacles)), arm.lengths
    one = qs[:1].copy()
    kernel.collides(lengths, qs, *packed, MAX_ANGLE)
    best = {"python": np.inf, "cpp": np.inf, "batch": np.inf, "single": np.inf}
    for _ in range(rounds):
        si.setStateValidityChecker(python_checker)
        t0 = time.process_time()
        for _ in range(repeats):
            for s in states:
                si.isValid(s)
        best["python"] = min(best["python"], time.process_time() - t0)
        si.setStateValidityChecker(all_valid)
        t0 = time.process_time()
        for _ in range(repeats):
            for s in states:
                si.isValid(s)
        best["cpp"] = min(best["cpp"], time.process_time() - t0)
        t0 = time.process_time()
        for _ in range(repeats):
            kernel.collides(lengths, qs, *packed, MAX_ANGLE)
        best["batch"] = min(best["batch"], time.process_time() - t0)
        t0 = time.process_time()
        for _ in range(k * repeats):
            kernel.collides(lengths, one, *packed, MAX_ANGLE)
        best["single"] = min(best["single"], time.process_time() - t0)
    si.setStateValidityChecker(python_checker)
    per = 1e6 / (k * repeats)
    return ((best["python"] - best["cpp"]) * per, best["batch"] * per, best["single"] * per)


def compare(arm, obstacles, excess_us):
    out = {}
    for name in ONLY or RAPP:
        run_rapp(name, arm, obstacles, 0)  # load the compiled loops (numba's disk cache)
        run_ompl(name, arm, obstacles, 0)
        runs = {"rapp": [], "ompl": []}
        VERTICES.clear()
        for seed in range(SEEDS):
            # Alternate who goes first, so neither side always runs on a warm or cold cache.
            order = ("rapp", "ompl") if seed % 2 == 0 else ("ompl", "rapp")
            for side in order:
                run = run_rapp if side == "rapp" else run_ompl
                runs[side].append(run(name, arm, obstacles, seed))
        out[name] = {side: summary(r) for side, r in runs.items()}
        out[name]["ompl"]["median_vertices"] = float(np.median(VERTICES))
        rapp_s = out[name]["rapp"]["median_cpu_s"]
        out[name]["ompl"]["median_cpu_s_callback_corrected"] = corrected(runs["ompl"], excess_us)
        out[name]["ratio_ompl_over_rapp_cpu"] = out[name]["ompl"]["median_cpu_s"] / rapp_s
        out[name]["ratio_ompl_corrected_over_rapp_cpu"] = (
            out[name]["ompl"]["median_cpu_s_callback_corrected"] / rapp_s)
        # Per seed, so that a skewed median cannot hide a spread.
        per_seed = [(o[0] - o[4] * excess_us * 1e-6) / r[0] for o, r in zip(runs["ompl"], runs["rapp"])]
        out[name]["corrected_ratio_per_seed_quartiles"] = [float(x) for x in
                                                           np.percentile(per_seed, [25, 50, 75])]
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
    callback_us, compiled_us, single_us = callback_cost(arm, obstacles)
    excess_us = callback_us - compiled_us
    planners = compare(arm, obstacles, excess_us)
    callback_after = callback_cost(arm, obstacles)
    result = {
        "date": date.today().isoformat(),
        "timing": "CPU time of the whole process (time.process_time, every thread), median over "
                  "seeds, rapp and OMPL alternated seed by seed in one process",
        "machine": {"cpus": os.cpu_count(), "load_1min": load_before[0],
                    "load_before": load_before, "load_after": os.getloadavg(),
                    "platform": platform.platform(), "python": platform.python_version()},
        "problem": {"links": LINKS3, "start": START, "goal": GOAL, "step": STEP,
                    "goal_tolerance": TOLERANCE, "seeds": SEEDS,
                    "ompl_range": RANGE_FACTOR * STEP, "rrt_star_step": RRT_STAR_STEP,
                    "ompl_rrt_star_range": RANGE_FACTOR * RRT_STAR_STEP,
                    "rrt_star_radius": RRT_STAR_RADIUS,
                    "rrt_star_iterations": RRT_STAR_ITERATIONS, "time_limit_s": TIME_LIMIT},
        "ompl_accepts_compiled_checker": False,
        "checker": {"callback_us": callback_us, "compiled_us": compiled_us,
                    "compiled_single_call_from_python_us": single_us,
                    "excess_us": excess_us,
                    "callback_us_after": callback_after[0], "compiled_us_after": callback_after[1]},
        "planners": planners,
    }
    print(f"load {load_before[0]:.1f} -> {result['machine']['load_after'][0]:.1f}; {SEEDS} seeds; "
          f"OMPL's Python callback {callback_us:.2f} us per call (after: {callback_after[0]:.2f}), "
          f"compiled check {compiled_us:.3f} us per configuration, one compiled call from Python "
          f"{single_us:.2f} us")
    print(f"{'planner':12s} {'side':5s} {'median CPU s':>12s} {'corrected':>10s} {'max s':>8s} "
          f"{'solved':>6s} {'calls':>8s} {'length':>7s} {'certified':>9s}")
    for name, sides in planners.items():
        for side in ("rapp", "ompl"):
            s = sides[side]
            corr = s.get("median_cpu_s_callback_corrected")
            print(f"{name:12s} {side:5s} {s['median_cpu_s']:12.4f} "
                  f"{'-' if corr is None else f'{corr:.4f}':>10s} {s['max_cpu_s']:8.3f} "
                  f"{s['solved']:3d}/{s['runs']:<2d} {s['median_checker_calls']:8.0f} "
                  f"{s['median_length'] or float('nan'):7.2f} {s['certified']:9d}")
        print(f"{name:12s} OMPL / rapp, median CPU time: {sides['ratio_ompl_over_rapp_cpu']:.2f}x "
              f"measured, {sides['ratio_ompl_corrected_over_rapp_cpu']:.2f}x callback-corrected")
    name = sys.argv[1] if len(sys.argv) > 1 else "planners_cpu.json"
    target = Path(__file__).resolve().parent.parent / "rapp" / "recorded" / name
    if ONLY and target.exists():  # the rows not measured keep their recording
        result["planners"] = {**json.loads(target.read_text())["planners"], **planners}
        result["rows_measured"] = {"date": result["date"], "planners": ONLY}
    target.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
