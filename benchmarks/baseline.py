"""A faithful naive baseline, written the way classic 2-link planning demos do it.

* The C-space grid: a Python loop over every cell; in each, forward kinematics
  and the segment–circle test (TM:SegmentCircleCollision) per link per
  obstacle, with small numpy arrays, one cell at a time.
* The search: greedy best-first that, at every step, picks the next node by a
  full-array ``argmin`` over a cost array, with a Manhattan heuristic that
  ignores the wrap of the torus (the grid's neighbours do wrap).

This is what rapp's vectorized ``occupancy`` and heap-based ``astar`` are timed
against. It is deliberately not optimised; it must still be *correct* so that
the comparison is fair (bench_core.py checks that both grids agree).
"""

from __future__ import annotations

import itertools

import numpy as np


def naive_segment_hits_circle(a, b, c, r):
    ab = b - a
    den = np.dot(ab, ab)
    t = np.dot(c - a, ab) / den if den > 0 else 0.0
    t = np.clip(t, 0.0, 1.0)
    p = a + t * ab
    return np.linalg.norm(p - c) <= r


def naive_forward_kinematics(lengths, q):
    pts = [np.array([0.0, 0.0])]
    phi = 0.0
    for L, qi in zip(lengths, q):
        phi += qi
        pts.append(pts[-1] + L * np.array([np.cos(phi), np.sin(phi)]))
    return pts


def naive_occupancy(lengths, circles, M):
    """``circles``: list of ``(cx, cy, r)``. Every axis wraps: theta_i = 2 pi i / M - pi."""
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
    """Greedy best-first on a 2-D torus grid; returns a list of index tuples or None."""
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
