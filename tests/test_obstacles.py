"""Properties of rapp.obstacles: validation, orientation, rectangles, containment."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import Circle, Polygon


def signed_area(v):
    v = np.asarray(v)
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def regular(k, r=1.0, c=(0.0, 0.0), start=0.0):
    t = start + 2 * np.pi * np.arange(k) / k
    return np.c_[c[0] + r * np.cos(t), c[1] + r * np.sin(t)]


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 9), st.floats(0.1, 5), st.floats(-3, 3), st.booleans())
def test_polygon_stored_counter_clockwise_with_same_vertices(k, r, start, clockwise):
    v = regular(k, r, start=start)
    if clockwise:
        v = v[::-1]
    p = Polygon(v)
    assert signed_area(p.array) > 0
    assert sorted(map(tuple, p.array.round(12))) == sorted(map(tuple, v.round(12)))
    assert p.array.shape == (k, 2)


@pytest.mark.parametrize(
    "verts",
    [
        [(0, 0), (1, 0)],                            # too few
        [(0, 0), (2, 0), (1, 0.2), (2, 2), (0, 2)],  # not convex (dent)
        [(0, 0), (1, 0), (2, 0)],                    # zero area
        [(0, 0), (2, 0), (2, 2), (3, 3), (0, 2)],    # not convex
        [(0, 0), (2, 2), (2, 0), (0, 2)],            # self-intersecting order
        [(0, 0), (1, 0), (np.inf, 1)],               # not finite
        [(0, 0), (1, 0), (1, 1), (0.5, 1), (0, 1)],  # collinear vertex: not strictly convex
    ],
)
def test_invalid_polygons_rejected(verts):
    with pytest.raises(ValueError):
        Polygon(verts)


@settings(max_examples=100, deadline=None)
@given(st.floats(-5, 5), st.floats(-5, 5), st.floats(0.01, 4), st.floats(0.01, 4), st.floats(-7, 7))
def test_rectangle_vertices(cx, cy, w, h, angle):
    v = Polygon.rectangle((cx, cy), w, h, angle).array
    np.testing.assert_allclose(v[0], (cx, cy), atol=1e-12)
    e = np.roll(v, -1, axis=0) - v
    np.testing.assert_allclose(np.linalg.norm(e, axis=1), [w, h, w, h], rtol=1e-9)
    np.testing.assert_allclose(e[0], w * np.array([math.cos(angle), math.sin(angle)]), atol=1e-9)
    assert abs(float(e[0] @ e[1])) <= 1e-9 * max(w, h) ** 2  # right angles
    assert signed_area(v) == pytest.approx(w * h, rel=1e-9)


@pytest.mark.parametrize("w, h, a", [(0, 1, 0), (1, -1, 0), (1, 1, np.nan)])
def test_invalid_rectangle_rejected(w, h, a):
    with pytest.raises(ValueError):
        Polygon.rectangle((0, 0), w, h, a)


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 8), st.floats(0.2, 3), st.integers(0, 2**32 - 1))
def test_polygon_contains_matches_disc_bounds(k, r, seed):
    # A regular polygon lies between its inscribed and circumscribed discs.
    p = Polygon(regular(k, r))
    pts = np.random.default_rng(seed).uniform(-2 * r, 2 * r, (400, 2))
    inside = p.contains(pts)
    rad = np.linalg.norm(pts, axis=1)
    assert np.all(inside[rad <= r * math.cos(math.pi / k) * (1 - 1e-9)])
    assert not np.any(inside[rad > r * (1 + 1e-9)])
    assert np.all(p.contains(p.array))  # closed: vertices belong


def test_circle():
    c = Circle((1, 2), 0.5)
    assert c.center == (1.0, 2.0) and c.radius == 0.5
    assert c.contains([[1.5, 2.0], [1.0, 2.51], [1.0, 2.0]]).tolist() == [True, False, True]
    for bad in [((0, 0), 0), ((0, 0), -1), ((0, 0, 0), 1), ((np.nan, 0), 1), ((0, 0), np.inf)]:
        with pytest.raises(ValueError):
            Circle(*bad)
