"""Properties of rapp.arm: forward kinematics (TM:FWDKinematics) and the workspace annulus."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm, wrap_angle

lengths_st = st.lists(st.floats(0.05, 5.0), min_size=1, max_size=5)
angle_st = st.floats(-10.0, 10.0)


def fk_srs(lengths, q):
    """TM:FWDKinematics written out term by term: x = sum L_i cos(sum_{j<=i} theta_j)."""
    x = y = 0.0
    for i in range(len(lengths)):
        s = sum(q[: i + 1])
        x += lengths[i] * math.cos(s)
        y += lengths[i] * math.sin(s)
    return x, y


@settings(max_examples=100, deadline=None)
@given(st.data(), lengths_st)
def test_fk_batch_matches_srs_sum(data, lengths):
    n = len(lengths)
    qs = data.draw(st.lists(st.lists(angle_st, min_size=n, max_size=n), min_size=1, max_size=6))
    arm = Arm(lengths)
    q = np.array(qs).reshape(-1, 1, n)  # extra batch axis: shape (k, 1, n)
    pts = arm.joint_positions(q)
    assert pts.shape == (len(qs), 1, n + 1, 2)
    assert np.all(pts[..., 0, :] == 0.0)
    for k, qk in enumerate(qs):
        for j in range(1, n + 1):  # every joint is the FK of the arm cut after link j
            np.testing.assert_allclose(pts[k, 0, j], fk_srs(lengths[:j], qk[:j]), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(arm.end_effector(q), pts[..., -1, :])


@settings(max_examples=60, deadline=None)
@given(lengths_st, st.integers(0, 2**32 - 1))
def test_reach_annulus_contains_samples_and_outer_bound_attained(lengths, seed):
    arm = Arm(lengths)
    r_min, r_max = arm.reach
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (500, arm.n))
    r = np.linalg.norm(arm.end_effector(q), axis=-1)
    assert np.all(r >= r_min - 1e-9) and np.all(r <= r_max + 1e-9)
    assert np.linalg.norm(arm.end_effector(np.zeros(arm.n))) == pytest.approx(r_max, abs=1e-12)


@settings(max_examples=80, deadline=None)
@given(lengths_st)
def test_inner_bound_attained_by_folding_back_on_the_longest_link(lengths):
    arm = Arm(lengths)
    r_min = arm.reach[0]
    if r_min == 0.0 and arm.n > 1:
        return  # covered by the triangle test below
    k = int(np.argmax(lengths))
    phi = np.where(np.arange(arm.n) == k, 0.0, np.pi)  # absolute angles
    q = np.diff(phi, prepend=0.0)
    assert np.linalg.norm(arm.end_effector(q)) == pytest.approx(r_min, abs=1e-9)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.1, 3), st.floats(0.1, 3), st.floats(0.1, 3))
def test_inner_bound_zero_is_attained_by_a_closed_triangle(a, b, c):
    arm = Arm([a, b, c])
    if arm.reach[0] > 0:
        assert arm.reach[0] == pytest.approx(2 * max(a, b, c) - (a + b + c))
        return
    # Place the elbow X with |X - (a, 0)| = b and |X| = c: the arm returns to the base.
    x = (a * a + c * c - b * b) / (2 * a)
    y = math.sqrt(max(c * c - x * x, 0.0))
    phi = np.array([0.0, math.atan2(y, x - a), math.atan2(-y, -x)])
    q = np.diff(phi, prepend=0.0)
    assert np.linalg.norm(arm.end_effector(q)) == pytest.approx(0.0, abs=1e-6)


@settings(max_examples=100, deadline=None)
@given(st.floats(-100, 100))
def test_wrap_angle_range_and_equivalence(x):
    w = float(wrap_angle(x))
    assert -np.pi <= w < np.pi
    assert math.cos(w) == pytest.approx(math.cos(x), abs=1e-9)
    assert math.sin(w) == pytest.approx(math.sin(x), abs=1e-9)


def test_limits_and_properties():
    arm = Arm([1.0, 0.5], [None, (-1.0, 2.0)])
    assert arm.n == 2 and arm.limited.tolist() == [False, True]
    assert arm.lower.tolist() == [-np.pi, -1.0] and arm.upper.tolist() == [np.pi, 2.0]
    assert arm.within_limits([[5.0, 2.0], [0.0, 2.1], [0.0, -1.05]], tol=0.06).tolist() == [
        True, False, True]
    assert arm.absolute_angles([0.5, 0.25]).tolist() == [0.5, 0.75]


@pytest.mark.parametrize(
    "lengths, limits",
    [([], None), ([1.0, -1.0], None), ([1.0, np.nan], None), ([1.0], [(1.0, 0.0)]),
     ([1.0, 1.0], [None])],
)
def test_invalid_arm_rejected(lengths, limits):
    with pytest.raises(ValueError):
        Arm(lengths, limits)


def test_wrong_configuration_shape_rejected():
    with pytest.raises(ValueError):
        Arm([1.0, 1.0]).joint_positions([0.0, 0.0, 0.0])
