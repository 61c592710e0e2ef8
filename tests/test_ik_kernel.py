"""The compiled numerical IK (rapp.kernels.ik_numba) against ik_numeric's numpy path, its oracle.

Properties: every target reported solved is within tolerance by the caller's own check
(``ok`` is exactly that check), on random arms of 2-6 links, and every reachable target of
an arm without limits is solved; targets out of reach (beyond the outer circle, inside the
hole) are failures in both paths; both paths solve the same targets from the default start
and from the caller's; the closed-form start is exact wherever it exists, and exists exactly
where a straight tail lets the first two links reach the wrist; the compiled check of that
start is numpy's within a few rounding errors, and the compiled atan2 libm's within a few ulp.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm
from rapp.kernels import ik as ik_kernel
from rapp.ik import closed_form_start, ik_numeric

pytestmark = pytest.mark.skipif(ik_kernel.solver() is None, reason="numba is not installed")

TOL = 1e-10


def solve(arm, targets, compiled, **kw):
    """``ik_numeric`` by the compiled solver or by the numpy iteration, whatever the batch size."""
    saved = ik_kernel.loaded
    ik_kernel.loaded = (lambda m: ik_kernel.solver()) if compiled else (lambda m: None)
    try:
        return ik_numeric(arm, targets, **kw)
    finally:
        ik_kernel.loaded = saved


def tip_error(arm, q, targets):
    with np.errstate(over="ignore"):
        return np.linalg.norm(arm.end_effector(q) - targets, axis=-1)


def random_arm(rng, n, hole=False):
    lengths = rng.uniform(0.2, 1.5, n)
    if hole:  # one link longer than all the others together: the workspace has a hole
        lengths[rng.integers(n)] = 1.2 * lengths.sum()
    return Arm(lengths)


def rim_and_far_targets(arm, rng, k=20):
    """Points on, just inside and just outside both boundary circles, far away, and the base."""
    r_in, r_out = arm.reach
    th = rng.uniform(-np.pi, np.pi, k)
    u = np.stack((np.cos(th), np.sin(th)), axis=-1)
    radii = [r_out, r_out * (1 - 1e-10), r_out * (1 + 1e-9), r_out * 1.5, r_in, r_in + 1e-9]
    if r_in > 0:
        radii += [r_in * (1 - 1e-9), 0.5 * r_in]
    return np.concatenate([r * u for r in radii] + [[[0.0, 0.0], [1e3, -2e3]]])


@settings(max_examples=15, deadline=None)
@given(st.integers(2, 6), st.integers(0, 2**31 - 1), st.booleans(), st.booleans())
def test_every_solution_is_within_tolerance(n, seed, compiled, hole):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n, hole)
    reachable = arm.end_effector(rng.uniform(-np.pi, np.pi, (60, n)))
    targets = np.concatenate([reachable, rim_and_far_targets(arm, rng, 5)])
    q, ok = solve(arm, targets, compiled, tol=TOL)
    err = tip_error(arm, q, targets)
    assert np.array_equal(ok, err <= TOL)            # ok is the caller's own check
    assert ok[:60].all()                             # every reachable target is solved
    assert np.all((q >= -np.pi) & (q < np.pi))
    r = np.hypot(*targets.T)
    assert not ok[r > arm.reach[1] + TOL].any()      # nothing beyond the outer circle
    assert not ok[r < arm.reach[0] - TOL].any()      # nor inside the hole


@pytest.mark.slow
@settings(max_examples=25, deadline=None)
@given(st.integers(2, 6), st.integers(0, 2**31 - 1), st.booleans())
def test_both_paths_solve_the_same_targets(n, seed, hole):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n, hole)
    targets = np.concatenate([arm.end_effector(rng.uniform(-np.pi, np.pi, (100, n))),
                              rim_and_far_targets(arm, rng)])
    for q0 in (None, np.zeros(n), rng.uniform(-np.pi, np.pi, (len(targets), n))):
        _, ok_c = solve(arm, targets, True, q0=q0, tol=TOL)
        _, ok_n = solve(arm, targets, False, q0=q0, tol=TOL)
        assert np.array_equal(ok_c, ok_n)


@settings(max_examples=12, deadline=None)
@given(st.integers(2, 5), st.integers(0, 2**31 - 1))
def test_both_paths_agree_within_joint_limits(n, seed):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-2.5, 0.0, n)
    arm = Arm(rng.uniform(0.2, 1.5, n), list(zip(lo, lo + rng.uniform(1.0, 3.0, n))))
    # Solutions strictly inside the limits (on a limit the restarts decide, see below).
    targets = arm.end_effector(rng.uniform(arm.lower + 0.05, arm.upper - 0.05, (100, n)))
    q_c, ok_c = solve(arm, targets, True, tol=TOL)
    q_n, ok_n = solve(arm, targets, False, tol=TOL)
    for q, ok in ((q_c, ok_c), (q_n, ok_n)):
        assert np.all(arm.within_limits(q))
        assert np.array_equal(ok, tip_error(arm, q, targets) <= TOL)
    # The two iterations differ in the last bits of cos/sin; a target solved by one and not
    # the other would need a restart that the other did not draw. Rare, never a wrong ok.
    assert (ok_c != ok_n).mean() <= 0.02
    assert abs(ok_c.mean() - ok_n.mean()) <= 0.02


@pytest.mark.parametrize("tol", [1e-15, 1e-12])
def test_ok_is_exact_at_tolerances_near_round_off(tol):
    # Tip errors within a few rounding errors of tol are decided by numpy's own check.
    rng = np.random.default_rng(11)
    arm = Arm([1.0, 0.8, 0.5])
    targets = np.concatenate([arm.end_effector(rng.uniform(-np.pi, np.pi, (3000, 3))),
                              rim_and_far_targets(arm, rng)])
    q, ok = solve(arm, targets, True, tol=tol)
    assert np.array_equal(ok, tip_error(arm, q, targets) <= tol)
    assert ok.mean() > 0.9


def closed_form_exists_by_sweep(lengths, target, k=20001):
    """Oracle: some direction of the straight tail puts the wrist within the first two links' annulus."""
    l1, l2, lt = lengths[0], lengths[1], lengths[2:].sum()
    a = np.linspace(-np.pi, np.pi, k)
    wrist = target[:, None] - lt * np.stack((np.cos(a), np.sin(a)))
    d = np.hypot(*wrist)
    return bool(np.any((d >= abs(l1 - l2)) & (d <= l1 + l2)))


@settings(max_examples=20, deadline=None)
@given(st.integers(2, 6), st.integers(0, 2**31 - 1), st.booleans())
def test_closed_form_start_is_exact_where_it_exists(n, seed, hole):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, n, hole)
    lengths = arm.lengths / arm.lengths.sum()
    r = rng.uniform(0.0, 1.1, 40)
    th = rng.uniform(-np.pi, np.pi, 40)
    targets = np.stack((r * np.cos(th), r * np.sin(th)))
    q, exists = closed_form_start(lengths, targets)
    scaled = Arm(lengths)
    err = tip_error(scaled, q.T, targets.T)
    assert err[exists].max(initial=0.0) <= 1e-14
    # Where the answer is not a rounding error away, the sweep agrees on where it exists.
    lo_d = np.maximum(abs(lengths[0] - lengths[1]), np.abs(r - lengths[2:].sum()))
    hi_d = np.minimum(lengths[0] + lengths[1], r + lengths[2:].sum())
    clear = np.abs(hi_d - lo_d) > 1e-3
    for i in np.flatnonzero(clear):
        assert exists[i] == closed_form_exists_by_sweep(lengths, targets[:, i])
    # The compiled solver starts from the same configuration (its Newton-Raphson idle).
    q_c, ok_c = solve(scaled, targets.T, True, tol=1e-12, restarts=0)
    same = exists & ok_c
    assert np.abs(np.angle(np.exp(1j * (q_c[same] - q.T[same])))).max(initial=0.0) <= 1e-9


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(0, 2**31 - 1), st.booleans(), st.floats(-3.0, 3.0))
def test_start_error_is_numpys_within_a_few_rounding_errors(n, seed, hole, exponent):
    # The compiled check of a closed-form start sums the link directions instead of calling
    # cos and sin; ok stays exact because this differs from numpy's evaluation by far less
    # than the 64 rounding errors the solver leaves undecided.
    rng = np.random.default_rng(seed)
    arm = Arm(random_arm(rng, n, hole).lengths * 10.0**exponent)
    targets = np.concatenate([arm.end_effector(rng.uniform(-np.pi, np.pi, (200, n))),
                              rim_and_far_targets(arm, rng)])
    q = np.zeros((len(targets), n))
    err = ik_kernel.solver().start_errors(arm.lengths, targets, q)
    have = ~np.isnan(err)
    assert have.any()
    eps = np.finfo(float).eps
    bound = 16 * eps * (arm.lengths.sum() + np.abs(targets[have]).sum(axis=1))
    assert np.all(np.abs(err[have] - tip_error(arm, q[have], targets[have])) <= bound)


def test_atan2_is_libms_within_a_few_ulp():
    atan2 = ik_kernel.solver().atan2
    rng = np.random.default_rng(3)
    y = rng.standard_normal(20_000) * 10.0 ** rng.uniform(-8, 8, 20_000)
    x = rng.standard_normal(20_000) * 10.0 ** rng.uniform(-8, 8, 20_000)
    # the octant edges, the switch at 0.66, extreme ratios, signed zeros, infinities, NaN
    edges = [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (0.66, 1.0), (np.nextafter(0.66, 1), 1.0),
             (1.0, 0.66), (1e-300, 1.0), (1.0, 1e-300), (5e-324, -1.0), (0.0, 1.0), (-0.0, 1.0),
             (0.0, -1.0), (-0.0, -1.0), (0.0, 0.0), (-0.0, -0.0), (1.0, 0.0), (-1.0, -0.0),
             (np.inf, 1.0), (1.0, -np.inf), (np.inf, np.inf), (np.nan, 1.0)]
    y = np.concatenate([y, [a for a, _ in edges]])
    x = np.concatenate([x, [b for _, b in edges]])
    got = np.array([atan2(a, b) for a, b in zip(y, x)])
    ref = np.arctan2(y, x)
    assert np.array_equal(np.isnan(got), np.isnan(ref))
    fine = ~np.isnan(ref)
    assert np.all(np.abs(got[fine] - ref[fine]) <= 4 * np.spacing(np.abs(ref[fine])))
    assert np.array_equal(np.signbit(got[fine]), np.signbit(ref[fine]))
