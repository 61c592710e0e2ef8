"""A faithful naive baseline, written the way classic 2-link planning demos do it.

* The C-space grid: a Python loop over every cell; in each, forward kinematics
  and the segment–circle test (TM:SegmentCircleCollision) per link per
  obstacle, with small numpy arrays, one cell at a time.
* The search: greedy best-first that, at every step, picks the next node by a
  full-array ``argmin`` over a cost array, with a Manhattan heuristic that
  ignores the wrap of the torus (the grid's neighbours do wrap).

This is what rapp's vectorized ``occupancy`` and heap-based ``astar`` are timed
against (``benchmarks/bench_core.py``, recorded in :mod:`rapp.recorded`). It is
deliberately not optimised; it must still be *correct* so that the comparison is
fair (the benchmark checks that both grids agree). It lives in the package so that
the performance chapter can run and count it with only ``rapp`` installed; nothing
else in ``rapp`` uses it.

Examples
--------
>>> occ = naive_occupancy([1.0, 1.0], [(1.75, 0.75, 0.6)], 8)
>>> occ.shape, bool(occ.any()), bool(occ.all())
((8, 8), True, False)
"""

from __future__ import annotations

import itertools

import numpy as np


__all__ = ["naive_segment_hits_circle", "naive_forward_kinematics", "naive_occupancy",
           "naive_greedy"]


def naive_segment_hits_circle(a, b, c, r):
    """Whether segment ``a``-``b`` meets the disc of centre ``c`` and radius ``r`` (touching counts).

    Examples
    --------
    >>> a, b = np.array([0.0, 0.0]), np.array([2.0, 0.0])
    >>> bool(naive_segment_hits_circle(a, b, np.array([1.0, 0.5]), 0.5))
    True
    """
    ab = b - a
    den = np.dot(ab, ab)
    t = np.dot(c - a, ab) / den if den > 0 else 0.0
    t = np.clip(t, 0.0, 1.0)
    p = a + t * ab
    return np.linalg.norm(p - c) <= r


def naive_forward_kinematics(lengths, q):
    """Joint positions, base first, of one configuration ``q``: a Python loop over the links.

    Examples
    --------
    >>> [p.round(6).tolist() for p in naive_forward_kinematics([1.0, 1.0], [0.0, np.pi / 2])]
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
    """
    pts = [np.array([0.0, 0.0])]
    phi = 0.0
    for L, qi in zip(lengths, q):
        phi += qi
        pts.append(pts[-1] + L * np.array([np.cos(phi), np.sin(phi)]))
    return pts


def naive_occupancy(lengths, circles, M):
    """The C-space grid, one cell at a time: ``circles`` is a list of ``(cx, cy, r)``.

    Every axis wraps: theta_i = 2 pi i / M - pi, the angles of ``rapp.JointGrid(arm, M)``.
    See the module's example.
    """
    n = len(lengths)
    theta = [2 * np.pi * i / M - np.pi for i in range(M)]
    obs = [(np.array([cx, cy]), r) for cx, cy, r in circles]
    occ = np.zeros((M,) * n, dtype=bool)
    for idx in itertools.product(range(M), repeat=n):
        pts = naive_forward_kinematics(lengths, [theta[i] for i in idx])
        hit = False
        for k in range(n):
            for c, r in obs:
                if naive_segment_hits_circle(pts[k], pts[k + 1], c, r):
                    hit = True
        occ[idx] = hit
    return occ


def naive_greedy(occ, start, goal):
    """Greedy best-first on a 2-D torus grid; returns a list of index tuples or None.

    Examples
    --------
    >>> occ = np.zeros((6, 6), dtype=bool); occ[1:5, 3] = True
    >>> path = naive_greedy(occ, (2, 1), (2, 5))
    >>> path[0], path[-1], all(not occ[c] for c in path)
    ((2, 1), (2, 5), True)
    """
    M0, M1 = occ.shape
    ii, jj = np.indices(occ.shape)
    h = np.abs(ii - goal[0]) + np.abs(jj - goal[1])  # ignores the wrap
    cost = np.full(occ.shape, np.inf)
    seen = np.zeros(occ.shape, dtype=bool)
    parent = {}
    cost[start] = h[start]
    seen[start] = True
    while True:
        k = np.argmin(cost)  # full-array scan every step
        if not np.isfinite(cost.flat[k]):
            return None
        u = np.unravel_index(k, occ.shape)
        u = (int(u[0]), int(u[1]))
        if u == tuple(goal):
            break
        cost[u] = np.inf
        for d0, d1 in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            v = ((u[0] + d0) % M0, (u[1] + d1) % M1)
            if not occ[v] and not seen[v]:
                seen[v] = True
                parent[v] = u
                cost[v] = h[v]
    path = [tuple(goal)]
    while path[-1] != tuple(start):
        path.append(parent[path[-1]])
    return path[::-1]
