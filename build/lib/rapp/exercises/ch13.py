"""Checks for the exercises of chapter 13, "Case study: a 2-DOF model-based arm".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['13.1', '13.2', '13.3', '13.4']
>>> _count(2.0, 1.25, 2.0, 1.0), _count(2.0, 1.25, 3.25, 0.0), _count(2.0, 1.25, 0.3, -0.2)
(2, 1, 0)
>>> _count(1.5, 1.5, 0.0, 0.0)
inf
"""

from __future__ import annotations

import math

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.exercises.core import (CLOSE_FACTOR, TOLERANCE_ANGLES, Exercise, Judgement, as_number_array, close,
                                 describe, implement, numeric)
from rapp.ik import ik_2link

__all__ = ["EXERCISES"]

_ARM = (2.0, 1.25)          # the chapter's arm, L = (2, 1.25) m
_BASE_TOL = 1e-9            # a target this close to the base counts as the base (13.4)


def _same_angles(a, b, atol: float) -> bool:
    """Equal modulo 2 pi, componentwise (nan only where both are nan)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape or not np.array_equal(np.isnan(a), np.isnan(b)):
        return False
    ok = ~np.isnan(a)
    return bool(np.all(np.abs(wrap_angle(a[ok] - b[ok])) <= atol))


# --- 13.1: the elbow angles of the target (0, 1) ----------------------------------------------

def _elbows_0_1() -> np.ndarray:
    """theta_2 of both solutions for the target (0, 1), elbow-down first."""
    return ik_2link(_ARM, [0.0, 1.0])[:, 1]


def _interior_angle_0_1() -> np.ndarray:
    """The law-of-cosines angle of the triangle at the elbow, pi - |theta_2|, with both signs."""
    l1, l2 = _ARM
    inner = math.acos((l1**2 + l2**2 - 1.0) / (2 * l1 * l2))
    return np.array([inner, -inner])


def _judge_elbows(answer) -> Judgement:
    got = as_number_array(answer)
    if isinstance(got, str):
        return Judgement(False, got + ".")
    want = _elbows_0_1()
    if got.size != want.size:
        return Judgement(False, f"you passed {got.size} elbow angle(s), one per solution: count the "
                                "solutions first (where does r = 1 lie relative to the annulus "
                                "eq. ch13-annulus?), then pass one θ2 per solution.")
    return numeric(_elbows_0_1, angles=True, mistakes=[
        (lambda: _elbows_0_1()[::-1], "the right angles in the wrong order; pass elbow-down (θ2 ≥ 0) "
                                      "first, then elbow-up."),
        (lambda: np.degrees(_elbows_0_1()), "those look like degrees; pass radians."),
        (lambda: np.degrees(_elbows_0_1()[::-1]), "those look like degrees (and elbow-up first); "
                                                  "pass radians, elbow-down first."),
        (_interior_angle_0_1, "that is the triangle's interior angle at the elbow (law of cosines "
                              "with L1² + L2² − r² on top), π − |θ2|; θ2 is measured from the "
                              "direction of the first link, eq. ch13-cos."),
        (lambda: ik_2link(_ARM, [0.0, 1.0])[:, 0], "those are the shoulder angles θ1; the exercise "
                                                   "asks for the elbow angles θ2."),
    ], hint="cos θ2 = (x² + y² − L1² − L2²) / (2 L1 L2), eq. ch13-cos, then θ2 = ±arccos, "
            "elbow-down (+) first.")(got.reshape(want.shape))


# --- 13.2: the elbow on the right -------------------------------------------------------------

_TARGET_RIGHT = (0.0, -2.5)


def _right_and_left():
    """The solution of (0, -2.5) whose elbow has x > 0, and the other one."""
    sols = ik_2link(_ARM, _TARGET_RIGHT)
    elbow_x = [Arm(_ARM).joint_positions(q)[1, 0] for q in sols]
    right = int(np.argmax(elbow_x))
    return sols[right], sols[1 - right]


def _judge_right_elbow(answer) -> Judgement:
    got = as_number_array(answer)
    if isinstance(got, str):
        return Judgement(False, got + ".")
    if got.shape != (2,):
        return Judgement(False, f"expected a configuration (θ1, θ2), two numbers; got shape {got.shape}.")
    right, left = _right_and_left()
    if close(got, right, angles=True):
        return Judgement(True, f"{describe(answer)} is right (to three significant figures, modulo 2π).")
    if close(got, left, angles=True):
        return Judgement(False, f"{describe(answer)} reaches the target, but its elbow is at negative x, "
                                "on the left of the line; take the other solution.")
    if close(got, right, CLOSE_FACTOR, angles=True):
        return Judgement(False, f"{describe(answer)} is close but not within the tolerance; give more digits.")
    if close(np.radians(got), right, angles=True) or close(np.radians(got), left, angles=True):
        return Judgement(False, f"{describe(answer)} looks like degrees; pass radians.")
    tip = Arm(_ARM).end_effector(got)
    if np.hypot(*(tip - _TARGET_RIGHT)) > 1e-2:
        return Judgement(False, f"{describe(answer)} puts the tip at {describe(tip)}, not on the target "
                                "(0, -2.5); compute the two solutions with eq. ch13-cos and ch13-q1.")
    return Judgement(False, f"{describe(answer)} is not it; the elbow of (θ1, θ2) is at "
                            "L1 (cos θ1, sin θ1).")


_judge_elbows.tolerance = _judge_right_elbow.tolerance = TOLERANCE_ANGLES


# --- 13.3: both analytic solutions ------------------------------------------------------------

def _ik2_ref(L1, L2, x, y):
    return ik_2link((L1, L2), (x, y))


def _at_base_of_equal_arm(L1, L2, x, y) -> bool:
    return L1 == L2 and math.hypot(x, y) <= _BASE_TOL


def _on_circle(L1, L2, x, y) -> bool:
    r = math.hypot(x, y)
    return min(abs(r - (L1 + L2)), abs(r - abs(L1 - L2))) <= 1e-9


def _ik_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (x < 0, the outer and inner circles, rounding past a circle, the hole, the base
    of an arm with L1 = L2, L1 < L2), then random arms and targets well inside or well outside."""
    a = 0.4                                          # (3.25 cos a)^2 + (3.25 sin a)^2 > 3.25^2
    cases: list[tuple] = [
        (2.0, 1.25, 2.0, 1.0),                       # the chapter's target 0
        (2.0, 1.25, -1.5, 1.8),                      # x < 0
        (2.0, 1.25, 3.25, 0.0),                      # on the outer circle, exactly
        (2.0, 1.25, -0.75, 0.0),                     # on the inner circle, exactly
        (2.0, 1.25, 3.25 * math.cos(a), 3.25 * math.sin(a)),  # on the outer circle, cos q2 = 1 + 4e-16
        (2.0, 1.25, 0.3, -0.2),                      # in the hole
        (2.0, 1.25, 3.0, 2.0),                       # beyond the outer circle
        (1.25, 2.0, 0.0, 1.0),                       # L1 < L2: L1 + L2 cos q2 < 0
        (1.25, 2.0, 0.75, 0.0),                      # L1 < L2, on the inner circle
        (1.5, 1.5, 0.0, 0.0),                        # the base of an arm with L1 = L2
    ]
    for _ in range(50):
        l1, l2 = (float(v) for v in rng.uniform(0.2, 3.0, 2))
        if rng.random() < 0.1:
            l2 = l1
        r_in, r_out = abs(l1 - l2), l1 + l2
        kind = rng.random()
        if kind < 0.7:
            r = float(rng.uniform(r_in + 1e-3, r_out - 1e-3))
        elif kind < 0.85:
            r = float(rng.uniform(r_out + 1e-3, r_out + 2.0))
        else:
            r = float(rng.uniform(0.0, r_in - 1e-3)) if r_in > 2e-3 else float(rng.uniform(r_out + 1e-3, r_out + 2.0))
        phi = float(rng.uniform(-math.pi, math.pi))
        cases.append((l1, l2, r * math.cos(phi), r * math.sin(phi)))
    return cases


def _compare_ik(got, want, args) -> str | None:
    if got is None:
        return "returned None (a missing return?)."
    try:
        g = np.asarray(got, dtype=float)
    except Exception:
        return f"returned {describe(got)}, not an array of angles."
    if np.isinf(g).any():
        return f"returned {describe(got)}, which is infinite; use nan for an unreachable target."
    if g.shape != (2, 2):
        return f"returned shape {g.shape}; expected (2, 2): one row (θ1, θ2) per elbow."
    L1, L2, x, y = args
    w = np.asarray(want, dtype=float)
    reach = not np.isnan(w).any()
    if not reach:
        if np.isnan(g).all():
            return None
        return ("returned numbers for a target outside the annulus eq. ch13-annulus; an unreachable "
                "target has no solution: return nan in every entry.")
    if np.isnan(g).any():
        if _on_circle(L1, L2, x, y):
            return ("returned nan for a target on a boundary circle (up to rounding): there cos θ2 "
                    "can come out a hair beyond ±1, where arccos is nan (and r a hair beyond the "
                    "circle, where a strict test says unreachable); allow a tolerance of about 1e-9 "
                    "and clip cos θ2 to [-1, 1].")
        return "returned nan for a reachable target (inside the annulus eq. ch13-annulus)."
    if _at_base_of_equal_arm(L1, L2, x, y):
        if np.all(np.abs(wrap_angle(g[:, 1] - math.pi)) <= 1e-7):
            return None         # every θ1 reaches the base with the arm folded
        return "at the base of an arm with L1 = L2 the arm must be folded, θ2 = ±π, in both rows."
    if _same_angles(g, w, 1e-7):
        return None
    if _same_angles(g[::-1], w, 1e-7):
        return ("returned the two elbows in the other order: row 0 must be elbow-down (θ2 ≥ 0), "
                "row 1 elbow-up (θ2 ≤ 0).")
    if _same_angles(g[:, 1], w[:, 1], 1e-7) and np.all(np.abs(np.abs(wrap_angle(g[:, 0] - w[:, 0])) - math.pi) <= 1e-7):
        return ("returned θ1 off by π: atan(y / x) loses the quadrant (it cannot tell (x, y) from "
                "(-x, -y)); use atan2, in both terms of eq. ch13-q1.")
    tips = Arm((L1, L2)).end_effector(g)
    miss = np.hypot(*(tips - np.array([x, y])).T)
    bad = int(np.argmax(miss))
    if miss[bad] > 1e-6:
        return (f"returned row {bad} = {describe(g[bad])}, which puts the tip at {describe(tips[bad])}, not on the "
                "target; check the signs in eq. ch13-q1 (the θ2 of the same row goes into it).")
    return ("both rows reach the target, but not with the elbows asked for: row 0 must be "
            "elbow-down (θ2 ≥ 0), row 1 elbow-up (θ2 ≤ 0).")


# --- 13.4: 0, 1, 2 or infinitely many ----------------------------------------------------------

def _count(L1, L2, x, y):
    """The number of solutions, from ``ik_2link``: nan rows 0, equal rows 1, else 2; the base of an
    arm with L1 = L2 is the one target with a whole circle of them."""
    if _at_base_of_equal_arm(L1, L2, x, y):
        return math.inf
    q = ik_2link((L1, L2), (x, y))
    if np.isnan(q).any():
        return 0
    return 1 if _same_angles(q[0], q[1], 1e-9) else 2


def _count_cases(rng: np.random.Generator) -> list[tuple]:
    cases: list[tuple] = [
        (2.0, 1.25, 2.0, 1.0),                       # inside
        (2.0, 1.25, 3.25, 0.0),                      # outer circle
        (2.0, 1.25, 0.0, -0.75),                     # inner circle
        (2.0, 1.25, 3.25 * math.cos(0.4), 3.25 * math.sin(0.4)),  # outer circle, rounded outwards
        (2.0, 1.25, 3.0, 2.0),                       # beyond
        (2.0, 1.25, 0.3, -0.2),                      # in the hole
        (2.0, 1.25, 0.0, 0.0),                       # the base, L1 != L2: in the hole
        (1.5, 1.5, 0.0, 0.0),                        # the base, L1 = L2
        (1.5, 1.5, 1e-3, 0.0),                       # next to it: inside
        (1.5, 1.5, 0.0, -3.0),                       # L1 = L2, outer circle
    ]
    for _ in range(50):
        l1, l2 = (float(v) for v in rng.uniform(0.2, 3.0, 2))
        if rng.random() < 0.2:
            l2 = l1
        r_in, r_out = abs(l1 - l2), l1 + l2
        kind = rng.random()
        if kind < 0.4:
            r = float(rng.uniform(r_in + 1e-3, r_out - 1e-3))
        elif kind < 0.6:
            r = r_out
        elif kind < 0.75:
            r = r_in
        elif kind < 0.9:
            r = float(rng.uniform(r_out + 1e-3, r_out + 2.0))
        else:
            r = float(rng.uniform(0.0, r_in - 1e-3)) if r_in > 2e-3 else 0.0
        phi = float(rng.uniform(-math.pi, math.pi))
        cases.append((l1, l2, r * math.cos(phi), r * math.sin(phi)))
    return cases


def _compare_count(got, want, args) -> str | None:
    if isinstance(got, (bool, np.bool_)) or not isinstance(got, (int, float, np.integer, np.floating)):
        return f"returned {describe(got)}; expected 0, 1, 2 or math.inf."
    if got not in (0, 1, 2, math.inf):
        return f"returned {describe(got)}; a count of solutions is 0, 1, 2 or math.inf."
    if got == want:
        return None
    L1, L2, x, y = args
    r = math.hypot(x, y)
    if want == math.inf:
        return ("undercounts the base of an arm with L1 = L2: the folded arm puts its tip there "
                "for which values of θ1?")
    if got == math.inf:
        if L1 != L2 and r <= _BASE_TOL:
            return "counts infinitely many at the base of an arm with L1 ≠ L2; is the base reachable then?"
        return "counts infinitely many for a target that is not the base; r fixes θ2, then atan2 fixes θ1."
    if want == 1 and got == 2:
        return ("counts 2 on a boundary circle: there cos θ2 = ±1 and the two elbows are one "
                "configuration (straight or folded).")
    if want == 1 and got == 0:
        return ("counts 0 for a target on a boundary circle: rounding puts r a hair beyond it; "
                "compare with a small tolerance (say 1e-9).")
    if want == 0:
        return "counts solutions for a target outside the annulus eq. ch13-annulus."
    return ("counts too few for a target strictly inside the annulus: both signs of arccos give "
            "a different elbow there.")


EXERCISES = (
    Exercise(
        "13.1", 13, "numeric", "Elbow angles for one target", 1,
        "an array of elbow angles θ2 in radians, one per solution, elbow-down (θ2 ≥ 0) first",
        _judge_elbows,
    ),
    Exercise(
        "13.2", 13, "numeric", "Which elbow is on the right", 1,
        "a configuration (θ1, θ2) in radians: the solution whose elbow has x > 0",
        _judge_right_elbow,
    ),
    Exercise(
        "13.3", 13, "implement", "Both analytic solutions", 2,
        "a function ik2(L1, L2, x, y) returning a (2, 2) array, rows (θ1, θ2): elbow-down, elbow-up",
        implement(_ik2_ref, _ik_cases, call="ik2(L1, L2, x, y)", names=("L1", "L2", "x", "y"),
                  compare=_compare_ik, seed=133),
    ),
    Exercise(
        "13.4", 13, "argue", "Zero, one, two or infinitely many", 2,
        "a function count_solutions(L1, L2, x, y) returning 0, 1, 2 or math.inf",
        implement(_count, _count_cases, call="count_solutions(L1, L2, x, y)", names=("L1", "L2", "x", "y"),
                  compare=_compare_count, seed=134),
    ),
)

# For the catalog test that proves no message gives the value away.
_judge_elbows.expected = _elbows_0_1
_judge_right_elbow.expected = lambda: _right_and_left()[0]
