"""The compiled and the numpy collision kernels against the oracle (rapp.reference, per configuration).

Properties: the compiled ``collides``, ``link_clearances`` and ``segment_collision_free`` give
the numpy answers on random arms, obstacles and configurations (touching counts as collision
in both); the sampling planners grow the same trees from the same seeds with either; without
numba everything falls back to the numpy versions.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rapp
from rapp import reference
from rapp.kernels import collision_numba as collision_kernel
from rapp.kernels import collision_numpy
from rapp.kernels import collision as collision_dispatch
from rapp.collision import collides, link_clearances, segment_collision_free
from rapp.prm import prm

prm_module = importlib.import_module("rapp.prm")
from rapp.rrt import rrt
from rapp.rrt_connect import rrt_connect
from rapp.rrt_star import rrt_star

pytestmark = pytest.mark.skipif(collision_kernel.kernels() is None, reason="numba is not installed")

# The 3-link problem of the benchmarks, defined once in benchmarks/bench_core.py.
from tests.scenes import LINKS3, OBSTACLES3  # noqa: E402  the benchmarks' problem


@st.composite
def worlds(draw):
    n = draw(st.integers(1, 4))
    lengths = draw(st.lists(st.floats(0.2, 1.5), min_size=n, max_size=n))
    obstacles = []
    for _ in range(draw(st.integers(0, 3))):
        c = draw(st.tuples(st.floats(-3, 3), st.floats(-3, 3)))
        obstacles.append(rapp.Circle(c, draw(st.floats(0.05, 0.8))))
    for _ in range(draw(st.integers(0, 2))):
        corner = draw(st.tuples(st.floats(-3, 3), st.floats(-3, 3)))
        obstacles.append(rapp.Polygon.rectangle(corner, draw(st.floats(0.1, 1.0)),
                                                draw(st.floats(0.1, 1.0)),
                                                draw(st.floats(-np.pi, np.pi))))
    seed = draw(st.integers(0, 2**32 - 1))
    return rapp.Arm(lengths), obstacles, np.random.default_rng(seed)


def _backends():
    """The compiled kernel, loaded first (so the dispatcher of rapp.collision runs it), and the numpy one."""
    assert collision_dispatch.loaded() is collision_kernel.kernels() is not None
    return {"compiled": (collides, link_clearances, segment_collision_free),
            "numpy": (collision_numpy.collides, collision_numpy.link_clearances,
                      collision_numpy.segment_collision_free)}


def check_collides(world, m):
    arm, obstacles, rng = world
    q = rng.uniform(-np.pi, np.pi, (m, arm.n))
    slow = reference.collides(arm, q, obstacles)
    # Only a configuration within rounding of touching may differ (cos/sin's last bits).
    near = np.abs(reference.link_clearances(arm, q, obstacles).min(axis=-1)) < 1e-9
    for name, (fast_collides, _, _) in _backends().items():
        fast = fast_collides(arm, q, obstacles)
        assert fast.shape == slow.shape == (m,), name
        assert (fast == slow)[~near].all(), name
    one = [collides(arm, row, obstacles) for row in q]  # one configuration at a time: the planners' call
    assert all(isinstance(answer, np.bool_) for answer in one)
    assert (np.array(one) == slow)[~near].all()


@settings(max_examples=15, deadline=None, derandomize=True)
@given(worlds())
def test_collides_is_the_oracles_answer(world):
    check_collides(world, 30)


@pytest.mark.slow
@settings(max_examples=60, deadline=None, derandomize=True)
@given(worlds())
def test_collides_is_the_oracles_answer_on_many(world):
    check_collides(world, 200)


def check_clearances(world, m):
    arm, obstacles, rng = world
    q = rng.uniform(-np.pi, np.pi, (m, 2, arm.n))
    slow = reference.link_clearances(arm, q, obstacles)
    for name, (_, fast_clearances, _) in _backends().items():
        fast = fast_clearances(arm, q, obstacles)
        assert fast.shape == slow.shape == (m, 2, arm.n), name
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-12, err_msg=name)


@settings(max_examples=15, deadline=None, derandomize=True)
@given(worlds())
def test_link_clearances_are_the_oracles_values(world):
    check_clearances(world, 8)


@pytest.mark.slow
@settings(max_examples=60, deadline=None, derandomize=True)
@given(worlds())
def test_link_clearances_are_the_oracles_values_on_many(world):
    check_clearances(world, 50)


def check_certificates(world, m):
    arm, obstacles, rng = world
    q0 = rng.uniform(-np.pi, np.pi, (m, arm.n))
    q1 = q0 + rng.uniform(-0.6, 0.6, (m, arm.n))
    slow = _answer(reference.segment_collision_free, arm, q0, q1, obstacles)
    for name, (_, _, fast_certificate) in _backends().items():
        assert _answer(fast_certificate, arm, q0, q1, obstacles) == slow, name


@settings(max_examples=12, deadline=None, derandomize=True)
@given(worlds())
def test_edge_certificates_are_the_oracles(world):
    check_certificates(world, 5)


@pytest.mark.slow
@settings(max_examples=60, deadline=None, derandomize=True)
@given(worlds())
def test_edge_certificates_are_the_oracles_on_many(world):
    check_certificates(world, 40)


def _answer(certify, *args):
    """The certificate's answers, or that it refused (a segment needs too many pieces)."""
    try:
        return certify(*args).tolist()
    except rapp.errors.CertificationLimit:
        return "refused"


def test_touching_counts_as_collision_in_the_kernel():
    arm = rapp.Arm([1.0, 1.0])
    # The arm along +x ends at (2, 0); a disc of radius 1 centred at (3, 0) touches its tip,
    # a square with a corner at (2, 0) too.
    assert collides(arm, [0.0, 0.0], [rapp.Circle((3.0, 0.0), 1.0)])
    assert collides(arm, [0.0, 0.0], [rapp.Polygon.rectangle((2.0, 0.0), 1.0, 1.0)])
    assert not collides(arm, [0.0, 0.0], [rapp.Circle((3.0, 0.0), 0.999)])
    assert not segment_collision_free(arm, [0.0, 0.5], [0.0, -0.5], [rapp.Circle((3.0, 0.0), 1.0)])


def test_bad_input_is_refused_as_before():
    arm = rapp.Arm([1.0, 1.0])
    bad = [[0.0, np.nan], [0.0, 1e101], [0.0, np.inf], [0.0, 0.0, 0.0], "x"]
    for q in bad + [np.array(q) for q in bad[:3]]:  # lists, and the float arrays of one configuration
        with pytest.raises(ValueError) as fast:
            collides(arm, q, OBSTACLES3)
        with pytest.raises(ValueError) as slow:
            reference.collides(arm, q, OBSTACLES3)
        assert str(fast.value) == str(slow.value)
    with pytest.raises(ValueError, match="obstacles must be rapp.Circle or rapp.Polygon"):
        collides(arm, [0.0, 0.0], [(1.0, 2.0)])


def test_the_certification_limit_is_raised_with_the_numpy_message():
    # Links of 1e6 beside a clearance of 1 need 2**18 pieces: every backend refuses, the oracle too.
    arm = rapp.Arm([1e6, 1e6])
    obs = [rapp.Circle((0.0, -2.0), 1.0)]
    _backends()
    with pytest.raises(rapp.errors.CertificationLimit) as fast:
        segment_collision_free(arm, [0.0, 0.0], [0.5, 0.0], obs)
    with pytest.raises(rapp.errors.CertificationLimit) as slow:
        collision_numpy.segment_collision_free(arm, [0.0, 0.0], [0.5, 0.0], obs)
    assert str(fast.value) == str(slow.value)
    assert "MAX_PENDING_INTERVALS" in str(fast.value)
    with pytest.raises(rapp.errors.CertificationLimit, match=r"more than 64 pieces"):
        reference.segment_collision_free(arm, [0.0, 0.0], [0.5, 0.0], obs, max_intervals=64)


def _without_numba(monkeypatch):
    monkeypatch.setattr(collision_kernel, "kernels", lambda: None)
    monkeypatch.setattr(prm_module, "_compiled_dijkstra", lambda: None)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.integers(2, 200), st.integers(0, 2**32 - 1))
def test_prm_compiled_dijkstra_is_its_python_loop(n, seed):
    # Weights drawn from {1, 2, uniform}: many exact ties, which both must break alike.
    rng = np.random.default_rng(seed)
    edges = {}
    for _ in range(int(rng.integers(0, 6 * n))):
        i, j = sorted(int(x) for x in rng.integers(0, n, 2))
        if i != j:
            edges[(i, j)] = float(rng.choice([1.0, 2.0, rng.uniform()]))
    targets = rng.integers(0, n, 3)
    parent, hit = prm_module._dijkstra(n, edges, [0], targets)
    fast_parent, fast_hit = prm_module._shortest(n, edges, [0], targets)
    assert fast_hit == hit
    assert np.array_equal(fast_parent, parent)


@pytest.mark.parametrize("planner", [rrt_connect, prm, pytest.param(rrt, marks=pytest.mark.slow), rrt_star])
def test_same_seeds_grow_the_same_trees(planner, monkeypatch):
    arm = rapp.Arm(LINKS3)
    kw = {"max_iterations": 300} if planner is rrt_star else {}
    seeds = range(3)
    fast = [planner(arm, (0, 0, 0), (-2, 0.5, 0.5), OBSTACLES3, seed=s, raise_on_failure=False, **kw)
            for s in seeds]
    _without_numba(monkeypatch)
    slow = [planner(arm, (0, 0, 0), (-2, 0.5, 0.5), OBSTACLES3, seed=s, raise_on_failure=False, **kw)
            for s in seeds]
    for f, s in zip(fast, slow):
        assert f.success == s.success
        assert np.array_equal(f.nodes, s.nodes)
        assert np.array_equal(f.parent, s.parent)
        assert np.array_equal(f.path, s.path)


def test_line_path_is_unchanged(monkeypatch):
    from rapp.cartesian import line_path

    arm = rapp.Arm([1.0, 1.0])
    obs = [rapp.Circle((-0.5, 1.4), 0.25), rapp.Polygon.rectangle((0.2, -1.5), 0.6, 0.4)]
    fast = line_path(arm, [0.3, 0.6], [1.2, 0.9], obs)
    _without_numba(monkeypatch)
    slow = line_path(arm, [0.3, 0.6], [1.2, 0.9], obs)
    assert len(fast) > 2
    assert np.array_equal(fast, slow)


def test_without_numba_the_numpy_versions_answer(monkeypatch):
    arm = rapp.Arm(LINKS3)
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (100, 3))
    fast = collides(arm, q, OBSTACLES3), link_clearances(arm, q, OBSTACLES3)
    _without_numba(monkeypatch)
    assert np.array_equal(collides(arm, q, OBSTACLES3), fast[0])
    np.testing.assert_allclose(link_clearances(arm, q, OBSTACLES3), fast[1], rtol=0, atol=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(worlds(), st.floats(0.0, 0.2), st.floats(0.0, 0.2), st.booleans())
def test_one_configuration_scene_is_the_batch_answer(world, radius, margin, as_list):
    """The packed one-configuration scene (compiled, and its numpy twin) answers as the batch,
    link radii, margins and the obstacles grown for some links only included."""
    lengths, obstacles, rng = world[0].link_lengths, world[1], world[2]
    arm = rapp.Arm(lengths, link_radius=[radius * (j % 2) for j in range(len(lengths))])
    obstacles = list(obstacles) if as_list else tuple(obstacles)
    q = rng.uniform(-np.pi, np.pi, (40, arm.n))
    batch = collides(arm, q, obstacles, margin=margin)
    thin, pieces = rapp.collision.scene(arm, obstacles, margin)
    packed = collision_kernel.pack_scene(thin.lengths, pieces, rapp.arm.MAX_ANGLE)
    compiled = collision_kernel.kernels().collides_scene
    twin = [collision_numpy.collides_scene(packed, row) for row in q]
    near = np.abs(rapp.collision.link_clearances(arm, q, obstacles, margin=margin).min(axis=-1)) < 1e-9
    assert (np.array(twin) == batch)[~near].all()
    assert (np.array([compiled(packed, row) for row in q]) == batch)[~near].all()
    one = [collides(arm, row, obstacles, margin=margin) for row in q]  # the cached scene's path
    assert (np.array(one) == batch)[~near].all()


def test_the_cached_scene_follows_its_arguments():
    arm, q = rapp.Arm([1.0, 1.0]), np.array([0.0, 0.0])
    obstacles = [rapp.Circle((0.0, 2.0), 0.3)]
    assert not collides(arm, q, obstacles) and not collides(arm, q, obstacles)  # cached now
    obstacles.append(rapp.Circle((2.0, 0.0), 0.3))  # a list may change: its copy is compared
    assert collides(arm, q, obstacles)
    obstacles.pop()
    assert not collides(arm, q, obstacles)
    assert collides(arm, q, obstacles, margin=2.0) and not collides(arm, q, obstacles)
    assert collides(rapp.Arm([1.0, 1.0], link_radius=2.0), q, obstacles)
    assert not collides(arm, q, tuple(obstacles)) and not collides(arm, q, tuple(obstacles))
    for bad in (np.array([0.0, np.nan]), np.array([0.0, 0.0, 0.0]), np.array([0.0, 2e100])):
        with pytest.raises(ValueError) as fast:  # after the cached call: the same one-line errors
            collides(arm, bad, obstacles)
        with pytest.raises(ValueError) as slow:
            reference.collides(arm, bad, obstacles)
        assert str(fast.value) == str(slow.value)
    # Any other 1-D array (not contiguous, read-only) takes the general path, with the same answer.
    assert collides(arm, np.zeros(4)[::2], obstacles) == collides(arm, np.zeros((1, 2)), obstacles)[0]


def test_a_graze_is_not_free_in_every_backend_and_raises_nothing():
    # three_link's square has a corner at (0.6, -0.8), exactly one first link from the base: any
    # segment crossing theta_1 = -0.9273 puts the elbow on that corner. Along this one (a PRM
    # edge from the CI run of 2026-12-05) the clearance grows quadratically past the touch, so
    # plain halving doubled its pending pieces every two levels and raised CertificationLimit.
    s = rapp.load_scenario("three_link")
    q0 = np.zeros(3)
    q1 = np.array([-1.0698271771715926, 1.8122509915502087, -1.0304694641430887])
    t = np.linspace(0.8667, 0.8668, 20001)
    assert link_clearances(s.arm, q0 + t[:, None] * (q1 - q0), s.obstacles).min() < 1e-10
    _backends()
    for free in (segment_collision_free, collision_numpy.segment_collision_free,
                 reference.segment_collision_free):
        assert not free(s.arm, q0, q1, s.obstacles)
    # The same segment stopped just short of the corner is certified free by each of them.
    short = q0 + 0.85 * (q1 - q0)
    for free in (segment_collision_free, collision_numpy.segment_collision_free,
                 reference.segment_collision_free):
        assert free(s.arm, q0, short, s.obstacles)
