"""The helpers the chapters call instead of hidden code: rapp.cartesian's ride along a line,
rapp.ik's plain iterations and damped step, rapp.symbolic's checks, the line-ride explorer."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rapp
from rapp import symbolic
from rapp.cartesian import line_fraction, line_path, ride_line, tip_along_edges
from rapp.ik import damped_step, dls_step, ik_2link, ik_failure, iterate_ik

ARM = rapp.Arm([1.0, 1.0])


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=6, max_size=6), st.integers(1, 5))
def test_tip_along_edges_interpolates_each_edge_in_joint_space(flat, per_edge):
    qs = np.array(flat).reshape(3, 2)
    expected = [ARM.end_effector(qs[i] + k / per_edge * (qs[i + 1] - qs[i]))      # the slow way
                for i in range(2) for k in range(per_edge)] + [ARM.end_effector(qs[-1])]
    assert np.allclose(tip_along_edges(ARM, qs, per_edge), expected)


def test_line_fraction_is_the_projection():
    pts = np.array([[0.0, 1.0], [2.0, 2.0], [-1.0, 0.0]])
    a, b = np.array([0.0, 0.0]), np.array([2.0, 2.0])
    assert np.allclose(line_fraction(pts, a, b), [np.dot(p, b) / 8.0 for p in pts])


def test_ride_line_keeps_the_tip_on_the_line_at_the_planned_speed():
    a, b = np.array([-0.9, 0.35]), np.array([1.85, 0.35])
    q_line = line_path(ARM, ik_2link(ARM, a)[0], b, tolerance=1e-3)
    ride = ride_line(ARM, a, b, q_line, vmax=0.5, amax=0.5)
    assert np.isclose(ride.timing.duration, ride.length / 0.5 + 1.0)
    for t in np.linspace(0.0, ride.timing.duration, 13):
        q, xdot, qdot = ride.state(t)
        assert abs(ARM.end_effector(q)[1] - 0.35) < 2e-3                  # on the line, within tolerance
        assert np.allclose(rapp.jacobian(ARM, q) @ qdot, xdot)
        assert xdot[1] == 0 and 0 <= xdot[0] <= 0.5 + 1e-12
    assert np.allclose(ride.state(0.0)[2], 0.0) and np.allclose(ride.state(ride.timing.duration)[2], 0.0)


def _newton_one(arm, target, q0, lam, iterations):
    # One start at a time, the textbook formulas written out.
    q, errs = np.array(q0, float), []
    for _ in range(iterations):
        e = target - arm.end_effector(q)
        J = rapp.jacobian(arm, q)
        errs.append(np.linalg.norm(e))
        q = q + (np.linalg.solve(J, e) if lam == 0 else J.T @ np.linalg.inv(J @ J.T + lam**2 * np.eye(2)) @ e)
    return np.array(errs), q


@pytest.mark.parametrize("lam", [0.0, 0.05])
def test_iterate_ik_is_the_textbook_iteration_start_by_start(lam):
    target = 1.5 * np.array([np.cos(0.4), np.sin(0.4)])
    starts = np.random.default_rng(1).uniform(-1, 1, (5, 2)) + [0.4, 1.0]
    errors, travel, q = iterate_ik(ARM, target, starts, lam, iterations=12)
    for k, q0 in enumerate(starts):
        errs, qk = _newton_one(ARM, target, q0, lam, 12)
        assert np.allclose(errors[:, k], errs, atol=1e-12) and np.allclose(q[k], qk, atol=1e-9)
    assert np.allclose(travel[0], 0.0)


def test_damped_step_is_dls_step_column_by_column():
    rng = np.random.default_rng(2)
    arm = rapp.Arm([1.0, 0.8, 0.5])
    qs, e = rng.uniform(-3, 3, (4, 3)), rng.uniform(-0.1, 0.1, (4, 2))
    J = rapp.jacobian(arm, qs)
    got = damped_step(J, e, 1e-3, 1e-2)
    for k in range(4):
        one = dls_step(J[k, 0][:, None], J[k, 1][:, None], e[k, :1], e[k, 1:], 1e-3, 1e-2)[:, 0]
        assert np.allclose(got[k], one)


def test_ik_failure_names_the_reason_or_none():
    limited = rapp.Arm([1.0, 0.8], joint_limits=[(0.0, np.pi / 2), (0.0, np.pi / 2)])
    arm = rapp.Arm([1.0, 0.8])
    assert ik_failure(arm, [2.0, 0.5]) == "out of reach" == ik_failure(arm, [0.1, 0.0])
    assert ik_failure(limited, [-1.0, -0.6]) == "joint limits"
    assert ik_failure(arm, [1.0, 0.6]) is None


def test_symbolic_checks_agree_and_consume_the_generator_as_the_chapters_do():
    c = symbolic.check_ik_2link(np.random.default_rng(0), arms=10)
    assert all(c["elbow_order"]) and c["worst_angle"] < 1e-12 and c["worst_tip"] < 1e-12
    rng = np.random.default_rng(0)
    j = symbolic.check_jacobian(rng, links=2, samples=10)
    assert j["shapes"] == [True, True] and max(j["central"]) < 1e-8
    # the draws: lengths then configurations, per number of links
    ref = np.random.default_rng(0)
    for n in (1, 2):
        ref.uniform(0.3, 1.5, size=n), ref.uniform(-np.pi, np.pi, size=(10, n))
    assert rng.random() == ref.random()
    f = symbolic.check_fk(np.random.default_rng(0), links=2, samples=10, joints_checked=3)
    assert set(f["fk"]) == {1, 2} and max(f["joints"].values()) < 1e-12


def test_a_check_fails_when_the_package_disagrees(monkeypatch):
    import importlib
    ik_module = importlib.import_module("rapp.ik")
    original = ik_module.jacobian
    monkeypatch.setattr(ik_module, "jacobian", lambda arm, q: 1.01 * original(arm, q))
    assert max(symbolic.check_jacobian(np.random.default_rng(0), links=2, samples=10)["sympy"]) > 1e-3


def test_line_ride_explorer_reports_each_instant():
    from rapp.view_stack import selected, sliders_of
    from rapp.widgets import line_ride_explorer

    a, b = np.array([1.0, 0.5]), np.array([1.5, 0.5])
    ride = ride_line(ARM, a, b, line_path(ARM, ik_2link(ARM, a)[0], b), vmax=0.5, amax=0.5)
    w = line_ride_explorer(ride, frames=5, default=2)
    assert len(sliders_of(w)[0].options) == 5
    assert selected(w)[1].startswith("t = 1.00 s: tip speed 0.50 m/s")
