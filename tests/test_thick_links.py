"""Links with width and a safety margin (issue 31, item 3), against slow oracles.

The oracle is :func:`rapp.reference.capsule_distance`: one capsule against one obstacle in
plain Python, no grown shapes. Properties: a point is in :func:`rapp.obstacles.grown` exactly
when it is within the distance of the obstacle; ``collides`` with link radii and a margin is
the oracle's "some link is within its radius plus the margin"; ``link_clearances`` is the
oracle's gap beyond it; ``occupancy`` paints what ``collides`` says on every cell (per-link
radii included); certified moves and every planner's paths keep the gap on dense samples.
Configurations within 1e-9 of the boundary are left out: there touching is a rounding
question, as it is for zero-width links.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import rapp
from rapp.errors import CertificationLimit
from rapp import reference
from rapp.collision import collides, link_clearances, scene, segment_collision_free
from rapp.cspace import JointGrid, certified_free, grid_q, occupancy, occupancy_numpy
from rapp.obstacles import grown
from rapp.planners import PLANNERS, run

EDGE = 1e-9  # oracle values this close to the required distance are not compared


def _obstacle(draw):
    if draw(st.booleans()):
        c = draw(st.tuples(st.floats(-2.5, 2.5), st.floats(-2.5, 2.5)))
        return rapp.Circle(c, draw(st.floats(0.05, 0.6)))
    corner = draw(st.tuples(st.floats(-2.5, 2.5), st.floats(-2.5, 2.5)))
    return rapp.Polygon.rectangle(corner, draw(st.floats(0.1, 1.0)), draw(st.floats(0.1, 1.0)),
                                  draw(st.floats(-3.0, 3.0)))


@st.composite
def worlds(draw, max_links=3):
    n = draw(st.integers(1, max_links))
    lengths = draw(st.lists(st.floats(0.3, 1.2), min_size=n, max_size=n))
    if draw(st.booleans()):
        radius = draw(st.floats(0.0, 0.2))
    else:
        radius = draw(st.lists(st.floats(0.0, 0.2), min_size=n, max_size=n))
    margin = draw(st.sampled_from([0.0, 0.05, 0.13]))
    obstacles = [_obstacle(draw) for _ in range(draw(st.integers(1, 3)))]
    return rapp.Arm(lengths, link_radius=radius), obstacles, margin


def _gaps(arm, q, obstacles):
    """The oracle's gap of every link, ``(k, n)``, for configurations ``(k, n)``."""
    return np.array([reference.link_gaps(arm, row, obstacles) for row in np.atleast_2d(q)])


@settings(max_examples=60, deadline=None)
@given(ob=st.composite(_obstacle)(), d=st.floats(1e-3, 0.5),
    pts=st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4)), min_size=1, max_size=40))
def test_grown_pieces_are_the_points_within_the_distance(ob, d, pts):
    pieces = grown(ob, d)
    for p in pts:
        dist = reference.capsule_distance(p, p, 0.0, ob)
        assume(abs(max(dist, 0.0) - d) > EDGE)
        inside = any(bool(piece.contains(p)) for piece in pieces)
        assert inside == (dist <= d), (p, dist, d)


@settings(max_examples=15, deadline=None)
@given(world=worlds(), seed=st.integers(0, 2**32 - 1))
def test_collides_and_clearances_are_the_capsule_oracle(world, seed):
    arm, obstacles, margin = world
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (30, arm.n))
    gaps = _gaps(arm, q, obstacles)  # beyond the link radius
    keep = (np.abs(gaps - margin) > EDGE).all(axis=1)
    want = (gaps <= margin).any(axis=1)
    got = collides(arm, q, obstacles, margin=margin)
    assert (got[keep] == want[keep]).all()
    thin, pieces = scene(arm, obstacles, margin)
    assert (reference.collides(thin, q, pieces)[keep] == want[keep]).all()
    clear = link_clearances(arm, q, obstacles, margin=margin)
    free = gaps > margin
    assert np.allclose(clear[free], gaps[free] - margin, atol=1e-9)
    assert (clear[~free & (np.abs(gaps - margin) > EDGE)] <= 0).all()


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(world=worlds(), seed=st.integers(0, 2**32 - 1))
def test_collides_and_clearances_are_the_capsule_oracle_on_many(world, seed):
    test_collides_and_clearances_are_the_capsule_oracle.hypothesis.inner_test(world=world, seed=seed)


def test_a_thick_link_hits_what_a_thin_one_passes():
    arm0, arm = rapp.Arm([1.0, 1.0]), rapp.Arm([1.0, 1.0], link_radius=0.02)
    ob = [rapp.Polygon.rectangle((0.5, 0.01), 0.5, 0.5)]  # 1 cm above the stretched-out arm
    q = [0.0, 0.0]
    assert not collides(arm0, q, ob) and collides(arm, q, ob)
    assert not collides(arm0, q, ob, margin=0.0099) and collides(arm0, q, ob, margin=0.01)
    assert collides(rapp.Arm([1.0, 1.0], link_radius=[0.0, 0.02]), [0.0, 0.0], ob)
    # Only link 0 lies below the rectangle's span in x... link 1 from x = 1 to 2 is beyond it.
    assert not collides(rapp.Arm([1.0, 1.0], link_radius=[0.005, 0.02]),
                        [0.0, 0.0], [rapp.Polygon.rectangle((0.2, 0.01), 0.5, 0.5)])


@settings(max_examples=15, deadline=None)
@given(world=worlds(max_links=3), cells=st.integers(6, 14))
def test_occupancy_of_thick_links_is_collides_on_every_cell(world, cells):
    arm, obstacles, margin = world
    grid = JointGrid(arm, cells)
    q = grid_q(grid)
    want = collides(arm, q, obstacles, margin=margin)
    gaps = _gaps(arm, q.reshape(-1, arm.n), obstacles).reshape(q.shape)
    keep = (np.abs(gaps - margin) > EDGE).all(axis=-1)
    for occ in (occupancy(arm, obstacles, grid, margin=margin),
                occupancy_numpy(arm, obstacles, grid, margin=margin),
                reference.occupancy(arm, obstacles, grid, margin=margin)):
        assert (occ[keep] == want[keep]).all()


@settings(max_examples=10, deadline=None)
@given(world=worlds(max_links=2), cells=st.integers(8, 16))
def test_certified_cells_of_thick_links_are_the_reference_and_their_moves_are_free(world, cells):
    arm, obstacles, margin = world
    grid = JointGrid(arm, cells)
    safe = certified_free(arm, obstacles, grid, margin=margin)
    assert (safe == reference.certified_free(arm, obstacles, grid, margin=margin)).all()
    q = grid_q(grid)
    for axis in range(arm.n):
        both = safe & np.roll(safe, -1, axis=axis)
        a = q[both]
        b = a.copy()
        b[:, axis] += grid.step[axis]
        if len(a):
            assert segment_collision_free(arm, a, b, obstacles, margin=margin).all()


@settings(max_examples=25, deadline=None)
@given(world=worlds(), seed=st.integers(0, 2**32 - 1))
def test_certified_segments_keep_the_gap_on_dense_samples(world, seed):
    arm, obstacles, margin = world
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(-np.pi, np.pi, (8, arm.n))
    q1 = q0 + rng.uniform(-0.6, 0.6, q0.shape)
    t = np.linspace(0.0, 1.0, 101)[:, None]
    reach = float(np.sum(arm.lengths))
    for a, b in zip(q0, q1):
        try:
            free = segment_collision_free(arm, a[None], b[None], obstacles, margin=margin)[0]
        except CertificationLimit:
            # The documented answer where the motion grazes an obstacle closer than the
            # bisection's interval limit can resolve (found by hypothesis: a box 2.4e-9 from
            # the base). Only there.
            assert _gaps(arm, a + t * (b - a), obstacles).min() - margin < 1e-6 * reach
            continue
        if free:
            assert (_gaps(arm, a + t * (b - a), obstacles) > margin).all()


def test_margin_and_radius_are_checked():
    with pytest.raises(ValueError, match="margin"):
        collides(rapp.Arm([1.0]), [0.0], [], margin=-1.0)
    with pytest.raises(ValueError, match="link_radius"):
        rapp.Arm([1.0, 1.0], link_radius=[0.1])
    with pytest.raises(ValueError, match="link_radius"):
        rapp.Arm([1.0], link_radius=float("nan"))
    with pytest.raises(ValueError, match="distance"):
        grown(rapp.Polygon.rectangle((0, 0), 1, 1), -1e-3)
    # Thinner than float64 resolves beside the edge: widened (never fewer points), not refused.
    pieces = grown(rapp.Polygon.rectangle((0, 0), 1, 1), 1e-300)
    assert any(bool(p.contains((0.5, -1e-300))) for p in pieces)


# A corridor: a 3-link arm must swing between a disc and a rectangle.
ARM = rapp.Arm([0.6, 0.5, 0.4], link_radius=[0.04, 0.03, 0.02])
OBSTACLES = [rapp.Circle((0.2, 1.05), 0.25), rapp.Polygon.rectangle((0.6, -0.9), 0.4, 0.5, 0.2)]
MARGIN = 0.03
START, GOAL = np.array([-0.4, 0.3, 0.2]), np.array([2.0, -0.3, 0.4])


@pytest.mark.parametrize("name", sorted(PLANNERS))
def test_every_planner_keeps_the_radius_and_the_margin(name):
    settings_ = {"cells": 40, "seed": 3, "step": 0.2, "max_iterations": 4000}
    res = run(name, ARM, START, GOAL, OBSTACLES, margin=MARGIN, **settings_)
    assert res.success
    path = np.asarray(res.path)
    assert segment_collision_free(ARM, path[:-1], path[1:], OBSTACLES, margin=MARGIN).all()
    t = np.linspace(0.0, 1.0, 41)[:, None, None]
    dense = (path[:-1] + t * (path[1:] - path[:-1])).reshape(-1, ARM.n)
    assert (_gaps(ARM, dense, OBSTACLES) > MARGIN).all()


def test_a_plan_with_thick_links_keeps_them_apart_and_says_so():
    s = rapp.load_scenario({
        "arm": {"link_lengths": [0.6, 0.5, 0.4], "link_radius": [0.04, 0.03, 0.02]},
        "safety_margin": 0.03,
        "obstacles": [{"type": "circle", "center": [0.2, 1.05], "radius": 0.25},
                      {"type": "polygon", "vertices": OBSTACLES[1].array.tolist()}],
        "start": START.tolist(), "goal": {"joints": GOAL.tolist()},
        "planner": {"algorithm": "rrt_connect", "seed": 2},
        "trajectory": {"duration": 4.0, "samples": 60}})
    p = rapp.plan(s)
    assert p.report.ok
    gaps = _gaps(s.arm, p.q, s.obstacles)
    assert (gaps > 0.03).all()
    check = p.report["min clearance"]
    # The motion's smallest gap (measured to 0.1 %, verify's CLEARANCE_RTOL) is at most the
    # samples' (they lie on the motion), and positive: the motion keeps the distance too.
    assert 0 < check.value <= (gaps - 0.03).min() * (1 + 1e-3)
    assert "safety margin" in check.detail
    assert rapp.load_scenario(s.to_dict()) == s


@settings(max_examples=25, deadline=None)
@given(world=worlds(max_links=4), seed=st.integers(0, 2**32 - 1))
def test_the_compiled_kernel_honours_the_link_masks_as_numpy_does(world, seed):
    from rapp.kernels import collision_numba, collision_numpy
    k = collision_numba.kernels()
    if k is None:
        pytest.skip("numba is not installed")
    arm, obstacles, margin = world
    thin, pieces = scene(arm, obstacles, margin)
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (40, arm.n))
    packed = collision_numba.pack(pieces)
    hit, ok = k.collides(thin.lengths, q, *packed, 1e100)
    assert ok and (hit == collision_numpy.collides(thin, q, pieces)).all()
    assert np.allclose(k.clearances(thin.lengths, q, *packed),
                       collision_numpy.link_clearances(thin, q, pieces), atol=1e-12)


@pytest.mark.parametrize("name", sorted(PLANNERS))
def test_every_planner_takes_a_margin_keyword(name):
    import inspect
    p = inspect.signature(PLANNERS[name].function).parameters["margin"]
    assert p.kind is inspect.Parameter.KEYWORD_ONLY and p.default == 0.0
