"""Timing a certified path into a motion ``q(t)``: the pipeline's timing policy.

:func:`time_route` is step 6 of :func:`rapp.plan`. It takes the shortcut polyline (every
straight joint-space edge certified free) and the scenario's
:class:`~rapp.scenario.TrajectorySettings`, and returns the sampled motion:

* without joint limits: :func:`rapp.time_scaling.time_path` of the profile asked, over the
  duration asked; unless that smooth curve is certified free and within the joint limits over
  its whole time span, between samples too (:func:`rapp.motion.certify_motion`), each segment
  is timed rest-to-rest instead (the quintic smoothstep of
  :func:`rapp.trajectory.time_polyline`), which follows the certified polyline exactly;
* with ``max_velocity`` and/or ``max_acceleration`` (:mod:`rapp.time_scaling`):
  ``"trapezoidal"`` (needs both) is the time-optimal LSPB move along each segment, joints
  synchronized, at rest at every waypoint; ``"cubic"``, ``"quintic"``, ``"spline"`` are
  ``time_path`` scaled uniformly to the smallest duration within the limits (a missing limit
  is unbounded); unless that curve is certified free and within the joint limits over its
  whole time span, each segment is timed rest-to-rest with the quintic smoothstep, each at its
  own shortest time;
* a line goal (``line=True``): rest-to-rest per edge of the line's waypoints (trapezoidal, or
  the cubic or quintic rest-to-rest shape), never a spline through them, which would cut
  their corners and leave the line.

Every motion returned is a :class:`~rapp.trajectory.PiecewisePolynomial` from exactly 0 to
exactly its duration (``TimedPath.motion``); the samples are that motion at strictly increasing
times, the last exactly the duration.

Without ``duration`` the motion takes the shortest duration times ``1 + DURATION_MARGIN``,
so that the peaks stay strictly below the limits after rounding. A ``duration`` is kept as
given: the motion is the same one stretched uniformly in time (speeds scale as ``1/c``,
accelerations as ``1/c**2``); a duration shorter than the shortest is an
:class:`~rapp.errors.InvalidValue` naming ``trajectory.duration`` and that shortest
duration.

Examples
--------
>>> from rapp import Arm
>>> from rapp.scenario import TrajectorySettings
>>> path = np.array([[0.0, 0.0], [1.0, 0.5]])
>>> m = time_route(Arm([1.0, 1.0]), [], path, TrajectorySettings(duration=None, max_velocity=(1.0, 1.0),
...                                                               max_acceleration=(2.0, 2.0), profile="trapezoidal"))
>>> m.profile, round(m.info["min_duration_s"], 6), m.q[-1].tolist()
('trapezoidal', 1.5, [1.0, 0.5])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from decimal import ROUND_CEILING, Decimal

import numpy as np

from rapp.checks import sorted_unique

from rapp.errors import InvalidValue
from rapp.scenario import MAX_DURATION, MIN_DURATION
from rapp.motion import certify_motion
from rapp.time_scaling import clean_waypoints, clock_after, peak_rates, time_path, trapezoidal_path
from rapp.trajectory import PiecewisePolynomial, cubic_local, quintic_local, step_lengths

__all__ = ["time_route", "TimedPath", "sample_times", "round_up", "DURATION_MARGIN"]

#: Relative margin on a shortest duration: the plan runs ``T_min * (1 + DURATION_MARGIN)``,
#: so that its peak speeds and accelerations stay strictly within the limits after rounding.
DURATION_MARGIN = 1e-9
#: Peak ``|s'|`` and ``|s''|`` of the rest-to-rest shapes ``s(u)`` on ``[0, 1]``: the cubic
#: ``3u^2 - 2u^3`` and the quintic smoothstep ``10u^3 - 15u^4 + 6u^5``.
_REST_SHAPES = {"cubic": (1.5, 6.0), "quintic": (1.875, 10.0 / math.sqrt(3.0))}


def sample_times(duration: float, samples: int, breakpoints, dt: float | None = None) -> np.ndarray:
    """``samples`` even times, plus each breakpoint and three inner times of every piece that
    the even times leave with fewer than three samples inside.

    The times lie in ``[0, duration]``, strictly increasing, the first 0 and the last exactly
    ``duration``: a breakpoint that rounding put an ulp past the duration is clipped to it,
    never kept as a second sample next to it. With ``dt`` (a fixed time step,
    ``trajectory.dt``) the even times are ``0, dt, 2 dt, ...`` and ``duration`` (the last step
    may be shorter); ``samples`` is then not used. Plotting a piece seen only at its two ends (a
    rest-to-rest quintic has zero velocity and acceleration there) would show a jump.

    Examples
    --------
    >>> sample_times(5.0, 3, [0.0, 2.5, 5.000000000000001]).tolist()
    [0.0, 0.625, 1.25, 1.875, 2.5, 3.125, 3.75, 4.375, 5.0]
    """
    if dt is None:
        t = np.linspace(0.0, duration, samples)
    else:
        steps = np.arange(0.0, duration, dt)
        t = np.append(steps[steps < duration - 1e-9 * dt], duration)
    bp = np.asarray(breakpoints, float)
    inside = np.searchsorted(t, bp[1:], side="left") - np.searchsorted(t, bp[:-1], side="right")
    sparse = np.flatnonzero(inside < 3)
    if sparse.size:
        h = np.diff(bp)[sparse, None]
        extra = bp[sparse, None] + h * np.array([0.0, 0.25, 0.5, 0.75, 1.0])
        t = np.concatenate((t, extra.ravel()))
    return _times(t, duration)


def _times(t, duration: float) -> np.ndarray:
    """``t`` clipped to ``[0, duration]``, sorted, repeats dropped, ending exactly at ``duration``."""
    return sorted_unique(np.clip(np.concatenate((t, [0.0, duration])), 0.0, duration))


def _ending_at(pp: PiecewisePolynomial, duration: float) -> PiecewisePolynomial:
    """``pp`` with its first breakpoint exactly 0 and its last exactly ``duration``.

    Scaled or summed breakpoints can end an ulp away from the duration; the pieces keep their
    local polynomials, so the motion moves by rounding only, and a sample at ``duration`` is
    then the motion's end.
    """
    bp = pp.breakpoints
    if bp[0] == 0.0 and bp[-1] == duration:
        return pp
    bp = bp.copy()
    bp[0], bp[-1] = 0.0, duration
    return PiecewisePolynomial.from_local(bp, pp.local)


def _motion_ok(arm, obs, pp: PiecewisePolynomial, path) -> bool:
    """The motion is finite, starts and ends on ``path``'s ends, and is certified free and
    within the joint limits over its whole time span (:func:`rapp.motion.certify_motion`)."""
    ends = pp.evaluate([pp.t0, pp.tf])
    return bool(np.isfinite(pp.local).all()
                and np.abs(ends[0] - path[0]).max() <= 1e-9
                and np.abs(ends[1] - path[-1]).max() <= 1e-9
                and certify_motion(arm, pp, obs).free)


def _rest_along(path, duration: float) -> PiecewisePolynomial:
    """Rest-to-rest quintic smoothstep along each segment of ``path`` (m, n), the time shared
    in proportion to joint-space length, ending exactly at ``duration``: the motion stays on
    the polyline (:func:`rapp.trajectory.time_polyline`'s motion, as polynomials)."""
    w = np.asarray(path, float)
    if len(w) < 2 or not step_lengths(w).sum() > 0:
        return time_path(w[:1], duration)              # rest at the start
    w = clean_waypoints(w, None)
    lengths = step_lengths(w)
    bp = np.concatenate(([0.0], np.cumsum(duration * lengths / lengths.sum())))
    bp[-1] = duration
    if np.any(np.diff(bp) <= 0):   # a segment too short to get its own time: equal shares
        bp = np.linspace(0.0, duration, len(w))
    hh = np.diff(bp)[:, None]
    z = np.zeros_like(w[:-1])
    b = quintic_local(hh, w[:-1], w[1:], z, z, z, z)
    return PiecewisePolynomial.from_local(bp, np.moveaxis(b, 0, 1))


def _time_smooth(arm, obs, path, tr):
    """The requested smooth profile of ``tr`` (TrajectorySettings) if it is certified free and
    within limits over its whole time span, else rest-to-rest along the certified polyline:
    ``(t, q, qd, qdd, profile, motion)``."""
    path = np.asarray(path, float)
    if len(path) >= 2:
        pp = _ending_at(time_path(path, tr.duration, profile=tr.profile), tr.duration)
        if _motion_ok(arm, obs, pp, path):
            t, q, qd, qdd = _sample(pp, path, tr.duration, tr.samples, dt=getattr(tr, "dt", None))
            return t, q, qd, qdd, tr.profile, pp
        fallback = f"rest-to-rest per segment (the {tr.profile} curve left the free polyline)"
    else:
        fallback = "rest (start is the goal)"
    pp = _rest_along(path, tr.duration)
    t, q, qd, qdd = _sample(pp, path, tr.duration, tr.samples, every_breakpoint=True)
    return t, q, qd, qdd, fallback, pp


def round_up(x: float, digits: int = 6) -> float:
    """``x`` rounded up to ``digits`` significant digits (a duration that is sure to suffice).

    Examples
    --------
    >>> round_up(1.8750000018), round_up(2.0)
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
        bp.append(clock_after(bp[-1], float(hj)))   # each piece rounded up: never faster than asked
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
                f"{round_up(T_min)} s (the shortest feasible duration)",
                field="trajectory.duration")
    return build(T), T_min


def _sample(pp: PiecewisePolynomial, path, duration: float, samples: int, every_breakpoint=False,
            dt: float | None = None):
    """The motion's samples; ``pp`` must end exactly at ``duration`` (:func:`_ending_at`)."""
    t = sample_times(duration, samples, pp.breakpoints, dt)
    if every_breakpoint:   # every sample chord then lies on one edge of the path
        t = _times(np.concatenate((t, pp.breakpoints)), duration)
    q, qd, qdd = (np.asarray(a, float) for a in pp.sample(t))
    q[0], q[-1] = path[0], path[-1]
    return t, q, qd, qdd


def _time_motion(arm, obs, path, tr, line: bool):
    """Timing under joint limits, or of a line goal: ``(t, q, qd, qdd, profile, motion, info)``."""
    w = clean_waypoints(path, None) if len(path) >= 2 else np.asarray(path, float)
    if len(w) < 2:
        T = tr.duration if tr.duration is not None else MIN_DURATION
        pp = _rest_along(np.asarray(path, float)[:1], T)
        t, q, qd, qdd = _sample(pp, np.asarray(path, float), T, tr.samples)
        return t, q, qd, qdd, "rest (start is the goal)", pp, {"duration_s": T}
    info = {}
    rest = "quintic" if tr.profile in ("quintic", "spline") else "cubic"
    if line:
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
        pp = _ending_at(pp, T)
        t, q, qd, qdd = _sample(pp, w, T, tr.samples, every_breakpoint=True, dt=getattr(tr, "dt", None))
    elif tr.profile == "trapezoidal":
        label = "trapezoidal"
        pp, info["min_duration_s"] = _limited_motion(tr, w, "trapezoidal",
                                                     "trapezoidal motion along the planned path")
        T = tr.duration if tr.duration is not None else pp.tf
        pp = _ending_at(pp, T)
        t, q, qd, qdd = _sample(pp, w, T, tr.samples, dt=getattr(tr, "dt", None))
    else:
        label = tr.profile
        pp, info["min_duration_s"] = _limited_motion(
            tr, w, "uniform", f"{tr.profile} motion along the planned path")
        T = tr.duration if tr.duration is not None else pp.tf
        pp = _ending_at(pp, T)
        t, q, qd, qdd = _sample(pp, w, T, tr.samples, dt=getattr(tr, "dt", None))
        if not _motion_ok(arm, obs, pp, w):   # rest-to-rest along the certified polyline, each segment at its shortest
            label = (f"rest-to-rest quintic per segment (the {tr.profile} curve left the free "
                     "polyline)")
            pp, info["min_duration_s"] = _limited_motion(
                tr, w, "rest-quintic", "rest-to-rest quintic motion along the planned path "
                f"(the {tr.profile} curve leaves the free polyline)")
            T = tr.duration if tr.duration is not None else pp.tf
            pp = _ending_at(pp, T)
            t, q, qd, qdd = _sample(pp, w, T, tr.samples, dt=getattr(tr, "dt", None))
    info["duration_s"] = float(t[-1])
    return t, q, qd, qdd, label, pp, info


@dataclass(frozen=True, eq=False)
class TimedPath:
    """A sampled motion: times ``t`` (k,), ``q``, ``qd``, ``qdd`` (k, n), the ``profile`` as the
    plan reports it, the ``motion`` itself as a :class:`~rapp.trajectory.PiecewisePolynomial`
    (from 0 exactly to the duration; ``q`` is ``motion`` at ``t``, its ends set exactly to the
    path's ends), and ``info`` (``duration_s``, ``min_duration_s``) for the plan's metrics."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    profile: str
    motion: PiecewisePolynomial | None = None
    info: dict = field(default_factory=dict)


def time_route(arm, obstacles, path, trajectory, *, line: bool = False) -> TimedPath:
    """Time the certified polyline ``path`` (m, n) by the settings ``trajectory``.

    Parameters
    ----------
    arm : Arm
    obstacles : iterable of Circle and Polygon
    path : ndarray (m, n)
        Every straight segment between consecutive rows certified free.
    trajectory : TrajectorySettings
    line : bool
        The waypoints are a line goal's: rest-to-rest along each edge, never a spline.

    Raises
    ------
    InvalidValue
        Naming ``trajectory.duration`` when it is too short for the limits, or the binding
        limit when the shortest motion is longer than ``MAX_DURATION``.
    """
    if trajectory.limited or line:
        return TimedPath(*_time_motion(arm, obstacles, path, trajectory, line))
    t, q, qd, qdd, profile, motion = _time_smooth(arm, obstacles, path, trajectory)
    return TimedPath(t, q, qd, qdd, profile, motion)
