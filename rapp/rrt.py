"""Rapidly-exploring random trees in joint space.

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

Recording. Pass a list as ``trace`` and :func:`rrt` appends one
:class:`RRTStep` per iteration (the target, the nearest node, the steered
configuration, whether the edge was added or blocked), plus one for the last
edge to a joint goal; :func:`rapp.plotting.plot_rrt_step` draws them. The
recording changes nothing: the same seed gives the same tree and path.

Failure. :func:`rrt` raises :class:`rapp.NoPathFound` when ``max_iterations``
pass without reaching the goal (the planner relies on this); with
``raise_on_failure=False`` it returns a result with ``success=False`` instead,
which is what parameter sweeps use.

References
----------
LaValle (1998), Rapidly-exploring random trees: a new tool for path planning.
Seed 003 (the 3-link RRT report): step alpha, goal bias beta, its Algorithm 1.
SRS of 2D-RAPP (seed 000): LC3 (other planners).
"""

from __future__ import annotations

import inspect
import time
from dataclasses import dataclass
from typing import Mapping

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm
    from rapp.obstacles import Circle, Polygon

from rapp.kernels import collision as collision_backend
from rapp import progress
from rapp.collision import collides, scene, segment_collision_free
from rapp.errors import InvalidSetting, NoPathFound
from rapp.ik import jacobian
from rapp.paths import ITERATION_CAP, NO_PATH, TIME_BUDGET_SPENT, PlannerResult, tree_result
from rapp.sampling import warms
from rapp.sampling import Budget, EdgeCertifier, Tree
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, mark_sampled, user_validity

__all__ = ["RRTResult", "RRTStep", "rrt", "plan_rrt", "check_reachable", "Grower", "MIN_STEP", "MAX_STEP"]

_BATCH = 32  # random targets drawn, and edges certified together, per batch

#: The joint-space step of the sampling planners lies in ``[MIN_STEP, MAX_STEP]`` rad. Below
#: 1e-6 rad no joint can be told apart (a 20-bit encoder resolves 6e-6 rad), and a step above
#: pi would steer the long way round. With ``steer="step"``, :func:`rrt` also refuses a step
#: too small to reach the goal within ``max_iterations`` (each iteration advances at most one
#: step), and RRT-Connect one too small for its node limit.
MIN_STEP, MAX_STEP = 1e-6, float(np.pi)


#: The result of every planner (:class:`rapp.paths.PlannerResult`): ``path``, ``success``,
#: ``cost`` and, for RRT, ``nodes`` (every tree node, root first, wrapped into the joint
#: bounds), ``parent`` (``parent[i]`` the index of node ``i``'s parent, -1 for the root) and
#: ``iterations`` (on success, the iteration that reached the goal). The old name is kept.
RRTResult = PlannerResult


@dataclass(frozen=True, eq=False)
class RRTStep:
    """One recorded iteration of :func:`rrt` (what ``trace`` receives).

    Attributes
    ----------
    iteration : int
        The iteration, from 1 (a ``join`` record carries the iteration that
        reached the goal region; 0 when the start already lies in it).
    target : ndarray, shape (n,)
        The configuration the tree was extended toward: a uniform sample, the
        goal when ``goal_biased`` (with ``goal_xy`` alone: the Gauss-Newton
        target), the exact goal for a ``join``.
    goal_biased : bool
        The target is the goal (drawn with probability beta), or a ``join``.
    nearest : int
        Index in ``RRTResult.nodes`` of the tree node nearest to ``target``
        (wrapped joint-space distance).
    new : ndarray, shape (n,)
        The steered configuration, unwrapped from the nearest node: the edge
        certified is the straight segment ``nodes[nearest] -> new``.
    status : {"added", "blocked", "no move"}
        ``"added"``: the edge was certified collision-free and ``new`` became
        node ``node``; ``"blocked"``: the edge could not be certified free
        (:func:`rapp.collision.segment_collision_free` is False) and nothing
        was added; ``"no move"``: the target was the nearest node itself.
    node : int
        Index of the node added, ``-1`` unless ``status == "added"``.
    join : bool
        The last edge, from the node that reached the goal region to the exact
        goal configuration (joint goals only).
    """

    iteration: int
    target: np.ndarray
    goal_biased: bool
    nearest: int
    new: np.ndarray
    status: str
    node: int
    join: bool = False

    @property
    def accepted(self) -> bool:
        """True when the edge was certified free and a node added."""
        return self.status == "added"


def rrt(
    arm: Arm,
    start: ArrayLike,
    goal: ArrayLike | None = None,
    obstacles: Iterable[Circle | Polygon] = (),
    *,
    goal_xy: ArrayLike | None = None,
    step: float = 0.1,
    goal_bias: float = 0.1,
    goal_threshold: float = 0.01,
    max_iterations: int = 20000,
    seed: int | np.random.SeedSequence = 0,
    steer: str = "step",
    raise_on_failure: bool = True,
    trace: list | None = None,
    time_budget: float | None = None,
    margin: float = 0.0,
    validity: ValidityFunction | None = None,
    validity_resolution: float = DEFAULT_RESOLUTION,
) -> PlannerResult:
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
    trace : list, optional
        When a list is given, one :class:`RRTStep` per iteration is appended to
        it (and one for the last edge to a joint goal). Off by default; it
        never changes the result.
    time_budget : float, optional
        Seconds at most (as for the other sampling planners); a run cut short
        by it depends on the machine, a run without it does not.
    margin : float
        Safety margin (metres, >= 0) every link keeps beyond its radius
        (``arm.link_radius``) from every obstacle (:func:`rapp.collision.scene`).
    validity : callable, optional
        A user's checker, ``(m, n)`` configurations -> ``m`` booleans (True: allowed), on top
        of rapp's certified obstacles: every edge is also sampled at ``validity_resolution``
        (:mod:`rapp.validity`), and a start it rejects is refused. The result says its path
        was sampled (``certified`` False, ``checked_by``). RRT has no compiled loop: nothing
        else changes.
    validity_resolution : float
        Largest joint-space step (rad) between two samples of an edge for ``validity``.

    Returns
    -------
    PlannerResult
        ``path``, ``success``, ``cost``; its details ``nodes``, ``parent``, ``iterations``.

    Raises
    ------
    NoPathFound
        The start collides, every joint goal collides (said before any iteration; a
        colliding goal among others is dropped), the goal is beyond reach, or ``max_iterations``
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
    >>> steps = []
    >>> again = rrt(arm, [0.0, 0.0], [np.pi / 2, 0.0], [Circle((1.5, 1.5), 0.4)], step=0.2, seed=1,
    ...             trace=steps)
    >>> np.array_equal(again.path, res.path), sum(s.accepted for s in steps) == len(res.nodes) - 1
    (True, True)
    """
    arm, obstacles = scene(arm, list(obstacles), margin)
    obstacles = list(obstacles)
    start, goals, gxy, step = _check_rrt_arguments(arm, start, goal, goal_xy, step, goal_bias,
                                                   goal_threshold, steer)
    checker = user_validity(validity, validity_resolution)
    tree = _Tree(arm, arm.wrap(start))

    def fail(msg, it, status):
        if raise_on_failure:
            raise NoPathFound(msg)
        return mark_sampled(tree_result(arm, None, tree.nodes.copy(), tree.parent.copy(), it,
                                        status), checker)

    if obstacles:  # thousands of checks follow: the compiled kernel (rapp.kernels.collision_numba)
        collision_backend.kernels()
    if collides(arm, start, obstacles):
        return fail("the start configuration collides", 0, NO_PATH)
    if goals is not None and gxy is None and (obstacles or arm.self_collision):
        # As the other planners do (rapp.sampling.check_start_and_goals): a colliding goal can
        # never be joined, so it is dropped, and when every goal collides the answer is at once.
        goals = goals[~collides(arm, goals, obstacles)]
        if len(goals) == 0:
            return fail("every goal configuration collides", 0, NO_PATH)
    if gxy is not None and np.linalg.norm(gxy) > arm.reach[1] + goal_threshold:
        return fail("goal_xy is beyond the arm's reach", 0, NO_PATH)
    if checker is not None:
        if not checker.points(start, arm)[0]:
            return fail("the start configuration is rejected by validity", 0, NO_PATH)
        if goals is not None and gxy is None:
            goals = goals[checker.points(goals, arm)]
            if len(goals) == 0:
                return fail("every goal configuration is rejected by validity", 0, NO_PATH)
    free = _edge_test(arm, obstacles, checker)

    def reached(q, p):
        if gxy is not None:
            return np.linalg.norm(p - gxy) <= goal_threshold
        return np.min(np.linalg.norm(arm.joint_delta(q, goals), axis=-1)) <= goal_threshold

    def arrive(i) -> int:
        """The node that ends the path when node ``i`` reached the goal region, or -1.

        With a joint goal the path must end exactly on a goal configuration: the last edge
        to it is certified too, and when it is not free the tree keeps growing.
        """
        if not reached(tree.nodes[i], tree.xy[i]):
            return -1
        if goals is not None and gxy is None:
            return _join_goal(arm, free, tree, i, goals, trace, grow.iteration)
        return i

    budget = Budget(max_iterations, time_budget)  # validates both
    rng = np.random.default_rng(seed)
    grow = Grower(arm, obstacles, tree, goals, gxy, step, steer, goal_bias, trace, free)
    hit = arrive(0)
    it = 0
    while hit < 0 and it < max_iterations:
        if budget.time_budget is not None and time.perf_counter() - budget.t0 > budget.time_budget:
            return fail(f"RRT stopped: time_budget {budget.time_budget:g} s spent after {it} "
                        "iterations, no goal reached", it, TIME_BUDGET_SPENT)
        progress.report("RRT", it, max_iterations)
        batch = grow.draw(rng)
        for k in range(_BATCH):
            if hit >= 0 or it >= max_iterations:
                break
            it += 1
            if grow.extend(batch, k):
                hit = arrive(tree.m - 1)
    if hit < 0:
        return fail(f"RRT stopped: max_iterations {max_iterations} reached, no goal reached", it,
                    ITERATION_CAP)
    path = _unwrapped_path(arm, tree, hit, start)
    return mark_sampled(tree_result(arm, path, tree.nodes.copy(), tree.parent.copy(), it), checker)


def _edge_test(arm, obstacles, checker):
    """Free or not for edges ``(a, b) -> (m,)``: certified (:func:`segment_collision_free`), and
    with a user's checker also sampled by it (:class:`rapp.sampling.EdgeCertifier`)."""
    if checker is None:
        return lambda a, b: segment_collision_free(arm, a, b, obstacles)
    return EdgeCertifier(arm, obstacles, checker)


def _check_rrt_arguments(arm, start, goal, goal_xy, step, goal_bias, goal_threshold, steer):
    """Validated ``start`` (n,), ``goals`` (g, n) or None, ``goal_xy`` (2,) or None, ``step``."""
    n = arm.n
    start = arm.check_q(start, "start").reshape(n)
    if steer not in ("step", "fraction"):
        raise ValueError(f"steer must be 'step' or 'fraction', got {steer!r}")
    step = float(step)
    if not (np.isfinite(step) and step > 0) or (steer == "fraction" and step > 1):
        raise InvalidSetting(f"step must be > 0 (and <= 1 for steer='fraction'), got {step}",
                             "step")
    if steer == "step" and not MIN_STEP <= step <= MAX_STEP:
        raise InvalidSetting(f"step must lie in [{MIN_STEP:g}, pi] rad, got {step:g}", "step")
    if not 0.0 <= goal_bias <= 1.0:
        raise ValueError(f"goal_bias must lie in [0, 1], got {goal_bias}")
    if not (np.isfinite(goal_threshold) and goal_threshold > 0):
        raise ValueError(f"goal_threshold must be finite and > 0, got {goal_threshold}")
    goals = None if goal is None else arm.check_q(goal, "goal").reshape(-1, n)
    if goals is None and goal_xy is None:
        raise ValueError("give a joint goal, a task-space goal_xy, or both")
    gxy = None
    if goal_xy is not None:
        gxy = np.asarray(goal_xy, dtype=float).reshape(2)
        if not np.isfinite(gxy).all():
            raise ValueError(f"goal_xy must be a finite point (x, y), got {gxy.tolist()}")
    return start, goals, gxy, step


class _Tree(Tree):
    """A :class:`rapp.sampling.Tree` that also keeps each node's end-effector position, for
    task-space goals and the report's Newton step toward ``goal_xy``."""

    def __init__(self, arm, root):
        self._xy = np.empty((256, 2))
        super().__init__(arm, [root])

    xy = property(lambda self: self._xy[: self.m])

    def add(self, q, parent_index, cost=0.0):
        if self.m == len(self._xy):
            self._xy = np.concatenate((self._xy, np.empty_like(self._xy)))
        self._xy[self.m] = self.arm.end_effector(q)
        return super().add(q, parent_index, cost)


class Grower:
    """One iteration of RRT at a time, on targets drawn in fixed batches.

    Random numbers come in batches of ``_BATCH``, so a run is a prefix of any
    longer run. Speculation: the edges each target of a batch would add to the
    tree as it stands are certified in one vectorized call; a target whose
    nearest node turns out to be one added later in the batch (or a Newton
    target, known only then) gets its own check. The tree is the one grown
    edge by edge.
    """

    def __init__(self, arm, obstacles, tree, goals, gxy, step, steer, goal_bias, trace=None,
                 free=None):
        self.arm, self.obstacles, self.tree = arm, obstacles, tree
        #: The edge test ``(a, b) -> (m,) bool``; by default certified against ``obstacles``.
        self.free = _edge_test(arm, obstacles, None) if free is None else free
        self.goals, self.gxy, self.step, self.steer, self.goal_bias = goals, gxy, step, steer, goal_bias
        self.newton_goal = goals is None
        self.trace = trace
        self.iteration = 0  # extend() calls so far: rrt's iteration count

    def steer_from(self, base, target):
        """Nearest node(s) among ``base`` to each target and the steered new configuration."""
        diff = self.arm.joint_delta(base[None, :, :], target[:, None, :])  # (t, m, n)
        d2 = np.einsum("tmi,tmi->tm", diff, diff)
        i = np.argmin(d2, axis=1)
        rows = np.arange(target.shape[0])
        dq, dist = diff[rows, i], np.sqrt(d2[rows, i])
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = (np.minimum(1.0, self.step / dist) if self.steer == "step"
                     else np.full_like(dist, self.step))
        # Unwrapped: the edge certified is the short way round.
        return i, base[i] + scale[:, None] * dq, dist

    def draw(self, rng):
        """A batch of targets, which of them aim at the goal, and their speculative edges."""
        arm = self.arm
        u = rng.random(_BATCH)
        targets = rng.uniform(arm.lower, arm.upper, (_BATCH, arm.n))
        to_goal = u < self.goal_bias
        if self.goals is not None:
            pick = rng.integers(self.goals.shape[0], size=_BATCH)
            targets[to_goal] = self.goals[pick[to_goal]]
        m0 = self.tree.m
        spec = ~to_goal if self.newton_goal else np.ones(_BATCH, dtype=bool)
        spec_i = np.full(_BATCH, -1)
        spec_free = np.zeros(_BATCH, dtype=bool)
        if spec.any():
            nodes = self.tree.nodes
            i_s, q_s, d_s = self.steer_from(nodes, targets[spec])
            ok = d_s > 0
            spec_free_s = np.zeros(i_s.shape, dtype=bool)
            if ok.any():
                spec_free_s[ok] = self.free(nodes[i_s[ok]], q_s[ok])
            spec_i[spec], spec_free[spec] = i_s, spec_free_s
        return targets, to_goal, spec_i, spec_free, m0

    def extend(self, batch, k) -> bool:
        """Try target ``k`` of ``batch``; True when a node was added."""
        targets, to_goal, spec_i, spec_free, m0 = batch
        tree, arm = self.tree, self.arm
        self.iteration += 1
        target = targets[k]
        if self.newton_goal and to_goal[k]:
            # The report's Algorithm 1: a Gauss-Newton step toward goal_xy from the node
            # whose end effector is nearest to it.
            xy = tree.xy
            j = np.argmin(np.einsum("ij,ij->i", xy - self.gxy, xy - self.gxy))
            newton = np.linalg.pinv(jacobian(arm, tree.nodes[j])) @ (self.gxy - xy[j])
            target = np.clip(tree.nodes[j] + newton, arm.lower, arm.upper)
        i, q_new, dist = self.steer_from(tree.nodes, target[None])
        i, q_new, dist = int(i[0]), q_new[0], dist[0]
        if dist == 0.0:
            self.record(target, to_goal[k], i, q_new, "no move")
            return False
        if i == spec_i[k] and i < m0:
            edge_free = spec_free[k]
        else:
            edge_free = bool(np.asarray(self.free(tree.nodes[i][None], q_new[None])).reshape(-1)[0])
        if not edge_free:
            self.record(target, to_goal[k], i, q_new, "blocked")
            return False
        tree.add(q_new, i)
        self.record(target, to_goal[k], i, q_new, "added")
        return True

    def record(self, target, goal_biased, nearest, new, status):
        if self.trace is not None:
            self.trace.append(RRTStep(self.iteration, np.array(target, dtype=float),
                                      bool(goal_biased), nearest, np.array(new, dtype=float), status,
                                      self.tree.m - 1 if status == "added" else -1))


def _join_goal(arm, edge_free, tree, hit, goals, trace=None, iteration=0) -> int:
    """Join node ``hit`` to its nearest goal by an edge ``edge_free`` passes (:func:`_edge_test`):
    the goal's node index, or -1."""
    gd = arm.joint_delta(tree.nodes[hit], goals)
    g = int(np.argmin(np.einsum("ij,ij->i", gd, gd)))
    if not np.any(gd[g] != 0):
        return hit
    end = tree.nodes[hit] + gd[g]
    free = bool(np.asarray(edge_free(tree.nodes[hit][None], end[None])).reshape(-1)[0])
    if free:
        tree.add(goals[g], hit)
    if trace is not None:
        trace.append(RRTStep(iteration, np.array(goals[g], dtype=float), True, int(hit), end.copy(),
                             "added" if free else "blocked", tree.m - 1 if free else -1, join=True))
    return tree.m - 1 if free else -1


def _unwrapped_path(arm, tree, hit, start) -> np.ndarray:
    """Root-to-``hit`` chain, unwrapped from the exact start: each step is the certified edge."""
    chain = [hit]
    while tree.parent[chain[-1]] >= 0:
        chain.append(int(tree.parent[chain[-1]]))
    walk = tree.nodes[chain[::-1]]
    steps = arm.joint_delta(walk[:-1], walk[1:])
    return np.concatenate((start[None], start + np.cumsum(steps, axis=0)))


_SETTINGS = ("step", "goal_bias", "goal_threshold", "max_iterations", "seed", "steer", "time_budget")


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
    if goal_qs is not None and goal_xy is None and kw.get("steer", "step") == "step":
        check_reachable(arm, start, goal_qs, **kw)
    return rrt(arm, start, goal_qs, obstacles, goal_xy=goal_xy, **kw).path


def check_reachable(arm, start, goals, *, step: float | None = None, max_iterations=None,
                    goal_threshold: float | None = None, **_other_settings) -> None:
    """Refuse a ``step`` with which no run of ``max_iterations`` can reach a goal.

    Every iteration moves the tree at most one step nearer a goal, so a goal ``d`` beyond the
    threshold needs ``d / step`` iterations at least. (:func:`rrt` itself runs such a budget,
    for a partial tree is worth drawing; a plan asking for one is a mistake in its settings.)

    Examples
    --------
    >>> from rapp import Arm
    >>> check_reachable(Arm([1.0, 1.0]), [0.0, 0.0], [2.0, 0.0], step=0.1, max_iterations=100)
    >>> check_reachable(Arm([1.0, 1.0]), [0.0, 0.0], [2.0, 0.0], step=1e-4, max_iterations=100)
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidSetting: step 0.0001 rad is too small: ...
    """
    # A setting not given is rrt's own default (one source of defaults: rrt's signature).
    own = inspect.signature(rrt).parameters
    step = float(own["step"].default if step is None else step)
    goal_threshold = float(own["goal_threshold"].default if goal_threshold is None else goal_threshold)
    max_iterations = own["max_iterations"].default if max_iterations is None else max_iterations
    start = arm.check_q(start, "start").reshape(arm.n)
    d = arm.joint_delta(start, arm.check_q(goals, "goal").reshape(-1, arm.n))
    gap = float(np.sqrt((d * d).sum(axis=-1)).min()) - goal_threshold
    iterations = Budget(max_iterations, None).max_iterations
    if step > 0 and gap > step * iterations:
        raise InvalidSetting(
            f"step {step:g} rad is too small: the goal is {gap:.3g} rad beyond the goal "
            f"threshold, at least {gap / step:.3g} steps, and max_iterations is {iterations}; "
            f"use a step of at least {gap / iterations:.3g} rad (or more iterations)", "step")


# Its kernels are compiled before a time budget of it starts (rapp.sampling.prepare_kernels).
warms(rrt, max_iterations=300)
