"""Bad and extreme input to the core modules: refused with a ValueError naming the argument.

Covers rapp.arm, rapp.obstacles, rapp.collision, rapp.cspace, rapp.search and
rapp.trajectory: non-finite configurations, times and durations; the work
limit of the certified segment check; the size limit of joint grids; start
and goal cells outside the grid; malformed joint limits and oversized arms;
self-intersecting or degenerate polygons and rectangles; and extreme but
finite input, which must never leak a RuntimeWarning.
"""

import tracemalloc
import warnings

import numpy as np
import pytest

import rapp
from rapp import Arm, Circle, NoPathFound, Polygon
from rapp.collision import (
    MAX_PENDING_INTERVALS,
    clearance,
    closest_point_on_segment,
    collides,
    link_clearances,
    motion_bounds,
    path_collision_free,
    segment_collision_free,
)
from rapp.cspace import MAX_GRID_CELLS, JointGrid, certified_free, grid_q, occupancy
from rapp.errors import CertificationLimit, InvalidCell
from rapp.search import astar, astar_search, bfs, bfs_distances, greedy_best_first
from rapp.trajectory import (
    PiecewisePolynomial,
    cubic,
    heuristic_velocities,
    quintic,
    spline_velocities,
    time_polyline,
    via_points,
)
from rapp.time_scaling import time_path

NAN, INF = float("nan"), float("inf")
ARM = Arm([1.0, 1.0])
OBS = [Circle((1.5, 0.5), 0.3), Polygon.rectangle((-2.0, -2.0), 1.0, 1.0)]


# ----------------------------------------------------------------- 1. non-finite input


@pytest.mark.parametrize("bad", [[NAN, 0.0], [0.0, INF], [-INF, 0.0]])
@pytest.mark.parametrize("f", [collides, clearance, link_clearances])
def test_collision_queries_refuse_non_finite_q(f, bad):
    with pytest.raises(ValueError, match=r"^q must be finite joint angles"):
        f(ARM, bad, OBS)
    with pytest.raises(ValueError, match=r"^q must be finite"):
        f(ARM, bad, [])  # no obstacles: still refused, not "free"


def test_path_collision_free_refuses_non_finite_path_q():
    with pytest.raises(ValueError, match=r"^path_q must be finite"):
        path_collision_free(ARM, [[0.0, 0.0], [NAN, 0.0]], OBS)
    with pytest.raises(ValueError, match=r"^path_q must be finite"):
        path_collision_free(ARM, [[0.0, 0.0]] * 3 + [[0.0, INF]], OBS)


def test_segment_collision_free_refuses_non_finite_ends_at_once():
    with pytest.raises(ValueError, match=r"^q0 must be finite"):
        segment_collision_free(ARM, [NAN, 0.0], [1.0, 0.0], OBS)
    with pytest.raises(ValueError, match=r"^q1 must be finite"):
        segment_collision_free(ARM, [0.0, 0.0], [[1.0, 0.0], [0.0, INF]], OBS)
    with pytest.raises(ValueError, match=r"^min_interval"):
        segment_collision_free(ARM, [0.0, 0.0], [1.0, 0.0], OBS, min_interval=NAN)
    with pytest.raises(ValueError, match=r"^min_interval"):
        segment_collision_free(ARM, [0.0, 0.0], [1.0, 0.0], OBS, min_interval=0.0)


@pytest.mark.parametrize("bad", [[NAN, 0.0], [0.0, INF]])
def test_kinematics_and_grid_index_refuse_non_finite_q(bad):
    grid = JointGrid(ARM, 8)
    for f in (ARM.joint_positions, ARM.end_effector, grid.index, grid.fractional_index):
        with pytest.raises(ValueError, match=r"^q must be finite"):
            f(bad)


def test_time_path_refuses_non_finite_waypoints_duration_and_t0():
    w = [[0.0, 0.0], [1.0, 0.0]]
    with pytest.raises(ValueError, match=r"^waypoints must be finite"):
        time_path([[0.0, 0.0], [NAN, 0.0]], 1.0)
    with pytest.raises(ValueError, match=r"^waypoints must be finite"):
        time_path([[0.0, 0.0], [0.0, -INF]], 1.0)
    for bad in (NAN, INF):
        with pytest.raises(ValueError, match=r"^duration must be finite"):
            time_path(w, bad)
        with pytest.raises(ValueError, match=r"^t0 must be finite"):
            time_path(w, 1.0, t0=bad)
    with pytest.raises(ValueError, match=r"^duration must be > 0"):
        time_path(w, 0.0)


def test_time_polyline_refuses_non_finite_waypoints_duration_and_bad_samples():
    w = [[0.0, 0.0], [1.0, 0.0]]
    with pytest.raises(ValueError, match=r"^waypoints must be finite"):
        time_polyline([[0.0, 0.0], [NAN, 0.0]], 1.0, 5)
    with pytest.raises(ValueError, match=r"^waypoints must be finite"):
        time_polyline([[0.0, 0.0], [INF, 0.0]], 1.0, 5)
    for bad in (NAN, INF):
        with pytest.raises(ValueError, match=r"^duration must be finite"):
            time_polyline(w, bad, 5)
    for bad in (0.0, -1.0):
        with pytest.raises(ValueError, match=r"^duration must be > 0"):
            time_polyline(w, bad, 5)
    for bad in (1.5, 1, None):
        with pytest.raises(ValueError, match=r"^samples must be an integer >= 2"):
            time_polyline(w, 1.0, bad)


@pytest.mark.parametrize("kwargs, name", [
    ({"times": [0.0, NAN]}, "times"),
    ({"times": [0.0, INF]}, "times"),
    ({"positions": [0.0, NAN]}, "positions"),
    ({"velocities": [NAN, 0.0]}, "velocities"),
    ({"velocities": [[0.0], [INF]], "profile": "spline"}, "velocities"),
    ({"profile": "quintic", "accelerations": [0.0, NAN]}, "accelerations"),
])
def test_via_points_refuses_non_finite_arguments(kwargs, name):
    args = {"times": [0.0, 1.0], "positions": [0.0, 1.0]} | kwargs
    with pytest.raises(ValueError, match=rf"^{name} must be finite"):
        via_points(**args)


@pytest.mark.parametrize("f, names", [
    (cubic, ["t0", "tf", "p0", "pf", "v0", "vf"]),
    (quintic, ["t0", "tf", "p0", "pf", "v0", "vf", "a0", "af"]),
])
@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_cubic_and_quintic_refuse_non_finite_arguments(f, names, bad):
    good = {"t0": 0.0, "tf": 1.0, "p0": 0.0, "pf": 1.0, "v0": 0.0, "vf": 0.0, "a0": 0.0, "af": 0.0}
    for name in names:
        args = {k: good[k] for k in names} | {name: bad}
        with pytest.raises(ValueError, match=rf"^{name} must be finite"):
            f(**args)


def test_piecewise_polynomial_refuses_non_finite_breakpoints_coefficients_and_times():
    with pytest.raises(ValueError, match=r"^breakpoints must be finite"):
        PiecewisePolynomial([0.0, NAN], [[1.0, 0.0]])
    with pytest.raises(ValueError, match=r"^coefficients must be finite"):
        PiecewisePolynomial([0.0, 1.0], [[1.0, INF]])
    pp = via_points([0.0, 1.0], [0.0, 1.0])
    with pytest.raises(ValueError, match=r"^t must be times"):
        pp.evaluate(NAN)
    # An infinite time is well defined: the arm waits at the end.
    assert pp.evaluate([-INF, INF]).ravel().tolist() == [0.0, 1.0]
    assert pp.evaluate(INF, 1).ravel().tolist() == [0.0]


# ----------------------------------------------------------------- 2. bounded certification


HUGE_ARM = Arm([1e20, 1e20])
NEAR_BASE = [Circle((0.0, -2.0), 1.0)]  # clearance 1 along the whole segment below


def test_certification_of_a_huge_arm_stops_at_once_and_is_conservative():
    # Before: links of 1e20 beside an obstacle bisected up to 1.7 GB. A clearance of 1 beside
    # an arm 2e20 long is below the rounding of the arm's own coordinates (about 1e5): it cannot
    # be told from touching, and touching counts as collision.
    assert MAX_PENDING_INTERVALS == 1 << 14
    assert np.all(clearance(HUGE_ARM, [[0.0, 0.0], [0.5, 0.0]], NEAR_BASE) == 1.0)
    tracemalloc.start()
    try:
        free = segment_collision_free(HUGE_ARM, [0.0, 0.0], [0.5, 0.0], NEAR_BASE)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 16e6 and not free
    assert not path_collision_free(HUGE_ARM, [[0.0, 0.0], [0.5, 0.0]], NEAR_BASE)


def test_a_grazing_vertex_is_touching_not_a_runaway():
    # Found by hypothesis: a triangle whose vertex lies 2e-17 from the base of a 1-link arm.
    # Every sub-interval grazes it; the answer is "not free" (touching), at once.
    tri = Polygon([(-0.15, 0.08660254037844388), (-0.15000000000000005, -0.08660254037844384),
                   (0.0, -2.4492935982947065e-17)])
    assert not segment_collision_free(Arm([1.0]), [0.2852734221408886], [-0.40800717439217005], [tri])


def test_certification_limit_applies_where_the_old_bisection_ran_on():
    # Links of 1e6 beside a clearance of 1 need 2**18 pieces; the old code
    # bisected all of them (some 100 MB). Now the limit stops it.
    with pytest.raises(CertificationLimit, match="1e\\+06"):
        segment_collision_free(Arm([1e6, 1e6]), [0.0, 0.0], [0.5, 0.0], NEAR_BASE)


def test_certification_limit_is_per_segment_not_per_batch():
    # 100 segments needing a few hundred pieces each exceed the limit together;
    # they are then certified one by one, with the answers of single calls.
    arm = Arm([1e3, 1e3])
    q0 = np.zeros((100, 2))
    q1 = np.c_[np.linspace(0.3, 0.5, 100), np.zeros(100)]
    q1[::7, 0] = -1.2  # some of them swing link 1 down through the disc
    together = segment_collision_free(arm, q0, q1, NEAR_BASE)
    alone = [bool(segment_collision_free(arm, a, b, NEAR_BASE)) for a, b in zip(q0, q1)]
    assert together.tolist() == alone
    assert together.any() and not together.all()
    with pytest.raises(CertificationLimit):
        segment_collision_free(arm, q0, q1, NEAR_BASE, max_intervals=16)
    for bad in (1, 2.5, None):
        with pytest.raises(ValueError, match=r"^max_intervals"):
            segment_collision_free(arm, q0, q1, NEAR_BASE, max_intervals=bad)


# ----------------------------------------------------------------- 3. grid size limit


def test_joint_grid_refuses_more_cells_than_the_limit_before_allocating():
    assert MAX_GRID_CELLS == 50_000_000
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"^cells \(30000, 30000\) make a grid of 900,000,000 cells"):
            JointGrid(ARM, 30000)
        with pytest.raises(ValueError, match=r"^cells .*MAX_GRID_CELLS"):
            JointGrid(Arm([1.0, 1.0, 1.0]), (400, 400, 400))
        with pytest.raises(ValueError, match=r"^cells .* 4.52e\+74 cells"):
            JointGrid(Arm([1.0] * 4), 2**62)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1e6
    assert JointGrid(ARM, 7071).shape == (7071, 7071)  # 49,999,041 cells: accepted
    with pytest.raises(ValueError, match=r"^cells"):
        JointGrid(ARM, 7072)


def test_grid_functions_refuse_what_is_not_a_joint_grid():
    for f in (lambda g: occupancy(ARM, OBS, g), lambda g: certified_free(ARM, OBS, g), grid_q):
        with pytest.raises(ValueError, match=r"^grid must be a rapp.JointGrid"):
            f((30000, 30000))


def test_certified_free_painted_matches_the_clearance_reference():
    from rapp.reference import certified_free as _certified_free_reference

    arm = Arm([1.0, 0.7, 0.5], [None, (-2.0, 2.5), None])
    grid = JointGrid(arm, (12, 9, 10))
    obs = [Circle((1.2, 0.3), 0.3), Polygon.rectangle((-1.5, -1.0), 0.5, 0.8, 0.3)]
    assert np.array_equal(certified_free(arm, obs, grid), _certified_free_reference(arm, obs, grid))


# ----------------------------------------------------------------- 4. start and goal cells


FREE = np.zeros((5, 5), bool)
SEARCHES = [astar, astar_search, bfs, greedy_best_first]


@pytest.mark.parametrize("f", SEARCHES)
@pytest.mark.parametrize("which, start, goal", [
    ("start", (0, 5), (0, 0)),
    ("start", (-1, 0), (0, 0)),
    ("goal", (0, 0), (5, 0)),
    ("goal", (0, 0), (0, -1)),
])
def test_searches_refuse_cells_outside_the_grid_with_value_error(f, which, start, goal):
    with pytest.raises(ValueError, match=rf"^{which} cell .* is outside the grid of shape \(5, 5\)") as e:
        f(FREE, start, goal)
    # A bad argument, not a planning answer.
    assert isinstance(e.value, InvalidCell) and not isinstance(e.value, NoPathFound)


@pytest.mark.parametrize("f", SEARCHES)
@pytest.mark.parametrize("bad", [(0.5, 1), (0.0, 1), (True, 1), (0, 0, 0), (0,), "ab", None, 3])
def test_searches_refuse_malformed_cells_naming_them(f, bad):
    with pytest.raises(ValueError, match=r"^start "):
        f(FREE, bad, (1, 1))
    with pytest.raises(ValueError, match=r"^goal "):
        f(FREE, (1, 1), bad)


def test_bfs_distances_refuses_start_outside_and_blocked_cells_keep_their_meaning():
    with pytest.raises(ValueError, match=r"^start cell \(5, 0\) is outside"):
        bfs_distances(FREE, (5, 0))
    with pytest.raises(ValueError, match=r"^start "):
        bfs_distances(FREE, (1.0, 0))
    occ = FREE.copy()
    occ[1, 1] = True
    assert (bfs_distances(occ, (1, 1)) == -1).all()  # documented: all -1 from a blocked start
    for f in SEARCHES:
        with pytest.raises(NoPathFound, match="blocked") as e:
            f(occ, (1, 1), (0, 0))
        assert not isinstance(e.value, ValueError)  # a blocked cell is an answer, not a bad argument


def test_search_keyword_arguments_named():
    with pytest.raises(ValueError, match=r"^max_expansions"):
        astar(FREE, (0, 0), (1, 1), max_expansions=1.5)
    with pytest.raises(ValueError, match=r"^heuristic_weight"):
        astar(FREE, (0, 0), (1, 1), heuristic_weight="heavy")
    with pytest.raises(ValueError, match=r"^wraps"):
        astar(FREE, (0, 0), (1, 1), wraps=1)


# ----------------------------------------------------------------- 5. arm arguments


@pytest.mark.parametrize("limits, i", [
    ([1.0, 2.0], 0),
    ([(1.0,), None], 0),
    ([None, (0.0, 1.0, 2.0)], 1),
    ([None, "ab"], 1),
    ([(None, 1.0), None], 0),
    ([None, ("a", 1.0)], 1),
    ([(2.0, 1.0), None], 0),
    ([(NAN, 1.0), None], 0),
    ([None, (0.0, INF)], 1),
    ([None, (-1e200, 1e200)], 1),
    ([{}, None], 0),
])
def test_malformed_joint_limits_entry_named(limits, i):
    with pytest.raises(ValueError, match=rf"^joint_limits\[{i}\] must be None or a pair"):
        Arm([1.0, 1.0], limits)


def test_joint_limits_argument_and_link_lengths_named():
    with pytest.raises(ValueError, match=r"^joint_limits must be None or a list"):
        Arm([1.0, 1.0], 5)
    with pytest.raises(ValueError, match=r"^joint_limits has 1 entries"):
        Arm([1.0, 1.0], [None])
    for lengths in ([1e308, 1e308], [1e200], [6e99, 6e99]):
        with pytest.raises(ValueError, match=r"^link_lengths must add up to at most 1e\+100"):
            Arm(lengths)
    for lengths in (["a"], [[1.0], [1.0, 2.0]], None):
        with pytest.raises(ValueError, match=r"^link_lengths must be a non-empty list of numbers"):
            Arm(lengths)
    assert Arm([5e99, 5e99]).reach == (0.0, 1e100)  # the limit itself is accepted


def test_huge_angles_refused_naming_the_argument():
    with pytest.raises(ValueError, match=r"^q must be joint angles of magnitude at most 1e\+100"):
        ARM.joint_positions([1e300, 1e300])
    with pytest.raises(ValueError, match=r"^q0 must be joint angles of magnitude"):
        segment_collision_free(ARM, [-1e308, 0.0], [1e308, 0.0], OBS)


# ----------------------------------------------------------------- 6. polygons


def _star(k, step, r=1.0):
    t = 2 * np.pi * step * np.arange(k) / k
    return np.c_[r * np.cos(t), r * np.sin(t)]


@pytest.mark.parametrize("verts, message", [
    (_star(5, 2), r"^vertices wind 2 times around"),            # pentagram, counter-clockwise
    (_star(5, 2)[::-1], r"^vertices wind 2 times around"),      # pentagram, clockwise
    (_star(7, 3), r"^vertices wind 3 times around"),            # heptagram {7/3}
    ([(0, 0), (1, 0), (1, 0), (1, 1), (0, 1)], r"^vertices must be distinct: vertices\[2\] repeats vertices\[1\]"),
    ([(0, 0), (1, 0), (1, 1), (0, 1), (0, 0)], r"^vertices must be distinct"),
    ([(1, 1), (1, 1), (1, 1)], r"^vertices must be distinct"),
    ([(0, 0), (1, 0), (2, 0)], r"^vertices are collinear"),
    ([(0, 0), (1, 1), (3, 3), (2, 2)], r"^vertices are collinear"),
    ([(0, 0), (2, 0), (1, 0.2), (2, 2), (0, 2)], r"^vertices must form a strictly convex polygon"),
    ([(0, 0), (1, 0), (np.inf, 1)], r"^vertices must be finite"),
    ([(0, 0), (1e200, 0), (0, 1)], r"^vertices must lie within 1e\+100"),
    ("abc", r"^vertices must be a \(k, 2\) array"),
])
def test_polygon_refuses_stars_repeats_and_degenerate_vertices(verts, message):
    with pytest.raises(ValueError, match=message):
        Polygon(verts)


@pytest.mark.parametrize("corner, w, h, message", [
    ((0.0, 0.0), 1e-17, 1.0, r"^width 1e-17 is too small beside the height 1"),
    ((0.0, 0.0), 1.0, 1e-17, r"^height 1e-17 is too small beside the width 1"),
    ((1e17, 0.0), 1.0, 1.0, r"^corner \(1e\+17, 0.0\) is too far from the origin"),
    ((1.0, 1.0), 1e-17, 1e-17, r"^corner \(1.0, 1.0\) is too far from the origin"),
    ((1e300, 0.0), 1.0, 1.0, r"^corner puts the rectangle beyond 1e\+100"),
    ((0.0, 0.0), 1e300, 1.0, r"^width puts the rectangle beyond 1e\+100"),
    ((0.0, NAN), 1.0, 1.0, r"^corner must be two finite numbers"),
    ((0.0, 0.0, 0.0), 1.0, 1.0, r"^corner must be two finite numbers"),
    ((0.0, 0.0), NAN, 1.0, r"^width must be finite and > 0"),
    ((0.0, 0.0), 1.0, -1.0, r"^height must be finite and > 0"),
    ((0.0, 0.0), None, 1.0, r"^width must be a number"),
])
def test_rectangle_errors_name_the_argument(corner, w, h, message):
    with pytest.raises(ValueError, match=message) as e:
        Polygon.rectangle(corner, w, h)
    assert "strictly convex" not in str(e.value)


def test_rectangle_angle_named_and_valid_shapes_still_accepted():
    with pytest.raises(ValueError, match=r"^angle must be finite"):
        Polygon.rectangle((0, 0), 1, 1, INF)
    Polygon.rectangle((0.0, 0.0), 1e-17, 1e-17)        # tiny but well resolved at the origin
    Polygon.rectangle((1e6, -1e6), 1e-3, 2.0, 0.7)     # a thin wall far out
    Polygon.rectangle((-5e99, 0.0), 1e99, 1e99)        # huge, inside MAX_COORDINATE
    for k in range(3, 40):
        assert Polygon(_star(k, 1)).array.shape == (k, 2)
    assert Polygon([(0, 0), (1, 0), (0, 1)]).vertices == ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0))
    assert Polygon([(0, 0), (0, 1), (1, 0)]).vertices == ((1.0, 0.0), (0.0, 1.0), (0.0, 0.0))


def test_circle_errors_name_the_argument():
    with pytest.raises(ValueError, match=r"^circle center puts the disc beyond 1e\+100"):
        Circle((1e200, 0.0), 1.0)
    with pytest.raises(ValueError, match=r"^circle radius puts the disc beyond 1e\+100"):
        Circle((0.0, 0.0), 1e200)
    with pytest.raises(ValueError, match=r"^circle center must be two finite numbers"):
        Circle("ab", 1.0)
    with pytest.raises(ValueError, match=r"^circle radius must be finite"):
        Circle((0.0, 0.0), "r")
    with pytest.raises(ValueError, match=r"^points must not be NaN"):
        Circle((0.0, 0.0), 1.0).contains([NAN, 0.0])


# ----------------------------------------------------------------- 7. no RuntimeWarning


def _extreme_calls():
    short_link = Arm([1e-300, 1.0])
    far_disc = [Circle((5e99, 0.0), 1.0)]
    big_square = Polygon.rectangle((0.0, 0.0), 1e10, 1e10)
    narrow = JointGrid(Arm([1.0, 1.0], [(0.0, 1e-300), None]), 10)
    return {
        "huge links": lambda: Arm([1e200, 1e200]),
        "motion_bounds overflow": lambda: motion_bounds(ARM, [1e308, 1e308]),
        "FK of 1e308 angles": lambda: ARM.joint_positions([1.7e308, 1.7e308]),
        "segment across 1e308": lambda: segment_collision_free(ARM, [-1e308, 0.0], [1e308, 0.0], OBS),
        "clearance of a short link far away": lambda: clearance(short_link, [0.0, 0.0], far_disc),
        "occupancy of a short link": lambda: occupancy(short_link, far_disc, JointGrid(short_link, 8)),
        "certified cells of a short link": lambda: certified_free(short_link, far_disc, JointGrid(short_link, 8)),
        "closest point of a tiny segment": lambda: closest_point_on_segment([0, 0], [1e-150, 0], [1e200, 0]),
        "disc contains a far point": lambda: Circle((0.0, 0.0), 1.0).contains([1e200, 1e200]),
        "polygon contains a far point": lambda: big_square.contains([[1e300, 1e300], [-1.7e308, 1e308]]),
        "index on a narrow axis": lambda: narrow.index([1e100, 0.0]),
        "fractional index on a narrow axis": lambda: narrow.fractional_index([1e100, 0.0]),
        "cubic over 1e-300 s": lambda: cubic(0.0, 1e-300, 0.0, 1e300),
        "cubic at t0 = 1e200": lambda: cubic(1e200, 1e200 + 1e190, 0.0, 1.0),
        "cubic from -1e308 to 1e308": lambda: cubic(-1e308, 1e308, 0.0, 1.0),
        "quintic over 1e-100 s": lambda: quintic(0.0, 1e-100, 0.0, 1e100),
        "via points 1e300 apart": lambda: via_points([0.0, 1e-300, 1.0], [0.0, 1e300, 0.0]),
        "quintic via points": lambda: via_points([0.0, 1e-300, 1.0], [0.0, 1e300, 0.0], profile="quintic"),
        "spline via points": lambda: via_points([0.0, 1e-300, 1.0], [0.0, 1e300, 0.0], profile="spline"),
        "heuristic velocities": lambda: heuristic_velocities([0.0, 1e-300, 2e-300], [0.0, 1e300, 1.7e308]),
        "spline velocities": lambda: spline_velocities([0.0, 1e-300, 2e-300], [0.0, 1e300, 1.7e308]),
        "times 2e308 apart": lambda: via_points([-1e308, 1e308], [0.0, 1.0]),
        "time_path 1e200 steps": lambda: time_path([[0.0, 0.0], [1e200, 1e200], [-1e200, 0.0]], 1.0),
        "time_path 2e308 steps": lambda: time_path([[-1e308, 0.0], [1e308, 0.0]], 1.0),
        "time_path late start": lambda: time_path([[0.0, 0.0], [1.0, 0.0]], 1.0, t0=1e300),
        "time_path ends past 1e308": lambda: time_path([[0.0], [1.0], [2.0]], 1.7e308, t0=1e308),
        "time_polyline 2e308 steps": lambda: time_polyline([[-1e308, 0.0], [1e308, 0.0]], 1.0, 5),
        "time_polyline too fast": lambda: time_polyline([[0.0, 0.0], [1e300, 0.0]], 1e-300, 5),
        "time_polyline 1e308 s": lambda: time_polyline([[0.0, 0.0], [1.0, 0.0], [1e-300, 0.0]], 1e308, 5),
    }


@pytest.mark.parametrize("name", list(_extreme_calls()))
def test_extreme_finite_input_never_leaks_a_runtime_warning(name):
    call = _extreme_calls()[name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            out = call()
        except ValueError:
            return  # refused, with a message: fine
    # Accepted: then the answer holds no nan (inf is allowed only as an honest bound).
    for part in out if isinstance(out, tuple) else (out,):
        if isinstance(part, PiecewisePolynomial):
            part = part.local
        assert not np.isnan(np.asarray(part, dtype=float)).any(), name


def test_extreme_but_valid_answers_are_right():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert motion_bounds(ARM, [1e308, 1e308]).tolist() == [1e308, INF]
        assert not Circle((0.0, 0.0), 1.0).contains([1e200, 1e200])
        assert not Polygon.rectangle((0.0, 0.0), 1e10, 1e10).contains([1e300, 1e300])
        grid = JointGrid(Arm([1.0, 1.0], [(0.0, 1e-300), None]), 10)
        assert grid.index([[1e100, 0.0], [-1e100, 0.0]]).tolist() == [[9, 5], [0, 5]]
        pp = time_path([[0.0, 0.0], [1e200, 0.0]], 2.0)
        assert pp.evaluate(2.0).tolist() == [1e200, 0.0]
        assert float(clearance(Arm([1e-300, 1.0]), [0.0, 0.0], [Circle((5e99, 0.0), 1.0)])) == 5e99 - 1.0 - 1.0
        assert rapp.segment_collision_free(Arm([5e99, 5e99]), [0.0, 0.0], [0.1, 0.0], [])
