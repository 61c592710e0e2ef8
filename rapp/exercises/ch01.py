"""Checks for the exercises of chapter 1, "Introduction: an arm, some obstacles, and the space of its joints".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['1.1', '1.2', '1.3', '1.4', '1.5']
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.exercises.core import (CLOSE_FACTOR, TOLERANCE_ANGLES, Exercise, Judgement, as_number_array, close,
                                 describe, implement, numeric)

__all__ = ["EXERCISES"]


def _configuration(answer, n: int) -> np.ndarray | Judgement:
    """The answer as a configuration of ``n`` joints, or the verdict saying why it is not one."""
    got = as_number_array(answer)
    if isinstance(got, str):
        return Judgement(False, got + f"; expected {n} joint angles in radians.")
    if got.shape != (n,):
        return Judgement(False, f"expected {n} joint angles (one per joint), got shape {got.shape}.")
    return got


def _looks_like_degrees(arm: Arm, q: np.ndarray, target) -> bool:
    return bool(np.abs(q).max() > 2 * np.pi and np.allclose(arm.end_effector(np.radians(q)), target, atol=1e-3))


# --- 1.1: pointing straight up ---------------------------------------------------------------

def _judge_straight_up(answer) -> Judgement:
    arm, target = Arm([1.0, 1.0, 1.0]), np.array([0.0, 3.0])
    q = _configuration(answer, 3)
    if isinstance(q, Judgement):
        return q
    tip = arm.end_effector(q)
    want = np.array([np.pi / 2, 0.0, 0.0])  # the only configuration that reaches (0, 3)
    if close(q, want, angles=True):
        return Judgement(True, "the end effector is at (0, 3): every link points along +y.")
    if close(q, want, CLOSE_FACTOR, angles=True):
        return Judgement(False, "close, but not within the tolerance: give more digits.")
    if _looks_like_degrees(arm, q, target):
        return Judgement(False, "those look like degrees; rapp's angles are in radians.")
    if np.allclose(arm.end_effector(np.diff(q, prepend=0.0)), target, atol=1e-3):
        return Judgement(False, "those are absolute link angles; a joint angle is relative to the "
                                "previous link, so a link that keeps the direction has joint angle 0.")
    return Judgement(False, f"that puts the end effector at {describe(np.round(tip, 3))}, not (0, 3). "
                            "Which direction must every link point?")


_judge_straight_up.tolerance = TOLERANCE_ANGLES


# --- 1.2: the second configuration -----------------------------------------------------------

def _judge_second_configuration(answer) -> Judgement:
    arm, q = Arm([1.0, 0.8]), np.array([0.3, 1.0])
    other = _configuration(answer, 2)
    if isinstance(other, Judgement):
        return other
    target = arm.end_effector(q)
    # The mirror image in the base-to-tip line: the elbow negated, the shoulder turned by the
    # angle it makes with that line, twice.
    want = np.array([q[0] + 2 * np.arctan2(0.8 * np.sin(q[1]), 1.0 + 0.8 * np.cos(q[1])), -q[1]])
    if close(other, want, angles=True):
        return Judgement(True, "same end effector, elbow on the other side of the base-to-tip line.")
    if close(other, q, angles=True):
        return Judgement(False, "that is the same configuration on the torus (angles differ by whole "
                                "turns, or not at all); reflect the elbow instead.")
    if close(other, want, CLOSE_FACTOR, angles=True):
        return Judgement(False, "close, but not within the tolerance: give more digits.")
    if _looks_like_degrees(arm, other, target):
        return Judgement(False, "those look like degrees; rapp's angles are in radians.")
    if close(other[1], want[1], angles=True) and not close(other[0], want[0], CLOSE_FACTOR, angles=True):
        if close(other[0], q[0], angles=True):   # the elbow flipped, the shoulder left where it was
            return Judgement(False, "the elbow angle is right, but the shoulder must turn too: flipping "
                                    "the elbow alone moves the end effector.")
        # The shoulder did turn, so "flipping the elbow alone" would name a mistake not made.
        return Judgement(False, f"the elbow angle is right and the shoulder turned, but not by the right "
                                f"angle: the end effector lands "
                                f"{np.linalg.norm(arm.end_effector(other) - target):.3g} m away. By how "
                                "much must the shoulder turn to put the elbow on the other side of the "
                                "base-to-tip line?")
    return Judgement(False, f"that configuration puts the end effector "
                            f"{np.linalg.norm(arm.end_effector(other) - target):.3g} m away from where "
                            "(0.3, 1.0) puts it.")


_judge_second_configuration.tolerance = TOLERANCE_ANGLES


# --- 1.5: wrapping an angle ------------------------------------------------------------------

def _wrap_cases(rng: np.random.Generator) -> list[tuple]:
    cases = [(0.0,), (np.pi,), (-np.pi,), (3 * np.pi,), (-3 * np.pi / 2,), (2 * np.pi,), (7.0,), (-7.0,),
             (1e-12,), (100.0,), (-1000.5,)]
    cases += [(float(x),) for x in rng.uniform(-50, 50, 40)]
    return cases


def _compare_wrapped(got, want, args) -> str | None:
    g = as_number_array(got)
    if isinstance(g, str):
        return "returned None (a missing return?)." if got is None else f"returned {describe(got)}, not a number."
    if g.shape != ():
        return f"returned shape {g.shape}; expected a single number."
    value = float(g)
    if not (-np.pi <= value < np.pi):
        if np.isclose(value, np.pi):
            return "returned pi; the range is [-pi, pi), so pi itself wraps to -pi."
        return f"returned {value:.6g}, outside [-pi, pi)."
    if not np.isclose(np.cos(value - args[0]), 1.0, atol=1e-9):
        return f"returned {value:.6g}, which is not the same angle (it must differ by whole turns)."
    return None


EXERCISES = (
    Exercise(
        "1.1", 1, "numeric", "Pointing straight up", 1,
        "three joint angles in radians, e.g. [a, b, c]",
        _judge_straight_up,
    ),
    Exercise(
        "1.2", 1, "argue", "Two poses, one end effector", 2,
        "two joint angles in radians: the second configuration",
        _judge_second_configuration,
    ),
    Exercise(
        "1.3", 1, "numeric", "The hole near the base", 1,
        "a number: the radius in metres",
        numeric(lambda: Arm([1.0, 0.3]).reach[0],
                mistakes=[(lambda: 1.3, "that is the outer radius, the arm stretched out."),
                          (lambda: 0.3, "that is the second link alone; fold the elbow back."),
                          (lambda: 1.0, "that is the first link alone; fold the elbow back.")],
                hint="fold the elbow all the way back and measure the distance from the base."),
    ),
    Exercise(
        "1.4", 1, "numeric", "The short way round", 1,
        "a number: the length in radians of the shortest joint-space move",
        numeric(lambda: float(np.linalg.norm(wrap_angle(np.array([-3.0, 0.5]) - [3.0, 0.5]))),
                mistakes=[(lambda: 6.0, "that is the long way round; on the torus -3.0 and 3.0 are close.")],
                hint="the difference of two angles is only defined up to whole turns; take the smallest."),
    ),
    Exercise(
        "1.5", 1, "implement", "Wrap an angle", 1,
        "a function wrap(angle) returning the same angle in [-pi, pi)",
        implement(lambda a: float(wrap_angle(a)), _wrap_cases, call="wrap(angle)", names=("angle",),
                  compare=_compare_wrapped, seed=15),
    ),
)
