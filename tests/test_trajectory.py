"""Cubic/quintic segments, via points and timed paths: boundary conditions and continuity."""

import functools

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp.symbolic import (
    cubic_coefficients_symbolic,
    cubic_function,
    quintic_coefficients_symbolic,
    quintic_function,
)
from rapp.trajectory import (
    PiecewisePolynomial,
    cubic,
    heuristic_velocities,
    polyval,
    quintic,
    spline_velocities,
    via_points,
)
from rapp.time_scaling import time_path

CUBIC_REF = cubic_function()
QUINTIC_REF = quintic_function()

t0_st = st.floats(0.0, 10.0)
dur_st = st.floats(0.5, 5.0)
val_st = st.floats(-10.0, 10.0)
vel_st = st.floats(-5.0, 5.0)


def _exact(f, *args):
    mpmath.mp.dps = 40
    return np.array([float(v) for v in f(*[mpmath.mpf(float(x)) for x in args])])


def _eval_bound(c, t, derivative=0):
    """Rounding bound of evaluating absolute-time coefficients at t."""
    k = np.arange(len(c))
    mult = np.ones(len(c))
    for i in range(derivative):
        mult = mult * np.maximum(k - i, 0)
    terms = mult * np.abs(c) * np.abs(t) ** np.maximum(k - derivative, 0)
    return 1e-14 * (1 + terms.sum())


@functools.cache
def _exact_coefficients(solve):
    """The symbolic solution as an mpmath function, made on first use (not at collection)."""
    coeffs, symbols = solve()
    return sp.lambdify(symbols, coeffs, modules="mpmath")


@settings(max_examples=150, deadline=None)
@given(t0_st, dur_st, val_st, val_st, vel_st, vel_st)
def test_cubic_boundary_conditions_and_symbolic_solution(t0, dur, p0, pf, v0, vf):
    tf = t0 + dur
    c = cubic(t0, tf, p0, pf, v0, vf)
    assert c.shape == (4,)
    # the sympy solution of seed 002's absolute-time system, exactly and in floats
    exact = _exact(_exact_coefficients(cubic_coefficients_symbolic), t0, tf, p0, pf, v0, vf)
    assert np.abs(c - exact).max() <= 1e-13 * np.abs(exact).max()
    assert np.allclose(c, CUBIC_REF(t0, tf, p0, pf, v0, vf), rtol=1e-6, atol=1e-6)
    # boundary conditions: within the rounding of evaluating absolute powers ...
    for t, d, want in ((t0, 0, p0), (t0, 1, v0), (tf, 0, pf), (tf, 1, vf)):
        assert abs(polyval(c, t, d) - want) <= _eval_bound(c, t, d)
    # ... and to 1e-9 through the trajectory object, which evaluates in local time
    pp = via_points([t0, tf], [p0, pf], velocities=[v0, vf])
    q, qd, _ = pp.sample(np.array([t0, tf]))
    assert np.allclose(q.ravel(), [p0, pf], rtol=0, atol=1e-9)
    assert np.allclose(qd.ravel(), [v0, vf], rtol=0, atol=1e-9)
    assert np.allclose(pp.coefficients[0, :, 0], c, rtol=0, atol=1e-12 * np.abs(c).max())


@settings(max_examples=150, deadline=None)
@given(t0_st, dur_st, val_st, val_st, vel_st, vel_st, vel_st, vel_st)
def test_quintic_boundary_conditions_and_symbolic_solution(t0, dur, p0, pf, v0, vf, a0, af):
    tf = t0 + dur
    c = quintic(t0, tf, p0, pf, v0, vf, a0, af)
    assert c.shape == (6,)
    exact = _exact(_exact_coefficients(quintic_coefficients_symbolic), t0, tf, p0, pf, v0, vf, a0, af)
    assert np.abs(c - exact).max() <= 1e-13 * np.abs(exact).max()
    ref = QUINTIC_REF(t0, tf, p0, pf, v0, vf, a0, af)
    assert np.abs(ref - exact).max() <= 1e-6 * np.abs(exact).max()
    for t, want in ((t0, (p0, v0, a0)), (tf, (pf, vf, af))):
        for d in (0, 1, 2):
            assert abs(polyval(c, t, d) - want[d]) <= _eval_bound(c, t, d)
    pp = via_points([t0, tf], [p0, pf], velocities=[v0, vf], profile="quintic",
                    accelerations=[a0, af])
    q, qd, qdd = pp.sample(np.array([t0, tf]))
    assert np.allclose(np.concatenate([q, qd, qdd]).ravel(), [p0, pf, v0, vf, a0, af],
                       rtol=0, atol=1e-9)


def test_array_arguments_broadcast():
    p0 = np.array([[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]])
    c = cubic(1.0, 2.0, p0, 2 * p0, 0.0, 1.0)
    assert c.shape == (4, 3, 2)
    assert np.allclose(polyval(c, 2.0), 2 * p0)
    assert np.allclose(c[:, 1, 0], cubic(1.0, 2.0, 2.0, 4.0, 0.0, 1.0))


def test_shifted_solution_is_accurate_where_the_absolute_matrix_is_not():
    # Against the exact solution (sympy, 50-digit mpmath), for segments that
    # start late (t0 / T up to 4e4): inverting seed 002's absolute-time matrix
    # loses digits; the shifted closed form plus binomial expansion does not.
    a, syms = cubic_coefficients_symbolic()
    exact_f = sp.lambdify(syms, a, modules="mpmath")
    mpmath.mp.dps = 50
    rng = np.random.default_rng(0)
    worst_ours = worst_naive = 0.0
    for _ in range(100):
        t0, dur = rng.uniform(50, 2000), rng.uniform(0.05, 2)
        p0, pf, v0, vf = rng.normal(size=4)
        tf = t0 + dur
        args = (t0, tf, p0, pf, v0, vf)
        exact = np.array([float(v) for v in exact_f(*[mpmath.mpf(x) for x in args])])
        A = np.array([[1, t, t**2, t**3] for t in (t0, tf)]
                     + [[0, 1, 2 * t, 3 * t**2] for t in (t0, tf)])
        naive = np.linalg.solve(A, [p0, pf, v0, vf])
        rel = lambda c: np.max(np.abs(c - exact) / np.abs(exact))  # noqa: E731
        worst_ours = max(worst_ours, rel(cubic(*args)))
        worst_naive = max(worst_naive, rel(naive))
    assert worst_ours < 1e-13
    assert worst_naive > 1e3 * worst_ours


def test_seed002_task1_tables_and_misprints():
    # Task 1 (eq. 10-11): reproduced to the printed digits.
    x = np.concatenate([cubic(0, 3, 2, 5, 0, 0.25)[::-1], cubic(3, 8, 5, 14, 0.25, 0)[::-1]])
    assert np.allclose(x, [-0.1944, 0.9167, 0, 2, -0.134, 2.186, -9.248, 16.688], atol=6e-4)
    y = np.concatenate([cubic(0, 3, 5, 8, 0, 0.25)[::-1], cubic(3, 8, 8, 7, 0.25, 0)[::-1]])
    assert np.allclose(y, [-0.1944, 0.9167, 0, 5, 0.026, -0.454, 2.272, 4.568], atol=6e-4)
    # Task 2, segment DC of x (eq. 20/24) prints a0 = 144.56; with the other
    # printed digits that misses C = 14 at t = 8 by 1.74 m. The solve gives 146.30.
    printed = np.array([144.56, -64.2048, 9.8496, -0.4864])
    assert abs(polyval(printed, 8.0) - 14.0) > 1.7
    dc = cubic(5.5, 8, 10.2, 14, 0, 0)
    assert abs(dc[0] - 146.3008) < 1e-3 and np.allclose(dc[1:], printed[1:], atol=1e-4)
    # Tasks 2-3 print b_AB,0 = 2 although y_A = 5 (their eq. 25/43 say + 5).
    assert cubic(0, 3, 5, 8, 0, 0.25)[0] == 5.0


# ----------------------------------------------------------------- via points

points_st = st.integers(2, 7).flatmap(lambda k: st.tuples(
    st.lists(st.floats(0.2, 3.0), min_size=k - 1, max_size=k - 1),
    st.lists(st.lists(val_st, min_size=2, max_size=2), min_size=k, max_size=k),
    st.lists(st.lists(vel_st, min_size=2, max_size=2), min_size=k, max_size=k)))


def _segment_ends(pp, derivative):
    """Left and right limits at every interior breakpoint, from the two segment polynomials."""
    h = np.diff(pp.breakpoints)[:-1, None]
    c = np.moveaxis(pp.local, 1, 0)          # (deg+1, m, d), local time per segment
    left = polyval(c[:, :-1], h, derivative)   # end of segment i
    right = polyval(c[:, 1:], 0.0, derivative)  # start of segment i + 1
    return left, right


@settings(max_examples=50, deadline=None)
@given(points_st, st.sampled_from(["cubic", "quintic"]))
def test_via_points_pass_with_given_velocities(data, profile):
    steps, p, v = data
    times = np.concatenate([[1.0], 1.0 + np.cumsum(steps)])
    p, v = np.array(p), np.array(v)
    pp = via_points(times, p, velocities=v, profile=profile)
    assert np.allclose(pp.evaluate(times), p, atol=1e-9)
    assert np.allclose(pp.evaluate(times, 1), v, atol=1e-9)
    for d in (0, 1) + ((2,) if profile == "quintic" else ()):
        left, right = _segment_ends(pp, d)
        assert np.allclose(left, right, atol=1e-8)


@settings(max_examples=50, deadline=None)
@given(points_st)
def test_continuous_heuristic_and_spline_continuity(data):
    steps, p, _ = data
    times = np.concatenate([[0.0], np.cumsum(steps)])
    p = np.array(p)
    heur = via_points(times, p, velocities="continuous")
    assert np.allclose(heur.evaluate(times), p, atol=1e-9)
    assert np.allclose(heur.evaluate(times[[0, -1]], 1), 0.0)
    left, right = _segment_ends(heur, 1)
    assert np.allclose(left, right, atol=1e-8)
    spline = via_points(times, p, profile="spline")
    assert np.allclose(spline.evaluate(times), p, atol=1e-9)
    for d in (0, 1, 2):
        left, right = _segment_ends(spline, d)
        scale = 1 + np.abs(left).max(initial=0)
        assert np.allclose(left, right, atol=1e-8 * scale)


def test_heuristic_rule_mean_or_zero_on_sign_change():
    v = heuristic_velocities([0, 1, 3, 4, 5], [0.0, 2.0, 4.0, 3.0, 3.0])
    # slopes 2, 1, -1, 0 -> mean 1.5; sign change -> 0; zero slope -> 0
    assert v.ravel().tolist() == [0.0, 1.5, 0.0, 0.0, 0.0]


def test_spline_velocities_solve_the_dense_system():
    rng = np.random.default_rng(2)
    times = np.cumsum(rng.uniform(0.3, 2, 8))
    p = rng.normal(size=(8, 3))
    v = spline_velocities(times, p, 0.5, -0.2)
    h = np.diff(times)
    A = np.zeros((6, 6))
    rhs = 3 * (np.diff(p, axis=0)[:-1] / h[:-1, None] ** 2 + np.diff(p, axis=0)[1:] / h[1:, None] ** 2)
    for i in range(6):
        A[i, i] = 2 * (1 / h[i] + 1 / h[i + 1])
        if i:
            A[i, i - 1] = 1 / h[i]
        if i < 5:
            A[i, i + 1] = 1 / h[i + 1]
    rhs[0] -= 0.5 / h[0]
    rhs[-1] -= -0.2 / h[-1]
    assert np.allclose(v[1:-1], np.linalg.solve(A, rhs), atol=1e-12)


def test_evaluate_vectorized_equals_per_sample_loop_and_holds_outside():
    pp = via_points([0.0, 1.0, 2.5, 3.0], np.array([[0, 1], [1, 0], [3, 2], [2, 2.0]]))
    t = np.linspace(-0.5, 3.5, 41)
    for d in (0, 1, 2):
        fast = pp.evaluate(t, d)
        for ti, row in zip(t, fast):
            tc = min(max(ti, 0.0), 3.0)
            i = min(np.searchsorted(pp.breakpoints, tc, side="right") - 1, 2)
            ref = polyval(pp.coefficients[i], tc, d)
            if d and not 0.0 <= ti <= 3.0:
                ref = np.zeros(2)
            assert np.allclose(row, ref)
    assert np.allclose(pp.evaluate(-1.0), [0, 1]) and np.allclose(pp.evaluate(9.0), [2, 2])


def test_piecewise_polynomial_validates():
    with pytest.raises(ValueError):
        PiecewisePolynomial([0.0, 0.0], np.zeros((1, 4, 1)))
    with pytest.raises(ValueError):
        PiecewisePolynomial([0.0, 1.0, 2.0], np.zeros((1, 4, 1)))


# ----------------------------------------------------------------- time_path


@settings(max_examples=50, deadline=None)
@given(st.integers(2, 12), st.integers(0, 2**31 - 1),
       st.sampled_from(["cubic", "quintic", "spline"]))
def test_time_path_rests_at_both_ends_and_passes_waypoints(k, seed, profile):
    rng = np.random.default_rng(seed)
    w = np.cumsum(rng.normal(size=(k, 3)), axis=0)
    pp = time_path(w, 5.0, profile)
    assert pp.t0 == 0.0 and np.isclose(pp.tf, 5.0)
    q, qd, qdd = pp.sample(np.array([0.0, 5.0]))
    assert np.allclose(q, w[[0, -1]], atol=1e-9) and np.allclose(qd, 0.0, atol=1e-9)
    assert np.allclose(pp.evaluate(pp.breakpoints), w, atol=1e-9)
    s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(w, axis=0), axis=1))])
    assert np.allclose(pp.breakpoints, 5.0 * s / s[-1])


def test_time_path_unwraps_free_joints_and_drops_repeats():
    w = np.array([[3.0, 0.0], [3.0, 0.0], [-3.0, 0.1]])      # crosses +-pi
    pp = time_path(w, 2.0, wraps=[True, False])
    end = pp.evaluate(2.0)
    assert np.isclose(end[0], -3.0 + 2 * np.pi) and pp.coefficients.shape[0] == 1
    still = time_path([[0.5, 0.5]] * 3, 1.0)
    assert np.allclose(still.sample(np.linspace(0, 1, 5))[1], 0.0)
