"""Seed 003 (3-link RRT report): its conventions, its Jacobian, its rectangles, its experiment.

Quotes from the report are in comments; each test computes the report's claim and compares
it with an independent derivation (sympy, finite differences, dense sampling).
"""

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from rapp import Arm, NoPathFound, Polygon, collides, jacobian, segment_collision_free
from rapp.collision import segment_hits_polygon
from rapp.rrt import rrt
from rapp.cases.rrt_report import (
    alpha_beta_experiment,
    GOAL_THETA,
    SQUARE_SIDE,
    START_THETA,
    THETA_LIMIT,
    compare_with_astar,
    printed_jacobian,
    rapp_to_report,
    report_fk,
    report_rotation,
    report_to_rapp,
    seed_arm,
    seed_square,
)
from rapp.symbolic import fk_symbolic

angles3 = st.lists(st.floats(-np.pi, np.pi), min_size=3, max_size=3).map(np.array)
lengths3 = st.lists(st.floats(0.1, 2.0), min_size=3, max_size=3).map(np.array)


# -- conventions --------------------------------------------------------------------------


@settings(max_examples=100, deadline=None)
@given(theta=angles3, lengths=lengths3)
def test_report_fk_is_rapp_fk_after_the_angle_change(theta, lengths):
    # "x = l1 sin(t1) + l2 sin(t1 + t2) + l3 sin(t1 + t2 + t3), y = l1 cos(t1) + ..." (eq. 2)
    np.testing.assert_allclose(report_fk(lengths, theta),
                               Arm(lengths).end_effector(report_to_rapp(theta)), atol=1e-12)
    np.testing.assert_allclose(rapp_to_report(report_to_rapp(theta)), theta, atol=1e-12)


def test_report_fk_symbolically_equals_rapp_fk():
    f, q, L = fk_symbolic(3)
    t = sp.symbols("t1:4", real=True)
    sub = {q[0]: sp.pi / 2 - t[0], q[1]: -t[1], q[2]: -t[2]}
    report = sp.Matrix([sum(L[i] * sp.sin(sum(t[: i + 1])) for i in range(3)),
                        sum(L[i] * sp.cos(sum(t[: i + 1])) for i in range(3))])
    assert sp.simplify(f.subs(sub) - report) == sp.zeros(2, 1)


@settings(max_examples=50, deadline=None)
@given(theta=angles3, lengths=lengths3, a=st.floats(-np.pi, np.pi), b=st.floats(-np.pi, np.pi))
def test_report_rotation_builds_the_report_fk(theta, lengths, a, b):
    # eq. 1: x' = x cos t + y sin t, y' = -x sin t + y cos t: a clockwise turn (rapp's by -t).
    R = report_rotation(np.cumsum(theta))  # (3, 2, 2)
    links = np.stack((np.zeros(3), lengths), -1)  # every link drawn along +y, then turned
    np.testing.assert_allclose(np.einsum("kij,kj->i", R, links), report_fk(lengths, theta), atol=1e-12)
    np.testing.assert_allclose(report_rotation(a) @ report_rotation(b), report_rotation(a + b), atol=1e-12)
    ccw = np.array([[np.cos(-a), -np.sin(-a)], [np.sin(-a), np.cos(-a)]])
    np.testing.assert_allclose(report_rotation(a), ccw, atol=1e-12)


# -- the Jacobian (report eq. 3) ------------------------------------------------------------


def _true_report_jacobian():
    J_printed, l, t = printed_jacobian()
    Theta = [t[0], t[0] + t[1], t[0] + t[1] + t[2]]
    fk = sp.Matrix([sum(li * sp.sin(T) for li, T in zip(l, Theta)),
                    sum(li * sp.cos(T) for li, T in zip(l, Theta))])
    return fk.jacobian(sp.Matrix(t)), J_printed, l, t


def test_printed_jacobian_is_wrong_and_exactly_where():
    J, P, l, t = _true_report_jacobian()
    diff = (P - J).applyfunc(sp.simplify)
    summ = (P + J).applyfunc(sp.simplify)
    # Five entries are the negative of the truth: the sign of d(sin)/dt and d(cos)/dt flipped.
    for i, j in [(0, 0), (0, 1), (0, 2), (1, 0), (1, 2)]:
        assert summ[i, j] == 0 and diff[i, j] != 0, (i, j)
    # dy/dt2, printed "l2 sin(t1 + t2) - l3 sin(t1 + t2 + t3)", is neither J nor -J:
    # the truth is -l2 sin(t1 + t2) - l3 sin(t1 + t2 + t3); the l2 term's sign is wrong.
    assert diff[1, 1] == sp.simplify(2 * l[1] * sp.sin(t[0] + t[1]))
    assert summ[1, 1] == sp.simplify(-2 * l[2] * sp.sin(t[0] + t[1] + t[2]))
    # The correct entries, as the book prints them.
    assert sp.simplify(J[0, 0] - (l[0] * sp.cos(t[0]) + l[1] * sp.cos(t[0] + t[1])
                                  + l[2] * sp.cos(t[0] + t[1] + t[2]))) == 0
    assert sp.simplify(J[1, 1] + l[1] * sp.sin(t[0] + t[1]) + l[2] * sp.sin(t[0] + t[1] + t[2])) == 0


@pytest.mark.slow
@settings(max_examples=50, deadline=None)
@given(theta=angles3, lengths=lengths3)
def test_true_report_jacobian_matches_finite_differences_and_rapp(theta, lengths):
    J, P, l, t = _true_report_jacobian()
    env = dict(zip(l, lengths)) | dict(zip(t, theta))
    Jn = np.array(J.subs(env).evalf(), dtype=float)
    Pn = np.array(P.subs(env).evalf(), dtype=float)
    h = 1e-6
    fd = np.stack([(report_fk(lengths, theta + h * e) - report_fk(lengths, theta - h * e)) / (2 * h)
                   for e in np.eye(3)], -1)
    np.testing.assert_allclose(Jn, fd, atol=1e-6)
    # Chain rule through q = (pi/2 - t1, -t2, -t3): dq/dt = -I.
    np.testing.assert_allclose(Jn, -jacobian(Arm(lengths), report_to_rapp(theta)), atol=1e-12)
    # The printed matrix fails the check unless the arm's reach is ~0 (all sines and cosines vanish).
    if np.abs(fd).max() > 1e-3:
        assert not np.allclose(Pn, fd, atol=1e-4)


# -- rectangles and separating axes (§4.6) ----------------------------------------------------


@settings(max_examples=100, deadline=None)
@given(x=st.floats(-2, 2), y=st.floats(-2, 2), w=st.floats(0.05, 2), h=st.floats(0.05, 2),
       a=st.floats(-np.pi, np.pi))
def test_rectangle_from_corner_follows_the_report(x, y, w, h, a):
    v = np.array(Polygon.rectangle((x, y), w, h, a).vertices)
    # "its adjacent vertex will be x + w cos(t), y + w sin(t)"
    assert np.isclose(v, [x + w * np.cos(a), y + w * np.sin(a)], atol=1e-9).all(-1).any()
    # Opposite corner: sqrt(w^2 + h^2) times sin and cos of (angle ACB + angle C), with
    # tan(ACB) = w / h. It holds when the figure's angle C is -t (measured clockwise).
    d, acb = np.hypot(w, h), np.arctan(w / h)
    far = [x + d * np.sin(acb - a), y + d * np.cos(acb - a)]
    assert np.isclose(v, far, atol=1e-9).all(-1).any()


def _dense_hits(a, b, poly, k=3000):
    """Obviously correct, slow: sample the segment, test each point against every edge."""
    t = np.linspace(0, 1, k)[:, None]
    pts = a + t * (b - a)
    v = poly.array
    e = np.roll(v, -1, axis=0) - v
    rel = pts[:, None, :] - v
    cross = (e[:, 0] * rel[..., 1] - e[:, 1] * rel[..., 0]) / np.linalg.norm(e, axis=-1)
    # One sample spacing, and never less than rounding: a zero-length segment on a corner
    # would otherwise be held to a tolerance of exactly zero.
    margin = max(np.linalg.norm(b - a) / (k - 1), 1e-12 * (1.0 + np.abs(v).max()))
    # Inside by more than rounding (an exact touch is decided by the last bit: see the lead's
    # notes), or within one sample spacing of the polygon.
    assert np.array_equal(poly.contains(pts), (cross >= 0).all(-1))  # same test as contains
    return bool((cross > 1e-9).all(-1).any()), bool((cross >= -margin).all(-1).any())


point = st.tuples(st.floats(-2, 2), st.floats(-2, 2)).map(np.array)


@settings(max_examples=200, deadline=None)
@given(a=point, b=point, c=point, w=st.floats(0.1, 1.5), h=st.floats(0.1, 1.5),
       ang=st.floats(-np.pi, np.pi))
@example(a=np.array([-8.970470336602435e-308, 0.0]), b=np.array([-8.970470336602435e-308, 0.0]),
         c=np.array([0.0, 0.0]), w=1.0, h=1.0, ang=-2.0)   # a point on a corner, found once
@example(a=np.array([1e-133, 0.0]), b=np.array([1e-133, 0.0]), c=np.array([0.0, 0.0]),
         w=0.5, h=0.5, ang=0.3)
def test_separating_axes_agree_with_dense_sampling(a, b, c, w, h, ang):
    rect = Polygon.rectangle(c, w, h, ang)
    sat = bool(segment_hits_polygon(a, b, rect))
    inside, near = _dense_hits(a, b, rect)
    if inside:
        assert sat
    if sat:
        assert near  # within one sample spacing: a grazing hit can fall between samples


@settings(max_examples=60, deadline=None)
@given(theta=st.lists(st.floats(-THETA_LIMIT, THETA_LIMIT), min_size=3, max_size=3),
       c=point, ang=st.floats(-np.pi, np.pi))
def test_arm_collision_agrees_with_dense_sampling(theta, c, ang):
    arm = seed_arm()
    q = report_to_rapp(np.array(theta))
    rect = seed_square(c, ang)
    pts = arm.joint_positions(q)
    dense = [_dense_hits(pts[i], pts[i + 1], rect, 500) for i in range(3)]
    hit = bool(collides(arm, q, [rect]))
    if any(d[0] for d in dense):
        assert hit
    if hit:
        assert any(d[1] for d in dense)


@settings(max_examples=200, deadline=None)
@given(a=st.floats(-5, 5), la=st.floats(0, 3), b=st.floats(-5, 5), lb=st.floats(0, 3))
def test_report_overlap_cases_are_one_condition(a, la, b, lb):
    amin, amax, bmin, bmax = a, a + la, b, b + lb
    # "Amin < Bmin, Amax > Bmin / Amin < Bmax, Amax > Bmin / Amin > Bmin, Amax < Bmax /
    #  Amin < Bmin, Amax > Bmax": the union is the second line alone.
    cases = [amin < bmin and amax > bmin, amin < bmax and amax > bmin,
             amin > bmin and amax < bmax, amin < bmin and amax > bmax]
    assert any(cases) == cases[1]


def test_overlap_on_one_axis_is_not_a_collision():
    # "Once the overlap conditions are satisfied, the program terminates": overlapping
    # projections on one axis prove nothing; only a gap on some axis is conclusive.
    sq = Polygon.rectangle((0.0, 0.0), 1.0, 1.0)
    a, b = np.array([1.5, -1.0]), np.array([2.5, 0.5])
    x_overlap = min(a[1], b[1]) <= 1.0 and max(a[1], b[1]) >= 0.0  # on the axis normal to y
    assert x_overlap and not segment_hits_polygon(a, b, sq)


# -- the RRT set-up and experiment (§4, §5) -------------------------------------------------


def test_report_constants():
    # "Nodes are randomly generated within the boundaries, in this case -1.5 to 1.5"
    arm = seed_arm()
    lo, hi = np.array(arm.joint_limits).T
    assert np.allclose(rapp_to_report(np.stack((lo, hi))).min(0), -THETA_LIMIT)
    assert np.allclose(rapp_to_report(np.stack((lo, hi))).max(0), THETA_LIMIT)
    # "a 0.2 by 0.2 square obstacle"
    v = seed_square().array
    assert SQUARE_SIDE == 0.2 and np.allclose(np.linalg.norm(np.diff(v, axis=0), axis=-1), 0.2)


def _problem():
    arm = seed_arm()
    return arm, report_to_rapp(START_THETA), report_to_rapp(GOAL_THETA), [seed_square()]


def test_seed_problem_needs_a_detour():
    arm, s, g, obs = _problem()
    assert not collides(arm, np.stack((s, g)), obs).any()
    assert not segment_collision_free(arm, s, g, obs)


def test_beta_one_never_leaves_the_blocked_straight_line():
    # Always sampling the goal (beta = 1) grows the tree only along the straight segment,
    # which the square blocks: the report's "high beta increases efficiency" fails here.
    arm, s, g, obs = _problem()
    res = rrt(arm, s, g, obs, step=0.3, goal_bias=1.0, steer="fraction", max_iterations=200,
              raise_on_failure=False)
    assert not res.success
    u = (g - s) / np.linalg.norm(g - s)
    off = (res.nodes - s) - np.outer((res.nodes - s) @ u, u)
    assert np.abs(off).max() < 1e-12
    with pytest.raises(NoPathFound):
        rrt(arm, s, g, obs, step=0.3, goal_bias=1.0, steer="fraction", max_iterations=200)


def test_cost_without_the_square_is_lower_in_every_cell():
    # "graph 1, regardless of alpha and beta values, maintains a lower cost than in graph 2"
    arm, s, g, obs = _problem()
    gxy = arm.end_effector(g)
    kw = dict(alphas=[0.4, 1.0], betas=[0.1, 0.5], trials=2, seed=0, goal=g, max_iterations=600)
    free = alpha_beta_experiment(arm, s, gxy, [], **kw)
    blocked = alpha_beta_experiment(arm, s, gxy, obs, **kw)
    both = ~np.isnan(blocked["mean_cost"])
    assert both.any()
    assert np.all(free["success_rate"] == 1.0)
    assert np.all(free["mean_cost"][both] < blocked["mean_cost"][both])


def test_compare_with_astar():
    arm, s, g, obs = _problem()
    out = compare_with_astar(arm, s, g, obs, cells=16, rrt_settings={"step": 0.2, "goal_bias": 0.2})
    straight = np.linalg.norm(g - s)
    assert out["straight_distance"] == pytest.approx(straight)
    # Both go round the square, so both are strictly longer than the blocked straight line.
    assert out["rrt_cost"] > straight and out["astar_cost"] > straight
    assert out["astar_seconds"] >= 0 and out["rrt_seconds"] >= 0


def test_seed_problem_is_the_report_problem():
    from rapp.cases.rrt_report import seed_problem

    arm, obs, s, g = seed_problem()
    ref_arm, ref_s, ref_g, ref_obs = _problem()
    assert arm.joint_limits == ref_arm.joint_limits and np.allclose(obs[0].array, ref_obs[0].array)
    assert np.allclose(s, ref_s) and np.allclose(g, ref_g)


def test_the_angle_box_is_the_joint_limits_and_the_reach_box_is_vacuous():
    # Error 6: "-1.5 to 1.5" read once, as bounds on the report's angles in radians.
    arm = seed_arm()
    corners = np.array(np.meshgrid(*[[-1.5, 1.5]] * 3)).reshape(3, -1).T  # the report's angle box
    assert arm.within_limits(report_to_rapp(corners)).all()
    assert not arm.within_limits(report_to_rapp(1.01 * corners)).any()
    np.testing.assert_allclose(arm.joint_limits, [(np.pi / 2 - 1.5, np.pi / 2 + 1.5), (-1.5, 1.5), (-1.5, 1.5)])
    whole_circle = np.random.default_rng(6).uniform(-np.pi, np.pi, (20000, 3))  # the IK range
    assert np.abs(Arm([0.5, 0.5, 0.5]).joint_positions(whole_circle)).max() <= 1.5 + 1e-12  # a 1.5 m box
    assert (~arm.within_limits(whole_circle)).mean() > 0.85  # the angle box excludes most of it
    assert THETA_LIMIT < np.pi  # two different ranges in the report


def test_wilson_interval_inverts_the_score_test():
    from rapp.cases.rrt_report import wilson_interval

    p = np.linspace(0.0, 1.0, 200_001)
    for n in (4, 30):
        for k in range(n + 1):
            accepted = p[np.abs(k / n - p) <= 1.96 * np.sqrt(p * (1 - p) / n)]
            lo, hi = wilson_interval(k, n)
            assert abs(accepted.min() - lo) < 1e-4 and abs(accepted.max() - hi) < 1e-4


def test_mean_interval_skips_failed_trials_like_a_loop():
    from rapp.cases.rrt_report import mean_interval

    x = np.random.default_rng(3).normal(size=(4, 5, 7))
    x[x > 1.0] = np.nan
    m, h = mean_interval(x)
    for i in np.ndindex(x.shape[:-1]):
        v = x[i][~np.isnan(x[i])]
        if len(v) >= 2:
            assert np.isclose(m[i], v.mean()) and np.isclose(h[i], 1.96 * v.std(ddof=1) / np.sqrt(len(v)))
        else:
            assert np.isnan(h[i])


def test_success_table_rows_hold_the_counts_and_wilson_bounds():
    from rapp.cases.rrt_report import success_table, wilson_interval

    k = np.array([[0, 30], [15, 28]])
    lines = success_table(k, 30, [0.25, 1.0], [0.05, 1.0]).splitlines()
    lo, hi = wilson_interval(k, 30)
    assert len(lines) == 3 and lines[0].split()[-2:] == ["0.05", "1"]
    assert f"28  [{lo[1, 1]:.2f}, {hi[1, 1]:.2f}]" in lines[2] and lines[1].split()[0] == "0.25"


def test_the_walks_of_a_tree():
    from rapp.cases.rrt_report import printed_walk, walk_to_root

    s = np.array([0.0, 0.0])
    res = rrt(Arm([1.0, 1.0]), s, [2.5, 2.5], [], step=0.2, goal_bias=0.1, seed=0)
    np.testing.assert_allclose(walk_to_root(res.nodes, res.parent), res.path, atol=1e-12)
    printed = printed_walk(res.nodes, res.parent, s)
    assert len(res.path) > 5 and len(printed) == len(res.path) - 2  # start and final node missing
    assert not np.allclose(printed, res.path[1:-1])  # and the order is scrambled


def test_seed_scenario_plans_the_report_problem():
    from rapp.cases.rrt_report import seed_problem, seed_scenario
    from rapp.scenario import load_scenario

    arm, obs, s, g = seed_problem()
    sc = load_scenario(seed_scenario(arm, s, g, {"algorithm": "rrt", "step": 0.2, "seed": 0}))
    assert np.allclose(sc.arm.lengths, arm.lengths) and np.allclose(sc.start, s)
    assert np.allclose(sc.obstacles[0].array, obs[0].array)
