"""Checks for the exercises of chapter 4, "The configuration space".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['4.1', '4.2', '4.3', '4.4', '4.5', '4.6']
>>> _cells_of([np.pi / 2, 3.0], 12)
[9, 0]
>>> round(_interval_width(), 3)
0.659
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm
from rapp.collision import check_obstacle, collides
from rapp.cspace import JointGrid, occupancy
from rapp.obstacles import Circle
from rapp.exercises.core import Exercise, Judgement, describe, implement, numeric

__all__ = ["EXERCISES"]


# --- 4.1 and 4.2: the cell of an angle -------------------------------------------------------

def _cell_of(angle, m):
    """The package's conversion: ``JointGrid.index`` on one freely turning joint of ``m`` cells."""
    return int(JointGrid(Arm([1.0]), int(m)).index([float(angle)])[0])


def _cells_of(angles, m) -> list:
    return [_cell_of(a, m) for a in angles]


_EX1_ANGLES, _EX1_M = (np.pi / 2, 3.0), 12


def _fraction(angle, m) -> float:
    """Where ``angle`` falls between grid angles, in ``[0, m)``: the package's fractional index."""
    return float(JointGrid(Arm([1.0]), int(m)).fractional_index([float(angle)])[0])


def _angles_and_sizes(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (the seam from both sides, whole turns, negative angles, few cells), then random.

    No case lies exactly half way between two grid angles, where "nearest" is a tie.
    """
    cases: list[tuple] = [
        (0.0, 8),                       # a grid angle: cell M/2
        (-np.pi, 12),                   # the first grid angle
        (np.pi, 12),                    # the same pose as -pi
        (3.0, 12),                      # just below pi: nearest grid angle is -pi, across the seam
        (-3.1, 12),                     # just above -pi
        (np.pi / 2 + 4 * np.pi, 12),    # two whole turns added
        (-7.0, 10),                     # a negative angle beyond -2 pi
        (1.0, 2),                       # two cells
        (0.3, 7),                       # odd M
        (100.0, 360),                   # many turns, fine grid
    ]
    for _ in range(50):
        m = int(rng.integers(2, 500))
        angle = float(rng.uniform(-20.0, 20.0))
        if abs(_fraction(angle, m) % 1.0 - 0.5) < 1e-6:
            angle += 0.1 * 2 * np.pi / m
        cases.append((angle, m))
    return cases


def _compare_cell(got, want, args) -> str | None:
    angle, m = args
    if isinstance(got, (bool, np.bool_)) or not isinstance(got, (int, np.integer, float, np.floating)):
        return f"returned {describe(got)}; expected an integer cell index."
    if not np.isfinite(got) or got != np.round(got):
        return f"returned {describe(got)}, which is not a whole number; a cell index is an integer."
    got = int(got)
    if got == want:
        return None
    if not 0 <= got < m:
        if got == m:
            return (f"returned {got}, one past the last cell: on a wrapping axis of {m} cells the "
                    "indices run from 0 to M - 1, and the cell past the end is across the seam.")
        return (f"returned {got}, which is not a cell index on an axis of {m} cells (0 to M - 1): "
                "wrap the angle (whole turns) first.")
    frac = _fraction(angle, m)
    if got == int(np.floor(frac)) % m:
        return (f"returned {got}: that is the grid angle just below the angle (floor); the cell of an "
                "angle is the one whose grid angle (equation ch04-theta) is nearest.")
    if got == (want + 1) % m:
        return (f"returned {got}: one cell too far; cells are numbered from 0, the cell of "
                "-pi, not from 1.")
    return (f"returned {got}, which is not the cell whose grid angle is nearest to the angle "
            "(the angle is in radians; whole turns do not change the cell).")


# --- 4.3: the interval of one link and one disc ----------------------------------------------

_EX3 = dict(L=1.3, d=1.5, r=0.5)


def _half_width_by_bisection(L, d, r) -> float:
    """Largest angle between the link and the centre at which the package says the link hits."""
    arm, disc = Arm([L]), [Circle((d, 0.0), r)]
    lo, hi = 0.0, np.pi   # the link at 0 points at the centre; here it hits there and not at pi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if bool(collides(arm, [mid], disc)):
            lo = mid
        else:
            hi = mid
    return lo


def _interval_width() -> float:
    return 2 * _half_width_by_bisection(**_EX3)


def _tangent_width() -> float:
    return 2 * float(np.arcsin(_EX3["r"] / _EX3["d"]))


# --- 4.4: full columns -----------------------------------------------------------------------

_BENCH_ARM = Arm([1.0, 1.0])
_BENCH_OBSTACLES = (Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25))
_BENCH_M = 120


def _bench_occupancy() -> np.ndarray:
    return occupancy(_BENCH_ARM, _BENCH_OBSTACLES, JointGrid(_BENCH_ARM, _BENCH_M))


def _full_columns() -> int:
    return int(_bench_occupancy().all(axis=1).sum())


# --- 4.5: a collision between the samples ----------------------------------------------------

def _judge_missed_collision(answer) -> Judgement:
    """``(lengths, obstacles, cells, q)``: ``q`` collides, the sample of its cell does not."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (lengths, obstacles, cells, q).")
    try:
        lengths, obstacles, cells, q = answer
    except Exception:
        return Judgement(False, f"expected a tuple (lengths, obstacles, cells, q); got {describe(answer)}.")
    try:
        arm = lengths if isinstance(lengths, Arm) else Arm(lengths)
    except Exception as exc:
        return Judgement(False, f"lengths do not make an arm: {exc}.")
    try:
        obstacles = [check_obstacle(ob) for ob in obstacles]
    except Exception:
        return Judgement(False, "obstacles must be a list of rapp.Circle (or rapp.Polygon).")
    if not obstacles:
        return Judgement(False, "with no obstacle nothing collides; give at least one.")
    try:
        grid = JointGrid(arm, cells)
    except Exception as exc:
        return Judgement(False, f"cells do not make a grid: {exc}.")
    try:
        q = arm.check_q(q)
    except Exception as exc:
        return Judgement(False, f"q is not a configuration of that arm: {exc}.")
    if q.shape != (arm.n,):
        return Judgement(False, f"q must be one configuration of {arm.n} angles, got shape {q.shape}.")
    if not bool(collides(arm, q, obstacles)):
        return Judgement(False, f"the arm does not collide at q = {describe(q)}; the counterexample needs "
                                "a colliding configuration inside a cell the grid calls free.")
    if not bool(arm.within_limits(q)):
        return Judgement(False, "q lies beyond a joint limit: no cell of the grid holds it.")
    cell = grid.index(q)
    sample = grid.angles(cell)
    occ = bool(collides(arm, sample, obstacles))
    where = tuple(int(i) for i in cell)
    if occ:
        return Judgement(False, f"q collides, but so does the sample of its cell {where}, so the grid "
                                "marks that cell occupied. Make the obstacle small enough to fit "
                                "between the samples (or the grid coarser).")
    return Judgement(True, f"q collides, yet its cell {where} is free on the grid: its sample "
                           f"{describe(sample)} misses the obstacle. A grid sees only its samples.")


# --- 4.6: how far link 1 reaches (answered with the live C-space explorer) ----------------------

def _farthest_reach(L=1.0, r=0.25) -> float:
    """The largest distance of a disc's centre (radius ``r``) from the base at which a link of
    length ``L`` pointing at it still touches it: found by bisection on :func:`rapp.collides`."""
    arm = Arm([L])
    lo, hi = 0.0, 4.0 * (L + r)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if bool(collides(arm, np.array([-np.pi / 2]), [Circle((0.0, -mid), r)])) else (lo, mid)
    return lo


EXERCISES = (
    Exercise(
        "4.1", 4, "numeric", "The cell of an angle", 1,
        "a list of two integers: the cell indices of pi/2 and of 3.0 rad",
        numeric(lambda: _cells_of(_EX1_ANGLES, _EX1_M), exact_integer=True,
                mistakes=[(lambda: [9, 12], "there is no cell 12 on an axis of 12 cells: the one past "
                                            "the end is across the seam."),
                          (lambda: [9, 11], "that takes the grid angle just below each angle (floor); "
                                            "the cell is the one whose grid angle is nearest."),
                          (lambda: [10, 1], "cells are numbered from 0 (the cell of -pi), not from 1."),
                          (lambda: [9, 6], "the angles are in radians, not degrees: 3.0 is 3.0 rad, not 3 degrees.")],
                hint="k = M (theta + pi) / (2 pi), rounded to the nearest integer, modulo M."),
    ),
    Exercise(
        "4.2", 4, "implement", "Implement the cell of an angle", 2,
        "a function cell_of(angle, m) returning the cell index (an int in 0 .. m-1)",
        implement(_cell_of, _angles_and_sizes, call="cell_of(angle, m)", names=("angle", "m"),
                  compare=_compare_cell, seed=42),
    ),
    Exercise(
        "4.3", 4, "numeric", "The width of a forbidden interval", 2,
        "a number: the full width of the interval of link angles that hit the disc, in radians",
        numeric(_interval_width,
                mistakes=[(lambda: _interval_width() / 2, "that is the half-width; the question asks "
                                                          "for the full width of the interval."),
                          (_tangent_width, "that is the tangent case, arcsin(r/d); can this link reach "
                                           "the tangent point? Compare L with sqrt(d^2 - r^2)."),
                          (lambda: _tangent_width() / 2, "that is half the tangent case; can this link "
                                                         "reach the tangent point?"),
                          (lambda: np.degrees(_interval_width()), "give the angle in radians, not degrees.")],
                hint="find which case of equation ch04-interval applies, then double the half-width."),
    ),
    Exercise(
        "4.4", 4, "numeric", "Full columns of the benchmark", 2,
        "an integer: the number of theta1 columns of the 120 x 120 benchmark grid that are "
        "entirely occupied",
        numeric(_full_columns, exact_integer=True,
                mistakes=[(lambda: int(_bench_occupancy().any(axis=1).sum()),
                           "that counts the columns with at least one occupied cell; count the "
                           "columns occupied for every theta2."),
                          (lambda: int(occupancy(_BENCH_ARM, _BENCH_OBSTACLES[2:],
                                                 JointGrid(_BENCH_ARM, _BENCH_M)).any(axis=1).sum()),
                           "that counts every column the small disc touches, link 2 hits included; "
                           "only link 1 fills a whole column."),
                          (lambda: int(_bench_occupancy().all(axis=0).sum()),
                           "that counts full rows (fixed theta2); a column is a fixed theta1."),
                          (lambda: _full_columns() + 1, "one too many: a grid angle counts only if "
                                                        "it lies inside the interval, "
                                                        "|theta1 - direction| <= delta_max.")],
                hint="which discs can link 1 reach? For those, count the grid angles theta1 inside "
                     "the interval of equation ch04-interval."),
    ),
    Exercise(
        "4.5", 4, "argue", "A collision between the samples", 2,
        "a tuple (lengths, obstacles, cells, q): q collides, but the sample of its cell does not",
        _judge_missed_collision,
    ),
    Exercise(
        "4.6", 4, "numeric", "When the full columns vanish", 1,
        "a number: the distance (m) of the small disc's centre from the base at which its band of "
        "full columns disappears",
        numeric(_farthest_reach, abs_tol=0.03,
                mistakes=[(lambda: 1.0, "that is the link's length; the link must reach the disc's "
                                        "near edge, not its centre."),
                          (lambda: 0.75, "that is where the disc's near edge is at the start; move the "
                                         "disc away until link 1 no longer touches it."),
                          (lambda: 2.25, "at that distance link 2 still reaches the disc, but only link "
                                         "1 fills whole columns.")],
                hint="link 1 touches the disc while its near edge, at distance d - r, is within L."),
    ),
)
