"""RRT-Connect: two trees, one from the start and one from the goals, grown toward each other.

Each iteration draws a random configuration; one tree *extends* one step of at most ``step``
toward it, and the other tree then *connects*: it steps toward the new node again and again
until it reaches it or is blocked. The trees swap roles every iteration. Every edge is certified
collision-free (:func:`rapp.collision.segment_collision_free`), so the returned path is; a
connect attempt certifies its whole chain of steps in one vectorized call and keeps the longest
free prefix, the same tree as stepping one edge at a time. An edge whose end clearances prove it
free (:func:`rapp.sampling.endpoint_certified`) needs no bisection.

With numba the whole iteration runs compiled (:mod:`rapp.kernels.sampling_numba`) on samples drawn by
the same generator, and grows the same trees bit for bit; the numpy loop is the fallback.

References
----------
Kuffner and LaValle (2000), RRT-Connect: an efficient approach to single-query path planning.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm
    from rapp.obstacles import Circle, Polygon

from rapp import progress
from rapp.checks import finite_number
from rapp.collision import reach_matrix, link_clearances, scene
from rapp.kernels import sampling as sampling_backend
from rapp.kernels import collision as collision_backend
from rapp.collision import MAX_PENDING_INTERVALS
from rapp.kernels.collision import pack
from rapp.obstacles import Circle
from rapp.errors import InvalidSetting, NoPathFound
from rapp.paths import NODE_CAP, PlannerResult, tree_result
from rapp.rrt import MAX_STEP, MIN_STEP
from rapp.sampling import warms
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, mark_sampled, user_validity
from rapp.sampling import (Budget, ClearanceTree, EdgeCertifier, Tree, check_start_and_goals,
                           endpoint_certified, motion_bounds_of, squared_norms, uniform_samples,
                           unwrapped_chain)

__all__ = ["rrt_connect", "MAX_NODES", "MIN_STEP", "MAX_STEP", "smallest_step"]

#: Nodes of both trees together at most. The nearest node is found by a linear scan, so an
#: iteration costs time in proportion to the nodes (about 0.1 ms per 1,000 nodes for two
#: joints); 20,000 keep a whole default run of 20,000 iterations within tens of seconds
#: whatever the step, and the trees' memory under 6 MB for 16 joints. Every node advances
#: at most ``step``, so this bounds the step from below: see :func:`smallest_step`.
MAX_NODES = 20_000
#: Bytes the clearances of one connect chain may take at once; a longer chain stops there (and
#: goes on at the next iteration), so a tiny step cannot allocate ``distance / step`` points.
CHAIN_BYTES = 64_000_000


def smallest_step(distance: float) -> float:
    """The smallest ``step`` with which the trees can join two configurations ``distance`` apart.

    Each node lies at most ``step`` from its parent, so joining needs at least
    ``distance / step`` nodes, and the trees hold :data:`MAX_NODES`.

    Examples
    --------
    >>> float(smallest_step(2.0))
    0.0001
    """
    return max(MIN_STEP, float(distance) / MAX_NODES)


class _Clearance:
    """Lower bounds of the link clearances of a batch of configurations ``(k, n) -> (k, n)``.

    Exact for discs; a polygon is replaced by its bounding disc (centred on its vertex mean),
    which can only lower the clearance, so every certificate built on these values is still a
    proof. Rows where some link comes within ``touch`` of a disc get the exact clearance of
    :func:`rapp.collision.link_clearances`, so a point counts as colliding exactly when it does.
    All discs go through one broadcast: what a planner calling this for one configuration at a
    time pays for is the number of numpy calls, not the arithmetic.
    """

    def __init__(self, arm, obstacles, touch):
        self.arm, self.obstacles, self.touch = arm, obstacles, touch
        # Discs first, then the polygons' bounding discs. A disc that applies to some links only
        # (rapp.collision.scene) is bounded like a polygon: the exact clearance decides near it.
        discs = [ob for ob in obstacles if isinstance(ob, Circle) and ob.links is None]
        centers = [ob.center for ob in discs]
        radii = [ob.radius for ob in discs]
        self.discs = len(radii)
        for ob in obstacles:
            if isinstance(ob, Circle) and ob.links is not None:
                centers.append(ob.center)
                radii.append(ob.radius)
            elif not isinstance(ob, Circle):
                v = np.asarray(ob.vertices, float)
                c = v.mean(axis=0)
                centers.append(c)
                radii.append(float(np.sqrt(((v - c) ** 2).sum(axis=1)).max()))
        self.centers = np.asarray(centers, float).reshape(-1, 2)
        self.radii = np.asarray(radii, float)
        self.polygons = len(radii) > self.discs
        self.compiled = collision_backend.kernels() is not None

    def __call__(self, q) -> np.ndarray:
        q = np.atleast_2d(q)
        if not len(self.radii):
            return np.full(q.shape, np.inf)
        if self.compiled:  # exact clearances cost less than these bounds in numpy
            return link_clearances(self.arm, q, self.obstacles)
        # The clipped projection of every disc centre on every link, written out: the same
        # arithmetic as rapp.collision.segment_point_distance in a third of the numpy calls.
        # Links have positive length, so |ab|^2 > 0.
        pts = self.arm.joint_positions_unchecked(q)  # q comes from the planner's own arithmetic: finite
        a = pts[:, :-1, None, :]
        ab = pts[:, 1:, None, :] - a
        ap = self.centers - a
        den = np.einsum("...i,...i->...", ab, ab)
        t = np.minimum(np.maximum(np.einsum("...i,...i->...", ap, ab), 0.0), den) / den
        v = ap - t[..., None] * ab
        d = np.sqrt(np.einsum("...i,...i->...", v, v)) - self.radii
        lower = d.min(axis=-1)
        if self.polygons:
            # A row that touches a real disc collides whatever the polygons do; a row that only
            # comes near a polygon's bounding disc needs the polygon's exact clearance.
            touches_disc = (d[..., : self.discs] <= self.touch).any(axis=(-1, -2))
            close = (lower <= self.touch).any(axis=-1) & ~touches_disc
            if close.any():
                lower[close] = link_clearances(self.arm, q[close], self.obstacles)
        return lower


def _extend(tree: ClearanceTree, target, step: float, certify, chain: bool, reach, clearance,
            room: int = MAX_NODES):
    """Step from the node nearest ``target`` toward it: one step, or (``chain``) until blocked
    or ``room`` nodes were added.

    Returns ``(index of the last node added or -1, reached)``; ``reached`` means that node is
    ``target`` itself (the short way round).
    """
    arm = tree.arm
    i = tree.nearest(target)
    base = tree.nodes[i]
    d = arm.joint_delta(base, target)
    dist = float(np.sqrt(squared_norms(d)))
    if dist == 0.0:
        return i, True
    k = min(int(np.ceil(dist / step)), room) if chain else 1
    if k <= 0:  # the trees are full
        return -1, False
    frac = np.minimum(np.arange(1, k + 1) * step / dist, 1.0)
    points = base + frac[:, None] * d  # unwrapped from base: the certified motion
    prev = np.vstack((base, points[:-1]))
    # One vectorized clearance call for the whole chain: a point in collision ends it, and the
    # clearances at both ends of each edge usually certify it without any bisection.
    touch = clearance.touch
    clear = clearance(points)
    hit = (clear <= touch).any(axis=-1)
    reach_k = int(np.argmax(hit)) if hit.any() else k
    free = np.zeros(reach_k, dtype=bool)
    if reach_k:
        c0 = np.vstack((tree.clear[i], clear[: reach_k - 1]))
        if getattr(certify, "validity", None) is not None:
            # A user's checker samples every edge (rapp.validity): all of them through certify,
            # in one call, which still proves most of them free of obstacles by their ends.
            ends = () if arm.self_collision else (c0, clear[:reach_k])
            free = certify(prev[:reach_k], points[:reach_k], *ends)
        else:
            bounds = motion_bounds_of(points[:reach_k] - prev[:reach_k], reach)
            free = (np.zeros(reach_k, bool) if arm.self_collision  # ends say nothing of link pairs
                    else endpoint_certified(c0, clear[:reach_k], bounds, touch))
            todo = np.flatnonzero(~free)
            if todo.size:  # the rest are bisected, as every edge was before
                ends = () if arm.self_collision else (c0[todo], clear[todo])
                free[todo] = certify(prev[todo], points[todo], *ends)
    ok = int(np.argmin(free)) if not free.all() else reach_k  # the free prefix
    last = -1
    parent = i
    if ok:
        lengths = np.sqrt(np.einsum("ij,ij->i", points[:ok] - prev[:ok], points[:ok] - prev[:ok]))
    for j in range(ok):
        parent = tree.add(points[j], parent, tree.cost[parent] + float(lengths[j]), clear[j])
        last = parent
    return last, ok == k and frac[-1] == 1.0


def rrt_connect(arm: Arm, start: ArrayLike, goal: ArrayLike, obstacles: Iterable[Circle | Polygon] = (), *,
                step: float = 0.1, seed: int | np.random.SeedSequence = 0,
                max_iterations: int = 20000, time_budget: float | None = None,
                raise_on_failure: bool = True, margin: float = 0.0,
                validity: ValidityFunction | None = None,
                validity_resolution: float = DEFAULT_RESOLUTION) -> PlannerResult:
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

    Returns
    -------
    PlannerResult
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
    arm, obstacles = scene(arm, list(obstacles), margin)
    obstacles = list(obstacles)
    step = finite_number(step, "step", above=0.0)
    if not MIN_STEP <= step <= MAX_STEP:
        raise InvalidSetting(f"step must lie in [{MIN_STEP:g}, pi] rad, got {step:g}", "step")
    budget = Budget(max_iterations, time_budget)
    checker = user_validity(validity, validity_resolution)
    start, goals = check_start_and_goals(arm, start, goal, obstacles, checker)
    gaps = arm.joint_delta(start, goals)
    gap = float(np.sqrt((gaps * gaps).sum(axis=-1)).min())
    if step < smallest_step(gap):
        raise InvalidSetting(
            f"step {step:g} rad is too small: the trees would need at least {gap / step:.3g} "
            f"nodes to join the start and the goal {gap:.3g} rad apart, and they hold "
            f"{MAX_NODES}; use a step of at least {smallest_step(gap):.3g} rad", "step")
    # A chain's clearances take (points x links x discs) pairs of floats, several times over.
    chain_room = max(1, CHAIN_BYTES // (64 * arm.n * (len(obstacles) + 1)))
    rng = np.random.default_rng(seed)
    reach = reach_matrix(arm)
    # Clearances this small cannot be told from touching (as in segment_collision_free).
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    # The compiled loops know obstacles only: an arm with self-collision, or a user's checker
    # (Python), grows in numpy.
    loops = (sampling_backend.kernels() if collision_backend.loaded() is not None
             and not arm.self_collision and checker is None else None)
    grown = None
    if loops is not None:
        grown = _grow_compiled(loops, arm, start, goals, obstacles, step, rng, budget, reach,
                               touch, chain_room)
    if grown is None:  # no numba, or an edge beyond the kernel's interval limit (numpy raises)
        rng = np.random.default_rng(seed)
        budget = Budget(max_iterations, time_budget)
        grown = _grow(arm, start, goals, obstacles, step, rng, budget, reach, touch, chain_room,
                      checker)
    trees, meet, full = grown
    nodes = np.vstack((trees[0].nodes, trees[1].nodes))
    parent = np.concatenate((trees[0].parent, np.where(trees[1].parent >= 0,
                                                      trees[1].parent + len(trees[0].nodes), -1)))
    if meet is None:
        if raise_on_failure:
            if full:
                raise NoPathFound(f"RRT-Connect stopped: its trees reached their {MAX_NODES} nodes "
                                  f"after {budget.iterations} iterations (each node advances at "
                                  f"most step = {step:g} rad), no goal joined")
            raise NoPathFound(budget.stopped("RRT-Connect", "no goal joined"))
        return mark_sampled(tree_result(arm, None, nodes, parent, budget.iterations,
                                        NODE_CAP if full else budget.status()), checker)
    walk = _root_chain(trees[0], meet[0])[::-1] + _root_chain(trees[1], meet[1])[1:]
    path = unwrapped_chain(arm, np.array(walk), start)
    return mark_sampled(tree_result(arm, path, nodes, parent, budget.iterations), checker)


def _grow(arm, start, goals, obstacles, step, rng, budget, reach, touch, chain_room,
          checker=None):
    """The numpy loop: ``(trees, meet, full)``, ``meet`` the two nodes that met or None."""
    clearance = _Clearance(arm, obstacles, touch)
    certify = EdgeCertifier(arm, obstacles, checker)
    trees = [ClearanceTree(arm, [start], clearance), ClearanceTree(arm, goals, clearance)]
    meet = None
    # The start may already see a goal along one straight chain.
    room = lambda: min(chain_room, MAX_NODES - trees[0].m - trees[1].m)  # noqa: E731
    j, reached = _extend(trees[1], start, step, certify, True, reach, clearance, room())
    if reached:
        meet = (0, j)
    full = False
    while meet is None and not budget.spent():
        if trees[0].m + trees[1].m >= MAX_NODES:
            full = True
            break
        if budget.iterations % 64 == 0:
            progress.report("RRT-Connect", budget.iterations, budget.max_iterations)
        a, b = trees if budget.iterations % 2 else trees[::-1]
        q_rand = uniform_samples(arm, rng, 1)[0]
        new, _ = _extend(a, q_rand, step, certify, False, reach, clearance)
        if new < 0:
            continue
        other, reached = _extend(b, a.nodes[new], step, certify, True, reach, clearance,
                                 room())
        if reached:
            meet = (new, other) if a is trees[0] else (other, new)
    return trees, meet, full


#: Iterations the compiled loop runs between two looks at the clock (and the progress line);
#: without a time budget the batches double up to :data:`LARGEST_BATCH` (fewer calls from
#: Python, each with its samples drawn: the same stream, so the same trees).
BATCH = 64
LARGEST_BATCH = 1024


def _grow_compiled(loops, arm, start, goals, obstacles, step, rng, budget, reach, touch,
                   chain_room):
    """:func:`_grow` in the compiled loops of :mod:`rapp.kernels.sampling_numba`, the same trees;
    None when an edge needs more bisection intervals than allowed (numpy says so then)."""
    n = arm.n
    cap = MAX_NODES + len(goals) + 2
    nodes, clear = np.empty((2, cap, n)), np.empty((2, cap, n))
    parent, cost = np.empty((2, cap), dtype=np.int64), np.empty((2, cap))
    m = np.zeros(2, dtype=np.int64)
    for t, roots in enumerate((start[None], goals)):
        k = len(roots)
        nodes[t, :k] = arm.wrap(roots)
        clear[t, :k] = link_clearances(arm, nodes[t, :k], obstacles)
        parent[t, :k], cost[t, :k], m[t] = -1, 0.0, k
    scene = sampling_backend.Scene(arm.lengths, np.asarray(arm.limited, dtype=np.bool_), reach,
                                  *pack(obstacles), touch, 1e-9, MAX_PENDING_INTERVALS)
    arrays = sampling_backend.Trees(nodes, parent, cost, clear, m)
    meet = None
    room = int(min(chain_room, MAX_NODES - m[0] - m[1]))
    scratch = np.empty((sampling_backend.EXTEND_ROWS + n, max(n, 2)))
    j, reached, status = loops.extend(1, start, True, room, step, scene, arrays, scratch)
    if status == sampling_backend.CONNECT_LIMIT:
        return None
    if reached:
        meet = (0, j)
    full = False
    met = np.full(2, -1, dtype=np.int64)
    batch = BATCH
    while meet is None:
        k = budget.grant(batch)
        if not k:
            break
        if budget.time_budget is None:
            batch = min(2 * batch, LARGEST_BATCH)
        progress.report("RRT-Connect", budget.iterations, budget.max_iterations)
        samples = uniform_samples(arm, rng, k)
        status, ran = loops.connect(samples, budget.iterations, MAX_NODES, chain_room, step,
                                    scene, arrays, met)
        budget.iterations += int(ran)
        if status == sampling_backend.CONNECT_MEET:
            meet = (int(met[0]), int(met[1]))
        elif status == sampling_backend.CONNECT_FULL:
            full = True
            break
        elif status == sampling_backend.CONNECT_LIMIT:
            return None
    trees = [SimpleNamespace(nodes=nodes[t, :m[t]], parent=parent[t, :m[t]]) for t in (0, 1)]
    return trees, meet, full


def _root_chain(tree: Tree, i: int) -> list:
    """Nodes from ``i`` up to its root (``i`` first)."""
    out = [tree.nodes[i]]
    while tree.parent[i] >= 0:
        i = int(tree.parent[i])
        out.append(tree.nodes[i])
    return out


# Its kernels are compiled before a time budget of it starts (rapp.sampling.prepare_kernels).
warms(rrt_connect, max_iterations=300)
