"""Minimum-time timing under velocity and acceleration limits (rapp.time_scaling).

Properties over random moves, paths and limits: the limits hold everywhere
(exact peaks and a dense sample) and are reached (minimum time); joints start
and stop together and move in proportion; position and velocity are
continuous; the closed forms of the trapezoid, the cubic and the quintic,
the last two derived here with sympy.
"""

import warnings

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from rapp.time_scaling import minimum_duration, peak_rates, trapezoidal, trapezoidal_path
from rapp.time_scaling import time_path
from rapp.trajectory import PiecewisePolynomial, via_points

REL = 1e-9          # "reached" and "respected": relative to the limit
# Rounding allowance of a respected limit. A cubic spline's accelerations come from a linear
# solve whose rounding grows with uneven segments: waypoints 2, -1, 0, 0.001, -1, 2.25 (a step
# of 0.001 among steps of 1 to 3) at their minimum duration are 1.2e-12 over the limit.
SLACK = 1 + 1e-11
POLY = ("cubic", "quintic", "spline")

limit_st = st.floats(0.1, 10.0)
coord_st = st.floats(-5.0, 5.0).map(lambda x: round(x, 3))


@st.composite
def moves(draw, max_joints=4):
    """(p0, pf, vmax, amax): some joints may stay put, not all; limits scalar or per joint."""
    n = draw(st.integers(1, max_joints))
    p0 = np.array(draw(st.lists(coord_st, min_size=n, max_size=n)))
    pf = np.array(draw(st.lists(coord_st, min_size=n, max_size=n)))
    still = np.array(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    pf = np.where(still, p0, pf)
    assume(np.any(pf != p0))
    vmax, amax = (draw(st.one_of(limit_st, st.lists(limit_st, min_size=n, max_size=n)))
                  for _ in range(2))
    return p0, pf, vmax, amax


@st.composite
def paths(draw, max_points=6, max_joints=3):
    """(waypoints (k, n), vmax, amax) with at least one move."""
    n = draw(st.integers(1, max_joints))
    k = draw(st.integers(2, max_points))
    w = np.array(draw(st.lists(st.lists(coord_st, min_size=n, max_size=n),
                               min_size=k, max_size=k)))
    assume(np.any(np.diff(w, axis=0) != 0))
    vmax, amax = (draw(st.one_of(limit_st, st.lists(limit_st, min_size=n, max_size=n)))
                  for _ in range(2))
    return w, vmax, amax


def _limits(vmax, amax, n):
    return np.broadcast_to(np.asarray(vmax, float), (n,)), np.broadcast_to(np.asarray(amax, float), (n,))


def _dense(pp, per_piece=200):
    """Sample times: every breakpoint and ``per_piece`` even times inside each piece."""
    bp = pp.breakpoints
    u = np.linspace(0.0, 1.0, per_piece + 1)
    return np.unique(np.concatenate([bp, (bp[:-1, None] + np.diff(bp)[:, None] * u).ravel()]))


def _per_piece(pp, per_piece=200):
    """|qd| and |qdd| sampled inside every piece, both ends included: (samples, n) each.

    ``pp.sample`` at a breakpoint sees one piece only; a jump of the
    acceleration there (cubic via points, trapezoid blends) has two sides.
    """
    P = np.polynomial.polynomial
    u = np.linspace(0.0, 1.0, per_piece + 1)
    out = []
    for der in (1, 2):
        c = P.polyder(pp.local, m=der, axis=1)
        out.append(np.abs(np.concatenate([
            np.stack([P.polyval(h * u, c[i, :, j]) for j in range(pp.dim)], axis=-1)
            for i, h in enumerate(np.diff(pp.breakpoints))])))
    return out


def assert_within_limits(pp, vmax, amax):
    """Exact peaks and a dense sample: nowhere above a limit (up to rounding)."""
    vmax, amax = _limits(vmax, amax, pp.dim)
    vpk, apk = peak_rates(pp)
    assert np.all(vpk <= vmax * SLACK), (vpk, vmax)
    assert np.all(apk <= amax * SLACK), (apk, amax)
    _, qd, qdd = pp.sample(_dense(pp))
    vs, as_ = _per_piece(pp)
    for sv, sa in ((np.abs(qd), np.abs(qdd)), (vs, as_)):
        assert np.all(sv <= vmax * SLACK) and np.all(sa <= amax * SLACK)
        # A sample never beats the exact peak.
        assert np.all(sv.max(axis=0) <= vpk * SLACK + 1e-300)
        assert np.all(sa.max(axis=0) <= apk * SLACK + 1e-300)
    return vpk / vmax, apk / amax


def assert_reached(pp, vmax, amax):
    """Some joint is at its speed or acceleration limit (within REL): no time to spare."""
    vr, ar = assert_within_limits(pp, vmax, amax)
    assert max(vr.max(), ar.max()) >= 1 - REL, (vr, ar)
    return vr, ar


def assert_continuous(pp):
    """q and qd agree at each inner breakpoint from both sides (local coefficients)."""
    P = np.polynomial.polynomial
    h = np.diff(pp.breakpoints)
    for i in range(len(h) - 1):
        for der in (0, 1):
            c = P.polyder(pp.local, m=der, axis=1)
            left = np.array([P.polyval(h[i], c[i, :, j]) for j in range(pp.dim)])
            right = c[i + 1, 0, :]
            scale = 1 + np.abs(pp.local[:, 0, :]).max() if der == 0 else 1 + np.abs(left).max()
            np.testing.assert_allclose(left, right, rtol=0, atol=1e-12 * scale)


# --------------------------------------------------------------------------- one move


def single_joint_T(d, v, a):
    """Textbook minimum time of one joint: trapezoid if full speed is reached, else triangle."""
    d = abs(d)
    return d / v + v / a if d >= v * v / a else 2 * np.sqrt(d / a)


@settings(max_examples=200, deadline=None)
@given(coord_st, coord_st, limit_st, limit_st)
def test_single_joint_closed_form(p0, pf, v, a):
    assume(p0 != pf)
    pp = trapezoidal(p0, pf, v, a)
    d = abs(pf - p0)
    assert pp.duration == pytest.approx(single_joint_T(d, v, a), rel=1e-12)
    triangle = d < v * v / a
    # A triangle has no cruise (2 pieces); a trapezoid cruises at exactly vmax.
    assert len(pp.breakpoints) - 1 == (2 if triangle else 3) or np.isclose(d, v * v / a)
    vpk, apk = peak_rates(pp)
    assert apk[0] == pytest.approx(a, rel=REL)
    if triangle:
        assert vpk[0] == pytest.approx(np.sqrt(d * a), rel=REL) and vpk[0] <= v * SLACK
    else:
        assert vpk[0] == pytest.approx(v, rel=REL)


def test_triangular_when_the_move_is_short():
    # d = 0.5 < v^2 / a = 4: the joint never reaches vmax = 2.
    pp = trapezoidal(1.0, 1.5, vmax=2.0, amax=1.0)
    assert pp.breakpoints.tolist() == pytest.approx([0.0, np.sqrt(0.5), 2 * np.sqrt(0.5)])
    vpk, apk = peak_rates(pp)
    assert vpk[0] == pytest.approx(np.sqrt(0.5)) and vpk[0] < 2.0
    assert apk[0] == pytest.approx(1.0)
    # Exactly at the boundary d = v^2 / a the cruise has zero length and is dropped.
    edge = trapezoidal(0.0, 4.0, vmax=2.0, amax=1.0)
    assert edge.breakpoints.tolist() == [0.0, 2.0, 4.0]


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(moves())
def test_trapezoidal_move_is_minimum_time_and_synchronized(move):
    p0, pf, vmax, amax = move
    pp = trapezoidal(p0, pf, vmax, amax)
    n = len(p0)
    v, a = _limits(vmax, amax, n)
    vr, ar = assert_reached(pp, vmax, amax)
    assert_continuous(pp)
    # Bang-coast-bang is optimal: a cruise means some joint at vmax AND some at amax;
    # a triangle means some joint at amax (the speed limit never binds).
    assert ar.max() >= 1 - REL
    if len(pp.breakpoints) == 4:
        assert vr.max() >= 1 - REL
    # No synchronized motion beats any joint moving on its own.
    assert pp.duration >= max(single_joint_T(d, vi, ai) for d, vi, ai in zip(pf - p0, v, a)
                              if d != 0) * (1 - 1e-12)
    # Rest to rest, from p0 to pf.
    q, qd, qdd = pp.sample([pp.t0, pp.tf])
    np.testing.assert_allclose(q, [p0, pf], rtol=0, atol=1e-12 * (1 + np.abs([p0, pf]).max()))
    np.testing.assert_array_equal(qd[0], 0.0)
    np.testing.assert_allclose(qd[1], 0.0, atol=1e-12 * (1 + v.max()))
    # Synchronized: inside (0, T) every moving joint moves, the others stay put,
    # and all move in proportion (the straight joint-space segment).
    t = np.linspace(pp.t0, pp.tf, 101)[1:-1]
    q, qd, _ = pp.sample(t)
    delta = pf - p0
    moving = delta != 0
    assert np.all(qd[:, moving] * np.sign(delta[moving]) > 0)
    np.testing.assert_array_equal(qd[:, ~moving], 0.0)
    np.testing.assert_array_equal(q[:, ~moving], np.broadcast_to(p0[~moving], q[:, ~moving].shape))
    s = (q[:, moving] - p0[moving]) / delta[moving]
    np.testing.assert_allclose(s, s[:, :1].repeat(s.shape[1], axis=1), rtol=0, atol=1e-12 * 1e3)


def test_slowest_joint_timing_alone_would_break_another_joint():
    # Joint 0 is fast to accelerate, joint 1 fast to cruise. Alone, joint 1 needs
    # 2 sqrt(0.5) = 1.414 s with tb = 0.707; joint 0 would then cruise at
    # 1 / 0.707 = 1.414 > vmax = 1. The synchronized optimum takes 1.5 s.
    pp = trapezoidal([0.0, 0.0], [1.0, 0.5], vmax=[1.0, 100.0], amax=[100.0, 1.0])
    assert pp.duration == pytest.approx(1.5)
    assert pp.duration > 2 * np.sqrt(0.5)
    vr, ar = assert_reached(pp, [1.0, 100.0], [100.0, 1.0])
    assert vr[0] == pytest.approx(1.0) and ar[1] == pytest.approx(1.0)


# --------------------------------------------------------------------------- paths


@pytest.mark.slow
@settings(max_examples=100, deadline=None)
@given(paths())
def test_trapezoidal_path_stops_at_every_waypoint_within_limits(case):
    w, vmax, amax = case
    pp = trapezoidal_path(w, vmax, amax)
    assert pp.t0 == 0.0
    assert_reached(pp, vmax, amax)
    assert_continuous(pp)
    # Back to back: each segment is the minimum-time move, at rest at both ends.
    keep = np.concatenate([[True], np.any(np.diff(w, axis=0) != 0, axis=1)])
    w = w[keep]
    durations = [trapezoidal(a, b, vmax, amax).duration for a, b in zip(w[:-1], w[1:])]
    times = np.concatenate([[0.0], np.cumsum(durations)])
    assert pp.tf == pytest.approx(times[-1], rel=1e-12)
    assert minimum_duration(w, "trapezoidal", vmax, amax) == pp.duration
    q, qd, _ = pp.sample(times)
    np.testing.assert_allclose(q, w, rtol=0, atol=1e-10 * (1 + np.abs(w).max()))
    np.testing.assert_allclose(qd, 0.0, atol=1e-10 * (1 + np.max(vmax)))
    for a, b in zip(w[:-1], w[1:]):
        assert_reached(trapezoidal(a, b, vmax, amax), vmax, amax)


def test_trapezoidal_path_drops_repeated_waypoints_and_unwraps():
    pp = trapezoidal_path([[0.0], [0.0], [1.0], [1.0]], 1.0, 2.0)
    assert pp.breakpoints.tolist() == [0.0, 0.5, 1.0, 1.5]
    # From 3 to -3 rad the short way is 0.28 rad across +-pi, not 6 rad back.
    short = trapezoidal_path([[3.0], [-3.0]], 1.0, 1.0, wraps=[True])
    assert short.evaluate(short.tf)[0] == pytest.approx(2 * np.pi - 3.0)
    assert short.duration == pytest.approx(2 * np.sqrt(2 * np.pi - 6.0))
    assert minimum_duration([[3.0], [-3.0]], "cubic", 1.0, 1.0, wraps=[True]) == pytest.approx(
        max(1.5 * (2 * np.pi - 6.0), np.sqrt(6 * (2 * np.pi - 6.0))))


# --------------------------------------------------------------------------- minimum duration


@settings(max_examples=60, deadline=None)
@given(paths(), st.sampled_from(POLY))
@example((np.array([[2.0], [-1.0], [0.0], [1e-3], [-1.0], [2.25]]), 1.0, 1.0), "cubic")  # found by CI
def test_minimum_duration_of_time_path_is_tight(case, profile):
    w, vmax, amax = case
    T = minimum_duration(w, profile, vmax, amax)
    pp = time_path(w, T, profile)
    assert_reached(pp, vmax, amax)
    # Any shorter uniform timing breaks a limit.
    vr, ar = (r / lim for r, lim in zip(peak_rates(time_path(w, T * (1 - 1e-6), profile)),
                                        _limits(vmax, amax, w.shape[1])))
    assert max(vr.max(), ar.max()) > 1


@settings(max_examples=100, deadline=None)
@given(moves())
def test_trapezoid_never_slower_than_polynomials_for_one_move(move):
    p0, pf, vmax, amax = move
    t_trap = minimum_duration([p0, pf], "trapezoidal", vmax, amax)
    assert t_trap == trapezoidal(p0, pf, vmax, amax).duration
    for profile in POLY:
        assert t_trap <= minimum_duration([p0, pf], profile, vmax, amax) * (1 + 1e-12)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 3), st.integers(2, 6), st.data(), limit_st, limit_st)
def test_trapezoid_never_slower_on_paths_where_time_path_stops_too(n, k, data, vmax, amax):
    # Every joint reverses or stays put at every waypoint: the via-point
    # heuristic puts the arm at rest there, so cubic and quintic are rest-to-rest
    # per segment too, and the trapezoid is the fastest of those per segment.
    steps = np.array(data.draw(st.lists(st.lists(st.floats(0.01, 5.0).map(lambda x: round(x, 3)),
                                                 min_size=n, max_size=n),
                                        min_size=k - 1, max_size=k - 1)))
    signs = (-1.0) ** np.arange(k - 1)[:, None] * data.draw(st.sampled_from([-1.0, 1.0]))
    w = np.concatenate([np.zeros((1, n)), np.cumsum(steps * signs, axis=0)])
    t_trap = minimum_duration(w, "trapezoidal", vmax, amax)
    for profile in ("cubic", "quintic"):
        assert t_trap <= minimum_duration(w, profile, vmax, amax) * (1 + 1e-12)


def test_stopping_at_every_waypoint_can_cost_time_on_a_straight_path():
    # Ten collinear steps of 2: cubic and spline pass the waypoints at speed,
    # the trapezoid stops at each (3 s per step).
    w = np.arange(0.0, 21.0, 2.0)
    t_trap = minimum_duration(w, "trapezoidal", 1.0, 1.0)
    assert t_trap == pytest.approx(30.0)
    assert minimum_duration(w, "cubic", 1.0, 1.0) == pytest.approx(20 * np.sqrt(2))   # 28.28
    assert minimum_duration(w, "spline", 1.0, 1.0) < t_trap


def test_no_motion_takes_no_time():
    for profile in ("cubic", "quintic", "spline", "trapezoidal"):
        assert minimum_duration([[1.0, 2.0]] * 3, profile, 1.0, 1.0) == 0.0


# --------------------------------------------------------------------------- closed forms


def _rest_to_rest_peaks(s):
    """Exact max |s'| and |s''| on [0, 1] of a normalized profile, with sympy."""
    u = sp.symbols("u", real=True)
    s = s(u)
    peaks = []
    for f in (sp.diff(s, u), sp.diff(s, u, 2)):
        crit = [r for r in sp.solve(sp.diff(f, u), u) if r.is_real and 0 <= r <= 1]
        peaks.append(sp.nsimplify(max(sp.Abs(f.subs(u, x)) for x in [0, 1, *crit])))
    return u, s, peaks


def test_cubic_and_quintic_minimum_durations_derived_with_sympy():
    D, v, a = sp.symbols("Delta v_max a_max", positive=True)
    u, s3, (V3, A3) = _rest_to_rest_peaks(lambda u: 3 * u**2 - 2 * u**3)
    _, s5, (V5, A5) = _rest_to_rest_peaks(lambda u: 10 * u**3 - 15 * u**4 + 6 * u**5)
    assert (V3, A3) == (sp.Rational(3, 2), 6)
    assert V5 == sp.Rational(15, 8) and sp.simplify(A5 - 10 / sp.sqrt(3)) == 0
    # q = p0 + D s(t/T): speed D V / T <= v and acceleration D A / T^2 <= a.
    T3 = sp.Max(V3 * D / v, sp.sqrt(A3 * D / a))
    T5 = sp.Max(V5 * D / v, sp.sqrt(A5 * D / a))
    assert sp.simplify(T3 - sp.Max(sp.Rational(3, 2) * D / v, sp.sqrt(6 * D / a))) == 0
    assert sp.simplify(T5 - sp.Max(sp.Rational(15, 8) * D / v,
                                   sp.sqrt(10 * D / (sp.sqrt(3) * a)))) == 0
    # time_path's single segment is that cubic / quintic in u = t / T.
    for profile, s in (("cubic", s3), ("quintic", s5)):
        c = time_path([0.0, 1.0], 1.0, profile).local[0, :, 0]
        ref = [float(x) for x in sp.Poly(s, u).all_coeffs()[::-1]]
        np.testing.assert_allclose(c, ref, atol=1e-12)
    f3 = sp.lambdify((D, v, a), T3, "math")
    f5 = sp.lambdify((D, v, a), T5, "math")
    rng = np.random.default_rng(7)
    for _ in range(200):
        p0, pf = rng.uniform(-5, 5, 2)
        vm, am = rng.uniform(0.1, 10, 2)
        d = abs(pf - p0)
        assert minimum_duration([p0, pf], "cubic", vm, am) == pytest.approx(f3(d, vm, am), rel=1e-12)
        assert minimum_duration([p0, pf], "quintic", vm, am) == pytest.approx(f5(d, vm, am), rel=1e-12)


@pytest.mark.slow
@settings(max_examples=100, deadline=None)
@given(moves(max_joints=3))
def test_polynomial_minimum_duration_of_one_move_is_the_slowest_joints(move):
    p0, pf, vmax, amax = move
    v, a = _limits(vmax, amax, len(p0))
    d = np.abs(pf - p0)
    cubic = max(np.max(1.5 * d / v), np.sqrt(np.max(6 * d / a)))
    quintic = max(np.max(15 * d / (8 * v)), np.sqrt(np.max(10 * d / (np.sqrt(3) * a))))
    assert minimum_duration([p0, pf], "cubic", vmax, amax) == pytest.approx(cubic, rel=1e-12)
    assert minimum_duration([p0, pf], "quintic", vmax, amax) == pytest.approx(quintic, rel=1e-12)


# --------------------------------------------------------------------------- peak_rates


@settings(max_examples=60, deadline=None)
@given(paths(), st.sampled_from(POLY), st.floats(0.5, 20.0))
def test_peak_rates_bound_a_dense_sample_tightly(case, profile, T):
    w = case[0]
    pp = time_path(w, T, profile)
    vpk, apk = peak_rates(pp)
    vs, as_ = (x.max(axis=0) for x in _per_piece(pp, per_piece=2000))
    assert np.all(vs <= vpk * SLACK + 1e-300) and np.all(as_ <= apk * SLACK + 1e-300)
    # The sample comes within its resolution of the peak: the peak is attained.
    np.testing.assert_allclose(vs, vpk, rtol=1e-5, atol=1e-12)
    np.testing.assert_allclose(as_, apk, rtol=1e-5, atol=1e-12)


def test_peak_rates_exact_values():
    # Velocity peaks between breakpoints (a quadratic at its vertex), acceleration at an end.
    pp = via_points([0.0, 2.0], [0.0, 1.0])          # 0.75 t^2 - 0.25 t^3
    v, a = peak_rates(pp)
    assert v.tolist() == [0.75] and a.tolist() == [1.5]
    # An acceleration jump counts with both sides: t^3, then 1 + 3 (t - 1) with no
    # acceleration. The peak 6 is the left limit at t = 1, where sample sees 0.
    pp = PiecewisePolynomial.from_local([0.0, 1.0, 2.0], [[[0.0], [0.0], [0.0], [1.0]],
                                                          [[1.0], [3.0], [0.0], [0.0]]])
    assert pp.sample(1.0)[2].tolist() == [0.0]
    v, a = peak_rates(pp)
    assert v.tolist() == [3.0] and a.tolist() == [6.0]


# --------------------------------------------------------------------------- bad input


NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize("name", ["vmax", "amax"])
@pytest.mark.parametrize("bad", [0.0, -1.0, NAN, INF, [1.0, 0.0], [1.0, 1.0, 1.0], [[1.0, 1.0]], "x"])
def test_bad_limits_are_refused_by_name(name, bad):
    kw = {"vmax": 1.0, "amax": 1.0, name: bad}
    w = [[0.0, 0.0], [1.0, 1.0]]
    for call in (lambda: trapezoidal(w[0], w[1], **kw), lambda: trapezoidal_path(w, **kw),
                 lambda: minimum_duration(w, "cubic", **kw),
                 lambda: minimum_duration(w, "trapezoidal", **kw)):
        with pytest.raises(ValueError, match=f"^{name} "):
            call()


@pytest.mark.parametrize("bad", [[[0.0, 0.0]], [[[0.0]], [[1.0]]], [[0.0, NAN], [1.0, 1.0]], [], 3.0])
def test_bad_waypoints_are_refused_by_name(bad):
    with pytest.raises(ValueError, match="^waypoints "):
        trapezoidal_path(bad, 1.0, 1.0)
    with pytest.raises(ValueError, match="^waypoints "):
        minimum_duration(bad, "quintic", 1.0, 1.0)


def test_other_bad_arguments_are_refused_by_name():
    with pytest.raises(ValueError, match="^p0 and pf"):
        trapezoidal([0.0, 0.0], [1.0], 1.0, 1.0)
    with pytest.raises(ValueError, match="^pf must differ"):
        trapezoidal([1.0, 2.0], [1.0, 2.0], 1.0, 1.0)
    with pytest.raises(ValueError, match="^p0 must be finite"):
        trapezoidal(NAN, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="^waypoints must move"):
        trapezoidal_path([[1.0], [1.0]], 1.0, 1.0)
    with pytest.raises(ValueError, match="^profile "):
        minimum_duration([0.0, 1.0], "linear", 1.0, 1.0)
    with pytest.raises(ValueError, match="^wraps "):
        trapezoidal_path([[0.0, 0.0], [1.0, 1.0]], 1.0, 1.0, wraps=[True, False, True])
    with pytest.raises(ValueError, match="^pp must be"):
        peak_rates(np.zeros(3))


def test_extreme_input_is_an_error_not_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="overflows float64"):
            trapezoidal(0.0, 1e300, vmax=1e-300, amax=1.0)
        with pytest.raises(ValueError, match="overflows float64"):
            minimum_duration([0.0, 1e300], "cubic", vmax=1e-300, amax=1.0)
        # Tiny but representable moves still work.
        pp = trapezoidal(0.0, 1e-200, vmax=1.0, amax=1.0)
        assert pp.duration == pytest.approx(2e-100)


def test_rounding_late_in_a_long_path_never_breaks_a_limit():
    # The second move's blends (0.022 s) start near t = 1e6 s, where floats are
    # 1.2e-10 s apart: a blend rounded short would accelerate 5e-9 too hard.
    w = [[0.0, 0.0], [1e6, 1.0], [1e6 + 1e-3, 1.0 - 1e-3], [1e6 + 2e-3, 1.0]]
    pp = trapezoidal_path(w, vmax=1.0, amax=1.0)
    vpk, apk = peak_rates(pp)
    assert np.all(vpk <= 1.0) and np.all(apk <= 1.0)
    assert apk.max() == pytest.approx(1.0, rel=1e-7)
    assert_continuous(pp)
    np.testing.assert_array_equal(pp.evaluate(pp.tf), w[-1])
