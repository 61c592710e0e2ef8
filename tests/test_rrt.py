"""RRT in joint space (rapp.rrt): every path is collision-free, the tree is a valid RRT, seeded."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm, Circle, NoPathFound, Polygon, collides, segment_collision_free
from rapp.cases.rrt_report import alpha_beta_experiment
from rapp.paths import path_length as path_cost
from rapp.rrt import plan_rrt, rrt


def wrapped(d):
    return (np.asarray(d) + np.pi) % (2 * np.pi) - np.pi


def densely_free(arm, path, obstacles, per_edge=400):
    """Slow, independent check: sample every straight edge densely and test each sample."""
    path = np.asarray(path)
    t = np.linspace(0.0, 1.0, per_edge)[:, None, None]
    q = path[:-1][None] + t * (path[1:] - path[:-1])[None]
    return not collides(arm, q.reshape(-1, arm.n), obstacles).any()


ARM2 = Arm([1.0, 0.8])
OBSTACLES2 = [Circle((1.2, 1.0), 0.35), Polygon.rectangle((-1.6, -0.4), 0.5, 0.8, 0.3)]
START2 = np.array([0.0, 0.0])
GOAL2 = np.array([2.3, 0.4])  # reaching the goal means swinging past the circle


@pytest.mark.slow
@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 10**6), step=st.floats(0.1, 0.6), steer=st.sampled_from(["step", "fraction"]))
def test_path_is_collision_free_and_joins_start_to_goal(seed, step, steer):
    res = rrt(ARM2, START2, GOAL2, OBSTACLES2, step=step, goal_bias=0.2, goal_threshold=0.1,
              seed=seed, steer=steer, max_iterations=4000)
    assert res.success
    np.testing.assert_array_equal(res.path[0], START2)
    # The exact goal is appended; the path is unwrapped, so free joints may end 2 pi k away.
    np.testing.assert_allclose(wrapped(res.path[-1] - GOAL2), 0.0, atol=1e-12)
    assert densely_free(ARM2, res.path, OBSTACLES2)
    assert res.cost == pytest.approx(path_cost(res.path))
    assert res.cost >= np.linalg.norm(wrapped(GOAL2 - START2)) - 1e-12


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6), gx=st.floats(-0.9, 1.5), gy=st.floats(0.5, 1.6))
def test_task_space_goal_ends_within_threshold(seed, gx, gy):
    goal_xy = np.array([gx, gy])
    if np.linalg.norm(goal_xy) > 1.75:
        goal_xy *= 1.75 / np.linalg.norm(goal_xy)
    res = rrt(ARM2, START2, None, OBSTACLES2[1:], goal_xy=goal_xy, step=0.3, goal_bias=0.3,
              goal_threshold=0.05, seed=seed, max_iterations=4000)
    assert np.linalg.norm(ARM2.end_effector(res.path[-1]) - goal_xy) <= 0.05
    assert densely_free(ARM2, res.path, OBSTACLES2[1:])


def test_tree_is_an_rrt():
    """Parent map is a tree rooted at the start; each parent is the nearest earlier node.

    For ``steer="step"`` the new node lies on the segment from the node nearest the
    target toward the target, and by the triangle inequality that node is then also
    the nearest earlier node to the new node: a check of the vectorized (and batched)
    nearest-neighbour search that does not look inside it.
    """
    arm = Arm([1.0, 0.8, 0.5])  # free joints: distances are wrapped
    obs = [Circle((0.0, 1.4), 0.3), Polygon.rectangle((1.0, -1.0), 0.4, 0.4, 0.5)]
    res = rrt(arm, [0.0, 0.0, 0.0], None, obs, goal_xy=(-1.5, 0.6), step=0.25,
              goal_bias=0.1, seed=3, goal_threshold=0.05)
    nodes, parent = res.nodes, res.parent
    assert parent[0] == -1 and np.all(parent[1:] < np.arange(1, len(parent)))
    assert np.all((nodes >= -np.pi) & (nodes < np.pi))
    d_parent = np.linalg.norm(wrapped(nodes[1:] - nodes[parent[1:]]), axis=-1)
    assert np.all(d_parent <= 0.25 + 1e-12)
    for i in range(1, len(nodes)):  # a test oracle, not library code: loop is fine
        d = np.linalg.norm(wrapped(nodes[:i] - nodes[i]), axis=-1)
        assert d_parent[i - 1] <= d.min() + 1e-9
    edges = np.stack((nodes[parent[1:]], nodes[parent[1:]] + wrapped(nodes[1:] - nodes[parent[1:]])), 1)
    t = np.linspace(0, 1, 60)[:, None, None]
    samples = edges[:, 0][None] + t * (edges[:, 1] - edges[:, 0])[None]
    assert not collides(arm, samples, obs).any()  # every tree edge, not just the path


def test_limited_joints_stay_within_limits():
    # The disc blocks the stretched arm; the way round is to fold joint 2 past |q2| ~ 1.
    arm = Arm([1.0, 1.0], [(-0.5, 2.0), (-1.5, 1.5)])
    obs = [Circle((1.85 * np.cos(1.0), 1.85 * np.sin(1.0)), 0.1)]
    assert not segment_collision_free(arm, [0.0, 0.0], [1.8, 0.9], obs)
    res = rrt(arm, [0.0, 0.0], [1.8, 0.9], obs, step=0.2, seed=5)
    assert arm.within_limits(res.nodes).all() and arm.within_limits(res.path).all()
    assert densely_free(arm, res.path, obs)
    assert np.abs(res.path[:, 1]).max() > 1.0


def test_wraps_the_short_way_across_the_seam():
    arm = Arm([1.0, 1.0])
    res = rrt(arm, [3.0, 0.0], [-3.0, 0.0], [], step=0.05, goal_bias=0.5, seed=0)
    short = 2 * np.pi - 6.0  # 0.283 the short way, 6.0 the long way
    assert res.cost < 2 * short
    steps = np.linalg.norm(np.diff(res.path, axis=0), axis=-1)
    assert steps.max() <= 0.05 + 1e-12  # unwrapped: no 2 pi jumps between waypoints
    assert np.allclose(wrapped(res.path[-1] - [-3.0, 0.0]), 0.0)


def test_same_seed_same_tree_other_seed_other_tree():
    kw = dict(step=0.3, goal_bias=0.1, seed=42, goal_threshold=0.1)
    a = rrt(ARM2, START2, GOAL2, OBSTACLES2, **kw)
    b = rrt(ARM2, START2, GOAL2, OBSTACLES2, **kw)
    np.testing.assert_array_equal(a.nodes, b.nodes)
    np.testing.assert_array_equal(a.parent, b.parent)
    np.testing.assert_array_equal(a.path, b.path)
    c = rrt(ARM2, START2, GOAL2, OBSTACLES2, **{**kw, "seed": 43})
    assert c.nodes.shape != a.nodes.shape or not np.array_equal(c.nodes, a.nodes)


def test_shorter_budget_gives_a_prefix_of_the_tree():
    full = rrt(ARM2, START2, [3.0, 3.0], OBSTACLES2, step=0.2, goal_bias=0.0, seed=1,
               max_iterations=150, raise_on_failure=False)
    part = rrt(ARM2, START2, [3.0, 3.0], OBSTACLES2, step=0.2, goal_bias=0.0, seed=1,
               max_iterations=70, raise_on_failure=False)
    m = len(part.nodes)
    np.testing.assert_array_equal(full.nodes[:m], part.nodes)
    assert part.iterations == 70 and full.iterations == 150


@settings(max_examples=25, deadline=None)
@given(d=st.floats(0.3, 2.5), step=st.floats(0.05, 0.5), angle=st.floats(0, 2 * np.pi))
def test_goal_bias_one_walks_straight_in_dist_over_alpha_steps(d, step, angle):
    """Always targeting the goal, free space: ceil((d - threshold) / alpha) iterations."""
    arm = Arm([1.0, 1.0], [(-4.0, 4.0)] * 2)
    start = np.array([0.0, 0.0])
    goal = d * np.array([np.cos(angle), np.sin(angle)])
    thr = 0.01
    res = rrt(arm, start, goal, [], step=step, goal_bias=1.0, goal_threshold=thr, seed=0)
    expected = math.ceil((d - thr) / step)
    assert abs(res.iterations - expected) <= 1  # float rounding at an exact multiple
    assert res.cost == pytest.approx(d)  # a straight line


@settings(max_examples=25, deadline=None)
@given(d=st.floats(0.3, 2.5), alpha=st.floats(0.05, 0.9))
def test_report_fraction_rule_closes_the_gap_geometrically(d, alpha):
    """Seed 003's q_new = q_near + alpha (q_target - q_near): d_k = (1 - alpha)^k d."""
    arm = Arm([1.0, 1.0], [(-4.0, 4.0)] * 2)
    thr = 0.01
    res = rrt(arm, [0.0, 0.0], [d, 0.0], [], step=alpha, goal_bias=1.0, goal_threshold=thr,
              steer="fraction", seed=0)
    expected = math.ceil(math.log(thr / d) / math.log(1 - alpha))
    assert abs(res.iterations - expected) <= 1
    np.testing.assert_allclose(res.path[1:-1, 0], d * (1 - (1 - alpha) ** np.arange(1, len(res.path) - 1)))


def test_no_path_when_the_goal_is_enclosed():
    box = Polygon.rectangle((1.3, -0.2), 0.4, 0.4)  # the goal point (1.5, 0) is inside
    with pytest.raises(NoPathFound):
        rrt(ARM2, [np.pi / 2, 0.0], None, [box], goal_xy=(1.5, 0.0), goal_threshold=0.05,
            step=0.3, max_iterations=300, seed=0)
    res = rrt(ARM2, [np.pi / 2, 0.0], None, [box], goal_xy=(1.5, 0.0), goal_threshold=0.05,
              step=0.3, max_iterations=300, seed=0, raise_on_failure=False)
    assert not res.success and res.path.shape == (0, 2) and res.cost == np.inf
    assert res.iterations == 300 and len(res.nodes) > 1


def test_no_path_when_the_joint_goal_is_walled_off():
    # A limited 1-link arm: the wall at angle 1 splits its joint interval in two.
    arm = Arm([1.0], [(-2.0, 2.0)])
    u, v = np.array([np.cos(1.0), np.sin(1.0)]), np.array([-np.sin(1.0), np.cos(1.0)])
    wall = Polygon.rectangle(0.4 * u - 0.1 * v, 0.2, 0.2, 1.0)  # straddles the ray at angle 1
    assert collides(arm, [[1.0]], [wall]).all() and not collides(arm, [[0.0], [1.8]], [wall]).any()
    with pytest.raises(NoPathFound):
        rrt(arm, [0.0], [1.8], [wall], step=0.1, max_iterations=400)


def test_immediate_failures():
    with pytest.raises(NoPathFound, match="start"):
        rrt(ARM2, [0.5, 0.0], GOAL2, [Circle((0.5, 0.25), 0.1)])
    res = rrt(ARM2, START2, None, [], goal_xy=(3.0, 0.0), raise_on_failure=False)
    assert not res.success and res.iterations == 0  # beyond reach: no search
    with pytest.raises(ValueError):
        rrt(ARM2, START2, GOAL2, [], step=1.5, steer="fraction")
    with pytest.raises(ValueError):
        rrt(ARM2, START2, None, [])


def test_plan_rrt_adapter_matches_the_planner_call():
    goals = np.array([[2.3, 0.4], [-2.0, -0.4]])  # e.g. two IK solutions: either will do
    path = plan_rrt(ARM2, OBSTACLES2, START2, goals,
                    settings={"step": 0.3, "seed": 7, "cells": 64, "goal_threshold": 0.05})
    assert path.shape[1] == 2 and np.array_equal(path[0], START2)
    assert np.min(np.linalg.norm(wrapped(path[-1] - goals), axis=-1)) < 1e-12
    assert densely_free(ARM2, path, OBSTACLES2)


def test_alpha_beta_experiment_aggregates_seeded_runs():
    arm = Arm([1.0, 1.0])
    goal = np.array([2.0, 0.5])
    goal_xy = arm.end_effector(goal)
    obs = [Circle((-1.5, -1.0), 0.3)]
    out = alpha_beta_experiment(arm, [0.0, 0.0], goal_xy, obs, [0.5, 1.0], [0.3, 1.0], 3,
                                seed=9, goal=goal, max_iterations=300)
    assert out["success_rate"].shape == (2, 2) and out["mean_cost"].shape == (2, 2)
    # alpha = beta = 1: the first sample is the goal and the step reaches it.
    assert out["success_rate"][1, 1] == 1.0 and out["mean_iterations"][1, 1] == 1.0
    assert out["mean_cost"][1, 1] == pytest.approx(np.linalg.norm(goal))
    seeds = np.random.SeedSequence(9).spawn(3)
    runs = [rrt(arm, [0.0, 0.0], goal, obs, goal_xy=goal_xy, step=0.5, goal_bias=0.3,
                steer="fraction", goal_threshold=0.05, max_iterations=300, seed=s,
                raise_on_failure=False) for s in seeds]
    ok = [r.success for r in runs]
    assert out["success_rate"][0, 0] == pytest.approx(np.mean(ok))
    assert out["mean_iterations"][0, 0] == pytest.approx(np.mean([r.iterations for r in runs]))
    if any(ok):
        assert out["mean_cost"][0, 0] == pytest.approx(np.mean([r.cost for r in runs if r.success]))


def test_rrt_stops_at_its_time_budget_and_the_planner_passes_it():
    """A budget far too short for the problem ends the run early, as a planning failure."""
    import time as _time

    import rapp
    from rapp.errors import NoPathFound as _NoPath

    arm = rapp.Arm([1.0, 1.0])
    walls = [rapp.Circle((0.0, 1.5), 0.45), rapp.Circle((0.0, -1.5), 0.45)]
    t0 = _time.perf_counter()
    res = rapp.rrt(arm, [0.0, 0.0], [np.pi, 0.0], walls, step=0.01, goal_bias=0.0,
                   max_iterations=10**9, time_budget=0.2, raise_on_failure=False)
    assert not res.success and _time.perf_counter() - t0 < 5.0
    with pytest.raises(ValueError, match="time_budget"):
        rapp.rrt(arm, [0.0, 0.0], [1.0, 0.0], [], time_budget=-1.0)
    scenario = {"arm": {"link_lengths": [1.0, 1.0]}, "start": [0.0, 0.0], "goal": {"joints": [3.14, 0.0]},
                "units": {"angle": "rad"}, "obstacles": [{"type": "circle", "center": [0.0, 1.5], "radius": 0.45},
                                                        {"type": "circle", "center": [0.0, -1.5], "radius": 0.45}],
                "planner": {"algorithm": "rrt", "step": 0.01, "goal_bias": 0.0, "max_iterations": 1000000,
                            "time_budget": 0.2}}
    t0 = _time.perf_counter()
    with pytest.raises(_NoPath, match=r"RRT stopped: time_budget 0.2 s spent after \d+ iterations"):
        rapp.plan(scenario)
    assert _time.perf_counter() - t0 < 10.0
