"""Inverse kinematics: FK(IK(target)) == target, solution counts, honest failures."""

import warnings

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


# ----------------------------------------------------------------- boundary circles, n >= 3

DIRECTIONS = np.deg2rad(np.arange(360.0))
UNIT = np.stack((np.cos(DIRECTIONS), np.sin(DIRECTIONS)), axis=-1)
OUTER_ARMS = [[0.7, 0.6, 0.5, 0.4, 0.3], [1.0, 0.8, 0.5], [2.0, 0.5, 0.4, 0.3, 0.2]]
# r_min = 2 max(L) - sum(L) > 0, with the longest link first, in the middle and last.
INNER_ARMS = [[2.0, 0.5, 0.4, 0.3, 0.2], [0.3, 1.5, 0.4], [0.2, 0.3, 1.4]]


def fk_error(arm, q, target):
    return np.linalg.norm(arm.end_effector(q) - target, axis=-1).max()


@pytest.mark.parametrize("lengths", OUTER_ARMS)
def test_ik_on_the_outer_circle_is_the_stretched_arm(lengths):
    # Exactly at full reach the self-motion manifold is one point. Before, ik returned
    # 3 to 10 rows there, all approximations of it (up to 1e-5 rad off).
    arm = Arm(lengths)
    r_out = arm.reach[1]
    for u in UNIT:
        target = r_out * u
        q = ik(arm, target)
        assert q.shape == (1, arm.n)
        assert abs(wrap_angle(q[0, 0] - np.arctan2(u[1], u[0]))) <= 1e-12
        assert np.all(q[0, 1:] == 0.0)
        assert fk_error(arm, q, target) <= 1e-12


@pytest.mark.parametrize("lengths", [OUTER_ARMS[0], OUTER_ARMS[1]])
def test_ik_just_inside_the_outer_circle(lengths):
    arm = Arm(lengths)
    r_out = arm.reach[1]
    for scale in (1 - 1e-10, 1 - 1e-9 / r_out, 1 - 1e-6):
        for u in UNIT[::4]:
            q = ik(arm, r_out * scale * u)
            assert fk_error(arm, q, r_out * scale * u) <= 1e-9
            # every solution is a slightly bent arm
            assert np.abs(wrap_angle(q[:, 1:])).max() < 10 * np.sqrt(1 - scale) + 1e-9
        # the batch solver's default start handles them too
        q, ok = ik_numeric(arm, r_out * scale * UNIT)
        assert ok.all() and fk_error(arm, q, r_out * scale * UNIT) <= 1e-10


@pytest.mark.parametrize("lengths", INNER_ARMS)
def test_ik_on_the_inner_circle_is_the_folded_arm(lengths):
    arm = Arm(lengths)
    r_in = arm.reach[0]
    longest = int(np.argmax(lengths))
    for u in UNIT:
        target = r_in * u
        q = ik(arm, target)
        assert q.shape == (1, arm.n)
        assert fk_error(arm, q, target) <= 1e-12
        # the longest link points at the target, every other link straight back
        phi = arm.absolute_angles(q[0]) - np.arctan2(u[1], u[0])
        back = np.arange(arm.n) != longest
        assert abs(wrap_angle(phi[longest])) <= 1e-12
        assert np.all(np.abs(wrap_angle(phi[back] + np.pi)) <= 1e-12)
    for r in (r_in * (1 + 1e-10), r_in + 1e-9, r_in + 1e-6, r_in - 5e-11):
        for u in UNIT[::8]:
            assert fk_error(arm, ik(arm, r * u), r * u) <= 1e-9
        q, ok = ik_numeric(arm, r * UNIT)
        assert ok.all() and fk_error(arm, q, r * UNIT) <= 1e-10


def test_ik_boundary_tolerance_and_limits():
    arm = Arm([1.0, 0.8, 0.5])
    # within tol (1e-10) outside a circle: the boundary solution, as for 2 links
    assert ik(arm, [2.3 + 5e-11, 0.0]).tolist() == [[0.0, 0.0, 0.0]]
    with pytest.raises(NoIKSolution) as err:
        ik(arm, [2.3 + 1e-9, 0.0])
    assert err.value.reason == "out of reach"
    # the one solution on a circle breaks a limit: that is exact, not "not found"
    bent = Arm([1.0, 0.8, 0.5], [None, (0.1, 2.0), None])
    with pytest.raises(NoIKSolution, match="stretched arm") as err:
        ik(bent, [0.0, 2.3])
    assert err.value.reason == "joint limits"
    # a limited joint takes its 2 pi equivalent(s) within the limits
    wide = Arm([0.3, 1.5, 0.4], [None, (0.0, 7.0), None])
    q = ik(wide, [0.0, -0.8])
    assert q.shape == (1, 3) and np.isclose(q[0, 1], np.pi)
    assert fk_error(wide, q, [0.0, -0.8]) <= 1e-12


# --------------------------------------------------------- ik_numeric: honest ok, no warnings


def hard_batch(arm, rng, k=300):
    """Targets that stress the solver: solutions on joint limits, on and next to both
    boundary circles, at the base, far away, and ordinary ones."""
    n = arm.n
    q = rng.uniform(arm.lower, arm.upper, (k, n))
    j = rng.integers(n, size=k)
    on = arm.limited[j]
    q[np.arange(k)[on], j[on]] = np.where(rng.random(on.sum()) < 0.5, arm.lower[j[on]],
                                          arm.upper[j[on]])
    r_in, r_out = arm.reach
    u = UNIT[rng.integers(360, size=40)]
    rims = np.concatenate([r_out * u[:10], r_out * (1 - 1e-10) * u[10:20], r_in * u[20:30],
                           (r_in + 1e-9) * u[30:40]])
    far = np.array([[1e3, -2e3], [0.0, 1e12], [-1e300, 1e300], [r_out * 1.5, 0.0]])
    return np.concatenate([arm.end_effector(q), rims, far, [[0.0, 0.0]]])


STRESS_ARMS = [
    Arm([1.0, 0.8, 0.5]),
    Arm([1.0, 0.3, 0.2], [(-1.0, 1.0), (0.0, 2.0), (-2.0, 0.5)]),
    Arm([0.7, 0.6, 0.5, 0.4, 0.3], [None, (-2.5, 2.5), (0.0, 2.5), None, (-1.0, 0.0)]),
    Arm([3e99, 2e99, 1e99]),
    Arm([1e-300, 2e-300, 3e-300], [(-1.0, 1.0)] * 3),
]


@pytest.mark.parametrize("arm", STRESS_ARMS, ids=["plain", "limited", "5-link", "huge", "tiny"])
def test_numeric_never_warns(arm):
    # Before: 59 overflow warnings in one call (a singular J at a stretched arm made
    # the closed-form 2 x 2 determinant cancel to nothing).
    rng = np.random.default_rng(1)
    targets = hard_batch(arm, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for tol in (1e-15, 1e-10, 1e-3):
            q, ok = ik_numeric(arm, targets, tol=tol)
            assert np.isfinite(q).all()
        ik_numeric(arm, targets, q0=np.zeros(arm.n), tol=1e-15)   # singular start
        ik_numeric(arm, targets, q0=np.full(arm.n, 1e9), max_step=1e300)


@pytest.mark.parametrize("arm", STRESS_ARMS[:3], ids=["plain", "limited", "5-link"])
@pytest.mark.parametrize("tol", [1e-15, 1e-12, 1e-9])
def test_numeric_ok_is_exactly_the_tip_check(arm, tol):
    # Before: at tol 1e-15, ok disagreed with the returned q's real tip error.
    rng = np.random.default_rng(int(tol * 1e15) + arm.n)
    targets = hard_batch(arm, rng, k=2000)
    q, ok = ik_numeric(arm, targets, tol=tol)
    with np.errstate(over="ignore"):
        truth = (np.linalg.norm(arm.end_effector(q) - targets, axis=-1) <= tol)
    assert np.array_equal(ok, truth & arm.within_limits(q))
    assert ok.mean() > 0.5


@pytest.mark.slow
@settings(max_examples=30, deadline=None)
@given(st.integers(3, 6), st.integers(0, 2**31 - 1), st.sampled_from([1e-15, 1e-12, 1e-9]),
       st.booleans())
def test_numeric_ok_property(n, seed, tol, limited):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-2.5, 0.0, n)
    limits = list(zip(lo, lo + rng.uniform(0.3, 3.0, n))) if limited else None
    arm = Arm(rng.uniform(0.2, 1.5, n), limits)
    targets = hard_batch(arm, rng, k=100)
    q, ok = ik_numeric(arm, targets, tol=tol)
    with np.errstate(over="ignore"):
        truth = np.linalg.norm(arm.end_effector(q) - targets, axis=-1) <= tol
    assert np.array_equal(ok, truth & arm.within_limits(q))


@pytest.mark.parametrize("n", [3, 4, 5])
def test_numeric_solves_solutions_on_a_joint_limit(n):
    # One joint of q* exactly on a limit. Before: 98.1 % solved for 3 links.
    rng = np.random.default_rng(100 + n)
    solved = total = 0
    for _ in range(8):
        lo = rng.uniform(-2.5, 0.0, n)
        hi = lo + rng.uniform(0.3, 3.0, n)
        arm = Arm(rng.uniform(0.3, 1.2, n), list(zip(lo, hi)))
        q_star = rng.uniform(lo, hi, (250, n))
        j = rng.integers(n, size=250)
        q_star[np.arange(250), j] = np.where(rng.random(250) < 0.5, lo[j], hi[j])
        targets = arm.end_effector(q_star)
        q, ok = ik_numeric(arm, targets)
        assert np.all(arm.within_limits(q))
        assert np.linalg.norm(arm.end_effector(q[ok]) - targets[ok], axis=-1).max() <= 1e-10
        solved += ok.sum()
        total += ok.size
    assert solved / total >= 0.99


def test_numeric_refuses_non_finite_targets():
    with pytest.raises(ValueError, match="finite"):
        ik_numeric(Arm([1.0, 0.8, 0.5]), [[np.nan, 0.0]])
