"""Seed 004 (2-DOF arm README): workspace annulus, analytic IK, motion through all solutions.

Seed 004 prints formulas but no numeric targets or angles, so its claims are
tested as properties:

* reachable iff |L1 - L2| <= r <= L1 + L2 (inner and outer circle);
* cos q2 = (x^2 + y^2 - L1^2 - L2^2) / (2 L1 L2),
  q1 = atan2(y, x) - atan2(L2 sin q2, L1 + L2 cos q2) reaches the target for
  both signs of q2 (the formula is right);
* "Elbow-up (+)": wrong label. With this q1, q2 = +arccos puts the elbow
  clockwise of the base-target line (below it for a target on +x): elbow-DOWN
  in seed 002's and rapp's naming; test_seed004_elbow_labels_are_swapped;
* "each reachable target produces 0, 1, or 2 configurations": a reachable
  target has 1 (on a circle) or 2; 0 means unreachable; and with L1 == L2 the
  base itself has infinitely many (every q1), which the claim misses;
* unreachable targets are flagged and skipped by the motion.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm
from rapp.arm import wrap_angle
from rapp.ik import ik, ik_2link
from rapp.errors import NoIKSolution
from rapp.cases.two_dof_workspace import (
    interpolate_joints,
    motion_through_solutions,
    reachable,
    workspace_radii,
)

length = st.floats(0.2, 3.0)
point = st.tuples(st.floats(-7, 7), st.floats(-7, 7))


@settings(max_examples=100, deadline=None)
@given(length, length, st.lists(point, min_size=1, max_size=20))
def test_reachable_matches_a_loop_oracle_and_ik(l1, l2, pts):
    pts = np.array(pts)
    flags = reachable([l1, l2], pts)
    for p, f in zip(pts, flags):  # slow obviously-correct oracle
        r = float(np.hypot(*p))
        inside = abs(l1 - l2) - 1e-9 <= r <= l1 + l2 + 1e-9
        if abs(r - abs(l1 - l2)) > 1e-9 and abs(r - (l1 + l2)) > 1e-9:
            assert f == inside
        try:
            ik(Arm([l1, l2]), p)
            assert f or not inside
        except NoIKSolution:
            assert not f or abs(r - (l1 + l2)) < 1e-9 or abs(r - abs(l1 - l2)) < 1e-9


@settings(max_examples=100, deadline=None)
@given(length, length, st.floats(0, 1), st.floats(-np.pi, np.pi))
def test_both_solutions_reach_the_target_and_agree_with_ik(l1, l2, u, phi):
    r_in, r_out = workspace_radii([l1, l2])
    r = r_in + (0.02 + 0.96 * u) * (r_out - r_in)
    target = r * np.array([np.cos(phi), np.sin(phi)])
    sols = ik_2link([l1, l2], target)
    np.testing.assert_allclose(Arm([l1, l2]).end_effector(sols), [target, target], atol=1e-9)
    assert sols[0, 1] > 0 > sols[1, 1]
    ref = ik(Arm([l1, l2]), target)
    if len(ref) == 2:
        assert np.abs(wrap_angle(sols - ref)).max() < 1e-7


@settings(max_examples=100, deadline=None)
@given(length, length, st.floats(0.05, 0.95), st.floats(-np.pi, np.pi))
def test_seed004_elbow_labels_are_swapped(l1, l2, u, phi):
    r_in, r_out = workspace_radii([l1, l2])
    target = (r_in + u * (r_out - r_in)) * np.array([np.cos(phi), np.sin(phi)])
    plus = ik_2link([l1, l2], target)[0]  # seed 004's "elbow-up (+)"
    elbow = Arm([l1, l2]).joint_positions(plus)[1]
    cross = target[0] * elbow[1] - target[1] * elbow[0]
    assert cross < 0  # elbow clockwise of the base->target line: elbow DOWN


def test_solution_counts_0_1_2_and_the_infinite_case():
    L = [2.0, 1.5]
    pts = np.array([[2.5, 0.0], [3.5, 0.0], [0.0, 0.5], [4.0, 0.0], [0.1, 0.0]])
    counts = [len(ik(Arm(L), p)) if f else 0 for p, f in zip(pts, reachable(L, pts))]
    assert counts == [2, 1, 1, 0, 0]
    sols = ik_2link(L, pts)
    assert np.isnan(sols[3:]).all() and not np.isnan(sols[:3]).any()
    np.testing.assert_allclose(sols[1, 0], sols[1, 1], atol=1e-7)  # on the outer circle they coincide
    # L1 == L2: the base is reachable with q2 = pi and ANY q1.
    q1 = np.linspace(-3, 3, 7)
    q = np.stack((q1, np.full_like(q1, np.pi)), axis=-1)
    np.testing.assert_allclose(Arm([1.0, 1.0]).end_effector(q), 0, atol=1e-12)


def test_interpolation_ends_and_short_way():
    q = interpolate_joints([3.0, 0.0], [-3.0, 1.0], 11)
    np.testing.assert_allclose(q[0], [3.0, 0.0])
    np.testing.assert_allclose(wrap_angle(q[-1] - [-3.0, 1.0]), 0, atol=1e-12)
    assert np.all(np.diff(q[:, 0]) > 0)  # 3 -> 2 pi - 3 across the seam, not back through 0
    np.testing.assert_allclose(np.diff(q[[0, 1, -2, -1], 1])[[0, 2]], [0.028, 0.028])


@settings(max_examples=50, deadline=None)
@given(length, length, st.lists(point, min_size=1, max_size=8), st.integers(3, 20))
def test_motion_visits_every_solution_and_skips_unreachable(l1, l2, pts, steps):
    pts = np.array(pts)
    q, flags = motion_through_solutions([l1, l2], pts, steps=steps)
    assert flags.tolist() == reachable([l1, l2], pts).tolist()
    assert not np.isnan(q).any()
    sols = ik_2link([l1, l2], pts[flags]).reshape(-1, 2)
    arm = Arm([l1, l2])
    ee = arm.end_effector(q)
    for s in sols:  # every solution is a row of the motion (up to 2 pi)
        assert np.min(np.abs(wrap_angle(q - s)).max(axis=-1)) < 1e-9
    for p in pts[~flags] if len(q) else ():  # unreachable targets are never reached
        assert np.linalg.norm(ee - p, axis=-1).min() > 1e-9
    if len(q) > 1:  # continuous: each step at most 1.5 pi / (steps - 1) per joint
        assert np.abs(np.diff(q, axis=0)).max() <= 1.5 * np.pi / (steps - 1) + 1e-9


def test_motion_with_start_and_nothing_reachable():
    q, flags = motion_through_solutions([1.0, 1.0], [[5.0, 0.0]], steps=5)
    assert q.shape == (0, 2) and flags.tolist() == [False]
    q, flags = motion_through_solutions([1.0, 1.0], [[1.0, 1.0]], steps=5, q_start=[0.0, 0.0])
    assert q.shape == (9, 2)
    np.testing.assert_allclose(q[0], [0.0, 0.0])
    np.testing.assert_allclose(Arm([1.0, 1.0]).end_effector(q[[4, 8]]), [[1.0, 1.0]] * 2, atol=1e-12)
