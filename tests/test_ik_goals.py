"""free_ik_solutions: the collision-free goal configurations of a Cartesian goal.

For 3+ links the IK solutions of a goal form a continuum (the self-motion
manifold). The cases here are built so that a free solution is known to exist
while most of the manifold collides: pick a configuration ``q*``, take the goal
``FK(q*)``, and place discs on the links of the other solutions, clear of
``q*``'s links. A search that samples the manifold sparsely says "no path"
for most of them; ``free_ik_solutions`` must find a free solution every time.
"""

import numpy as np
import pytest

from rapp.arm import Arm
from rapp.collision import collides, segment_point_distance
from rapp.errors import NoIKSolution, NoPathFound
from rapp.ik import free_ik_solutions, ik_2link
from rapp.obstacles import Circle


def manifold(arm, target, phis):
    """Solutions of ``target`` with the absolute angles of links 3..n equal to ``phis``
    (k, n - 2): the wrist is then fixed and the 2-link IK places the first two links.
    Independent of the code under test apart from the analytic 2-link IK."""
    tail = arm.lengths[2:]
    wrist = target - np.stack(((tail * np.cos(phis)).sum(-1), (tail * np.sin(phis)).sum(-1)), -1)
    q12 = ik_2link(arm.link_lengths[:2], wrist)                   # (k, 2 branches, 2)
    rows = []
    for branch in range(2):
        absolute = np.concatenate([q12[:, branch].sum(-1, keepdims=True), phis], axis=1)
        rows.append(np.concatenate([q12[:, branch], np.diff(absolute, axis=1)], axis=1))
    q = np.concatenate(rows)
    q = q[~np.isnan(q).any(axis=1)]
    assert np.abs(arm.end_effector(q) - target).max() < 1e-9
    return q


def constructed_case(rng, n=3, keep_out=0.3, max_discs=15):
    """(arm, goal, discs, q_star): ``q_star`` is free; the discs hit every solution
    of a dense sample of the manifold farther than ``keep_out`` rad from it (as far
    as ``max_discs`` discs get)."""
    arm = Arm(rng.uniform(0.4, 1.2, n))
    r_in, r_out = arm.reach
    while True:
        q_star = rng.uniform(-np.pi, np.pi, n)
        goal = arm.end_effector(q_star)
        if r_in + 0.1 < np.hypot(*goal) < r_out - 0.1:
            break
    if n == 3:
        phis = np.linspace(-np.pi, np.pi, 720, endpoint=False)[:, None]
    else:
        phis = rng.uniform(-np.pi, np.pi, (2500, n - 2))
    sols = manifold(arm, goal, phis)
    sols = sols[np.linalg.norm(arm.joint_delta(q_star, sols), axis=-1) > keep_out]
    star = arm.joint_positions(q_star)
    along = np.linspace(0.05, 1.0, 20)[:, None]
    discs = []
    for _ in range(max_discs):
        hit = collides(arm, sols, discs) if discs else np.zeros(len(sols), bool)
        if hit.all():
            break
        # A free solution of the sample; a disc on its link point farthest from q*'s links.
        pts = arm.joint_positions(sols[rng.choice(np.flatnonzero(~hit))])
        cand = (pts[:-1, None] + along * (pts[1:, None] - pts[:-1, None])).reshape(-1, 2)
        d = segment_point_distance(star[None, :-1], star[None, 1:], cand[:, None]).min(axis=1)
        best = int(np.argmax(d))
        if d[best] < 0.02:
            break
        discs.append(Circle(tuple(cand[best]), float(min(0.3, 0.8 * d[best]))))
    assert not collides(arm, q_star, discs)                        # the known free solution
    return arm, goal, discs, q_star


def check_goal_set(arm, goal, discs, free, count, cap=64):
    assert 1 <= len(free) <= cap and count >= len(free)
    assert np.abs(arm.end_effector(free) - goal).max() <= 1e-10
    assert not collides(arm, free, discs).any()
    assert arm.within_limits(free).all()
    d = np.linalg.norm(arm.joint_delta(free[:, None], free[None]), axis=-1)
    assert np.all(d[~np.eye(len(free), dtype=bool)] > 1e-6)


@pytest.mark.slow
def test_constructed_3link_goals_always_find_their_free_solution():
    # Before the dense search, 28 of these 50 cases (224 of 400 with seed 1)
    # ended in "every one of the 32 IK solutions ... collides".
    rng = np.random.default_rng(2024)
    free_fraction = []
    for _ in range(50):
        arm, goal, discs, q_star = constructed_case(rng)
        fine = manifold(arm, goal, np.linspace(-np.pi, np.pi, 2000, endpoint=False)[:, None])
        free_fraction.append(1.0 - collides(arm, fine, discs).mean())
        free, count = free_ik_solutions(arm, goal, discs)
        check_goal_set(arm, goal, discs, free, count)
    # The cases are hard: on average most of the manifold collides.
    assert np.mean(free_fraction) < 0.25


@pytest.mark.slow
@pytest.mark.parametrize("n", [4, 5])
def test_constructed_goals_with_more_links(n):
    # Before: 7 of the 10 four-link and 6 of the 10 five-link cases were false "no path".
    rng = np.random.default_rng(7 + n)
    for _ in range(10):
        arm, goal, discs, q_star = constructed_case(rng, n=n)
        free, count = free_ik_solutions(arm, goal, discs, q0=np.zeros(n))
        check_goal_set(arm, goal, discs, free, count)


def test_limited_arm_goal_set_respects_the_limits():
    rng = np.random.default_rng(5)
    for _ in range(10):
        arm, goal, discs, q_star = constructed_case(rng)
        # Limits around q*, so that q* stays a solution within them.
        lim = Arm(arm.link_lengths, [(float(v) - 1.5, float(v) + 1.0) for v in q_star])
        free, count = free_ik_solutions(lim, goal, discs)
        check_goal_set(lim, goal, discs, free, count)


def test_nearest_to_q0_first_and_spread():
    arm = Arm([1.0, 0.8, 0.5])
    q_star = np.array([0.4, -0.9, 1.2])
    goal = arm.end_effector(q_star)
    discs = [Circle((-0.6, 0.9), 0.3)]
    free, count = free_ik_solutions(arm, goal, discs, q0=q_star)
    check_goal_set(arm, goal, discs, free, count)
    dist = np.linalg.norm(arm.joint_delta(q_star, free), axis=-1)
    assert dist[0] < 1e-6                       # q0 is itself a free solution
    assert np.all(np.diff(dist) >= 0)
    assert len(free) == 64 and count > 1000
    # Spread: the returned rows reach across the free set, not one cluster near q0.
    assert dist.max() > 2.0
    again, _ = free_ik_solutions(arm, goal, discs, q0=q_star)
    assert np.array_equal(free, again)          # deterministic


def test_no_free_solution_says_what_was_searched():
    arm = Arm([1.0, 0.8, 0.5])
    with pytest.raises(NoPathFound, match=r"no collision-free IK solution found for the goal "
                       r"\(0\.9, 0\.3\) among \d+ solutions of the self-motion manifold "
                       r"sampled from \d+ starts projected by Newton-Raphson and 1024 "
                       r"wrist angles"):
        free_ik_solutions(arm, [0.9, 0.3], [Circle((0.9, 0.3), 0.05)])   # a disc on the goal


def test_complete_sets_keep_their_proof():
    # Two links: the analytic pair is every solution, so "every one" is a proof.
    with pytest.raises(NoPathFound, match="every one of the 2 IK solutions"):
        free_ik_solutions(Arm([1.0, 1.0]), [1.0, 1.0], [Circle((0.0, 1.0), 0.2),
                                                        Circle((1.0, 0.0), 0.2)])
    # On the outer circle of a 3-link arm the stretched arm is the only solution.
    with pytest.raises(NoPathFound, match="every one of the 1 IK solutions"):
        free_ik_solutions(Arm([1.0, 0.8, 0.5]), [2.3, 0.0], [Circle((1.0, 0.0), 0.1)])
    free, count = free_ik_solutions(Arm([1.0, 0.8, 0.5]), [0.0, 2.3], [Circle((1.0, 0.0), 0.1)])
    assert count == 1 and np.allclose(free, [[np.pi / 2, 0.0, 0.0]], atol=1e-12)
    with pytest.raises(NoIKSolution) as err:
        free_ik_solutions(Arm([1.0, 0.8, 0.5]), [2.5, 0.0], [])
    assert err.value.reason == "out of reach"
