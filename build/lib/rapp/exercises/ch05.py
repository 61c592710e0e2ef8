"""Checks for the exercises of chapter 5, "A* on the torus and the heuristic GD1".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['5.1', '5.2', '5.3', '5.4', '5.5', '5.6']
"""

from __future__ import annotations

import numpy as np

from rapp import search
from rapp.arm import Arm
from rapp.cspace import JointGrid, occupancy
from rapp.ik import ik
from rapp.obstacles import Circle
from rapp.errors import NoPathFound
from rapp.exercises.core import Exercise, Judgement, describe, implement, numeric

__all__ = ["EXERCISES"]


# --- 5.2: the toroidal heuristic -------------------------------------------------------------

def _gd1(a, b, shape):
    return int(search.toroidal_manhattan(a, b, shape))


def _cell_pairs(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (same cell, the seam, exactly half way, odd sizes) then random cells."""
    cases: list[tuple] = [
        ((0, 0), (0, 0), (10, 10)),
        ((0, 0), (9, 0), (10, 10)),        # neighbours across the seam
        ((0, 5), (5, 0), (10, 10)),        # exactly half way on both axes
        ((3,), (4,), (7,)),                # one joint
        ((0, 0, 0), (6, 1, 3), (7, 7, 7)),  # three joints, odd size
        ((2, 30), (90, 2), (100, 36)),      # axes of different sizes
    ]
    for _ in range(60):
        n = int(rng.integers(1, 5))
        shape = tuple(int(m) for m in rng.integers(2, 400, n))
        a = tuple(int(rng.integers(0, m)) for m in shape)
        b = tuple(int(rng.integers(0, m)) for m in shape)
        cases.append((a, b, shape))
    return cases


def _compare_distance(got, want, args) -> str | None:
    if isinstance(got, (bool, np.bool_)) or not isinstance(got, (int, np.integer, float, np.floating)) \
            or not np.isfinite(got):
        return f"returned {describe(got)}; expected a whole number of steps."
    if got != want:
        a, b, shape = args
        direct = sum(abs(x - y) for x, y in zip(a, b))
        if got == direct:
            return ("counted the steps without the wrap: on each axis the way across the seam, "
                    "M_i - |a_i - b_i|, may be shorter.")
        return (f"returned {describe(got)}, which is {'more' if got > want else 'fewer'} steps than "
                "the shortest way on an empty torus (take the shorter way round on each axis).")
    return None


# --- 5.4: a heuristic for 8-connected moves --------------------------------------------------

def _judge_king_heuristic(h) -> Judgement:
    """Admissible and consistent for king moves on a torus, and not the zero heuristic."""
    if h is None:
        return Judgement(False, "no answer yet: pass your heuristic h(a, b, shape).")
    if not callable(h):
        return Judgement(False, f"expected a function h(a, b, shape); got {type(h).__name__} {describe(h)}.")
    shape = (9, 12)
    goal = (2, 10)
    # The true cost-to-go with unit-cost king moves on an empty torus, by breadth-first search.
    true = _king_distances(shape, goal)
    judge = implement(
        lambda a, b, s: 0, lambda rng: [((i, j), goal, shape) for i in range(shape[0]) for j in range(shape[1])],
        call="h(a, b, shape)", names=("a", "b", "shape"), seed=54,
        compare=lambda got, want, args: _admissible(got, true[args[0]]),
    )
    verdict = judge(h)
    if not verdict:
        return verdict
    values = np.zeros(shape)
    for i in range(shape[0]):
        for j in range(shape[1]):
            problem = _admissible(got := h((i, j), goal, shape), true[(i, j)])
            if problem:  # the same inputs as the first pass: a function that changes its mind
                return Judgement(False, f"on a second call with a={(i, j)}: your function {problem}")
            values[i, j] = float(got)
    steps = [(1, 0), (0, 1), (1, 1), (1, -1)]
    for di, dj in steps:
        moved = np.roll(values, (-di, -dj), axis=(0, 1))
        if np.any(np.abs(values - moved) > 1 + 1e-9):
            i, j = np.argwhere(np.abs(values - moved) > 1 + 1e-9)[0]
            return Judgement(False, f"admissible, but not consistent: h changes by more than 1 on the king "
                                    f"move from {(int(i), int(j))} to {((i + di) % 9, (j + dj) % 12)}.")
    if np.all(values == 0):
        # Admissible and consistent, as asked; the message says what a better answer gains.
        return Judgement(True, "h = 0 is admissible and consistent, as asked, but it tells the search "
                               "nothing (A* becomes Dijkstra); a larger lower bound is exact on an "
                               "empty torus.")
    exact = bool(np.all(values == _true_grid(true, shape)))
    return Judgement(True, "admissible and consistent for king moves" +
                     (", and exact on an empty torus." if exact else
                      "; a larger admissible h exists (it is exact on an empty torus)."))


def _true_grid(true: dict, shape) -> np.ndarray:
    return np.array([[true[(i, j)] for j in range(shape[1])] for i in range(shape[0])], float)


def _admissible(got, true_cost) -> str | None:
    if isinstance(got, (bool, np.bool_, str, bytes)) or got is None:
        return f"returned {describe(got)}, not a number."
    try:
        value = float(got)
    except Exception:
        return f"returned {describe(got)}, not a number."
    if not np.isfinite(value):
        return f"returned {describe(got)}, not a finite number."
    if value > true_cost + 1e-9:
        return (f"returned {value:g}, more than the true number of king moves: not admissible "
                "(a diagonal step changes two indices at once).")
    return None


def _king_distances(shape, goal) -> dict:
    dist = {goal: 0}
    frontier = [goal]
    while frontier:
        nxt = []
        for i, j in frontier:
            for di in (-1, 0, 1):
                for dj in (-1, 0, 1):
                    c = ((i + di) % shape[0], (j + dj) % shape[1])
                    if c not in dist:
                        dist[c] = dist[(i, j)] + 1
                        nxt.append(c)
        frontier = nxt
    return dist


# --- 5.5: greedy best-first is not optimal ---------------------------------------------------

def _judge_greedy_counterexample(answer) -> Judgement:
    """``(occupied, start, goal)`` on which greedy best-first returns a longer path than A*."""
    if answer is None:
        return Judgement(False, "no answer yet: pass (occupied, start, goal).")
    try:
        occupied, start, goal = answer
        occupied = np.asarray(occupied)
    except Exception:
        return Judgement(False, f"expected a tuple (occupied, start, goal); got {describe(answer)}.")
    if occupied.dtype != bool or occupied.ndim < 1 or occupied.size > 10_000:
        return Judgement(False, "occupied must be a bool array (True = blocked) of at most 10,000 cells.")
    try:
        best = search.astar_search(occupied, start, goal)
        greedy_cost = len(search.greedy_best_first(occupied, start, goal)) - 1
    except NoPathFound:
        return Judgement(False, "there is no path from start to goal on that grid; a counterexample needs one.")
    except ValueError as exc:
        return Judgement(False, f"that grid does not work: {exc}.")
    if greedy_cost > best.cost:
        return Judgement(True, f"greedy best-first takes {greedy_cost} steps where {best.cost} suffice: "
                               "a counterexample.")
    return Judgement(False, f"on that grid greedy best-first finds a shortest path ({greedy_cost} steps). "
                            "Put a wall that the straight line towards the goal runs into.")


def _ring_wrap_blind() -> int:
    return search.astar_search(np.zeros(20, bool), [2], [17], heuristic_wraps=False).cost


# --- 5.6: when weighting starts to cost (answered with the live A* explorer) ---------------------

_WEIGHTS = tuple(1.0 + 0.25 * k for k in range(9))   # the explorer's slider: 1, 1.25, ..., 3


def _benchmark_search(w: float) -> int:
    """Steps of A* with weight ``w`` on the chapter's benchmark grid (100 x 100, start (0, 0),
    goal the elbow-down configuration for the point (-1.2, 0.8))."""
    arm = Arm([1.0, 1.0])
    obstacles = [Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25)]
    grid = JointGrid(arm, 100)
    occ = occupancy(arm, obstacles, grid)
    start, goal = (tuple(grid.index(q).tolist()) for q in ([0.0, 0.0], ik(arm, [-1.2, 0.8])[1]))
    return search.astar_search(occ, start, goal, heuristic_weight=w).cost


def _first_longer_weight() -> float:
    best = _benchmark_search(1.0)
    return next(w for w in _WEIGHTS if _benchmark_search(w) > best)


EXERCISES = (
    Exercise(
        "5.1", 5, "numeric", "GD1 between two cells", 1,
        "an integer: the number of steps",
        numeric(lambda: _gd1((3, 26), (50, 50), (100, 100)), exact_integer=True,
                mistakes=[(lambda: 53 + 76, "that is the long way round on both axes; take the shorter one."),
                          (lambda: 47, "that is one axis only; GD1 adds the two axes."),
                          (lambda: 24, "that is one axis only; GD1 adds the two axes.")],
                hint="on each axis take min(|a_i - b_i|, M - |a_i - b_i|), then add the axes."),
    ),
    Exercise(
        "5.2", 5, "implement", "Implement GD1", 2,
        "a function h(a, b, shape) returning the number of steps (an int)",
        implement(_gd1, _cell_pairs, call="h(a, b, shape)", names=("a", "b", "shape"),
                  compare=_compare_distance, seed=52),
    ),
    Exercise(
        "5.3", 5, "numeric", "A wrap-blind heuristic on a ring", 1,
        "an integer: the length of the path A* returns",
        numeric(_ring_wrap_blind, exact_integer=True,
                mistakes=[(lambda: 5, "5 steps is the shortest path, through the seam; but does A* with the "
                                      "wrap-blind heuristic ever pop a cell on that side before the goal?")],
                hint="write f = g + h for the first few cells on each side of the start."),
    ),
    Exercise(
        "5.4", 5, "argue", "An admissible heuristic for 8-connected moves", 2,
        "a function h(a, b, shape): your admissible, consistent heuristic for king moves",
        _judge_king_heuristic,
    ),
    Exercise(
        "5.5", 5, "argue", "Greedy best-first is not optimal", 2,
        "a tuple (occupied, start, goal) on which greedy best-first returns a longer path than A*",
        _judge_greedy_counterexample,
    ),
    Exercise(
        "5.6", 5, "numeric", "When weighting starts to cost", 1,
        "a number: the smallest weight w on the explorer's slider (1, 1.25, ..., 3) at which A*'s "
        "path on the benchmark is longer than the optimum",
        numeric(_first_longer_weight,
                mistakes=[(lambda: 2.0, "at w = 2 the path is longer, but it was already longer at a "
                                        "smaller weight; try the weights below it."),
                          (lambda: 1.25, "at w = 1.25 the path still has the optimal length (fewer "
                                         "expansions, same steps); look one notch higher.")],
                hint="set the explorer to the benchmark and raise w one notch at a time; watch the "
                     "number of steps in the status line."),
    ),
)
