"""JointGrid geometry and occupancy() against a slow per-cell loop of the plain TM formula."""

import itertools
import math
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm, Circle, JointGrid, Polygon, clearance, collides, occupancy
from rapp.cspace import grid_q
from rapp.reference import occupancy as _occupancy_reference

from tests.scenes import interval_scenes


def tm_hits_circle(a, b, c, r):
    abx, aby = b[0] - a[0], b[1] - a[1]
    den = abx * abx + aby * aby
    t = 0.0 if den == 0 else ((c[0] - a[0]) * abx + (c[1] - a[1]) * aby) / den
    t = min(max(t, 0.0), 1.0)
    return math.hypot(a[0] + t * abx - c[0], a[1] + t * aby - c[1]) <= r


def slow_hits_polygon(a, b, verts):
    """Endpoint inside, or a proper/touching crossing of some edge."""
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    def on_seg(p, q, r):
        return (min(p[0], r[0]) <= q[0] <= max(p[0], r[0])
                and min(p[1], r[1]) <= q[1] <= max(p[1], r[1]))

    def cross(p1, p2, p3, p4):
        d1, d2, d3, d4 = orient(p3, p4, p1), orient(p3, p4, p2), orient(p1, p2, p3), orient(p1, p2, p4)
        if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
            return True
        return ((d1 == 0 and on_seg(p3, p1, p4)) or (d2 == 0 and on_seg(p3, p2, p4))
                or (d3 == 0 and on_seg(p1, p3, p2)) or (d4 == 0 and on_seg(p1, p4, p2)))

    k = len(verts)
    inside = lambda p: all(orient(verts[i], verts[(i + 1) % k], p) >= 0 for i in range(k))
    return inside(a) or inside(b) or any(cross(a, b, verts[i], verts[(i + 1) % k]) for i in range(k))


def slow_occupancy(arm, obstacles, grid):
    """One cell at a time: FK by the SRS sum, then every link against every obstacle."""
    out = np.zeros(grid.shape, dtype=bool)
    for idx in itertools.product(*(range(m) for m in grid.shape)):
        q = [grid.axes[k][i] for k, i in enumerate(idx)]
        pts, phi = [(0.0, 0.0)], 0.0
        for L, qi in zip(arm.link_lengths, q):
            phi += qi
            pts.append((pts[-1][0] + L * math.cos(phi), pts[-1][1] + L * math.sin(phi)))
        out[idx] = any(
            tm_hits_circle(a, b, ob.center, ob.radius) if isinstance(ob, Circle)
            else slow_hits_polygon(a, b, ob.vertices)
            for a, b in zip(pts[:-1], pts[1:]) for ob in obstacles)
    return out


coord = st.floats(-2.5, 2.5)


@st.composite
def polygons(draw):
    k = draw(st.integers(3, 6))
    r = draw(st.floats(0.1, 0.8))
    c = (draw(coord), draw(coord))
    gaps = np.array(draw(st.lists(st.floats(0.5, 1.0), min_size=k, max_size=k)))
    t = draw(st.floats(0, 6.3)) + 2 * np.pi * np.cumsum(gaps) / gaps.sum()
    return Polygon(np.c_[c[0] + r * np.cos(t), c[1] + r * np.sin(t)])


obstacle_lists = st.lists(
    st.one_of(st.builds(Circle, st.tuples(coord, coord), st.floats(0.05, 1.0)), polygons()),
    min_size=1, max_size=3)


@st.composite
def grids(draw):
    n = draw(st.integers(2, 3))
    lengths = draw(st.lists(st.floats(0.3, 1.5), min_size=n, max_size=n))
    limits = []
    for _ in range(n):
        if draw(st.booleans()):
            lo = draw(st.floats(-3.0, 2.0))
            limits.append((lo, lo + draw(st.floats(0.2, 3.0))))
        else:
            limits.append(None)
    arm = Arm(lengths, limits)
    cells = draw(st.lists(st.integers(2, 14 if n == 2 else 7), min_size=n, max_size=n))
    return JointGrid(arm, cells)


@settings(max_examples=120, deadline=None)
@given(grids(), obstacle_lists)
def test_occupancy_agrees_cell_by_cell_with_slow_loop(grid, obstacles):
    occ = occupancy(grid.arm, obstacles, grid)
    slow = slow_occupancy(grid.arm, obstacles, grid)
    assert occ.shape == grid.shape and occ.dtype == bool
    # Cells within 1e-9 of touching may round either way; everywhere else they must agree.
    touching = np.abs(clearance(grid.arm, grid_q(grid), obstacles)) <= 1e-9
    assert np.array_equal(occ[~touching], slow[~touching])
    fast = collides(grid.arm, grid_q(grid), obstacles)
    assert np.array_equal(occ[~touching], fast[~touching])


def test_occupancy_of_the_book_scenario_matches_slow_loop():
    arm = Arm([1.0, 1.0])
    obs = [Circle((1.75, 0.75), 0.6), Circle((0.55, 1.5), 0.5), Circle((0.0, -1.0), 0.25)]
    grid = JointGrid(arm, 60)
    occ = occupancy(arm, obs, grid)
    # Cell (45, 15) is exactly tangent (link 2 from (0, 1) to (1, 1), disc (0.55, 1.5) r 0.5):
    # the slow loop's rounded cosines miss it, the interval includes it; both are rounding.
    touching = np.abs(clearance(arm, grid_q(grid), obs)) <= 1e-9
    assert np.array_equal(occ[~touching], slow_occupancy(arm, obs, grid)[~touching])
    assert touching.sum() <= 2
    assert 0 < occ.sum() < occ.size
    assert np.array_equal(occupancy(arm, [], grid), np.zeros((60, 60), bool))


def test_joint_grid_axes_and_properties():
    arm = Arm([1.0, 1.0, 1.0], [None, (-1.0, 2.0), None])
    g = JointGrid(arm, (8, 4, 5))
    assert g.shape == (8, 4, 5) and g.wraps == (True, False, True)
    np.testing.assert_allclose(g.axes[0], 2 * np.pi * np.arange(8) / 8 - np.pi)
    np.testing.assert_allclose(g.axes[1], [-1.0, 0.0, 1.0, 2.0])
    assert g.axes[1][0] == -1.0 and g.axes[1][-1] == 2.0
    np.testing.assert_allclose(g.step, [2 * np.pi / 8, 1.0, 2 * np.pi / 5])
    assert JointGrid(arm, 6).shape == (6, 6, 6)
    assert grid_q(g).shape == (8, 4, 5, 3)


@pytest.mark.parametrize("cells", [1, 0, 2.5, True, (4, 4), (4, 4, 4, 4), "8", (4, 1, 4)])
def test_invalid_cells_rejected(cells):
    with pytest.raises(ValueError):
        JointGrid(Arm([1.0, 1.0, 1.0]), cells)


@settings(max_examples=30, deadline=None)
@given(grids(), st.integers(0, 2**32 - 1))
def test_index_and_angles_round_trip_and_nearest(grid, seed):
    rng = np.random.default_rng(seed)
    m = np.array(grid.shape)
    idx = rng.integers(0, m, (20, grid.n))
    q = grid.angles(idx)
    assert np.array_equal(grid.index(q), idx)
    assert np.array_equal(grid.angles(tuple(idx[0])), q[0])
    # Wrapping axes accept any integer modulo M, and index() is wrap-aware.
    wr = np.array(grid.wraps)
    shifted = idx + np.where(wr, m, 0)
    assert np.array_equal(grid.angles(shifted), q)
    assert np.array_equal(grid.index(q + np.where(wr, 2 * np.pi, 0.0)), idx)
    # Nearest: the chosen cell's angle is within half a step of q (wrapped on torus axes).
    x = rng.uniform(grid.arm.lower, grid.arm.upper, (50, grid.n))
    err = x - grid.angles(grid.index(x))
    err = np.where(wr, (err + np.pi) % (2 * np.pi) - np.pi, err)
    assert np.all(np.abs(err) <= grid.step / 2 + 1e-12)


@pytest.mark.slow
@settings(max_examples=100, deadline=None)
@given(grids(), st.integers(0, 2**32 - 1))
def test_index_and_angles_round_trip_and_nearest_on_many(grid, seed):
    test_index_and_angles_round_trip_and_nearest.hypothesis.inner_test(grid=grid, seed=seed)


def test_index_clips_bounded_axis_and_angles_rejects_out_of_range():
    g = JointGrid(Arm([1.0, 1.0], [(-1.0, 1.0), None]), (3, 4))
    assert g.index([[5.0, 3.1], [-5.0, -3.1]]).tolist() == [[2, 0], [0, 0]]
    with pytest.raises(ValueError):
        g.angles((3, 0))
    with pytest.raises(ValueError):
        g.angles((0.5, 1.0))


def test_grid_for_another_arm_rejected():
    with pytest.raises(ValueError):
        occupancy(Arm([1.0, 1.0]), [], JointGrid(Arm([1.0, 2.0]), 4))


# --- occupancy by direction intervals (issue "Speed toward the limit") -------------------------
# occupancy() paints, per prefix cell, the interval of the link's own joint angle that hits each
# obstacle. The obviously-correct check is rapp.collides on every grid configuration; the
# previous implementation (_occupancy_reference) must agree as well. Only cells touching an
# obstacle to within rounding (|clearance| <= 1e-9) may differ.


@settings(max_examples=50, deadline=None)
@given(interval_scenes())
def test_interval_occupancy_equals_collides_and_previous_grid(scene):
    grid, obstacles = scene
    arm = grid.arm
    q = grid_q(grid)
    occ = occupancy(arm, obstacles, grid)
    assert occ.shape == grid.shape and occ.dtype == bool
    touching = np.abs(clearance(arm, q, obstacles)) <= 1e-9
    exact = collides(arm, q, obstacles)
    assert np.array_equal(occ[~touching], exact[~touching])
    assert np.array_equal(occ[~touching], _occupancy_reference(arm, obstacles, grid)[~touching])


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(interval_scenes())
def test_interval_occupancy_equals_collides_and_previous_grid_on_many(scene):
    test_interval_occupancy_equals_collides_and_previous_grid.hypothesis.inner_test(scene=scene)


def test_interval_occupancy_on_the_3link_benchmark_scene():
    arm = Arm([1.0, 0.8, 0.5])
    obs = [Circle((1.4, 0.9), 0.35), Circle((-0.4, 1.5), 0.3), Circle((0.2, -1.3), 0.3),
           Circle((1.0, -1.0), 0.3), Polygon.rectangle((-1.9, -0.6), 0.5, 1.0)]
    grid = JointGrid(arm, (24, 20, 16))
    occ = occupancy(arm, obs, grid)
    touching = np.abs(clearance(arm, grid_q(grid), obs)) <= 1e-9
    assert np.array_equal(occ[~touching], collides(arm, grid_q(grid), obs)[~touching])
    assert 0 < occ.sum() < occ.size


def test_interval_crossing_the_seam_and_polygon_around_the_base():
    arm = Arm([1.0])
    grid = JointGrid(arm, 16)               # angles -pi, -7pi/8, ..., 7pi/8
    # A disc straight along -x: the hitting interval is centred on the seam at +-pi.
    # Half-width asin(0.5 / 0.9) = 0.59 rad > one step (0.39): cells 15, 0 and 1.
    occ = occupancy(arm, [Circle((-0.9, 0.0), 0.5)], grid)
    assert np.flatnonzero(occ).tolist() == [0, 1, 15]
    # A polygon containing the base: every angle hits; one just out of reach: none.
    assert occupancy(arm, [Polygon.rectangle((-0.1, -0.1), 0.2, 0.2)], grid).all()
    assert not occupancy(arm, [Polygon.rectangle((1.01, -0.1), 0.2, 0.2)], grid).any()


def test_interval_occupancy_on_a_limited_joint_spanning_many_turns():
    # 5 cells over 200 rad: more turns than cells, so every cell is tested on its own.
    arm = Arm([1.0, 0.7], [(-100.0, 100.0), (-7.0, 7.0)])
    grid = JointGrid(arm, (5, 12))
    obs = [Circle((0.5, 1.2), 0.4), Polygon.rectangle((-1.5, -0.4), 0.3, 0.8)]
    q = grid_q(grid)
    touching = np.abs(clearance(arm, q, obs)) <= 1e-9
    occ = occupancy(arm, obs, grid)
    assert np.array_equal(occ[~touching], collides(arm, q, obs)[~touching])


@settings(max_examples=60 if os.environ.get("CI") else 40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3))
def test_certified_free_equals_the_clearance_threshold(seed, n):
    """Painting the grown obstacles certifies exactly the cells whose link clearances exceed half a
    step's motion bound (the definition), except where a clearance equals that bound to rounding."""
    from rapp.collision import link_clearances, motion_bounds
    from rapp.cspace import certified_free, grid_q

    rng = np.random.default_rng(seed)
    lengths = rng.uniform(0.3, 1.2, n)
    arm = Arm(lengths, [None if rng.random() < 0.7 else (-2.0, 2.5) for _ in range(n)])
    reach = lengths.sum()
    obs = []
    for _ in range(int(rng.integers(1, 4))):
        c = rng.uniform(-reach, reach, 2)
        if rng.random() < 0.5:
            obs.append(Circle(c, rng.uniform(0.05, 0.4)))
        else:
            obs.append(Polygon.rectangle(c, *rng.uniform(0.1, 0.6, 2), rng.uniform(0, np.pi)))
    grid = JointGrid(arm, tuple(int(m) for m in rng.integers(6, 16, n)))
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)
    margin = link_clearances(arm, grid_q(grid), obs) - need
    want = (margin > 0).all(axis=-1)
    got = certified_free(arm, obs, grid)
    borderline = (np.abs(margin) <= 1e-9 * reach).any(axis=-1)
    assert np.array_equal(got[~borderline], want[~borderline])
