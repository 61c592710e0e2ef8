"""Checks for the exercises of chapter 11, "Case study: cubic via points around an obstacle".

Every expected value is computed here from the package (``rapp.trajectory`` and
``rapp.cases.via_point_detour``) with the seed's data, never typed in.

Examples
--------
>>> [ex.id for ex in EXERCISES]
['11.1', '11.2', '11.3', '11.4', '11.5', '11.6', '11.7']
>>> round(_fastest_time_dc(), 6)
6.75
>>> _via_velocities_ref([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 3.0, 2.0]).tolist()
[0.0, 1.5, 0.0, 0.0]
>>> _most_backward(trajectory.via_points([0.0, 1.0, 2.0], [0.0, 1.0, 2.0]), 1.0)[0] >= 0
True
"""

from __future__ import annotations

import numpy as np

from rapp import trajectory
from rapp.exercises.core import Exercise, Judgement, as_number_array, describe, implement, numeric

__all__ = ["EXERCISES"]

# Seed 002's data (the chapter's first code cell).
_A, _B, _C = np.array([2.0, 5.0]), np.array([5.0, 8.0]), np.array([14.0, 7.0])
_V_B = np.array([0.25, 0.25])
_REST = np.zeros(2)
_CENTER, _RADIUS = np.array([10.0, 7.0]), 1.5
_D2 = np.array([10.20, 8.54])          # Task 2's D
_D3 = np.array([9.86, 5.32])           # Task 3's D
_TIMES1 = np.array([0.0, 3.0, 8.0])
_TIMES2 = np.array([0.0, 3.0, 5.5, 8.0])


# --- 11.1: Constraint 1 read literally -------------------------------------------------------

def _literal_b_ab(v_b: float = 0.0) -> np.ndarray:
    """(b3, b2, b1, b0) of the y segment AB with y_B' = v_b, in the seed's (descending) order."""
    return trajectory.cubic(_TIMES1[0], _TIMES1[1], _A[1], _B[1], 0.0, v_b)[::-1]


# --- 11.2: when segment DC of Task 2 is fastest ----------------------------------------------

def _task2():
    return trajectory.via_points(_TIMES2, [_A, _B, _D2, _C], velocities=[_REST, _V_B, _REST, _REST])


def _fastest_time_dc(local: bool = False) -> float:
    """Rest to rest, so the speed peaks where the acceleration 2 b2 + 6 b3 tau vanishes."""
    b = _task2().local[2, :, 0]
    tau = -b[2] / (3.0 * b[3])
    return float(tau if local else _TIMES2[2] + tau)


# --- 11.3: reach D later -----------------------------------------------------------------------

def _late_clearance() -> float:
    from rapp.cases.via_point_detour import path_clearance

    return float(path_clearance(_D2, _B, _C, _CENTER, v_start=_V_B, times=(3.0, 6.0, 8.0)))


def _straight_bd() -> float:
    from rapp.collision import segment_point_distance

    return float(segment_point_distance(_B, _D2, _CENTER))


# --- 11.4 and 11.5: the heuristic via-point velocities -----------------------------------------

def _heuristic_at_b(sign_rule: bool = True, divide: bool = True) -> np.ndarray:
    """The heuristic velocity at B of Task 1, or what a slip in the rule gives."""
    if sign_rule and divide:
        return trajectory.heuristic_velocities(_TIMES1, [_A, _B, _C])[1]
    steps = np.diff([_A, _B, _C], axis=0) / (np.diff(_TIMES1)[:, None] if divide else 1.0)
    mean = 0.5 * steps[0] + 0.5 * steps[1]
    return mean if not sign_rule else np.where(steps[0] * steps[1] > 0, mean, 0.0)


def _via_velocities_ref(times, positions) -> np.ndarray:
    return trajectory.heuristic_velocities(times, positions).ravel()


def _via_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (a turn, uneven times, two points, a flat segment, falling data), then random."""
    cases: list[tuple] = [
        (np.array([0.0, 1.0, 2.0, 3.0]), np.array([0.0, 1.0, 3.0, 2.0])),    # a turn at index 2
        (np.array([0.0, 2.0, 3.0, 7.0]), np.array([0.0, 4.0, 5.0, 1.0])),    # uneven time steps
        (np.array([0.0, 1.5]), np.array([0.0, 5.0])),                        # only the two ends
        (np.array([0.0, 1.0, 2.0, 3.0]), np.array([1.0, 1.0, 2.0, 3.0])),    # a flat segment
        (np.array([0.0, 0.5, 2.5, 3.0]), np.array([3.0, 2.0, 0.0, -1.0])),   # falling, uneven
        (_TIMES1.copy(), np.array([2.0, 5.0, 14.0])),                        # Task 1, x
    ]
    for _ in range(50):
        k = int(rng.integers(3, 9))
        times = np.concatenate(([float(rng.uniform(-2.0, 2.0))], rng.uniform(0.2, 3.0, k - 1))).cumsum()
        if rng.random() < 0.3:
            positions = rng.integers(-3, 4, k).astype(float)                 # repeats: flat segments
        else:
            positions = rng.uniform(-5.0, 5.0, k)
        cases.append((times, positions))
    return cases


def _compare_via(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not numbers."
    times, positions = (np.asarray(a, dtype=float) for a in args)
    k = len(times)
    if g.size != k:
        return f"returned {g.size} numbers; expected one velocity per via point ({k})."
    g = g.reshape(k)
    close = np.isclose(g, want, rtol=1e-9, atol=1e-9)
    if close.all():
        return None
    i = int(np.argmin(close))
    shown = f"returned {describe(g)}: the velocity at index {i} ({describe(float(g[i]))})"
    if i in (0, k - 1):
        return f"{shown} is wrong; the motion starts and ends at rest."
    left = (positions[i] - positions[i - 1]) / (times[i] - times[i - 1])
    right = (positions[i + 1] - positions[i]) / (times[i + 1] - times[i])
    if left * right < 0:
        return (f"{shown} is wrong: the slopes on either side have opposite signs there (the path "
                "turns back), and the heuristic stops at such a point.")
    if left * right == 0:
        return (f"{shown} is wrong: a neighbouring slope is zero there (a flat segment); the rule "
                "wants both slopes of the same strict sign, otherwise it stops.")
    undivided = 0.5 * (positions[i] - positions[i - 1]) + 0.5 * (positions[i + 1] - positions[i])
    if np.isclose(g[i], undivided, rtol=1e-9, atol=1e-9):
        return (f"{shown} is the mean of the position differences; a slope is a difference "
                "divided by its time step.")
    return f"{shown} is not the mean of the two neighbouring slopes."


# --- 11.6 and 11.7: monotone data, a motion that goes backwards -------------------------------

def _most_backward(pp, direction: float) -> tuple[float, float]:
    """Smallest ``direction * velocity`` over the whole trajectory (exact per segment), and when.

    Each cubic segment's velocity is a quadratic in local time: its minimum over ``[0, h]`` is at
    an end or at the vertex.
    """
    worst, when = np.inf, 0.0
    for i in range(len(pp.breakpoints) - 1):
        h = pp.breakpoints[i + 1] - pp.breakpoints[i]
        b = pp.local[i, :, 0]
        cand = [0.0, h]
        if b[3] != 0:
            vertex = -b[2] / (3.0 * b[3])
            if 0.0 < vertex < h:
                cand.append(vertex)
        tau = np.array(cand)
        v = direction * (b[1] + 2 * b[2] * tau + 3 * b[3] * tau**2)
        j = int(np.argmin(v))
        if v[j] < worst:
            worst, when = float(v[j]), float(pp.breakpoints[i] + tau[j])
    return worst, when


def _goes_backward(pp, times, positions, direction) -> tuple[bool, float]:
    scale = float(np.abs(np.diff(positions) / np.diff(times)).max())
    worst, when = _most_backward(pp, direction)
    return worst < -1e-9 * max(scale, 1e-300), when


def _judge_heuristic_counterexample(answer) -> Judgement:
    """``(times, positions)``: monotone positions whose heuristic cubic trajectory turns back."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (times, positions).")
    try:
        times, positions = answer
        times = np.asarray(times, dtype=float)
        positions = np.asarray(positions, dtype=float)
    except Exception:
        return Judgement(False, f"expected a tuple (times, positions) of two 1-D arrays; got {describe(answer)}.")
    if times.ndim != 1 or positions.shape != times.shape or not 3 <= times.size <= 50:
        return Judgement(False, "times and positions must be 1-D arrays of the same length, 3 to 50 via points.")
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(positions))):
        return Judgement(False, "times and positions must be finite numbers.")
    if np.any(np.diff(times) <= 0):
        return Judgement(False, "times must be strictly increasing.")
    steps = np.diff(positions)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        return Judgement(False, "the positions must be strictly monotone (all increasing or all "
                                "decreasing): the claim is about monotone data.")
    try:
        pp = trajectory.via_points(times, positions)          # heuristic velocities, rest at the ends
    except ValueError as exc:
        return Judgement(False, f"those via points do not make a trajectory: {exc}.")
    back, when = _goes_backward(pp, times, positions, float(np.sign(steps[0])))
    if back:
        return Judgement(True, f"the positions are monotone, but the heuristic cubics turn back "
                               f"near t = {when:.3g}: a counterexample.")
    return Judgement(False, "with these via points every segment stays monotone. A segment turns back "
                            "when an end velocity is several times its own slope: make a short, "
                            "shallow step between two steep ones.")


_X3 = np.array([_A[0], _B[0], _D3[0], _C[0]])      # Task 3's x: 2, 5, 9.86, 14


def _judge_spline_times(answer) -> Judgement:
    """``(t_B, t_D)``: the spline's x turns back, the heuristic cubics' x does not."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (t_B, t_D).")
    got = as_number_array(answer)
    if isinstance(got, str):
        return Judgement(False, got + " Pass two times (t_B, t_D).")
    if got.shape != (2,):
        return Judgement(False, f"expected two times (t_B, t_D), got shape {got.shape}.")
    t_b, t_d = (float(v) for v in got)
    times = np.array([_TIMES2[0], t_b, t_d, _TIMES2[-1]])
    if not (np.all(np.diff(times) > 0)):
        return Judgement(False, f"the times must satisfy {_TIMES2[0]:g} < t_B < t_D < {_TIMES2[-1]:g}.")
    try:
        spline = trajectory.via_points(times, _X3, profile="spline")
        cubic = trajectory.via_points(times, _X3)
    except ValueError as exc:
        return Judgement(False, f"those times do not make a trajectory: {exc}.")
    s_back, s_when = _goes_backward(spline, times, _X3, 1.0)
    c_back, c_when = _goes_backward(cubic, times, _X3, 1.0)
    if not s_back:
        return Judgement(False, f"with t_B = {t_b:g} s and t_D = {t_d:g} s the spline's x never goes "
                                "backwards. The spline shares each via point's velocity between two "
                                "segments of very different lengths: make them very unequal.")
    if c_back:
        return Judgement(False, f"the spline's x goes backwards (near t = {s_when:.3g} s), but so does "
                                f"the heuristic cubics' (near t = {c_when:.3g} s); find times for which "
                                "only the spline turns back.")
    return Judgement(True, f"the spline's x goes backwards near t = {s_when:.3g} s while the heuristic "
                           "cubics' x keeps increasing: the spline overshoots.")


EXERCISES = (
    Exercise(
        "11.1", 11, "numeric", "Constraint 1 read literally", 1,
        "an array (b3, b2, b1, b0): the coefficients of y on segment AB, in the seed's order",
        numeric(_literal_b_ab,
                mistakes=[(lambda: _literal_b_ab(0.25), "those are the printed tables, with ẏ_B = 0.25; "
                                                        "read Constraint 1 literally, ẏ_B = 0."),
                          (lambda: _literal_b_ab()[::-1], "that is ascending order (b0 first); give "
                                                          "(b3, b2, b1, b0), the seed's order."),
                          (lambda: np.append(_literal_b_ab()[:3], _A[0]),
                           "b0 is the position y_A at t = 0, not x_A (the seed's eq. 21 makes the "
                           "same slip).")],
                hint="a rest-to-rest cubic over T = 3 s and Δy = 3 m: b2 = 3Δy/T², b3 = -2Δy/T³."),
    ),
    Exercise(
        "11.2", 11, "numeric", "When segment DC is fastest", 1,
        "a number: the absolute time t in seconds at which the speed on segment DC of Task 2 peaks",
        numeric(_fastest_time_dc,
                mistakes=[(lambda: _fastest_time_dc(local=True),
                           "that is the local time on the segment; give the absolute time t."),
                          (lambda: _TIMES2[2], "the tip is at rest at D; the speed peaks later."),
                          (lambda: _TIMES2[3], "the tip is at rest at C; the speed peaks earlier.")],
                hint="the speed peaks where the acceleration is zero."),
    ),
    Exercise(
        "11.3", 11, "numeric", "Reach D later", 2,
        "a number: the distance in metres from the cubic path B → D → C to the obstacle's centre",
        numeric(_late_clearance, abs_tol=5e-4,
                mistakes=[(lambda: _late_clearance() - _RADIUS,
                           "that is the distance to the disc's surface; the question asks for the centre."),
                          (lambda: _RADIUS, "that is the obstacle's radius, as if the path touched the disc; "
                                           "if you rounded, give four decimals: it clears the disc."),
                          (_straight_bd, "that is the distance of the straight segment BD; the path "
                                         "comes closer to the centre elsewhere."),
                          (lambda: 0.0, "right that the distance does not change, but the exercise asks "
                                        "for its value.")],
                hint="which segment comes closest, and does its shape depend on the via time?"),
    ),
    Exercise(
        "11.4", 11, "numeric", "The heuristic velocity at B", 1,
        "an array (ẋ_B, ẏ_B) in m/s: the heuristic velocity at B of Task 1",
        numeric(_heuristic_at_b,
                mistakes=[(lambda: _heuristic_at_b(sign_rule=False),
                           "the y slopes on either side of B have opposite signs; the heuristic stops "
                           "such a coordinate."),
                          (lambda: _heuristic_at_b(divide=False),
                           "those are mean position differences; divide each by its time step."),
                          (lambda: _heuristic_at_b(sign_rule=False, divide=False),
                           "divide each difference by its time step, and mind the signs of the y slopes."),
                          (lambda: _V_B, "that is the seed's prescribed velocity; the exercise asks for "
                                         "the heuristic one.")],
                hint="per coordinate: the slopes of AB and BC, then their mean or 0."),
    ),
    Exercise(
        "11.5", 11, "implement", "Heuristic via-point velocities", 2,
        "a function via_velocities(times, positions) returning one velocity per via point",
        implement(_via_velocities_ref, _via_cases, call="via_velocities(times, positions)",
                  names=("times", "positions"), compare=_compare_via, seed=115),
    ),
    Exercise(
        "11.6", 11, "argue", "Monotone via points, a motion that turns back", 2,
        "a tuple (times, positions): strictly monotone positions whose heuristic cubic trajectory "
        "turns back",
        _judge_heuristic_counterexample,
    ),
    Exercise(
        "11.7", 11, "argue", "Via times for which the spline overshoots", 3,
        "a tuple (t_B, t_D) of via times in seconds",
        _judge_spline_times,
    ),
)
