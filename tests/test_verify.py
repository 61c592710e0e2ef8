"""verify() (R4, NFR1, MIS verifyOutput): a good plan passes with measured values inside
their limits, and each kind of damage to a plan fails exactly the check that should see it."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from rapp import load_scenario, plan
from rapp.collision import collides, segment_collision_free
from rapp.verify import FK_TOL, JOINT_TOL, POSITION_TOL, Check, Report, verify


@pytest.fixture(scope="module")
def default():
    s = load_scenario("default")
    return s, plan(s)


def failed(report):
    return {c.name for c in report.checks if not c.ok}


def test_a_planned_trajectory_passes_with_its_measured_values(default):
    s, p = default
    r = verify(p, s)
    assert r.ok and failed(r) == set()
    assert r["goal reached"].value <= POSITION_TOL and r["goal reached"].unit == "m"
    assert r["FK consistency"].value <= FK_TOL
    assert r["min clearance"].value > 0
    assert r["collision-free"].value == 0
    assert r == p.report  # plan() stores the same report


def test_report_round_trips_and_prints_every_check(default):
    s, p = default
    r = p.report
    assert Report.from_dict(r.to_dict()) == r
    text = str(r)
    for c in r.checks:
        assert c.name in text
    assert text.splitlines()[-1] == "verification: passed"


def test_moving_the_end_fails_the_goal_check(default):
    s, p = default
    q = p.q.copy()
    q[-1] += 0.01
    bad = replace(p, q=q, xy=s.arm.end_effector(q))
    assert "goal reached" in failed(verify(bad, s))


def test_joint_goal_tolerance_is_nfr1_and_wrap_aware():
    s = load_scenario("rectangles")
    p = plan(s)
    r = p.report
    assert r.ok and r["goal reached"].unit == "rad" and r["goal reached"].limit == JOINT_TOL
    for shift, ok in ((2 * np.pi, True), (0.5 * JOINT_TOL, True), (2 * JOINT_TOL, False)):
        q = p.q.copy()
        q[-1, 0] += shift
        names = failed(verify(replace(p, q=q, xy=s.arm.end_effector(q)), s))
        assert ("goal reached" not in names) == ok


def test_a_chord_through_an_obstacle_fails_even_when_every_sample_is_free():
    # Two samples on either side of a small disc: each sample is free, the motion is not.
    s = load_scenario({"arm": {"link_lengths": [1.0, 1.0]},
                       "obstacles": [{"type": "circle", "center": [0.0, 1.5], "radius": 0.1}],
                       "start": [1.2, 0.0], "goal": {"joints": [1.9, 0.0]},
                       "trajectory": {"duration": 1.0, "samples": 2}})
    q = np.array([s.start, s.goal_q])
    assert not collides(s.arm, q, s.obstacles).any()
    fake = type("P", (), {})()
    fake.t, fake.q = np.array([0.0, 1.0]), q
    fake.qd = np.array([[0.0, 0.0], [0.0, 0.0]]) + (q[1] - q[0])
    fake.qdd = np.zeros_like(q)
    fake.xy = s.arm.end_effector(q)
    assert failed(verify(fake, s)) == {"collision-free"}


def test_each_damage_fails_its_own_check(default):
    s, p = default
    k = len(p.t)
    # A jump in the middle: continuity.
    q = p.q.copy()
    q[k // 2:] += np.array([0.0, 0.3])
    names = failed(verify(replace(p, q=q, xy=s.arm.end_effector(q)), s))
    assert "continuity" in names
    # Cartesian samples not FK of the joint samples.
    xy = p.xy.copy()
    xy[3] += 1e-6
    assert failed(verify(replace(p, xy=xy), s)) == {"FK consistency"}
    # Wrong start.
    q = p.q.copy()
    q[0] += 1e-3
    assert "starts at start" in failed(verify(replace(p, q=q, xy=s.arm.end_effector(q)), s))
    # Non-increasing time.
    t = p.t.copy()
    t[5] = t[4]
    assert "time" in failed(verify(replace(p, t=t), s))
    # NaN anywhere.
    qd = p.qd.copy()
    qd[2, 1] = np.nan
    assert not verify(replace(p, qd=qd), s).ok
    # Wrong shapes.
    assert failed(verify(replace(p, xy=p.xy[:-1]), s)) == {"shapes"}


def test_joint_limits_check_measures_the_violation():
    s = load_scenario("no_solution", check=False)
    q = np.linspace([-1.2, 0.0], [-1.7, 0.0], 20)  # beyond the -90 degree limit
    fake = type("P", (), {})()
    fake.t = np.linspace(0, s.trajectory.duration, 20)
    fake.q, fake.qd, fake.qdd = q, np.gradient(q, fake.t, axis=0), np.zeros_like(q)
    fake.xy = s.arm.end_effector(q)
    c = verify(fake, s)["joint limits"]
    assert not c.ok and c.value == pytest.approx(1.7 - np.pi / 2)


@settings(max_examples=30, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3))
def test_collision_check_agrees_with_the_certified_segment_test(a0, a1, b0, b1):
    s = load_scenario({"arm": {"link_lengths": [1.0, 1.0]},
                       "obstacles": [{"type": "circle", "center": [0.8, 0.8], "radius": 0.3}],
                       "start": [a0, a1], "goal": {"joints": [b0, b1]},
                       "trajectory": {"duration": 1.0, "samples": 2}}, check=False)
    q = np.array([s.start, s.goal_q])
    fake = type("P", (), {})()
    fake.t, fake.q = np.array([0.0, 1.0]), q
    fake.qd = np.zeros_like(q) + (q[1] - q[0])
    fake.qdd = np.zeros_like(q)
    fake.xy = s.arm.end_effector(q)
    r = verify(fake, s)
    expect = bool(segment_collision_free(s.arm, q[0], q[1], s.obstacles))
    assert r["collision-free"].ok == expect
    assert r["min clearance"].ok == (not collides(s.arm, q, s.obstacles).any())
    if not r["min clearance"].ok:  # a colliding sample can never be on a free segment
        assert not r["collision-free"].ok


def test_check_dict_maps_infinities_to_null():
    c = Check("x", True, float("inf"), None, "m")
    assert c.to_dict()["value"] is None
