"""The planning pipeline: scenario in, verified trajectory out.

``plan(scenario)`` runs, in order:

1. **IK** — a Cartesian goal becomes every goal configuration :func:`rapp.ik`
   finds that is within the limits and free of obstacles;
2. **C-space** — the joint grid and its occupancy (:mod:`rapp.cspace`);
3. **search** — breadth-first distances from the start cell pick the goal
   configuration that is *reachable* and nearest in grid steps, and A* finds
   the path to it (one BFS answers "which goal" and proves "no path" at once);
4. **certification** — the exact start and goal are joined to free cells by
   certified segments, and every grid move is checked by the continuous
   certified test (occupancy samples cell centres only; a move whose segment
   cannot be certified blocks its cell and the search is repeated);
5. **smoothing** — greedy shortcutting: from each waypoint jump to the farthest
   later waypoint whose straight joint-space segment is certified free;
6. **trajectory** — the shortcut polyline is timed into ``q(t)``, ``q'(t)``,
   ``q''(t)`` (:func:`rapp.trajectory.time_path`); if the smooth curve leaves
   the certified polyline and collides (or breaks a limit), each segment is
   timed rest-to-rest instead, which follows the polyline exactly;
7. **verification** — :func:`rapp.verify.verify` fills ``plan.report``.

The timing policy (the profile asked, under joint limits, and its fallbacks) is
:mod:`rapp.timing`.

A goal with ``"path": "line"`` replaces steps 1 to 5 by
:func:`rapp.cartesian.line_path`: closely spaced waypoints whose straight
joint-space edges keep the end effector within ``LINE_TOLERANCE`` of the
segment (proved, not sampled). The timing must not leave those edges, so it is
rest-to-rest per edge (trapezoidal, or the cubic or quintic rest-to-rest
shape, :func:`rapp.timing.time_route`), never a spline through the waypoints.
A line that cannot be followed raises :class:`~rapp.errors.PathNotFollowable`.

Planners are looked up by name in the planner table (:mod:`rapp.planners`), so a new
planner plugs in without touching the pipeline. ``plan()`` never prints. The result
value and its file live in :mod:`rapp.results`.

References
----------
SRS of 2D-RAPP (seed 000): IM1 (the instance model of path planning), R3.
MIS of 2D-RAPP (seed 001): ``executePlanning``.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    import os
    from typing import Any, Mapping
    from rapp.scenario import Scenario

from rapp.cartesian import line_path
from rapp.collision import scene
from rapp.errors import InvalidSetting, InvalidValue, NoIKSolution, NoPathFound
from rapp import planners as planner_table
from rapp.ik import free_ik_solutions
from rapp.paths import PlannerResult, drop_repeats, path_length, shortcut, unwrap_path
from rapp.results import Plan
from rapp.sampling import prepare_kernels
from rapp.scenario import Scenario, load_scenario
from rapp.timing import DURATION_MARGIN, time_route
from rapp.verify import verify

__all__ = ["plan", "preflight", "PLANNERS", "STAGES", "DURATION_MARGIN", "LINE_TOLERANCE"]

#: Distance (m) from the segment within which :func:`rapp.cartesian.line_path` keeps the end
#: effector along each of its edges. The verification bounds every chord between samples by
#: its distance at 17 points plus a curvature term; on a sub-chord of an edge certified at
#: ``tol`` (its curvature term at most ``tol / 2`` on 4 intervals) that bound is at most
#: ``tol * (1 + 1/32)``, so 0.9 mm keeps it within the verification's 1 mm.
LINE_TOLERANCE = 0.9e-3


def _goal_configurations(scenario: Scenario) -> tuple[np.ndarray, int]:
    """Free goal configurations (g, n) and how many IK solutions there were."""
    if scenario.goal_q is not None:
        return np.array([scenario.goal_q], float), 1
    arm, obstacles = scene(scenario.arm, scenario.obstacles, scenario.safety_margin)
    return free_ik_solutions(arm, scenario.goal_xy, obstacles, q0=scenario.start_array)


def _search(scenario: Scenario, goal_qs: np.ndarray) -> PlannerResult:
    """The scenario's planner (looked up in the table) from the exact start to ``goal_qs``.

    Its path is unwrapped; its metrics and stage times are the grid planner's own, or, for a
    planner that reports none, the path's nodes and the wall time of the call.
    """
    p = scenario.planner
    t0 = time.perf_counter()
    result = planner_table.run(p.algorithm, scenario.arm, scenario.start_array, goal_qs,
                               scenario.obstacles, margin=scenario.safety_margin, **p.values())
    elapsed = time.perf_counter() - t0
    path = np.asarray(result.path, float)
    if not result.success or path.ndim != 2 or len(path) == 0:
        raise NoPathFound(f"{p.algorithm} found no path ({result.status})")
    path = unwrap_path(scenario.arm, path)
    details = dict(result.details)
    details.setdefault("metrics", {"tree_path_nodes": int(len(path)),
                                   "goal_candidates": int(len(goal_qs))})
    details.setdefault("times", {"cspace": 0.0, "search": elapsed})
    return PlannerResult(path, True, result.cost, details)


def _refusal(e: InvalidSetting) -> InvalidValue:
    """A planner's refusal of one of its settings, named as the scenario file names it."""
    return InvalidValue(e.message, field=f"planner.{e.setting}")


def preflight(scenario) -> None:
    """Every refusal of a setting that :func:`plan` would make, without planning.

    Some settings can only be judged against the problem (an RRT-Connect ``step`` too small to
    join this start and goal within the trees' nodes, a roadmap too large for the memory
    budget). They are judged by the planner itself, so this runs the planner table's check of
    the scenario's planner with the settings as given, then the planner, with the same
    settings, on the same start and goal configurations, for one iteration and without
    obstacles: the refusals are the planner's own code, the same as :func:`plan` meets, and
    nothing is searched. A planner with no iterations (the grid planners) is judged by the
    scenario loader alone. ``python -m rapp check`` calls it.

    Raises
    ------
    InvalidValue
        Naming ``planner.<setting>``, with the message :func:`plan` would give.

    Examples
    --------
    >>> d = load_scenario("default").to_dict()
    >>> d["planner"] = {"algorithm": "rrt_connect", "step": 1e-6}
    >>> preflight(d)
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidValue: planner.step: step 1e-06 rad is too small: ...
    """
    scenario = load_scenario(scenario)
    p = scenario.planner
    values = p.values()
    if scenario.goal_path == "line" or "max_iterations" not in values:
        return
    try:
        goal_qs, _ = _goal_configurations(scenario)
    except (NoIKSolution, NoPathFound):   # a planning answer, not a refusal
        return
    entry = planner_table.entry(p.algorithm)
    try:
        if entry.check is not None:   # the table's own check, with the settings as given
            entry.check(scenario.arm, scenario.start_array, goal_qs,
                        **{s.key: values.get(s.key, s.default) for s in entry.settings})
        planner_table.run(p.algorithm, scenario.arm, scenario.start_array, goal_qs, (),
                          raise_on_failure=False, **dict(values, max_iterations=1,
                                                         time_budget=None))
    except InvalidSetting as e:
        raise _refusal(e) from None
    except NoPathFound:
        return


#: The pipeline's stages, in order, as named in ``Plan.timings``; ``compile`` is the time spent
#: compiling (or loading from numba's cache) a sampling planner's kernels before its clock
#: starts (:func:`rapp.sampling.prepare_kernels`), so that a ``time_budget`` measures planning.
STAGES = ("compile", "ik", "cspace", "search", "smoothing", "trajectory", "verify", "total")

#: The planner table (:data:`rapp.planners.PLANNERS`): name -> entry, read-only.
PLANNERS = planner_table.PLANNERS


def plan(scenario: Scenario | str | os.PathLike | Mapping[str, Any]) -> Plan:
    """Plan, time and verify a collision-free trajectory.

    It plans against the scenario's obstacles only, every segment certified. A user's own
    checker (``validity=``, :mod:`rapp.validity`) is a keyword of the planner functions, not a
    scenario key: a scenario file cannot carry a Python callable.

    Parameters
    ----------
    scenario : Scenario, or anything :func:`rapp.load_scenario` accepts

    Returns
    -------
    Plan
        With ``report`` filled by :func:`rapp.verify` and ``metrics``.

    Raises
    ------
    NoIKSolution
        The Cartesian goal has no joint solution within the limits.
    NoPathFound
        No collision-free path exists on the grid (proved by exhausting it),
        every IK solution collides, or the search limit was hit.
    PathNotFollowable
        A line goal the end effector cannot follow (it leaves the workspace,
        passes a singularity, breaks a joint limit or hits an obstacle).
    ScenarioError
        From loading, when ``scenario`` is not already a Scenario; an
        :class:`~rapp.errors.InvalidValue` naming ``trajectory.duration`` when
        the duration given is too short for the joint limits along the path.

    Examples
    --------
    >>> p = plan("default")
    >>> p.report.ok, p.q.shape[1], bool(np.allclose(p.xy[-1], [-1.2, 0.8], atol=1e-3))
    (True, 2, True)
    """
    scenario = load_scenario(scenario)
    algorithm = scenario.planner.algorithm
    if algorithm not in planner_table.PLANNERS:
        raise InvalidValue(f"unknown planner {algorithm!r}", field="planner.algorithm")
    # Thick links and a safety margin: every test below is of zero-width links against the
    # obstacles grown by the distance each link keeps, the same question (rapp.collision.scene).
    arm, obs = scene(scenario.arm, scenario.obstacles, scenario.safety_margin)
    times = {}
    t_all = time.perf_counter()

    if scenario.goal_path == "line":
        # No IK, search or shortcut: the waypoints are the line's, which a shortcut would leave.
        t0 = time.perf_counter()
        line = line_path(arm, scenario.start_array, scenario.goal_xy, obs,
                         tolerance=LINE_TOLERANCE)
        route = PlannerResult(line, True, path_length(line), {
            "metrics": {"line_waypoints": int(len(line))}, "times": {"search": time.perf_counter() - t0}})
        n_ik, waypoints, short = None, line, line
    else:
        t0 = time.perf_counter()
        goal_qs, n_ik = _goal_configurations(scenario)
        times["ik"] = time.perf_counter() - t0

        if scenario.planner.values().get("time_budget") is not None:
            times["compile"] = prepare_kernels()
        try:
            route = _search(scenario, goal_qs)
        except InvalidSetting as e:  # the planner names its parameter; the file names the key
            raise _refusal(e) from None
        times.update(route.times)

        t0 = time.perf_counter()
        waypoints = route.waypoints
        short = shortcut(arm, drop_repeats(waypoints), obs)
        times["smoothing"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    timed = time_route(arm, obs, short, scenario.trajectory, line=scenario.goal_path == "line")
    t, q = timed.t, timed.q
    xy = arm.end_effector(q)
    times["trajectory"] = time.perf_counter() - t0

    metrics = dict(route.metrics)
    if n_ik is not None:
        metrics["ik_solutions"] = int(n_ik)
    metrics.update({
        "waypoints": int(len(waypoints)),
        "shortcut_waypoints": int(len(short)),
        "joint_length_rad": path_length(q),
        "waypoint_length_rad": path_length(waypoints),
        "shortcut_length_rad": path_length(short),
        "ee_length_m": path_length(xy),
        "samples": int(len(t)),
        **timed.info,
    })
    result = Plan(t=t, q=q, qd=timed.qd, qdd=timed.qdd, xy=xy, waypoints=waypoints, shortcut=short,
                  goal_q=np.asarray(route.goal_q, float), scenario=scenario, grid=route.details.get("grid"),
                  occupancy=route.details.get("occupancy"), profile=timed.profile, metrics=metrics,
                  expanded=route.details.get("expanded"), motion=timed.motion)
    t0 = time.perf_counter()
    report = verify(result, scenario)
    times["verify"] = time.perf_counter() - t0
    times["total"] = time.perf_counter() - t_all
    timings = {k: float(times.get(k, 0.0)) for k in STAGES}
    return replace(result, report=report, timings=timings)
