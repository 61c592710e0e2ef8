"""Checks for the exercises of chapter 8, "Trajectories".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['8.1', '8.2', '8.3', '8.4']
>>> round(float(_peak(trajectory.cubic(0.0, 2.0, 0.0, 1.0), 1, 0.0, 2.0)), 6)
0.75
"""

from __future__ import annotations

import numpy as np

from rapp import trajectory
from rapp.exercises.core import Exercise, as_number_array, describe, implement, numeric

__all__ = ["EXERCISES"]


def _peak(coeffs, derivative: int, t0: float, tf: float) -> float:
    """Largest ``|p^(derivative)(t)|`` on ``[t0, tf]``: at an end or where the next derivative is 0."""
    c = np.asarray(coeffs, dtype=float)
    nxt = np.polynomial.Polynomial(c).deriv(derivative + 1)
    roots = nxt.roots() if nxt.degree() > 0 else np.array([])
    inside = [r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-9 and t0 <= r.real <= tf]
    candidates = np.array([t0, tf, *inside])
    return float(np.abs(trajectory.polyval(c, candidates, derivative)).max())


# --- 8.1 and 8.3: peaks of rest-to-rest moves ------------------------------------------------

_DELTA, _T = 1.0, 2.0   # 0 -> 1 rad in 2 s


def _cubic_peak_velocity() -> float:
    return _peak(trajectory.cubic(0.0, _T, 0.0, _DELTA), 1, 0.0, _T)


def _quintic_peak_velocity() -> float:
    return _peak(trajectory.quintic(0.0, _T, 0.0, _DELTA), 1, 0.0, _T)


def _cubic_peak_acceleration() -> float:
    return _peak(trajectory.cubic(0.0, _T, 0.0, _DELTA), 2, 0.0, _T)


def _quintic_peak_acceleration() -> float:
    return _peak(trajectory.quintic(0.0, _T, 0.0, _DELTA), 2, 0.0, _T)


# --- 8.2: cubic coefficients in local time ---------------------------------------------------

def _cubic_ref(h, p0, pf, v0, vf):
    return trajectory.cubic_local(h, p0, pf, v0, vf)


def _segments(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (rest to rest, a move back to the start, short and long segments), then random."""
    cases: list[tuple] = [
        (2.0, 0.0, 1.0, 0.0, 0.0),      # rest to rest
        (1.0, 0.5, 0.5, 1.0, -1.0),     # back to where it started
        (3.0, -1.0, 2.0, 0.5, 0.0),     # v0 only
        (0.1, 0.0, -0.2, 0.0, 1.5),     # short segment, vf only
        (20.0, 3.0, -4.0, -0.3, 0.7),   # long segment
    ]
    for _ in range(50):
        h = float(rng.uniform(0.2, 5.0))
        p0, pf, v0, vf = (float(x) for x in rng.uniform(-3.0, 3.0, 4))
        cases.append((h, p0, pf, v0, vf))
    return cases


def _compare_coeffs(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not numbers."
    w = np.asarray(want, dtype=float)
    if g.size != 4:
        return f"returned {g.size} numbers; expected the 4 coefficients (a0, a1, a2, a3)."
    g = g.reshape(4)

    def same(a, b) -> bool:
        return bool(np.allclose(a, b, rtol=1e-9, atol=1e-9))

    if same(g, w):
        return None
    h, p0, pf, v0, vf = args
    if same(g[::-1], w):
        return ("returned the coefficients in descending order; return (a0, a1, a2, a3), "
                "ascending powers of t.")
    if v0 != vf and same(g, _cubic_ref(h, p0, pf, vf, v0)):
        return "meets p(0) = p0 and p(h) = pf, but with v0 and vf swapped."
    poly = g
    names = ("p(0) = p0", "p'(0) = v0", "p(h) = pf", "p'(h) = vf")
    values = (trajectory.polyval(poly, 0.0), trajectory.polyval(poly, 0.0, 1),
              trajectory.polyval(poly, h), trajectory.polyval(poly, h, 1))
    missed = [n for n, got_v, want_v in zip(names, values, (p0, v0, pf, vf))
              if not np.isclose(got_v, want_v, rtol=1e-9, atol=1e-9)]
    return (f"returned {describe(got)}, a cubic that misses {', '.join(missed)}"
            " (put your polynomial back into the four end conditions).")


# --- 8.4: the shortest cubic move under a speed limit ----------------------------------------

def _shortest_ref(delta, vmax) -> float:
    """The peak speed of a cubic scales as 1/T: measure it at T = 1 with the package, then scale."""
    return _peak(trajectory.cubic(0.0, 1.0, 0.0, delta), 1, 0.0, 1.0) / vmax


def _moves(rng: np.random.Generator) -> list[tuple]:
    cases: list[tuple] = [(1.0, 1.0), (-1.0, 0.5), (1e-3, 10.0), (100.0, 0.1), (-2.5, 3.0)]
    for _ in range(50):
        sign = 1.0 if rng.random() < 0.5 else -1.0
        cases.append((sign * float(rng.uniform(0.01, 5.0)), float(rng.uniform(0.1, 5.0))))
    return cases


def _compare_duration(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not a number."
    if g.shape != ():
        return f"returned an array of shape {g.shape}; expected one duration T."
    T = float(g)
    if np.isclose(T, want, rtol=1e-9, atol=0.0):
        return None
    if T <= 0:
        return f"returned {describe(got)}; a duration must be positive (is delta negative here?)."
    delta, vmax = args
    speed = _peak(trajectory.cubic(0.0, T, 0.0, delta), 1, 0.0, T)
    if speed > vmax:
        return (f"returned {describe(got)}, too short: the cubic of that duration peaks above vmax "
                "(where does its velocity peak, and how large is it there?).")
    return (f"returned {describe(got)}, longer than needed: that cubic never reaches vmax, "
            "so a shorter one still keeps |v| <= vmax.")


EXERCISES = (
    Exercise(
        "8.1", 8, "numeric", "Peak velocity of a cubic", 1,
        "a number: the peak velocity in rad/s",
        numeric(_cubic_peak_velocity,
                mistakes=[(lambda: _DELTA / _T, "that is the average velocity Δ/T; the cubic starts "
                                                "and ends at rest, so its peak is higher."),
                          (_quintic_peak_velocity, "that is the quintic's peak; this exercise asks "
                                                   "for the cubic."),
                          (lambda: 3 * _DELTA / _T, "find where the velocity peaks (where q'' = 0) and "
                                                    "evaluate q' there; a factor is off.")],
                hint="differentiate the cubic of eq. ch08-cubic and evaluate its velocity where q'' = 0."),
    ),
    Exercise(
        "8.2", 8, "implement", "Cubic coefficients in local time", 2,
        "a function cubic_coeffs(h, p0, pf, v0, vf) returning (a0, a1, a2, a3)",
        implement(_cubic_ref, _segments, call="cubic_coeffs(h, p0, pf, v0, vf)",
                  names=("h", "p0", "pf", "v0", "vf"), compare=_compare_coeffs, seed=82),
    ),
    Exercise(
        "8.3", 8, "numeric", "Peak acceleration of a quintic", 2,
        "a number: the peak |acceleration| in rad/s²",
        numeric(_quintic_peak_acceleration,
                mistakes=[(_cubic_peak_acceleration, "that is the cubic's peak acceleration (at its "
                                                     "ends); the quintic's is zero at the ends."),
                          (_quintic_peak_velocity, "that is the quintic's peak velocity, not its "
                                                   "acceleration."),
                          (lambda: _quintic_peak_acceleration() * _T ** 2,
                           "that is the peak for T = 1 s; the acceleration scales as Δ/T²."),
                          (lambda: _quintic_peak_acceleration() * _T,
                           "the acceleration scales as Δ/T², not Δ/T."),
                          (lambda: 0.0, "that is the acceleration at the ends and at mid-time; "
                                        "the peak lies in between, where q''' = 0.")],
                hint="the peak is where the jerk q''' is zero, inside the move; scale by Δ/T²."),
    ),
    Exercise(
        "8.4", 8, "argue", "The shortest cubic move under a speed limit", 2,
        "a function shortest(delta, vmax) returning the shortest duration T in seconds",
        implement(_shortest_ref, _moves, call="shortest(delta, vmax)", names=("delta", "vmax"),
                  compare=_compare_duration, seed=84),
    ),
)
