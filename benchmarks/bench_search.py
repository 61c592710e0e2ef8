"""rapp.astar (numba) against scipy's breadth-first order and the previous rapp.astar.

Run from the repository root:  python benchmarks/bench_search.py
(scipy from benchmarks/requirements.txt: a peer to compare against, never a
runtime dependency of rapp.)

Three grids of benchmarks/bench_core.py: the 2-link torus at M = 360 and 720 and
the 3-link 64^3 grid. On each, in this one process and interleaved round by
round (the machine is shared; best-of-k CPU time, ``time.process_time``, per method), it times

* ``rapp.astar`` -- the compiled A* (numba, GD1 heuristic);
* scipy -- the grid graph built as a ``scipy.sparse`` adjacency (wrap included)
  plus ``scipy.sparse.csgraph.breadth_first_order`` from the start and the path
  read back from the predecessors: a shortest path with no heuristic, graph
  build included; and the same search given the graph, built once outside the
  timing (what scipy costs when the graph already exists: the fair peer);
* the previous ``rapp.astar`` -- the pure-Python loop, which lives on as the teaching
  :func:`rapp.astar_search` (called through :func:`old_astar`).

All path lengths are asserted equal (and equal to the BFS optimum).
Prints a table of times and ratios (other / rapp, > 1 means rapp is faster) and
writes rapp/recorded/search.json. The numba kernel is compiled (or loaded
from its cache) before timing; that one-off time is recorded separately.
"""

from __future__ import annotations

import datetime
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import CIRCLES, GOAL3, GOAL_Q, LINKS, LINKS3, OBSTACLES3, START3, START_Q  # noqa: E402

import rapp  # noqa: E402
from rapp.kernels import search_numba  # noqa: E402
from rapp.errors import NoPathFound  # noqa: E402
from rapp.search import _as_tuples, astar_search, bfs_distances  # noqa: E402

HERE = Path(__file__).resolve().parent
ROUNDS = 7


# ----------------------------------------------------------------- previous rapp.astar (baseline)


def old_astar(occupied, start, goal):
    """rapp.astar before numba: the Python loop that :func:`rapp.astar_search` keeps for the
    book, path as tuples (the closed-set array it also returns costs a copy, noise here)."""
    return _as_tuples(astar_search(occupied, start, goal).path)


# ----------------------------------------------------------------- scipy peer


def scipy_bfs(occ, start, goal, wraps=True):
    """Shortest path by scipy: sparse grid adjacency (with wrap) + breadth_first_order."""
    return scipy_bfs_on(grid_graph(occ, wraps), occ.shape, start, goal)


def grid_graph(occ, wraps=True):
    """The free cells' 4-/6-neighbour adjacency as a scipy.sparse CSR matrix (wrap included)."""
    shape = occ.shape
    size = occ.size
    free = ~occ.ravel()
    idx = np.arange(size).reshape(shape)
    wr = (wraps,) * occ.ndim if isinstance(wraps, bool) else wraps
    rows, cols = [], []
    for axis, (m, w) in enumerate(zip(shape, wr)):
        nxt = np.roll(idx, -1, axis=axis)
        if not w:  # bounded axis: no edge from the last layer
            cut = [slice(None)] * occ.ndim
            cut[axis] = slice(0, m - 1)
            a, b = idx[tuple(cut)].ravel(), nxt[tuple(cut)].ravel()
        else:
            a, b = idx.ravel(), nxt.ravel()
        keep = free[a] & free[b] & (a != b)
        rows += [a[keep], b[keep]]
        cols += [b[keep], a[keep]]
    r, c = np.concatenate(rows), np.concatenate(cols)
    return sp.csr_matrix((np.ones(r.size, np.int8), (r, c)), shape=(size, size))


def scipy_bfs_on(graph, shape, start, goal):
    """Breadth-first search given the graph: what scipy costs once the graph exists."""
    s = int(np.ravel_multi_index(start, shape))
    t = int(np.ravel_multi_index(goal, shape))
    _, pred = breadth_first_order(graph, s, directed=True, return_predecessors=True)
    if t != s and pred[t] < 0:
        raise NoPathFound("unreachable")
    flat = [t]
    while flat[-1] != s:
        flat.append(int(pred[flat[-1]]))
    cells = np.stack(np.unravel_index(np.asarray(flat[::-1]), shape), axis=-1)
    return [tuple(row) for row in cells.tolist()]


# ----------------------------------------------------------------- run


def cases():
    arm = rapp.Arm(LINKS)
    obstacles = [rapp.Circle((cx, cy), r) for cx, cy, r in CIRCLES]
    out = {}
    for M in (360, 720):
        grid = rapp.JointGrid(arm, M)
        occ = rapp.occupancy(arm, obstacles, grid)
        out[f"2link_M{M}"] = (occ, tuple(grid.index(START_Q).tolist()),
                              tuple(grid.index(GOAL_Q).tolist()))
    arm3 = rapp.Arm(LINKS3)
    grid3 = rapp.JointGrid(arm3, 64)
    occ3 = rapp.occupancy(arm3, OBSTACLES3, grid3)
    out["3link_M64"] = (occ3, tuple(grid3.index(START3).tolist()), tuple(grid3.index(GOAL3).tolist()))
    return out


def interleaved(fns, rounds):
    """Best-of-``rounds`` and median CPU time of each function, calling them round-robin."""
    best = {k: np.inf for k in fns}
    times = {k: [] for k in fns}
    outs = {}
    for _ in range(rounds):
        for k, fn in fns.items():
            # CPU time, not wall time: on a shared machine a descheduled call is not slower.
            t0 = time.process_time()
            outs[k] = fn()
            times[k].append(time.process_time() - t0)
            best[k] = min(best[k], times[k][-1])
    return best, {k: float(np.median(t)) for k, t in times.items()}, outs


def run():
    load_before = os.getloadavg()
    t0 = time.perf_counter()
    rapp.astar(np.zeros((2, 2), bool), (0, 0), (1, 1))  # compile or load the numba cache
    warmup = time.perf_counter() - t0
    compiled = search_numba.kernel() is not None

    results, rows = {}, []
    for name, (occ, s, g) in cases().items():
        fns = {
            "rapp": lambda: rapp.astar(occ, s, g),
            "scipy_bfs": lambda: scipy_bfs(occ, s, g),
            "scipy_given_graph": lambda graph=grid_graph(occ): scipy_bfs_on(graph, occ.shape, s, g),
            "old_rapp": lambda: old_astar(occ, s, g),
        }
        best, median, outs = interleaved(fns, ROUNDS)
        lengths = {k: len(p) - 1 for k, p in outs.items()}
        opt = int(bfs_distances(occ, s)[g])
        assert set(lengths.values()) == {opt}, (name, lengths, opt)
        teach = astar_search(occ, s, g)
        assert outs["rapp"] == outs["old_rapp"] == _as_tuples(teach.path)
        res = {
            "cells": int(occ.size), "free_cells": int((~occ).sum()),
            "start": s, "goal": g, "path_steps": opt,
            "astar_expansions": teach.expansions,
            "expanded_fraction_of_free": teach.expansions / int((~occ).sum()),
            "rapp_astar_s": best["rapp"], "scipy_bfs_with_build_s": best["scipy_bfs"],
            "old_rapp_astar_s": best["old_rapp"],
            "scipy_bfs_given_graph_s": best["scipy_given_graph"],
            "ratio_scipy_given_graph_over_rapp": best["scipy_given_graph"] / best["rapp"],
            "ratio_scipy_over_rapp": best["scipy_bfs"] / best["rapp"],
            "ratio_old_over_rapp": best["old_rapp"] / best["rapp"],
            # Medians beside the best: how much the shared machine's load moved the ratio.
            "median_s": median,
            "ratio_scipy_over_rapp_median": median["scipy_bfs"] / median["rapp"],
            "same_path_as_astar_search": True,
            "targets": {"ratio_scipy_over_rapp_min": 1.0},
        }
        results[name] = res
        rows.append((name, res))

    info = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu_count": os.cpu_count(),
        "load_average_1min": load_before[0],
        "load_before": load_before, "load_after": os.getloadavg(),
        "machine": platform.machine(), "platform": platform.platform(),
        "python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
        "numba": _version("numba"), "compiled": compiled,
        "first_call_s": warmup,
        "timing": f"best-of-{ROUNDS} CPU seconds (time.process_time), the four timings interleaved"
                  " per round",
    }
    (HERE.parent / "rapp" / "recorded" / "search.json").write_text(
        json.dumps({"machine": info, "results": results}, indent=2) + "\n")

    print(f"{'case':12s} {'steps':>5s} {'expanded':>9s} {'rapp [ms]':>10s} {'scipy [ms]':>11s}"
          f" {'given graph':>12s} {'old [ms]':>9s} {'scipy/rapp':>11s} {'given/rapp':>11s} {'old/rapp':>9s}")
    for name, r in rows:
        print(f"{name:12s} {r['path_steps']:5d} {r['expanded_fraction_of_free']:9.1%}"
              f" {1e3 * r['rapp_astar_s']:10.2f} {1e3 * r['scipy_bfs_with_build_s']:11.2f}"
              f" {1e3 * r['scipy_bfs_given_graph_s']:12.2f}"
              f" {1e3 * r['old_rapp_astar_s']:9.2f} {r['ratio_scipy_over_rapp']:10.1f}x"
              f" {r['ratio_scipy_given_graph_over_rapp']:10.2f}x"
              f" {r['ratio_old_over_rapp']:8.1f}x")
    print(f"compiled={compiled} first call {warmup:.2f} s; cpu_count={info['cpu_count']}"
          f" load={info['load_average_1min']} numba={info['numba']} scipy={info['scipy']}")


def _version(mod):
    try:
        return __import__(mod).__version__
    except ImportError:
        return None


if __name__ == "__main__":
    run()
