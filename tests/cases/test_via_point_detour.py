"""Properties of rapp.cases.via_point_detour: exact curve distance, tangent optimality, search constraints."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm, Circle
from rapp.collision import link_clearances, segment_point_distance
from rapp.trajectory import cubic
from rapp.cases.via_point_detour import (
    _sample_path,
    arm_link_distance,
    cubic_segment,
    curve_point_distance,
    first_arm_collision,
    path_clearance,
    search_via_point,
    tangent_via_point,
    to_absolute_time,
    via_segments,
)

coord = st.floats(-10, 10, allow_nan=False)


@settings(max_examples=100, deadline=None)
@given(st.lists(coord, min_size=10, max_size=10), st.floats(0.2, 5.0))
def test_curve_distance_is_the_minimum_of_a_dense_sample(vals, T):
    p0, p1, v0, v1, c = np.array(vals).reshape(5, 2)
    coef = cubic_segment(p0, p1, v0, v1, T)
    d, s = curve_point_distance(coef, T, c)
    t = np.linspace(0, T, 20001)
    pts = (t[:, None] ** np.arange(4)) @ coef
    dist = np.linalg.norm(pts - c, axis=-1)
    speed = np.linalg.norm((t[:, None] ** np.arange(3)) @ (coef[1:] * [[1], [2], [3]]), axis=-1).max()
    assert d <= dist.min() + 1e-7
    assert dist.min() - d <= speed * T / 20000 / 2 + 1e-7
    assert 0 <= s <= T
    assert np.linalg.norm((s ** np.arange(4)) @ coef - c) == pytest.approx(d, abs=1e-7)


@settings(max_examples=50, deadline=None)
@given(coord, coord, coord, coord, st.floats(-2, 2), st.floats(0.0, 10.0), st.floats(0.5, 4.0))
def test_local_coefficients_agree_with_rapp_trajectory(p0, p1, v0, v1, t0, a, T):
    local = cubic_segment([p0], [p1], [v0], [v1], T)
    np.testing.assert_allclose(to_absolute_time(local, t0 + a)[:, 0],
                               cubic(t0 + a, t0 + a + T, p0, p1, v0, v1), rtol=1e-8, atol=1e-6)


@settings(max_examples=60, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3), st.floats(0.3, 2.0), st.floats(-1, 1), st.floats(-1, 1))
def test_tangent_point_is_clear_and_shortest(cx, cy, r, by, gy):
    start, goal = np.array([-6.0, by]), np.array([6.0, gy])
    obs = Circle((cx, cy), r)
    d = tangent_via_point(start, goal, obs)
    D = np.array(d.point)
    seg = [segment_point_distance(start, D, obs.center), segment_point_distance(D, goal, obs.center)]
    assert min(seg) >= r - 1e-9
    assert d.length == pytest.approx(np.linalg.norm(D - start) + np.linalg.norm(goal - D))
    # Optimal: no candidate whose two straight segments clear the disc is shorter.
    rng = np.random.default_rng(0)
    cand = rng.uniform([-8, -8], [8, 8], size=(20000, 2))
    ok = (segment_point_distance(start, cand, obs.center) > r) & (segment_point_distance(cand, goal, obs.center) > r)
    lengths = np.linalg.norm(cand - start, axis=-1) + np.linalg.norm(goal - cand, axis=-1)
    assert np.all(lengths[ok] >= d.length - 1e-9)


@settings(max_examples=15, deadline=None)
@given(st.floats(8.5, 11.5), st.floats(5.5, 8.5), st.floats(0.6, 1.5))
def test_search_result_satisfies_the_clearance_constraint(cx, cy, r):
    obs = Circle((cx, cy), r)
    B, C = (5.0, 8.0), (14.0, 7.0)
    d = search_via_point(B, C, obs, v_start=(0.25, 0.25), resolutions=(0.2, 0.05))
    assert d.clearance > r
    assert path_clearance(d.point, B, C, obs.center, v_start=(0.25, 0.25)) == pytest.approx(d.clearance)
    _, pts = _sample_path(np.array(d.point), B, C, (0.25, 0.25), (3.0, 5.5, 8.0), 5001)
    assert np.linalg.norm(pts - obs.center, axis=-1).min() >= d.clearance - 1e-9


def test_via_segments_hit_their_boundary_values():
    seg = via_segments([5, 8], [10, 9], [14, 7], v_start=(0.25, 0.25))
    ev = lambda c, s, k=0: np.polynomial.polynomial.polyval(s, np.polynomial.polynomial.polyder(c, k))  # noqa: E731
    np.testing.assert_allclose(ev(seg[0], 2.5), [10, 9])
    np.testing.assert_allclose(ev(seg[0], 0.0, 1), [0.25, 0.25])
    np.testing.assert_allclose(ev(seg[1], 2.5, 1), [0, 0], atol=1e-12)
    # Rest-to-rest cubic DC moves along the straight line D -> C.
    s = np.linspace(0, 2.5, 11)
    pts = ev(seg[1], s).T - [10, 9]
    assert np.abs(pts[:, 0] * -2 - pts[:, 1] * 4).max() < 1e-12


def test_arm_distances_agree_with_rapp_collision():
    from rapp.ik import ik_2link

    B, C, D, obs = (5.0, 8.0), (14.0, 7.0), (9.86, 5.32), Circle((10, 7), 1.5)
    t, pts = _sample_path(np.array(D), B, C, (0.25, 0.25), (3.0, 5.5, 8.0), 51)
    q = np.array([ik_2link((9, 9), p)[0] for p in pts[::10]])  # slow per-point oracle
    ref = link_clearances(Arm([9, 9]), q, [obs]).min() + obs.radius
    from rapp.cases.via_point_detour import _link_distances

    d1, d2 = _link_distances((9.0, 9.0), pts[::10], obs.center, "down")
    assert np.minimum(d1, d2).min() == pytest.approx(ref, abs=1e-9)
    dist, bound = arm_link_distance((9, 9), D, B, C, obs.center, v_start=(0.25, 0.25), samples=51)
    assert bound <= dist


def test_first_collision_is_a_collision_and_nothing_earlier():
    from rapp import collides
    from rapp.ik import ik_2link

    B, C, D, obs = (5.0, 8.0), (14.0, 7.0), (9.86, 5.32), Circle((10, 7), 1.5)
    t_hit, link = first_arm_collision((9, 9), D, B, C, obs, v_start=(0.25, 0.25), samples=2001)
    t, pts = _sample_path(np.array(D), B, C, (0.25, 0.25), (3.0, 5.5, 8.0), 2001)
    k = int(np.flatnonzero(t == t_hit)[0])
    up = np.array([ik_2link((9, 9), p)[1] for p in pts[: k + 1 : max(1, k // 40)]] + [ik_2link((9, 9), pts[k])[1]])
    hits = collides(Arm([9, 9]), up, [obs])
    assert hits[-1] and not hits[:-2].any()
    assert link_clearances(Arm([9, 9]), up[-1], [obs])[link - 1] <= 0
