"""rapp.cartesian.line_path: the tip follows a straight segment, between waypoints too."""

import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import rapp
import rapp.cartesian
from rapp import Arm, Circle
from rapp.cartesian import edge_deviation_bound, line_path
from rapp.collision import segment_point_distance
from rapp.errors import PathNotFollowable, RappError
from rapp.ik import ik_2link

TOL = 1e-3


def _s_of(message: str) -> float:
    m = re.search(r"at s=([0-9.]+)", message)
    assert m, message
    return float(m.group(1))


def _dense_deviation(arm, q, a, b, samples=33):
    """Largest distance from the segment ab of the tip along every joint-space edge of q."""
    t = np.linspace(0.0, 1.0, samples)
    qs = q[:-1, None, :] + t[None, :, None] * (q[1:] - q[:-1])[:, None, :]
    return float(segment_point_distance(a, b, arm.end_effector(qs.reshape(-1, arm.n))).max())


def _r_range(a, b):
    """Smallest and largest distance from the base along the segment ab."""
    d = b - a
    s = np.clip(-(a @ d) / (d @ d), 0.0, 1.0)
    return float(np.hypot(*(a + s * d))), max(float(np.hypot(*a)), float(np.hypot(*b)))


def _crossing(a, b, radius, first=True):
    """The s at which |a + s (b - a)| = radius, the smaller root (first) or the larger."""
    d = b - a
    A, B, C = d @ d, a @ d, a @ a - radius * radius
    root = np.sqrt(B * B - A * C)
    return float((-B - root) / A if first else (-B + root) / A)


arms = st.builds(
    lambda ls, n: Arm(ls[:n]),
    st.lists(st.floats(0.4, 1.2), min_size=3, max_size=3),
    st.sampled_from([2, 3]),
)


@st.composite
def reachable_lines(draw):
    """An arm, a start and a goal with the whole segment well inside the annulus."""
    arm = draw(arms)
    q0 = np.array(draw(st.lists(st.floats(-np.pi, np.pi), min_size=arm.n, max_size=arm.n)))
    r_in, r_out = max(0.0, 2 * float(arm.lengths.max()) - float(arm.lengths.sum())), float(arm.lengths.sum())
    band = 0.08 * r_out
    # A start away from the singular (collinear) configurations, which are tested apart.
    assume(np.linalg.svd(rapp.jacobian(arm, q0), compute_uv=False)[-1] >= 0.05 * r_out)
    a = arm.end_effector(q0)
    rad = draw(st.floats(r_in + band, r_out - band))
    ang = draw(st.floats(-np.pi, np.pi))
    goal = rad * np.array([np.cos(ang), np.sin(ang)])
    lo, hi = _r_range(a, goal)
    assume(lo >= r_in + band and hi <= r_out - band)
    assume(np.hypot(*(goal - a)) > 1e-3)
    return arm, q0, goal


@settings(max_examples=25, deadline=None)
@given(reachable_lines())
def test_tip_stays_on_the_segment_at_and_between_waypoints(line):
    arm, q0, goal = line
    a = arm.end_effector(q0)
    q = line_path(arm, q0, goal, tolerance=TOL)
    assert q.ndim == 2 and q.shape[1] == arm.n and q.shape[0] >= 2
    assert np.array_equal(q[0], q0)  # starts at q_start exactly
    assert np.linalg.norm(arm.end_effector(q[-1]) - goal) <= TOL
    assert segment_point_distance(a, goal, arm.end_effector(q)).max() <= TOL
    assert _dense_deviation(arm, q, a, goal) <= TOL
    # Continuation: every joint step small and bounded, no jump to another branch.
    assert np.linalg.norm(np.diff(q, axis=0), axis=1).max() <= 0.1 + 1e-12
    if arm.n == 2:  # the elbow keeps its side: sin q2 never changes sign
        s2 = np.sin(q[:, 1])
        assert np.all(s2 > 0) or np.all(s2 < 0)


@settings(max_examples=6, deadline=None)
@given(reachable_lines(), st.sampled_from([1e-2, 2e-4]), st.sampled_from([0.05, 0.3]))
def test_tolerance_and_max_step_are_honoured(line, tol, max_step):
    arm, q0, goal = line
    a = arm.end_effector(q0)
    q = line_path(arm, q0, goal, tolerance=tol, max_step=max_step)
    assert _dense_deviation(arm, q, a, goal) <= tol
    assert np.linalg.norm(np.diff(q, axis=0), axis=1).max() <= max_step + 1e-12


@settings(max_examples=60, deadline=None)
@given(arms, st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6), st.floats(-0.6, 0.6),
       st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))
def test_edge_deviation_bound_holds_between_samples(arm, qs, step, bx, by):
    """The curvature bound is a proof: dense samples never exceed it."""
    qa = np.array(qs[:arm.n])
    qb = qa + step * np.array(qs[3:3 + arm.n]) / 3.0
    a = arm.end_effector(qa)
    b = a + np.array([bx, by])
    bound = edge_deviation_bound(arm, qa, qb, a, b)
    t = np.linspace(0.0, 1.0, 257)
    dev = segment_point_distance(a, b, arm.end_effector(qa + t[:, None] * (qb - qa))).max()
    assert dev <= bound + 1e-12


# ------------------------------------------------------------------ failures, named and placed


@settings(max_examples=20, deadline=None)
@given(reachable_lines(), st.floats(1.05, 1.6))
def test_leaving_the_outer_circle_is_reported_with_s(line, factor):
    arm, q0, _ = line
    a = arm.end_effector(q0)
    r_out = float(arm.lengths.sum())
    ang = np.arctan2(a[1], a[0]) + 0.3
    goal = factor * r_out * np.array([np.cos(ang), np.sin(ang)])
    with pytest.raises(PathNotFollowable, match="workspace") as info:
        line_path(arm, q0, goal)
    s = _s_of(str(info.value))
    assert abs(s - _crossing(a, goal, r_out, first=False)) <= 1e-3
    assert info.value.reason == "workspace" and "\n" not in str(info.value)


def test_two_link_line_through_the_inner_boundary_leaves_the_workspace():
    arm = Arm([1.0, 0.6])  # hole of radius 0.4
    a, goal = np.array([-1.0, 0.2]), np.array([1.0, 0.2])
    q0 = ik_2link(arm, a)[0]
    with pytest.raises(PathNotFollowable, match="leaves the workspace") as info:
        line_path(arm, q0, goal)
    assert abs(_s_of(str(info.value)) - _crossing(a, goal, 0.4)) <= 1e-3
    assert "inner circle" in str(info.value)


def test_tangent_to_the_inner_circle_is_a_singularity():
    arm = Arm([1.0, 0.6])
    q0 = ik_2link(arm, (-1.0, 0.4))[0]
    with pytest.raises(PathNotFollowable, match=r"passes a singularity at s=0\.500") as info:
        line_path(arm, q0, (1.0, 0.4))
    assert info.value.reason == "singularity"
    # Just above the circle the line is followable, with the elbow on the same side throughout.
    q = line_path(arm, q0, (1.0, 0.45))
    assert np.all(np.sin(q[:, 1]) > 0)


def test_line_through_the_base_of_an_equal_link_arm_is_a_singularity():
    arm = Arm([1.0, 1.0])  # the folded arm puts the tip on the base
    q0 = np.array([np.pi / 2 + 0.2, np.pi - 0.4])
    a = arm.end_effector(q0)
    with pytest.raises(PathNotFollowable, match=r"singularity at s=0\.500.*folded"):
        line_path(arm, q0, -a)


def test_stretched_arm_is_a_singularity():
    arm = Arm([1.0, 1.0])
    with pytest.raises(PathNotFollowable, match=r"singularity at s=1\.000.*stretched"):
        line_path(arm, [0.3, 1.0], (2.0, 0.0))  # the goal needs the stretched arm
    with pytest.raises(PathNotFollowable, match=r"singularity at s=0\.000.*stretched"):
        line_path(arm, [0.0, 0.0], (1.0, 0.5))  # the start is stretched
    # Close to the circle but clear of it: followed, ending within tolerance.
    q = line_path(arm, [0.3, 1.0], (2.0 - 1e-5, 0.0))
    assert np.linalg.norm(arm.end_effector(q[-1]) - (2.0 - 1e-5, 0.0)) <= TOL


def test_collinear_three_link_start_is_a_singularity(monkeypatch):
    """Folded straight inside the annulus: the tip can only move across the arm at first.
    A restart turns the arm along its self-motion first (tip held), out of the singularity."""
    arm = Arm([1.0, 0.5, 0.75])
    with monkeypatch.context() as m:
        m.setattr(rapp.cartesian, "RESTART_ANGLES", ())
        with pytest.raises(PathNotFollowable, match=r"singularity at s=0\.000"):
            line_path(arm, [0.0, 0.0, np.pi], (-0.5, 1.1))
    q = line_path(arm, [0.0, 0.0, np.pi], (-0.5, 1.1))
    a = arm.end_effector(np.array([0.0, 0.0, np.pi]))
    assert _dense_deviation(arm, q, a, np.array([-0.5, 1.1])) <= TOL
    # Across the arm (the direction the Jacobian still spans) it moves off at once.
    q = line_path(arm, [0.0, 0.0, np.pi], (0.75, 0.5))
    assert _dense_deviation(arm, q, np.array([0.75, 0.0]), np.array([0.75, 0.5])) <= TOL


def test_two_link_joint_limit_is_reported_with_the_joint_and_s():
    arm = Arm([1.0, 1.0], [None, (0.3, 2.0)])
    q0 = np.array([0.0, 1.0])
    a, goal = arm.end_effector(q0), np.array([1.99, 0.0])
    with pytest.raises(PathNotFollowable, match=r"^θ2 \(joint_limits\[1\]\) leaves its limits") as info:
        line_path(arm, q0, goal)
    # q2 = 0.3 where |tip| = sqrt(2 + 2 cos 0.3).
    s_true = _crossing(a, goal, np.sqrt(2 + 2 * np.cos(0.3)), first=False)
    assert abs(_s_of(str(info.value)) - s_true) <= 2e-3
    assert info.value.reason == "joint limits"


def test_three_link_joint_limit_is_reported():
    arm = Arm([1.0, 0.8, 0.5], [None, (-1.0, 1.0), (-0.5, 0.5)])
    with pytest.raises(PathNotFollowable, match=r"^θ[23] \(joint_limits\[[12]\]\) leaves its limits .* at s=0\.\d+"):
        line_path(arm, [0.0, 0.5, 0.3], (0.3, 0.3))  # folding in needs more bend than allowed


@pytest.mark.parametrize("n", [2, 3])
def test_segment_through_a_disc_hits_the_obstacle(n):
    arm = Arm([1.0, 0.8, 0.5][:n])
    q0 = np.array([0.9, -1.4, 0.5][:n])
    a = arm.end_effector(q0)
    goal = a + np.array([-0.3, -1.0])
    mid = 0.5 * (a + goal)
    obstacles = [Circle((-3.0, -3.0), 0.1), Circle(tuple(mid), 0.05)]
    with pytest.raises(PathNotFollowable, match=r"hits obstacle 1 \(obstacles\[1\]\)") as info:
        line_path(arm, q0, goal, obstacles)
    # The tip enters the disc at s = 0.5 - 0.05 / |goal - a|; a link may hit it earlier.
    assert 0.0 < _s_of(str(info.value)) <= 0.5 - 0.05 / np.linalg.norm(goal - a) + 1e-3
    assert info.value.reason == "obstacle"
    # Without the disc on the line the same segment is followed and certified free.
    q = line_path(arm, q0, goal, obstacles[:1])
    assert rapp.path_collision_free(arm, q, obstacles[:1])


def test_start_in_collision_is_reported_at_s_zero():
    arm = Arm([1.0, 1.0])
    with pytest.raises(PathNotFollowable, match=r"hits obstacle 0 .* at s=0\.000"):
        line_path(arm, [0.3, 1.0], (1.0, 0.5), [Circle((0.5, 0.15), 0.1)])


# ------------------------------------------------------------------ the contract


def test_error_is_a_rapp_error_exported_by_the_package():
    assert issubclass(PathNotFollowable, RappError)
    assert rapp.PathNotFollowable is PathNotFollowable and "PathNotFollowable" in rapp.__all__


def test_goal_at_the_start_is_one_waypoint():
    arm = Arm([1.0, 0.7])
    q0 = np.array([0.2, 0.9])
    q = line_path(arm, q0, arm.end_effector(q0))
    assert q.shape == (1, 2) and np.array_equal(q[0], q0)


def test_free_joints_are_not_wrapped_across_the_seam():
    """A base joint crossing +-pi continues past it: every edge is the short motion."""
    arm = Arm([1.0, 0.7])
    q0 = ik_2link(arm, (-1.2, 0.5))[0]
    q = line_path(arm, q0, (-1.2, -0.5))
    assert np.abs(np.diff(q, axis=0)).max() <= 0.1


@pytest.mark.parametrize("kwargs, match", [
    (dict(q_start=[0.1]), r"q_start must have shape"),
    (dict(q_start=[[0.1, 0.2]]), r"q_start must be one configuration"),
    (dict(goal_xy=(np.nan, 0.0)), r"goal_xy must be a finite point"),
    (dict(goal_xy=(1.0, 0.0, 0.0)), r"goal_xy must be a finite point"),
    (dict(tolerance=0.0), r"tolerance"),
    (dict(max_step=-1.0), r"max_step"),
    (dict(obstacles=[(1.0, 1.0)]), r"obstacles must be"),
    (dict(arm=[1.0, 1.0]), r"arm must be a rapp.Arm"),
    (dict(arm=Arm([1.0, 1.0], [None, (1.0, 2.0)])), r"outside the joint limits"),
])
def test_bad_input_is_a_value_error(kwargs, match):
    args = dict(arm=Arm([1.0, 1.0]), q_start=[0.1, 0.5], goal_xy=(1.0, 0.5))
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        line_path(args.pop("arm"), args.pop("q_start"), args.pop("goal_xy"), **args)
