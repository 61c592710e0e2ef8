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

Planners are looked up by name in :data:`PLANNERS`, so a new search method
plugs in without touching the pipeline. ``plan()`` never prints. The result
value and its file live in :mod:`rapp.results`.

References
----------
SRS of 2D-RAPP (seed 000): IM1 (the instance model of path planning), R3.
MIS of 2D-RAPP (seed 001): ``executePlanning``.
"""

from __future__ import annotations

import time
from dataclasses import replace
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from rapp.collision import segment_collision_free
from rapp.errors import InvalidValue, NoPathFound
from rapp.grid_route import grid_route
from rapp.ik import free_ik_solutions
from rapp.paths import Route, drop_repeats, path_length, shortcut, unwrap_path
from rapp.results import Plan
from rapp.prm import prm
from rapp.rrt import plan_rrt
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star
from rapp.scenario import Scenario, load_scenario
from rapp.trajectory import time_path, time_polyline
from rapp.verify import verify

__all__ = ["plan", "PLANNERS", "STAGES"]


def _goal_configurations(scenario: Scenario) -> tuple[np.ndarray, int]:
    """Free goal configurations (g, n) and how many IK solutions there were."""
    if scenario.goal_q is not None:
        return np.array([scenario.goal_q], float), 1
    return free_ik_solutions(scenario.arm, scenario.goal_xy, scenario.obstacles,
                             q0=scenario.start_array)


def _plan_astar(scenario: Scenario, goal_qs: np.ndarray) -> Route:
    """A* on the joint grid, every move certified (:func:`rapp.grid_route.grid_route`)."""
    p = scenario.planner
    return grid_route(scenario.arm, scenario.obstacles, scenario.start_array, goal_qs,
                      cells=p.cells, heuristic_weight=p.heuristic_weight,
                      max_expansions=p.max_expansions)


def _plan_rrt(scenario: Scenario, goal_qs: np.ndarray) -> Route:
    """RRT from the exact start to the goal configurations; its path is certified edge by edge."""
    p = scenario.planner
    settings = {"step": p.step, "goal_bias": p.goal_bias, "goal_threshold": p.goal_threshold,
                "max_iterations": p.max_iterations, "seed": p.seed}
    return _sampled_route(scenario, goal_qs, lambda arm, obs, start, goals: plan_rrt(
        arm, obs, start, goals, settings=settings))


def _sampling_planner(function, keys):
    """A PLANNERS entry for a sampling planner called as ``function(arm, start, goal,
    obstacles, **settings)`` with the scenario's settings named in ``keys``."""
    def run(scenario: Scenario, goal_qs: np.ndarray) -> Route:
        p = scenario.planner
        kw = {k: getattr(p, k) for k in keys}
        return _sampled_route(scenario, goal_qs, lambda arm, obs, start, goals: function(
            arm, start, goals, obs, **kw).path)
    run.__doc__ = f"{function.__name__} from the exact start to the goal configurations."
    return run


def _sampled_route(scenario: Scenario, goal_qs, solve) -> Route:
    t0 = time.perf_counter()
    path = np.asarray(solve(scenario.arm, scenario.obstacles, scenario.start_array, goal_qs), float)
    if path.ndim != 2 or len(path) == 0:
        raise NoPathFound(f"{scenario.planner.algorithm} found no path")
    path = unwrap_path(scenario.arm, path)
    metrics = {"tree_path_nodes": int(len(path)), "goal_candidates": int(len(goal_qs))}
    return Route(path, path[-1], None, None, metrics,
                 {"cspace": 0.0, "search": time.perf_counter() - t0})


#: The pipeline's stages, in order, as named in ``Plan.timings``.
STAGES = ("ik", "cspace", "search", "smoothing", "trajectory", "verify", "total")

#: Planner name -> function(scenario, goal configurations (g, n)) -> Route.
#: Read-only: a new planner is added here, in code, not registered at run time.
PLANNERS: Mapping[str, Callable] = MappingProxyType({
    "astar": _plan_astar,
    "rrt": _plan_rrt,
    "rrt_connect": _sampling_planner(rrt_connect, ("step", "seed", "max_iterations", "time_budget")),
    "rrt_star": _sampling_planner(rrt_star, ("step", "goal_bias", "goal_threshold", "seed",
                                             "max_iterations", "time_budget")),
    "prm": _sampling_planner(prm, ("samples", "neighbours", "seed", "max_iterations",
                                   "time_budget")),
})


def _sample_times(duration: float, samples: int, breakpoints) -> np.ndarray:
    """``samples`` even times, plus each breakpoint and three inner times of every piece that
    the even times leave with fewer than three samples inside.

    The verification bounds the motion between consecutive samples by their velocities and
    accelerations; a polynomial piece seen only at its two ends (a rest-to-rest quintic has
    zero velocity and acceleration there) would look like a jump.
    """
    t = np.linspace(0.0, duration, samples)
    bp = np.asarray(breakpoints, float)
    inside = np.searchsorted(t, bp[1:], side="left") - np.searchsorted(t, bp[:-1], side="right")
    sparse = np.flatnonzero(inside < 3)
    if sparse.size:
        h = np.diff(bp)[sparse, None]
        extra = bp[sparse, None] + h * np.array([0.0, 0.25, 0.5, 0.75, 1.0])
        t = np.unique(np.concatenate((t, extra.ravel())))
    t[-1] = duration
    return t


def _time_smooth(arm, obs, path, tr):
    """The requested smooth profile of ``tr`` (TrajectorySettings) if it stays free and within
    limits, else ``time_polyline``."""
    if len(path) >= 2:
        pp = time_path(path, tr.duration, profile=tr.profile)
        t = _sample_times(tr.duration, tr.samples, pp.breakpoints)
        q, qd, qdd = (np.asarray(a, float) for a in pp.sample(t))
        good = (np.isfinite(q).all() and np.isfinite(qd).all() and np.isfinite(qdd).all()
                and np.abs(q[0] - path[0]).max() <= 1e-9
                and np.abs(q[-1] - path[-1]).max() <= 1e-9
                and arm.within_limits(q, 1e-9).all()
                and segment_collision_free(arm, q[:-1], q[1:], obs).all())
        if good:
            q[0], q[-1] = path[0], path[-1]
            return t, q, qd, qdd, tr.profile
        fallback = f"rest-to-rest per segment (the {tr.profile} curve left the free polyline)"
    else:
        fallback = "rest (start is the goal)"
    t, q, qd, qdd = time_polyline(path, tr.duration, tr.samples)
    return t, q, qd, qdd, fallback


def plan(scenario) -> Plan:
    """Plan, time and verify a collision-free trajectory.

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
    ScenarioError
        From loading, when ``scenario`` is not already a Scenario.

    Examples
    --------
    >>> p = plan("default")
    >>> p.report.ok, p.q.shape[1], bool(np.allclose(p.xy[-1], [-1.2, 0.8], atol=1e-3))
    (True, 2, True)
    """
    scenario = load_scenario(scenario)
    algorithm = scenario.planner.algorithm
    if algorithm not in PLANNERS:
        raise InvalidValue(f"unknown planner {algorithm!r}", field="planner.algorithm")
    arm, obs = scenario.arm, scenario.obstacles
    times = {}
    t_all = time.perf_counter()

    t0 = time.perf_counter()
    goal_qs, n_ik = _goal_configurations(scenario)
    times["ik"] = time.perf_counter() - t0

    route = PLANNERS[algorithm](scenario, goal_qs)
    times.update(route.times)

    t0 = time.perf_counter()
    waypoints = route.waypoints
    short = shortcut(arm, drop_repeats(waypoints), obs)
    times["smoothing"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    t, q, qd, qdd, profile = _time_smooth(arm, obs, short, scenario.trajectory)
    xy = arm.end_effector(q)
    times["trajectory"] = time.perf_counter() - t0

    metrics = dict(route.metrics)
    metrics.update({
        "ik_solutions": int(n_ik),
        "waypoints": int(len(waypoints)),
        "shortcut_waypoints": int(len(short)),
        "joint_length_rad": path_length(q),
        "waypoint_length_rad": path_length(waypoints),
        "shortcut_length_rad": path_length(short),
        "ee_length_m": path_length(xy),
        "samples": int(len(t)),
    })
    result = Plan(t=t, q=q, qd=qd, qdd=qdd, xy=xy, waypoints=waypoints, shortcut=short,
                  goal_q=np.asarray(route.goal_q, float), scenario=scenario, grid=route.grid,
                  occupancy=route.occupancy, profile=profile, metrics=metrics,
                  expanded=route.expanded)
    t0 = time.perf_counter()
    report = verify(result, scenario)
    times["verify"] = time.perf_counter() - t0
    times["total"] = time.perf_counter() - t_all
    timings = {k: float(times.get(k, 0.0)) for k in STAGES}
    return replace(result, report=report, timings=timings)
