"""Inverse kinematics: FK(IK(target)) == target, solution counts, honest failures."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp.arm import Arm, wrap_angle
from rapp.errors import NoIKSolution
from rapp.ik import ik, ik_2link, ik_numeric, jacobian
from rapp.symbolic import ik_2link_function, jacobian_function

ACC = 1e-9
IK_REF = ik_2link_function()          # derived once: sympy is slow
JAC_REF = {}
lengths_st = st.floats(0.2, 2.0)
frac_st = st.floats(0.0, 1.0)
angle_st = st.floats(-np.pi, np.pi)


def annulus_point(l1, l2, frac, angle):
    r_in, r_out = abs(l1 - l2), l1 + l2
    r = r_in + frac * (r_out - r_in)
    return np.array([r * np.cos(angle), r * np.sin(angle)]), r


def wrap_close(a, b, atol=1e-7):
    return np.all(np.abs(wrap_angle(np.asarray(a) - np.asarray(b))) < atol)


# ----------------------------------------------------------------- analytic 2-link


@settings(max_examples=200, deadline=None)
@given(lengths_st, lengths_st, frac_st, angle_st)
def test_2link_fk_of_ik_is_target_and_counts(l1, l2, frac, angle):
    target, r = annulus_point(l1, l2, frac, angle)
    arm = Arm([l1, l2])
    q = ik(arm, target)
    assert np.abs(arm.end_effector(q) - target).max() <= ACC
    assert np.all((q >= -np.pi) & (q < np.pi))
    on_edge = min(abs(r - (l1 + l2)), abs(r - abs(l1 - l2))) <= 1e-10
    if on_edge:
        assert q.shape == (1, 2)
    elif min(abs(r - (l1 + l2)), abs(r - abs(l1 - l2))) > 1e-6:
        # Strictly inside: two distinct solutions, elbow-down (q2 > 0) first.
        assert q.shape == (2, 2)
        assert q[0, 1] > 0 > q[1, 1]


@settings(max_examples=100, deadline=None)
@given(lengths_st, lengths_st, st.floats(0.01, 0.99), angle_st)
def test_2link_matches_the_symbolic_derivation(l1, l2, frac, angle):
    target, _ = annulus_point(l1, l2, frac, angle)
    ours = ik_2link([l1, l2], target)
    ref = IK_REF(target, [l1, l2])
    assert wrap_close(ours, ref, atol=1e-6)


@pytest.mark.parametrize("l1, l2", [(1.0, 1.0), (1.0, 0.4), (0.4, 1.0)])
def test_boundary_circles_give_exactly_one_solution(l1, l2):
    arm = Arm([l1, l2])
    for r, q2 in ((l1 + l2, 0.0), (abs(l1 - l2), -np.pi)):
        for ang in np.linspace(-3, 3, 7):
            target = r * np.array([np.cos(ang), np.sin(ang)])
            q = ik(arm, target)
            assert q.shape == (1, 2)
            assert abs(wrap_angle(q[0, 1] - q2)) < 1e-12
            assert np.abs(arm.end_effector(q) - target).max() <= ACC


@pytest.mark.parametrize("target", [[2.0 + 1e-6, 0.0], [0.0, 3.0], [0.2, 0.2]])
def test_out_of_reach(target):
    with pytest.raises(NoIKSolution) as err:
        ik(Arm([1.0, 0.6] if target == [0.2, 0.2] else [1.0, 1.0]), target)
    assert err.value.reason == "out of reach"


def test_limits_drop_solutions_and_name_the_reason():
    target = [1.0, 1.0]
    down_only = Arm([1.0, 1.0], [None, (0.0, np.pi)])
    q = ik(down_only, target)
    assert q.shape == (1, 2) and q[0, 1] > 0
    neither = Arm([1.0, 1.0], [(-0.5, -0.1), None])
    with pytest.raises(NoIKSolution) as err:
        ik(neither, target)
    assert err.value.reason == "joint limits"


@settings(max_examples=150, deadline=None)
@given(lengths_st, lengths_st, frac_st, angle_st, st.floats(-4.0, 4.0), st.floats(0.5, 7.0),
       st.floats(-4.0, 4.0), st.floats(0.5, 7.0))
def test_limits_respected_with_2pi_equivalents(l1, l2, frac, angle, lo1, w1, lo2, w2):
    arm = Arm([l1, l2], [(lo1, lo1 + w1), (lo2, lo2 + w2)])
    free = Arm([l1, l2])
    target, _ = annulus_point(l1, l2, frac, angle)
    free_q = ik(free, target)
    # Oracle: a free solution survives iff some 2 pi shift of each joint fits.
    k = np.arange(-3, 4) * 2 * np.pi
    fits = [np.any((row[:, None] + k >= arm.lower[:, None] - 1e-12)
                   & (row[:, None] + k <= arm.upper[:, None] + 1e-12), axis=1).all()
            for row in free_q]
    if not any(fits):
        with pytest.raises(NoIKSolution) as err:
            ik(arm, target)
        assert err.value.reason == "joint limits"
        return
    q = ik(arm, target)
    assert np.all(arm.within_limits(q))
    assert np.abs(arm.end_effector(q) - target).max() <= ACC
    # every returned row is one of the free solutions, modulo 2 pi
    for row in q:
        assert any(wrap_close(row, f) for f in free_q)
    assert q.shape[0] >= sum(fits)


@settings(max_examples=100, deadline=None)
@given(lengths_st, lengths_st, st.integers(0, 2**32 - 1))
def test_batched_2link_matches_one_target_at_a_time(l1, l2, seed):
    # The batch is the per-target contract of ik() row by row: NaN exactly where ik()
    # says "out of reach", both elbows (or the boundary solution twice) elsewhere.
    rng = np.random.default_rng(seed)
    arm = Arm([l1, l2])
    pts = rng.uniform(-1.2, 1.2, (40, 2)) * (l1 + l2)
    both = ik_2link(arm, pts.reshape(4, 10, 2))
    assert both.shape == (4, 10, 2, 2)
    both = both.reshape(40, 2, 2)
    for p, qs in zip(pts, both):
        try:
            ref = ik(arm, p)
        except NoIKSolution:
            assert np.isnan(qs).all()
            continue
        assert np.isfinite(qs).all()
        assert np.abs(arm.end_effector(qs) - p).max() <= ACC
        assert all(any(wrap_close(row, r) for row in qs) for r in ref)


def test_elbow_down_is_below_the_line_for_a_target_on_x():
    # The naming in the docstring: q2 > 0 puts the elbow below the base-target line.
    arm = Arm([1.0, 1.0])
    q = ik_2link(arm, [1.5, 0.0])
    elbow = arm.joint_positions(q)[:, 1, :]
    assert q[0, 1] > 0 and elbow[0, 1] < 0
    assert q[1, 1] < 0 and elbow[1, 1] > 0


def test_seed002_shoulder_formula_fails_where_atan2_does_not():
    # Seed 002 eq. 34/36: Q1 = atan(y/x) -+ asin(L2 sin Q2 / r). asin only
    # returns angles up to 90 degrees and atan(y/x) loses the quadrant, so the
    # formula breaks when the angle at the base is obtuse (L2 > L1) or x < 0.
    l1, l2 = 0.5, 1.0
    arm = Arm([l1, l2])
    target = np.array([0.7, 0.3])
    r = np.hypot(*target)
    q2 = np.arccos((r**2 - l1**2 - l2**2) / (2 * l1 * l2))
    q1_seed = np.arctan(target[1] / target[0]) - np.arcsin(l2 * np.sin(q2) / r)
    seed_err = np.linalg.norm(arm.end_effector([q1_seed, q2]) - target)
    assert seed_err > 0.1
    ours = ik(arm, target)
    assert np.abs(arm.end_effector(ours) - target).max() <= ACC


# ----------------------------------------------------------------- numeric N-link


@settings(max_examples=25, deadline=None)
@given(st.integers(3, 6), st.integers(0, 2**31 - 1))
def test_numeric_fk_of_ik_is_target(n, seed):
    rng = np.random.default_rng(seed)
    arm = Arm(rng.uniform(0.2, 1.5, n))
    targets = arm.end_effector(rng.uniform(-np.pi, np.pi, (40, n)))
    q, ok = ik_numeric(arm, targets)
    assert ok.all()
    assert np.abs(arm.end_effector(q) - targets).max() <= ACC
    assert np.all((q >= -np.pi) & (q <= np.pi))


def test_numeric_batch_shapes_and_honest_failure():
    arm = Arm([1.0, 0.8, 0.5])
    rng = np.random.default_rng(3)
    reachable = arm.end_effector(rng.uniform(-np.pi, np.pi, (3, 4, 3)))
    targets = reachable.copy()
    targets[0, 0] = [2.5, 0.0]             # beyond the outer circle
    targets[1, 1] = [0.0, 0.0]             # inside: 1.0 - 0.8 - 0.5 < 0, reachable
    q, ok = ik_numeric(arm, targets)
    assert q.shape == (3, 4, 3) and ok.shape == (3, 4)
    assert not ok[0, 0]
    err = np.linalg.norm(arm.end_effector(q) - targets, axis=-1)
    assert np.all(err[ok] <= 1e-10)        # every "ok" is true
    assert ok.sum() == 11


def test_numeric_unreachable_hole_is_not_reported_ok():
    arm = Arm([1.0, 0.3, 0.2])             # hole of radius 0.5
    q, ok = ik_numeric(arm, [[0.2, 0.1], [0.7, 0.0]])
    assert ok.tolist() == [False, True]


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_numeric_respects_joint_limits(seed):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-2.5, 0.0, 3)
    arm = Arm([1.0, 0.8, 0.5], list(zip(lo, lo + rng.uniform(0.5, 2.5, 3))))
    q_true = rng.uniform(arm.lower, arm.upper, (30, 3))
    targets = arm.end_effector(q_true)
    q, ok = ik_numeric(arm, targets)
    assert np.all(arm.within_limits(q))
    assert np.abs(arm.end_effector(q[ok]) - targets[ok]).max(initial=0) <= ACC
    assert ok.mean() >= 0.9                 # every target is reachable within limits


def test_numeric_q0_is_used():
    arm = Arm([1.0, 0.8, 0.5])
    q_true = np.array([0.3, -0.4, 0.9])
    target = arm.end_effector(q_true)
    q, ok = ik_numeric(arm, target, q0=q_true + 0.01)
    assert ok and np.abs(q - q_true).max() < 0.05   # stays on the nearby branch


# ----------------------------------------------------------------- contract ik()


def test_ik_nlink_returns_distinct_correct_solutions_sorted_by_q0():
    arm = Arm([1.0, 0.8, 0.5])
    q0 = np.array([0.2, 0.4, -0.3])
    target = arm.end_effector([0.1, 0.5, -0.2])
    sols = ik(arm, target, q0=q0)
    assert sols.shape[0] >= 3 and sols.shape[1] == 3
    assert np.abs(arm.end_effector(sols) - target).max() <= ACC
    d = np.linalg.norm(wrap_angle(sols[:, None] - sols[None]), axis=-1)
    assert np.all(d[~np.eye(len(sols), dtype=bool)] > 1e-6)
    dist = np.linalg.norm(wrap_angle(sols - q0), axis=-1)
    assert np.all(np.diff(dist) >= 0)


def test_ik_2link_contract_is_the_analytic_set_sorted():
    arm = Arm([1.0, 1.0])
    sols = ik(arm, [1.0, 1.0], q0=[1.5, -1.5])
    assert sols.shape == (2, 2) and sols[0, 1] < 0


def test_ik_reasons():
    arm = Arm([1.0, 0.8, 0.5])
    with pytest.raises(NoIKSolution) as err:
        ik(arm, [3.0, 0.0])
    assert err.value.reason == "out of reach"
    stiff = Arm([1.0, 0.8, 0.5], [(-0.1, 0.1)] * 3)
    with pytest.raises(NoIKSolution) as err:
        ik(stiff, [0.0, 1.5])
    assert err.value.reason == "joint limits"
    with pytest.raises(NoIKSolution) as err:
        ik(Arm([1.0, 0.2, 0.2]), [0.1, 0.0])       # inside the hole of radius 0.6
    assert err.value.reason == "out of reach"


def test_ik_one_link():
    arm = Arm([1.5])
    assert np.allclose(ik(arm, [0.0, 1.5]), [[np.pi / 2]])
    with pytest.raises(NoIKSolution):
        ik(arm, [0.0, 1.0])


# ----------------------------------------------------------------- Jacobian


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(0, 2**31 - 1))
def test_jacobian_matches_central_differences_and_sympy(n, seed):
    rng = np.random.default_rng(seed)
    arm = Arm(rng.uniform(0.2, 1.5, n))
    q = rng.uniform(-np.pi, np.pi, (5, n))
    J = jacobian(arm, q)
    assert J.shape == (5, 2, n)
    h = 1e-6
    eye = np.eye(n) * h
    fd = (arm.end_effector(q[:, None, :] + eye) - arm.end_effector(q[:, None, :] - eye)) / (2 * h)
    assert np.abs(J - np.swapaxes(fd, -1, -2)).max() < 1e-8
    if n not in JAC_REF:
        JAC_REF[n] = jacobian_function(n)
    Js = JAC_REF[n](q, arm.lengths)
    assert np.abs(J - Js).max() < 1e-12


def test_ik_names_a_wrongly_shaped_q0():
    arm = Arm([1.0, 0.8, 0.5])
    with pytest.raises(ValueError, match=r"q0 must be 3 finite joint angles, got shape \(2,\)"):
        ik(arm, [1.0, 0.5], q0=[0.0, 0.5])
