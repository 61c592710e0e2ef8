"""Lazy PRM: a probabilistic roadmap whose edges are certified only when a path needs them.

Free configurations are sampled uniformly and each is joined to its ``neighbours`` nearest
(wrap-aware distance) by a *candidate* edge. A* (Dijkstra's algorithm guided by the distance to
the nearest goal, a lower bound) finds the shortest candidate path from the start to a goal; only that path's uncertified edges are then certified
(:func:`rapp.collision.segment_collision_free`, all in one call). Edges that fail are refuted
(never taken again) and the search is repeated; when the roadmap holds no path, it grows: the
first batch is ``samples`` configurations, each later one doubles the roadmap, so that an easy
query is answered by a small roadmap (as OMPL's PRM grows until its query is solved).
Most candidate edges are never checked, which is where the time of a PRM goes.

With numba the candidate edges are found by a compiled nearest-k scan and kept as arrays, and the
rounds of search, certification and removal run in one compiled loop (:func:`_lazy_searches`,
calling the compiled A*); the roadmaps, searches and paths are those of the dict-based
numpy loop, which is the fallback.

References
----------
Kavraki, Švestka, Latombe and Overmars (1996), Probabilistic roadmaps for path planning in
high-dimensional configuration spaces. Bohlin and Kavraki (2000), Path planning using lazy PRM.
"""

from __future__ import annotations

import functools
import heapq
import itertools
import time
from collections import namedtuple

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm
    from rapp.obstacles import Circle, Polygon

from rapp import heap, progress
from rapp.kernels import sampling as sampling_backend
from rapp.checks import positive_integer
from rapp.collision import MAX_PENDING_INTERVALS, collides, scene
from rapp.errors import InvalidSetting, NoPathFound
from rapp.jit import jit
from rapp.paths import NODE_CAP, TIME_BUDGET_SPENT, PlannerResult, tree_result
from rapp.rrt import RRTResult
from rapp.sampling import warms
from rapp.sampling import (Budget, EdgeCertifier, check_start_and_goals, squared_norms, uniform_samples,
                           unwrapped_chain)
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, mark_sampled, user_validity

__all__ = ["prm", "roadmap_bytes", "MAX_SAMPLES", "largest_roadmap", "MEMORY_BUDGET", "BYTES_PER_EDGE", "CandidateEdges", "grow_roadmap",
           "heuristic", "path_of", "SEARCHES", "OutOfTime"]

#: The default largest roadmap (samples) of a PRM whose ``samples`` are few.
MAX_SAMPLES = 10_000


def largest_roadmap(samples: int) -> int:
    """The default ``max_samples`` of :func:`prm` for a first batch of ``samples``.

    Examples
    --------
    >>> largest_roadmap(10), largest_roadmap(1000)
    (10000, 20000)
    """
    return max(MAX_SAMPLES, 20 * samples)


#: Peak bytes the roadmap may take (as the grid planner's budget, rapp.scenario.MEMORY_BUDGET).
MEMORY_BUDGET = 1.5e9
#: Bytes per candidate edge: its dict entry (about 190 B, measured with tracemalloc) and its
#: two entries in Dijkstra's adjacency lists (about 200 B).
BYTES_PER_EDGE = 400
#: Bytes of the distance block of one batch of new nodes against all nodes (its rows shrink
#: as the roadmap grows, so it never takes more).
BLOCK_BYTES = 64_000_000


def _dijkstra_kernel(n, start, stop, dst, wt, sources, is_target, h):
    """A* over a CSR graph (node u's neighbours ``dst[start[u]:stop[u]]``), for numba.

    ``h`` is a consistent lower bound of each node's distance to the targets (zeros: Dijkstra).
    The heap (:mod:`rapp.heap`) holds ``(distance + h, node)`` pairs compared as heapq compares
    the tuples of :func:`_dijkstra`, and every neighbour list is in the order :func:`_dijkstra`
    builds, so both pop the same nodes in the same order and return the same parents.
    """
    dist = np.full(n, np.inf)
    parent = np.full(n, -1, dtype=np.int64)
    cap = len(sources) + len(dst) + 1
    hd = np.empty(cap)
    hu = np.empty(cap, dtype=np.int64)
    size = 0
    for s in sources:
        dist[s] = 0.0
        size = heap.push(hd, hu, size, 0.0 + h[s], s)
    while size:
        f, u, size = heap.pop(hd, hu, size)
        if f > dist[u] + h[u]:
            continue
        if is_target[u]:
            return parent, u
        d = dist[u]
        for e in range(start[u], stop[u]):
            v = dst[e]
            nd = d + wt[e]
            if nd < dist[v]:
                dist[v] = nd
                parent[v] = u
                size = heap.push(hd, hu, size, nd + h[v], v)
    return parent, -1


@functools.cache
def _compiled_dijkstra():
    """:func:`_dijkstra_kernel` compiled by numba (cached on disk), or None without numba."""
    return jit(_dijkstra_kernel) if heap.compiled() else None  # heap's functions first


def _shortest(nodes_n: int, edges: dict, sources, targets, budget=None, h=None):
    """:func:`_dijkstra`, compiled when numba is there: the same parents and the same target."""
    kernel = _compiled_dijkstra()
    if kernel is None or not edges:
        return _dijkstra(nodes_n, edges, sources, targets, budget, h)
    _check_time(budget)  # compiled, the search itself takes a small fraction of a batch
    m = len(edges)
    ij = np.fromiter(itertools.chain.from_iterable(edges), dtype=np.int64, count=2 * m)
    w = np.fromiter(edges.values(), dtype=float, count=m)
    # Both directions of edge k at positions 2k, 2k + 1; a stable sort by source keeps every
    # neighbour list in edge order, the order _dijkstra appends them in.
    src = ij
    dst = ij.reshape(-1, 2)[:, ::-1].ravel()
    order = np.argsort(src, kind="stable")
    dst, wt = dst[order], np.repeat(w, 2)[order]
    counts = np.bincount(src, minlength=nodes_n)
    stop = np.cumsum(counts)
    is_target = np.zeros(nodes_n, dtype=np.bool_)
    is_target[np.asarray(targets, dtype=np.int64)] = True
    parent, hit = kernel(nodes_n, stop - counts, stop, dst, wt,
                         np.asarray(sources, dtype=np.int64), is_target,
                         np.zeros(nodes_n) if h is None else h)
    return parent, int(hit)


def roadmap_bytes(n: int, nodes: int, neighbours: int) -> float:
    """Peak bytes of a roadmap of ``nodes`` configurations of ``n`` joints, ``neighbours`` each.

    Examples
    --------
    >>> roadmap_bytes(2, 10_001, 10) / 1e6   # the default: MAX_SAMPLES, start and goal
    104.164016
    """
    return nodes * neighbours * BYTES_PER_EDGE + BLOCK_BYTES + nodes * n * 8


class OutOfTime(Exception):
    """The time budget ran out inside a roadmap's growth or search (the planner says so)."""


_OutOfTime = OutOfTime


class _Limit(Exception):
    """An edge needed more bisection intervals than the compiled loop allows."""


def _check_time(budget) -> None:
    if (budget is not None and budget.time_budget is not None
            and time.perf_counter() - budget.t0 > budget.time_budget):
        raise _OutOfTime


def _dijkstra(nodes_n: int, edges: dict, sources, targets, budget=None, h=None):
    """Shortest path on an undirected weighted graph {(i, j): w}; parent map and the target hit.

    With ``h`` (each node's consistent lower bound on its distance to the targets) it is A*:
    the same shortest paths, fewer nodes popped. An edge of length ``inf`` is never taken."""
    h = np.zeros(nodes_n) if h is None else h
    adj = [[] for _ in range(nodes_n)]
    for count, ((i, j), w) in enumerate(edges.items()):
        adj[i].append((j, w))
        adj[j].append((i, w))
        if count % 65536 == 65535:
            _check_time(budget)
    dist = np.full(nodes_n, np.inf)
    parent = np.full(nodes_n, -1)
    heap = []
    for s in sources:
        dist[s] = 0.0
        heap.append((0.0 + h[s], s))
    heapq.heapify(heap)
    goal_set = set(int(t) for t in targets)
    pops = 0
    while heap:
        pops += 1
        if pops % 16384 == 0:
            _check_time(budget)
        f, u = heapq.heappop(heap)
        if f > dist[u] + h[u]:
            continue
        if u in goal_set:
            return parent, u
        d = dist[u]
        for v, w in adj[u]:
            nd = d + w
            if nd < dist[v]:
                dist[v], parent[v] = nd, u
                heapq.heappush(heap, (nd + h[v], v))
    return parent, -1


def prm(arm: Arm, start: ArrayLike, goal: ArrayLike, obstacles: Iterable[Circle | Polygon] = (), *,
        samples: int = 10, neighbours: int = 10, seed: int | np.random.SeedSequence = 0,
        max_iterations: int = 500, time_budget: float | None = None,
        max_samples: int | None = None, raise_on_failure: bool = True,
        neighbors: int | None = None, margin: float = 0.0,
        validity: ValidityFunction | None = None,
        validity_resolution: float = DEFAULT_RESOLUTION) -> PlannerResult:
    """Plan with a lazy probabilistic roadmap from ``start`` to a goal configuration.

    Parameters
    ----------
    arm, start, goal, obstacles
        As :func:`rapp.rrt_connect.rrt_connect`.
    samples : int
        Free configurations of the roadmap's first batch; each time the roadmap holds no
        path, it grows by as many samples as it holds (it doubles), up to ``max_samples``.
    neighbours : int
        Candidate edges from each node to its nearest nodes.
    neighbors : int, optional
        The same, spelled the American way; give one of the two.
    max_iterations : int
        Path searches at most (each followed by certifying the path it found).
    max_samples : int, optional
        Largest roadmap in samples (default :func:`largest_roadmap`, the larger of
        :data:`MAX_SAMPLES` and ``20 * samples``): when it holds no path, the answer is failure.
    time_budget : float, optional
        Seconds at most.
    margin : float
        Safety margin (metres, >= 0) every link keeps beyond its radius
        (``arm.link_radius``) from every obstacle (:func:`rapp.collision.scene`).
    validity : callable, optional
        A user's checker, ``(m, n)`` configurations -> ``m`` booleans (True: allowed), on top
        of rapp's certified obstacles: samples it rejects are not added, and an edge is sampled
        at ``validity_resolution`` (:mod:`rapp.validity`). The roadmap is then searched in
        numpy (compiled loops cannot call Python), and the result says its path was sampled
        (``certified`` False, ``checked_by``).
    validity_resolution : float
        Largest joint-space step (rad) between two samples of an edge for ``validity``.

    Returns
    -------
    PlannerResult
        ``nodes`` the roadmap (start first, then the goals, then the samples) and ``parent``
        the last search's shortest-path tree.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> res = prm(arm, [0.0, 0.0], [2.5, 0.0], [Circle((0.0, 1.2), 0.3)], samples=200, seed=1)
    >>> res.success, bool(np.allclose(arm.wrap(res.path[-1]), [2.5, 0.0]))
    (True, True)
    """
    arm, obstacles = scene(arm, list(obstacles), margin)
    obstacles = list(obstacles)
    samples = positive_integer(samples, "samples")
    if neighbors is not None:
        if neighbours != 10 and neighbours != neighbors:
            raise InvalidSetting(f"neighbors={neighbors} and neighbours={neighbours} disagree: "
                                 "give one of them", "neighbors")
        neighbours = neighbors
    neighbours = positive_integer(neighbours, "neighbours")
    cap_name = "samples" if max_samples is None else "max_samples"
    max_samples = largest_roadmap(samples) if max_samples is None else positive_integer(max_samples, "max_samples")
    budget = Budget(max_iterations, time_budget)
    checker = user_validity(validity, validity_resolution)
    start, goals = check_start_and_goals(arm, start, goal, obstacles, checker)
    peak = roadmap_bytes(arm.n, max_samples + 1 + len(goals), neighbours)
    if peak > MEMORY_BUDGET:
        raise InvalidSetting(
            f"a roadmap of up to {max_samples + 1 + len(goals)} nodes"
            + (f" (the larger of {MAX_SAMPLES} and 20 x samples)" if cap_name == "samples" else "")
            + f" with {neighbours} neighbours each would need about {peak / 1e9:.3g} GB, over "
            f"the {MEMORY_BUDGET / 1e9:g} GB budget: lower {cap_name} or neighbours", cap_name)
    try:
        try:
            return mark_sampled(_roadmap(arm, start, goals, obstacles, samples, neighbours,
                                         max_samples, budget, seed, raise_on_failure,
                                         checker=checker), checker)
        except _Limit:  # the numpy loop meets the same edge and raises its message
            budget = Budget(max_iterations, time_budget)
            return _roadmap(arm, start, goals, obstacles, samples, neighbours, max_samples,
                            budget, seed, raise_on_failure, compiled=False)
    except _OutOfTime:
        if raise_on_failure:
            raise NoPathFound(f"PRM stopped: time_budget {budget.time_budget:g} s spent after "
                              f"{budget.iterations} searches, no goal joined") from None
        return tree_result(arm, None, np.vstack((start, goals)), np.full(1 + len(goals), -1),
                           budget.iterations, TIME_BUDGET_SPENT)


def _roadmap(arm, start, goals, obstacles, samples, neighbours, max_samples, budget, seed,
             raise_on_failure, compiled=True, checker=None) -> RRTResult:
    """The lazy PRM loop of :func:`prm` on validated arguments; raises _OutOfTime. A user's
    ``checker`` (:class:`rapp.validity.UserValidity`) runs it in numpy."""
    compiled = compiled and checker is None  # the compiled loops cannot call Python
    rng = np.random.default_rng(seed)
    nodes = arm.wrap(np.vstack((start, goals)))
    goal_ids = np.arange(1, len(goals) + 1)
    edges = CandidateEdges(arm, obstacles, neighbours, compiled=compiled, checker=checker)
    parent, hit = np.full(len(nodes), -1), -1
    grow, full = True, False
    while True:
        rounds = budget.grant(SEARCHES)
        if not rounds:
            break
        if grow:
            if len(nodes) - 1 - len(goals) >= max_samples:
                budget.iterations += 1  # this search was counted before the roadmap was full
                full = True
                break
            first_new = len(nodes)
            have = first_new - 1 - len(goals)
            # The first batch is ``samples``; each later one doubles the roadmap (never past
            # max_samples): a query solved by a few samples pays for a few, a hard one
            # grows in a handful of batches.
            batch = min(max(samples, have), max_samples - have)
            nodes = grow_roadmap(arm, rng, nodes, batch, obstacles, budget, checker)
            edges.add(nodes, 0 if first_new <= 1 + len(goals) else first_new, budget)
        parent, hit, used, found = edges.search(nodes, rounds, [0], goal_ids, budget)
        budget.iterations += used
        if found:
            return tree_result(arm, path_of(arm, nodes, parent, hit, start), nodes, parent,
                               budget.iterations)
        grow = hit < 0
    outcome = f"the roadmap of {len(nodes)} nodes joined no goal"
    if full:
        status, msg = NODE_CAP, (f"PRM stopped: its roadmap reached max_samples {max_samples} "
                                 f"after {budget.iterations} searches, {outcome}")
    else:
        status, msg = budget.status(), budget.stopped("PRM", outcome, unit="searches")
    if raise_on_failure:
        raise NoPathFound(msg)
    return tree_result(arm, None, nodes, parent, budget.iterations, status)


def path_of(arm, nodes, parent, hit, start) -> np.ndarray:
    """The path a search's ``parent`` tree holds from its source to node ``hit``, unwrapped
    from ``start``: ``(k, n)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> path_of(Arm([1.0, 1.0]), np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]),
    ...         np.array([-1, 0, 1]), 2, np.zeros(2)).tolist()
    [[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]
    """
    up = parent.tolist()  # Python ints: the walk is a few list look-ups
    chain = [int(hit)]
    while up[chain[-1]] >= 0:
        chain.append(up[chain[-1]])
    return unwrapped_chain(arm, nodes[chain[::-1]], start)


def heuristic(arm, nodes, targets) -> np.ndarray:
    """Each node's distance to its nearest target node (wrap-aware), a hair under: the lower
    bound that makes a roadmap's shortest-path search A* (:func:`_dijkstra`), ``(m,)``.

    Examples
    --------
    >>> from rapp import Arm
    >>> heuristic(Arm([1.0, 1.0]), np.array([[0.0, 0.0], [0.3, 0.4]]), [1]).round(9).tolist()
    [0.5, 0.0]
    """
    targets = np.asarray(targets, dtype=np.int64)
    if targets.size == 1:  # one goal, as most queries: no (m, 1, n) broadcast
        d = arm.joint_delta(nodes, nodes[targets[0]])[:, None, :]
    else:
        d = arm.joint_delta(nodes[:, None, :], nodes[targets][None])
    # Scaled down by far more than rounding, so that the bound stays below every path's length
    # as the kernels sum it (the edge lengths come from the compiled scan).
    return np.sqrt(squared_norms(d)).min(axis=1) * (1 - 1e-9)


class CandidateEdges:
    """A lazy roadmap's candidate edges and what is known of them: certified free (``done``),
    refuted (length ``inf``, never taken) or not yet checked.

    ``add`` joins new nodes to their nearest; ``search`` runs shortest-path searches from
    ``sources`` to ``targets``, certifying each path's unchecked edges until one path is free;
    ``keep(nodes_n, m)`` forgets nodes from ``nodes_n`` on and edges from ``m`` on (a query's
    own nodes, found last); ``state()`` and ``restore(...)`` give and take ``(ij, w, done)``.
    The compiled loops (arrays, :func:`_lazy_searches`) when numba is there and the arm has no
    self-collision, the numpy loop (a dict) otherwise; both keep the same edges in the same
    order and search alike. A user's ``checker`` (:class:`rapp.validity.UserValidity`) also
    judges every edge (sampled, numpy loop). With ``fallback`` an edge beyond the compiled certificate's limit
    moves the edges to the numpy loop, which says so; without it, the search raises _Limit.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> edges = CandidateEdges(arm, [Circle((0.0, 1.5), 0.3)], neighbours=1)
    >>> nodes = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]])
    >>> edges.add(nodes, 0)
    >>> parent, hit, used, found = edges.search(nodes, 4, [0], [2])
    >>> int(hit), bool(found), edges.state()[2].tolist()
    (2, True, [True, True])
    """

    def __init__(self, arm, obstacles, neighbours, compiled=True, fallback=False, checker=None):
        self.arm, self.obstacles, self.neighbours = arm, list(obstacles), neighbours
        self.fallback = fallback
        # The compiled loops know obstacles only: an arm with self-collision, or a user's
        # checker (Python), searches in numpy.
        loops = (sampling_backend.kernels() if compiled and self.obstacles and not arm.self_collision
                 and checker is None else None)
        lazy = _compiled_lazy() if loops is not None else None
        self.impl = (_ArrayEdges(arm, neighbours, loops, lazy) if lazy is not None
                     else _DictEdges(arm, neighbours))
        self.certify = EdgeCertifier(arm, self.obstacles, checker)

    def add(self, nodes, first_new, budget=None) -> None:
        self.impl.add(nodes, first_new, budget)

    def search(self, nodes, rounds, sources, targets, budget=None):
        """Up to ``rounds`` searches: ``(parent, hit, searches, found)``; it stops at a
        certified path to ``hit`` (``found``) or when the roadmap holds none (``hit < 0``)."""
        h = heuristic(self.arm, nodes, targets)
        sources = np.asarray(sources, dtype=np.int64)
        targets = np.asarray(targets, dtype=np.int64)
        try:
            return self.impl.search(nodes, rounds, self.certify, budget, sources, targets, h)
        except _Limit:
            if not self.fallback:
                raise
            state = self.state()
            self.impl = _DictEdges(self.arm, self.neighbours)
            self.impl.restore(*state, len(nodes))
            return self.impl.search(nodes, rounds, self.certify, budget, sources, targets, h)

    def certify_all(self, nodes, budget=None) -> None:
        """Certify every edge not yet checked, in one call (a roadmap built for many queries
        pays for its edges once, at the build): each becomes certified free or refuted."""
        _check_time(budget)
        ij, w, done = self.impl.state()
        todo = np.flatnonzero(~done & np.isfinite(w))
        if not len(todo):
            return
        a = nodes[ij[todo, 0]]
        free = self.certify(a, a + self.arm.joint_delta(a, nodes[ij[todo, 1]]))
        self.impl.settle_edges(todo, ij[todo], free)

    @property
    def count(self) -> int:
        """How many candidate edges there are."""
        return len(self.impl.w) if isinstance(self.impl, _ArrayEdges) else len(self.impl.edges)

    def keep(self, nodes_n, m) -> None:
        if isinstance(self.impl, _ArrayEdges):
            return self.impl.keep(nodes_n, m)
        self.impl.restore(*(a[:m] for a in self.impl.state()), nodes_n)

    def state(self):
        """``(ij, w, done)``: the edges' node pairs, lengths (``inf`` refuted) and certified
        flags, in the order they were found (copies)."""
        return tuple(a.copy() for a in self.impl.state())

    def restore(self, ij, w, done, nodes_n) -> None:
        self.impl.restore(np.array(ij, dtype=np.int64).reshape(-1, 2),
                          np.array(w, dtype=float), np.array(done, dtype=bool), nodes_n)


class _DictEdges:
    """Candidate edges as a dict ``{(i, j): length}`` (``i < j``) in the order they were found
    (a refuted edge's length ``inf``), the certified ones in a set; A* by :func:`_shortest`.
    The path without numba."""

    def __init__(self, arm, neighbours):
        self.arm, self.neighbours = arm, neighbours
        self.edges: dict = {}
        self.done: set = set()

    def add(self, nodes, first_new, budget):
        _add_candidate_edges(self.arm, nodes, self.neighbours, self.edges, first_new, budget)

    def certified(self, pairs):
        return np.array([(int(a), int(b)) in self.done for a, b in pairs], dtype=bool)

    def search(self, nodes, rounds, certify, budget, sources, targets, h):
        """:meth:`CandidateEdges.search`."""
        for used in range(1, rounds + 1):
            parent, hit = _shortest(len(nodes), self.edges, sources, targets, budget, h)
            if hit < 0:
                return parent, hit, used, False
            chain = [hit]
            while parent[chain[-1]] >= 0:
                chain.append(int(parent[chain[-1]]))
            chain = np.array(chain[::-1])
            pairs = np.sort(np.stack((chain[:-1], chain[1:]), axis=-1), axis=-1)
            todo = pairs[~self.certified(pairs)]
            if len(todo):
                a = nodes[todo[:, 0]]
                free = certify(a, a + self.arm.joint_delta(a, nodes[todo[:, 1]]))
                self.settle(todo, free)
                if not free.all():
                    continue
            return parent, hit, used, True
        return parent, hit, rounds, False

    def settle(self, pairs, free):
        """Keep the certified edges of ``pairs`` (``free``), refute the others."""
        for (a, b), ok in zip(pairs, free):
            if ok:
                self.done.add((int(a), int(b)))
            else:
                self.edges[(int(a), int(b))] = np.inf

    def settle_edges(self, index, pairs, free):
        """:meth:`settle` (the edges' ``index`` unused: the dict is keyed by their ends)."""
        self.settle(pairs, free)

    def state(self):
        m = len(self.edges)
        ij = np.array(list(self.edges), dtype=np.int64).reshape(m, 2)
        w = np.fromiter(self.edges.values(), dtype=float, count=m)
        return ij, w, self.certified(ij)

    def restore(self, ij, w, done, nodes_n):
        self.edges = {(int(a), int(b)): float(x) for (a, b), x in zip(ij, w)}
        self.done = {(int(a), int(b)) for (a, b), ok in zip(ij, done) if ok}


class _ArrayEdges:
    """:class:`_DictEdges` as arrays, for the compiled loops: the same edges in the same order,
    found by the compiled nearest-neighbour scan, and one CSR graph per roadmap size in which a
    refuted edge weighs ``inf`` (A* never relaxes it: the same search as without it)."""

    def __init__(self, arm, neighbours, loops, lazy):
        self.arm, self.neighbours, self.loops, self.lazy = arm, neighbours, loops, lazy
        self.limited = np.asarray(arm.limited, dtype=np.bool_)
        self.restore(np.empty((0, 2), dtype=np.int64), np.empty(0), np.empty(0, dtype=bool), 0)

    def add(self, nodes, first_new, budget):
        k = min(self.neighbours, len(nodes) - 1)
        if k <= 0:
            return
        _check_time(budget)
        rows = len(nodes) - first_new
        near, dist = np.empty((rows, k), dtype=np.int64), np.empty((rows, k))
        self.loops.nearest_k(nodes, first_new, k, self.limited, near, dist)
        i = np.repeat(np.arange(first_new, len(nodes)), k)
        ij = np.sort(np.stack((i, near.ravel()), axis=-1), axis=-1)
        # The first time each edge is met, in the order the dict of _DictEdges fills.
        first = np.sort(np.unique(ij[:, 0] * len(nodes) + ij[:, 1], return_index=True)[1])
        # The graph before, for keep() to return to without rebuilding it (only wt changes).
        self.before = (first_new, len(self.w), self.start, self.stop, self.dst, self.order,
                       self.slot)
        self.restore(np.concatenate((self.ij, ij[first])),
                     np.concatenate((self.w, dist.ravel()[first])),
                     np.concatenate((self.done, np.zeros(len(first), dtype=bool))), len(nodes))

    def state(self):
        return self.ij, self.w, self.done

    def settle_edges(self, index, pairs, free):
        """Edges ``index`` certified free (``free``) or refuted, in place (their CSR entries
        too)."""
        self.done[index[free]] = True
        bad = index[~free]
        self.w[bad] = np.inf
        self.wt[self.slot[2 * bad]] = np.inf
        self.wt[self.slot[2 * bad + 1]] = np.inf

    def keep(self, nodes_n, m):
        """:meth:`CandidateEdges.keep`; back to the graph before the last ``add`` when it was
        of this size (a query's ends), its lengths from ``w`` (a refuted edge's ``inf``)."""
        before = getattr(self, "before", None)
        if before is None or before[:2] != (nodes_n, m):
            return self.restore(self.ij[:m], self.w[:m], self.done[:m], nodes_n)
        self.ij, self.w, self.done = self.ij[:m], self.w[:m].copy(), self.done[:m].copy()
        _, _, self.start, self.stop, self.dst, self.order, self.slot = before
        self.wt = self.w[self.order >> 1]
        self.before = None

    def restore(self, ij, w, done, nodes_n):
        """These edges, and their CSR graph over ``nodes_n`` nodes (:func:`_csr_kernel`)."""
        self.ij, self.w, self.done = ij, np.ascontiguousarray(w, dtype=float), done
        m = len(self.w)
        self.start, self.stop = np.zeros(nodes_n, dtype=np.int64), np.empty(nodes_n, dtype=np.int64)
        self.dst, self.order, self.slot = (np.empty(2 * m, dtype=np.int64) for _ in range(3))
        self.wt = np.empty(2 * m)
        self.lazy.csr(np.ascontiguousarray(ij, dtype=np.int64), self.w,
                      _Csr(self.start, self.stop, self.dst, self.wt, self.order, self.slot))

    def search(self, nodes, rounds, certify, budget, sources, targets, h):
        """:meth:`_DictEdges.search` in one compiled loop (:func:`_lazy_searches`)."""
        _check_time(budget)
        c = certify
        is_target = np.zeros(len(nodes), dtype=np.bool_)
        is_target[targets] = True
        status, used, hit, parent = self.lazy.searches(
            rounds, len(nodes),
            _Roadmap(self.start, self.stop, self.dst, self.wt, self.order, self.slot, self.w,
                     self.done, sources, is_target, h),
            _Scene(nodes, self.limited, self.arm.lengths, c.reach, *c.packed, c.touch, 1e-9,
                   MAX_PENDING_INTERVALS))
        if status == _LIMIT:  # an edge beyond the kernel's interval limit: numpy says so
            raise _Limit
        return parent, int(hit), int(used), status == _FOUND


#: Fewest configurations :func:`grow_roadmap` draws at a time.
GROW_DRAWS = 32


def grow_roadmap(arm, rng, nodes, k, obstacles, budget=None, checker=None) -> np.ndarray:
    """``nodes`` with ``k`` free uniform samples appended (drawn until that many are free;
    with a user's ``checker``, also allowed by it).

    Examples
    --------
    >>> from rapp import Arm
    >>> grow_roadmap(Arm([1.0, 1.0]), np.random.default_rng(0), np.zeros((1, 2)), 3, []).shape
    (4, 2)
    """
    new = []
    have = 0
    for _ in range(100):
        _check_time(budget)
        # Never fewer than GROW_DRAWS a round: a small batch is then drawn in one round.
        q = uniform_samples(arm, rng, max(k - have, GROW_DRAWS))
        if obstacles or arm.self_collision:
            q = q[~collides(arm, q, obstacles)]
        if checker is not None:
            q = q[checker.points(q, arm)]
        new.append(q)
        have += len(q)
        if have >= k:
            break
    return np.vstack([nodes] + new)[: len(nodes) + k]


def _add_candidate_edges(arm, nodes, k, edges, first_new, budget=None):
    """Join every node from ``first_new`` on to its ``k`` nearest (wrap-aware) by a candidate
    edge; edges already there keep their state. Blocks of new nodes against all nodes, each
    block within BLOCK_BYTES (its distance arrays take about 4 floats per pair and joint)."""
    k = min(k, len(nodes) - 1)
    if k <= 0:
        return
    rows = int(max(1, min(256, BLOCK_BYTES // (32 * len(nodes) * arm.n))))
    for lo in range(first_new, len(nodes), rows):
        _check_time(budget)
        progress.report("PRM roadmap", lo - first_new, len(nodes) - first_new)
        block = np.arange(lo, min(lo + rows, len(nodes)))
        d = arm.joint_delta(nodes[block, None, :], nodes[None, :, :])
        dist = np.sqrt(squared_norms(d))
        dist[np.arange(len(block)), block] = np.inf
        near = np.argpartition(dist, k - 1, axis=1)[:, :k]
        # Nearest first, equal distances by index: the order of the compiled scan
        # (rapp.kernels.sampling_numba), so both fill the roadmap alike.
        near = np.take_along_axis(near, np.lexsort((near, np.take_along_axis(dist, near, 1))), 1)
        for row, i in enumerate(block):
            for j in near[row]:
                key = (min(int(i), int(j)), max(int(i), int(j)))
                if key not in edges:
                    edges[key] = float(dist[row, j])


#: Searches the roadmap loop runs between two looks at the clock.
SEARCHES = 16
_NO_PATH, _FOUND, _MORE, _LIMIT = 0, 1, 2, 3


#: A CSR graph as :func:`_csr_kernel` fills it (see :data:`_Roadmap`).
_Csr = namedtuple("_Csr", "start stop dst wt order slot")


def _csr_kernel(ij, w, csr):
    """The CSR graph of the edges ``ij`` (lengths ``w``) into ``csr`` (:data:`_Csr`; ``start``
    zeros): node u's neighbours ``dst[start[u]:stop[u]]`` in edge order, entry ``p`` edge
    ``order[p] >> 1``'s (``2e`` its first end's, ``2e + 1`` its second's), ``slot`` the
    inverse of ``order``: the stable sort by source of :func:`_shortest`, by counting."""
    start, stop, dst, wt, order, slot = csr
    m = ij.shape[0]
    for e in range(m):
        start[ij[e, 0]] += 1
        start[ij[e, 1]] += 1
    total = 0
    for u in range(start.shape[0]):
        count = start[u]
        start[u] = total
        stop[u] = total
        total += count
    for e in range(m):
        for end in range(2):
            u, v = ij[e, end], ij[e, 1 - end]
            p = stop[u]
            stop[u] += 1
            dst[p], wt[p], order[p], slot[2 * e + end] = v, w[e], 2 * e + end, p


#: The roadmap as :func:`_lazy_searches` reads it: the CSR graph of :class:`_ArrayEdges`
#: (``start``/``stop`` per node into ``dst``, ``wt``, ``order`` and ``slot``; the edges' weights
#: ``w`` and certified flags ``done``) and the search's ``sources``, ``is_target`` and A*'s
#: lower bounds ``h``.
_Roadmap = namedtuple("_Roadmap", "start stop dst wt order slot w done sources is_target h")
#: What certifying an edge needs: the ``nodes``, the arm (``limited``, ``lengths``, ``reach``),
#: the packed obstacles (``circles pv pn pr offsets``) and the certificate's limits.
_Scene = namedtuple("_Scene", "nodes limited lengths reach circles pv pn pr offsets touch "
                            "min_interval cap")


def _lazy_searches(rounds, nodes_n, roadmap, scene):
    """:meth:`_DictEdges.search` for numba: up to ``rounds`` Dijkstra searches on the CSR graph
    of :class:`_ArrayEdges` (:data:`_Roadmap`), each path's uncertified edges certified (the
    compiled bisection of :class:`rapp.sampling.EdgeCertifier`, :data:`_Scene`), those not free
    dropped (weight ``inf``).

    Returns ``(status, searches, hit, parent)``: _FOUND a certified path to ``hit``, _NO_PATH
    none in the roadmap, _MORE the rounds ran out, _LIMIT an edge over ``cap`` intervals.
    """
    start, stop, dst, wt, order, slot, w, done, sources, is_target, h = roadmap
    nodes, limited, lengths, reach, circles, pv, pn, pr, offsets, touch, min_interval, cap = scene
    n = nodes.shape[1]
    scratch = np.empty((3, n))
    d = np.empty(n)
    chain = np.empty(nodes_n, dtype=np.int64)
    parent = np.full(nodes_n, -1, dtype=np.int64)
    hit = -1
    for used in range(1, rounds + 1):
        parent, hit = _dijkstra_compiled(nodes_n, start, stop, dst, wt, sources, is_target, h)
        if hit < 0:
            return _NO_PATH, used, hit, parent
        size = 0
        v = hit
        while v >= 0:
            chain[size] = v
            size += 1
            v = parent[v]
        found = True
        for t in range(size - 1, 0, -1):  # from the start on, as the numpy loop lists them
            lo = min(chain[t], chain[t - 1])
            hi = max(chain[t], chain[t - 1])
            e = -1
            for pos in range(start[lo], stop[lo]):
                if dst[pos] == hi and wt[pos] < np.inf:
                    e = order[pos] >> 1
                    break
            if done[e]:
                continue
            for j in range(n):
                dj = nodes[hi, j] - nodes[lo, j]
                d[j] = dj if limited[j] else _wrap_compiled(dj)
            code = _bisect_compiled(nodes[lo], d, scene, scratch)
            if code < 0:
                return _LIMIT, used, hit, parent
            if code == 1:
                done[e] = True
            else:
                found = False
                w[e] = np.inf
                wt[slot[2 * e]] = np.inf
                wt[slot[2 * e + 1]] = np.inf
        if found:
            return _FOUND, used, hit, parent
    return _MORE, rounds, hit, parent


def _dijkstra_compiled(*args):
    """The compiled Dijkstra (set by :func:`_compiled_lazy`)."""
    raise RuntimeError("compiled only")


_bisect_compiled = _wrap_compiled = _dijkstra_compiled
#: The compiled loops of :class:`_ArrayEdges`: the searches and the CSR builder.
_Lazy = namedtuple("_Lazy", "searches csr")


@functools.cache
def _compiled_lazy():
    """:func:`_lazy_searches` compiled (cached on disk), calling the compiled Dijkstra and the
    compiled loops of :mod:`rapp.kernels.sampling_numba`; None without numba."""
    dijkstra, loops = _compiled_dijkstra(), sampling_backend.kernels()
    if dijkstra is None or loops is None:
        return None
    g = globals()
    g["_dijkstra_compiled"], g["_bisect_compiled"], g["_wrap_compiled"] = (
        dijkstra, loops.bisect, loops.wrap)
    return _Lazy(jit(_lazy_searches), jit(_csr_kernel))


# Its kernels are compiled before a time budget of it starts (rapp.sampling.prepare_kernels).
warms(prm, max_iterations=5)
