"""Collision geometry against slow, obviously-correct loops and dense sampling."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Arm, Circle, Polygon, clearance, collides, path_collision_free, segment_collision_free
from rapp.collision import (
    closest_point_on_segment, line_distance_mis, link_clearances, motion_bounds,
    segment_circle_distance, segment_hits_circle, segment_hits_polygon, segment_polygon_distance,
)

coord = st.floats(-3, 3)
point = st.tuples(coord, coord)


# --- slow reference implementations: plain Python, one case at a time ---------------------------

def tm_hits_circle(a, b, c, r):
    """TM:SegmentCircleCollision exactly as written in the SRS."""
    abx, aby = b[0] - a[0], b[1] - a[1]
    den = abx * abx + aby * aby
    t = 0.0 if den == 0 else ((c[0] - a[0]) * abx + (c[1] - a[1]) * aby) / den
    t = min(max(t, 0.0), 1.0)
    px, py = a[0] + t * abx, a[1] + t * aby
    return math.hypot(px - c[0], py - c[1]) <= r, math.hypot(px - c[0], py - c[1])


def orient(p, q, r):
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])


def on_seg(p, q, r):
    return min(p[0], r[0]) <= q[0] <= max(p[0], r[0]) and min(p[1], r[1]) <= q[1] <= max(p[1], r[1])


def seg_seg_intersect(p1, p2, p3, p4):
    d1, d2 = orient(p3, p4, p1), orient(p3, p4, p2)
    d3, d4 = orient(p1, p2, p3), orient(p1, p2, p4)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    return ((d1 == 0 and on_seg(p3, p1, p4)) or (d2 == 0 and on_seg(p3, p2, p4))
            or (d3 == 0 and on_seg(p1, p3, p2)) or (d4 == 0 and on_seg(p1, p4, p2)))


def slow_hits_polygon(a, b, verts):
    """A segment meets a convex polygon iff an endpoint is inside or it crosses an edge."""
    k = len(verts)
    inside = lambda p: all(orient(verts[i], verts[(i + 1) % k], p) >= 0 for i in range(k))
    return inside(a) or inside(b) or any(
        seg_seg_intersect(a, b, verts[i], verts[(i + 1) % k]) for i in range(k))


def slow_collides(arm, q, obstacles):
    pts = [(0.0, 0.0)]
    phi = 0.0
    for L, qi in zip(arm.link_lengths, q):
        phi += qi
        pts.append((pts[-1][0] + L * math.cos(phi), pts[-1][1] + L * math.sin(phi)))
    for a, b in zip(pts[:-1], pts[1:]):
        for ob in obstacles:
            if isinstance(ob, Circle):
                if tm_hits_circle(a, b, ob.center, ob.radius)[0]:
                    return True
            elif slow_hits_polygon(a, b, ob.vertices):
                return True
    return False


@st.composite
def polygons(draw):
    k = draw(st.integers(3, 7))
    r = draw(st.floats(0.1, 1.0))
    c = draw(point)
    t0 = draw(st.floats(0, 2 * np.pi))
    # Jittered angles keep the polygon strictly convex (inscribed in a circle).
    gaps = np.array(draw(st.lists(st.floats(0.5, 1.0), min_size=k, max_size=k)))
    t = t0 + 2 * np.pi * np.cumsum(gaps) / gaps.sum()
    return Polygon(np.c_[c[0] + r * np.cos(t), c[1] + r * np.sin(t)])


circles = st.builds(Circle, point, st.floats(0.05, 1.0))
obstacle_lists = st.lists(st.one_of(circles, polygons()), min_size=0, max_size=4)


# --- segment primitives ------------------------------------------------------------------------

@settings(max_examples=150, deadline=None)
@given(point, point, point)
def test_closest_point_is_closest_among_dense_samples(a, b, p):
    cp = closest_point_on_segment(a, b, p)
    s = np.linspace(0, 1, 2001)[:, None]
    samples = np.array(a) + s * (np.array(b) - np.array(a))
    d_samples = np.linalg.norm(samples - p, axis=1)
    d = np.linalg.norm(cp - p)
    seg_len = math.dist(a, b)
    assert d <= d_samples.min() + 1e-9
    assert d >= d_samples.min() - seg_len / 2000 - 1e-9
    # cp lies on the segment
    assert math.dist(a, cp) + math.dist(cp, b) == pytest.approx(seg_len, abs=1e-9)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(point, point, point, st.floats(0.01, 2)), min_size=1, max_size=20))
def test_segment_circle_batch_matches_tm_formula(cases):
    a = np.array([c[0] for c in cases])
    b = np.array([c[1] for c in cases])
    cen = np.array([c[2] for c in cases])
    r = np.array([c[3] for c in cases])
    got = segment_hits_circle(a, b, cen, r)
    dist = segment_circle_distance(a, b, cen, r)
    for k, (ai, bi, ci, ri) in enumerate(cases):
        hit, d = tm_hits_circle(ai, bi, ci, ri)
        assert dist[k] == pytest.approx(d - ri, abs=1e-12)
        if abs(d - ri) > 1e-12:
            assert got[k] == hit


@settings(max_examples=100, deadline=None)
@given(point, point, point)
def test_mis_line_distance_never_exceeds_segment_distance(a, b, c):
    if math.dist(a, b) < 1e-6:
        return  # the MIS formula divides by |b - a|
    seg = float(segment_circle_distance(a, b, c, 0.0))
    assert float(line_distance_mis(a, b, c)) <= seg + 1e-9


def test_mis_formula_reports_a_false_collision():
    # Arm straight along +x; a circle on the x axis beyond the tip is on the link's line.
    arm = Arm([1.0, 1.0])
    ob = Circle((3.0, 0.0), 0.5)
    pts = arm.joint_positions([0.0, 0.0])
    mis = line_distance_mis(pts[:-1], pts[1:], ob.center) <= ob.radius
    assert mis.any()                               # the MIS says collision
    assert not collides(arm, [0.0, 0.0], [ob])     # the tip is 0.5 short of the disc
    assert clearance(arm, [0.0, 0.0], [ob]) == pytest.approx(0.5)


def test_touching_counts_and_degenerate_segment():
    assert segment_hits_circle([0, 0], [1, 0], (1, 1), 1.0)
    assert segment_hits_circle([2, 0], [2, 0], (2, 1), 1.0)
    assert not segment_hits_circle([2, 0], [2, 0], (2, 1.5), 1.0)
    sq = Polygon.rectangle((1, 0), 1, 1)
    assert segment_hits_polygon([0, 1], [1, 1], sq)       # touches a corner
    assert segment_hits_polygon([1.5, 0.5], [1.5, 0.5], sq)  # a point inside
    assert not segment_hits_polygon([0.9, 0.5], [0.9, 0.5], sq)


@settings(max_examples=150, deadline=None)
@given(polygons(), st.lists(st.tuples(point, point), min_size=1, max_size=15))
def test_separating_axes_match_slow_edge_test_and_distance(poly, segs):
    a = np.array([s[0] for s in segs])
    b = np.array([s[1] for s in segs])
    hits = segment_hits_polygon(a, b, poly)
    dist = segment_polygon_distance(a, b, poly)
    s = np.linspace(0, 1, 401)[:, None]
    for k, (ai, bi) in enumerate(segs):
        slow = slow_hits_polygon(ai, bi, poly.vertices)
        assert (dist[k] == 0) == hits[k]
        samples = np.array(ai) + s * (np.array(bi) - np.array(ai))
        inside = poly.contains(samples)
        if inside.any():
            assert hits[k]
        if not hits[k]:
            # distance from samples to the polygon boundary bounds the true distance from above
            v = poly.array
            w = np.roll(v, -1, axis=0)
            dmin = min(float(segment_circle_distance(v[i], w[i], samples, 0.0).min())
                       for i in range(len(v)))
            assert 0 < dist[k] <= dmin + 1e-9
        if hits[k] != slow:
            # Only a touch may round either way, and a touch puts a vertex of one on an
            # edge of the other: the vertex-edge distance is then ~0.
            v = poly.array
            w = np.roll(v, -1, axis=0)
            raw = min(float(segment_circle_distance(v, w, ai, 0.0).min()),
                      float(segment_circle_distance(v, w, bi, 0.0).min()),
                      float(segment_circle_distance(ai, bi, v, 0.0).min()))
            assert raw < 1e-9


# --- arms --------------------------------------------------------------------------------------

arm_st = st.lists(st.floats(0.2, 1.5), min_size=1, max_size=4).map(Arm)


@settings(max_examples=80, deadline=None)
@given(arm_st, obstacle_lists, st.integers(0, 2**32 - 1))
def test_collides_matches_slow_loop_on_random_configurations(arm, obstacles, seed):
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (40, arm.n))
    got = collides(arm, q.reshape(8, 5, arm.n), obstacles).reshape(-1)
    c = clearance(arm, q, obstacles)
    for k in range(len(q)):
        if abs(c[k]) > 1e-9:
            assert got[k] == slow_collides(arm, q[k], obstacles)
            assert got[k] == (c[k] <= 0)
    if not obstacles:
        assert np.all(np.isinf(c)) and not got.any()


@settings(max_examples=60, deadline=None)
@given(arm_st, st.integers(0, 2**32 - 1))
def test_motion_bound_holds_for_every_point_of_every_link(arm, seed):
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(-np.pi, np.pi, arm.n)
    dq = rng.uniform(-2, 2, arm.n)
    B = motion_bounds(arm, dq)
    t = np.linspace(0, 1, 101)
    pts = arm.joint_positions(q0 + t[:, None] * dq)  # (101, n+1, 2)
    for j in range(arm.n):
        for s in (0.0, 0.3, 1.0):  # points along link j
            x = (1 - s) * pts[:, j] + s * pts[:, j + 1]
            step = np.linalg.norm(np.diff(x, axis=0), axis=1)
            assert np.all(step <= B[j] * (t[1] - t[0]) + 1e-12)


@settings(max_examples=60, deadline=None)
@given(arm_st, obstacle_lists, st.integers(0, 2**32 - 1))
def test_segment_check_never_says_free_when_dense_sampling_collides(arm, obstacles, seed):
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(-np.pi, np.pi, (6, arm.n))
    q1 = q0 + rng.uniform(-1.0, 1.0, (6, arm.n))
    free = segment_collision_free(arm, q0, q1, obstacles)
    t = np.linspace(0, 1, 301)[:, None, None]
    dense = collides(arm, q0 + t * (q1 - q0), obstacles).any(axis=0)
    assert not np.any(free & dense)
    # and the endpoints alone never contradict it
    assert not np.any(free & (collides(arm, q0, obstacles) | collides(arm, q1, obstacles)))


@settings(max_examples=40, deadline=None)
@given(arm_st, st.integers(0, 2**32 - 1))
def test_segments_far_from_obstacles_are_free(arm, seed):
    rng = np.random.default_rng(seed)
    R = float(arm.lengths.sum())
    obstacles = [Circle((R + 1.0, 0.0), 0.5), Polygon.rectangle((-R - 2, -1), 1, 2)]
    q0 = rng.uniform(-np.pi, np.pi, (10, arm.n))
    q1 = q0 + rng.uniform(-6, 6, (10, arm.n))
    assert segment_collision_free(arm, q0, q1, obstacles).all()
    assert path_collision_free(arm, np.stack((q0, q1, q0), axis=1), obstacles).all()


def test_segment_free_when_certified_and_blocked_when_crossing():
    arm = Arm([1.0, 1.0])
    obs = [Circle((0.0, 1.5), 0.3)]
    q0 = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]])
    q1 = np.array([[0.5, 0.0], [3.0, 0.0], [1.0, 0.0]])
    assert segment_collision_free(arm, q0, q1, obs).tolist() == [True, False, True]
    # grazing: the tip passes exactly through the disc boundary -> conservative "not free"
    graze = [Circle((0.0, 2.3), 0.3)]
    assert not segment_collision_free(arm, [0.0, 0.0], [np.pi, 0.0], graze)
    assert path_collision_free(arm, [[0.0, 0.0]], obs)
    assert not path_collision_free(arm, [[0.0, 0.0], [0.5, 0.0], [3.0, 0.0]], obs)


def test_link_clearances_shape_and_bad_obstacle():
    arm = Arm([1.0, 1.0, 1.0])
    assert link_clearances(arm, np.zeros((4, 5, 3)), [Circle((5, 5), 1)]).shape == (4, 5, 3)
    with pytest.raises(ValueError):
        collides(arm, np.zeros(3), [(1.0, 1.0, 0.5)])
