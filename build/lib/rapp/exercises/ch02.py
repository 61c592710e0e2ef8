"""Checks for the exercises of chapter 2, "Forward kinematics".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['2.1', '2.2', '2.3', '2.4']
>>> bool(EXERCISES[2].judge(lambda lengths, q: tuple(_tip(lengths, q))))
True
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm
from rapp.exercises.core import Exercise, describe, implement, numeric

__all__ = ["EXERCISES"]

#: The arm and the configuration of Exercises 2.1 and 2.2.
_LENGTHS = (1.0, 0.8, 0.5)
_Q = (np.pi / 2, -np.pi / 2, np.pi / 2)


def _tip(lengths, q) -> np.ndarray:
    """The package's end effector of the arm ``lengths`` at ``q``: the reference of 2.3."""
    return Arm(lengths).end_effector(q)


def _mis_tip(lengths, angles) -> np.ndarray:
    """The MIS formula fed the relative angles: link i along theta_i, measured from +x."""
    angles = np.asarray(angles, dtype=float)
    lengths = np.asarray(lengths, dtype=float)
    return np.array([np.sum(lengths * np.cos(angles)), np.sum(lengths * np.sin(angles))])


# --- 2.3: forward kinematics for any number of links -----------------------------------------

def _arms(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (one link, a bent elbow, the arm of 2.2) then random arms of 1 to 6 links."""
    cases: list[tuple] = [
        ((1.0,), (0.0,)),
        ((2.0,), (np.pi / 2,)),                    # one link straight up
        ((1.0, 1.0), (np.pi / 2, np.pi / 2)),      # relative and absolute angles differ
        (_LENGTHS, _Q),
        ((0.5, 1.5, 1.0, 0.25), (0.0, 0.0, 0.0, 0.0)),
        ((1.0, 1.0, 1.0), (-np.pi, np.pi, -np.pi)),
    ]
    for _ in range(50):
        n = int(rng.integers(1, 7))
        lengths = tuple(float(v) for v in np.round(rng.uniform(0.1, 2.0, n), 2))
        q = tuple(float(v) for v in np.round(rng.uniform(-np.pi, np.pi, n), 3))
        cases.append((lengths, q))
    return cases


def _fk_slips(lengths, q) -> list[tuple[np.ndarray, str]]:
    """What the usual mistakes return on this arm, with what to say about each."""
    arm = Arm(lengths)
    q = np.asarray(q, dtype=float)
    exclusive = np.concatenate(([0.0], np.cumsum(q)[:-1]))
    return [
        (_mis_tip(lengths, q), "that is the MIS formula fed the relative angles. Each link points "
                               "along its absolute angle, the running sum of the joint angles up to it."),
        (arm.end_effector(np.rad2deg(q)), "that converts q to degrees before cos and sin; they take "
                                          "radians, and q is in radians."),
        (arm.end_effector(np.deg2rad(q)), "that treats q as degrees and converts it to radians; q is "
                                          "in radians already."),
        (_mis_tip(lengths, exclusive), "link i's direction leaves out its own joint angle; the running "
                                       "sum must include theta_i: phi_i = theta_1 + ... + theta_i."),
        (_tip(lengths, q)[::-1], "that is (y, x); return (x, y)."),
    ]


def _compare_tip(got, want, args) -> str | None:
    lengths, q = args
    if got is None:
        return "returned None (a missing return?)."
    if isinstance(got, (str, bytes, bool, np.bool_)) or callable(got):
        return f"returned {describe(got)}; expected the pair (x, y)."
    try:
        g = np.asarray(got, dtype=float)
    except Exception:
        return f"returned {describe(got)}, which is not a pair of numbers (x, y)."
    if g.shape == (len(lengths) + 1, 2) and np.allclose(g[-1], want, rtol=0.0, atol=1e-9):
        return "returned every joint position; return only the end effector (x, y), the last of them."
    if g.shape != (2,):
        return f"returned shape {g.shape}; expected the pair (x, y), shape (2,)."
    if not np.all(np.isfinite(g)):
        return f"returned {describe(got)}, which is not finite."
    if np.allclose(g, want, rtol=0.0, atol=1e-9):
        return None
    for wrong, why in _fk_slips(lengths, q):
        if np.allclose(g, wrong, rtol=0.0, atol=1e-9):
            return f"returned {describe(got)}: {why}"
    return f"returned {describe(got)}: that end-effector position is not right."


# --- 2.4: when does a three-link arm reach its base ------------------------------------------

def _reaches_base(lengths) -> bool:
    return Arm(lengths).reach[0] == 0.0


def _triples(rng: np.random.Generator) -> list[tuple]:
    """Boundary cases first (2 max L = sum L exactly, in every order), then random lengths."""
    cases: list[tuple] = [
        ((1.0, 0.5, 0.5),),                 # flat triangle: the longest link first
        ((0.25, 0.75, 0.5),),               # flat triangle: the longest link in the middle
        ((1.0, 2.0, 3.0),),                 # flat triangle: the longest link last
        ((1.0, 1.0, 1.0),),
        ((3.0, 1.0, 1.0),),
        ((1.0, 1.0, 3.0),),
        ((0.5, 2.0, 1.0),),
    ]
    for _ in range(50):
        lengths = np.round(rng.uniform(0.1, 2.0, 3), 2)
        if rng.random() < 0.2:  # now and then a flat triangle, the longest link anywhere
            lengths = rng.integers(1, 9, 3) / 8  # eighths: the sum below is exact
            k = rng.integers(0, 3)
            lengths[k] = lengths.sum() - lengths[k]
        cases.append((tuple(float(v) for v in lengths),))
    return cases


def _compare_reach(got, want, args) -> str | None:
    if not isinstance(got, (bool, np.bool_)):
        return f"returned {describe(got)}; expected True or False."
    if bool(got) == want:
        return None
    lengths = np.asarray(args[0])
    if 2 * lengths.max() == lengths.sum():
        return (f"returned {bool(got)} on the boundary, where the longest link equals the other two "
                "together: fold the arm flat and see where its tip lands.")
    return (f"returned {bool(got)}, which is wrong for these lengths: compare the longest link, "
            "wherever it is in the list, with the other two together.")


# --- the catalog -----------------------------------------------------------------------------

EXERCISES = (
    Exercise(
        "2.1", 2, "numeric", "The reach of a three-link arm", 1,
        "a pair (r_min, r_max) in metres",
        numeric(lambda: Arm(_LENGTHS).reach,
                mistakes=[(lambda: (2 * max(_LENGTHS) - sum(_LENGTHS), sum(_LENGTHS)),
                           "a radius is never negative: when the longest link is shorter than the others "
                           "together, the inner radius is 0."),
                          (lambda: (abs(_LENGTHS[0] - _LENGTHS[1]), sum(_LENGTHS)),
                           "that inner radius is the two-link formula |L1 - L2|; this arm has three links."),
                          (lambda: (abs(_LENGTHS[0] - _LENGTHS[1] - _LENGTHS[2]), sum(_LENGTHS)),
                           "links 2 and 3 need not both fold back along link 1: they can bend towards "
                           "each other and close a triangle."),
                          (lambda: Arm(_LENGTHS).reach[::-1], "the order is (r_min, r_max).")],
                hint="r_max is the arm stretched out; for r_min fold the longest link back on the others."),
    ),
    Exercise(
        "2.2", 2, "numeric", "The end effector by hand", 1,
        "a pair (x, y) in metres",
        numeric(lambda: _tip(_LENGTHS, _Q),
                mistakes=[(lambda: _mis_tip(_LENGTHS, _Q),
                           "that is the MIS formula fed the relative angles. Each link points along its "
                           "absolute angle, the running sum of the joint angles up to it."),
                          (lambda: _tip(_LENGTHS, np.deg2rad(_Q)),
                           "that reads the angles as degrees (a calculator in degree mode); they are radians."),
                          (lambda: _tip(_LENGTHS, np.rad2deg(_Q)),
                           "that takes cos and sin of the angles in degrees; they want radians."),
                          (lambda: _tip(_LENGTHS, _Q)[::-1], "that is (y, x); give (x, y)."),
                          (lambda: _tip(_LENGTHS[:2], _Q[:2]), "that leaves out link 3.")],
                hint="add up the three link vectors, each along its absolute angle phi_i."),
    ),
    Exercise(
        "2.3", 2, "implement", "Forward kinematics for any number of links", 2,
        "a function fk(lengths, q) returning the end effector (x, y)",
        implement(_tip, _arms, call="fk(lengths, q)", names=("lengths", "q"),
                  compare=_compare_tip, seed=23),
    ),
    Exercise(
        "2.4", 2, "argue", "When a three-link arm reaches its own base", 2,
        "a function reaches_base(lengths) returning True or False",
        implement(_reaches_base, _triples, call="reaches_base(lengths)", names=("lengths",),
                  compare=_compare_reach, seed=24),
    ),
)
