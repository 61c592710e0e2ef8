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
from rapp.collision import motion_bounds, pair_bounds, scene, segment_collision_free, self_gaps
from rapp.cspace import JointGrid, certified_free, grid_q, occupancy
from rapp.errors import GridTooCoarse, NoPathFound
from rapp.obstacles import Circle
from rapp.paths import (GRID_TOO_COARSE, ITERATION_CAP, NO_PATH, PlannerResult, path_length,
                        unwrap_near, unwrap_path)
from rapp.search import astar_search, bfs_distances
from rapp.validity import DEFAULT_RESOLUTION, ValidityFunction, mark_sampled, user_validity

__all__ = ["default_cells", "edge_test", "anchor_cell", "grid_route", "grid_step_motion", "obstacle_size",
           "self_collision_cells"]


def edge_test(arm: Arm, obstacles, checker=None):
    """The test of a straight move ``(a, b) -> (m,) bool`` (``a``, ``b`` broadcast): certified
    free of ``obstacles`` (:func:`rapp.collision.segment_collision_free`), and with a user's
    ``checker`` (:class:`rapp.validity.UserValidity`) also allowed by it at every sample.

    Examples
    --------
    >>> from rapp.validity import UserValidity
    >>> free = edge_test(Arm([1.0, 1.0]), [], UserValidity(lambda q: q[:, 0] < 0.5, 0.1))
    >>> free([0.0, 0.0], [[0.4, 0.0], [0.6, 0.0]]).tolist()
    [True, False]
    """
    def free(a, b):
        a, b = np.broadcast_arrays(np.atleast_2d(np.asarray(a, float)),
                                   np.atleast_2d(np.asarray(b, float)))
        ok = np.array(segment_collision_free(arm, a, b, obstacles), dtype=bool).reshape(-1)
        if checker is not None and ok.any():
            ok[ok] = checker.edges(a[ok], b[ok], arm)
        return ok
    return free


def anchor_cell(arm: Arm, obstacles, grid: JointGrid, blocked, q, *, free=None) -> np.ndarray | None:
    """A free grid cell joined to the exact configuration ``q`` by a certified segment, or None.

    Candidates: the nearest cell, its axis neighbours and (for n <= 8) the
    corners of the grid box around ``q``; the nearest certified one wins. ``free``, the
    move test (:func:`edge_test`; by default certified against ``obstacles``), decides.

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
    ok = (segment_collision_free(arm, q, centres, obstacles) if free is None
          else free(q, centres))
    if not ok.any():
        return None
    c, centres = c[ok], centres[ok]
    return c[np.argmin(np.linalg.norm(centres - q, axis=1))]


def _anchors(arm, obstacles, grid, blocked, start, goal_qs, free=None):
    """Start cell, goal cells (g', n) and the goal configurations that could be anchored."""
    shape_txt = "x".join(map(str, grid.shape))
    s_cell = anchor_cell(arm, obstacles, grid, blocked, start, free=free)
    if s_cell is None:
        raise GridTooCoarse(
            "no free grid cell next to the start can be joined to it by a collision-free "
            f"segment on the {shape_txt} grid; try more planner.cells")
    anchors = [(anchor_cell(arm, obstacles, grid, blocked, g, free=free), g) for g in goal_qs]
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


def _failed_moves(arm, obstacles, grid, cells, full, certified_keys, free=None):
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
        ok[todo] = (segment_collision_free(arm, full[todo + 1], full[todo + 2], obstacles)
                    if free is None else free(full[todo + 1], full[todo + 2]))
        certified_keys = np.union1d(certified_keys, keys[todo[ok[todo]]])
    return np.flatnonzero(~ok), certified_keys


def _route_on(arm, obstacles, grid, blocked, start, goal_qs, *, certified: bool,
              heuristic_weight: float, max_expansions, free=None):
    """Search ``blocked`` from the exact start to the nearest reachable goal.

    Returns (full unwrapped path, metrics, closed set of the last search) or raises
    NoPathFound / GridTooCoarse.
    With ``certified`` the grid moves are known to be free; otherwise each new
    move is checked and a failing one blocks its cell and the search repeats.
    """
    s_cell, g_cells, g_qs = _anchors(arm, obstacles, grid, blocked, start, goal_qs, free)
    # The grid tests cell centres only, so its "no path" is a proof about the scene only when
    # one step moves the arm less than the thinnest obstacle is thick: then no obstacle can
    # lie between the centres of two neighbouring cells unseen.
    motion = grid_step_motion(arm, grid)
    thinnest = min((obstacle_size(ob) for ob in obstacles), default=np.inf)
    resolves = motion <= thinnest and free is None
    why = "" if resolves else (
        f"; one step of this grid moves the arm up to {motion:.3g} m, more than the thinnest "
        f"obstacle's half-thickness {thinnest:.3g} m, so a finer grid (planner.cells) may find one"
        if free is None else "; the user's validity checker is sampled at the cell centres and "
        "along the moves, which proves nothing between them, so a finer grid may find one")
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
        bad, certified_keys = _failed_moves(arm, obstacles, grid, cells, full, certified_keys, free)
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


def default_cells(n: int) -> int:
    """Default cells per joint: 100 for up to 2 joints, else about 2 million cells in all.

    Examples
    --------
    >>> default_cells(2), default_cells(3), default_cells(6)
    (100, 126, 11)
    """
    return 100 if n <= 2 else max(8, int(round(2e6 ** (1.0 / n))))


def grid_route(arm: Arm, start, goal, obstacles=(), *, cells=None, heuristic_weight: float = 1.0,
               max_expansions=None, raise_on_failure: bool = True,
               margin: float = 0.0, validity: ValidityFunction | None = None,
               validity_resolution: float = DEFAULT_RESOLUTION) -> PlannerResult:
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
    cells : int or sequence of int, optional
        Cells per joint of the :class:`~rapp.cspace.JointGrid`; by default
        :func:`default_cells` for the arm's number of joints (as a scenario file's default).
    heuristic_weight, max_expansions
        Passed to :func:`rapp.search.astar_search`.
    raise_on_failure : bool
        Raise :class:`~rapp.errors.NoPathFound` (default) or return ``success=False``.
    margin : float
        Safety margin (metres, >= 0) every link keeps beyond its radius
        (``arm.link_radius``) from every obstacle (:func:`rapp.collision.scene`).
    validity : callable, optional
        A user's checker, ``(m, n)`` configurations -> ``m`` booleans (True: allowed), on top
        of rapp's obstacles (:mod:`rapp.validity`): a cell is blocked when it rejects the
        cell's centre (one call for the whole grid), and every move of the path, the anchors'
        included, is sampled at ``validity_resolution`` (a failing move blocks its cell and the
        search repeats). A "no path" is then no proof (``grid too coarse``), and the result
        says its path was sampled (``certified`` False, ``checked_by``).
    validity_resolution : float
        Largest joint-space step (rad) between two samples of a move for ``validity``.

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
    checker = user_validity(validity, validity_resolution)
    try:
        return mark_sampled(_grid_route(arm, obstacles, start, goal, cells, heuristic_weight,
                                        max_expansions, margin, checker), checker)
    except NoPathFound as err:
        if raise_on_failure:
            raise
        status = (GRID_TOO_COARSE if isinstance(err, GridTooCoarse) else ITERATION_CAP
                  if "limit of" in str(err) and max_expansions is not None else NO_PATH)
        return mark_sampled(PlannerResult(np.empty((0, arm.n)), False, float("inf"), {}, status),
                            checker)


def self_collision_cells(arm: Arm, grid: JointGrid, *, margin: float = 0.0,
                         chunk: int = 1 << 16) -> tuple:
    """``(occupied, certified)``: the grid's cells painted for self-collision, bool ``grid.shape``.

    Self-collision has no closed-form occupancy here, so each cell is tested at its
    configuration (:func:`rapp.collision.self_gaps`, ``occupied`` where a non-adjacent pair
    is within its distance) and certified as :func:`rapp.cspace.certified_free` certifies
    obstacles: every pair's gap at the cell exceeds half the most its distance changes in one
    grid step along any axis (:func:`rapp.collision.pair_bounds`), so a move between two
    certified axis neighbours keeps every pair apart (each half within its end's gap). Work in chunks of ``chunk`` cells.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0, 1.0], link_radius=0.05, self_collision=True)
    >>> occ, safe = self_collision_cells(arm, JointGrid(arm, 16))
    >>> bool(occ.any()), bool((safe & occ).any()), bool(safe.sum() < (~occ).sum())
    (True, False, True)
    """
    q = grid_q(grid).reshape(-1, arm.n)
    need = 0.5 * pair_bounds(arm, np.diag(grid.step)).max(axis=0)  # (P,)
    occ = np.empty(q.shape[0], bool)
    safe = np.empty(q.shape[0], bool)
    for k in range(0, q.shape[0], chunk):
        g = self_gaps(arm, q[k:k + chunk], margin=margin)
        occ[k:k + chunk] = (g <= 0).any(axis=-1)
        safe[k:k + chunk] = (g > need).all(axis=-1)
    return occ.reshape(grid.shape), safe.reshape(grid.shape)


def _grid_route(arm, obstacles, start, goal, cells, heuristic_weight, max_expansions, margin,
                checker=None):
    if cells is None:
        cells = default_cells(arm.n)
    start = arm.check_q(start, "start")
    goal_qs = arm.check_q(np.atleast_2d(goal), "goal")
    if checker is not None:
        if not checker.points(start, arm)[0]:
            raise NoPathFound("the start configuration is rejected by validity")
        goal_qs = goal_qs[checker.points(goal_qs, arm)]
        if len(goal_qs) == 0:
            raise NoPathFound("every goal configuration is rejected by validity")
    obstacles = list(obstacles)
    t0 = time.perf_counter()
    grid = JointGrid(arm, cells)
    occ = occupancy(arm, obstacles, grid, margin=margin)
    safe = certified_free(arm, obstacles, grid, margin=margin) if obstacles else ~occ
    if arm.self_collision and arm.n >= 3:
        # Painted cell by cell (numpy), then every grid move is certified with the self test too.
        self_occ, self_safe = self_collision_cells(arm, grid, margin=margin)
        occ = occ | self_occ
        safe = safe & self_safe
    # The moves are certified with zero-width links against the grown obstacles: the same test.
    arm, obstacles = scene(arm, obstacles, margin)
    obstacles = list(obstacles)
    t1 = time.perf_counter()
    kw = {"heuristic_weight": heuristic_weight, "max_expansions": max_expansions}
    if checker is not None:
        # The user's checker at every cell centre (one batch), and every move sampled: no cell
        # is "certified" for it, so the search runs on the occupancy with each move checked.
        occ = occ | ~checker.points(grid_q(grid).reshape(-1, arm.n), arm).reshape(grid.shape)
        safe = safe & ~occ
        full, metrics, closed = _route_on(arm, obstacles, grid, occ, start, goal_qs,
                                          certified=False, free=edge_test(arm, obstacles, checker),
                                          **kw)
        metrics["search_grid"] = "occupancy and validity, moves checked"
    else:
        try:
            full, metrics, closed = _route_on(arm, obstacles, grid, ~safe, start, goal_qs,
                                              certified=True, **kw)
            metrics["search_grid"] = "certified cells"
        except GridTooCoarse:
            full, metrics, closed = _route_on(arm, obstacles, grid, occ, start, goal_qs,
                                              certified=False, **kw)
            metrics["search_grid"] = "occupancy, moves checked"
    times = {"cspace": t1 - t0, "search": time.perf_counter() - t1}
    metrics.update({"grid_cells": int(occ.size), "free_fraction": float(1.0 - occ.mean()),
                    "certified_fraction": float(safe.mean())})
    return PlannerResult(full, True, path_length(full), {
        "grid": grid, "occupancy": occ, "expanded": closed, "metrics": metrics, "times": times})
