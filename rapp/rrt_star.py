"""RRT*: an RRT that keeps improving its path: choose the cheapest parent, then rewire.

Each new node is joined not to its nearest node but to the node within a shrinking radius
``r = min(radius, gamma (log m / m)^(1/n))`` (``radius`` is the step unless given) that reaches
it most cheaply by a certified edge; then every node within ``r`` that the new node reaches
more cheaply is rewired through it. The
cost of the best path to a goal falls toward the optimum as the samples grow (asymptotic
optimality), unlike RRT's. Every node keeps its link clearances, so that most edges are proved
free by their ends alone (:func:`rapp.sampling.endpoint_certified`); the rest are bisected.

With numba the whole iteration runs compiled (:mod:`rapp.kernels.sampling_numba`: nearest and near
nodes through a grid of cells once the tree is large, descendants' costs through child lists)
on targets drawn by the same generator, and grows the same tree bit for bit; the numpy loop is
the fallback.

References
----------
Karaman and Frazzoli (2011), Sampling-based algorithms for optimal motion planning.
"""

from __future__ import annotations

import math

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm
    from rapp.obstacles import Circle, Polygon

from rapp.kernels import sampling as sampling_backend
from rapp.kernels import collision as collision_backend
from rapp.checks import finite_number
from rapp.collision import MAX_PENDING_INTERVALS, link_clearances, reach_matrix, scene
from rapp.kernels.collision import pack
from rapp.errors import NoPathFound
from rapp.paths import PlannerResult, tree_result
from rapp.sampling import warms
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, mark_sampled, user_validity
from rapp.sampling import (Budget, ClearanceTree, EdgeCertifier, Tree, check_start_and_goals, squared_norms,
                           uniform_samples, unwrapped_chain)

__all__ = ["rrt_star", "choose_parent_and_add"]


def choose_parent_and_add(tree: Tree, q_new, near, obstacles, clear_new=None) -> int:
    """Add ``q_new`` under the near node that reaches it most cheaply; -1 if no edge is free.

    ``obstacles`` may also be an :class:`rapp.sampling.EdgeCertifier` made for them; with a
    :class:`rapp.sampling.ClearanceTree` and ``q_new``'s link clearances ``clear_new``, the
    edges' end clearances certify most of them without a bisection (the same answers).
    """
    arm = tree.arm
    certify = obstacles if isinstance(obstacles, EdgeCertifier) else EdgeCertifier(arm, obstacles)
    d = arm.joint_delta(tree.nodes[near], q_new)
    dist = np.sqrt(squared_norms(d))
    order = np.argsort(tree.cost[near] + dist, kind="stable")
    near, d, dist = near[order], d[order], dist[order]
    if clear_new is None:
        free = certify(tree.nodes[near], tree.nodes[near] + d)
    else:
        free = certify(tree.nodes[near], tree.nodes[near] + d, tree.clear[near],
                       np.broadcast_to(clear_new, d.shape))
    if not free.any():
        return -1
    k = int(np.argmax(free))
    if clear_new is None:
        return tree.add(q_new, int(near[k]), float(tree.cost[near[k]] + dist[k]))
    return tree.add(q_new, int(near[k]), float(tree.cost[near[k]] + dist[k]), clear_new)


def _rewire(tree: Tree, new: int, near, certify) -> None:
    """Give each near node the new node as parent where that is cheaper and the edge is free."""
    arm = tree.arm
    near = near[near != tree.parent[new]]
    if near.size == 0:
        return
    d = arm.joint_delta(tree.nodes[new], tree.nodes[near])
    through = tree.cost[new] + np.sqrt(squared_norms(d))
    better = near[through < tree.cost[near] - 1e-12]
    if better.size == 0:
        return
    dd = arm.joint_delta(tree.nodes[new], tree.nodes[better])
    free = certify(np.broadcast_to(tree.nodes[new], dd.shape), tree.nodes[new] + dd,
                   np.broadcast_to(tree.clear[new], dd.shape), tree.clear[better])
    for i, c in zip(better[free], (tree.cost[new] + np.sqrt(squared_norms(dd)))[free]):
        delta = c - tree.cost[i]
        tree.set_parent(int(i), new, float(c))
        _shift_subtree_cost(tree, int(i), delta)


def _shift_subtree_cost(tree: Tree, root: int, delta: float) -> None:
    """Costs below a rewired node change by the same amount (its descendants keep their edges)."""
    todo = [root]
    parent = tree.parent
    while todo:
        kids = np.flatnonzero(np.isin(parent, todo))
        kids = kids[kids != root]
        tree.shift_cost(kids, delta)
        todo = kids.tolist()


def rrt_star(arm: Arm, start: ArrayLike, goal: ArrayLike, obstacles: Iterable[Circle | Polygon] = (), *,
             step: float = 0.1, goal_bias: float = 0.1,
             goal_threshold: float = 0.01, seed: int | np.random.SeedSequence = 0, max_iterations: int = 3000,
             time_budget: float | None = None, gamma: float | None = None,
             radius: float | None = None, raise_on_failure: bool = True,
             margin: float = 0.0, validity: ValidityFunction | None = None,
             validity_resolution: float = DEFAULT_RESOLUTION) -> PlannerResult:
    """Plan with RRT*: the best path found to a goal configuration within the budget.

    It runs for the whole budget (an anytime planner), so ``max_iterations`` sets how good the
    path gets; ``iterations`` in the result is the number run.

    Parameters
    ----------
    arm, start, goal, obstacles
        As :func:`rapp.rrt_connect.rrt_connect`.
    step : float
        Largest step toward a sample (rad).
    radius : float, optional
        Largest rewiring radius (rad): the cap on ``gamma (log m / m)^(1/n)``; by default the
        step (Karaman and Frazzoli's rule, and OMPL's, whose cap is its range). A cap of a few
        steps lets a new node choose a parent, and rewire nodes, beyond one step: straighter
        paths for the same samples (on the 3-link benchmark of ``benchmarks/bench_planners.py``,
        twice the step gives paths about 15 % shorter for 5000 samples, for at most a fifth more
        time).
    goal_bias : float
        Probability of sampling a goal.
    goal_threshold : float
        A node this close to a goal (rad) is joined to it by a certified edge.
    gamma : float, optional
        Radius constant of ``gamma (log m / m)^(1/n)``; by default large enough for asymptotic
        optimality on the joint space's volume.
    margin : float
        Safety margin (metres, >= 0) every link keeps beyond its radius
        (``arm.link_radius``) from every obstacle (:func:`rapp.collision.scene`).
    validity : callable, optional
        A user's checker, ``(m, n)`` configurations -> ``m`` booleans (True: allowed), on top
        of rapp's certified obstacles: every edge is also sampled at ``validity_resolution``
        (:mod:`rapp.validity`). The planner then runs its numpy loop (compiled loops cannot
        call Python), and the result says its path was sampled (``certified`` False,
        ``checked_by``).
    validity_resolution : float
        Largest joint-space step (rad) between two samples of an edge for ``validity``.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> res = rrt_star(arm, [0.0, 0.0], [2.5, 0.0], [Circle((0.0, 1.2), 0.3)], seed=1, max_iterations=600)
    >>> res.success, bool(np.allclose(arm.wrap(res.path[-1]), [2.5, 0.0]))
    (True, True)
    """
    arm, obstacles = scene(arm, list(obstacles), margin)
    obstacles = list(obstacles)
    step = finite_number(step, "step", above=0.0)
    radius = step if radius is None else finite_number(radius, "radius", above=0.0)
    if not 0.0 <= goal_bias <= 1.0:
        raise ValueError(f"goal_bias must lie in [0, 1], got {goal_bias!r}")
    budget = Budget(max_iterations, time_budget)
    checker = user_validity(validity, validity_resolution)
    start, goals = check_start_and_goals(arm, start, goal, obstacles, checker)
    n = arm.n
    volume = float(np.prod(arm.upper - arm.lower))
    if gamma is None:
        unit_ball = math.pi ** (n / 2) / math.gamma(n / 2 + 1)
        gamma = 2.0 * ((1 + 1 / n) * volume / unit_ball) ** (1 / n)
    rng = np.random.default_rng(seed)
    # The compiled loops know obstacles only: an arm with self-collision, or a user's checker
    # (Python), grows in numpy.
    loops = (sampling_backend.kernels() if collision_backend.loaded() is not None
             and not arm.self_collision and checker is None else None)
    grown = None
    if loops is not None:
        grown = _grow_compiled(loops, arm, goals, obstacles, step, radius, goal_bias,
                               goal_threshold, gamma, rng, budget, start)
    if grown is None:  # no numba, or an edge beyond the kernel's interval limit (numpy raises)
        rng, budget = np.random.default_rng(seed), Budget(max_iterations, time_budget)
        grown = _grow(arm, goals, obstacles, step, radius, goal_bias, goal_threshold, gamma, rng,
                      budget, start, checker)
    nodes, parent, best_goal = grown
    if best_goal < 0:
        if raise_on_failure:
            raise NoPathFound(budget.stopped("RRT*", "no goal reached"))
        return mark_sampled(tree_result(arm, None, nodes, parent, budget.iterations,
                                        budget.status()), checker)
    # Rewiring may have improved the goal's branch since it was found: walk the parent map now.
    chain = [best_goal]
    while parent[chain[-1]] >= 0:
        chain.append(int(parent[chain[-1]]))
    path = unwrapped_chain(arm, nodes[chain[::-1]], start)
    return mark_sampled(tree_result(arm, path, nodes, parent, budget.iterations), checker)


def _targets(arm, goals, goal_bias, rng, k) -> np.ndarray:
    """The next ``k`` targets: a goal with probability ``goal_bias``, else a uniform sample."""
    out = np.empty((k, arm.n))
    for t in range(k):
        out[t] = (goals[rng.integers(len(goals))] if rng.random() < goal_bias
                  else uniform_samples(arm, rng, 1)[0])
    return out


def _grow(arm, goals, obstacles, step, cap, goal_bias, goal_threshold, gamma, rng, budget, start,
          checker=None):
    """The numpy loop: ``(nodes, parent, best goal node or -1)``; every edge through one
    :class:`rapp.sampling.EdgeCertifier`, with the user's ``checker`` if any."""
    n = arm.n
    certify = EdgeCertifier(arm, obstacles, checker)
    clearance = lambda q: link_clearances(arm, q, obstacles)  # noqa: E731
    tree = ClearanceTree(arm, [start], clearance)
    goal_clear = clearance(goals)
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    best_goal = -1
    while not budget.spent():
        target = _targets(arm, goals, goal_bias, rng, 1)[0]
        i = tree.nearest(target)
        d = arm.joint_delta(tree.nodes[i], target)
        dist = float(np.sqrt(squared_norms(d)))
        if dist == 0.0:
            continue
        q_new = tree.nodes[i] + min(1.0, step / dist) * d
        clear_new = clearance(q_new[None])[0]
        if (clear_new <= touch).any():  # no edge to it is free: choose_parent_and_add says -1
            continue
        m = tree.m
        radius = min(cap, gamma * (math.log(m + 1) / (m + 1)) ** (1 / n))
        near = np.flatnonzero(squared_norms(tree.deltas(q_new)) <= radius * radius)
        if i not in near:
            near = np.append(near, i)
        new = choose_parent_and_add(tree, q_new, near, certify, clear_new)
        if new < 0:
            continue
        _rewire(tree, new, near, certify)
        # A node close to a goal is joined to it exactly (the edge certified too).
        dg = arm.joint_delta(tree.nodes[new], goals)
        g = int(np.argmin(squared_norms(dg)))
        gd = float(np.sqrt(squared_norms(dg[g])))
        # Against the best goal node's cost now: rewiring may have lowered it since.
        best_cost = math.inf if best_goal < 0 else float(tree.cost[best_goal])
        if gd <= goal_threshold and tree.cost[new] + gd < best_cost:
            if gd == 0.0:
                best_goal = new
            elif certify(tree.nodes[new][None], (tree.nodes[new] + dg[g])[None],
                         tree.clear[new][None], goal_clear[g][None])[0]:
                best_goal = tree.add(goals[g], new, float(tree.cost[new] + gd), goal_clear[g])
    return tree.nodes.copy(), tree.parent.copy(), best_goal


class _Targets:
    """:func:`_targets` for the compiled loop: with one goal, parsed from blocks of the
    generator's doubles by the compiled :mod:`rapp.kernels.sampling_numba` ``draw``, the same
    targets (the stream read further ahead, which no result depends on)."""

    def __init__(self, loops, arm, goals, goal_bias, rng):
        self.loops, self.arm, self.goals, self.goal_bias, self.rng = loops, arm, goals, goal_bias, rng
        self.buf, self.pos = np.empty(0), 0
        self.span = arm.upper - arm.lower  # as rng.uniform forms it

    def __call__(self, k) -> np.ndarray:
        if len(self.goals) != 1:
            return _targets(self.arm, self.goals, self.goal_bias, self.rng, k)
        need = k * (self.arm.n + 1)
        if len(self.buf) - self.pos < need:
            self.buf = np.concatenate((self.buf[self.pos:], self.rng.random(max(4096, need))))
            self.pos = 0
        out = np.empty((k, self.arm.n))
        _, self.pos = self.loops.draw(self.buf, self.pos, float(self.goal_bias), self.arm.lower,
                                      self.span, self.goals[0], out)
        return out


#: Cells of the grid that finds nearest and near nodes in a large tree, at most.
GRID_CELLS = 1 << 20


def _grid(arm, width):
    """The cells of the compiled loop's grid: ``(lower corner, widths, cells per joint, the
    list heads)``; cells at least ``width`` (no less than the largest near radius) wide."""
    span = arm.upper - arm.lower
    # Cells wider than the near radius by a margin far above rounding: a node within the
    # radius lies in the same cell or the next on every axis.
    per = np.maximum(1, np.floor(span / (width * (1 + 1e-6)))).astype(np.int64)
    cap = int(GRID_CELLS ** (1 / arm.n))
    per = np.minimum(per, max(1, cap))
    return (np.asarray(arm.lower, float), span / per, per,
            np.full(int(np.prod(per)), -1, dtype=np.int64))


#: Iterations the compiled loop runs between two looks at the clock.
BATCH = 64


def _grow_compiled(loops, arm, goals, obstacles, step, radius, goal_bias, goal_threshold, gamma,
                   rng, budget, start):
    """:func:`_grow` in the compiled loop of :mod:`rapp.kernels.sampling_numba`, the same tree; None
    when an edge needs more bisection intervals than allowed (numpy says so then)."""
    n = arm.n
    cap = 2 * BATCH + 2
    arrays = {"nodes": np.empty((cap, n)), "clear": np.empty((cap, n)),
              "parent": np.empty(cap, dtype=np.int64),
              "cost": np.empty(cap), "first_child": np.empty(cap, dtype=np.int64),
              "next_sib": np.empty(cap, dtype=np.int64), "prev_sib": np.empty(cap, dtype=np.int64),
              "grid_next": np.empty(cap, dtype=np.int64)}
    arrays["nodes"][0] = arm.wrap(start)
    arrays["clear"][0] = link_clearances(arm, arrays["nodes"][:1], obstacles)[0]
    arrays["parent"][0], arrays["cost"][0], arrays["first_child"][0] = -1, 0.0, -1
    arrays["next_sib"][0] = arrays["prev_sib"][0] = -1
    m = np.ones(1, dtype=np.int64)
    best, best_cost = np.full(1, -1, dtype=np.int64), np.full(1, np.inf)
    scratch = None
    # Cells of two steps (or the radius, if wider): cells of one step left most of them empty
    # on the benchmark, and the nearest-node search slower (the same trees either way).
    grid = _grid(arm, max(2 * step, radius))
    problem = sampling_backend.StarProblem(step, radius, gamma, goal_threshold,
                                           np.ascontiguousarray(goals),
                                           link_clearances(arm, goals, obstacles))
    scene = sampling_backend.Scene(arm.lengths, np.asarray(arm.limited, dtype=np.bool_),
                                   reach_matrix(arm), *pack(obstacles),
                                   16 * np.finfo(float).eps * float(np.sum(arm.lengths)), 1e-9,
                                   MAX_PENDING_INTERVALS)
    draw = _Targets(loops, arm, goals, goal_bias, rng)
    indexed = np.zeros(1, dtype=np.int64)  # nodes already in the grid
    while True:
        k = budget.grant(BATCH)
        if not k:
            break
        if m[0] + 2 * k > cap:  # each iteration adds two nodes at most (the new one, a goal)
            cap = 2 * (m[0] + 2 * k)
            for name, a in arrays.items():
                grown = np.empty((cap,) + a.shape[1:], dtype=a.dtype)
                grown[: m[0]] = a[: m[0]]
                arrays[name] = grown
            scratch = None
        if scratch is None:  # near set, its deltas, distances, sort keys; a DFS stack
            scratch = sampling_backend.NearSet(
                np.empty(cap, dtype=np.int64), np.empty((cap, n)), np.empty(cap), np.empty(cap),
                np.empty(cap, dtype=np.int64))
            tree = sampling_backend.StarTree(
                arrays["nodes"], arrays["clear"], arrays["parent"], arrays["cost"],
                arrays["first_child"], arrays["next_sib"], arrays["prev_sib"], m, best, best_cost)
            cells = sampling_backend.Cells(*grid, arrays["grid_next"], indexed)
        status, ran = loops.star(draw(k), problem, scene, tree, cells, scratch)
        budget.iterations += int(ran)
        if status == sampling_backend.CONNECT_LIMIT:
            return None
    mm = int(m[0])
    return arrays["nodes"][:mm].copy(), arrays["parent"][:mm].copy(), int(best[0])


# Its kernels are compiled before a time budget of it starts (rapp.sampling.prepare_kernels).
warms(rrt_star, max_iterations=100)
