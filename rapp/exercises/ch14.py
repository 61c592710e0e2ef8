"""Checks for the exercises of chapter 14, "Completeness and optimality".

Examples
--------
>>> [ex.id for ex in EXERCISES]
['14.1', '14.2', '14.3', '14.4']
>>> _all_successes_needed()
35
>>> _choose_parent_ref(Arm([1.0, 1.0]), np.array([[0.0, 0.0], [0.5, 0.0]]), np.array([1.0, 0.2]),
...                    np.array([0.6, 0.0]), [])
(1, 0.3)
"""

from __future__ import annotations

import math

import numpy as np

from rapp.arm import Arm
from rapp.collision import collides, segment_collision_free
from rapp.errors import NoPathFound, RappError
from rapp.exercises.core import Exercise, Judgement, describe, implement, numeric
from rapp.obstacles import Circle
from rapp.rrt_star import choose_parent_and_add
from rapp.sampling import Tree

__all__ = ["EXERCISES"]

_Z = 1.96  # the z of eq. (ch12-wilson), as chapter 12 uses it


# --- 14.1: all successes, how many runs? -----------------------------------------------------

def _wilson_low(k: int, n: int, z: float = _Z) -> float:
    """Lower end of the Wilson interval, eq. (ch12-wilson)."""
    return (k + z * z / 2 - z * math.sqrt(k * (n - k) / n + z * z / 4)) / (n + z * z)


def _all_successes_needed(z: float = _Z, rate: float = 0.9) -> int:
    """The fewest runs n, all successes, whose Wilson interval lies above ``rate``."""
    return next(n for n in range(1, 10_000) if _wilson_low(n, n, z) > rate)


# --- 14.2: RRT*'s choose-parent step ---------------------------------------------------------

_ARM = Arm([1.0, 1.0])  # both joints free: every difference is taken the short way round
_DISCS = (Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25))


def _choose_parent_ref(arm, near, costs, q_new, obstacles):
    """``rapp.rrt_star``'s own choose-parent step on a tree whose nodes are ``near``."""
    near = np.asarray(near, float)
    tree = Tree(arm, near)
    for i, c in enumerate(np.asarray(costs, float)):
        tree.set_parent(i, -1, float(c))
    new = choose_parent_and_add(tree, np.asarray(q_new, float), np.arange(len(near)), list(obstacles))
    if new < 0:
        return (-1, math.inf)
    return (int(tree.parent[new]), round(float(tree.cost[new]), 12))


def _free(rng, k):
    q = rng.uniform(-np.pi, np.pi, (4 * k + 20, 2))
    return q[~collides(_ARM, q, list(_DISCS))][:k]


def _parent_cases(rng: np.random.Generator) -> list[tuple]:
    """Edge cases (one node, nearest not cheapest, the seam, cheapest blocked, all blocked), then
    random ones."""
    obs = list(_DISCS)
    cases: list[tuple] = [
        (_ARM, np.array([[0.1, 0.2]]), np.array([0.7]), np.array([0.3, 0.1]), []),          # one node
        # the nearest node is not the cheapest way to q_new
        (_ARM, np.array([[2.0, 1.0], [2.3, 1.4]]), np.array([0.2, 3.0]), np.array([2.25, 1.35]), []),
        # across the seam: the node at 3.0 is 0.28 rad from -3.0 the short way round
        (_ARM, np.array([[3.0, -2.0], [-2.5, -2.0]]), np.array([0.1, 0.3]), np.array([-3.0, -2.0]), []),
        # the cheapest way to q_new is blocked by the discs; the other one is free
        (_ARM, np.array([[-0.61, 1.87], [-0.16, 1.61]]), np.array([1.62, 0.31]), np.array([-0.75, 1.34]), obs),
        # every edge blocked: no parent
        (_ARM, np.array([[2.3, -1.98], [2.25, -2.0]]), np.array([1.54, 2.0]), np.array([2.38, -1.5]), obs),
    ]
    while len(cases) < 56:
        q_new = _free(rng, 1)
        if len(q_new) == 0:
            continue
        k = int(rng.integers(2, 8))
        near = _ARM.wrap(q_new[0] + rng.uniform(-0.8, 0.8, (k, 2)))
        near = near[~collides(_ARM, near, obs)]
        if len(near) == 0:
            continue
        costs = rng.uniform(0.0, 4.0, len(near))
        cases.append((_ARM, near, costs, q_new[0], obs))
    return cases


def _pair(got):
    """``(index, cost)`` from the reader's answer, or the reason it is not one."""
    if got is None:
        return "returned None (a missing return?)."
    try:
        i, c = got
    except Exception:
        return f"returned {describe(got)}; expected a pair (index, cost)."
    if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
        return f"returned the index {describe(i)}; expected an integer (-1 for no parent)."
    try:
        c = float(np.asarray(c, dtype=float))
    except Exception:
        return f"returned the cost {describe(got[1])}, not a number."
    if math.isnan(c):
        return "returned a cost of nan; expected a number (inf when there is no parent)."
    return int(i), c


def _compare_parent(got, want, args) -> str | None:
    arm, near, costs, q_new, obstacles = args
    pair = _pair(got)
    if isinstance(pair, str):
        return pair
    i, c = pair
    wi, wc = want
    if i == wi and (math.isinf(wc) and math.isinf(c) or math.isclose(c, wc, abs_tol=1e-9)):
        return None
    d = arm.joint_delta(near, q_new)
    dist = np.sqrt((d * d).sum(axis=1))
    if wi < 0:
        return (f"returned {describe(got)}, but no near node has a certified edge to q_new here: "
                "return (-1, inf).")
    if not 0 <= i < len(near):
        if i == -1:
            return (f"returned {describe(got)}, but a near node does reach q_new by a certified edge "
                    "(check each edge with rapp.segment_collision_free, from the node to node + Δ).")
        return f"returned the index {i}, which is not an index into near."
    free = bool(segment_collision_free(arm, near[i], near[i] + d[i], obstacles))
    if not free:
        return (f"returned {describe(got)}: the edge from that node to q_new is not certified "
                "collision-free. Skip near nodes whose edge is blocked.")
    if i == wi:
        plain = float(np.linalg.norm(np.asarray(q_new) - near[i]))
        if math.isclose(c, dist[i], abs_tol=1e-9):
            return (f"returned {describe(got)}: the right parent, but the cost of q_new is the "
                    "parent's cost plus the edge length, not the edge length alone.")
        if math.isclose(c, costs[i] + plain, abs_tol=1e-9):
            return (f"returned {describe(got)}: the right parent, but the edge is measured the long way "
                    "round; use the wrap-aware difference arm.joint_delta.")
        return f"returned {describe(got)}: the right parent with the wrong cost."
    if i == int(np.argmin(dist)):
        return (f"returned {describe(got)}: that is RRT's parent, the nearest node. RRT* picks the "
                "free edge with the smallest cost(node) + distance.")
    plain = np.linalg.norm(np.asarray(q_new) - near, axis=1)
    if i == int(np.argmin(costs + plain)):
        return (f"returned {describe(got)}: with the plain difference the distance goes the long way "
                "across the ±π seam; use arm.joint_delta.")
    return (f"returned {describe(got)}: another free edge reaches q_new more cheaply "
            "(smallest cost(node) + distance).")


# --- 14.3: a staircase in three joints -------------------------------------------------------

_ARM3 = Arm([1.0, 0.8, 0.5])  # three free joints
_CELLS3 = 24
_RATIO = 1.65


def _judge_staircase(answer) -> Judgement:
    """``(q_start, q_goal)`` for the free 3-link arm: A*'s path at least 1.65 times the shortcut."""
    from rapp.planner import plan

    if answer is None:
        return Judgement(False, "no answer yet: pass (q_start, q_goal), two configurations of the 3-link arm.")
    try:
        q_s, q_g = (np.asarray(q, dtype=float) for q in answer)
    except Exception:
        return Judgement(False, f"expected a pair (q_start, q_goal); got {describe(answer)}.")
    if q_s.shape != (3,) or q_g.shape != (3,) or not (np.isfinite(q_s).all() and np.isfinite(q_g).all()):
        return Judgement(False, "q_start and q_goal must each be 3 finite joint angles (radians).")
    straight = float(np.linalg.norm(_ARM3.joint_delta(q_s, q_g)))
    if straight < 2.0:
        return Judgement(False, f"start and goal are {straight:.3g} rad apart (the short way round); "
                                "keep them at least 2 rad apart, so that snapping to the grid cells "
                                "does not decide the ratio.")
    try:
        p = plan({"arm": {"link_lengths": list(_ARM3.link_lengths)}, "start": q_s.tolist(),
                  "goal": {"joints": q_g.tolist()}, "planner": {"cells": _CELLS3}})
    except RappError as exc:
        return Judgement(False, f"rapp.plan refused it: {exc}.")
    ratio = p.metrics["waypoint_length_rad"] / p.metrics["shortcut_length_rad"]
    if ratio < _RATIO:
        return Judgement(False, f"the A* path is {ratio:.3f} times as long as the shortcut path; "
                                f"{_RATIO} is wanted. When is ‖Δ‖₁ / ‖Δ‖₂ largest?")
    # Between the centres of the start and goal cells the staircase is at most √3 times the
    # straight segment; the legs from the true start and to the true goal can push the reported
    # ratio above it, so the message says which is which rather than "at most √3".
    beyond = " (above √3 = 1.732: the legs to the true start and goal)" if ratio > math.sqrt(3) else ""
    return Judgement(True, f"the A* path, {p.metrics['path_cells']} steps and fewest possible, is "
                           f"{ratio:.3f} times as long as the straight motion{beyond}; between the "
                           f"centres of the start and goal cells it is at most √3 = 1.732.")


# --- 14.4: a sampling planner refutes a grid's "no" ------------------------------------------

_MAX_CELLS = 200


def _judge_refuted_no(answer) -> Judgement:
    """``(scenario, cells)``: delta <= rho / 2, A* says plain NoPathFound, RRT-Connect plans."""
    from rapp.grid_route import grid_step_motion, obstacle_size
    from rapp.planner import plan
    from rapp.scenario import load_scenario
    from rapp.cspace import JointGrid

    if answer is None:
        return Judgement(False, "no answer yet: pass (scenario, cells).")
    try:
        scenario, cells = answer
    except Exception:
        return Judgement(False, f"expected a pair (scenario, cells); got {describe(answer)}.")
    if isinstance(cells, (bool, np.bool_)) or not isinstance(cells, (int, np.integer)) or not 2 <= cells <= _MAX_CELLS:
        return Judgement(False, f"cells must be one integer from 2 to {_MAX_CELLS} (cells per joint), "
                                f"got {describe(cells)}.")
    try:
        s = load_scenario(scenario)
    except RappError as exc:
        return Judgement(False, f"the scenario does not load: {exc}.")
    except Exception as exc:
        return Judgement(False, f"the scenario does not load ({type(exc).__name__}); pass a dict.")
    if s.arm.n != 2:
        return Judgement(False, "use a 2-link arm, so that the check stays quick.")
    if not s.obstacles:
        return Judgement(False, "the scenario has no obstacle; a grid never says no without one.")
    delta = grid_step_motion(s.arm, JointGrid(s.arm, int(cells)))
    rho = min(obstacle_size(ob) for ob in s.obstacles)
    if delta > rho / 2:
        return Judgement(False, f"on {int(cells)} cells one step moves the arm up to {delta:.3f} m, more "
                                f"than half the thinnest obstacle's half-thickness ({rho / 2:.3f} m); "
                                "use a finer grid, or thicker obstacles.")
    d = s.to_dict()
    d["planner"] = {"algorithm": "astar", "cells": int(cells)}
    try:
        plan(d)
        return Judgement(False, f"on {int(cells)} cells the grid planner finds a path; make the passage "
                                "narrower than one grid step in C-space.")
    except NoPathFound as exc:
        if type(exc) is not NoPathFound:
            return Judgement(False, f"the grid planner raised {type(exc).__name__}; a plain NoPathFound "
                                    "is wanted.")
    except RappError as exc:
        return Judgement(False, f"the grid planner raised {type(exc).__name__}: {exc}.")
    d["planner"] = {"algorithm": "rrt_connect", "seed": 0, "max_iterations": 5000}
    try:
        p = plan(d)
    except RappError as exc:
        return Judgement(False, f"the grid says no path, but RRT-Connect (seed 0, 5000 iterations) "
                                f"found none either ({type(exc).__name__}); is there a path at all? "
                                "Leave a passage with some clearance.")
    if not p.report.ok:
        return Judgement(False, "RRT-Connect's plan did not pass verification.")
    return Judgement(True, f"on {int(cells)} cells (δ = {delta:.3f} m ≤ ρ/2) the grid says NoPathFound, "
                           "and RRT-Connect plans a verified path: that grid's no was about the grid.")


EXERCISES = (
    Exercise(
        "14.1", 14, "numeric", "All successes, how many runs", 1,
        "an integer: the fewest runs n",
        numeric(_all_successes_needed, exact_integer=True,
                mistakes=[(lambda: 1, "the textbook interval p̂ ± z√(p̂(1 − p̂)/n) has width 0 when "
                                      "every run succeeds, so it 'proves' a rate of 1 from one run; "
                                      "use the Wilson interval of eq. ch12-wilson."),
                          (lambda: 30, "that is the 'rule of three' (3/n ≤ 0.1), a one-sided bound; "
                                       "use the lower end of the Wilson interval with z = 1.96."),
                          (lambda: _all_successes_needed(1.645), "that uses z = 1.645, a one-sided or "
                                                                 "90 % interval; the 95 % interval has z = 1.96."),
                          (lambda: _all_successes_needed(2.0), "that rounds z to 2; use z = 1.96."),
                          (lambda: _all_successes_needed() - 1, "at that n the lower end is still below 0.9.")],
                hint="with k = n, the lower end of eq. ch12-wilson simplifies to n / (n + z²)."),
    ),
    Exercise(
        "14.2", 14, "implement", "Choose the parent", 2,
        "a function choose_parent(arm, near, costs, q_new, obstacles) returning (index, cost), "
        "or (-1, inf) when no edge is certified",
        implement(_choose_parent_ref, _parent_cases, call="choose_parent(arm, near, costs, q_new, obstacles)",
                  names=("arm", "near", "costs", "q_new", "obstacles"), compare=_compare_parent, seed=142,
                  time_limit=10.0),
    ),
    Exercise(
        "14.3", 14, "argue", "A staircase in three joints", 2,
        "a pair (q_start, q_goal) of configurations of the free 3-link arm, in radians",
        _judge_staircase,
    ),
    Exercise(
        "14.4", 14, "argue", "A sampling planner refutes a grid", 3,
        "a pair (scenario, cells): a 2-link scenario dict and the cells per joint of the grid",
        _judge_refuted_no,
    ),
)
