"""A* on the joint grid, joined to the exact start and goal, every move certified.

The grid marks cell *centres*, so a path of free cells is not yet a
collision-free motion. :func:`grid_route` makes it one:

1. **anchors** -- the exact start and each goal configuration are joined to a
   free cell nearby by a certified straight segment (:func:`anchor_cell`);
2. **which goal** -- one breadth-first search from the start cell gives the
   reachable goal nearest in grid steps, or proves that none is reachable;
3. **search** -- A* finds the path to it, first on the *certified cells*
   (:func:`rapp.cspace.certified_free`: every move from them is free, so no
   move needs checking); if those hold no path, on the plain occupancy with
   each new move checked by the continuous certified test, a failing move
   blocking its cell before the search is repeated.

References
----------
SRS of 2D-RAPP (seed 000): IM1, the search step; GS2.
Hart, Nilsson & Raphael (1968), A formal basis for the heuristic determination of minimum cost paths.
"""

from __future__ import annotations

import time
from itertools import product

import numpy as np

from rapp.arm import Arm
from rapp.collision import motion_bounds, segment_collision_free
from rapp.cspace import JointGrid, certified_free, occupancy
from rapp.errors import GridTooCoarse, NoPathFound
from rapp.obstacles import Circle
from rapp.paths import PlannerResult, path_length, unwrap_near, unwrap_path
from rapp.search import astar_search, bfs_distances

__all__ = ["anchor_cell", "grid_route", "grid_step_motion", "obstacle_size"]


def anchor_cell(arm: Arm, obstacles, grid: JointGrid, blocked, q) -> np.ndarray | None:
    """A free grid cell joined to the exact configuration ``q`` by a certified segment, or None.

    Candidates: the nearest cell, its axis neighbours and (for n <= 8) the
    corners of the grid box around ``q``; the nearest certified one wins.

    Examples
    --------
    >>> from rapp import Circle
    >>> arm = Arm([1.0, 1.0])
    >>> grid = JointGrid(arm, 8)
    >>> anchor_cell(arm, [], grid, np.zeros(grid.shape, bool), [0.1, 0.0]).tolist()
    [4, 4]
    """
    n = arm.n
    m = np.array(grid.shape)
    wr = np.array(grid.wraps)
    near = grid.index(q)
    eye = np.eye(n, dtype=int)
    cands = [near, *(near + eye), *(near - eye)]
    if n <= 8:
        floor = np.floor(grid.fractional_index(q)).astype(int)
        cands += [floor + np.array(c) for c in product((0, 1), repeat=n)]
    c = np.array(cands)
    c = np.where(wr, c % m, c)
    c = c[np.all((c >= 0) & (c < m), axis=1)]
    # The distinct rows in lexicographic order, as np.unique(c, axis=0) gives them (which
    # imports numpy.ma, a fifth of the command line's start-up).
    c = c[np.lexsort(c.T[::-1])]
    c = c[np.r_[True, (c[1:] != c[:-1]).any(axis=1)]] if len(c) else c
    c = c[~blocked[tuple(c.T)]]
    if len(c) == 0:
        return None
    centres = unwrap_near(arm, grid.angles(c), q)
    ok = segment_collision_free(arm, q, centres, obstacles)
    if not ok.any():
        return None
    c, centres = c[ok], centres[ok]
    return c[np.argmin(np.linalg.norm(centres - q, axis=1))]


def _anchors(arm, obstacles, grid, blocked, start, goal_qs):
    """Start cell, goal cells (g', n) and the goal configurations that could be anchored."""
    shape_txt = "x".join(map(str, grid.shape))
    s_cell = anchor_cell(arm, obstacles, grid, blocked, start)
    if s_cell is None:
        raise GridTooCoarse(
            "no free grid cell next to the start can be joined to it by a collision-free "
            f"segment on the {shape_txt} grid; try more planner.cells")
    anchors = [(anchor_cell(arm, obstacles, grid, blocked, g), g) for g in goal_qs]
    anchors = [(a, g) for a, g in anchors if a is not None]
    if not anchors:
        raise GridTooCoarse(
            "no free grid cell next to the goal can be joined to it by a collision-free "
            f"segment on the {shape_txt} grid; try more planner.cells")
    return s_cell, np.array([a for a, _ in anchors]), np.array([g for _, g in anchors], float)


def obstacle_size(obstacle) -> float:
    """Half the thickness of an obstacle: its radius, or half a convex polygon's smallest width.

    Examples
    --------
    >>> from rapp import Circle, Polygon
    >>> obstacle_size(Circle((0, 0), 0.3)), obstacle_size(Polygon.rectangle((0, 0), 2.0, 0.5))
    (0.3, 0.25)
    """
    if isinstance(obstacle, Circle):
        return float(obstacle.radius)
    v = obstacle.array
    e = np.roll(v, -1, axis=0) - v
    normals = np.stack((e[:, 1], -e[:, 0]), axis=-1) / np.linalg.norm(e, axis=1)[:, None]
    proj = v @ normals.T
    return 0.5 * float((proj.max(axis=0) - proj.min(axis=0)).min())


def grid_step_motion(arm: Arm, grid: JointGrid) -> float:
    """How far one step of ``grid`` along any axis can move a point of the arm (m).

    Examples
    --------
    >>> round(grid_step_motion(Arm([1.0, 1.0]), JointGrid(Arm([1.0, 1.0]), 4)), 4)
    3.1416
    """
    return float(motion_bounds(arm, np.diag(grid.step)).max())


def _nearest_reachable_goal(grid, blocked, s_cell, g_cells, coarse: bool, why: str = ""):
    """Index of the goal cell nearest the start in grid steps, and that number of steps.

    Raises NoPathFound (GridTooCoarse when ``coarse``) with the proof attached
    (``start_cell``, ``goal_cells``) when no goal cell is reachable.
    """
    dist = bfs_distances(blocked, tuple(s_cell), grid.wraps)
    d_goal = dist[tuple(g_cells.T)]
    if not np.any(d_goal >= 0):
        shape_txt = "x".join(map(str, grid.shape))
        msg = (f"no collision-free path: the {shape_txt} grid holds no path from the "
               f"start to any of the {len(g_cells)} goal configuration(s) "
               f"({int((dist >= 0).sum())} cells are reachable)")
        err = GridTooCoarse(msg + why) if coarse else NoPathFound(msg)
        # What was searched, so that a test can re-check the proof independently.
        err.start_cell, err.goal_cells = tuple(int(i) for i in s_cell), g_cells.copy()
        raise err
    best = int(np.argmin(np.where(d_goal >= 0, d_goal, np.iinfo(np.int64).max)))
    return best, int(d_goal[best])


def _failed_moves(arm, obstacles, grid, cells, full, certified_keys):
    """Check the grid moves of ``cells`` not certified before; return (failing move indices, keys).

    Segments 0 and -1 of ``full`` join the exact start and goal to their
    anchors (certified by :func:`anchor_cell`); grid move ``i`` is segment ``i + 1``.
    """
    size = int(np.prod(grid.shape))
    flat = np.ravel_multi_index(tuple(cells.T), grid.shape)
    keys = np.minimum(flat[:-1], flat[1:]) * size + np.maximum(flat[:-1], flat[1:])
    todo = np.flatnonzero(~np.isin(keys, certified_keys))
    ok = np.ones(len(keys), bool)
    if todo.size:
        ok[todo] = segment_collision_free(arm, full[todo + 1], full[todo + 2], obstacles)
        certified_keys = np.union1d(certified_keys, keys[todo[ok[todo]]])
    return np.flatnonzero(~ok), certified_keys


def _route_on(arm, obstacles, grid, blocked, start, goal_qs, *, certified: bool,
              heuristic_weight: float, max_expansions):
    """Search ``blocked`` from the exact start to the nearest reachable goal.

    Returns (full unwrapped path, metrics, closed set of the last search) or raises
    NoPathFound / GridTooCoarse.
    With ``certified`` the grid moves are known to be free; otherwise each new
    move is checked and a failing one blocks its cell and the search repeats.
    """
    s_cell, g_cells, g_qs = _anchors(arm, obstacles, grid, blocked, start, goal_qs)
    # The grid tests cell centres only, so its "no path" is a proof about the scene only when
    # one step moves the arm less than the thinnest obstacle is thick: then no obstacle can
    # lie between the centres of two neighbouring cells unseen.
    motion = grid_step_motion(arm, grid)
    thinnest = min((obstacle_size(ob) for ob in obstacles), default=np.inf)
    resolves = motion <= thinnest
    why = "" if resolves else (
        f"; one step of this grid moves the arm up to {motion:.3g} m, more than the thinnest "
        f"obstacle's half-thickness {thinnest:.3g} m, so a finer grid (planner.cells) may find one")
    work = blocked.copy()
    repairs = expansions = 0
    certified_keys = np.zeros(0, np.int64)
    best = None
    while True:
        if best is None:
            best, bfs_optimum = _nearest_reachable_goal(
                grid, work, s_cell, g_cells, coarse=bool(repairs or certified or not resolves),
                why=why)
        try:
            res = astar_search(work, tuple(s_cell), tuple(g_cells[best]), wraps=grid.wraps,
                               heuristic_weight=heuristic_weight, max_expansions=max_expansions)
        except NoPathFound:
            if repairs == 0 or max_expansions is not None:
                raise
            best = None  # blocking cut this goal off: let BFS choose again
            continue
        expansions += res.expansions
        cells = np.asarray(res.path)
        full = unwrap_path(arm, np.vstack([start, grid.angles(cells), g_qs[best]]))
        if certified:
            break
        bad, certified_keys = _failed_moves(arm, obstacles, grid, cells, full, certified_keys)
        if bad.size == 0:
            break
        # Block the cell a failing move enters (or leaves, if it enters the goal anchor).
        entered, left = cells[bad + 1], cells[bad]
        is_goal = np.all(entered == g_cells[best], axis=1)
        block = np.where(is_goal[:, None], left, entered)
        block = block[~np.all(block == s_cell, axis=1)]
        if block.size == 0:
            raise GridTooCoarse("the move between the start and goal cells cannot be certified "
                                "collision-free; try more planner.cells")
        work[tuple(block.T)] = True
        repairs += 1
    metrics = {
        "expansions": int(res.expansions),
        "expansions_total": int(expansions),
        "path_cells": int(len(cells) - 1),
        "bfs_optimum_cells": bfs_optimum,
        "certification_repairs": int(repairs),
        "goal_candidates": int(len(g_cells)),
    }
    return full, metrics, res.closed


def grid_route(arm: Arm, start, goal, obstacles=(), *, cells, heuristic_weight: float = 1.0,
               max_expansions=None, raise_on_failure: bool = True) -> PlannerResult:
    """A certified polyline from ``start`` to the nearest reachable of ``goal``, by A* on a grid.

    A* runs first on the certified cells (no move needs checking); if they
    hold no path, on the plain occupancy with each move checked, which also
    proves "no path" on that grid.

    Parameters
    ----------
    arm : Arm
    start : (n,) array_like
    goal : (n,) or (g, n) array_like
        Goal configuration(s), e.g. every free IK solution of a Cartesian goal.
    obstacles : iterable of Circle and Polygon
    cells : int or sequence of int
        Cells per joint of the :class:`~rapp.cspace.JointGrid`.
    heuristic_weight, max_expansions
        Passed to :func:`rapp.search.astar_search`.
    raise_on_failure : bool
        Raise :class:`~rapp.errors.NoPathFound` (default) or return ``success=False``.

    Returns
    -------
    PlannerResult
        ``path`` the certified polyline; its details ``grid``, ``occupancy``, ``expanded`` (the
        cells A* closed), ``metrics`` and ``times`` (``cspace``, ``search``).

    Raises
    ------
    NoPathFound
        The grid holds no path (proved by breadth-first search).
    GridTooCoarse
        The grid has a path, but it cannot be certified at this resolution.

    Examples
    --------
    >>> from rapp import Circle
    >>> r = grid_route(Arm([1.0, 1.0]), [0.0, 0.0], [[2.0, 0.0]], [Circle((1.5, 0.5), 0.3)], cells=32)
    >>> r.waypoints[0].tolist(), r.metrics["search_grid"]
    ([0.0, 0.0], 'certified cells')
    >>> r.goal_q.round(4).tolist()          # unwrapped: the way round clear of the disc
    [-4.2832, 0.0]
    """
    try:
        return _grid_route(arm, obstacles, start, goal, cells, heuristic_weight, max_expansions)
    except NoPathFound:
        if raise_on_failure:
            raise
        return PlannerResult(np.empty((0, arm.n)), False, float("inf"), {})


def _grid_route(arm, obstacles, start, goal, cells, heuristic_weight, max_expansions):
    start = arm.check_q(start, "start")
    goal_qs = arm.check_q(np.atleast_2d(goal), "goal")
    obstacles = list(obstacles)
    t0 = time.perf_counter()
    grid = JointGrid(arm, cells)
    occ = occupancy(arm, obstacles, grid)
    safe = certified_free(arm, obstacles, grid) if obstacles else ~occ
    t1 = time.perf_counter()
    kw = {"heuristic_weight": heuristic_weight, "max_expansions": max_expansions}
    try:
        full, metrics, closed = _route_on(arm, obstacles, grid, ~safe, start, goal_qs, certified=True,
                                          **kw)
        metrics["search_grid"] = "certified cells"
    except GridTooCoarse:
        full, metrics, closed = _route_on(arm, obstacles, grid, occ, start, goal_qs, certified=False,
                                          **kw)
        metrics["search_grid"] = "occupancy, moves checked"
    times = {"cspace": t1 - t0, "search": time.perf_counter() - t1}
    metrics.update({"grid_cells": int(occ.size), "free_fraction": float(1.0 - occ.mean()),
                    "certified_fraction": float(safe.mean())})
    return PlannerResult(full, True, path_length(full), {
        "grid": grid, "occupancy": occ, "expanded": closed, "metrics": metrics, "times": times})
