"""Graph search on the discretized joint space (TM:AStarJointSpace, GD1).

The search space is an occupancy grid of any dimension ``n``: ``occupied`` is
a bool array, ``True`` where the cell is blocked. A cell is a tuple of ``n``
indices. Every step moves one index by +-1 and costs 1, so a cell has at most
``2n`` neighbours. An axis *wraps* (a joint that turns freely: the grid is a
torus along it) or is bounded (a joint with limits); ``wraps`` is one bool for
every axis, or one bool per axis.

* :func:`astar` / :func:`astar_search` -- A* with the toroidal Manhattan
  heuristic of GD1, optionally weighted (MIS ``HEURISTIC_FACTOR``) and with an
  expansion limit (MIS ``MAX_ITERATIONS``).
* :func:`bfs` / :func:`bfs_distances` -- breadth-first search, the optimal
  oracle the tests compare A* against (on unit costs BFS is Dijkstra).
* :func:`greedy_best_first` -- kept only to show why it is not optimal.
* :func:`check_heuristic` -- exhaustive admissibility and consistency check.
* :func:`astar_steps` -- the same A*, recorded expansion by expansion (for figures).

Implementation note: :func:`astar_search`, the version the book shows, runs in
Python over flat cell numbers. The neighbour table (with the wrap of each axis
built in) and the heuristic of every cell are computed once with numpy; the
inner loop only reads Python lists and a bytearray, which is several times
faster than tuples of indices (:mod:`rapp.kernels.search_python`). :func:`astar` runs the
same search, in the same order, compiled with numba (:mod:`rapp.kernels.search_numba`)
when numba can be imported, and falls back to that Python loop when it
cannot (the choice: :mod:`rapp.kernels.search`). Its open list is a bucket queue of three
``f`` levels when ``w = 1`` and the binary heap of :mod:`rapp.heap` otherwise;
both pop the entries in the order of the heap of :func:`astar_search`. numba
is imported on the first search of a grid of :data:`COMPILE_FROM` cells or
more, not with rapp: a smaller grid is searched in Python until then.
"""

from __future__ import annotations

import heapq
import operator
from dataclasses import dataclass

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.kernels import search as search_backend
from rapp.kernels import search_python
from rapp.kernels.search import COMPILE_FROM
from rapp.kernels.search_python import PaddedGraph, heuristic_grid
from rapp.errors import InvalidCell, NoPathFound
from rapp.checks import sorted_unique, finite_number, positive_integer

__all__ = [
    "COMPILE_FROM",
    "SearchResult",
    "HeuristicCheck",
    "astar",
    "astar_search",
    "bfs",
    "bfs_distances",
    "greedy_best_first",
    "toroidal_manhattan",
    "check_heuristic",
    "AStarTrace",
    "astar_steps",
]


# --------------------------------------------------------------------------- helpers


def _grid(occupied):
    occ = np.asarray(occupied)
    if occ.dtype != bool:
        raise ValueError(f"occupied must be a bool array, got dtype {occ.dtype}")
    if occ.ndim < 1 or occ.size == 0:
        raise ValueError("occupied must be a non-empty array of at least one dimension")
    return np.ascontiguousarray(occ)


def _wraps(wraps, n):
    if isinstance(wraps, (bool, np.bool_)):
        return (bool(wraps),) * n
    try:
        w = tuple(bool(x) for x in wraps)
    except TypeError:
        raise ValueError(f"wraps must be a bool or one bool per axis, got {wraps!r}") from None
    if len(w) != n:
        raise ValueError(f"wraps needs one bool per axis ({n}), got {len(w)}")
    return w


def _cell(index, shape, what):
    """Flat number of a cell; a ValueError naming ``what`` if it is not a cell of the grid.

    A cell outside the grid raises :class:`~rapp.errors.InvalidCell`, a ValueError (before,
    the searches called it NoPathFound, a planning answer).
    """
    try:
        if isinstance(index, (str, bytes)):
            raise TypeError
        items = list(index)
        if any(isinstance(i, (bool, np.bool_)) for i in items):
            raise TypeError
        idx = tuple(operator.index(i) for i in items)
    except TypeError:
        raise ValueError(f"{what} must be a sequence of integer indices, got {index!r}") from None
    if len(idx) != len(shape):
        raise ValueError(f"{what} has {len(idx)} indices but the grid has {len(shape)} axes")
    if any(not 0 <= i < m for i, m in zip(idx, shape)):
        raise InvalidCell(f"{what} cell {idx} is outside the grid of shape {tuple(shape)}")
    return idx, int(np.ravel_multi_index(idx, shape))


def _neighbour_table(shape, wraps):
    """(N, 2n) flat neighbour numbers; ``N`` (one past the last cell) marks 'off the grid'."""
    size = int(np.prod(shape))
    idx = np.arange(size).reshape(shape)
    cols = []
    for axis, (m, w) in enumerate(zip(shape, wraps)):
        for step in (1, -1):
            # np.roll wraps every axis; the bounded ones get their edge cut off below.
            t = np.roll(idx, -step, axis=axis)
            if not w:
                edge = [slice(None)] * len(shape)
                edge[axis] = m - 1 if step == 1 else 0
                t[tuple(edge)] = size
            cols.append(t.ravel())
    return np.stack(cols, axis=1)


def _path_array(flat_path, shape):
    path = np.stack(np.unravel_index(np.asarray(flat_path, dtype=np.int64), shape), axis=-1)
    path.setflags(write=False)
    return path


def _as_tuples(path):
    return [tuple(int(i) for i in row) for row in path.tolist()]


# --------------------------------------------------------------------------- heuristic


def toroidal_manhattan(a, b, shape, wraps=True):
    """Toroidal Manhattan distance of GD1, vectorized.

    ``h(a, b) = sum_i min(|a_i - b_i|, M_i - |a_i - b_i|)`` on wrapping axes and
    ``|a_i - b_i|`` on bounded ones. It is the exact step count between two
    cells of an empty grid, so it never overestimates (admissible) and changes
    by at most 1 per step (consistent).

    Parameters
    ----------
    a, b : array_like of int, shape (..., n)
        Cell indices; broadcast against each other.
    shape : sequence of int
        Grid shape ``(M_1, ..., M_n)``.
    wraps : bool or sequence of bool
        Which axes wrap.

    Returns
    -------
    ndarray of int, shape (...)

    Examples
    --------
    >>> int(toroidal_manhattan([0, 0], [359, 180], (360, 360)))
    181
    >>> toroidal_manhattan([[0, 0], [1, 2]], [359, 2], (360, 360), wraps=[False, True]).tolist()
    [361, 358]
    """
    shape = tuple(int(m) for m in shape)
    w = np.asarray(_wraps(wraps, len(shape)))
    d = np.abs(np.asarray(a, dtype=np.int64) - np.asarray(b, dtype=np.int64))
    if d.shape[-1:] != (len(shape),):
        raise ValueError(f"cells must have shape (..., {len(shape)}), got {d.shape}")
    m = np.asarray(shape, dtype=np.int64)
    return np.where(w, np.minimum(d, m - d), d).sum(axis=-1)


@dataclass(frozen=True)
class HeuristicCheck:
    """Result of :func:`check_heuristic`.

    Attributes
    ----------
    consistent : bool
        ``h(u) <= 1 + h(v)`` for every pair of neighbouring free cells.
    admissible : bool
        ``h(u) <=`` true distance to the goal for every cell that reaches it.
    goal_zero : bool
        ``h(goal) == 0``.
    max_step_drop : int
        Largest ``h(u) - h(v)`` over neighbouring free cells (consistent: <= 1).
    max_overestimate : int
        Largest ``h(u) - d(u)`` over cells that reach the goal (admissible: <= 0).
    """

    consistent: bool
    admissible: bool
    goal_zero: bool
    max_step_drop: int
    max_overestimate: int


def check_heuristic(occupied, goal, *, wraps=True, heuristic_wraps=None):
    """Check GD1 exhaustively on one grid: consistency, admissibility, ``h(goal) = 0``.

    Every edge between free cells and every cell that reaches the goal is
    checked at once with numpy; the true distances come from
    :func:`bfs_distances` from the goal (the grid graph is undirected).

    Parameters
    ----------
    occupied : ndarray of bool
        The grid (``np.zeros(shape, bool)`` for an empty one).
    goal : sequence of int
        Goal cell (must be free).
    wraps : bool or sequence of bool
        Which axes wrap in the search space.
    heuristic_wraps : bool or sequence of bool, optional
        Which axes the heuristic treats as wrapping; defaults to ``wraps``.
        Pass ``False`` on a torus to see the wrap-blind heuristic fail.

    Returns
    -------
    HeuristicCheck

    Examples
    --------
    >>> free = np.zeros((8, 8), bool)
    >>> check_heuristic(free, (0, 0))
    HeuristicCheck(consistent=True, admissible=True, goal_zero=True, max_step_drop=1, max_overestimate=0)
    >>> check_heuristic(free, (0, 0), heuristic_wraps=False).admissible
    False
    """
    occ = _grid(occupied)
    shape = occ.shape
    w = _wraps(wraps, occ.ndim)
    hw = w if heuristic_wraps is None else _wraps(heuristic_wraps, occ.ndim)
    gidx, gflat = _cell(goal, shape, "goal")
    if occ[gidx]:
        raise ValueError(f"the goal cell {gidx} is blocked")
    size = occ.size
    h = np.append(heuristic_grid(shape, gidx, hw).ravel(), 0)
    free = np.append(~occ.ravel(), False)
    nb = _neighbour_table(shape, w)
    u = np.flatnonzero(free[:size])
    v = nb[u]
    edge = free[v]
    drops = (h[u][:, None] - h[v])[edge]
    max_drop = int(drops.max()) if drops.size else 0
    dist = bfs_distances(occ, gidx, wraps=w).ravel()
    reach = dist >= 0
    over = int((h[:size][reach] - dist[reach]).max())
    return HeuristicCheck(
        consistent=max_drop <= 1,
        admissible=over <= 0,
        goal_zero=bool(h[gflat] == 0),
        max_step_drop=max_drop,
        max_overestimate=over,
    )


# --------------------------------------------------------------------------- A*


@dataclass(frozen=True, eq=False)
class SearchResult:
    """What a search found, with the numbers the metrics and figures need.

    Attributes
    ----------
    path : ndarray of int, shape (k, n)
        Cells from start to goal, both included.
    cost : int
        Number of steps, ``k - 1``.
    expansions : int
        Cells expanded (taken off the open list and their neighbours generated);
        the goal is not counted.
    closed : ndarray of bool, grid shape
        The expanded cells, for figures of the search effort.
    """

    path: np.ndarray
    cost: int
    expansions: int
    closed: np.ndarray


def _prepare(occupied, start, goal, wraps):
    occ = _grid(occupied)
    w = _wraps(wraps, occ.ndim)
    sidx, s = _cell(start, occ.shape, "start")
    gidx, t = _cell(goal, occ.shape, "goal")
    if occ[sidx]:
        raise NoPathFound(f"the start cell {sidx} is blocked")
    if occ[gidx]:
        raise NoPathFound(f"the goal cell {gidx} is blocked")
    return occ, w, sidx, s, gidx, t


def _expansion_limit(max_expansions) -> int:
    """``max_expansions`` as an int, -1 for no limit; a ValueError naming it otherwise."""
    if max_expansions is None:
        return -1
    return positive_integer(max_expansions, "max_expansions", lo=0)


def astar_search(
    occupied,
    start,
    goal,
    *,
    wraps=True,
    heuristic_weight=1.0,
    max_expansions=None,
    heuristic_wraps=None,
):
    """A* on an occupancy grid with the toroidal Manhattan heuristic (TM:AStarJointSpace).

    Nodes are expanded in order of ``f = g + w h`` with ``h`` from GD1
    (:func:`toroidal_manhattan`); among equal ``f`` the node with the larger
    ``g`` goes first, which on unit-cost grids runs straight down one of the
    many equally short paths instead of widening over all of them. Tie-breaking
    never affects optimality: any order of equal ``f`` is a valid A* order.

    Guarantees. With ``w = 1`` the heuristic is admissible and consistent, so
    the path is a shortest one. With ``w > 1`` (weighted A*) the path costs at
    most ``w`` times the optimum ``C*``. Cells are never re-expanded; that
    keeps the bound because ``h`` is consistent: every expanded cell ``u`` has
    ``g(u) <= w g*(u)`` (the bound proved for ARA* by Likhachev, Gordon and
    Thrun, NIPS 2003), and the goal is returned when it is taken off the list. The tests check
    ``cost <= w C*`` against the breadth-first optimum on random grids.

    Parameters
    ----------
    occupied : ndarray of bool
        The grid of any dimension ``n``; ``True`` = blocked.
    start, goal : sequence of int
        Cells, ``n`` indices each.
    wraps : bool or sequence of bool, default True
        Which axes wrap (free joints); used for the neighbours and the heuristic.
    heuristic_weight : float, default 1.0
        ``w >= 1`` (MIS ``HEURISTIC_FACTOR``).
    max_expansions : int, optional
        Stop with :class:`~rapp.errors.NoPathFound` after this many expansions
        (MIS ``MAX_ITERATIONS``); ``None`` means no limit.
    heuristic_wraps : bool or sequence of bool, optional
        Which axes the *heuristic* treats as wrapping; defaults to ``wraps``.
        Only for teaching: on a torus ``False`` overestimates across the seam,
        and A* may then expand more cells or return a longer path.

    Returns
    -------
    SearchResult

    Raises
    ------
    ValueError
        ``start`` or ``goal`` is not ``n`` integer indices, or lies outside
        the grid (then an :class:`~rapp.errors.InvalidCell`); or another argument is invalid.
    NoPathFound
        The start or goal is blocked, the goal is unreachable, or the
        expansion limit was hit.

    Examples
    --------
    >>> grid = np.zeros((360, 360), bool)
    >>> r = astar_search(grid, (0, 0), (359, 10))
    >>> r.cost, r.path[[0, 1, -1]].tolist()
    (11, [[0, 0], [0, 1], [359, 10]])
    >>> r.expansions, int(r.closed.sum())
    (11, 11)
    """
    occ, w_ax, sidx, s, gidx, t = _prepare(occupied, start, goal, wraps)
    hw = w_ax if heuristic_wraps is None else _wraps(heuristic_wraps, occ.ndim)
    w = finite_number(heuristic_weight, "heuristic_weight", at_least=1.0)
    limit = _expansion_limit(max_expansions)
    status, flat, expansions, G = search_python.astar(occ, w_ax, hw, sidx, gidx, w, limit)
    _raise_for(status, limit, sidx, gidx)
    return SearchResult(path=G.path(flat), cost=len(flat) - 1, expansions=expansions,
                        closed=G.expanded(occ))


def _raise_for(status, limit, sidx, gidx):
    """NoPathFound for a search that ended with ``status`` 2 (the limit) or 1 (unreachable)."""
    if status == 2:
        raise NoPathFound(
            f"search stopped after the limit of {limit} expansions without reaching the goal {gidx}"
        )
    if status == 1:
        raise NoPathFound(f"the goal {gidx} cannot be reached from the start {sidx}")


def astar(occupied: ArrayLike, start: Sequence[int], goal: Sequence[int], *,
          wraps: bool | Sequence[bool] = True, heuristic_weight: float = 1.0,
          max_expansions: int | None = None) -> list[tuple[int, ...]]:
    """Shortest path on an occupancy grid by A* (TM:AStarJointSpace, MIS planPath).

    The search of :func:`astar_search` (see there for the heuristic, the
    tie-breaking and the ``cost <= w * optimum`` bound of weighted A*), compiled
    with numba (:mod:`rapp.kernels.search_numba`): the same cells expanded in the same
    order and the same path, 30-70 times faster than that Python loop on the
    benchmark grids (``benchmarks/bench_search.py``), and faster than the C++ A*
    of pyastar2d (``benchmarks/bench_astar_cpp.py``). If numba cannot be
    imported it falls back to :func:`astar_search` itself (same results,
    slower). The first call imports numba and loads the compiled kernel from
    its on-disk cache (or compiles it once, some seconds).

    Parameters
    ----------
    occupied : ndarray of bool
        The grid of any dimension ``n``; ``True`` = blocked.
    start, goal : sequence of int
        Cells, ``n`` indices each.
    wraps : bool or sequence of bool, default True
        Which axes wrap.
    heuristic_weight : float, default 1.0
        ``w >= 1``; the path costs at most ``w`` times the optimum.
    max_expansions : int, optional
        Expansion limit; ``None`` means no limit.

    Returns
    -------
    list of tuple of int
        Cells from start to goal, both included.

    Raises
    ------
    ValueError
        ``start`` or ``goal`` malformed or outside the grid (see :func:`astar_search`).
    NoPathFound
        Start or goal blocked, goal unreachable, or the expansion limit hit.

    Examples
    --------
    >>> grid = np.zeros((4, 4), bool)
    >>> astar(grid, (0, 0), (3, 0))
    [(0, 0), (3, 0)]
    >>> astar(grid, (0, 0), (3, 0), wraps=False)
    [(0, 0), (1, 0), (2, 0), (3, 0)]
    >>> astar(grid, (0, 4), (3, 0))
    Traceback (most recent call last):
    ...
    rapp.errors.InvalidCell: start cell (0, 4) is outside the grid of shape (4, 4)
    """
    occ, w_ax, sidx, _, gidx, _ = _prepare(occupied, start, goal, wraps)
    w = finite_number(heuristic_weight, "heuristic_weight", at_least=1.0)
    limit = _expansion_limit(max_expansions)
    status, cells = search_backend.astar_path(occ, w_ax, sidx, gidx, w, limit)
    _raise_for(status, limit, sidx, gidx)
    return cells


# --------------------------------------------------------------------------- BFS oracle


def bfs_distances(occupied: ArrayLike, start: Sequence[int],
                  wraps: bool | Sequence[bool] = True) -> np.ndarray:
    """Step distance from ``start`` to every cell, by breadth-first search.

    The frontier of each level is expanded at once with numpy, so the cost is
    one numpy pass per distance level over the frontier only.

    Parameters
    ----------
    occupied : ndarray of bool
        The grid; ``True`` = blocked.
    start : sequence of int
        The source cell.
    wraps : bool or sequence of bool, default True
        Which axes wrap.

    Returns
    -------
    ndarray of int, grid shape
        Distances; ``-1`` for blocked and unreachable cells (all ``-1`` when the
        start itself is blocked).

    Raises
    ------
    ValueError
        ``start`` is not ``n`` integer indices or lies outside the grid.

    Examples
    --------
    >>> bfs_distances(np.zeros(6, bool), [0]).tolist()
    [0, 1, 2, 3, 2, 1]
    >>> bfs_distances(np.array([False, False, True, False]), [0], wraps=False).tolist()
    [0, 1, -1, -1]
    """
    occ = _grid(occupied)
    w = _wraps(wraps, occ.ndim)
    sidx, s = _cell(start, occ.shape, "start")
    size = occ.size
    dist = np.full(size + 1, -1, dtype=np.int64)
    if not occ[sidx]:
        nb = _neighbour_table(occ.shape, w)
        seen = np.append(occ.ravel(), True)  # blocked and off-grid count as seen
        seen[s] = True
        dist[s] = 0
        frontier = np.array([s])
        level = 0
        while frontier.size:
            level += 1
            cand = nb[frontier].ravel()
            cand = sorted_unique(cand[~seen[cand]])  # np.unique would import numpy.ma
            seen[cand] = True
            dist[cand] = level
            frontier = cand
    return dist[:size].reshape(occ.shape)


def bfs(occupied, start, goal, *, wraps=True):
    """A shortest path by breadth-first search: the optimal oracle for A*.

    Parameters
    ----------
    occupied : ndarray of bool
        The grid; ``True`` = blocked.
    start, goal : sequence of int
        Cells.
    wraps : bool or sequence of bool, default True
        Which axes wrap.

    Returns
    -------
    list of tuple of int
        Cells from start to goal, both included.

    Raises
    ------
    ValueError
        ``start`` or ``goal`` malformed or outside the grid (see :func:`astar_search`).
    NoPathFound
        Start or goal blocked, or goal unreachable.

    Examples
    --------
    >>> grid = np.zeros((3, 3), bool)
    >>> grid[1, :2] = True
    >>> bfs(grid, (0, 0), (2, 0), wraps=False)
    [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (2, 1), (2, 0)]
    >>> bfs(grid, (0, 0), (2, 0))
    [(0, 0), (2, 0)]
    """
    occ, w, sidx, s, gidx, t = _prepare(occupied, start, goal, wraps)
    dist = bfs_distances(occ, gidx, wraps=w).ravel()  # undirected grid: from goal = to goal
    if dist[s] < 0:
        raise NoPathFound(f"the goal {gidx} cannot be reached from the start {sidx}")
    nb = _neighbour_table(occ.shape, w)
    dist = np.append(dist, -1)
    flat = [s]
    # Walk downhill in distance-to-goal: one step per loop, the path length.
    while flat[-1] != t:
        row = nb[flat[-1]]
        flat.append(int(row[np.argmax(dist[row] == dist[flat[-1]] - 1)]))
    return _as_tuples(_path_array(flat, occ.shape))


# --------------------------------------------------------------------------- greedy best-first


def greedy_best_first(occupied, start, goal, *, wraps=True, heuristic_wraps=None):
    """Greedy best-first search: always expand the cell with the smallest ``h``.

    Kept ONLY to show in the book why it is not a shortest-path method: it
    ignores the cost already paid (``g``), so it follows the heuristic into
    dead ends and keeps the first, often roundabout, route it finds. With a
    heuristic that ignores the wrap (``heuristic_wraps=False`` on a torus), it
    even walks the long way round.

    Parameters
    ----------
    occupied : ndarray of bool
        The grid; ``True`` = blocked.
    start, goal : sequence of int
        Cells.
    wraps : bool or sequence of bool, default True
        Which axes wrap in the search space.
    heuristic_wraps : bool or sequence of bool, optional
        Which axes the heuristic treats as wrapping; defaults to ``wraps``.

    Returns
    -------
    list of tuple of int
        A path from start to goal (not necessarily a shortest one).

    Raises
    ------
    ValueError
        ``start`` or ``goal`` malformed or outside the grid (see :func:`astar_search`).
    NoPathFound
        Start or goal blocked, or goal unreachable.

    Examples
    --------
    >>> ring = np.zeros(20, bool)
    >>> len(greedy_best_first(ring, [2], [17], heuristic_wraps=False)) - 1
    15
    >>> len(astar(ring, [2], [17])) - 1
    5
    """
    occ, w, sidx, s, gidx, t = _prepare(occupied, start, goal, wraps)
    hw = w if heuristic_wraps is None else _wraps(heuristic_wraps, occ.ndim)
    G = PaddedGraph(occ, w)
    size, closed, red, offs = G.size, G.closed, G.red, G.offsets
    h = G.padded(heuristic_grid(occ.shape, gidx, hw)).tolist()
    s, t = G.flat(sidx), G.flat(gidx)
    parent = {s: s}
    heap = [h[s] * size + s]
    while heap:
        u = heapq.heappop(heap) % size
        if u == t:
            break
        if closed[u]:
            continue
        closed[u] = 1
        for d in offs:
            v = red[u + d]
            if closed[v] or v in parent:
                continue
            parent[v] = u
            heapq.heappush(heap, h[v] * size + v)
    else:
        raise NoPathFound(f"the goal {gidx} cannot be reached from the start {sidx}")
    flat = [t]
    while flat[-1] != s:
        flat.append(parent[flat[-1]])
    return _as_tuples(G.path(flat[::-1]))


# --------------------------------------------------------------------------- A*, step by step


@dataclass(frozen=True, eq=False)
class AStarTrace:
    """What :func:`astar_steps` records: the search, one snapshot per expansion.

    Snapshot ``k`` (``0 <= k < expansions``) is the state right after the
    ``k``-th cell was taken off the open list, closed and its neighbours
    relaxed.

    Attributes
    ----------
    occupied : ndarray of bool
        The grid searched.
    start, goal : tuple of int
    wraps : tuple of bool
        Which axes wrap.
    h : ndarray of float, grid shape
        The heuristic used (GD1, times the weight).
    current : ndarray of int, shape (expansions, n)
        The cell expanded at each step.
    closed : ndarray of bool, shape (expansions,) + grid shape
        The closed set after each step; it grows by exactly the current cell.
    frontier : ndarray of bool, shape (expansions,) + grid shape
        The open list after each step: cells reached but not yet closed.
    g : ndarray of int, shape (expansions,) + grid shape
        Cost so far after each step, ``-1`` where no path is known yet.
    parent : ndarray of int, shape (expansions,) + grid shape + (n,)
        The parent map after each step, ``-1`` where a cell has no parent.
    relaxed : tuple of tuple of tuple of int
        Per step, the neighbours whose ``g`` dropped (pushed onto the open list).
    path : ndarray of int, shape (cost + 1, n)
        The path reconstructed from the final parent map, start to goal.
    cost : int
    expansions : int
    """

    occupied: np.ndarray
    start: tuple
    goal: tuple
    wraps: tuple
    h: np.ndarray
    current: np.ndarray
    closed: np.ndarray
    frontier: np.ndarray
    g: np.ndarray
    parent: np.ndarray
    relaxed: tuple
    path: np.ndarray
    cost: int
    expansions: int

    def chain(self, k):
        """Cells from the start to the cell expanded at step ``k``, along the parent map."""
        cells = [tuple(int(i) for i in self.current[k])]
        parent = self.parent[k]
        while cells[-1] != self.start:
            cells.append(tuple(int(i) for i in parent[cells[-1]]))
        return np.array(cells[::-1], dtype=np.int64).reshape(-1, len(self.start))


def astar_steps(occupied, start, goal, *, wraps=True, heuristic_weight=1.0):
    """Run A* as :func:`astar_search` does and record every expansion.

    The same loop in the same order: heap entries ``(f, -g, cell)`` (lowest
    ``f`` first, ties to the larger ``g``, then to the smaller cell), a closed
    set, a parent map, lazy deletion of stale heap entries, the goal accepted
    when it is taken off the heap, the path reconstructed by following parents
    back from the goal. It expands the same cells as :func:`astar_search` and
    returns the same cost. Meant for small grids and figures: each snapshot
    holds copies of the grid-sized arrays (about ``10 + 8 n`` bytes per cell
    per expansion).

    Parameters
    ----------
    occupied : ndarray of bool
        The grid of any dimension ``n``; ``True`` = blocked.
    start, goal : sequence of int
        Cells, ``n`` indices each.
    wraps : bool or sequence of bool, default True
        Which axes wrap (for the neighbours and the heuristic).
    heuristic_weight : float, default 1.0
        ``w >= 1``: ``f = g + w h`` (weighted A*).

    Returns
    -------
    AStarTrace

    Raises
    ------
    ValueError
        ``start`` or ``goal`` malformed or outside the grid (see :func:`astar_search`).
    NoPathFound
        Start or goal blocked, or goal unreachable.

    Examples
    --------
    A ring of 8 cells: from 1 to 6 the short way crosses the seam (1, 0, 7, 6).

    >>> t = astar_steps(np.zeros(8, bool), [1], [6])
    >>> t.cost, t.path.ravel().tolist()
    (3, [1, 0, 7, 6])
    >>> t.current.ravel().tolist()          # expanded in this order; the goal is not expanded
    [1, 0, 7]
    >>> t.closed.sum(axis=1).tolist()       # the closed set grows by one per step
    [1, 2, 3]
    >>> np.flatnonzero(t.frontier[0]).tolist(), t.g[0].tolist()
    ([0, 2], [1, 0, 1, -1, -1, -1, -1, -1])
    >>> t.expansions == astar_search(np.zeros(8, bool), [1], [6]).expansions
    True
    """
    occ, w_ax, sidx, _, gidx, _ = _prepare(occupied, start, goal, wraps)
    w = finite_number(heuristic_weight, "heuristic_weight", at_least=1.0)
    n = occ.ndim
    G = PaddedGraph(occ, w_ax)
    size, closed, red, offs = G.size, G.closed, G.red, G.offsets
    h = heuristic_grid(occ.shape, gidx, w_ax) * w
    wh = G.padded(h).tolist()
    s, t = G.flat(sidx), G.flat(gidx)
    # Padded flat number -> cell of the real grid (pad cells are never reached).
    cell_of = G.path(np.arange(size))
    g = [size + 1] * size
    g[s] = 0
    parent = {}
    reached = {s}
    heap = [(wh[s], 0, s)]
    snaps = {"current": [], "closed": [], "frontier": [], "g": [], "parent": []}
    relaxed = []
    done = set()
    found = s == t
    while heap and not found:
        u = heapq.heappop(heap)[2]
        if closed[u]:
            continue
        if u == t:
            found = True
            break
        closed[u] = 1
        done.add(u)
        gv = g[u] + 1
        pushed = []
        for d in offs:
            v = red[u + d]
            if closed[v] or gv >= g[v]:
                continue
            g[v] = gv
            parent[v] = u
            reached.add(v)
            pushed.append(tuple(int(i) for i in cell_of[v]))
            heapq.heappush(heap, (gv + wh[v], -gv, v))
        # Snapshot: the state after line "relax the neighbours" of this expansion.
        gk = np.full(occ.shape, -1, dtype=np.int64)
        pk = np.full(occ.shape + (n,), -1, dtype=np.int64)
        for v in reached:
            c = tuple(cell_of[v])
            gk[c] = g[v]
            if v in parent:
                pk[c] = cell_of[parent[v]]
        ck = np.zeros(occ.shape, dtype=bool)
        ck[tuple(cell_of[sorted(done)].T)] = True
        snaps["current"].append(cell_of[u])
        snaps["closed"].append(ck)
        snaps["frontier"].append((gk >= 0) & ~ck)
        snaps["g"].append(gk)
        snaps["parent"].append(pk)
        relaxed.append(tuple(pushed))
    if not found:
        raise NoPathFound(f"the goal {gidx} cannot be reached from the start {sidx}")
    flat = [t]
    while flat[-1] != s:
        flat.append(parent[flat[-1]])
    k = len(relaxed)

    def stack(name, shape, dtype):
        a = np.array(snaps[name], dtype=dtype).reshape((k,) + shape)
        a.setflags(write=False)
        return a

    path = G.path(flat[::-1])
    return AStarTrace(
        occupied=occ, start=sidx, goal=gidx, wraps=w_ax, h=h,
        current=stack("current", (n,), np.int64),
        closed=stack("closed", occ.shape, bool),
        frontier=stack("frontier", occ.shape, bool),
        g=stack("g", occ.shape, np.int64),
        parent=stack("parent", occ.shape + (n,), np.int64),
        relaxed=tuple(relaxed), path=path, cost=len(flat) - 1, expansions=k,
    )
