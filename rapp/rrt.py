"""Rapidly-exploring random trees in joint space (seed 003, LC3).

The tree grows from the start configuration. Each iteration draws a target:
with probability ``goal_bias`` (the report's beta) the goal, otherwise a
configuration drawn uniformly within the joint bounds. The node nearest to the
target is extended toward it and the new node is kept only when the whole
joint-space edge is certified collision-free
(:func:`rapp.collision.segment_collision_free`, a proof and not a sampling
resolution), so every edge of every returned path is collision-free.

Two steering rules:

``steer="step"`` (default)
    Move a fixed joint-space distance ``step`` toward the target (less if the
    target is nearer): the usual RRT, reaching a goal ``d`` away in about
    ``d / step`` goal-biased iterations.
``steer="fraction"``
    Seed 003's rule ``q_new = q_near + alpha (q_target - q_near)`` with
    ``0 < alpha <= 1``: the step is a fraction of the distance, so repeated
    goal-biased steps close the gap geometrically, ``d_k = (1 - alpha)^k d_0``.

Wrapping. A joint without limits is a circle: the difference of two angles is
wrapped into ``[-pi, pi)`` before measuring distance (nearest neighbour) and
before steering, so the tree moves the short way across the ``±pi`` seam.
Tree nodes are stored wrapped; the returned *path* is unwrapped (each waypoint
is the previous one plus the wrapped edge), so that the straight segment
between consecutive waypoints is exactly the edge that was certified. Limited
joints never wrap: samples lie within the limits and steering interpolates,
so every node stays within them.

Goals. A joint-space goal (one configuration or several, e.g. every IK
solution) is reached when a node lies within ``goal_threshold`` of one of them
(wrapped Euclidean distance); the goal itself is then appended when the last
edge to it is free, so the path ends exactly at the goal. A task-space goal
``goal_xy`` is reached when the end effector lies within ``goal_threshold``
(task-space units) of it, as in the report. With only ``goal_xy``, a
goal-biased iteration targets a Gauss-Newton step (the report's Algorithm 1,
``q + J^+ dx``) from the node whose end effector is nearest to ``goal_xy``.

Speed. Edges are certified in batches: each batch of random targets is
steered from the tree as it stands and all those edges are checked in one
vectorized call; a target whose nearest node was added later in the same batch
gets its own check. The tree is exactly the one grown edge by edge.

Failure. :func:`rrt` raises :class:`rapp.NoPathFound` when ``max_iterations``
pass without reaching the goal (the planner relies on this); with
``raise_on_failure=False`` it returns a result with ``success=False`` instead,
which is what parameter sweeps use.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from rapp.arm import wrap_angle
from rapp.collision import collides, segment_collision_free
from rapp.errors import NoPathFound
from rapp.ik import jacobian

__all__ = ["RRTResult", "rrt", "plan_rrt", "path_cost", "alpha_beta_experiment"]

_BATCH = 32  # random targets drawn, and edges certified together, per batch


@dataclass(frozen=True, eq=False)
class RRTResult:
    """The outcome of one RRT run.

    Attributes
    ----------
    path : ndarray, shape (k, n)
        Start to goal, unwrapped (see the module notes); ``(0, n)`` on failure.
    nodes : ndarray, shape (m, n)
        Every tree node, root (the start) first, wrapped into the joint bounds.
    parent : ndarray of int, shape (m,)
        The tree as a parent map: ``parent[i]`` is the index of node ``i``'s
        parent, ``-1`` for the root.
    iterations : int
        Iterations run (on success, the iteration that reached the goal).
    success : bool
    cost : float
        Joint-space length of ``path`` (sum of Euclidean edge lengths, radians);
        ``inf`` on failure.
    """

    path: np.ndarray
    nodes: np.ndarray
    parent: np.ndarray
    iterations: int
    success: bool
    cost: float


def _wrap_free(q, free):
    """``q`` with the free joints wrapped into ``[-pi, pi)``; limited joints untouched."""
    return np.where(free, wrap_angle(q), q)


def _delta(a, b, free):
    """``b - a`` with free joints wrapped into ``[-pi, pi)``."""
    return _wrap_free(np.asarray(b, dtype=float) - np.asarray(a, dtype=float), free)


def path_cost(path) -> float:
    """Joint-space length of a polyline: the sum of its edges' Euclidean lengths.

    Parameters
    ----------
    path : array_like, shape (k, n)
        Unwrapped waypoints.

    Examples
    --------
    >>> path_cost([[0.0, 0.0], [0.3, 0.4], [0.3, 1.4]])
    1.5
    """
    p = np.asarray(path, dtype=float)
    if p.shape[0] < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(p, axis=0), axis=-1).sum())


def rrt(
    arm,
    start,
    goal=None,
    obstacles=(),
    *,
    goal_xy=None,
    step: float = 0.1,
    goal_bias: float = 0.1,
    goal_threshold: float = 0.05,
    max_iterations: int = 5000,
    seed=0,
    steer: str = "step",
    raise_on_failure: bool = True,
) -> RRTResult:
    """Grow an RRT in joint space from ``start`` until it reaches the goal.

    Parameters
    ----------
    arm : Arm
    start : array_like, shape (n,)
        Must be collision-free.
    goal : array_like, shape (n,) or (g, n), optional
        Goal configuration(s). Used for goal-biased samples; the goal test is
        in joint space unless ``goal_xy`` is given.
    obstacles : iterable of Circle and Polygon
    goal_xy : array_like, shape (2,), optional
        Task-space goal: success when the end effector is within
        ``goal_threshold`` of it.
    step : float
        Alpha: the joint-space step (radians) for ``steer="step"``, the
        fraction in ``(0, 1]`` for ``steer="fraction"``.
    goal_bias : float
        Beta in ``[0, 1]``: probability of targeting the goal.
    goal_threshold : float
        Radius of the goal region (joint space, or task space with ``goal_xy``).
    max_iterations : int
    seed : int or numpy.random.SeedSequence
        Seeds a ``numpy.random.Generator``; same seed, same tree.
    steer : {"step", "fraction"}
    raise_on_failure : bool
        Raise :class:`rapp.NoPathFound` (default) or return ``success=False``.

    Returns
    -------
    RRTResult

    Raises
    ------
    NoPathFound
        The start collides, the goal is beyond reach, or ``max_iterations``
        passed without reaching the goal (unless ``raise_on_failure=False``).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> res = rrt(arm, [0.0, 0.0], [np.pi / 2, 0.0], [Circle((1.5, 1.5), 0.4)], step=0.2, seed=1)
    >>> res.success, res.path[0].tolist(), bool(np.allclose(res.path[-1], [np.pi / 2, 0.0]))
    (True, [0.0, 0.0], True)
    >>> int(res.parent[0]), res.nodes.shape[0] == res.parent.shape[0]
    (-1, True)
    """
    obstacles = list(obstacles)
    n = arm.n
    start = arm._check_q(start).reshape(n)
    free = ~arm.limited
    lower, upper = arm.lower, arm.upper
    if steer not in ("step", "fraction"):
        raise ValueError(f"steer must be 'step' or 'fraction', got {steer!r}")
    step = float(step)
    if not step > 0 or (steer == "fraction" and step > 1):
        raise ValueError(f"step must be > 0 (and <= 1 for steer='fraction'), got {step}")
    if not 0.0 <= goal_bias <= 1.0:
        raise ValueError(f"goal_bias must lie in [0, 1], got {goal_bias}")
    if not goal_threshold > 0:
        raise ValueError(f"goal_threshold must be > 0, got {goal_threshold}")
    goals = None if goal is None else arm._check_q(goal).reshape(-1, n)
    if goals is None and goal_xy is None:
        raise ValueError("give a joint goal, a task-space goal_xy, or both")
    gxy = None if goal_xy is None else np.asarray(goal_xy, dtype=float).reshape(2)

    def fail(msg, nodes, parent, it):
        if raise_on_failure:
            raise NoPathFound(msg)
        return RRTResult(np.empty((0, n)), nodes, parent, it, False, float("inf"))

    root = _wrap_free(start, free)
    if collides(arm, start, obstacles):
        return fail("the start configuration collides", root[None], np.array([-1]), 0)
    if gxy is not None and np.linalg.norm(gxy) > arm.reach[1] + goal_threshold:
        return fail("goal_xy is beyond the arm's reach", root[None], np.array([-1]), 0)

    rng = np.random.default_rng(seed)
    cap = 256
    nodes = np.empty((cap, n))
    parent = np.empty(cap, dtype=int)
    xy = np.empty((cap, 2))  # end effector of every node, for task-space tests
    nodes[0], parent[0], xy[0] = root, -1, arm.end_effector(root)
    m = 1

    def reached(q, p):
        if gxy is not None:
            return np.linalg.norm(p - gxy) <= goal_threshold
        return np.min(np.linalg.norm(_delta(q, goals, free), axis=-1)) <= goal_threshold

    def steer_from(base, target):
        """Nearest node(s) among ``base`` to each target and the steered new configuration."""
        diff = _delta(base[None, :, :], target[:, None, :], free)  # (t, m, n)
        d2 = np.einsum("tmi,tmi->tm", diff, diff)
        i = np.argmin(d2, axis=1)
        rows = np.arange(target.shape[0])
        dq, dist = diff[rows, i], np.sqrt(d2[rows, i])
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.minimum(1.0, step / dist) if steer == "step" else np.full_like(dist, step)
        # Unwrapped: the edge certified is the short way round.
        return i, base[i] + scale[:, None] * dq, dist

    hit = 0 if reached(root, xy[0]) else -1
    it = 0
    newton_goal = goals is None
    while hit < 0 and it < max_iterations:
        # Random numbers come in fixed batches, so a run is a prefix of any longer run.
        u = rng.random(_BATCH)
        targets = rng.uniform(lower, upper, (_BATCH, n))
        to_goal = u < goal_bias
        if goals is not None:
            pick = rng.integers(goals.shape[0], size=_BATCH)
            targets[to_goal] = goals[pick[to_goal]]
        # Speculation: the edges each target would add to the tree as it is now, certified in
        # one batched call. A target whose nearest node turns out to be one added later in this
        # batch (or a Newton target, known only then) gets its own check; the tree is the same
        # as one grown edge by edge.
        m0 = m
        spec = ~to_goal if newton_goal else np.ones(_BATCH, dtype=bool)
        spec_i = np.full(_BATCH, -1)
        spec_free = np.zeros(_BATCH, dtype=bool)
        if spec.any():
            i_s, q_s, d_s = steer_from(nodes[:m0], targets[spec])
            ok = d_s > 0
            spec_free_s = np.zeros(i_s.shape, dtype=bool)
            if ok.any():
                spec_free_s[ok] = segment_collision_free(arm, nodes[i_s[ok]], q_s[ok], obstacles)
            spec_i[spec], spec_free[spec] = i_s, spec_free_s
        for k in range(_BATCH):
            if hit >= 0 or it >= max_iterations:
                break
            it += 1
            target = targets[k]
            if newton_goal and to_goal[k]:
                j = np.argmin(np.einsum("ij,ij->i", xy[:m] - gxy, xy[:m] - gxy))
                newton = np.linalg.pinv(jacobian(arm, nodes[j])) @ (gxy - xy[j])
                target = np.clip(nodes[j] + newton, lower, upper)
            i, q_new, dist = steer_from(nodes[:m], target[None])
            i, q_new, dist = int(i[0]), q_new[0], dist[0]
            if dist == 0.0:
                continue
            if i == spec_i[k] and i < m0:
                edge_free = spec_free[k]
            else:
                edge_free = bool(segment_collision_free(arm, nodes[i], q_new, obstacles))
            if not edge_free:
                continue
            if m == cap:
                cap *= 2
                nodes = np.concatenate((nodes, np.empty_like(nodes)))
                parent = np.concatenate((parent, np.empty_like(parent)))
                xy = np.concatenate((xy, np.empty_like(xy)))
            nodes[m] = _wrap_free(q_new, free)
            parent[m], xy[m] = i, arm.end_effector(q_new)
            m += 1
            if reached(nodes[m - 1], xy[m - 1]):
                hit = m - 1

    if hit < 0:
        return fail(
            f"RRT reached no goal in {max_iterations} iterations", nodes[:m].copy(), parent[:m].copy(), it
        )
    if goals is not None and gxy is None:
        # End exactly at the nearest goal when that last edge is free too.
        gd = _delta(nodes[hit], goals, free)
        g = int(np.argmin(np.einsum("ij,ij->i", gd, gd)))
        if np.any(gd[g] != 0) and segment_collision_free(arm, nodes[hit], nodes[hit] + gd[g], obstacles):
            if m == cap:
                nodes = np.concatenate((nodes, nodes[:1]))
                parent = np.concatenate((parent, parent[:1]))
            nodes[m] = goals[g]
            parent[m] = hit
            hit, m = m, m + 1
    chain = [hit]
    while parent[chain[-1]] >= 0:
        chain.append(int(parent[chain[-1]]))
    walk = nodes[chain[::-1]]
    steps = _delta(walk[:-1], walk[1:], free)
    path = np.concatenate((start[None], start + np.cumsum(steps, axis=0)))
    return RRTResult(path, nodes[:m].copy(), parent[:m].copy(), it, True, path_cost(path))


_SETTINGS = ("step", "goal_bias", "goal_threshold", "max_iterations", "seed", "steer")


def plan_rrt(arm, obstacles, start, goal_qs=None, *, goal_xy=None, settings: Mapping | None = None):
    """The planner's adapter: a collision-free joint-space waypoint path, or NoPathFound.

    Parameters
    ----------
    arm : Arm
    obstacles : iterable of Circle and Polygon
    start : array_like, shape (n,)
    goal_qs : array_like, shape (n,) or (g, n), optional
        Goal configuration(s), e.g. every IK solution of a Cartesian goal.
    goal_xy : array_like, shape (2,), optional
        Task-space goal (see :func:`rrt`).
    settings : mapping, optional
        Any of ``step``, ``goal_bias``, ``goal_threshold``,
        ``max_iterations``, ``seed``, ``steer``; other keys (settings of
        other planners) are ignored.

    Returns
    -------
    ndarray, shape (k, n)
        Unwrapped waypoints, ``start`` first; every straight segment between
        consecutive waypoints is certified collision-free.

    Examples
    --------
    >>> from rapp import Arm
    >>> plan_rrt(Arm([1.0, 1.0]), [], [0.0, 0.0], [0.25, 0.0], settings={"step": 0.1}).round(2).tolist()
    [[0.0, 0.0], [0.1, 0.0], [0.2, 0.0], [0.25, 0.0]]
    """
    kw = {k: settings[k] for k in _SETTINGS if settings and k in settings}
    return rrt(arm, start, goal_qs, obstacles, goal_xy=goal_xy, **kw).path


def alpha_beta_experiment(
    arm,
    start,
    goal_xy,
    obstacles,
    alphas,
    betas,
    trials: int,
    seed=0,
    *,
    goal=None,
    steer: str = "fraction",
    goal_threshold: float = 0.05,
    max_iterations: int = 2000,
) -> dict:
    """Seed 003's experiment: success rate, path cost and iterations over a grid of alpha and beta.

    Every ``(alpha, beta)`` cell runs the same ``trials`` seeds (common random
    numbers, so that cells differ by the parameters and not by luck).

    Parameters
    ----------
    alphas, betas : array_like, shape (A,), (B,)
    trials : int
    goal : array_like, optional
        A goal configuration for goal-biased samples (the report's ``qGoal``).
    steer : {"fraction", "step"}
        ``"fraction"`` is the report's rule.

    Returns
    -------
    dict of ndarray
        ``alpha`` (A,), ``beta`` (B,), and of shape (A, B): ``success_rate``,
        ``mean_cost`` (over successful trials, ``nan`` if none),
        ``mean_iterations`` (over all trials; a failure counts
        ``max_iterations``).

    Examples
    --------
    >>> from rapp import Arm
    >>> out = alpha_beta_experiment(Arm([1.0, 1.0]), [0.0, 0.0], [0.0, 2.0], [], [0.5], [1.0], 2)
    >>> out["success_rate"].tolist(), out["mean_iterations"].tolist()
    ([[1.0]], [[9.0]])
    """
    alphas = np.asarray(alphas, dtype=float).reshape(-1)
    betas = np.asarray(betas, dtype=float).reshape(-1)
    seeds = np.random.SeedSequence(seed).spawn(int(trials))
    shape = (alphas.size, betas.size, int(trials))
    ok = np.zeros(shape, dtype=bool)
    cost = np.full(shape, np.nan)
    iters = np.zeros(shape)
    for a, alpha in enumerate(alphas):
        for b, beta in enumerate(betas):
            for t, s in enumerate(seeds):
                r = rrt(
                    arm, start, goal, obstacles, goal_xy=goal_xy, step=alpha, goal_bias=beta,
                    goal_threshold=goal_threshold, max_iterations=max_iterations, seed=s,
                    steer=steer, raise_on_failure=False,
                )
                ok[a, b, t], iters[a, b, t] = r.success, r.iterations
                if r.success:
                    cost[a, b, t] = r.cost
    with np.errstate(invalid="ignore"):
        with_cost = np.where(ok, cost, 0.0).sum(-1) / ok.sum(-1)
    return {
        "alpha": alphas,
        "beta": betas,
        "success_rate": ok.mean(-1),
        "mean_cost": np.where(ok.any(-1), with_cost, np.nan),
        "mean_iterations": iters.mean(-1),
    }
