"""rapp against the Robotics Toolbox for Python where the two overlap (chapter 15).

The toolbox (``roboticstoolbox-python``, pinned in benchmarks/requirements.txt) is an optional
peer, never a dependency of rapp: without it every test here skips, saying so.

What overlaps:

* ``rtb.jtraj`` and ``rtb.quintic``: the quintic through given end positions and velocities with
  zero end accelerations, ``rapp.quintic`` (and ``rapp.time_path(..., "quintic")`` for one move);
* ``rtb.trapezoidal``: an LSPB of one joint for a *given* duration ``T`` and cruise speed ``V``.
  ``rapp.time_scaling.trapezoidal`` computes the *shortest* ``T`` from ``vmax`` and ``amax``;
  given that ``T`` and ``V = vmax`` (or the triangle's peak speed), the toolbox must draw the same
  profile, with the same blend time;
* ``rtb.mtraj(rtb.trapezoidal, ...)``: every joint its own trapezoid over one duration with the
  default ``V`` (1.5 times the average speed), so every blend lasts ``T / 3`` and the joints stay
  synchronized; it equals rapp's synchronized move for limits whose blend is ``T / 3``.
"""

from __future__ import annotations

import numpy as np
import pytest

rtb = pytest.importorskip(
    "roboticstoolbox",
    reason="roboticstoolbox-python is not installed (optional peer: "
           "pip install -r benchmarks/requirements.txt)",
)

import rapp  # noqa: E402
from rapp.time_scaling import trapezoidal  # noqa: E402
from rapp.trajectory import polyval  # noqa: E402

RTOL, ATOL = 1e-9, 1e-9


def _rapp_quintic_samples(T, p0, pf, v0, vf, t):
    """q, qd, qdd of rapp's quintic on [0, T] at times t, shape (len(t), n)."""
    c = rapp.quintic(0.0, T, np.asarray(p0, float), np.asarray(pf, float),
                     np.asarray(v0, float), np.asarray(vf, float))
    tt = np.asarray(t, float)[:, None]
    return tuple(polyval(c[:, None, :], tt, d) for d in (0, 1, 2))


@pytest.mark.parametrize("seed", range(5))
def test_jtraj_is_rapps_rest_to_rest_quintic(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 7))
    q0, qf = rng.uniform(-np.pi, np.pi, (2, n))
    T = float(rng.uniform(0.5, 5.0))
    t = np.linspace(0.0, T, 51)
    tg = rtb.jtraj(q0, qf, t)
    q, qd, qdd = _rapp_quintic_samples(T, q0, qf, np.zeros(n), np.zeros(n), t)
    np.testing.assert_allclose(tg.q, q, rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qd, qd, rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qdd, qdd, rtol=RTOL, atol=ATOL)
    # time_path's single quintic segment is the same polynomial
    np.testing.assert_allclose(rapp.time_path(np.array([q0, qf]), T, "quintic").evaluate(t), tg.q,
                               rtol=RTOL, atol=ATOL)


@pytest.mark.parametrize("seed", range(5))
def test_jtraj_with_end_velocities_is_rapps_quintic(seed):
    rng = np.random.default_rng(100 + seed)
    n = 3
    q0, qf, qd0, qd1 = rng.uniform(-2.0, 2.0, (4, n))
    T = float(rng.uniform(0.5, 4.0))
    t = np.linspace(0.0, T, 41)
    tg = rtb.jtraj(q0, qf, t, qd0, qd1)
    q, qd, qdd = _rapp_quintic_samples(T, q0, qf, qd0, qd1, t)
    np.testing.assert_allclose(tg.q, q, rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qd, qd, rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qdd, qdd, rtol=RTOL, atol=ATOL)


def test_scalar_quintic_agrees():
    t = np.linspace(0.0, 2.0, 21)
    tg = rtb.quintic(0.3, 1.7, t, 0.2, -0.4)
    q, qd, qdd = _rapp_quintic_samples(2.0, [0.3], [1.7], [0.2], [-0.4], t)
    np.testing.assert_allclose(tg.q, q[:, 0], rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qd, qd[:, 0], rtol=RTOL, atol=ATOL)
    np.testing.assert_allclose(tg.qdd, qdd[:, 0], rtol=RTOL, atol=ATOL)


def _trapezoid_cases():
    """(p0, pf, vmax, amax): trapezoids and triangles, forwards and backwards."""
    rng = np.random.default_rng(7)
    cases = [(0.0, 1.2, 1.0, 2.0), (1.0, -0.5, 1.0, 2.0), (0.0, 0.3, 1.0, 2.0), (2.0, 1.9, 0.5, 0.5)]
    for _ in range(30):
        p0 = float(rng.uniform(-3, 3))
        cases.append((p0, p0 + float(rng.choice([-1, 1]) * rng.uniform(0.05, 4.0)),
                      float(rng.uniform(0.2, 3.0)), float(rng.uniform(0.2, 5.0))))
    return cases


@pytest.mark.parametrize("p0,pf,vmax,amax", _trapezoid_cases())
def test_rtb_trapezoidal_draws_rapps_minimum_time_profile(p0, pf, vmax, amax):
    pp = trapezoidal(p0, pf, vmax, amax)
    T = pp.duration
    tb = float(pp.breakpoints[1] - pp.breakpoints[0])
    (peak,), _ = rapp.time_scaling.peak_rates(pp)
    triangle = pp.breakpoints.size == 3
    # The cruise speed rapp reached: vmax, or the triangle's peak a*tb (rtb accepts V <= 2|D|/T).
    V = min(peak, 2 * abs(pf - p0) / T) if triangle else vmax
    t = np.linspace(0.0, T, 301)
    tg = rtb.trapezoidal(p0, pf, t, V)
    assert tg.tblend == pytest.approx(tb, rel=1e-9, abs=1e-12)
    q, qd, qdd = pp.sample(t)
    np.testing.assert_allclose(tg.q, q[:, 0], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(tg.qd, qd[:, 0], rtol=1e-9, atol=1e-9)
    # The acceleration jumps at the blend ends; compare away from them.
    away = (np.abs(t - tb) > 1e-6) & (np.abs(t - (T - tb)) > 1e-6)
    np.testing.assert_allclose(tg.qdd[away], qdd[away, 0], rtol=1e-9, atol=1e-9)


def test_rtb_refuses_a_cruise_speed_below_rapps_minimum_time():
    """rapp's T is the shortest: asked to cruise any slower over that T, the toolbox has no profile."""
    pp = trapezoidal(0.0, 1.2, 1.0, 2.0)
    with pytest.raises(ValueError, match="too small"):
        rtb.trapezoidal(0.0, 1.2, np.linspace(0.0, pp.duration, 11), 0.99 * 1.2 / pp.duration)


@pytest.mark.parametrize("seed", range(4))
def test_mtraj_trapezoidal_is_rapps_synchronized_move_when_the_blend_is_a_third(seed):
    rng = np.random.default_rng(200 + seed)
    n = 3
    q0 = rng.uniform(-2.0, 2.0, n)
    qf = q0 + rng.choice([-1.0, 1.0], n) * rng.uniform(0.2, 2.0, n)
    T = float(rng.uniform(1.0, 4.0))
    d = np.abs(qf - q0)
    # Limits that make rapp's synchronized move last T with tb = T/3: the slowest joint cruises
    # at 1.5 d/T (its vmax) and blends at 4.5 d/T^2 (its amax); the others have slack.
    vmax = 1.5 * d.max() / T * np.where(d == d.max(), 1.0, 3.0)
    amax = 4.5 * d.max() / T**2 * np.where(d == d.max(), 1.0, 3.0)
    pp = trapezoidal(q0, qf, vmax, amax)
    assert pp.duration == pytest.approx(T, rel=1e-12)
    t = np.linspace(0.0, T, 121)
    tg = rtb.mtraj(rtb.trapezoidal, q0, qf, t)
    np.testing.assert_allclose(tg.q, pp.evaluate(t), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(tg.qd, pp.evaluate(t, 1), rtol=1e-9, atol=1e-9)
    # Both stay on the straight joint-space segment: every joint at the same fraction s of its move.
    s = (tg.q - q0) / (qf - q0)
    np.testing.assert_allclose(s, np.repeat(s[:, :1], n, axis=1), atol=1e-9)
