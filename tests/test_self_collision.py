"""Links that do not cross (issue 31, item 4): ``Arm(self_collision=True)`` keeps every
non-adjacent pair of links ``r_i + r_j + margin`` apart, in ``collides``, certified segments,
every planner, ``rapp.plan``, verification and scenario files.

The oracles are plain Python: the segment distance as the minimum of a convex function over the
unit square (the lines' meeting point by Cramer's rule, else the square's edges), checked
besides against dense samples of the links; and dense samples of motions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import rapp
from rapp.collision import (collides, segment_collision_free, segment_distance, self_clearance,
                            self_gaps, self_pairs, self_segment_free)
from rapp.cspace import JointGrid, grid_q
from rapp.errors import InvalidValue
from rapp.grid_route import self_collision_cells
from rapp.planners import PLANNERS, run


def _point_segment(p, a, b) -> float:
    """Distance from p to segment ab, plain Python (clamped projection)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = min(max(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
    return math.hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1])


def _oracle_distance(p1, q1, p2, q2) -> float:
    """Distance between segments p1q1 and p2q2 (2D), plain Python. |P(s) - Q(t)|^2 is convex
    on the unit square, so its minimum is at an interior stationary point (where the lines
    meet, found by Cramer's rule) or on the square's edges (an end of one segment against the
    other segment)."""
    best = min(_point_segment(p1, p2, q2), _point_segment(q1, p2, q2),
               _point_segment(p2, p1, q1), _point_segment(q2, p1, q1))
    d1 = (q1[0] - p1[0], q1[1] - p1[1])
    d2 = (q2[0] - p2[0], q2[1] - p2[1])
    det = d1[0] * (-d2[1]) - d1[1] * (-d2[0])
    if det != 0.0:
        rx, ry = p2[0] - p1[0], p2[1] - p1[1]
        s = (rx * (-d2[1]) - ry * (-d2[0])) / det
        t = (d1[0] * ry - d1[1] * rx) / det
        if 0.0 <= s <= 1.0 and 0.0 <= t <= 1.0:
            best = min(best, math.hypot(p1[0] + s * d1[0] - p2[0] - t * d2[0],
                                        p1[1] + s * d1[1] - p2[1] - t * d2[1]))
    return best


coord = st.floats(-3.0, 3.0, allow_nan=False)
point = st.tuples(coord, coord)


@settings(max_examples=300, deadline=None)
@given(p1=point, q1=point, p2=point, q2=point)
def test_segment_distance_is_the_plain_python_minimum(p1, q1, p2, q2):
    assume(math.dist(p1, q1) > 1e-2 and math.dist(p2, q2) > 1e-2)
    got = float(segment_distance(p1, q1, p2, q2))
    assert got == pytest.approx(_oracle_distance(p1, q1, p2, q2), abs=1e-9)
    # and a batch gives each pair's value (vectorised, not one answer broadcast)
    batch = segment_distance([p1, p2], [q1, q2], [p2, p1], [q2, q1])
    assert batch.shape == (2,) and np.allclose(batch, got, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(q=st.lists(st.floats(-4.0, 4.0, allow_nan=False), min_size=4, max_size=4),
       r=st.floats(0.0, 0.1), margin=st.floats(0.0, 0.1))
def test_self_gaps_are_the_sampled_distances_of_non_adjacent_links(q, r, margin):
    arm = rapp.Arm([1.0, 0.7, 0.6, 0.5], link_radius=r, self_collision=True)
    p = arm.joint_positions(q)
    s = np.linspace(0.0, 1.0, 201)[:, None]
    gaps = self_gaps(arm, q, margin=margin)
    i, j = self_pairs(arm.n)
    assert list(zip(i.tolist(), j.tolist())) == [(0, 2), (0, 3), (1, 3)]
    for k, (a, b) in enumerate(zip(i, j)):
        pa = p[a] + s * (p[a + 1] - p[a])
        pb = p[b] + s * (p[b + 1] - p[b])
        sampled = np.linalg.norm(pa[:, None] - pb[None], axis=-1).min()
        # samples 1/200 of a link (<= 1 m) apart: the true distance is at most 2 x 0.0025 below
        assert sampled - 2 * 0.0025 - 1e-12 <= gaps[k] + 2 * r + margin <= sampled + 1e-12


FOLDED = [0.0, 2.5, 2.5]   # link 2 folded back across link 0


def test_a_folded_arm_collides_only_with_self_collision():
    on = rapp.Arm([1.0, 1.0, 1.0], self_collision=True)
    off = rapp.Arm([1.0, 1.0, 1.0])
    assert bool(collides(on, FOLDED, [])) and not bool(collides(off, FOLDED, []))
    assert not bool(collides(on, [0.0, 0.0, 0.0], []))
    assert segment_collision_free(off, [0.0, 0.0, 0.0], FOLDED, []).item()
    assert not segment_collision_free(on, [0.0, 0.0, 0.0], FOLDED, []).item()
    # two links: no non-adjacent pair, nothing to test
    two = rapp.Arm([1.0, 1.0], self_collision=True)
    assert float(self_clearance(two, [0.0, 3.1])) == math.inf and not bool(collides(two, [0.0, 3.1], []))


def test_radius_and_margin_count_in_the_pair_distance():
    arm = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05, self_collision=True)
    q = [0.0, 2.0, 2.0]
    d = float(self_gaps(rapp.Arm([1.0, 1.0, 1.0]), q)[0])   # the bare distance
    assert 0.15 < d < 0.5
    assert not bool(collides(arm, q, [], margin=d - 0.1 - 1e-6))
    assert bool(collides(arm, q, [], margin=d - 0.1 + 1e-6))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), r=st.floats(0.0, 0.08), margin=st.floats(0.0, 0.05))
def test_certified_segments_keep_every_pair_apart_on_dense_samples(seed, r, margin):
    rng = np.random.default_rng(seed)
    arm = rapp.Arm([1.0, 0.8, 0.7, 0.5], link_radius=r, self_collision=True)
    q0 = rng.uniform(-3, 3, (8, 4))
    q1 = q0 + rng.uniform(-1.5, 1.5, (8, 4))
    free = segment_collision_free(arm, q0, q1, [], margin=margin)
    assert (free == self_segment_free(arm, q0, q1, margin=margin)).all()
    t = np.linspace(0.0, 1.0, 801)[:, None, None]
    dense = self_clearance(arm, q0 + t * (q1 - q0), margin=margin)   # (801, 8)
    assert (dense[:, free] > 0).all()
    # a segment refused has a sample within the distance, or one within the bisection's floor
    assert (dense[:, ~free].min(axis=0) < 1e-2).all()


def test_self_collision_adds_to_obstacles_and_the_thin_scene_keeps_it():
    arm = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05, self_collision=True)
    obs = [rapp.Circle((0.0, -2.0), 0.2)]
    thin, _ = rapp.collision.scene(arm, obs, 0.02)
    assert thin.self_collision and thin.link_radius == (0.0,) * 3
    q = np.random.default_rng(0).uniform(-3, 3, (500, 3))
    assert (collides(thin, q, _) == collides(arm, q, obs, margin=0.02)).all()
    assert np.allclose(self_gaps(thin, q), self_gaps(arm, q, margin=0.02))


def test_grid_cells_are_the_configurations_test_and_certified_moves_keep_apart():
    arm = rapp.Arm([1.0, 0.8, 0.8], link_radius=0.05, self_collision=True)
    grid = JointGrid(arm, 14)
    occ, safe = self_collision_cells(arm, grid, margin=0.01, chunk=500)
    q = grid_q(grid)
    assert (occ == (self_clearance(arm, q, margin=0.01) <= 0)).all()
    assert occ.any() and safe.any() and not (safe & occ).any()
    # every move between two certified axis neighbours is free on dense samples
    t = np.linspace(0.0, 1.0, 21)[:, None]
    for axis in range(3):
        nb = np.roll(safe, -1, axis=axis)
        idx = np.argwhere(safe & nb)[::7]
        for cell in idx:
            a = q[tuple(cell)]
            b = a.copy()
            b[axis] += grid.step[axis]
            assert (self_clearance(arm, a + t * (b - a), margin=0.01) > 0).all()


ARM = rapp.Arm([1.0, 0.8, 0.8], link_radius=0.05, self_collision=True)
# the example of book/scenario_format.md ('links that do not cross')
START, GOAL = np.array([0.0, 1.35, 0.25]), np.array([0.0, -2.03, 2.82])
MARGIN = 0.02


def test_the_straight_move_of_the_planning_problem_folds_through_itself():
    assert not bool(collides(ARM, START, [], margin=MARGIN)) and not bool(collides(ARM, GOAL, [], margin=MARGIN))
    assert not self_segment_free(ARM, START, START + ARM.joint_delta(START, GOAL), margin=MARGIN)
    # without self-collision the straight move is free
    off = rapp.Arm([1.0, 0.8, 0.8], link_radius=0.05)
    assert segment_collision_free(off, START, START + off.joint_delta(START, GOAL), [], margin=MARGIN).item()


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PLANNERS))
def test_every_planner_keeps_links_apart_on_dense_samples(name):
    obstacles = [rapp.Circle((-1.6, -1.2), 0.3)]
    res = run(name, ARM, START, GOAL, obstacles, margin=MARGIN, cells=40, seed=3, step=0.2,
              max_iterations=4000)
    assert res.success
    path = np.asarray(res.path)
    assert segment_collision_free(ARM, path[:-1], path[1:], obstacles, margin=MARGIN).all()
    t = np.linspace(0.0, 1.0, 201)[:, None, None]
    dense = (path[:-1] + t * (path[1:] - path[:-1])).reshape(-1, ARM.n)
    assert (self_clearance(ARM, dense, margin=MARGIN) > 0).all()
    assert not collides(ARM, dense, obstacles, margin=MARGIN).any()


def test_rrt_connect_keeps_links_apart_on_dense_samples():
    res = run("rrt_connect", ARM, START, GOAL, [], margin=MARGIN, seed=3, step=0.2)
    assert res.success
    path = np.asarray(res.path)
    t = np.linspace(0.0, 1.0, 201)[:, None, None]
    dense = (path[:-1] + t * (path[1:] - path[:-1])).reshape(-1, ARM.n)
    assert (self_clearance(ARM, dense, margin=MARGIN) > 0).all()


SCENARIO = {
    "arm": {"link_lengths": [1.0, 0.8, 0.8], "link_radius": 0.05, "self_collision": True},
    "safety_margin": MARGIN,
    "obstacles": [],
    "start": START.tolist(), "goal": {"joints": GOAL.tolist()},
    "planner": {"algorithm": "rrt_connect", "seed": 2},
    "trajectory": {"duration": 4.0, "samples": 80},
}


def test_a_plan_keeps_links_apart_and_its_report_says_so():
    s = rapp.load_scenario(SCENARIO)
    assert s.arm.self_collision
    p = rapp.plan(s)
    assert p.report.ok
    gaps = self_clearance(s.arm, p.q, margin=MARGIN)
    assert (gaps > 0).all()
    check = p.report["min self-gap"]
    assert check.ok and check.value == pytest.approx(float(gaps.min()), abs=1e-9)
    assert "self-collision checked" in check.detail
    # its motion q(t), densely, between the samples too (10,000 times per second)
    dense = p.motion.evaluate(np.linspace(p.motion.t0, p.motion.tf, 40_001))
    assert (self_clearance(s.arm, dense, margin=MARGIN) > 0).all()


@pytest.mark.parametrize("profile", ["cubic", "quintic", "spline"])
def test_a_motion_is_certified_only_when_its_links_stay_apart(profile):
    from rapp.motion import certify_motion
    from rapp.time_scaling import time_path
    arm = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05, self_collision=True)
    layered = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05)
    # Ends folded back across link 0: the motion passes through a self-collision.
    folding = time_path([[0.0, 0.0, 0.0], [0.0, 1.2, 1.0], [0.0, 2.5, 2.5]], 2.0, profile)
    assert (self_gaps(arm, folding.evaluate(np.linspace(0.0, 2.0, 2001))) <= 0).any()
    assert not certify_motion(arm, folding).free
    assert certify_motion(layered, folding).free            # links in layers may cross
    # A motion that stays open is certified, and the dense check agrees.
    open_ = time_path([[0.0, 0.0, 0.0], [0.6, 0.4, -0.3], [1.0, 0.9, 0.2]], 2.0, profile)
    assert certify_motion(arm, open_).free
    assert (self_gaps(arm, open_.evaluate(np.linspace(0.0, 2.0, 2001))) > 0).all()
    # The margin counts as it does for obstacles.
    big = float(self_gaps(arm, open_.evaluate(np.linspace(0.0, 2.0, 2001))).min()) + 0.01
    assert not certify_motion(arm, open_, margin=big).free


def test_the_scenario_key_round_trips_and_defaults_to_false():
    s = rapp.load_scenario(SCENARIO)
    d = s.to_dict()
    assert d["arm"]["self_collision"] is True
    assert rapp.load_scenario(d) == s
    plain = dict(SCENARIO, arm={"link_lengths": [1.0, 0.8, 0.8]})
    s2 = rapp.load_scenario(plain)
    assert not s2.arm.self_collision and "self_collision" not in s2.to_dict()["arm"]
    assert s2 != s


@pytest.mark.parametrize("bad", ["yes", 1, None, [True]])
def test_a_bad_self_collision_is_one_line_naming_the_field(bad):
    with pytest.raises(InvalidValue) as e:
        rapp.load_scenario(dict(SCENARIO, arm=dict(SCENARIO["arm"], self_collision=bad)))
    assert e.value.field == "arm.self_collision"
    assert "\n" not in str(e.value) and "arm.self_collision" in str(e.value)
    with pytest.raises(ValueError, match="self_collision"):
        rapp.Arm([1.0, 1.0, 1.0], self_collision="yes")


def test_ik_goals_of_a_self_colliding_arm_keep_links_apart():
    from rapp.ik import free_ik_solutions
    on = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05, self_collision=True)
    off = rapp.Arm([1.0, 1.0, 1.0], link_radius=0.05)
    sols, _ = free_ik_solutions(on, (0.3, 0.0), [])
    assert len(sols) and (self_clearance(on, sols) > 0).all()
    assert np.allclose(on.end_effector(sols), (0.3, 0.0), atol=1e-6)
    loose, _ = free_ik_solutions(off, (0.3, 0.0), [])
    assert (self_clearance(on, loose) <= 0).any()   # without the flag folded solutions remain
