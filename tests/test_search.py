"""Properties of rapp.search: A* is optimal (equals the BFS optimum), weighted A*
is within w of it, paths are valid moves on the (partly) wrapping grid, the
heuristic of GD1 is admissible and consistent, and the failure cases raise.

The slow oracles here (a deque BFS over index tuples and an explicit move
check) share no code with rapp.search.
"""

from collections import deque

import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp.errors import NoPathFound, RappError
from rapp.search import (
    HeuristicCheck,
    SearchResult,
    astar,
    astar_search,
    bfs,
    bfs_distances,
    check_heuristic,
    greedy_best_first,
    toroidal_manhattan,
)

# ----------------------------------------------------------------- slow, obviously correct oracles


def neighbours(cell, shape, wraps):
    for axis, (m, w) in enumerate(zip(shape, wraps)):
        for step in (1, -1):
            x = cell[axis] + step
            if w:
                x %= m
            elif not 0 <= x < m:
                continue
            yield cell[:axis] + (x,) + cell[axis + 1 :]


def slow_bfs(occ, start, wraps):
    dist = {start: 0} if not occ[start] else {}
    queue = deque(dist)
    while queue:
        u = queue.popleft()
        for v in neighbours(u, occ.shape, wraps):
            if not occ[v] and v not in dist:
                dist[v] = dist[u] + 1
                queue.append(v)
    return dist


def is_unit_move(a, b, shape, wraps):
    diff = [(j, bj - aj) for j, (aj, bj) in enumerate(zip(a, b)) if aj != bj]
    if len(diff) != 1:
        return False
    j, d = diff[0]
    return abs(d) == 1 or (wraps[j] and abs(d) == shape[j] - 1)


def assert_valid_path(path, occ, start, goal, wraps):
    assert path[0] == tuple(start) and path[-1] == tuple(goal)
    assert all(isinstance(i, int) for c in path for i in c)
    assert not any(occ[c] for c in path)
    for a, b in zip(path, path[1:]):
        assert is_unit_move(a, b, occ.shape, wraps), (a, b)


# ----------------------------------------------------------------- random grids


@st.composite
def grids(draw, free_ends=True, sides=None, densities=(0.0, 0.1, 0.25, 0.4, 0.6), min_side=1):
    """A random grid: ``sides`` maps each dimension drawn to its largest side."""
    sides = sides or {1: 25, 2: 10, 3: 5}
    n = draw(st.integers(min(sides), max(sides)))
    shape = tuple(draw(st.lists(st.integers(min_side, sides[n]), min_size=n, max_size=n)))
    wraps = tuple(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    density = draw(st.sampled_from(densities))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    occ = rng.random(shape) < density
    start = tuple(int(rng.integers(m)) for m in shape)
    goal = tuple(int(rng.integers(m)) for m in shape)
    if free_ends:
        occ[start] = occ[goal] = False
    return occ, wraps, start, goal


@settings(max_examples=100, deadline=None)
@given(grids(free_ends=False))
def test_bfs_distances_match_slow_bfs(case):
    occ, wraps, start, _ = case
    d = bfs_distances(occ, start, wraps)
    slow = slow_bfs(occ, start, wraps)
    expect = np.full(occ.shape, -1)
    for cell, k in slow.items():
        expect[cell] = k
    np.testing.assert_array_equal(d, expect)


@settings(max_examples=200, deadline=None)
@given(grids())
def test_astar_is_optimal_and_valid(case):
    occ, wraps, start, goal = case
    opt = bfs_distances(occ, start, wraps)[goal]
    if opt < 0:
        for f in (astar, bfs):
            with pytest.raises(NoPathFound, match="cannot be reached"):
                f(occ, start, goal, wraps=wraps)
        return
    path = astar(occ, start, goal, wraps=wraps)
    assert len(path) - 1 == opt
    assert_valid_path(path, occ, start, goal, wraps)
    oracle = bfs(occ, start, goal, wraps=wraps)
    assert len(oracle) - 1 == opt
    assert_valid_path(oracle, occ, start, goal, wraps)
    r = astar_search(occ, start, goal, wraps=wraps)
    assert r.cost == opt and r.path.shape == (opt + 1, occ.ndim)
    assert r.path.tolist() == [list(c) for c in path]
    # closed records exactly the expanded cells, all of them free
    assert int(r.closed.sum()) == r.expansions and not np.any(r.closed & occ)


@settings(max_examples=200, deadline=None)
@given(grids(), st.floats(1.0, 5.0))
def test_weighted_astar_within_w_of_optimum(case, w):
    occ, wraps, start, goal = case
    opt = bfs_distances(occ, start, wraps)[goal]
    if opt < 0:
        with pytest.raises(NoPathFound):
            astar(occ, start, goal, wraps=wraps, heuristic_weight=w)
        return
    path = astar(occ, start, goal, wraps=wraps, heuristic_weight=w)
    assert_valid_path(path, occ, start, goal, wraps)
    assert opt <= len(path) - 1 <= w * opt


def test_weighted_astar_bound_is_attained_not_vacuous():
    # On a maze-like grid a large weight does return a longer path than the
    # optimum, so the bound test above checks something real.
    rng = np.random.default_rng(3)
    worse = 0
    for _ in range(40):
        occ = rng.random((30, 30)) < 0.3
        occ[0, 0] = occ[29, 29] = False
        opt = bfs_distances(occ, (0, 0), False)[29, 29]
        if opt < 0:
            continue
        cost = astar_search(occ, (0, 0), (29, 29), wraps=False, heuristic_weight=3.0).cost
        assert opt <= cost <= 3 * opt
        worse += cost > opt
    assert worse > 0


@settings(max_examples=100, deadline=None)
@given(grids())
def test_expansion_limit_is_exact(case):
    occ, wraps, start, goal = case
    try:
        r = astar_search(occ, start, goal, wraps=wraps)
    except NoPathFound:
        return
    again = astar_search(occ, start, goal, wraps=wraps, max_expansions=r.expansions)
    assert again.cost == r.cost
    if r.expansions > 0:
        with pytest.raises(NoPathFound, match=f"limit of {r.expansions - 1} expansions"):
            astar(occ, start, goal, wraps=wraps, max_expansions=r.expansions - 1)


# ----------------------------------------------------------------- heuristic (GD1)


@settings(max_examples=100, deadline=None)
@given(grids())
def test_heuristic_consistent_and_admissible_exhaustively(case):
    occ, wraps, _, goal = case
    check = check_heuristic(occ, goal, wraps=wraps)
    assert check.consistent and check.admissible and check.goal_zero
    # the vectorized check agrees with a loop over every cell and every move
    h = lambda c: int(toroidal_manhattan(c, goal, occ.shape, wraps))  # noqa: E731
    dist = slow_bfs(occ, goal, wraps)
    drops = [
        h(u) - h(v)
        for u in np.ndindex(occ.shape)
        if not occ[u]
        for v in neighbours(u, occ.shape, wraps)
        if not occ[v]
    ]
    assert check.max_step_drop == max(drops, default=0) <= 1
    assert check.max_overestimate == max(h(u) - k for u, k in dist.items()) <= 0
    assert h(goal) == 0


@settings(max_examples=100, deadline=None)
@given(
    st.lists(st.integers(1, 12), min_size=1, max_size=3),
    st.data(),
)
def test_toroidal_manhattan_is_exact_distance_on_empty_grid(shape, data):
    shape = tuple(shape)
    wraps = tuple(data.draw(st.lists(st.booleans(), min_size=len(shape), max_size=len(shape))))
    start = tuple(data.draw(st.integers(0, m - 1)) for m in shape)
    d = bfs_distances(np.zeros(shape, bool), start, wraps)
    cells = np.stack(np.indices(shape), axis=-1)
    np.testing.assert_array_equal(toroidal_manhattan(cells, start, shape, wraps), d)


def test_toroidal_manhattan_formula():
    a = np.array([[0, 0], [359, 0], [10, 350], [180, 180]])
    h = toroidal_manhattan(a, [0, 0], (360, 360))
    expect = [sum(min(abs(x), 360 - abs(x)) for x in row) for row in a.tolist()]
    assert h.tolist() == expect == [0, 1, 20, 360]
    assert toroidal_manhattan(a, [0, 0], (360, 360), wraps=False).tolist() == [0, 359, 360, 360]


def test_wrap_blind_heuristic_is_neither_admissible_nor_consistent_on_a_torus():
    free = np.zeros((12, 12), bool)
    check = check_heuristic(free, (0, 0), wraps=True, heuristic_wraps=False)
    assert not check.consistent and not check.admissible and check.goal_zero
    assert check.max_step_drop == 11 and check.max_overestimate == 20  # h(11,11)=22 vs d=2
    # on a grid that does not wrap the same formula is fine
    assert check_heuristic(free, (0, 0), wraps=False).consistent


def test_wrap_blind_heuristic_makes_astar_suboptimal_on_a_ring():
    ring = np.zeros(20, bool)
    opt = bfs_distances(ring, [2])[17]
    blind = astar_search(ring, [2], [17], heuristic_wraps=False)
    good = astar_search(ring, [2], [17])
    assert good.cost == opt == 5
    assert blind.cost == 15 > opt  # it walked the long way round
    assert blind.expansions > good.expansions


def test_wrap_blind_heuristic_makes_astar_expand_more_on_a_torus():
    # A wall at column 15 leaves only the route across the seam (columns 0/29).
    occ = np.zeros((30, 30), bool)
    occ[:, 15] = True
    good = astar_search(occ, (15, 5), (15, 25))
    blind = astar_search(occ, (15, 5), (15, 25), heuristic_wraps=False)
    assert good.cost == blind.cost == len(bfs(occ, (15, 5), (15, 25))) - 1 == 10
    assert blind.expansions > 5 * good.expansions


# ----------------------------------------------------------------- greedy best-first

TRAP = """
.........
.#######.
.#...G.#.
.#.....#.
.#.....#.
.##.####.
S........
"""


def parse(picture):
    rows = picture.strip().splitlines()
    chars = np.array([list(r) for r in rows])
    occ = chars == "#"
    start = tuple(int(i) for i in np.argwhere(chars == "S")[0])
    goal = tuple(int(i) for i in np.argwhere(chars == "G")[0])
    return occ, start, goal


def test_greedy_best_first_returns_a_longer_path_than_astar():
    occ, start, goal = parse(TRAP)
    greedy = greedy_best_first(occ, start, goal, wraps=False)
    best = astar(occ, start, goal, wraps=False)
    assert_valid_path(greedy, occ, start, goal, (False, False))
    assert len(best) - 1 == bfs_distances(occ, start, False)[goal]
    assert len(greedy) > len(best) + 10


def test_greedy_with_wrap_blind_heuristic_walks_the_long_way():
    ring = np.zeros(20, bool)
    assert len(greedy_best_first(ring, [2], [17], heuristic_wraps=False)) - 1 == 15
    assert len(greedy_best_first(ring, [2], [17])) - 1 == 5


@settings(max_examples=100, deadline=None)
@given(grids())
def test_greedy_paths_are_valid_but_never_shorter_than_optimum(case):
    occ, wraps, start, goal = case
    opt = bfs_distances(occ, start, wraps)[goal]
    if opt < 0:
        with pytest.raises(NoPathFound):
            greedy_best_first(occ, start, goal, wraps=wraps)
        return
    path = greedy_best_first(occ, start, goal, wraps=wraps)
    assert_valid_path(path, occ, start, goal, wraps)
    assert len(path) - 1 >= opt


# ----------------------------------------------------------------- failures and arguments


def test_goal_walled_off_raises():
    occ = np.zeros((9, 9, 9), bool)
    occ[3:6, 3:6, 3:6] = True
    occ[4, 4, 4] = False  # a free cell inside a closed box
    for f in (astar, bfs, greedy_best_first):
        with pytest.raises(NoPathFound, match="cannot be reached"):
            f(occ, (0, 0, 0), (4, 4, 4))


@pytest.mark.parametrize("f", [astar, bfs, greedy_best_first])
def test_blocked_or_outside_ends_raise(f):
    occ = np.zeros((5, 5), bool)
    occ[1, 1] = True
    with pytest.raises(NoPathFound, match="start cell .* blocked"):
        f(occ, (1, 1), (0, 0))
    with pytest.raises(NoPathFound, match="goal cell .* blocked"):
        f(occ, (0, 0), (1, 1))
    with pytest.raises(ValueError, match="outside the grid"):
        f(occ, (0, 5), (0, 0))
    with pytest.raises(ValueError, match="outside the grid"):
        f(occ, (0, 0), (-1, 0))
    assert issubclass(NoPathFound, RappError)


def test_argument_errors():
    occ = np.zeros((5, 5), bool)
    with pytest.raises(ValueError, match="heuristic_weight"):
        astar(occ, (0, 0), (1, 1), heuristic_weight=0.5)
    with pytest.raises(ValueError, match="heuristic_weight"):
        astar(occ, (0, 0), (1, 1), heuristic_weight=float("inf"))
    with pytest.raises(ValueError, match="2 axes"):
        astar(occ, (0, 0, 0), (1, 1))
    with pytest.raises(ValueError, match="one bool per axis"):
        astar(occ, (0, 0), (1, 1), wraps=[True])
    with pytest.raises(ValueError, match="bool array"):
        astar(occ.astype(int), (0, 0), (1, 1))
    with pytest.raises(ValueError, match="max_expansions"):
        astar(occ, (0, 0), (1, 1), max_expansions=-1)
    with pytest.raises(NoPathFound, match="limit of 0"):
        astar(occ, (0, 0), (1, 1), max_expansions=0)


def test_start_equals_goal_and_result_is_frozen():
    occ = np.zeros((4, 4, 4), bool)
    assert astar(occ, (1, 2, 3), (1, 2, 3)) == [(1, 2, 3)]
    r = astar_search(occ, (1, 2, 3), (1, 2, 3), max_expansions=0)
    assert isinstance(r, SearchResult) and r.cost == 0 and r.expansions == 0
    with pytest.raises(AttributeError):
        r.cost = 1
    assert not r.path.flags.writeable and not r.closed.flags.writeable
    assert isinstance(check_heuristic(occ, (0, 0, 0)), HeuristicCheck)


def test_tie_breaking_dives_straight_on_an_open_torus():
    # Many shortest paths have equal f; preferring the larger g expands only
    # the cells of one of them (the figure the book shows for effort).
    free = np.zeros((360, 360), bool)
    r = astar_search(free, (0, 0), (180, 180))
    assert r.cost == 360 and r.expansions == 360


# ----------------------------------------------------------------- compiled A* (numba) = teaching A*


@st.composite
def grids_1_to_4d(draw):
    n = draw(st.integers(1, 4))
    side = {1: 40, 2: 14, 3: 7, 4: 5}[n]
    shape = tuple(draw(st.lists(st.integers(1, side), min_size=n, max_size=n)))
    wraps = tuple(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    density = draw(st.sampled_from([0.0, 0.15, 0.3, 0.45, 0.6]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    occ = rng.random(shape) < density
    start = tuple(int(rng.integers(m)) for m in shape)
    goal = start if draw(st.integers(0, 9)) == 0 else tuple(int(rng.integers(m)) for m in shape)
    occ[start] = occ[goal] = False
    return occ, wraps, start, goal


@settings(max_examples=300, deadline=None)
@given(grids_1_to_4d(), st.sampled_from([1.0, 1.0, 1.5, 2.5]))
def test_compiled_astar_equals_teaching_astar_and_bfs_optimum(case, w):
    occ, wraps, start, goal = case
    opt = bfs_distances(occ, start, wraps)[goal]
    if opt < 0:
        for f in (astar, astar_search):
            with pytest.raises(NoPathFound, match="cannot be reached"):
                f(occ, start, goal, wraps=wraps, heuristic_weight=w)
        return
    path = astar(occ, start, goal, wraps=wraps, heuristic_weight=w)
    r = astar_search(occ, start, goal, wraps=wraps, heuristic_weight=w)
    # Same keys (f, -g, cell), same order: the very same path, not only the same length.
    assert path == [tuple(c) for c in r.path.tolist()]
    assert_valid_path(path, occ, start, goal, wraps)
    if w == 1.0:
        assert len(path) - 1 == opt
    else:
        assert opt <= len(path) - 1 <= w * opt
    # The expansion limit stops at the same expansion as the teaching version.
    assert astar(occ, start, goal, wraps=wraps, heuristic_weight=w, max_expansions=r.expansions) == path
    if r.expansions > 0:
        with pytest.raises(NoPathFound, match=f"limit of {r.expansions - 1} expansions"):
            astar(occ, start, goal, wraps=wraps, heuristic_weight=w, max_expansions=r.expansions - 1)


#: 2-D and 3-D grids big enough for wide open lists: odd and even sides, each axis wrapping or
#: not, walls as dense as a maze or none.
larger_grids = grids(sides={2: 48, 3: 13}, densities=(0.0, 0.2, 0.35, 0.5), min_side=2)


@settings(max_examples=80, deadline=None)
@given(larger_grids, st.sampled_from([1.0, 1.0, 1.0, 1.7]))
def test_compiled_astar_is_optimal_against_the_slow_bfs(case, w):
    # The compiled kernel (bucket queue for w = 1, rapp.heap for w > 1; its open list starts
    # small and grows here) against the slow deque BFS of this file, sharing no code with it:
    # the optimal length, every step a unit move between free cells, the teaching search's path.
    pytest.importorskip("numba")
    from rapp.kernels import search_numba

    assert search_numba.kernel() is not None  # numba imported: astar runs the kernel
    occ, wraps, start, goal = case
    opt = slow_bfs(occ, start, wraps).get(goal)
    if opt is None:
        with pytest.raises(NoPathFound, match="cannot be reached"):
            astar(occ, start, goal, wraps=wraps, heuristic_weight=w)
        return
    path = astar(occ, start, goal, wraps=wraps, heuristic_weight=w)
    assert_valid_path(path, occ, start, goal, wraps)
    if w == 1.0:
        assert len(path) - 1 == opt
    else:
        assert opt <= len(path) - 1 <= w * opt
    r = astar_search(occ, start, goal, wraps=wraps, heuristic_weight=w)
    assert path == [tuple(c) for c in r.path.tolist()]
    # The same expansions: the limit at the teaching search's count still finds the path.
    assert astar(occ, start, goal, wraps=wraps, heuristic_weight=w, max_expansions=r.expansions) == path


def test_astar_is_compiled_when_numba_is_installed():
    pytest.importorskip("numba")
    from rapp.kernels import search_numba

    assert search_numba.kernel() is not None


def test_astar_falls_back_to_the_teaching_version_without_numba(monkeypatch):
    from rapp.kernels import search_numba

    occ = np.zeros((12, 12), bool)
    occ[:, 6] = True
    occ[3, 6] = False
    fast = astar(occ, (0, 0), (11, 11))
    search_numba.kernel.cache_clear()
    try:
        with monkeypatch.context() as m:
            m.setitem(sys.modules, "numba", None)  # import numba now raises ImportError
            assert search_numba.kernel() is None
            slow = astar(occ, (0, 0), (11, 11))
            assert slow == fast and len(fast) - 1 == bfs_distances(occ, (0, 0))[11, 11]
            with pytest.raises(NoPathFound, match="limit of 0"):
                astar(occ, (0, 0), (11, 11), max_expansions=0)
    finally:
        search_numba.kernel.cache_clear()  # later tests get the compiled kernel back


def test_compiled_astar_on_a_4d_torus_and_an_open_plateau():
    rng = np.random.default_rng(11)
    occ = rng.random((9, 8, 7, 6)) < 0.3
    occ[0, 0, 0, 0] = occ[4, 4, 3, 3] = False
    opt = bfs_distances(occ, (0, 0, 0, 0))[4, 4, 3, 3]
    assert opt > 0
    path = astar(occ, (0, 0, 0, 0), (4, 4, 3, 3))
    assert len(path) - 1 == opt
    assert path == [tuple(c) for c in astar_search(occ, (0, 0, 0, 0), (4, 4, 3, 3)).path.tolist()]
    # Ties toward the larger g: on an open torus the compiled search dives straight too.
    free = np.zeros((360, 360), bool)
    path = astar(free, (0, 0), (180, 180))
    assert path == [tuple(c) for c in astar_search(free, (0, 0), (180, 180)).path.tolist()]
    assert len(path) - 1 == 360
