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

From path to motion under limits
--------------------------------
With ``trajectory.max_velocity`` and/or ``trajectory.max_acceleration`` the
timing keeps every joint within them (:mod:`rapp.time_scaling`):

* ``"trapezoidal"`` (needs both): the time-optimal LSPB move along each
  segment, joints synchronized, at rest at every waypoint
  (:func:`rapp.time_scaling.trapezoidal_path`);
* ``"cubic"``, ``"quintic"``, ``"spline"``: :func:`rapp.trajectory.time_path`
  scaled uniformly to the smallest duration within the limits, the formula of
  :func:`rapp.time_scaling.minimum_duration` (a missing limit is unbounded);
  if that curve leaves the free polyline, each segment is timed rest-to-rest
  with the quintic smoothstep, each at its own shortest time.

Without ``duration`` the plan takes that shortest duration times
``1 + DURATION_MARGIN`` (1e-9), so that the peaks stay strictly below the
limits after rounding. A ``duration`` is kept as given: the motion is the
same one stretched uniformly in time (speeds scale as ``1/c``, accelerations
as ``1/c**2``); a duration shorter than the shortest is an
:class:`~rapp.errors.InvalidValue` naming ``trajectory.duration`` and that
shortest duration.

A goal with ``"path": "line"`` replaces steps 1 to 5 by
:func:`rapp.cartesian.line_path`: closely spaced waypoints whose straight
joint-space edges keep the end effector within ``LINE_TOLERANCE`` of the
segment (proved, not sampled). The timing must not leave those edges, so it is
rest-to-rest per edge (trapezoidal, or the cubic or quintic rest-to-rest
shape), never a spline through the waypoints, which would cut their corners.
A line that cannot be followed raises :class:`~rapp.errors.PathNotFollowable`.

Planners are looked up by name in :data:`PLANNERS`, so a new search method
plugs in without touching the pipeline. ``plan()`` never prints. The result
value and its file live in :mod:`rapp.results`.

References
----------
SRS of 2D-RAPP (seed 000): IM1 (the instance model of path planning), R3.
MIS of 2D-RAPP (seed 001): ``executePlanning``.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from decimal import ROUND_CEILING, Decimal
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from rapp.cartesian import line_path
from rapp.collision import segment_collision_free
from rapp.errors import InvalidSetting, InvalidValue, NoPathFound
from rapp.grid_route import grid_route
from rapp.ik import free_ik_solutions
from rapp.paths import Route, drop_repeats, path_length, shortcut, unwrap_path
from rapp.results import Plan
from rapp.prm import prm
from rapp.rrt import plan_rrt
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star
from rapp.scenario import MAX_DURATION, MIN_DURATION, Scenario, load_scenario
from rapp.time_scaling import _clock, _waypoints, peak_rates, trapezoidal_path
from rapp.trajectory import (PiecewisePolynomial, cubic_local, quintic_local, time_path,
                             time_polyline)
from rapp.verify import verify

__all__ = ["plan", "PLANNERS", "STAGES", "DURATION_MARGIN", "LINE_TOLERANCE"]

#: Relative margin on a shortest duration: the plan runs ``T_min * (1 + DURATION_MARGIN)``,
#: so that its peak speeds and accelerations stay strictly within the limits after rounding.
DURATION_MARGIN = 1e-9
#: Distance (m) from the segment within which :func:`rapp.cartesian.line_path` keeps the end
#: effector along each of its edges. The verification bounds every chord between samples by
#: its distance at 17 points plus a curvature term; on a sub-chord of an edge certified at
#: ``tol`` (its curvature term at most ``tol / 2`` on 4 intervals) that bound is at most
#: ``tol * (1 + 1/32)``, so 0.9 mm keeps it within the verification's 1 mm.
LINE_TOLERANCE = 0.9e-3
#: Peak ``|s'|`` and ``|s''|`` of the rest-to-rest shapes ``s(u)`` on ``[0, 1]``: the cubic
#: ``3u^2 - 2u^3`` and the quintic smoothstep ``10u^3 - 15u^4 + 6u^5``.
_REST_SHAPES = {"cubic": (1.5, 6.0), "quintic": (1.875, 10.0 / math.sqrt(3.0))}


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
                "max_iterations": p.max_iterations, "seed": p.seed, "time_budget": p.time_budget}
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


# --------------------------------------------------------------------------- timing under limits


def _round_up(x: float, digits: int = 6) -> float:
    """``x`` rounded up to ``digits`` significant digits (a duration that is sure to suffice).

    Examples
    --------
    >>> _round_up(1.8750000018), _round_up(2.0)
    (1.87501, 2.0)
    """
    if not x > 0:
        return float(x)
    step = Decimal(1).scaleb(math.floor(math.log10(x)) - digits + 1)
    return float(Decimal(x).quantize(step, rounding=ROUND_CEILING))


def _stretch(pp: PiecewisePolynomial, c: float) -> PiecewisePolynomial:
    """``pp`` run ``c`` times slower: ``q_c(t) = q(t / c)``, speeds ``/ c``, accelerations ``/ c**2``."""
    k = np.arange(pp.local.shape[1])
    return PiecewisePolynomial.from_local(pp.breakpoints * c, pp.local / c ** k[None, :, None])


def _rest_to_rest(w: np.ndarray, shape: str, h: np.ndarray) -> PiecewisePolynomial:
    """Edge ``j`` of ``w`` in time ``h[j]`` with the cubic or quintic rest-to-rest shape: the arm
    stays on each straight joint-space edge and is at rest at every waypoint."""
    bp = [0.0]
    for hj in h:
        bp.append(_clock(bp[-1], float(hj)))   # each piece rounded up: never faster than asked
    bp = np.array(bp)
    hh = np.diff(bp)[:, None]
    p0, pf = w[:-1], w[1:]
    z = np.zeros_like(p0)
    b = (quintic_local(hh, p0, pf, z, z, z, z) if shape == "quintic"
         else cubic_local(hh, p0, pf, z, z))
    return PiecewisePolynomial.from_local(bp, np.moveaxis(b, 0, 1))


def _limits(tr):
    vmax = None if tr.max_velocity is None else np.asarray(tr.max_velocity, float)
    amax = None if tr.max_acceleration is None else np.asarray(tr.max_acceleration, float)
    return vmax, amax


def _shortest(tr, w: np.ndarray, kind: str):
    """``(T_min, build, T_v, T_a)`` of the timing ``kind`` of ``w`` under the limits of ``tr``.

    ``build(T)`` is the motion of duration ``T >= T_min``; ``T_v`` and ``T_a`` are the shortest
    durations under the velocity and under the acceleration limit alone (which one binds).
    ``kind``: ``"trapezoidal"``, ``"uniform"`` (time_path of ``tr.profile``, scaled) or
    ``"rest-cubic"`` / ``"rest-quintic"`` (rest-to-rest per edge, each edge at its own shortest).
    """
    vmax, amax = _limits(tr)
    d = np.abs(np.diff(w, axis=0))
    with np.errstate(all="ignore"):
        if kind == "trapezoidal":
            pp = trapezoidal_path(w, vmax, amax)
            tv = float(np.max(d / vmax, axis=1).sum())
            ta = float(2.0 * np.sqrt(np.max(d / amax, axis=1)).sum())
            return pp.duration, lambda T: _stretch(pp, T / pp.duration), tv, ta
        if kind == "uniform":
            # minimum_duration's formula, with either limit allowed to be absent (unbounded).
            V, A = peak_rates(time_path(w, 1.0, tr.profile))
            tv = float(np.max(V / vmax)) if vmax is not None else 0.0
            ta = float(np.max(np.sqrt(A / amax))) if amax is not None else 0.0
            return max(tv, ta), lambda T: time_path(w, T, tr.profile), tv, ta
        shape = kind.split("-", 1)[1]
        s1, s2 = _REST_SHAPES[shape]
        hv = np.max(s1 * d / vmax, axis=1) if vmax is not None else np.zeros(len(d))
        ha = np.max(np.sqrt(s2 * d / amax), axis=1) if amax is not None else np.zeros(len(d))
        h = np.maximum(hv, ha)
        total = float(h.sum())
        return total, lambda T: _rest_to_rest(w, shape, h * (T / total)), float(hv.sum()), \
            float(ha.sum())


def _limited_motion(tr, w: np.ndarray, kind: str, what: str):
    """The motion of ``kind`` within the limits: ``(pp, T_min)``; the duration is ``tr.duration``
    or the shortest times ``1 + DURATION_MARGIN``. Refuses a duration that is too short."""
    T_min, build, tv, ta = _shortest(tr, w, kind)
    if tr.duration is None:
        T = T_min * (1.0 + DURATION_MARGIN)
        if T > MAX_DURATION:
            field = "max_velocity" if tv >= ta else "max_acceleration"
            raise InvalidValue(
                f"the {what} needs {T:.4g} s within these limits, above the longest duration "
                f"{MAX_DURATION:g} s: raise the limit", field=f"trajectory.{field}")
    else:
        T = tr.duration
        if T < T_min:
            raise InvalidValue(
                f"{T:g} s is too short for the joint limits: the {what} needs at least "
                f"{_round_up(T_min)} s (the shortest feasible duration)",
                field="trajectory.duration")
    return build(T), T_min


def _sample(pp: PiecewisePolynomial, path, duration: float, samples: int, every_breakpoint=False):
    t = _sample_times(duration, samples, pp.breakpoints)
    if every_breakpoint:   # every sample chord then lies on one edge of the path
        bp = pp.breakpoints[(pp.breakpoints > 0) & (pp.breakpoints < duration)]
        t = np.unique(np.concatenate((t, bp)))
    q, qd, qdd = (np.asarray(a, float) for a in pp.sample(t))
    q[0], q[-1] = path[0], path[-1]
    return t, q, qd, qdd


def _time_motion(arm, obs, path, scenario):
    """Timing under joint limits, or of a line goal: ``(t, q, qd, qdd, profile, motion, info)``."""
    tr = scenario.trajectory
    w = _waypoints(path, None) if len(path) >= 2 else np.asarray(path, float)
    if len(w) < 2:
        T = tr.duration if tr.duration is not None else MIN_DURATION
        t, q, qd, qdd = time_polyline(np.asarray(path, float)[:1], T, tr.samples)
        return t, q, qd, qdd, "rest (start is the goal)", None, {"duration_s": T}
    info = {}
    rest = "quintic" if tr.profile in ("quintic", "spline") else "cubic"
    if scenario.goal_path == "line":
        shape = "trapezoidal" if tr.profile == "trapezoidal" else rest
        label = f"rest-to-rest {shape} per edge of the line's waypoints"
        if tr.limited:
            kind = "trapezoidal" if shape == "trapezoidal" else f"rest-{rest}"
            pp, info["min_duration_s"] = _limited_motion(
                tr, w, kind, f"rest-to-rest {shape} motion along the line's waypoints")
        else:   # time shares proportional to the joint-space length of each edge
            lengths = np.linalg.norm(np.diff(w, axis=0), axis=1)
            pp = _rest_to_rest(w, rest, tr.duration * lengths / lengths.sum())
        T = tr.duration if tr.duration is not None else pp.tf
        t, q, qd, qdd = _sample(pp, w, T, tr.samples, every_breakpoint=True)
    elif tr.profile == "trapezoidal":
        label = "trapezoidal"
        pp, info["min_duration_s"] = _limited_motion(tr, w, "trapezoidal",
                                                     "trapezoidal motion along the planned path")
        T = tr.duration if tr.duration is not None else pp.tf
        t, q, qd, qdd = _sample(pp, w, T, tr.samples)
    else:
        label = tr.profile
        pp, info["min_duration_s"] = _limited_motion(
            tr, w, "uniform", f"{tr.profile} motion along the planned path")
        T = tr.duration if tr.duration is not None else pp.tf
        t, q, qd, qdd = _sample(pp, w, T, tr.samples)
        good = (np.isfinite(q).all() and np.isfinite(qd).all() and np.isfinite(qdd).all()
                and arm.within_limits(q, 1e-9).all()
                and segment_collision_free(arm, q[:-1], q[1:], obs).all())
        if not good:   # rest-to-rest along the certified polyline, each segment at its shortest
            label = (f"rest-to-rest quintic per segment (the {tr.profile} curve left the free "
                     "polyline)")
            pp, info["min_duration_s"] = _limited_motion(
                tr, w, "rest-quintic", "rest-to-rest quintic motion along the planned path "
                f"(the {tr.profile} curve leaves the free polyline)")
            T = tr.duration if tr.duration is not None else pp.tf
            t, q, qd, qdd = _sample(pp, w, T, tr.samples)
    info["duration_s"] = float(t[-1])
    return t, q, qd, qdd, label, pp, info


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
    if algorithm not in PLANNERS:
        raise InvalidValue(f"unknown planner {algorithm!r}", field="planner.algorithm")
    arm, obs = scenario.arm, scenario.obstacles
    times = {}
    t_all = time.perf_counter()

    if scenario.goal_path == "line":
        # No IK, search or shortcut: the waypoints are the line's, which a shortcut would leave.
        t0 = time.perf_counter()
        line = line_path(arm, scenario.start_array, scenario.goal_xy, obs,
                         tolerance=LINE_TOLERANCE)
        route = Route(line, line[-1], metrics={"line_waypoints": int(len(line))},
                      times={"search": time.perf_counter() - t0})
        n_ik, waypoints, short = None, line, line
    else:
        t0 = time.perf_counter()
        goal_qs, n_ik = _goal_configurations(scenario)
        times["ik"] = time.perf_counter() - t0

        try:
            route = PLANNERS[algorithm](scenario, goal_qs)
        except InvalidSetting as e:  # the planner names its parameter; the file names the key
            raise InvalidValue(e.message, field=f"planner.{e.setting}") from None
        times.update(route.times)

        t0 = time.perf_counter()
        waypoints = route.waypoints
        short = shortcut(arm, drop_repeats(waypoints), obs)
        times["smoothing"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    motion, extra = None, {}
    if scenario.trajectory.limited or scenario.goal_path == "line":
        t, q, qd, qdd, profile, motion, extra = _time_motion(arm, obs, short, scenario)
    else:
        t, q, qd, qdd, profile = _time_smooth(arm, obs, short, scenario.trajectory)
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
        **extra,
    })
    result = Plan(t=t, q=q, qd=qd, qdd=qdd, xy=xy, waypoints=waypoints, shortcut=short,
                  goal_q=np.asarray(route.goal_q, float), scenario=scenario, grid=route.grid,
                  occupancy=route.occupancy, profile=profile, metrics=metrics,
                  expanded=route.expanded, motion=motion)
    t0 = time.perf_counter()
    report = verify(result, scenario)
    times["verify"] = time.perf_counter() - t0
    times["total"] = time.perf_counter() - t_all
    timings = {k: float(times.get(k, 0.0)) for k in STAGES}
    return replace(result, report=report, timings=timings)
