"""rapp.search.astar_steps records the A* of astar_search, step by step: the same expansions,
an optimal path (the breadth-first optimum), a closed set that grows by one cell per step, and
snapshots that agree with each other (frontier, g, parent). rapp.plotting.plot_astar_step draws
any of its steps.
"""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from rapp.errors import NoPathFound  # noqa: E402
from rapp.plotting import animate_astar, plot_astar_step  # noqa: E402
from rapp.search import astar_search, astar_steps, bfs, bfs_distances  # noqa: E402
from test_search import neighbours  # noqa: E402  the slow oracle, defined once


@st.composite
def grids(draw):
    n = draw(st.integers(1, 3))
    side = {1: 25, 2: 10, 3: 5}[n]
    shape = tuple(draw(st.lists(st.integers(1, side), min_size=n, max_size=n)))
    wraps = tuple(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    density = draw(st.sampled_from([0.0, 0.1, 0.25, 0.4]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    occ = rng.random(shape) < density
    start = tuple(int(rng.integers(m)) for m in shape)
    goal = tuple(int(rng.integers(m)) for m in shape)
    occ[start] = occ[goal] = False
    return occ, wraps, start, goal


@settings(max_examples=150, deadline=None)
@given(grids(), st.sampled_from([1.0, 1.5, 3.0]))
def test_trace_is_the_astar_of_astar_search(case, w):
    occ, wraps, start, goal = case
    opt = bfs_distances(occ, start, wraps)[goal]
    if opt < 0:
        with pytest.raises(NoPathFound):
            astar_steps(occ, start, goal, wraps=wraps, heuristic_weight=w)
        return
    trace = astar_steps(occ, start, goal, wraps=wraps, heuristic_weight=w)
    ref = astar_search(occ, start, goal, wraps=wraps, heuristic_weight=w)
    # The same search: the same number of expansions, the same expanded cells, the same path.
    assert trace.expansions == ref.expansions == len(trace.current) == len(trace.relaxed)
    final = trace.closed[-1] if trace.expansions else np.zeros(occ.shape, bool)
    np.testing.assert_array_equal(final, ref.closed)
    np.testing.assert_array_equal(trace.path, ref.path)
    assert trace.cost == ref.cost
    if w == 1.0:
        # Optimal: the breadth-first optimum.
        assert trace.cost == opt == len(bfs(occ, start, goal, wraps=wraps)) - 1
    else:
        assert opt <= trace.cost <= w * opt


@settings(max_examples=150, deadline=None)
@given(grids())
def test_closed_set_grows_by_one_cell_per_step_and_snapshots_agree(case):
    occ, wraps, start, goal = case
    if bfs_distances(occ, start, wraps)[goal] < 0:
        return
    t = astar_steps(occ, start, goal, wraps=wraps)
    previous = np.zeros(occ.shape, bool)
    for k in range(t.expansions):
        u = tuple(int(i) for i in t.current[k])
        closed = t.closed[k]
        # grows by exactly the current cell
        assert not previous[u] and closed[u]
        assert int(closed.sum()) == k + 1 and (closed | previous).sum() == k + 1
        assert not np.any(closed & occ)
        # a closed cell's g is final: the breadth-first distance from the start
        np.testing.assert_array_equal(t.g[k][closed], bfs_distances(occ, start, wraps)[closed])
        # the open list: reached, not closed, never blocked; the goal is never expanded
        assert not np.any(t.frontier[k] & closed) and not np.any(t.frontier[k] & occ)
        np.testing.assert_array_equal(t.frontier[k] | closed, t.g[k] >= 0)
        assert u != tuple(goal)
        # the parent map: every reached cell but the start has a neighbour one step cheaper
        for c in map(tuple, np.argwhere(t.g[k] >= 0)):
            p = tuple(int(i) for i in t.parent[k][c])
            if c == tuple(start):
                assert p == (-1,) * occ.ndim and t.g[k][c] == 0
            else:
                assert p in set(neighbours(c, occ.shape, wraps)) and t.g[k][p] == t.g[k][c] - 1
        # the cells relaxed at this step are neighbours of the current cell with g = g(u) + 1
        for v in t.relaxed[k]:
            assert v in set(neighbours(u, occ.shape, wraps)) and t.g[k][v] == t.g[k][u] + 1
        chain = t.chain(k)
        assert tuple(chain[0]) == tuple(start) and tuple(chain[-1]) == u
        assert len(chain) - 1 == t.g[k][u]
        previous = closed


def test_trace_on_the_small_torus_crosses_the_seam():
    occ = np.zeros((12, 12), bool)
    occ[6, :11] = True  # a wall with one gap, at the top
    occ[0, 4:9] = True  # and a wall on the seam
    start, goal = (2, 6), (9, 5)
    t = astar_steps(occ, start, goal)
    assert t.cost == len(bfs(occ, start, goal)) - 1 == 10
    assert bfs_distances(occ, start, wraps=(False, True))[goal] == 18  # without the wrap
    assert (np.abs(np.diff(t.path[:, 0])) == 11).any()  # one step from column 0 to 11
    assert t.h[start] == 5 + 1 and t.h[goal] == 0


def test_plot_astar_step_draws_every_step_and_the_end():
    occ = np.zeros((12, 12), bool)
    occ[0, 3:9] = True
    t = astar_steps(occ, (2, 6), (9, 5))
    for k in (0, t.expansions // 2, t.expansions - 1, t.expansions):
        ax = plot_astar_step(t, k)
        assert ax.get_xlabel() and ax.get_ylabel() and ax.get_legend() is not None
        plt.close(ax.figure)
    with pytest.raises(ValueError):
        plot_astar_step(t, t.expansions + 1)
    anim = animate_astar(t)
    assert anim._save_count == t.expansions + 1
    plt.close(anim._fig)
    with pytest.raises(ValueError):
        plot_astar_step(astar_steps(np.zeros(6, bool), [0], [3]), 0)
