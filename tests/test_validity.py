"""Bring your own checker (rapp.validity): a user's ``validity=`` respected by every planner.

The property every planner is held to (issue 35's done criterion): a keep-out disc for the end
effector, given only as ``validity=``, is respected by the path, re-checked by an independent
oracle at a step ten times finer than ``validity_resolution``. What a sampled check proves, and
so what the oracle asks: every point of a returned edge lies within ``r / 2`` (joint-space
distance) of a sample the planner checked (samples at most ``r`` apart, ends included), and
over a joint-space distance ``s`` the end effector moves at most ``s * |R|``
(:func:`rapp.validity.end_effector_travel`); so every point keeps out of the disc shrunk by
``|R| r / 2``. The oracle samples each path segment at ``r / 10`` and checks that shrunk disc.
The same planners without the checker enter the disc, so the test can fail.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rapp
from rapp import planners
from rapp.errors import InvalidSetting, NoPathFound
from rapp.validity import (DEFAULT_RESOLUTION, MAX_BATCH, UserValidity, check_configurations,
                          edges_valid, end_effector_travel, motion_samples, user_validity)

ARM = rapp.Arm([1.0, 1.0])
#: The keep-out disc of the end effector: it covers the straight arm's tip at pi/2.
CENTRE, RADIUS = np.array([0.0, 1.85]), 0.4
#: A certified obstacle too, on the other way round: both tests hold at once.
OBSTACLES = [rapp.Circle((-1.2, -1.2), 0.2)]
START, GOALS = [0.0, 0.0], [[2.6, 0.0]]
RESOLUTION = 0.05
#: Small settings per planner (rrt_star runs its whole budget; a wider goal region joins sooner).
OWN = {"rrt_star": {"max_iterations": 300, "goal_threshold": 0.3, "step": 0.3}}


def keep_out(q):
    """The user's checker: the end effector outside the disc."""
    return np.hypot(*(ARM.end_effector(q) - CENTRE).T) > RADIUS


def oracle_distance(path, step):
    """The end effector's smallest distance from the disc's centre over ``path``, each segment
    sampled (a plain loop) at most ``step`` apart, ends included."""
    points = []
    for a, b in zip(path[:-1], path[1:]):
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / step)))
        for i in range(k + 1):
            points.append(a + (b - a) * (i / k))
    return float(np.hypot(*(ARM.end_effector(np.array(points)) - CENTRE).T).min())


# --------------------------------------------------------------------------- the samples


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-3.0, 3.0), min_size=4, max_size=4),
       st.floats(1e-3, 1.0), st.booleans())
def test_samples_are_at_most_the_resolution_apart_along_the_edge_ends_included(x, r, wrap):
    qa, qb = np.array([x[:2]]), np.array([x[2:]])
    arm = ARM if wrap else None
    pts, counts = motion_samples(qa, qb, r, arm)
    d = qb - qa if arm is None else ARM.joint_delta(qa, qb)
    assert counts.tolist() == [len(pts)] and len(pts) >= 2
    assert np.array_equal(pts[0], qa[0]) and np.array_equal(pts[-1], qb[0])
    steps = np.linalg.norm(np.diff(pts[:-1], axis=0), axis=1) if len(pts) > 2 else np.zeros(0)
    assert (steps <= r * (1 + 1e-9)).all()
    last = np.linalg.norm(qa[0] + d[0] - pts[-2])   # the last step, to the end unwrapped
    assert last <= r * (1 + 1e-9) + 1e-12
    # on the straight edge qa -> qa + d
    t = (pts[:-1] - qa) @ d[0] / max(float(d[0] @ d[0]), 1e-300)
    assert np.allclose(qa + t[:, None] * d, pts[:-1], atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 6), st.floats(0.05, 0.5), st.integers(0, 2**31))
def test_edges_valid_is_the_plain_loop_over_each_edge_in_one_call(m, r, seed):
    rng = np.random.default_rng(seed)
    qa, qb = rng.uniform(-3, 3, (m, 2)), rng.uniform(-3, 3, (m, 2))
    calls = []

    def checker(q):
        calls.append(len(q))
        return q[:, 0] + 0.5 * q[:, 1] < 1.0

    got = edges_valid(checker, qa, qb, r)
    assert len(calls) == (1 if m else 0)   # one call for every sample of every edge
    expected = []
    for a, b in zip(qa, qb):   # the oracle: each edge, each sample, one at a time
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / r)))
        expected.append(all(checker(np.array([a + (b - a) * (i / k)]))[0] for i in range(k + 1)))
    assert got.tolist() == expected


@settings(max_examples=80, deadline=None)
@given(st.lists(st.floats(0.1, 2.0), min_size=1, max_size=4), st.integers(0, 2**31),
       st.floats(1e-4, 0.5))
def test_the_tip_moves_at_most_the_travel_bound_over_a_step(lengths, seed, step):
    # The lemma behind the oracle: over a joint-space move of length <= step, the end effector
    # moves at most end_effector_travel(lengths, step), all along the move.
    arm = rapp.Arm(lengths)
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (20, arm.n))
    dq = rng.normal(size=(20, arm.n))
    dq *= step * rng.uniform(0, 1, (20, 1)) / np.linalg.norm(dq, axis=1, keepdims=True)
    t = np.linspace(0.0, 1.0, 11)
    moved = arm.end_effector(q[:, None] + t[:, None] * dq[:, None]) - arm.end_effector(q)[:, None]
    assert np.linalg.norm(moved, axis=-1).max() <= end_effector_travel(lengths, step) * (1 + 1e-9)


def test_the_users_function_is_called_once_per_batch_not_once_per_sample():
    calls = []

    def checker(q):
        calls.append(q.shape)
        return np.ones(len(q), bool)

    edges_valid(checker, np.zeros((50, 2)), np.full((50, 2), 1.0), 0.01)
    assert len(calls) == 1 and calls[0][0] == 50 * (142 + 1)   # ceil(sqrt(2) / 0.01) steps
    calls.clear()
    check_configurations(checker, np.zeros((MAX_BATCH + 1, 2)))
    assert [c[0] for c in calls] == [MAX_BATCH, 1]


# --------------------------------------------------------------------------- bad checkers


@pytest.mark.parametrize("bad, words", [
    (lambda q: np.ones((len(q), 1), bool), "must return 3 booleans"),
    (lambda q: np.ones(len(q) + 1, bool), "must return 3 booleans"),
    (lambda q: q[:, 0], "dtype bool"),
    (lambda q: np.ones(len(q), int), "dtype bool"),
    (lambda q: 1 / 0, "validity raised ZeroDivisionError: division by zero"),
    (lambda q: None, "must return 3 booleans"),
])
def test_a_bad_answer_is_one_line_naming_validity(bad, words):
    with pytest.raises(InvalidSetting) as info:
        check_configurations(bad, np.zeros((3, 2)))
    assert info.value.setting == "validity" and words in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("name", sorted(planners.PLANNERS))
def test_every_planner_names_a_bad_checker_or_resolution(name):
    with pytest.raises(InvalidSetting) as info:
        planners.run(name, ARM, START, GOALS, [], validity=lambda q: q, seed=0, cells=16)
    assert info.value.setting == "validity" and "\n" not in str(info.value)
    with pytest.raises(InvalidSetting) as info:
        planners.run(name, ARM, START, GOALS, [], validity="keep out", seed=0, cells=16)
    assert info.value.setting == "validity"
    for r in (0.0, -1.0, float("nan"), 4.0, "x"):
        with pytest.raises(InvalidSetting) as info:
            planners.run(name, ARM, START, GOALS, [], validity=keep_out,
                         validity_resolution=r, seed=0, cells=16)
        assert info.value.setting == "validity_resolution"


def test_user_validity_defaults_and_refusals():
    assert user_validity(None) is None
    v = user_validity(keep_out)
    assert isinstance(v, UserValidity) and v.resolution == DEFAULT_RESOLUTION == 0.01
    assert v.text == "sampled at 0.01 rad, not certified"


# --------------------------------------------------------------------------- the planners


def plan(name, seed, **kw):
    return planners.run(name, ARM, START, GOALS, OBSTACLES, seed=seed, raise_on_failure=False,
                        **{**OWN.get(name, {}), **kw})


def respected(result):
    """The oracle: certified free of the obstacles, and out of the shrunk disc at r / 10."""
    gap = end_effector_travel(ARM.lengths, RESOLUTION) / 2
    assert rapp.path_collision_free(ARM, result.path, OBSTACLES)
    return oracle_distance(result.path, RESOLUTION / 10) > RADIUS - gap


def check_planner(name, seed):
    plain = plan(name, seed)
    assert plain.success and plain.certified and not respected(plain)   # it matters
    r = plan(name, seed, validity=keep_out, validity_resolution=RESOLUTION)
    assert r.success and r.status == "solved"
    assert np.allclose(r.path[0], START) and np.allclose(ARM.wrap(r.path[-1]), GOALS[0])
    assert respected(r)
    assert r.certified is False and r.checked_by == "sampled at 0.05 rad, not certified"
    assert r.validity_resolution == RESOLUTION


@pytest.mark.parametrize("name", sorted(planners.PLANNERS))   # rrt_connect, prm, rrt_star, ...
def test_a_keep_out_disc_given_only_as_validity_is_respected(name):
    check_planner(name, 0)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(planners.PLANNERS))
@pytest.mark.parametrize("seed", [1, 2])
def test_a_keep_out_disc_is_respected_for_other_seeds(name, seed):
    check_planner(name, seed)


def test_a_start_or_every_goal_the_checker_rejects_is_said():
    inside = [np.pi / 2, 0.0]   # the tip at (0, 2), inside the disc
    for name in sorted(planners.PLANNERS):
        with pytest.raises(NoPathFound, match="start configuration is rejected by validity"):
            planners.run(name, ARM, inside, GOALS, [], validity=keep_out, seed=0, cells=16)
        with pytest.raises(NoPathFound, match="every goal configuration is rejected by validity"):
            planners.run(name, ARM, START, [inside], [], validity=keep_out, seed=0, cells=16)


def test_a_failure_with_a_checker_says_so_and_astar_proves_nothing():
    wall = lambda q: np.abs(ARM.wrap(q)[:, 0] - 1.5) > 0.1   # noqa: E731  (joint 0 never at 1.5)
    r = planners.run("astar", ARM, [0.0, 0.0], [[3.0, 0.0]], [], validity=wall,
                     raise_on_failure=False, cells=32)
    assert r.success   # the other way round
    def blocked(q):   # joint 0 never at 1.5 nor at -1.5: no way from 0 to 3 either way round
        a = ARM.wrap(q)[:, 0]
        return (np.abs(a - 1.5) > 0.1) & (np.abs(a + 1.5) > 0.1)

    r = planners.run("astar", ARM, [0.0, 0.0], [[3.0, 0.0]], [], validity=blocked,
                     raise_on_failure=False, cells=32)
    assert not r.success and r.status == "grid too coarse" and r.certified is False
    r = planners.run("rrt_connect", ARM, [0.0, 0.0], [[3.0, 0.0]], [], validity=blocked,
                     raise_on_failure=False, max_iterations=200)
    assert not r.success and r.checked_by == "sampled at 0.01 rad, not certified"


def test_without_a_checker_nothing_changes():
    for name in sorted(planners.PLANNERS):
        a = plan(name, 0)
        b = plan(name, 0, validity=None)
        assert np.array_equal(a.path, b.path) and "checked_by" not in a.details and a.certified


# --------------------------------------------------------------------------- the report


def test_the_verification_report_says_sampled_never_certified():
    s = rapp.load_scenario("default")
    p = rapp.plan(s)
    away = lambda q: np.hypot(*s.arm.end_effector(q).T) > 0.1   # noqa: E731
    report = rapp.verify(p, s, validity=away, validity_resolution=0.02)
    line = [c for c in report.checks if c.name.startswith("validity")]
    assert len(line) == 1 and line[0].ok
    assert line[0].name == "validity (sampled at 0.02 rad, not certified)"
    text = str(report)
    row = [r for r in text.splitlines() if r.startswith("validity")][0]
    assert "sampled at 0.02 rad, not certified" in row and "certified" not in row.replace(
        "not certified", "")
    assert rapp.verify(p, s) == p.report   # without a checker, the same report as before
    everywhere = rapp.verify(p, s, validity=lambda q: np.zeros(len(q), bool))
    assert not everywhere.ok and everywhere.failed[0].name.startswith("validity")


# --------------------------------------------------------------------------- the table, the files


def test_every_entry_of_the_table_takes_the_checker_and_no_file_can():
    for entry in planners.PLANNERS.values():
        assert entry.code_keys == ("validity", "validity_resolution")
        assert entry.default("validity") is None
        assert entry.default("validity_resolution") == DEFAULT_RESOLUTION
        assert not set(entry.code_keys) & set(entry.keys)
    assert not {"validity", "validity_resolution"} & set(planners.all_settings())
    d = rapp.load_scenario("default").to_dict()
    for key in ("validity", "validity_resolution"):
        d["planner"] = {"algorithm": "rrt_connect", key: 0.1}
        with pytest.raises(rapp.errors.InvalidValue) as info:
            rapp.load_scenario(d)
        assert info.value.field == f"planner.{key}" and "cannot carry" in str(info.value)
