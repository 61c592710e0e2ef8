"""The compiled loops of RRT-Connect, RRT* and PRM (rapp.kernels.sampling_numba) against the numpy
loops they replaced.

Properties: from the same seed both grow the same trees (roadmaps), node for node and bit for
bit, and return the same path (hypothesis over arms of 2 to 4 joints, free and limited, discs
and polygons, one or several goals, steps from 0.05 to 0.5 rad); every path of the compiled
loops passes rapp.verify's certificate, the numpy certificate of rapp.reference and a dense
sampled check, over many seeds; budgets, the node limit and the certification limit are
answered as the numpy loops answer them.
"""

from __future__ import annotations


import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import rapp
from rapp import reference
from rapp.kernels import sampling as sampling_kernel
from rapp.errors import CertificationLimit, NoPathFound
from rapp.prm import prm
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

pytestmark = pytest.mark.skipif(sampling_kernel.kernels() is None, reason="numba is not installed")

# The 3-link problem of the benchmarks, defined once in benchmarks/bench_core.py.
from tests.scenes import LINKS3, OBSTACLES3, dense_free, scattered_obstacles  # noqa: E402


def both(monkeypatch, *args, planner=rrt_connect, **kw):
    """The compiled run and the numpy run (the compiled loops switched off) of ``planner``;
    an exception is returned, not raised, so that both can be compared."""
    out = []
    for compiled in (True, False):
        with monkeypatch.context() as m:
            if not compiled:
                m.setattr(sampling_kernel, "kernels", lambda: None)
            try:
                out.append(planner(*args, **kw))
            except (NoPathFound, CertificationLimit) as e:
                out.append(e)
    return out


#: Each planner with settings small enough for a property test (and RRT*'s goal region wide
#: enough that it often succeeds).
LOOPS = [rrt_connect, rrt_star, prm]
SMALL = {
    "rrt_connect": (rrt_connect, lambda step: {"step": step, "max_iterations": 300}),
    "rrt_star": (rrt_star, lambda step: {"step": step, "max_iterations": 300, "goal_threshold": 0.3}),
    # a rewiring radius beyond the step (the grid's cells widen with it), and one below it
    "rrt_star_radius": (rrt_star, lambda step: {"step": step, "radius": 2.5 * step,
                                                "max_iterations": 300, "goal_threshold": 0.3}),
    "rrt_star_small_radius": (rrt_star, lambda step: {"step": step, "radius": 0.5 * step,
                                                      "max_iterations": 300, "goal_threshold": 0.3}),
    "prm": (prm, lambda step: {"samples": 60, "max_iterations": 40}),
}


def assert_same(fast, slow):
    if isinstance(slow, Exception):
        assert type(fast) is type(slow) and str(fast) == str(slow)
        return
    assert fast.success == slow.success and fast.iterations == slow.iterations
    assert np.array_equal(fast.nodes, slow.nodes)
    assert np.array_equal(fast.parent, slow.parent)
    assert np.array_equal(fast.path, slow.path)


def assert_verified(arm, res, start, goals, obstacles):
    """The path joins the exact start to a goal, and three checks find it free."""
    assert np.array_equal(res.path[0], start)
    goals = np.atleast_2d(goals)
    assert np.abs(arm.joint_delta(res.path[-1], goals)).max(axis=-1).min() < 1e-12
    assert rapp.path_collision_free(arm, res.path, obstacles)  # rapp.verify's certificate
    assert reference.segment_collision_free(arm, res.path[:-1], res.path[1:], obstacles).all()
    assert dense_free(arm, res.path, obstacles)


@st.composite
def problems(draw):
    n = draw(st.integers(2, 4))
    lengths = draw(st.lists(st.floats(0.3, 1.0), min_size=n, max_size=n))
    limited = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    arm = rapp.Arm(lengths, [(-2.5, 2.5) if lim else None for lim in limited])
    reach = sum(lengths)
    obstacles = scattered_obstacles(draw, reach, count=(0, 4), near=(0.3, 1.1), radius=(0.05, 0.4), side=(0.1, 0.5))
    angles = st.lists(st.floats(-2.4, 2.4), min_size=n, max_size=n)
    start = np.array(draw(angles))
    goals = np.array(draw(st.lists(angles, min_size=1, max_size=3)))
    step = draw(st.floats(0.05, 0.5))
    return arm, obstacles, start, goals, step


@pytest.mark.parametrize("name", [pytest.param(name, marks=pytest.mark.slow) if name.endswith("radius") else name
                                  for name in SMALL])  # the radius variants: seconds, make test
@settings(max_examples=25, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(problem=problems(), seed=st.integers(0, 2**32 - 1))
def test_the_compiled_loops_grow_the_numpy_trees(name, problem, seed, monkeypatch):
    arm, obstacles, start, goals, step = problem
    planner, settings_of = SMALL[name]
    fast, slow = both(monkeypatch, arm, start, goals, obstacles, planner=planner, seed=seed,
                      raise_on_failure=False, **settings_of(step))
    assert_same(fast, slow)
    if not isinstance(fast, Exception) and fast.success:
        assert_verified(arm, fast, start, goals, obstacles)


BENCHMARK = {  # the settings of benchmarks/bench_planners.py
    rrt_connect: {"step": 0.1},
    rrt_star: {"step": 0.2, "radius": 0.4, "max_iterations": 5000},
    prm: {},
}


@pytest.mark.parametrize("planner, seeds", [
    (rrt_connect, range(6)), (prm, range(6)), (rrt_star, range(1)),
    pytest.param(rrt_connect, range(6, 40), marks=pytest.mark.slow),
    pytest.param(prm, range(6, 40), marks=pytest.mark.slow),
    pytest.param(rrt_star, range(1, 7), marks=pytest.mark.slow),
], ids=lambda x: x.__name__ if callable(x) else f"seeds{len(x)}")
def test_the_benchmark_problem_same_trees_and_verified_paths(planner, seeds, monkeypatch):
    arm = rapp.Arm(LINKS3)
    for seed in seeds:
        fast, slow = both(monkeypatch, arm, (0, 0, 0), (-2, 0.5, 0.5), OBSTACLES3,
                          planner=planner, seed=seed, raise_on_failure=False, **BENCHMARK[planner])
        assert_same(fast, slow)
        assert fast.success, seed
        assert_verified(arm, fast, np.zeros(3), [(-2, 0.5, 0.5)], OBSTACLES3)


@pytest.mark.slow
@pytest.mark.parametrize("radius", [None, 0.1])
def test_rrt_star_on_the_benchmark_with_the_step_as_radius_and_below(radius, monkeypatch):
    # Thousands of nodes: near sets come from the grid, whose cells are a step wide here.
    arm = rapp.Arm(LINKS3)
    fast, slow = both(monkeypatch, arm, (0, 0, 0), (-2, 0.5, 0.5), OBSTACLES3, planner=rrt_star,
                      seed=3, step=0.2, radius=radius, max_iterations=3000, raise_on_failure=False)
    assert_same(fast, slow)
    assert fast.success
    assert_verified(arm, fast, np.zeros(3), [(-2, 0.5, 0.5)], OBSTACLES3)


@pytest.mark.slow
@pytest.mark.parametrize("algorithm", ["rrt_connect", "prm", "rrt_star"])
def test_plans_with_the_compiled_loops_pass_rapp_verify_over_many_seeds(algorithm):
    d = rapp.load_scenario("three_link").to_dict()
    for seed in range(20 if algorithm != "rrt_star" else 5):
        d["planner"] = {"algorithm": algorithm, "seed": seed}
        plan = rapp.plan(d)
        assert plan.report.ok, (seed, str(plan.report))


@pytest.mark.parametrize("planner", LOOPS, ids=lambda p: p.__name__)
def test_budgets_are_those_of_the_numpy_loop(planner, monkeypatch):
    s = rapp.load_scenario("no_solution")   # no path exists: the budget decides
    # PRM's node cap at 2000 keeps the numpy loop's roadmap small (seconds at the default
    # cap) and still comes after the iteration caps 63-65, which the kernel must match.
    kw = {"samples": 30, "max_samples": 2000} if planner is prm else {}
    for k in (1, 15, 16, 17, 63, 64, 65, 200):
        fast, slow = both(monkeypatch, s.arm, s.start_array, s.goal_q, s.obstacles,
                          planner=planner, max_iterations=k, raise_on_failure=False, **kw)
        assert_same(fast, slow)
        assert not fast.success and fast.iterations <= k
    fast, slow = both(monkeypatch, s.arm, s.start_array, s.goal_q, s.obstacles, planner=planner,
                      max_iterations=50, **kw)
    assert_same(fast, slow)
    res = planner(s.arm, s.start_array, s.goal_q, s.obstacles, max_iterations=10**7,
                  time_budget=0.2, raise_on_failure=False, **kw)
    assert not res.success and 0 < res.iterations < 10**7


@pytest.mark.slow
def test_the_node_limit_is_that_of_the_numpy_loop(monkeypatch):
    # A wall between start and goal: the trees grow until they hold MAX_NODES.
    s = rapp.load_scenario("no_solution")
    fast, slow = both(monkeypatch, s.arm, s.start_array, s.goal_q, s.obstacles, step=0.05,
                      max_iterations=10**6)
    assert "its trees reached their 20000 nodes" in str(slow)
    assert_same(fast, slow)


@pytest.mark.parametrize("planner", LOOPS, ids=lambda p: p.__name__)
def test_the_certification_limit_is_raised_with_the_numpy_message(planner, monkeypatch):
    # Links of 1e6 beside a clearance of 1: an edge needs 2**18 pieces.
    arm = rapp.Arm([1e6, 1e6])
    kw = {"samples": 20, "seed": 1} if planner is prm else {}
    fast, slow = both(monkeypatch, arm, [0.0, 0.0], [0.5, 0.0], [rapp.Circle((0.0, -2.0), 1.0)],
                      planner=planner, **kw)
    assert isinstance(slow, CertificationLimit)
    assert_same(fast, slow)
