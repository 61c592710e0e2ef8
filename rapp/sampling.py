"""What the sampling planners share: trees in joint space, uniform samples, budgets, checks.

A free joint is a circle, so every distance and every step is taken the short way round
(:meth:`rapp.Arm.joint_delta`); nodes are stored wrapped (:meth:`rapp.Arm.wrap`) and paths
are returned unwrapped, each waypoint the previous one plus the certified edge, so that the
straight segment between consecutive waypoints is exactly the motion that was certified
collision-free (:func:`rapp.collision.segment_collision_free`).

References
----------
LaValle (2006), *Planning Algorithms*, ch. 5: sampling-based motion planning.
"""

from __future__ import annotations

import time

import numpy as np

from rapp.arm import Arm
from rapp.checks import finite_number, positive_integer
from rapp.kernels import collision as collision_backend
from rapp.collision import collides, reach_matrix, segment_collision_free
from rapp.kernels.collision import pack
from rapp.errors import NoPathFound
from rapp.obstacles import Circle, Polygon
from rapp.paths import ITERATION_CAP, TIME_BUDGET_SPENT

__all__ = ["ClearanceTree", "squared_norms", "motion_bounds_of", "endpoint_certified", "EdgeCertifier", "Tree", "Budget", "prepare_kernels", "warms", "check_start_and_goals", "uniform_samples", "unwrapped_chain"]


def squared_norms(d) -> np.ndarray:
    """Sum of squares along the last axis, joint by joint in order: ``(..., n) -> (...)``.

    Written out rather than ``d @ d`` or ``einsum``, whose rounding depends on the BLAS and
    the processor (fused multiply-adds, vector lanes): this order is the one the compiled
    loops of :mod:`rapp.kernels.sampling_numba` use, so both find the same nearest nodes and steps
    to the last bit.

    Examples
    --------
    >>> squared_norms(np.array([[3.0, 4.0], [1.0, 1.0]])).tolist()
    [25.0, 2.0]
    """
    d = np.asarray(d, float)
    s = d[..., 0] * d[..., 0]
    for j in range(1, d.shape[-1]):
        s = s + d[..., j] * d[..., j]
    return s


def motion_bounds_of(dq, reach) -> np.ndarray:
    """``np.abs(dq) @ reach`` (:func:`rapp.collision.motion_bounds`), summed joint by joint in
    order: the compiled loops' order, whatever the BLAS rounds (see :func:`squared_norms`).

    Examples
    --------
    >>> from rapp import Arm
    >>> from rapp.collision import reach_matrix
    >>> motion_bounds_of(np.array([[0.1, 0.0]]), reach_matrix(Arm([1.0, 1.0]))).tolist()
    [[0.1, 0.2]]
    """
    a = np.abs(np.asarray(dq, float))
    b = a[..., 0, None] * reach[0]
    for j in range(1, a.shape[-1]):
        b = b + a[..., j, None] * reach[j]
    return b


def endpoint_certified(c0, c1, bounds, touch):
    """Edges certified free by their end clearances alone: ``c0 + c1 > B + 2 touch`` on every link.

    Along a straight joint-space edge every point of link ``j`` moves at most ``B_j t`` from
    where it is at the start (parameter ``t``) and ``B_j (1 - t)`` from where it is at the end
    (:func:`rapp.collision.motion_bounds`), and a clearance changes no faster than the points
    move. So link ``j`` is free at ``t`` when ``c0_j > B_j t`` or ``c1_j > B_j (1 - t)``, and
    both intervals of ``t`` together cover ``[0, 1]`` exactly when ``c0_j + c1_j > B_j``; with
    ``2 touch`` more, every point keeps a clearance over the touching distance ``touch``, as the
    bisection of :func:`rapp.collision.segment_collision_free` requires of its pieces. The
    same lemma, applied at the ends, where the clearances are already known: most short edges
    need nothing more.

    Examples
    --------
    >>> endpoint_certified(np.array([[0.3, 0.2]]), np.array([[0.3, 0.2]]),
    ...                    np.array([[0.5, 0.5]]), 1e-14).tolist()
    [False]
    """
    return ((c0 + c1 > bounds + 2 * touch) & (c0 > touch) & (c1 > touch)).all(axis=-1)


class EdgeCertifier:
    """:func:`rapp.collision.segment_collision_free` for a planner's own edges, the same answers.

    A planner certifies a few edges at a time, thousands of times, always with the same arm
    and obstacles, and its configurations are its own finite arithmetic: the obstacles'
    arrays, the reach matrix and the touching distance are made once here, the angles are
    not checked again, and the compiled bisection first runs with a small interval allowance
    (an edge needing more goes through ``segment_collision_free``, which also raises its
    message). Without the compiled kernel it is ``segment_collision_free``.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((0.0, 1.5), 0.3)]
    >>> EdgeCertifier(arm, obs)(np.zeros((2, 2)), np.array([[0.5, 0.0], [3.0, 0.0]])).tolist()
    [True, False]
    """

    #: Pending intervals of the first, compiled try (the answer does not depend on it).
    FIRST_CAP = 64

    def __init__(self, arm, obstacles, validity=None):
        self.arm, self.obstacles = arm, list(obstacles)
        #: A user's checker (:class:`rapp.validity.UserValidity`) or None: with one, an edge is
        #: free when rapp certifies it and the checker allows every sample of it.
        self.validity = validity
        # Self-collision (arm.self_collision) is certified only by segment_collision_free.
        self.kernel = (collision_backend.loaded() if self.obstacles and not arm.self_collision
                       else None)
        #: Clearance within which a configuration counts as touching (no edge leaves it).
        self.touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
        if self.kernel is not None:
            self.packed = pack(self.obstacles)
            self.reach = reach_matrix(arm)

    def __call__(self, q0, q1, c0=None, c1=None) -> np.ndarray:
        """Free or not, for each straight edge ``q0 -> q1`` (``(m, n)`` each): bool ``(m,)``.

        With the link clearances ``c0``, ``c1`` of both ends, an edge whose ends certify it
        (:func:`endpoint_certified`) is free and one with an end within touching distance is
        not, without a bisection: the answers the bisection gives. With a user's checker
        (``validity``), an edge rapp certifies is then sampled at its resolution
        (:meth:`rapp.validity.UserValidity.edges`, one call for all of them).
        """
        free = self.certified(q0, q1, c0, c1)
        if self.validity is not None and free.any():
            free = np.array(free, dtype=bool)
            q0, q1 = np.atleast_2d(q0), np.atleast_2d(q1)
            free[free] = self.validity.edges(q0[free], q1[free], self.arm)
        return free

    def certified(self, q0, q1, c0=None, c1=None) -> np.ndarray:
        """:meth:`__call__` for rapp's obstacles alone (the user's checker left out)."""
        if self.kernel is None:
            if c0 is None or self.arm.self_collision:
                return segment_collision_free(self.arm, q0, q1, self.obstacles)
            # An end within touching distance: not free, without a bisection that could not end.
            q0, q1 = np.atleast_2d(q0), np.atleast_2d(q1)
            hit = ((np.atleast_2d(c0) <= self.touch) | (np.atleast_2d(c1) <= self.touch)).any(axis=-1)
            free = np.zeros(hit.shape[0], dtype=bool)
            rest = np.flatnonzero(~hit)
            if rest.size:
                free[rest] = segment_collision_free(self.arm, q0[rest], q1[rest], self.obstacles)
            return free
        q0 = np.ascontiguousarray(q0, dtype=float)
        dq = np.ascontiguousarray(q1 - q0)  # as segment_collision_free forms it
        bounds = motion_bounds_of(dq, self.reach)
        if c0 is not None:
            free = endpoint_certified(c0, c1, bounds, self.touch)
            hit = ((c0 <= self.touch) | (c1 <= self.touch)).any(axis=-1)
            rest = np.flatnonzero(~free & ~hit)
            if rest.size:
                free[rest] = self.certified(q0[rest], q1[rest])
            return free
        code = self.kernel.certify(self.arm.lengths, q0, dq, bounds, *self.packed, 1e-9,
                                   self.FIRST_CAP, self.touch)
        if (code < 0).any():
            return segment_collision_free(self.arm, q0, q1, self.obstacles)
        return code > 0


class Tree:
    """A tree in joint space as growable arrays: wrapped nodes, parent map, cost from the root.

    Examples
    --------
    >>> from rapp import Arm
    >>> t = Tree(Arm([1.0, 1.0]), [[0.0, 0.0]])
    >>> t.add([3.0, 0.0], 0, cost=3.0)
    1
    >>> t.nearest([-3.1, 0.0])      # 3.0 is 0.18 rad from -3.1 the short way round
    1
    >>> t.parent.tolist(), t.cost.tolist()
    ([-1, 0], [0.0, 3.0])
    """

    def __init__(self, arm, roots):
        self.arm = arm
        roots = np.atleast_2d(np.asarray(roots, float))
        cap = max(256, 2 * len(roots))
        self._nodes = np.empty((cap, arm.n))
        self._parent = np.empty(cap, dtype=int)
        self._cost = np.empty(cap)
        self.m = 0
        for r in roots:
            self.add(r, -1, 0.0)

    nodes = property(lambda self: self._nodes[: self.m], doc="Nodes ``(m, n)``, wrapped.")
    parent = property(lambda self: self._parent[: self.m], doc="Parent index, -1 for a root.")
    cost = property(lambda self: self._cost[: self.m], doc="Path length from the root (rad).")

    def add(self, q, parent_index: int, cost: float = 0.0) -> int:
        """Append a node; returns its index."""
        if self.m == len(self._nodes):
            self._nodes = np.concatenate((self._nodes, np.empty_like(self._nodes)))
            self._parent = np.concatenate((self._parent, np.empty_like(self._parent)))
            self._cost = np.concatenate((self._cost, np.empty_like(self._cost)))
        self._nodes[self.m] = self.arm.wrap(q)
        self._parent[self.m] = parent_index
        self._cost[self.m] = cost
        self.m += 1
        return self.m - 1

    def deltas(self, q) -> np.ndarray:
        """``q - node`` for every node, the short way round: ``(m, n)``."""
        return self.arm.joint_delta(self.nodes, q)

    def nearest(self, q) -> int:
        """Index of the node nearest ``q`` (wrap-aware Euclidean distance)."""
        return int(np.argmin(squared_norms(self.deltas(q))))

    def set_parent(self, i: int, parent_index: int, cost: float) -> None:
        """Rewire node ``i`` under ``parent_index`` at path cost ``cost``."""
        self._parent[i] = parent_index
        self._cost[i] = cost

    def shift_cost(self, indices, delta: float) -> None:
        """Add ``delta`` to the cost of the (distinct) nodes ``indices``: a rewired branch."""
        self._cost[np.asarray(indices, dtype=int)] += delta


#: How many of the registered planners :func:`prepare_kernels` has run (or is running).
_PREPARED = [0]


def prepare_kernels() -> float:
    """Compile (or load from numba's disk cache) every kernel the sampling planners run, once
    per process, before a planning clock starts; returns the seconds this call spent (0 once
    done).

    numba compiles a kernel on its first call. Called inside a planner, that first call would
    charge seconds of compilation to the planner's ``time_budget`` (a run right after
    installing could stop after 0 iterations). :class:`Budget` calls this before it reads the
    clock, so a time budget measures planning only; ``rapp.plan`` reports this time as its
    ``compile`` stage. It plans a tiny problem with each sampling planner, which compiles the
    kernels with the argument types the planners pass. Without numba it costs nothing.

    Examples
    --------
    >>> first = prepare_kernels()
    >>> prepare_kernels()
    0.0
    """
    if _PREPARED[0] >= len(_WARMERS):
        return 0.0
    t0 = time.perf_counter()
    _plan_tiny_problems()
    return time.perf_counter() - t0


#: The planners whose tiny problem :func:`prepare_kernels` plans: each sampling planner's module
#: registers itself on import (:func:`warms`), so this module imports none of them.
_WARMERS: list = []


def warms(planner, **settings):
    """Register ``planner`` (with ``settings``) for :func:`prepare_kernels`; returns ``planner``.

    A sampling planner's module calls this once on import, so a time budget of that planner,
    however it is called, never pays for compiling its kernels.

    Examples
    --------
    >>> def planner(arm, start, goal, obstacles, **kw):
    ...     return None
    >>> warms(planner, max_iterations=5) is planner
    True
    >>> _ = _WARMERS.pop()
    """
    _WARMERS.append((planner, settings))
    return planner


def _plan_tiny_problems() -> None:
    """Run each registered sampling planner on a tiny problem (compiled kernels only)."""
    from rapp.kernels import sampling as sampling_backend
    if sampling_backend.kernels() is None:
        _PREPARED[0] = len(_WARMERS)   # nothing to compile
    else:
        arm = Arm([1.0, 0.6])
        obs = [Circle((0.0, 1.3), 0.2), Polygon.rectangle((-1.4, -1.4), 0.3, 0.3)]
        start, goal = np.array([0.0, 0.0]), np.array([[2.5, 0.3]])
        while _PREPARED[0] < len(_WARMERS):
            planner, kw = _WARMERS[_PREPARED[0]]
            _PREPARED[0] += 1   # first: the tiny run's own Budget must not start another
            planner(arm, start, goal, obs, seed=0, raise_on_failure=False, **kw)


class Budget:
    """Iterations and an optional wall-clock budget; ``spent()`` says when either ran out.

    A time budget makes a run depend on the machine; without one, the same seed gives the same
    result everywhere. A time budget measures planning only: the compiled kernels are prepared
    (:func:`prepare_kernels`) before its clock starts.

    Examples
    --------
    >>> b = Budget(3, None)
    >>> [b.spent() for _ in range(4)]
    [False, False, False, True]
    """

    def __init__(self, max_iterations, time_budget):
        self.max_iterations = positive_integer(max_iterations, "max_iterations")
        self.time_budget = None if time_budget is None else finite_number(
            time_budget, "time_budget", above=0.0)
        if self.time_budget is not None:
            prepare_kernels()
        self.t0 = time.perf_counter()
        self.iterations = 0

    def spent(self) -> bool:
        """Count one iteration; True when none is left (the iteration must not run)."""
        if self.iterations >= self.max_iterations:
            return True
        if self.time_budget is not None and time.perf_counter() - self.t0 > self.time_budget:
            return True
        self.iterations += 1
        return False

    def status(self) -> str:
        """Why it stopped, once it has (:data:`rapp.paths.ITERATION_CAP` when every iteration
        ran, else :data:`rapp.paths.TIME_BUDGET_SPENT`).

        Examples
        --------
        >>> b = Budget(2, 5.0)
        >>> b.iterations = 2
        >>> b.status()
        'iteration cap'
        """
        if self.iterations >= self.max_iterations or self.time_budget is None:
            return ITERATION_CAP
        return TIME_BUDGET_SPENT

    def stopped(self, planner: str, outcome: str, *, unit: str = "iterations") -> str:
        """The failure message of a run this budget stopped: it names the limit spent.

        Examples
        --------
        >>> b = Budget(20000, 5.0)
        >>> b.iterations = 64
        >>> b.stopped("RRT-Connect", "no goal joined")
        'RRT-Connect stopped: time_budget 5 s spent after 64 iterations, no goal joined'
        >>> b.iterations = 20000
        >>> b.stopped("RRT-Connect", "no goal joined")
        'RRT-Connect stopped: max_iterations 20000 reached, no goal joined'
        """
        if self.status() == ITERATION_CAP:
            return f"{planner} stopped: max_iterations {self.max_iterations} reached, {outcome}"
        return (f"{planner} stopped: time_budget {self.time_budget:g} s spent after "
                f"{self.iterations} {unit}, {outcome}")

    def grant(self, k: int) -> int:
        """How many of the next ``k`` iterations may run (0 when none is left); the caller
        adds those it ran to ``iterations``. The time is looked at once, for the batch.

        Examples
        --------
        >>> b = Budget(100, None)
        >>> b.grant(64), b.iterations
        (64, 0)
        >>> b.iterations = 90
        >>> b.grant(64)
        10
        """
        left = self.max_iterations - self.iterations
        if left <= 0 or (self.time_budget is not None
                         and time.perf_counter() - self.t0 > self.time_budget):
            return 0
        return min(int(k), left)


def check_start_and_goals(arm, start, goal, obstacles, validity=None):
    """Validated start ``(n,)`` and goals ``(g, n)``; NoPathFound if the start or every goal collides.

    With a user's checker (``validity``, a :class:`rapp.validity.UserValidity`), a start it
    rejects is refused the same way, and goals it rejects are dropped.

    Examples
    --------
    >>> from rapp import Arm
    >>> s, g = check_start_and_goals(Arm([1.0, 1.0]), [0, 0], [1, 0], [])
    >>> s.tolist(), g.tolist()
    ([0.0, 0.0], [[1.0, 0.0]])
    """
    start = arm.check_q(start, "start").reshape(arm.n)
    goals = arm.check_q(np.atleast_2d(goal), "goal").reshape(-1, arm.n)
    obstacles = list(obstacles)
    if obstacles:
        # A sampling planner checks thousands of single configurations and edges: load the
        # compiled collision kernel (rapp.kernels.collision_numba) for them, whatever their size.
        collision_backend.kernels()
    check = bool(obstacles) or arm.self_collision
    if check and collides(arm, start, obstacles):
        raise NoPathFound("the start configuration collides")
    if check:
        # A few goals one by one: the one-configuration kernel call is the shortest way.
        hit = (np.fromiter((collides(arm, g, obstacles) for g in goals), bool, len(goals))
               if len(goals) <= 8 else collides(arm, goals, obstacles))
        goals = goals[~hit]
        if len(goals) == 0:
            raise NoPathFound("every goal configuration collides")
    if validity is not None:
        if not validity.points(start, arm)[0]:
            raise NoPathFound("the start configuration is rejected by validity")
        goals = goals[validity.points(goals, arm)]
        if len(goals) == 0:
            raise NoPathFound("every goal configuration is rejected by validity")
    return start, goals


def uniform_samples(arm, rng, k: int) -> np.ndarray:
    """``k`` configurations drawn uniformly within the joint bounds, ``(k, n)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> q = uniform_samples(Arm([1.0, 1.0], [None, (0.0, 1.0)]), np.random.default_rng(0), 100)
    >>> q.shape, bool((q[:, 1] >= 0).all() and (q[:, 1] <= 1).all())
    ((100, 2), True)
    """
    return rng.uniform(arm.lower, arm.upper, (k, arm.n))


def unwrapped_chain(arm, walk, start) -> np.ndarray:
    """The waypoints ``walk`` (wrapped) as a path from the exact ``start``: each step the short way.

    Examples
    --------
    >>> from rapp import Arm
    >>> unwrapped_chain(Arm([1.0]), [[3.0], [-3.0]], [3.0]).round(4).tolist()
    [[3.0], [3.2832]]
    """
    walk = np.asarray(walk, float)
    start = np.asarray(start, float)
    steps = arm.joint_delta(walk[:-1], walk[1:])
    return np.concatenate((start[None], start + np.cumsum(steps, axis=0)))


class ClearanceTree(Tree):
    """A :class:`Tree` that also keeps every node's link clearances ``(m, n)``.

    Certifying an edge needs the clearances at its two ends, and the start of every new edge
    is a node already in the tree: stored once, they are never computed twice.
    ``clearance`` maps configurations ``(k, n)`` to their link clearances ``(k, n)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> t = ClearanceTree(Arm([1.0, 1.0]), [[0.0, 0.0]], lambda q: np.ones(q.shape))
    >>> t.add([0.1, 0.0], 0, 0.1, [0.5, 0.5]), t.clear.tolist()
    (1, [[1.0, 1.0], [0.5, 0.5]])
    """

    def __init__(self, arm, roots, clearance):
        self._clear = np.empty((max(256, 2 * len(np.atleast_2d(roots))), arm.n))
        super().__init__(arm, roots)
        self.clear[:] = clearance(self.nodes)

    clear = property(lambda self: self._clear[: self.m], doc="Link clearances of every node.")

    def add(self, q, parent_index: int, cost: float = 0.0, clearance=None) -> int:
        if self.m == len(self._clear):
            self._clear = np.concatenate((self._clear, np.empty_like(self._clear)))
        if clearance is not None:
            self._clear[self.m] = clearance
        return super().add(q, parent_index, cost)
