"""Case study: the 3-link RRT report (seed 003), its conventions, its numbers and its experiment.

The report measures angles from the +y axis, clockwise positive:
``x = sum l_i sin(Theta_i)``, ``y = sum l_i cos(Theta_i)`` with
``Theta_i = theta_1 + ... + theta_i``. rapp measures from +x, counter-clockwise,
so the two agree when ``q_1 = pi/2 - theta_1`` and ``q_i = -theta_i`` for
``i >= 2`` (:func:`report_to_rapp`). The report's rotation (its eq. 1) is
``[[cos, sin], [-sin, cos]]``: rapp's counter-clockwise rotation by ``-theta``;
applied to a link lying along +y it gives exactly the report's FK terms.

The report's printed Jacobian (its eq. 3) is wrong; :func:`printed_jacobian`
keeps it as printed so that the tests and the book can show the check that
finds the error (sympy differentiation and finite differences).

What the report does not give is chosen here and said so: the link lengths
(:data:`LINK_LENGTHS`) and where its 0.2 x 0.2 square lies (:data:`SQUARE_CORNER`),
and the start and goal (:data:`START_THETA`, :data:`GOAL_THETA`, report angles).
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import sympy as sp

from rapp.arm import Arm
from rapp.collision import path_collision_free
from rapp.cspace import JointGrid, occupancy
from rapp.obstacles import Polygon
from rapp.paths import path_length
from rapp.results import load_result
from rapp.rrt import rrt
from rapp.search import astar

__all__ = [
    "THETA_LIMIT",
    "SQUARE_SIDE",
    "LINK_LENGTHS",
    "SQUARE_CORNER",
    "START_THETA",
    "GOAL_THETA",
    "report_to_rapp",
    "rapp_to_report",
    "report_fk",
    "report_rotation",
    "printed_jacobian",
    "seed_arm",
    "seed_square",
    "seed_problem",
    "compare_with_astar",
    "alpha_beta_experiment",
    "wilson_interval",
    "mean_interval",
    "success_table",
    "walk_to_root",
    "printed_walk",
    "seed_scenario",
    "plan_on_the_command_line",
]

THETA_LIMIT = 1.5
"""Report §4.1: samples are drawn "within the boundaries, in this case -1.5 to 1.5".

Read as bounds on every report joint angle, in radians (Algorithm 2 draws a configuration,
``q.RANDOM(LowLim, HighLim)``), not as a workspace box in metres. The tree moves only toward its
samples, so every node stays in this box: for the planner it acts as joint limits
(:func:`seed_arm`). The report's "-pi to pi" (§3.1) is the wider range it allows IK solutions.
"""

SQUARE_SIDE = 0.2
"""Report §5: "a 0.2 by 0.2 square obstacle in the plane"."""

LINK_LENGTHS = (0.5, 0.5, 0.5)
"""Not in the report (chosen: three equal links, reach 1.5 m; nothing depends on the reach
matching :data:`THETA_LIMIT`, which bounds angles, not positions)."""

SQUARE_CORNER = (-0.1, 1.1)
"""Not in the report (chosen: the square blocks the straight joint-space motion from start to goal)."""

START_THETA = (-1.0, -0.5, -0.5)
"""Not in the report: the start, in the report's angles (leaning left)."""

GOAL_THETA = (1.0, 0.5, 0.5)
"""Not in the report: the goal, the start's mirror image (leaning right)."""


def report_to_rapp(theta) -> np.ndarray:
    """Report angles (from +y, clockwise) to rapp's (from +x, counter-clockwise), ``(..., n)``.

    Examples
    --------
    >>> report_to_rapp([0.0, 0.5, -0.25]).round(4).tolist()
    [1.5708, -0.5, 0.25]
    """
    t = np.asarray(theta, dtype=float)
    return np.concatenate((np.pi / 2 - t[..., :1], -t[..., 1:]), axis=-1)


def rapp_to_report(q) -> np.ndarray:
    """Inverse of :func:`report_to_rapp` (the map is its own inverse).

    Examples
    --------
    >>> rapp_to_report(report_to_rapp([0.3, -0.2, 0.1])).round(12).tolist()
    [0.3, -0.2, 0.1]
    """
    return report_to_rapp(q)


def report_fk(lengths, theta) -> np.ndarray:
    """The report's forward kinematics (its eq. 2): ``(x, y)`` of the tip, shape ``(..., 2)``.

    Examples
    --------
    >>> report_fk([0.5, 0.5, 0.5], [0.0, 0.0, 0.0]).tolist()   # straight up the +y axis
    [0.0, 1.5]
    """
    t = np.cumsum(np.asarray(theta, dtype=float), axis=-1)
    lengths = np.asarray(lengths, dtype=float)
    return np.stack(((lengths * np.sin(t)).sum(-1), (lengths * np.cos(t)).sum(-1)), axis=-1)


def report_rotation(theta) -> np.ndarray:
    """The report's eq. 1, ``[[cos, sin], [-sin, cos]]``, shape ``(..., 2, 2)``.

    Examples
    --------
    >>> (report_rotation(np.pi / 2) @ [0.0, 1.0]).round(12).tolist()   # +y turned to +x: clockwise
    [1.0, 0.0]
    """
    c, s = np.cos(theta), np.sin(theta)
    return np.stack((np.stack((c, s), -1), np.stack((-s, c), -1)), -2)


def printed_jacobian():
    """The report's eq. 3 exactly as printed, a sympy 2x3 Matrix in ``l1..l3, t1..t3``.

    Returns
    -------
    (sympy.Matrix, tuple of Symbol, tuple of Symbol)
        The matrix, the lengths ``(l1, l2, l3)`` and the angles ``(t1, t2, t3)``.

    Examples
    --------
    >>> J, l, t = printed_jacobian()
    >>> J.shape
    (2, 3)
    """
    l1, l2, l3 = l = sp.symbols("l1 l2 l3", positive=True)
    t1, t2, t3 = t = sp.symbols("t1 t2 t3", real=True)
    s1, s12, s123 = sp.sin(t1), sp.sin(t1 + t2), sp.sin(t1 + t2 + t3)
    c1, c12, c123 = sp.cos(t1), sp.cos(t1 + t2), sp.cos(t1 + t2 + t3)
    J = sp.Matrix(
        [
            [-l1 * c1 - l2 * c12 - l3 * c123, -l2 * c12 - l3 * c123, -l3 * c123],
            [l1 * s1 + l2 * s12 + l3 * s123, l2 * s12 - l3 * s123, l3 * s123],
        ]
    )
    return J, l, t


def seed_arm(lengths=LINK_LENGTHS) -> Arm:
    """The report's arm in rapp's convention: every report angle within ``±THETA_LIMIT``.

    ``theta_1 in [-1.5, 1.5]`` becomes ``q_1 in [pi/2 - 1.5, pi/2 + 1.5]``;
    the others only change sign, so their interval is the same.

    Examples
    --------
    >>> seed_arm().joint_limits[0] == (np.pi / 2 - 1.5, np.pi / 2 + 1.5)
    True
    """
    lim = THETA_LIMIT
    limits = [(np.pi / 2 - lim, np.pi / 2 + lim)] + [(-lim, lim)] * (len(lengths) - 1)
    return Arm(lengths, limits)


def seed_square(corner=SQUARE_CORNER, angle: float = 0.0) -> Polygon:
    """The report's 0.2 x 0.2 square (§5) at ``corner``, turned by ``angle`` about it (§4.6.1).

    Examples
    --------
    >>> seed_square().vertices[2]
    (0.1, 1.3)
    """
    return Polygon.rectangle(corner, SQUARE_SIDE, SQUARE_SIDE, angle)


def seed_problem():
    """The report's planning problem in rapp's convention: ``(arm, obstacles, start, goal)``.

    :func:`seed_arm`, ``[seed_square()]``, and :data:`START_THETA` and :data:`GOAL_THETA`
    converted (:func:`report_to_rapp`). Start and goal are free; the straight joint-space
    edge between them is not.

    Examples
    --------
    >>> arm, obstacles, start, goal = seed_problem()
    >>> arm.n, len(obstacles), start.round(4).tolist()
    (3, 1, [2.5708, 0.5, 0.5])
    """
    return seed_arm(), [seed_square()], report_to_rapp(START_THETA), report_to_rapp(GOAL_THETA)


def compare_with_astar(arm, start, goal, obstacles, *, cells=32, rrt_settings=None) -> dict:
    """RRT and grid A* on the same problem: joint-space path cost and wall time.

    A* runs on :class:`rapp.JointGrid` occupancy with ``cells`` per joint,
    from the cell nearest ``start`` to the cell nearest ``goal``; its time
    includes building the occupancy grid, which it needs. Its cost is the
    joint-space length of its cell-centre polyline (4-connected steps: a
    staircase, longer than the straight distance). RRT runs with a joint goal.

    Returns
    -------
    dict
        ``rrt_cost``, ``rrt_seconds``, ``rrt_iterations``, ``rrt_nodes``,
        ``astar_cost``, ``astar_seconds``, ``astar_cells`` (path length in
        cells), ``astar_certified`` (whether the A* polyline's straight
        segments pass the continuous collision check — the grid only checked
        its cells), ``straight_distance``.

    Examples
    --------
    >>> from rapp import Arm
    >>> out = compare_with_astar(Arm([1.0, 1.0], [(-2.0, 2.0)] * 2), [0.0, 0.0], [1.0, 0.0], [], cells=9)
    >>> round(out["astar_cost"], 6), out["straight_distance"]
    (1.0, 1.0)
    """
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    t0 = time.perf_counter()
    res = rrt(arm, start, goal, obstacles, **(rrt_settings or {}))
    t1 = time.perf_counter()
    grid = JointGrid(arm, cells)
    occ = occupancy(arm, obstacles, grid)
    cells_path = astar(occ, tuple(grid.index(start)), tuple(grid.index(goal)), wraps=grid.wraps)
    t2 = time.perf_counter()
    q = grid.angles(np.array(cells_path))
    q = np.unwrap(q, axis=0)  # free joints: consecutive cells are neighbours across the seam
    return {
        "rrt_cost": res.cost,
        "rrt_seconds": t1 - t0,
        "rrt_iterations": res.iterations,
        "rrt_nodes": int(res.nodes.shape[0]),
        "astar_cost": path_length(q),
        "astar_seconds": t2 - t1,
        "astar_cells": len(cells_path),
        "astar_certified": bool(path_collision_free(arm, q, obstacles)),
        "straight_distance": float(np.linalg.norm(goal - start)),
    }


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
        ``successes`` (the number of successful trials), ``mean_cost`` (over
        successful trials, ``nan`` if none), ``mean_iterations`` (over all
        trials; a failure counts ``max_iterations``); and every trial, of
        shape (A, B, trials): ``trial_success``, ``trial_cost`` (``nan`` on
        failure), ``trial_iterations``.

    Examples
    --------
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
        "successes": ok.sum(-1),
        "mean_cost": np.where(ok.any(-1), with_cost, np.nan),
        "mean_iterations": iters.mean(-1),
        "trial_success": ok,
        "trial_cost": cost,
        "trial_iterations": iters,
    }


def wilson_interval(k, n, z: float = 1.96):
    """Wilson score interval of a success rate: ``k`` successes in ``n`` trials (95 % for z = 1.96).

    The interval of the rates ``p`` that the score test does not reject:
    ``|k/n - p| <= z sqrt(p (1 - p) / n)`` (eq. (ch12-wilson)). Unlike ``k/n +- z sqrt(...)`` it
    stays in ``[0, 1]`` and is not empty at ``k = 0`` or ``k = n``.

    Returns
    -------
    (lo, hi) : ndarrays of the shape of ``k``

    Examples
    --------
    >>> lo, hi = wilson_interval([2, 3], 4)
    >>> lo.round(2).tolist(), hi.round(2).tolist()
    ([0.15, 0.3], [0.85, 0.95])
    """
    k = np.asarray(k, dtype=float)
    centre = (k + z**2 / 2) / (n + z**2)
    half = z / (n + z**2) * np.sqrt(k * (n - k) / n + z**2 / 4)
    return centre - half, centre + half


def mean_interval(x, z: float = 1.96):
    """Mean over the last axis, ``nan`` entries (failed trials) skipped, and its half-width.

    The half-width is ``z`` standard errors (sample standard deviation over ``sqrt(n)``);
    ``nan`` where fewer than two values remain.

    Examples
    --------
    >>> m, h = mean_interval([[1.0, 3.0, np.nan], [2.0, np.nan, np.nan]])
    >>> m.tolist(), h.round(4).tolist()
    ([2.0, 2.0], [1.96, nan])
    """
    x = np.asarray(x, dtype=float)
    ok = ~np.isnan(x)
    n = ok.sum(-1)
    with np.errstate(invalid="ignore", divide="ignore"):  # no or one value: nan
        m = np.where(ok, x, 0.0).sum(-1) / n
        var = np.where(ok, (x - m[..., None]) ** 2, 0.0).sum(-1) / (n - 1)
        return m, z * np.sqrt(var / n)


def success_table(successes, trials: int, alphas, betas) -> str:
    """The experiment's successes as text: one row per alpha, ``k  [lo, hi]`` per beta (Wilson).

    Examples
    --------
    >>> print(success_table(np.array([[2, 3]]), 4, [0.5], [0.1, 1.0]))
    alpha \\ beta                 0.1                   1
             0.5     2  [0.15, 0.85]     3  [0.30, 0.95]
    """
    lo, hi = wilson_interval(successes, trials)
    lines = ["alpha \\ beta" + "".join(f"{b:>20g}" for b in betas)]
    for i, a in enumerate(alphas):
        lines.append(f"{a:12g}" + "".join(f"{successes[i, j]:6d}  [{lo[i, j]:.2f}, {hi[i, j]:.2f}]"
                                          for j in range(len(betas))))
    return "\n".join(lines)


def walk_to_root(nodes, parent, leaf: int = -1) -> np.ndarray:
    """The path of a tree from its root to node ``leaf``: follow the parents, reverse once.

    ``parent[i]`` is the index of node ``i``'s parent, ``-1`` at the root (:class:`rapp.rrt`'s
    result).

    Examples
    --------
    >>> walk_to_root(np.array([[0.0], [1.0], [2.0], [5.0]]), np.array([-1, 0, 1, 0]), 2).ravel().tolist()
    [0.0, 1.0, 2.0]
    """
    nodes = np.asarray(nodes)
    i, walk = int(np.arange(len(nodes))[leaf]), []
    while i >= 0:
        walk.append(i)
        i = int(parent[i])
    return nodes[walk[::-1]]


def printed_walk(nodes, parent, start) -> np.ndarray:
    """The report's Algorithm 2 as printed: it stops before the start and reverses at every step.

    From the last node it appends each parent until the parent is ``start`` (so neither the
    start nor the last node is in the result), reversing the list inside the loop. Kept to show
    the error; :func:`walk_to_root` is the correct walk.

    Examples
    --------
    >>> nodes = np.array([[0.0], [1.0], [2.0], [3.0], [4.0]])
    >>> printed_walk(nodes, np.array([-1, 0, 1, 2, 3]), [0.0]).ravel().tolist()
    [1.0, 3.0, 2.0]
    """
    tree = {tuple(nodes[i]): tuple(nodes[p]) for i, p in enumerate(parent) if p >= 0}
    node, out = tuple(nodes[-1]), []
    while tree[node] != tuple(start):
        node = tree[node]
        out.append(node)
        out.reverse()
    return np.array(out)


def seed_scenario(arm, start, goal, planner) -> dict:
    """The report's problem as a rapp scenario (:func:`rapp.plan`'s input), with ``planner``.

    The arm's links and joint limits, the square (:data:`SQUARE_CORNER`, :data:`SQUARE_SIDE`),
    ``start`` and the ``goal`` configuration.

    Examples
    --------
    >>> sc = seed_scenario(seed_arm(), [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], {"algorithm": "astar"})
    >>> sc["obstacles"][0]["type"], sc["goal"], sc["planner"]["algorithm"]
    ('rectangle', {'joints': [2.0, 0.0, 0.0]}, 'astar')
    """
    return {
        "name": "seed003",
        "arm": {"link_lengths": list(arm.lengths.tolist() if hasattr(arm.lengths, "tolist") else arm.lengths),
                "joint_limits": [list(lim) for lim in np.asarray(arm.joint_limits).tolist()]},
        "obstacles": [{"type": "rectangle", "corner": list(SQUARE_CORNER),
                       "width": SQUARE_SIDE, "height": SQUARE_SIDE, "angle": 0.0}],
        "start": np.asarray(start, dtype=float).tolist(),
        "goal": {"joints": np.asarray(goal, dtype=float).tolist()},
        "planner": dict(planner),
    }


def plan_on_the_command_line(scenario):
    """Run ``python -m rapp plan FILE --quiet --out result.json`` on ``scenario``, in a new process.

    The scenario is written to a temporary directory first (the command reads a file, as a
    reader would run it). Returns the finished process (``returncode``, ``stdout``) and the
    result file read back (:func:`rapp.load_result`), or ``None`` when the command wrote none.

    Examples
    --------
    >>> arm, obstacles, start, goal = seed_problem()
    >>> run, saved = plan_on_the_command_line(seed_scenario(arm, start, goal, {"algorithm": "rrt", "seed": 0}))
    >>> run.returncode, "verified" in run.stdout, saved.q.shape[1]
    (0, True, 3)
    """
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / f"{scenario.get('name', 'scenario')}.json", Path(tmp) / "result.json"
        path.write_text(json.dumps(scenario), encoding="utf-8")
        run = subprocess.run([sys.executable, "-m", "rapp", "plan", str(path), "--quiet", "--out", str(out)],
                             capture_output=True, text=True)
        return run, (load_result(out) if out.exists() else None)
