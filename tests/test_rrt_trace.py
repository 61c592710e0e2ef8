"""rapp.rrt(..., trace=[...]) records the RRT it grows, iteration by iteration, and changes nothing:
the same seed gives the same path, nodes and parent map with or without a trace; the records that
added a node are the tree's nodes, in order, with their parents; every rejected edge really is one
that cannot be certified collision-free; every nearest node is the nearest one of the tree as it
stood. rapp.plotting.plot_rrt_step draws any record, and animate_rrt all of them.
"""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from rapp import Arm, Circle, NoPathFound, Polygon, segment_collision_free  # noqa: E402
from rapp.cases import rrt_report  # noqa: E402
from rapp.plotting import animate_rrt, plot_rrt_step  # noqa: E402
from rapp.rrt import RRTStep, rrt  # noqa: E402

FREE2 = Arm([1.0, 0.8])
LIMITED2 = Arm([1.0, 0.8], [(-0.5, 2.5), (-2.0, 2.0)])
FREE3 = Arm([1.0, 0.8, 0.5])
OBSTACLES = [Circle((1.2, 1.0), 0.35), Polygon.rectangle((-1.6, -0.4), 0.5, 0.8, 0.3)]


def grow(arm, goal, goal_xy, **kw):
    """The same run twice, without and with a trace."""
    start = np.zeros(arm.n)
    plain = rrt(arm, start, goal, OBSTACLES, goal_xy=goal_xy, raise_on_failure=False, **kw)
    steps = []
    traced = rrt(arm, start, goal, OBSTACLES, goal_xy=goal_xy, raise_on_failure=False,
                 trace=steps, **kw)
    return plain, traced, steps


problems = st.sampled_from([
    (FREE2, [2.3, 0.4], None),
    (LIMITED2, [2.3, 0.4], None),
    (FREE2, [[2.3, 0.4], [-2.5, -0.3]], None),  # two goal configurations
    (FREE2, None, [-0.9, 1.2]),  # task-space goal: Gauss-Newton targets
    (FREE3, [2.0, 0.5, -0.5], None),
    (FREE3, [2.0, 0.5, -0.5], [-1.2, 1.0]),  # both: joint targets, task-space test
])


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(problem=problems, seed=st.integers(0, 10**6), step=st.floats(0.1, 0.9),
       steer=st.sampled_from(["step", "fraction"]), bias=st.sampled_from([0.0, 0.1, 0.5, 1.0]),
       budget=st.integers(1, 400))
def test_a_trace_changes_nothing_and_records_the_tree(problem, seed, step, steer, bias, budget):
    arm, goal, goal_xy = problem
    if goal is None and bias == 0.0:
        bias = 0.2
    plain, traced, steps = grow(arm, goal, goal_xy, step=step, steer=steer, goal_bias=bias,
                                max_iterations=budget, seed=seed)
    # Identical results: the recording draws no random numbers and changes no decision.
    assert traced.success == plain.success and traced.iterations == plain.iterations
    np.testing.assert_array_equal(traced.nodes, plain.nodes)
    np.testing.assert_array_equal(traced.parent, plain.parent)
    np.testing.assert_array_equal(traced.path, plain.path)
    assert traced.cost == plain.cost or (np.isinf(traced.cost) and np.isinf(plain.cost))
    assert all(isinstance(s, RRTStep) for s in steps)

    # One record per iteration, in order (plus the joins to a joint goal).
    its = [s.iteration for s in steps if not s.join]
    assert its == list(range(1, traced.iterations + 1))
    assert all(s.iteration >= 0 for s in steps)

    # The accepted records are the tree's nodes, in order, each with its parent.
    added = [s for s in steps if s.accepted]
    assert [s.node for s in added] == list(range(1, len(traced.nodes)))
    assert [s.nearest for s in added] == traced.parent[1:].tolist()
    for s in added:
        if s.join:  # the goal is stored as given, the edge ends on it unwrapped
            np.testing.assert_allclose(arm.wrap(s.new), traced.nodes[s.node], atol=1e-12)
        else:
            np.testing.assert_array_equal(arm.wrap(s.new), traced.nodes[s.node])
    assert all(s.node == -1 for s in steps if not s.accepted)

    # Every rejected edge is truly not certifiable; every accepted one is.
    blocked = [s for s in steps if s.status == "blocked"]
    if blocked:
        a = traced.nodes[[s.nearest for s in blocked]]
        b = np.array([s.new for s in blocked])
        assert not segment_collision_free(arm, a, b, OBSTACLES).any()
    if added:
        a = traced.nodes[[s.nearest for s in added]]
        b = np.array([s.new for s in added])
        assert segment_collision_free(arm, a, b, OBSTACLES).all()

    # The nearest node is the nearest of the tree as it stood, and the step is the steering rule.
    m = 1
    goals = None if goal is None else np.asarray(goal, dtype=float).reshape(-1, arm.n)
    for s in steps:
        if s.join:
            assert goals is not None and s.goal_biased
            assert np.min(np.abs(goals - s.target).max(-1)) == 0.0
        else:
            d = np.linalg.norm(arm.joint_delta(traced.nodes[:m], s.target), axis=-1)
            assert d[s.nearest] <= d.min() + 1e-12 and s.nearest < m
            near = traced.nodes[s.nearest]
            moved = np.linalg.norm(s.new - near)
            full = d[s.nearest]
            expected = min(step, full) if steer == "step" else step * full
            assert moved == pytest.approx(expected, abs=1e-9)
            if s.goal_biased and goals is not None:
                assert np.min(np.abs(goals - s.target).max(-1)) == 0.0
            assert arm.within_limits(arm.wrap(s.target)).all()
        m += s.accepted
    assert m == len(traced.nodes)


def test_no_trace_by_default_and_a_failed_run_is_recorded_too():
    # Seed 003's problem with beta = 1: the tree creeps along the blocked straight segment.
    arm = rrt_report.seed_arm()
    s, g = (rrt_report.report_to_rapp(t) for t in (rrt_report.START_THETA, rrt_report.GOAL_THETA))
    obs = [rrt_report.seed_square()]
    steps = []
    res = rrt(arm, s, g, obs, step=0.25, goal_bias=1.0, steer="fraction", max_iterations=50,
              raise_on_failure=False, trace=steps)
    assert not res.success and len(steps) == 50
    assert all(st.goal_biased for st in steps)
    assert [st.status for st in steps].count("added") == len(res.nodes) - 1 == 2
    assert all(st.status == "blocked" for st in steps[2:])
    steps2 = []
    with pytest.raises(NoPathFound):
        rrt(arm, s, g, obs, step=0.25, goal_bias=1.0, steer="fraction", max_iterations=50,
            trace=steps2)
    assert len(steps2) == 50


def test_plot_rrt_step_draws_every_kind_of_step_and_the_end():
    arm = Arm([1.0, 1.0])
    obstacles = [Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25)]
    steps = []
    res = rrt(arm, [0.0, 0.0], [-2.96, -1.53], obstacles, step=0.5, goal_bias=0.1, seed=0,
              trace=steps)
    kinds = {s.status for s in steps}
    assert {"added", "blocked"} <= kinds
    picks = [next(i for i, s in enumerate(steps) if s.status == "blocked"),
             next(i for i, s in enumerate(steps) if s.goal_biased), 0, len(steps) - 1, len(steps)]
    for k in picks:
        ax = plot_rrt_step(arm, res, steps, k, goal=[-2.96, -1.53])
        assert ax.get_xlabel() == "θ1 (rad)" and ax.get_ylabel() == "θ2 (rad)"
        assert ax.get_legend() is not None and ax.get_title()
        plt.close(ax.figure)
    for bad in (-1, len(steps) + 1):
        with pytest.raises(ValueError):
            plot_rrt_step(arm, res, steps, bad)
    with pytest.raises(ValueError):  # a trace of another run
        plot_rrt_step(arm, rrt(arm, [0.0, 0.0], [0.3, 0.0], [], seed=0), steps, 0)
    anim = animate_rrt(arm, res, steps)
    assert anim._save_count == len(steps) + 1
    assert anim._fig.get_size_inches()[0] * anim._fig.dpi >= 600  # the book's minimum width
    plt.close(anim._fig)
