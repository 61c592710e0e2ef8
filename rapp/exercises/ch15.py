"""Checks for the exercises of chapter 15, "From path to motion".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['15.1', '15.2', '15.3', '15.4', '15.5']
>>> _lspb_ref(1.2, 1.0, 2.0)
(1.7, 0.5)
>>> round(_unsynchronized_deviation(np.zeros(2), np.array([2.0, 0.5])), 3)
0.294
"""

from __future__ import annotations

import numpy as np

from rapp.exercises.core import Exercise, Judgement, as_number_array, describe, implement, numeric
from rapp.arm import Arm
from rapp.collision import segment_point_distance
from rapp.manipulability import condition_number, manipulability
from rapp.time_scaling import minimum_duration, peak_rates, trapezoidal
from rapp.time_scaling import time_path

__all__ = ["EXERCISES"]


# --- 15.1: the minimum duration of a quintic move --------------------------------------------

_DELTA, _VMAX, _AMAX = 0.5, 1.0, 2.0   # rad, rad/s, rad/s²


def _quintic_minimum() -> float:
    return minimum_duration([0.0, _DELTA], "quintic", _VMAX, _AMAX)


def _cubic_minimum() -> float:
    return minimum_duration([0.0, _DELTA], "cubic", _VMAX, _AMAX)


def _trapezoid_minimum() -> float:
    return minimum_duration([0.0, _DELTA], "trapezoidal", _VMAX, _AMAX)


def _quintic_speed_bound() -> float:
    """The duration at which the quintic's peak speed is exactly vmax (the speed limit alone)."""
    (v,), _ = peak_rates(time_path([0.0, _DELTA], 1.0, "quintic"))
    return float(v / _VMAX)


def _quintic_without_sqrt3() -> float:
    """The acceleration bound with the quintic's peak 10/sqrt(3) taken as 10."""
    _, (a,) = peak_rates(time_path([0.0, _DELTA], 1.0, "quintic"))
    return float(np.sqrt(a * np.sqrt(3.0) / _AMAX))


# --- 15.2: blend time and duration of a trapezoid --------------------------------------------

def _lspb_ref(delta, vmax, amax) -> tuple[float, float]:
    """(T, tb) of the package's minimum-time trapezoid from 0 to delta."""
    pp = trapezoidal(0.0, delta, vmax, amax)
    bp = pp.breakpoints
    return float(bp[-1] - bp[0]), float(bp[1] - bp[0])


def _moves(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (cruise, backwards, triangle, the boundary, long, tiny), then random moves."""
    cases: list[tuple] = [
        (1.2, 1.0, 2.0),      # a trapezoid
        (-1.2, 1.0, 2.0),     # the same move backwards
        (0.3, 1.0, 2.0),      # too short to reach vmax: a triangle
        (0.5, 1.0, 2.0),      # exactly vmax**2 / amax: the cruise has length zero
        (10.0, 0.5, 0.1),     # long, with long blends
        (-1e-3, 5.0, 1.0),    # tiny triangle, backwards
    ]
    for _ in range(50):
        sign = 1.0 if rng.random() < 0.5 else -1.0
        cases.append((sign * float(rng.uniform(0.01, 5.0)), float(rng.uniform(0.1, 3.0)),
                      float(rng.uniform(0.1, 5.0))))
    return cases


def _compare_lspb(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not numbers."
    if g.size != 2:
        return f"returned {g.size} numbers; expected the pair (T, tb)."
    T, tb = (float(x) for x in g.ravel())
    W, Wb = want

    def same(a, b) -> bool:
        return bool(np.isclose(a, b, rtol=1e-9, atol=1e-12))

    if same(T, W) and same(tb, Wb):
        return None
    if same(T, Wb) and same(tb, W):
        return "returned (tb, T); return the pair in the order (T, tb)."
    if not (T > 0 and tb > 0):
        return f"returned {describe(got)}; durations must be positive (is delta negative here?)."
    delta, vmax, amax = args
    d = abs(delta)
    cruise = d >= vmax**2 / amax
    if not cruise and same(T, d / vmax + vmax / amax):
        return ("used the cruise formula, but this move is too short to reach vmax: the profile is "
                "a triangle (when can the joint reach full speed?).")
    if cruise and same(T, 2.0 * np.sqrt(d / amax)) and d > vmax**2 / amax * (1 + 1e-9):
        return ("used the triangle formula, but this move is long enough to cruise at vmax: that "
                "triangle would exceed the speed limit at its peak.")
    if same(T, W):
        return "has the right duration T, but not the right blend time tb (how long does the joint accelerate?)."
    if same(tb, Wb):
        return "has the right blend time tb, but not the right duration T."
    if T < W:
        return "returned a duration T shorter than any motion within vmax and amax allows."
    return "returned a duration T longer than needed: a faster motion within vmax and amax exists."


# --- 15.3: unsynchronized joints leave the segment -------------------------------------------

_SYNC_LIMIT = 1.0          # vmax = amax = 1 for both joints
_MIN_DEVIATION = 0.1       # rad


def _unsynchronized_deviation(p0: np.ndarray, pf: np.ndarray) -> float:
    """Largest distance (rad) from the segment p0 -> pf when each joint runs its own trapezoid."""
    moving = [j for j in range(p0.size) if pf[j] != p0[j]]
    own = {j: trapezoidal(p0[j], pf[j], _SYNC_LIMIT, _SYNC_LIMIT) for j in moving}
    T = max(m.duration for m in own.values())
    ts = np.linspace(0.0, T, 2001)
    q = np.tile(p0, (ts.size, 1))
    for j, m in own.items():
        q[:, j] = m.evaluate(ts)[:, 0]
    return float(segment_point_distance(p0, pf, q).max())


def _counterexample_judge(answer) -> Judgement:
    if answer is None:
        return Judgement(False, "no answer yet.")
    try:
        pair = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
        pair = None
    if pair is None or pair.shape != (2, 2):
        return Judgement(False, f"got {describe(answer)}; expected a pair (p0, pf) of configurations, "
                                "each two joint angles in radians.")
    if not np.all(np.isfinite(pair)) or np.abs(pair).max() > 100.0:
        return Judgement(False, f"got {describe(answer)}; the angles must be finite and at most "
                                "100 rad in size.")
    p0, pf = pair
    delta = np.abs(pf - p0)
    if not delta.any():
        return Judgement(False, "p0 and pf are the same configuration: there is no move to time.")
    if (delta == 0).any():
        return Judgement(False, "only one joint moves, so the arm stays on the segment whatever the "
                                "timing; both joints must move.")
    if np.isclose(delta[0], delta[1], rtol=1e-9, atol=0.0):
        return Judgement(False, "both joints move by the same amount, so their own timings coincide "
                                "and the arm stays on the segment.")
    dev = _unsynchronized_deviation(p0, pf)
    synced = trapezoidal(p0, pf, _SYNC_LIMIT, _SYNC_LIMIT)
    ts = np.linspace(0.0, synced.duration, 2001)
    on = float(segment_point_distance(p0, pf, synced.evaluate(ts)).max())
    if dev <= _MIN_DEVIATION:
        return Judgement(False, f"each joint on its own clock leaves the segment by only {dev:.3f} rad "
                                "here; find a move where it leaves by more than 0.1 rad (how different "
                                "are the joints' own durations?).")
    return Judgement(True, f"right: each joint on its own clock leaves the segment by up to {dev:.3f} rad, "
                           f"while the synchronized move stays within {on:.1e} rad of it.")


# --- 15.4: the condition number of a two-link arm --------------------------------------------

_ARM_LENGTHS = (1.0, 0.5)
_Q = (0.3, np.pi / 3)


def _kappa() -> float:
    return float(condition_number(Arm(list(_ARM_LENGTHS)), list(_Q)))


def _w() -> float:
    return float(manipulability(Arm(list(_ARM_LENGTHS)), list(_Q)))


def _kappa_degrees() -> float:
    return float(condition_number(Arm(list(_ARM_LENGTHS)), [_Q[0], 60.0]))


# --- 15.5: the price of stopping at every waypoint -------------------------------------------

def _stops_judge(answer) -> Judgement:
    if answer is None:
        return Judgement(False, "no answer yet.")
    try:
        w = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
        w = None
    if w is None or w.ndim != 1:
        return Judgement(False, f"got {describe(answer)}; expected a list of joint angles in radians, "
                                "the waypoints of one joint.")
    if not np.all(np.isfinite(w)) or (w.size and np.abs(w).max() > 1000.0):
        return Judgement(False, f"got {describe(answer)}; the angles must be finite and at most 1000 "
                                "rad in size.")
    if w.size > 50:
        return Judgement(False, f"got {w.size} waypoints; a counterexample needs only a few (at most 50).")
    moves = w[np.concatenate([[True], np.diff(w) != 0])] if w.size else w
    if moves.size < 2:
        return Judgement(False, "the waypoints do not move: give at least three different ones in a row.")
    if moves.size == 2:
        return Judgement(False, "with one move (two waypoints) the trapezoid is the fastest of all "
                                "rest-to-rest motions, so it cannot lose; use at least three waypoints.")
    t_trap = minimum_duration(moves, "trapezoidal", 1.0, 1.0)
    t_cubic = minimum_duration(moves, "cubic", 1.0, 1.0)
    if t_trap <= t_cubic * (1 + 1e-9):
        return Judgement(False, f"on these waypoints the trapezoid takes {t_trap:.3f} s and the cubic "
                                f"{t_cubic:.3f} s: the trapezoid is not slower. Where does a stop cost "
                                "the most time?")
    return Judgement(True, f"right: stopping at every waypoint, the trapezoid takes {t_trap:.3f} s, the "
                           f"cubic, which passes them at speed, {t_cubic:.3f} s.")


EXERCISES = (
    Exercise(
        "15.1", 15, "numeric", "Minimum duration of a quintic move", 1,
        "a number: the shortest duration in seconds",
        numeric(_quintic_minimum,
                mistakes=[(_quintic_speed_bound, "that duration keeps the speed within vmax, but the "
                                                 "acceleration limit asks for more time here."),
                          (_cubic_minimum, "that is the cubic's minimum duration; this exercise asks "
                                           "for the quintic."),
                          (_trapezoid_minimum, "that is the trapezoid's minimum duration; this exercise "
                                               "asks for the quintic."),
                          (_quintic_without_sqrt3, "the quintic's normalized peak acceleration is "
                                                   "10/√3, not 10.")],
                hint="take the larger of the durations set by the speed limit and by the "
                     "acceleration limit, eq. ch15-tmin."),
    ),
    Exercise(
        "15.2", 15, "implement", "Blend time and duration of a trapezoid", 2,
        "a function lspb(delta, vmax, amax) returning (T, tb)",
        implement(_lspb_ref, _moves, call="lspb(delta, vmax, amax)", names=("delta", "vmax", "amax"),
                  compare=_compare_lspb, seed=152),
    ),
    Exercise(
        "15.3", 15, "argue", "Unsynchronized joints leave the segment", 2,
        "a pair (p0, pf) of 2-joint configurations in radians",
        _counterexample_judge,
    ),
    Exercise(
        "15.4", 15, "numeric", "Condition number of a two-link arm", 1,
        "a number: the condition number (no unit)",
        numeric(_kappa,
                mistakes=[(_w, "that is the manipulability w = σ1 σ2; the condition number is the "
                               "ratio σ1 / σ2."),
                          (lambda: 1.0 / _kappa(), "that is σ2 / σ1; the condition number is at "
                                                   "least 1."),
                          (lambda: _kappa() ** 2, "that is the ratio of the eigenvalues of J Jᵀ, "
                                                  "which are the squares of the singular values."),
                          (_kappa_degrees, "θ2 is π/3 rad; the angle was taken in degrees.")],
                hint="the singular values of J are the square roots of the eigenvalues of J Jᵀ."),
    ),
    Exercise(
        "15.5", 15, "argue", "The price of stopping at every waypoint", 2,
        "a list of waypoints of one joint, in radians",
        _stops_judge,
    ),
)
