"""Seed 002 (cubic via-point trajectories, obstacle, 2-link arm): every printed number.

Each table is recomputed three ways that must agree: numpy.linalg.solve of the
seed's own matrix equation (eq. 5-6), rapp.trajectory.cubic, and
rapp.cases.via_point_detour.cubic_segment shifted to absolute time. Printed numbers are
compared at their printed precision (half a unit of the last printed digit).

Numbers the seed prints wrong (the tests assert the correct value):

* eq. 20 and 24: a_DC,0 = 144.56; correct 146.3008. Check: with 144.56,
  x_DC(5.5) = 8.4592, not D_x = 10.2.
* eq. 21 and 39: b_AB,0 = 2; correct 5 (= y_A; eq. 25 and 43 print +5).
* eq. 33: "0.5914t^2 - 7.9834 + 26.0198" lost the t of the middle term
  (-7.9834 t); its numbers are right.
* eq. 50: -1.1491 t^2; correct +1.1491 t^2 (3 x b_BD,3 = 3 x 0.3830 > 0).
* eq. 34: Q1,up = atan(y/x) + asin(L2 sin Q2 / r) with Q2,up < 0 puts the tip
  at (13.18, -8.44) for C = (14, 7); the sign must be minus (as in eq. 36).
* Task 3's D = (9.86, 5.32) is feasible but not the grid optimum: (9.87, 5.32)
  on the same 0.01 grid is also clear and shorter (10.01733 < 10.01784).

Reading of the seed: Constraint 1 says 0.25 m/s "in the X-direction" at B,
but every y table uses ydot_B = 0.25 as well (the table row "(xdot, ydot) 0.25").
"""

import numpy as np
import pytest

from rapp import Circle
from rapp.trajectory import cubic, via_points
from rapp.cases.via_point_detour import (
    arm_link_distance,
    cubic_segment,
    first_arm_collision,
    path_clearance,
    search_via_point,
    spline_vs_cubic,
    tangent_via_point,
    to_absolute_time,
)

A, B, C = (2.0, 5.0), (5.0, 8.0), (14.0, 7.0)
VB = (0.25, 0.25)
OBS = Circle((10.0, 7.0), 1.5)
D2_SEED = (10.20, 8.54)
D3_SEED = (9.86, 5.32)


def seed_matrix_solve(t0, tf, p0, pf, v0, vf):
    """Eq. 6 literally: inverse of the seed's 4x4 matrix times the boundary values (a3..a0)."""
    M = np.array([[t0**3, t0**2, t0, 1], [3 * t0**2, 2 * t0, 1, 0],
                  [tf**3, tf**2, tf, 1], [3 * tf**2, 2 * tf, 1, 0]], dtype=float)
    return np.linalg.solve(M, [p0, v0, pf, vf])


def table(points, times, vels, axis):
    """Descending coefficients [a3, a2, a1, a0] of every segment, stacked like eqs. 10/11/20/21."""
    out = []
    for i in range(len(points) - 1):
        args = (times[i], times[i + 1], points[i][axis], points[i + 1][axis], vels[i][axis], vels[i + 1][axis])
        a = seed_matrix_solve(*args)
        b = cubic(*args)[::-1]
        c = to_absolute_time(cubic_segment([args[2]], [args[3]], [args[4]], [args[5]], args[1] - args[0]),
                             args[0])[:, 0][::-1]
        np.testing.assert_allclose(b, a, rtol=1e-10, atol=1e-9)
        np.testing.assert_allclose(c, a, rtol=1e-10, atol=1e-9)
        out.append(a)
    return np.concatenate(out)


def velocity_table(coef_desc):
    """[3 a3, 2 a2, a1] per segment from a stacked descending table."""
    c = np.asarray(coef_desc).reshape(-1, 4)
    return (c[:, :3] * [3, 2, 1]).ravel()


def assert_printed(computed, printed):
    """Printed strings are matched at their own precision."""
    for value, text in zip(np.ravel(computed), printed):
        decimals = len(text.split(".")[1]) if "." in text else 0
        assert abs(value - float(text)) <= 0.5 * 10**-decimals + 1e-12, (value, text)


TASK1 = dict(points=[A, B, C], times=[0, 3, 8], vels=[(0, 0), VB, (0, 0)])


def task_tables(D):
    kw = dict(points=[A, B, D, C], times=[0, 3, 5.5, 8], vels=[(0, 0), VB, (0, 0), (0, 0)])
    return table(axis=0, **kw), table(axis=1, **kw)


def test_task1_eq10_to_19():
    x, y = table(axis=0, **TASK1), table(axis=1, **TASK1)
    assert_printed(x, ["-0.1944", "0.9167", "0", "2", "-0.134", "2.186", "-9.248", "16.688"])  # eq 10, 12, 13
    assert_printed(y, ["-0.1944", "0.9167", "0", "5", "0.026", "-0.454", "2.272", "4.568"])  # eq 11, 14, 15
    assert_printed(y[4:], ["0.026", "-0.4540", "2.272", "4.568"])  # eq 15
    assert_printed(velocity_table(x), ["-0.5833", "1.833", "0", "-0.402", "4.372", "-9.248"])  # eq 16, 17
    assert_printed(velocity_table(y), ["-0.5833", "1.833", "0", "0.078", "-0.908", "2.272"])  # eq 18, 19


def test_task1_y_tables_use_ydot_b_025():
    # b_AB,2 = 3 dy / T^2 - ydot_B / T, so the printed 0.9167 gives ydot_B = 3 (1 - 0.9167) = 0.25.
    assert 3 * (1 - 0.9167) == pytest.approx(0.25, abs=1e-3)
    y0 = table(axis=1, points=[A, B, C], times=[0, 3, 8], vels=[(0, 0), (0.25, 0.0), (0, 0)])
    assert abs(y0[0] - -0.1944) > 0.02  # the "x-direction only" reading does not give eq. 11


def test_task2_eq20_to_33():
    x, y = task_tables(D2_SEED)
    assert_printed(x[:11], ["-0.1944", "0.9167", "0", "2", "-0.6256", "7.9264", "-30.4172", "41.8052",
                            "-0.4864", "9.8496", "-64.2048"])  # eq 20, 22-24
    # eq 20/24 print a_DC,0 = 144.56: x_DC(5.5) would be 8.4592, not 10.2.
    printed = np.polyval([-0.4864, 9.8496, -64.2048, 144.56], 5.5)
    assert printed == pytest.approx(8.4592, abs=1e-3)
    assert x[11] == pytest.approx(146.3008, abs=1e-4)
    assert np.polyval(x[8:], 5.5) == pytest.approx(10.2, abs=1e-9)
    # eq 21 prints b_AB,0 = 2; y_A = 5 (eq 25 prints +5).
    assert y[3] == pytest.approx(5.0)
    assert_printed(y[4:], ["-0.0291", "0.3213", "-0.8914", "8.5690", "0.1971", "-3.9917", "26.0198", "-46.6166"])
    assert_printed(velocity_table(x)[3:], ["-1.8768", "15.8528", "-30.4172", "-1.4592", "19.6992", "-64.2048"])
    # eq 33's middle term lacks its t; the numbers match.
    assert_printed(velocity_table(y)[3:], ["-0.0874", "0.6426", "-0.8914", "0.5914", "-7.9834", "26.0198"])


def test_task3_eq38_to_51():
    x, y = task_tables(D3_SEED)
    assert_printed(x, ["-0.1944", "0.9167", "0", "2", "-0.5821", "7.3715", "-28.2630", "39.1614",
                       "-0.5299", "10.7309", "-69.9494", "158.1382"])  # eq 38, 40-42
    assert y[3] == pytest.approx(5.0)  # eq 39 prints 2 (eq 43: +5)
    assert_printed(y[4:], ["0.3830", "-4.9338", "19.5105", "-16.4697", "-0.2150", "4.3546", "-28.3853", "65.4909"])
    assert_printed(velocity_table(x)[3:], ["-1.7462", "14.7430", "-28.2630", "-1.5898", "21.4618", "-69.9494"])
    vy = velocity_table(y)[3:]
    assert vy[0] == pytest.approx(1.14912, abs=1e-5)  # eq 50 prints -1.1491
    assert_printed(vy[1:], ["-9.8675", "19.5105", "-0.6451", "8.7091", "-28.3853"])


def test_task2_grid_search_reproduces_seed_D():
    d = search_via_point(B, C, OBS, v_start=VB)
    assert np.round(d.point, 2).tolist() == list(D2_SEED)
    assert d.clearance > OBS.radius  # Condition 2A on the exact cubic path
    # The refined point sits on the edge of its refinement window (10.1 + 0.1): not converged.
    finer = search_via_point(B, C, OBS, v_start=VB, resolutions=(0.1, 0.01, 0.001))
    assert finer.length < d.length - 1e-3
    assert finer.clearance > OBS.radius


def test_task2_tangent_construction_and_why_the_grid_differs():
    t = tangent_via_point(B, C, OBS)
    assert t.clearance == pytest.approx(OBS.radius, abs=1e-9)
    # The seed's D is longer than the tangent point, the converged grid search shorter: the cubic
    # BD bulges towards v_B (away from the disc), so its path clears where the straight BD would not.
    seed = search_via_point(B, C, OBS, v_start=VB)
    # A third pass over a wide window (±0.1 at 0.001) finds the shorter points below the tangent
    # from B; narrow windows (the default) stall on the thin feasible wedge and stay above it.
    finer = search_via_point(B, C, OBS, v_start=VB, resolutions=(0.1, 0.01, 0.001), refine_bound=0.1)
    assert np.round(finer.point, 3).tolist() == [10.245, 8.519]
    assert finer.length < t.length < seed.length
    assert finer.clearance > OBS.radius
    from rapp.collision import segment_point_distance
    assert segment_point_distance(B, finer.point, OBS.center) < OBS.radius  # straight BD cuts the disc


@pytest.mark.slow
def test_task3_search_and_seed_D():
    d = search_via_point(B, C, OBS, v_start=VB, arm_lengths=(9, 9))
    assert np.round(d.point, 2).tolist() == [9.87, 5.32]
    L = lambda p: np.hypot(*np.subtract(p, B)) + np.hypot(*np.subtract(C, p))  # noqa: E731
    assert L(d.point) < L(D3_SEED)
    for D in (d.point, D3_SEED):
        assert path_clearance(D, B, C, OBS.center, v_start=VB) > OBS.radius
    # Continuous-time certificate for the seed's D, elbow down: both links clear at every time.
    dist, bound = arm_link_distance((9, 9), D3_SEED, B, C, OBS.center, v_start=VB, samples=20001)
    assert bound > OBS.radius
    assert first_arm_collision((9, 9), D3_SEED, B, C, OBS, v_start=VB, elbow="down") is None


def test_task3_elbow_up_collides_and_task2_D_fails_condition3():
    t, link = first_arm_collision((9, 9), D3_SEED, B, C, OBS, v_start=VB, elbow="up")
    assert link == 2 and 5.5 < t < 8.0
    t2, link2 = first_arm_collision((9, 9), D2_SEED, B, C, OBS, v_start=VB, elbow="down")
    assert link2 == 2 and 3.0 < t2 < 5.5


def test_eq34_to_37_ik():
    L1 = L2 = 9.0
    x, y = C
    r = np.hypot(x, y)
    q2u = -np.arccos((x * x + y * y - L1**2 - L2**2) / (2 * L1 * L2))
    fk = lambda a, b: np.array([L1 * np.cos(a) + L2 * np.cos(a + b), L1 * np.sin(a) + L2 * np.sin(a + b)])  # noqa: E731
    q1u_printed = np.arctan(y / x) + np.arcsin(L2 * np.sin(q2u) / r)  # eq 34 as printed
    assert np.linalg.norm(fk(q1u_printed, q2u) - C) > 10
    q1u = np.arctan(y / x) - np.arcsin(L2 * np.sin(q2u) / r)
    np.testing.assert_allclose(fk(q1u, q2u), C, atol=1e-9)
    q2d = -q2u  # eq 36-37 are right
    q1d = np.arctan(y / x) - np.arcsin(L2 * np.sin(q2d) / r)
    np.testing.assert_allclose(fk(q1d, q2d), C, atol=1e-9)
    from rapp.ik import ik_2link
    np.testing.assert_allclose(ik_2link((9, 9), C), [[q1d, q2d], [q1u, q2u]], atol=1e-9)
    # Figure 16: at C the elbow-up arm's link 2 meets the obstacle, elbow-down does not.
    from rapp import Arm, collides
    assert collides(Arm([9, 9]), [[q1u, q2u], [q1d, q2d]], [OBS]).tolist() == [True, False]


def test_spline_lowers_peaks():
    for D in (D2_SEED, D3_SEED):
        out = spline_vs_cubic([0, 3, 5.5, 8], [A, B, D, C], [(0, 0), VB, (0, 0), (0, 0)])
        assert out["spline"][0] < out["cubic"][0] and out["spline"][1] < out["cubic"][1]
    pp = via_points([0, 3, 5.5, 8], [A, B, D2_SEED, C], velocities=[(0, 0), VB, (0, 0), (0, 0)])
    assert spline_vs_cubic([0, 3, 5.5, 8], [A, B, D2_SEED, C],
                           [(0, 0), VB, (0, 0), (0, 0)])["cubic"][1] == pytest.approx(
        np.abs(np.linalg.norm(pp.evaluate(np.array([5.5 - 1e-12, 5.5]), 2), axis=-1)).max(), rel=1e-6)


# --------------------------------------------------------------------------- eqs. 34-37 as printed

def _reach(lens, q):
    """The tip of a 2-link arm, written out (the oracle of the domain test)."""
    return np.stack([lens[:, 0] * np.cos(q[:, 0]) + lens[:, 1] * np.cos(q.sum(1)),
                     lens[:, 0] * np.sin(q[:, 0]) + lens[:, 1] * np.sin(q.sum(1))], -1)


@pytest.mark.parametrize("sign", [+1, -1])
def test_printed_ik_is_right_exactly_on_its_domain(sign):
    # Inside x > 0 and L1 + L2 cos Q2 >= 0 the printed formulas reach the target; outside they miss.
    from rapp.cases.via_point_detour import printed_ik

    rng = np.random.default_rng(11)
    lens = rng.uniform(0.3, 2.0, (4000, 2))
    P = _reach(lens, rng.uniform(-np.pi, np.pi, (4000, 2)))
    with np.errstate(invalid="ignore", divide="ignore"):
        Q = printed_ik(P, sign, lengths=(lens[:, 0], lens[:, 1]), strict=False)
    miss = np.linalg.norm(_reach(lens, Q) - P, axis=1)
    margin = np.minimum(P[:, 0], lens[:, 0] + lens[:, 1] * np.cos(Q[:, 1]))
    ok = (np.linalg.norm(P, axis=1) > 0.05) & (np.abs(np.sin(Q[:, 1])) > 1e-2)  # off the boundaries
    assert (miss[ok & (margin > 1e-3)] < 1e-6).all()
    assert (miss[ok & (margin < -1e-2)] > 1e-3).all()
    assert (ok & (margin < -1e-2)).sum() > 500 and (ok & (margin > 1e-3)).sum() > 500


def test_printed_ik_refuses_points_outside_its_domain_when_strict():
    from rapp.cases.via_point_detour import printed_ik

    for links, target in (((1.0, 1.0), [-1.0, 0.5]), ((0.5, 1.0), [0.6, 0.0])):
        with pytest.raises(ValueError, match="outside the domain"):
            printed_ik(target, +1, lengths=links)
        assert printed_ik(target, +1, lengths=links, strict=False).shape == (2,)
    q = printed_ik([[14.0, 7.0], [9.0, 5.0]], -1, sign_q1=-1.0)  # elbow up, corrected: reaches C
    assert np.allclose(_reach(np.full((2, 2), 9.0), q), [[14.0, 7.0], [9.0, 5.0]])
