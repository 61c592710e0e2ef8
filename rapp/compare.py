"""Every planner on the same seeded random scenarios: success, time, path length, with 95 % intervals.

The harness builds ``count`` random scenarios (2-4 links; discs and rectangles; joint and
Cartesian goals; every fourth one a wall with a narrow door between start and goal), then runs
each planner on each of them, ``seeds`` times for the sampling planners (A* is deterministic:
once). Every run goes through :func:`rapp.plan` (IK, search, shortcutting, timing, verification),
so a success is a verified trajectory.

It runs on any :class:`concurrent.futures.Executor`: by default a process pool over every local
core; on a cluster, pass a Dask distributed client's executor unchanged::

    from dask.distributed import Client
    summary = run(executor=Client("scheduler:8786").get_executor())

``python -m rapp compare`` is its command line (:mod:`rapp.compare_command`: resumable,
parallel, with progress); ``benchmarks/compare_planners.py`` is the same command with OMPL's
planners added. The recorded run, 30 scenarios x 2 seeds with OMPL's planners, ships with the
package: :func:`recorded_results` reads it (chapter 14 does), wherever rapp is installed.

Examples
--------
>>> [round(v, 3) for v in wilson(20, 20)]
[0.839, 1.0]
>>> results = recorded_results()
>>> results["settings"]["scenarios"], len(results["records"])
(30, 990)
>>> scenario_class(results["scenarios"][3])
'2 links, narrow'
"""

from __future__ import annotations

import math
import os
import platform
import time
import signal
from concurrent.futures import Executor, as_completed
from dataclasses import asdict, dataclass
from datetime import date

import numpy as np

from rapp import planners as planner_table
from rapp.arm import Arm, wrap_angle
from rapp.collision import collides
from rapp.errors import NoIKSolution, NoPathFound, RappError
from rapp.obstacles import Circle, Polygon
from rapp.planner import plan as plan_scenario
from rapp.sampling import prepare_kernels
from rapp.scenario import load_scenario
from rapp.student_t import t_quantile

__all__ = ["make_scenarios", "scenario_class", "Task", "Record", "planners_for", "settings_for", "run_task",
           "wilson", "mean_interval", "summarize", "tasks", "run", "recorded_results", "task_key",
           "warm", "start_worker", "run_tasks", "settings_record", "result",
           "RESULTS_FILE", "ASTAR_CELLS", "SAMPLING", "TIME_BUDGET", "RRT_STAR_BUDGET", "STEP",
           "FAMILY_NAMES", "RunGroups", "Separations", "intervals_apart", "family_of", "group_runs"]

#: The recorded comparison: package data, ``rapp/recorded/planners.json`` (:func:`rapp.recorded.load`).
RESULTS_FILE = "recorded/planners.json"

#: Grid resolutions (cells per joint) by number of joints: coarse, medium, fine; every grid
#: planner of the table (:data:`rapp.planners.PLANNERS`) runs at each, as ``astar_24`` etc.
ASTAR_CELLS = {2: (24, 48, 96), 3: (16, 32, 48), 4: (8, 14, 20)}
#: The planners of the table that do not plan on a grid, in table order.
SAMPLING = tuple(name for name, p in planner_table.PLANNERS.items() if not p.grid)
#: Seconds a sampling planner may spend on one run before it counts as a failure.
TIME_BUDGET = 5.0
#: An anytime planner (RRT*, rapp's and OMPL's: :attr:`rapp.planners.Planner.anytime`) keeps
#: improving its path until this budget is spent: its "time to a solution" is this budget, and
#: its length is the length it reached by then.
RRT_STAR_BUDGET = 1.0
STEP = 0.1


# --- scenarios -------------------------------------------------------------------------------

def _free_configurations(arm, obstacles, rng, tries: int = 4000) -> np.ndarray:
    q = rng.uniform(-np.pi, np.pi, size=(tries, arm.n))
    return q[~collides(arm, q, obstacles)]


def _obstacles(rng, reach: float, narrow: bool) -> list[dict]:
    """Discs and axis-aligned rectangles in the annulus the arm sweeps; or a wall with a door."""
    obs: list[dict] = []
    if narrow:
        # A wall across the +x half plane at 55 % of the reach, with a door of 0.12-0.2 m.
        x = 0.55 * reach
        door, centre = rng.uniform(0.12, 0.2), rng.uniform(-0.3, 0.3) * reach
        obs.append({"type": "polygon", "vertices": _rect(x, x + 0.1, centre + door / 2, 1.2 * reach)})
        obs.append({"type": "polygon", "vertices": _rect(x, x + 0.1, -1.2 * reach, centre - door / 2)})
    for _ in range(int(rng.integers(2, 5))):
        r = rng.uniform(0.45, 0.95) * reach
        a = rng.uniform(-np.pi, np.pi)
        cx, cy = r * np.cos(a), r * np.sin(a)
        if narrow and cx > 0.3 * reach:
            continue  # keep the door side clear, so the door is the question
        if rng.random() < 0.6:
            obs.append({"type": "circle", "center": [round(cx, 3), round(cy, 3)],
                        "radius": round(float(rng.uniform(0.08, 0.2) * reach), 3)})
        else:
            w, h = rng.uniform(0.1, 0.3, 2) * reach
            obs.append({"type": "polygon", "vertices": _rect(cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2)})
    return obs


def _rect(x0, x1, y0, y1) -> list:
    return [[round(float(x), 3), round(float(y), 3)] for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]


def make_scenarios(count: int = 30, seed: int = 2026) -> list[dict]:
    """``count`` random, valid scenario dicts (start and goal free), reproducible from ``seed``.

    Scenario ``k`` has ``2 + k % 3`` links; every other one has a Cartesian goal; every fourth
    is "narrow" (a wall with a door between start and goal, on opposite sides of it).
    """
    rng = np.random.default_rng(seed)
    scenarios: list[dict] = []
    while len(scenarios) < count:
        k = len(scenarios)
        n, narrow, cartesian = 2 + k % 3, k % 4 == 3, k % 2 == 1
        lengths = np.round(rng.uniform(0.4, 1.0, n), 2)
        reach = float(lengths.sum())
        obstacles = _obstacles(rng, reach, narrow)
        arm = Arm(lengths)
        parsed = [Circle(o["center"], o["radius"]) if o["type"] == "circle"
                  else Polygon(o["vertices"]) for o in obstacles]
        free = _free_configurations(arm, parsed, rng)
        x = arm.end_effector(free)[:, 0]
        # Narrow: the start's tip left of the wall, the goal's tip beyond it, so the door matters.
        starts = free[x < 0.3 * reach] if narrow else free
        goals = free[x > 0.65 * reach] if narrow else free
        if len(starts) == 0 or len(goals) == 0:
            continue
        start, goal = starts[0], goals[-1]
        if np.linalg.norm(wrap_angle(goal - start)) < 1.0:
            continue  # a trivial problem says nothing about a planner
        scenarios.append(_scenario_dict(k, lengths, obstacles, start, goal, cartesian, "astar", {}))
    return scenarios


def _scenario_dict(k, lengths, obstacles, start, goal, cartesian, algorithm, settings) -> dict:
    arm = Arm(lengths)
    goal_entry = ({"position": [float(v) for v in np.round(arm.end_effector(goal), 4)]} if cartesian
                  else {"joints": [float(v) for v in np.round(goal, 4)]})
    n = len(lengths)
    return {
        "name": f"random-{k:02d}",
        "description": f"{n} links, {'narrow door' if k % 4 == 3 else 'open'}, "
                       f"{'Cartesian' if cartesian else 'joint'} goal",
        "arm": {"link_lengths": [float(v) for v in lengths]},
        "obstacles": obstacles,
        "start": [float(v) for v in np.round(start, 4)],
        "goal": goal_entry,
        "units": {"angle": "rad", "length": "m"},
        "planner": {"algorithm": algorithm, **settings},
        "trajectory": {"duration": 5.0, "profile": "cubic", "samples": 100},
    }


def scenario_class(s: dict) -> str:
    n = len(s["arm"]["link_lengths"])
    return f"{n} links, {'narrow' if 'narrow' in s['description'] else 'open'}"


# --- one run ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Task:
    scenario_index: int
    planner: str
    seed: int
    scenario: dict


@dataclass(frozen=True)
class Record:
    scenario_index: int
    planner: str
    seed: int
    success: bool
    error: str
    time_s: float            # to a path: IK + C-space + search (OMPL: its solve time)
    total_s: float           # the whole pipeline, verification included
    length_rad: float        # joint-space length of the path the planner returned
    shortcut_length_rad: float


def planners_for(n: int, extra=()) -> list[str]:
    """The runs' planner names for an arm of ``n`` joints: every grid planner of the table at
    three resolutions, the table's other planners, then ``extra`` (e.g. a benchmark's OMPL
    planners).

    Examples
    --------
    >>> planners_for(2)
    ['astar_24', 'astar_48', 'astar_96', 'rrt', 'rrt_connect', 'rrt_star', 'prm']
    """
    cells = ASTAR_CELLS[min(max(n, 2), 4)]  # beyond 4 joints, the 4-joint grids (may be refused)
    grid = [f"{name}_{c}" for name, p in planner_table.PLANNERS.items() if p.grid for c in cells]
    return grid + list(SAMPLING) + list(extra)


def settings_for(run_name: str, seed: int) -> tuple:
    """``(algorithm, settings)`` of a run named by :func:`planners_for`: a grid planner's
    resolution; for the others the comparison's step, time budget (an anytime planner's own,
    with iterations enough to spend it), goal threshold and ``seed``, those each reads.

    Examples
    --------
    >>> settings_for("astar_48", 3)
    ('astar', {'cells': 48})
    >>> settings_for("rrt_connect", 3)
    ('rrt_connect', {'step': 0.1, 'seed': 3, 'time_budget': 5.0})
    """
    algorithm, _, cells = run_name.rpartition("_")
    if algorithm in planner_table.PLANNERS and planner_table.PLANNERS[algorithm].grid:
        return algorithm, {"cells": int(cells)}
    entry = planner_table.entry(run_name)
    wanted = {"seed": seed, "step": STEP, "time_budget": TIME_BUDGET, "goal_threshold": 0.05}
    if entry.anytime:
        wanted.update(max_iterations=100_000, time_budget=RRT_STAR_BUDGET)
    return run_name, {k: wanted[k] for k in entry.keys if k in wanted}


def run_task(task: Task) -> Record:
    """Plan one scenario with one planner and one seed; never raises for a planning failure."""
    algorithm, settings = settings_for(task.planner, task.seed)
    s = dict(task.scenario, planner={"algorithm": algorithm, **settings})
    t0 = time.perf_counter()
    try:
        plan = plan_scenario(load_scenario(s))
    except (NoPathFound, NoIKSolution) as exc:
        return Record(task.scenario_index, task.planner, task.seed, False, type(exc).__name__,
                      math.nan, time.perf_counter() - t0, math.nan, math.nan)
    except RappError as exc:  # a grid too coarse for the arm, refused as bad input
        return Record(task.scenario_index, task.planner, task.seed, False, type(exc).__name__,
                      math.nan, time.perf_counter() - t0, math.nan, math.nan)
    tm = plan.timings
    return Record(task.scenario_index, task.planner, task.seed, bool(plan.report.ok), "",
                  tm["ik"] + tm["cspace"] + tm["search"], tm["total"],
                  plan.metrics["waypoint_length_rad"], plan.metrics["shortcut_length_rad"])


# --- statistics ------------------------------------------------------------------------------

def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score 95 % interval for a success rate.

    >>> [round(v, 3) for v in wilson(20, 20)]
    [0.839, 1.0]
    """
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    # The interval contains p in exact arithmetic; rounding must not put p outside it (at
    # p = 1 the upper end would come out as 1 - 1e-16).
    return (max(0.0, min(p, centre - half)), min(1.0, max(p, centre + half)))


def mean_interval(values, level: float = 0.95) -> dict:
    """Mean, Student-t interval (``level``, 95 % by default) and median of ``values`` (NaN
    when there are none); the t quantile is :func:`rapp.student_t.t_quantile`, exact for every
    sample size.

    >>> m = mean_interval([1.0, 2.0, 3.0])
    >>> round(m["low"], 6), round(m["high"], 6)
    (-0.484138, 4.484138)
    """
    v = np.asarray([x for x in values if math.isfinite(x)], float)
    if v.size == 0:
        return {"mean": math.nan, "low": math.nan, "high": math.nan, "median": math.nan, "n": 0}
    if v.size == 1:
        return {"mean": float(v[0]), "low": math.nan, "high": math.nan, "median": float(v[0]), "n": 1}
    t = t_quantile(0.5 + level / 2, v.size - 1)
    half = t * v.std(ddof=1) / math.sqrt(v.size)
    return {"mean": float(v.mean()), "low": float(v.mean() - half), "high": float(v.mean() + half),
            "median": float(np.median(v)), "n": int(v.size)}


def summarize(records: list[Record], scenarios: list[dict]) -> dict:
    """Per planner, overall and per scenario class."""
    out: dict = {}
    classes = ["all"] + sorted({scenario_class(s) for s in scenarios})
    for planner in sorted({r.planner for r in records}):
        mine = [r for r in records if r.planner == planner]
        out[planner] = {}
        for cls in classes:
            rs = [r for r in mine if cls == "all" or scenario_class(scenarios[r.scenario_index]) == cls]
            if not rs:
                continue
            ok = [r for r in rs if r.success]
            out[planner][cls] = {
                "runs": len(rs), "successes": len(ok),
                "success_rate": len(ok) / len(rs), "success_interval": wilson(len(ok), len(rs)),
                "time_s": mean_interval(r.time_s for r in ok),
                "length_rad": mean_interval(r.length_rad for r in ok),
                "shortcut_length_rad": mean_interval(r.shortcut_length_rad for r in ok),
            }
    return out


# --- the harness -----------------------------------------------------------------------------

def tasks(scenarios: list[dict], seeds: int, planners=None, extra=()) -> list[Task]:
    """Every run: each scenario with each of its planners (name prefixes in ``planners``, all
    when None), ``seeds`` times for a sampling planner, once for A*."""
    out = []
    for i, s in enumerate(scenarios):
        for p in planners_for(len(s["arm"]["link_lengths"]), extra):
            if planners is not None and not any(p.startswith(name) for name in planners):
                continue
            for seed in (range(1) if p.startswith("astar") else range(seeds)):
                out.append(Task(i, p, seed, s))
    return out


def task_key(item) -> tuple:
    """``(scenario_index, planner, seed)``: what names one run, of a :class:`Task`, a
    :class:`Record` or a record's dict.

    >>> task_key({"scenario_index": 2, "planner": "rrt", "seed": 4, "success": True})
    (2, 'rrt', 4)
    """
    get = item.get if isinstance(item, dict) else lambda k: getattr(item, k)
    return (int(get("scenario_index")), str(get("planner")), int(get("seed")))


def warm() -> float:
    """Compile (or load from numba's cache) every kernel a run uses, in this process, before
    any run is timed; returns the seconds it took.

    :func:`rapp.sampling.prepare_kernels` compiles the sampling planners'; one grid run on a
    2-link joint goal and one on a 3-link Cartesian goal compile the C-space, search and IK
    kernels. A worker calls it once as it starts (:func:`start_worker`), so no run's time
    includes a compilation.
    """
    t0 = time.perf_counter()
    prepare_kernels()
    two, three = make_scenarios(2, seed=1)
    run_task(Task(0, planners_for(2)[0], 0, two))
    run_task(Task(1, planners_for(3)[0], 0, three))
    return time.perf_counter() - t0


def start_worker() -> None:
    """A process pool's initializer: leave Ctrl-C to the parent (it stops the pool and keeps
    what is done), die quietly when the parent terminates the worker, then :func:`warm`."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not a command line's handler, if forked
    warm()


def run_tasks(todo, executor: Executor | None = None, runner=None):
    """Yield the :class:`Record` of each task of ``todo`` as it completes (in completion order).

    ``executor``: any :class:`concurrent.futures.Executor` (a process pool, a Dask client's
    executor, ...) whose workers are warmed (:func:`warm`); None runs the tasks here, one by
    one, after warming this process. Closing the generator early (an interrupt) cancels the
    tasks not yet started.
    """
    runner = run_task if runner is None else runner
    if executor is None:
        warm()
        for task in todo:
            yield runner(task)
        return
    futures = [executor.submit(runner, task) for task in todo]
    try:
        for future in as_completed(futures):
            yield future.result()
    finally:
        for future in futures:
            future.cancel()


def settings_record(scenarios: list[dict], seeds: int, seed, planners) -> dict:
    """What a comparison's records are records of: its scenarios and settings (a journal's
    header, the ``settings`` of a result)."""
    return {"scenarios": len(scenarios), "seeds": seeds, "scenario_seed": seed,
            "planners": None if planners is None else list(planners), "step": STEP,
            "time_budget_s": TIME_BUDGET, "rrt_star_budget_s": RRT_STAR_BUDGET,
            "astar_cells": ASTAR_CELLS}


def result(scenarios: list[dict], settings: dict, records, wall: float) -> dict:
    """The JSON-ready result of a comparison: its records in task order and their summary."""
    rs = sorted((r if isinstance(r, Record) else Record(**r) for r in records), key=task_key)
    return {
        "date": date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version()},
        "settings": settings,
        "wall_s": wall,
        "scenarios": scenarios,
        "summary": summarize(rs, scenarios),
        "records": [asdict(r) for r in rs],
    }


def run(scenarios: int = 30, seeds: int = 20, executor: Executor | None = None, planners=None,
        seed: int = 2026, *, runner=None, extra=()) -> dict:
    """Run the comparison; returns the JSON-ready result (records and summary).

    ``executor``: any :class:`concurrent.futures.Executor` (default: a process pool over all
    cores, each worker warmed by :func:`start_worker`). ``planners``: name prefixes to keep
    (default: all). ``runner``: the function that runs one :class:`Task` (default
    :func:`run_task`; a benchmark passes its own to add the planners named in ``extra``); it
    must be importable by the executor's workers. ``python -m rapp compare`` is the same run
    with a journal (resumable) and progress.
    """
    chosen = make_scenarios(scenarios, seed)
    todo = tasks(chosen, seeds, planners, extra)
    own = executor is None
    if own:
        from concurrent.futures import ProcessPoolExecutor  # multiprocessing: only when used

        executor = ProcessPoolExecutor(max_workers=os.cpu_count(), initializer=start_worker)
    try:
        t0 = time.perf_counter()
        records = list(run_tasks(todo, executor, runner))
        wall = time.perf_counter() - t0
    finally:
        if own:
            executor.shutdown()
    return result(chosen, settings_record(chosen, seeds, seed, planners), records, wall)


def recorded_results() -> dict:
    """The recorded comparison (30 scenarios x 2 seeds, every planner and OMPL's two), from the
    package data."""
    from rapp.recorded import load

    return load("planners")


# --- the recorded runs, grouped as chapter 14 reads them ----------------------------------------

#: The planners' names in the figures (A* is named by its level of resolution, see RunGroups).
FAMILY_NAMES = {"rrt": "RRT", "rrt_connect": "RRT-Connect", "rrt_star": "RRT*", "prm": "PRM",
                "ompl_rrt_connect": "OMPL RRT-Connect", "ompl_rrt_star": "OMPL RRT*"}


@dataclass(frozen=True)
class RunGroups:
    """The recorded runs grouped by planner family and scenario class (see :func:`group_runs`).

    ``runs[family, cls]`` lists the records, ``stats[family, cls]`` holds ``runs``,
    ``successes``, the Wilson ``interval`` and a :func:`mean_interval` of ``time_s``,
    ``length_rad`` and ``shortcut_length_rad`` over the successful runs; class ``"all"`` holds
    every run of a family. ``size[cls]`` counts the scenarios of a class.
    """

    families: list
    classes: list
    runs: dict
    stats: dict
    size: dict
    settings: dict

    def summary(self) -> str:
        """One line for the whole run, then one line per family: its success rate and interval."""
        cfg = self.settings
        lines = [f"{cfg['scenarios']} scenarios, {cfg['seeds']} seeds per sampling planner; "
                 f"step {cfg['step']} rad"]
        for f in self.families:
            a = self.stats[f, "all"]
            lo, hi = a["interval"]
            lines.append(f"{f:17s} {a['successes']:4d} of {a['runs']:4d} runs succeeded "
                         f"(rate {a['successes'] / a['runs']:.2f}, Wilson 95 % [{lo:.2f}, {hi:.2f}])")
        return "\n".join(lines)

    def interval(self, family: str, quantity: str) -> tuple:
        """``(low, high)`` of the 95 % interval of the mean ``quantity`` (``time_s``,
        ``length_rad`` or ``shortcut_length_rad``) over every scenario."""
        m = self.stats[family, "all"][quantity]
        return (m["low"], m["high"])

    def separated(self) -> "Separations":
        """Which comparisons the intervals decide, over every scenario (class ``"all"``).

        Two families differ only where their 95 % intervals lie apart: one's lower end above
        the other's upper end. The success rates and the mean times to a path are compared for
        every ordered pair of families; the mean path length before and after shortcutting,
        within each family.

        Examples
        --------
        >>> g = group_runs(recorded_results())
        >>> s = g.separated()
        >>> s.pairs == len(g.families) * (len(g.families) - 1) // 2, s.undecided <= s.pairs
        (True, True)
        """
        ival = self.interval
        fams = self.families
        pairs = [(f, g) for f in fams for g in fams if f != g]
        higher = [(f, g) for f, g in pairs
                  if intervals_apart(self.stats[f, "all"]["interval"], self.stats[g, "all"]["interval"])]
        faster = [(f, g) for f, g in pairs if intervals_apart(ival(g, "time_s"), ival(f, "time_s"))]
        shorter = [f for f in fams
                   if intervals_apart(ival(f, "length_rad"), ival(f, "shortcut_length_rad"))]
        return Separations(higher, faster, shorter, len(pairs) // 2 - len(higher), len(pairs) // 2)


def intervals_apart(x, y) -> bool:
    """``x``'s interval lies entirely above ``y``'s (both ``(low, high)``).

    >>> intervals_apart((0.5, 0.9), (0.1, 0.4)), intervals_apart((0.3, 0.9), (0.1, 0.4))
    (True, False)
    """
    return bool(np.isfinite(x[0]) and np.isfinite(y[1]) and x[0] > y[1])


@dataclass(frozen=True)
class Separations:
    """What :meth:`RunGroups.separated` finds: ``higher`` (f, g) pairs whose success rates are
    apart, f's above; ``faster`` (f, g) pairs, f's mean time to a path below g's; ``shorter``,
    the families whose shortcut shortens the mean path; ``undecided`` of ``pairs`` unordered
    pairs of success rates the intervals leave open."""

    higher: list
    faster: list
    shorter: list
    undecided: int
    pairs: int

    def lines(self) -> str:
        """The four findings, one line each."""
        return "\n".join([
            "success rate, intervals apart: " + ("; ".join(f"{f} > {g}" for f, g in self.higher) or "none"),
            f"success rate, not separated: {self.undecided} of {self.pairs} pairs",
            "time to a path, intervals apart: " + ("; ".join(f"{f} < {g}" for f, g in self.faster) or "none"),
            "shortcutting shortens the mean path beyond the noise for: " + (", ".join(self.shorter) or "none"),
        ])


def family_of(planner: str, scenario: dict, astar_cells: dict) -> str:
    """The planner's name in the figures; A* by its level of resolution for this arm.

    >>> family_of("rrt_connect", {}, {})
    'RRT-Connect'
    >>> family_of("astar_48", {"arm": {"link_lengths": [1, 1]}}, {"2": [24, 48, 96]})
    'A* medium'
    """
    if not planner.startswith("astar_"):
        return FAMILY_NAMES[planner]
    levels = astar_cells[str(len(scenario["arm"]["link_lengths"]))]
    return "A* " + ("coarse", "medium", "fine")[levels.index(int(planner.split("_")[1]))]


def group_runs(results: dict) -> RunGroups:
    """Group the records of :func:`recorded_results` (or of a run saved alike) by family and class.

    Examples
    --------
    >>> g = group_runs(recorded_results())
    >>> g.families[:3], g.stats["RRT", "all"]["runs"], sum(g.size.values())
    (['A* coarse', 'A* medium', 'A* fine'], 150, 30)
    """
    cfg, scenarios = results["settings"], results["scenarios"]
    runs: dict = {}
    for r in results["records"]:
        s = scenarios[r["scenario_index"]]
        for cls in ("all", scenario_class(s)):
            runs.setdefault((family_of(r["planner"], s, cfg["astar_cells"]), cls), []).append(r)
    families = [f for f in ("A* coarse", "A* medium", "A* fine", *FAMILY_NAMES.values())
                if (f, "all") in runs]
    classes = sorted({c for _, c in runs if c != "all"}, key=lambda c: (c.split()[0], "narrow" in c))
    stats = {}
    for key, rs in runs.items():
        ok = [r for r in rs if r["success"]]
        stats[key] = {"runs": len(rs), "successes": len(ok), "interval": wilson(len(ok), len(rs)),
                      **{q: mean_interval([r[q] for r in ok])
                         for q in ("time_s", "length_rad", "shortcut_length_rad")}}
    size = {c: sum(scenario_class(s) == c for s in scenarios) for c in classes}
    return RunGroups(families, classes, runs, stats, size, cfg)
