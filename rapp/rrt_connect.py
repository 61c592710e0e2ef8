"""RRT-Connect: two trees, one from the start and one from the goals, grown toward each other.

Each iteration draws a random configuration; one tree *extends* one step of at most ``step``
toward it, and the other tree then *connects*: it steps toward the new node again and again
until it reaches it or is blocked. The trees swap roles every iteration. Every edge is certified
collision-free (:func:`rapp.collision.segment_collision_free`), so the returned path is; a
connect attempt certifies its whole chain of steps in one vectorized call and keeps the longest
free prefix, the same tree as stepping one edge at a time.

References
----------
Kuffner and LaValle (2000), RRT-Connect: an efficient approach to single-query path planning.
"""

from __future__ import annotations

import numpy as np

from rapp.checks import finite_number
from rapp.collision import collides, segment_collision_free
from rapp.errors import NoPathFound
from rapp.paths import path_length
from rapp.rrt import RRTResult
from rapp.sampling import Budget, Tree, check_start_and_goals, uniform_samples, unwrapped_chain

__all__ = ["rrt_connect"]


def _extend(tree: Tree, target, step: float, obstacles, chain: bool):
    """Step from the node nearest ``target`` toward it: one step, or (``chain``) until blocked.

    Returns ``(index of the last node added or -1, reached)``; ``reached`` means that node is
    ``target`` itself (the short way round).
    """
    arm = tree.arm
    i = tree.nearest(target)
    base = tree.nodes[i]
    d = arm.joint_delta(base, target)
    dist = float(np.sqrt(d @ d))
    if dist == 0.0:
        return i, True
    k = int(np.ceil(dist / step)) if chain else 1
    frac = np.minimum(np.arange(1, k + 1) * step / dist, 1.0)
    points = base + frac[:, None] * d  # unwrapped from base: the certified motion
    prev = np.vstack((base, points[:-1]))
    # A step that ends in collision cannot be free: one cheap point test of the whole chain
    # first, and only the steps before the first colliding point are certified.
    hit = collides(arm, points, obstacles)
    reach = int(np.argmax(hit)) if hit.any() else k
    free = segment_collision_free(arm, prev[:reach], points[:reach], obstacles) if reach else hit[:0]
    ok = int(np.argmin(free)) if not free.all() else reach  # the free prefix
    last = -1
    parent = i
    for j in range(ok):
        step_len = float(np.linalg.norm(points[j] - prev[j]))
        parent = tree.add(points[j], parent, tree.cost[parent] + step_len)
        last = parent
    return last, ok == k and frac[-1] == 1.0


def rrt_connect(arm, start, goal, obstacles=(), *, step: float = 0.1, seed=0,
                max_iterations: int = 5000, time_budget: float | None = None,
                raise_on_failure: bool = True) -> RRTResult:
    """Plan from ``start`` to a goal configuration with two trees that grow toward each other.

    Parameters
    ----------
    arm : Arm
    start : array_like, shape (n,)
    goal : array_like, shape (n,) or (g, n)
        Goal configuration(s); the second tree has one root per free goal.
    obstacles : iterable of Circle and Polygon
    step : float
        Largest joint-space step of one edge (rad).
    seed : int or numpy.random.SeedSequence
        Same seed, same result (unless ``time_budget`` cuts a run short).
    max_iterations : int
        Iterations (random samples) at most.
    time_budget : float, optional
        Seconds at most.
    raise_on_failure : bool
        Raise :class:`rapp.NoPathFound` (default) or return ``success=False``.

    Returns
    -------
    RRTResult
        ``path`` from the exact start to the exact goal (unwrapped), ``nodes`` of both trees
        (the start's tree first) with their ``parent`` map (-1 at each root), ``cost`` its
        joint-space length.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> res = rrt_connect(arm, [0.0, 0.0], [2.5, 0.0], [Circle((0.0, 1.2), 0.3)], step=0.2, seed=1)
    >>> res.success, res.path[0].tolist(), bool(np.allclose(arm.wrap(res.path[-1]), [2.5, 0.0]))
    (True, [0.0, 0.0], True)
    """
    obstacles = list(obstacles)
    step = finite_number(step, "step", above=0.0)
    budget = Budget(max_iterations, time_budget)
    start, goals = check_start_and_goals(arm, start, goal, obstacles)
    rng = np.random.default_rng(seed)
    trees = [Tree(arm, [start]), Tree(arm, goals)]
    meet = None
    # The start may already see a goal along one straight chain.
    j, reached = _extend(trees[1], start, step, obstacles, chain=True)
    if reached:
        meet = (0, j)
    while meet is None and not budget.spent():
        a, b = trees if budget.iterations % 2 else trees[::-1]
        q_rand = uniform_samples(arm, rng, 1)[0]
        new, _ = _extend(a, q_rand, step, obstacles, chain=False)
        if new < 0:
            continue
        other, reached = _extend(b, a.nodes[new], step, obstacles, chain=True)
        if reached:
            meet = (new, other) if a is trees[0] else (other, new)
    nodes = np.vstack((trees[0].nodes, trees[1].nodes))
    parent = np.concatenate((trees[0].parent, np.where(trees[1].parent >= 0,
                                                      trees[1].parent + trees[0].m, -1)))
    if meet is None:
        if raise_on_failure:
            raise NoPathFound(f"RRT-Connect joined no goal in {budget.iterations} iterations")
        return RRTResult(np.empty((0, arm.n)), nodes, parent, budget.iterations, False, float("inf"))
    walk = _root_chain(trees[0], meet[0])[::-1] + _root_chain(trees[1], meet[1])[1:]
    path = unwrapped_chain(arm, np.array(walk), start)
    return RRTResult(path, nodes, parent, budget.iterations, True, path_length(path))


def _root_chain(tree: Tree, i: int) -> list:
    """Nodes from ``i`` up to its root (``i`` first)."""
    out = [tree.nodes[i]]
    while tree.parent[i] >= 0:
        i = int(tree.parent[i])
        out.append(tree.nodes[i])
    return out
