"""From path to motion under velocity and acceleration limits: minimum-time timing.

A planner returns a path, a list of joint-space waypoints; a motor can only
turn so fast (``|qd_i| <= vmax_i``) and accelerate so hard
(``|qdd_i| <= amax_i``). This module answers two questions about a path:

* what is the fastest motion that stops at every waypoint?
  :func:`trapezoidal` (one move) and :func:`trapezoidal_path` (a path) build
  the time-optimal LSPB profile, a *linear segment with parabolic blends*;
* how short may the duration of :func:`time_path` be?
  :func:`minimum_duration` scales its cubic, quintic or spline timing
  uniformly until the first joint touches a limit.

:func:`peak_rates` gives the exact peak speed and acceleration of any
:class:`~rapp.trajectory.PiecewisePolynomial`, the check behind both.

Conventions are those of :mod:`rapp.trajectory`: coefficients in ascending
powers, each piece kept in its local time ``tau = t - breakpoint``, and every
result a :class:`~rapp.trajectory.PiecewisePolynomial` whose ``sample(t)``
returns ``(q, qd, qdd)``. Every joint moves along the straight joint-space
segment between two waypoints, the segment the planner checked for collisions.

Examples
--------
>>> pp = trapezoidal(0.0, 1.0, vmax=1.0, amax=2.0)   # accelerate, cruise, decelerate
>>> pp.breakpoints.tolist()
[0.0, 0.5, 1.0, 1.5]
>>> [r.tolist() for r in peak_rates(pp)]
[[1.0], [2.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import chain
from operator import truediv

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

# rapp.trajectory's argument checks, so that a bad or overflowing input is refused with the
# same messages in both modules.
from rapp.trajectory import (PiecewisePolynomial, checked_duration, duration_shares, finite_array,
                             overflow_checked, step_lengths, via_points)

__all__ = ["time_path", "trapezoidal", "trapezoidal_moves", "TrapezoidMoves", "trapezoidal_path",
           "minimum_duration", "peak_rates", "PROFILES", "clock_after", "clean_waypoints",
           "drop_repeats", "REPEAT_SHARE"]

#: The profiles :func:`minimum_duration` knows: the three of
#: :func:`time_path` and the trapezoid of :func:`trapezoidal_path`.
PROFILES = ("cubic", "quintic", "spline", "trapezoidal")


# --------------------------------------------------------------------------- arguments


def _limit(value, name: str, n: int) -> np.ndarray:
    """``value`` as ``(n,)`` positive finite limits (a scalar applies to every joint)."""
    a = finite_array(value, name)
    if not (a.ndim == 0 or (a.ndim == 1 and a.size in (1, n))):
        raise ValueError(f"{name} must be a number or one number per joint ({n}), "
                         f"got shape {a.shape}")
    if np.any(a <= 0):
        raise ValueError(f"{name} must be > 0 for every joint, got {a.tolist()}")
    return np.broadcast_to(a, (n,)).astype(float)


def clean_waypoints(waypoints, wraps) -> np.ndarray:
    """``(k, n)`` waypoints, unwrapped where ``wraps`` says, repeats dropped (as time_path does)."""
    w = finite_array(waypoints, "waypoints")
    if w.ndim == 1:
        w = w[:, None]
    if w.ndim != 2 or w.shape[0] < 2 or w.shape[1] < 1:
        raise ValueError(f"waypoints must have shape (k, n) with k >= 2 waypoints, got {w.shape}")
    if wraps is not None:
        wraps = np.asarray(wraps, dtype=bool)
        if wraps.ndim > 1 or wraps.size not in (1, w.shape[1]):
            raise ValueError(f"wraps must have one bool per joint ({w.shape[1]}), "
                             f"got {wraps.tolist()}")
        w = np.where(wraps, np.unwrap(w, axis=0), w)
    return drop_repeats(w)


#: A step shorter than this share of the whole path counts as a repeat (:func:`drop_repeats`).
REPEAT_SHARE = 1e-12


def drop_repeats(w) -> np.ndarray:
    """The waypoints ``w`` ``(k, n)`` without repeats: steps of at most ``REPEAT_SHARE`` of the path.

    A repeated waypoint is a move of length 0: no time, no piece. A step of 1e-16 rad beside a
    path of 2 rad is one too: its share of the duration rounds away beside the others' (the
    times of a path cannot resolve it), and timed under limits its tiny piece would set the
    pace of the whole motion. Each waypoint dropped lies within that share of one kept, and
    the first and last waypoints are kept exactly.

    Examples
    --------
    >>> drop_repeats(np.array([[0.0, 0.0], [0.0, 0.0], [0.0, 1e-17], [1.0, 2.0]])).tolist()
    [[0.0, 0.0], [1.0, 2.0]]
    """
    steps = step_lengths(w)
    tol = REPEAT_SHARE * steps.sum()
    if np.all(steps > tol):
        return w
    keep = [0]
    for i in range(1, w.shape[0]):
        if np.linalg.norm(w[i] - w[keep[-1]]) > tol:
            keep.append(i)
    last = w.shape[0] - 1
    if keep[-1] != last:
        if len(keep) > 1:  # the end is within the share of the last one kept: it replaces it
            keep[-1] = last
        elif np.any(w[last] != w[0]):
            keep.append(last)
    return w[keep]


# --------------------------------------------------------------------------- the trapezoid


def _timing(delta: np.ndarray, vmax: np.ndarray, amax: np.ndarray):
    """Blend time ``tb`` and cruise time of the fastest synchronized move by ``delta`` (m, n).

    ``tv = max_i |delta_i| / vmax_i`` is the shortest time to cover the move at
    full speed and ``ta2 = max_i |delta_i| / amax_i`` the square of the
    time scale of the acceleration limit; the slowest joint of each sets them.
    Written as times, not as rates ``vmax_i / |delta_i|``, so that a joint
    that barely moves never divides by a tiny ``delta_i``.
    """
    d = np.abs(delta)
    with np.errstate(all="ignore"):
        tv = np.max(d / vmax, axis=-1)
        ta2 = np.max(d / amax, axis=-1)
        cruise = tv * tv > ta2                 # the move is long enough to reach full speed
        tb = np.where(cruise, ta2 / np.where(cruise, tv, 1.0), np.sqrt(ta2))
        # tv - tb, not T - 2 tb: no cancellation, and never negative.
        tc = np.where(cruise, np.maximum(tv - tb, 0.0), 0.0)
    msg = "the waypoints move too far for vmax and amax: the duration overflows float64"
    return overflow_checked(tb, msg), overflow_checked(tc, msg)


def clock_after(t: float, length: float) -> float:
    """The first float ``b`` with ``b - t >= length``: ``t + length`` rounded up.

    Breakpoints are absolute times, so late in a long path a short blend is
    only resolved to the spacing of floats near ``t`` (2e-10 s at 1e6 s).
    Rounding each piece *up* and fitting the coefficients to the piece as
    rounded (see :func:`_pieces`) means the rounding can only lower a speed or
    an acceleration, never push it over its limit, and costs at most an ulp
    of ``t`` per piece.
    """
    b = t + length
    while b - t < length:
        b = float(np.nextafter(b, np.inf))
    return b


def _pieces(w: np.ndarray, vmax: np.ndarray, amax: np.ndarray):
    """Breakpoints (p + 1,) and local coefficients (p, 3, n) of the trapezoids between rows of ``w``."""
    tb, tc = _timing(w[1:] - w[:-1], vmax, amax)
    bp, local = [0.0], []
    msg = "the waypoints move too far for vmax and amax: the duration overflows float64"
    with np.errstate(all="ignore"):
        for p0, pf, blend, cruise in zip(w[:-1], w[1:], tb, tc):
            # The pieces as the clock will run them (a triangle has no cruise).
            ends = [clock_after(bp[-1], blend)]
            if cruise > 0:
                ends.append(clock_after(ends[-1], cruise))
            ends.append(clock_after(ends[-1], blend))
            if not np.isfinite(ends[-1]):
                raise ValueError(msg)
            h = np.diff([bp[-1], *ends])
            h1, h2, h3 = h[0], (h[1] if cruise > 0 else 0.0), h[-1]
            # Every joint shares the timing: joint i cruises at delta_i / (T - tb),
            # T - tb = h1/2 + h2 + h3/2 with the pieces as rounded, which puts
            # each move exactly on its waypoints and keeps q and qd continuous.
            vel = (pf - p0) / (0.5 * h1 + h2 + 0.5 * h3)
            zero = np.zeros_like(vel)
            local.append([p0, zero, 0.5 * (vel / h1)])                   # accelerate
            if cruise > 0:
                local.append([p0 + 0.5 * vel * h1, vel, zero])           # cruise
            # Decelerate from pf backwards, so that the move ends exactly there.
            local.append([pf - 0.5 * vel * h3, vel, -0.5 * (vel / h3)])
            bp.extend(ends)
    local = np.array(local)
    overflow_checked(local, "the waypoints move too far or too little for vmax and amax: "
                 "the velocities or accelerations overflow float64")
    return np.array(bp), local


def trapezoidal(p0, pf, vmax, amax) -> PiecewisePolynomial:
    """The fastest rest-to-rest move from ``p0`` to ``pf``, every joint synchronized.

    An LSPB profile (linear segment with parabolic blends): accelerate at a
    constant rate for ``tb``, cruise at constant speed, decelerate for ``tb``.
    If the move is too short to reach full speed the cruise disappears and the
    profile is a triangle (``T = 2 tb``).

    Parameters
    ----------
    p0, pf : float or (n,)
        Start and goal configurations.
    vmax, amax : float or (n,), > 0
        Speed and acceleration limits, one for all joints or one per joint.

    Returns
    -------
    PiecewisePolynomial
        Degree 2 in local time, pieces accelerate, cruise and decelerate over
        ``[0, T]`` (a cruise of zero length is dropped); ``sample(t)`` gives
        ``q, qd, qdd``.

    Notes
    -----
    *Synchronized.* All joints start and stop together and share the blend
    time ``tb`` and the duration ``T``: each joint follows the same
    normalized profile ``s(t)`` scaled by its own displacement,
    ``q_i(t) = p0_i + delta_i s(t)``, so the arm stays on the straight
    joint-space segment the planner checked. Joint ``i`` cruises at
    ``delta_i / (T - tb)`` and blends at ``delta_i / (tb (T - tb))``.

    *Minimum time.* On that segment the limits of joint ``i`` read
    ``|s'| <= vmax_i / |delta_i|`` and ``|s''| <= amax_i / |delta_i|``; all of
    them hold exactly when ``s`` respects the tightest of each. In time units:
    ``tv = max_i |delta_i| / vmax_i`` (full speed) and
    ``ta2 = max_i |delta_i| / amax_i``. The fastest rest-to-rest motion of a
    double integrator under such bounds is bang-coast-bang, so

    * ``tv**2 > ta2`` (full speed reached): ``tb = ta2 / tv``, ``T = tv + tb``;
    * otherwise (triangle): ``tb = sqrt(ta2)``, ``T = 2 tb``.

    For one joint this is the textbook ``T = delta/vmax + vmax/amax`` when
    ``delta >= vmax**2 / amax``, else ``T = 2 sqrt(delta / amax)``. The joint
    that sets ``tv`` cruises exactly at its ``vmax``, the one that sets ``ta2``
    blends exactly at its ``amax`` (up to rounding).

    Copying the timing of the joint that is slowest on its own is *not*
    enough: its blend time can be too short for another joint (second example
    below; joint 0 would cruise at ``1 / 0.707 = 1.41 > vmax``). Letting every
    joint keep its own blend time would end all of them at that slowest time
    (here ``sqrt(2) = 1.414``), but then the joints no longer move in
    proportion and the arm leaves the segment between the waypoints.

    Examples
    --------
    >>> pp = trapezoidal([0.0, 0.0], [2.0, -1.0], vmax=1.0, amax=1.0)
    >>> pp.breakpoints.tolist()                   # tb = 1, T = 2/1 + 1/1
    [0.0, 1.0, 2.0, 3.0]
    >>> q, qd, qdd = pp.sample([0.5, 1.5, 3.0])
    >>> qd.tolist()                               # joint 1 at half speed: synchronized
    [[0.5, -0.25], [1.0, -0.5], [0.0, 0.0]]
    >>> q[-1].tolist()
    [2.0, -1.0]

    Two joints, each limited by a different bound (``tv = 1``, ``ta2 = 0.5``):

    >>> trapezoidal([0.0, 0.0], [1.0, 0.5], vmax=[1.0, 100.0], amax=[100.0, 1.0]).breakpoints.tolist()
    [0.0, 0.5, 1.0, 1.5]

    A short move never reaches full speed (triangle):

    >>> trapezoidal(0.0, 1.0, vmax=10.0, amax=1.0).breakpoints.tolist()
    [0.0, 1.0, 2.0]
    """
    one = _one_trapezoid(p0, pf, vmax, amax)
    if one is not None:
        return one
    a, b = finite_array(p0, "p0"), finite_array(pf, "pf")
    if a.ndim > 1 or b.ndim > 1 or a.shape != b.shape:
        raise ValueError(f"p0 and pf must be numbers or (n,) configurations of the same shape, "
                         f"got {a.shape} and {b.shape}")
    w = np.stack([np.atleast_1d(a), np.atleast_1d(b)])
    if not np.any(w[1] != w[0]):
        raise ValueError(f"pf must differ from p0 (a move of length 0 takes no time), "
                         f"got {b.tolist()}")
    n = w.shape[1]
    return PiecewisePolynomial.from_local(*_pieces(w, _limit(vmax, "vmax", n),
                                                  _limit(amax, "amax", n)))


def _clock_after_array(t: np.ndarray, length: np.ndarray) -> np.ndarray:
    """:func:`clock_after` of arrays, element by element (the same floats)."""
    b = t + length
    short = b - t < length
    while short.any():
        b = np.where(short, np.nextafter(b, np.inf), b)
        short = b - t < length
    return b


@dataclass(frozen=True)
class TrapezoidMoves:
    """``m`` independent rest-to-rest trapezoids as plain arrays (see :func:`trapezoidal_moves`).

    Move ``i`` accelerates over ``[0, ends[i, 0]]``, cruises to ``ends[i, 1]`` (equal to
    ``ends[i, 0]`` for a triangle) and decelerates to ``ends[i, 2] = duration[i]``, every
    joint at ``velocity[i]`` while cruising: the breakpoints and coefficients
    :func:`trapezoidal` builds for that move, without building it.
    """

    p0: np.ndarray        #: (m, n) start configurations
    pf: np.ndarray        #: (m, n) goal configurations
    ends: np.ndarray      #: (m, 3) end of the acceleration, of the cruise, of the move
    velocity: np.ndarray  #: (m, n) cruise velocity of every joint

    @property
    def duration(self) -> np.ndarray:
        """``(m,)`` durations, equal to ``trapezoidal(p0[i], pf[i], ...).duration``."""
        return self.ends[:, 2]

    def sample(self, t):
        """``q, qd, qdd`` of every move at times ``t`` of shape ``(m,)`` or ``(m, k)``.

        Each shaped ``t.shape + (n,)``; times are clipped to ``[0, duration]``.
        """
        t = np.asarray(t, dtype=float)
        extra = (slice(None),) + (None,) * (t.ndim - 1)
        e1, e2, e3 = (self.ends[:, j][extra] for j in range(3))
        t = np.clip(t, 0.0, e3)[..., None]
        e1, e2, e3 = e1[..., None], e2[..., None], e3[..., None]
        h1, h3 = e1, e3 - e2
        v, p0, pf = self.velocity[extra], self.p0[extra], self.pf[extra]
        acc, dec = 0.5 * (v / h1), -0.5 * (v / h3)
        tau2 = t - e2
        q = np.where(t <= e1, p0 + acc * t * t,
                     np.where(t <= e2, p0 + 0.5 * v * h1 + v * (t - e1),
                              pf - 0.5 * v * h3 + v * tau2 + dec * tau2 * tau2))
        qd = np.where(t <= e1, 2 * acc * t, np.where(t <= e2, v, v + 2 * dec * tau2))
        qdd = np.where(t <= e1, 2 * acc, np.where(t <= e2, 0.0 * v, 2 * dec))
        return q, qd, qdd


def _one_move(a, b, vmax, amax):
    """``(ends, velocity)`` of one move in Python floats, the operations of :func:`_timing`
    and :func:`_pieces` one by one (so the same floats); None where a value is not finite
    (the numpy path then raises its message)."""
    d = [abs(x1 - x0) for x0, x1 in zip(a, b)]
    tv = max(map(truediv, d, vmax))   # every d / v >= 0: the max from 0.0 of _timing
    ta2 = max(map(truediv, d, amax))
    if not math.isfinite(tv + ta2):
        return None
    if tv * tv > ta2:
        tb = ta2 / tv
        tc = max(tv - tb, 0.0)
    else:
        tb, tc = math.sqrt(ta2), 0.0
    e1 = tb  # clock_after(0.0, tb), exact
    e2 = e1 + tc if tc > 0 else e1
    if e2 - e1 < tc:
        e2 = clock_after(e1, tc)
    e3 = e2 + tb
    if e3 - e2 < tb:
        e3 = clock_after(e2, tb)
    den = 0.5 * e1 + (e2 - e1) + 0.5 * (e3 - e2)
    vel = [(x1 - x0) / den for x0, x1 in zip(a, b)]
    if not math.isfinite(e3 + sum(map(abs, vel))):  # a sum that overflows: numpy decides
        return None
    return (e1, e2, e3), vel


_FLOAT64 = np.dtype(np.float64)


def _floats(x):
    """A vector (list, tuple or 1-D array) or a number as a list of Python floats, else None
    (also where the values' sum is not finite: the numpy path then decides)."""
    if type(x) is np.ndarray and x.dtype is _FLOAT64:
        if x.ndim != 1:
            return None
        out = x.tolist()
    else:
        if isinstance(x, np.ndarray):
            if x.ndim > 1:
                return None
            x = x.tolist()
        if isinstance(x, (int, float)) and not isinstance(x, bool):
            return [float(x)] if math.isfinite(x) else None
        if not isinstance(x, (list, tuple)):
            return None
        try:
            out = [float(v) for v in x]
        except (TypeError, ValueError):
            return None
    return out if out and math.isfinite(sum(out)) else None  # inf, nan, or a sum that overflows


def _one_move_floats(p0, pf, vmax, amax):
    """``(p0, pf, ends, velocity)`` of one well-formed move timed in Python floats, or None:
    the numpy path then times it (or refuses it with its message)."""
    a, b, v, acc = _floats(p0), _floats(pf), _floats(vmax), _floats(amax)
    if a is None or b is None or v is None or acc is None or len(a) != len(b) or a == b:
        return None
    n = len(a)
    if len(v) not in (1, n) or len(acc) not in (1, n) or min(v) <= 0 or min(acc) <= 0:
        return None
    one = _one_move(a, b, v * n if len(v) == 1 else v, acc * n if len(acc) == 1 else acc)
    return None if one is None else (a, b, *one)


def _one_move_checked(p0, pf, vmax, amax):
    """:func:`_one_move_floats` as :class:`TrapezoidMoves`, or None."""
    one = _one_move_floats(p0, pf, vmax, amax)
    if one is None:
        return None
    a, b, ends, vel = one
    return TrapezoidMoves(np.array([a]), np.array([b]), np.array([ends]), np.array([vel]))


def _one_trapezoid(p0, pf, vmax, amax):
    """:func:`trapezoidal` of a well-formed move in Python floats, or None (the numpy path then
    builds it, or refuses it with its message).

    The operations of :func:`_pieces` and of ``PiecewisePolynomial.from_local`` (its
    ``_shift``: ``a_j = 0 + sum_k C(k, j) s^(k - j) b_k``, ``s = -t0``, ``s**2`` as ``s * s``)
    one by one, so the same floats, without a numpy call per value: one move then costs
    microseconds, as a planner timing candidate edges needs.
    """
    one = _one_move_floats(p0, pf, vmax, amax)
    if one is None:
        return None
    a, b, (e1, e2, e3), vel = one
    if not math.isfinite(e3 * e3):  # s * s below would overflow: numpy raises its message
        return None
    h1, h3 = e1, e3 - e2
    cruise = e2 > e1
    s = -e2  # the deceleration's start, on the clock
    ss, s2 = s * s, 2 * s
    rows = []
    for x0, x1, v in zip(a, b, vel):
        acc, dec, c0 = 0.5 * (v / h1), -0.5 * (v / h3), x1 - 0.5 * v * h3
        # Local forms, then from_local's absolute ones, term by term
        # (0 + 1 * 1.0 * b0 + 1 * s * b1 + 1 * s**2 * b2, ...) where no term is an exact zero:
        # at t0 = 0 and for the cruise's zero acceleration those terms add nothing, not even
        # a sign of zero, to 0.0 + b0 (see the tests against trapezoidal_path, bit for bit).
        if cruise:
            m0 = x0 + 0.5 * v * h1
            rows.append((x0, 0.0, acc, m0, v, 0.0, c0, v, dec, 0.0 + x0, 0.0, 0.0 + acc,
                         0.0 + m0 + -e1 * v + 0.0, 0.0 + v, 0.0,
                         0.0 + c0 + s * v + ss * dec, 0.0 + v + s2 * dec, 0.0 + dec))
        else:
            rows.append((x0, 0.0, acc, c0, v, dec, 0.0 + x0, 0.0, 0.0 + acc,
                         0.0 + c0 + s * v + ss * dec, 0.0 + v + s2 * dec, 0.0 + dec))
    if not math.isfinite(sum(map(sum, rows))):  # something overflowed (or the sum did): numpy decides
        return None
    # The breakpoints, then (2 forms, pieces, 3 powers, joints) C-ordered as _pieces makes
    # them (joints last): one array, read-only, and views of it.
    m = 4 if cruise else 3
    flat = np.array(list(chain((0.0, e1, e2, e3) if cruise else (0.0, e1, e3), *zip(*rows))))
    flat.setflags(write=False)
    both = flat[m:].reshape((2, m - 1, 3, len(a)))
    return PiecewisePolynomial.from_checked(flat[:m], both[1], both[0])


def trapezoidal_moves(p0, pf, vmax, amax) -> TrapezoidMoves:
    """Many :func:`trapezoidal` moves at once, as plain arrays: the same durations, no objects.

    The timing of :func:`trapezoidal` (blend and cruise times set by the tightest joint,
    every piece's end rounded up on the clock as :func:`clock_after` does) computed for
    ``m`` moves in one pass of numpy, the arguments checked once. For timing many moves
    (a benchmark, a planner comparing candidate paths) where a
    :class:`~rapp.trajectory.PiecewisePolynomial` per move would cost most of the time.

    Parameters
    ----------
    p0, pf : array_like, shape (m, n) or (n,)
        Start and goal of every move; each goal differs from its start.
    vmax, amax : float or (n,), > 0
        Limits, one for all joints or one per joint.

    Returns
    -------
    TrapezoidMoves

    Examples
    --------
    >>> moves = trapezoidal_moves([[0.0, 0.0], [0.0, 0.0]], [[2.0, -1.0], [0.1, 0.0]], 1.0, 1.0)
    >>> moves.duration.tolist()
    [3.0, 0.6324555320336759]
    >>> bool(moves.duration[0] == trapezoidal([0.0, 0.0], [2.0, -1.0], 1.0, 1.0).duration)
    True
    """
    one = _one_move_checked(p0, pf, vmax, amax)
    if one is not None:
        return one
    a, b = finite_array(p0, "p0"), finite_array(pf, "pf")
    if a.ndim == 1:
        a = a[None, :]
    if b.ndim == 1:
        b = b[None, :]
    if a.ndim != 2 or a.shape != b.shape or a.shape[1] < 1:
        raise ValueError(f"p0 and pf must be (m, n) configurations of the same shape, "
                         f"got {np.shape(p0)} and {np.shape(pf)}")
    still = ~np.any(b != a, axis=1)
    if still.any():
        raise ValueError(f"pf must differ from p0 in every move (a move of length 0 takes no "
                         f"time), move {int(np.argmax(still))} does not move")
    n = a.shape[1]
    vmax, amax = _limit(vmax, "vmax", n), _limit(amax, "amax", n)
    tb, tc = _timing(b - a, vmax, amax)
    msg = "the waypoints move too far for vmax and amax: the duration overflows float64"
    with np.errstate(all="ignore"):
        e1 = _clock_after_array(np.zeros_like(tb), tb)
        e2 = np.where(tc > 0, _clock_after_array(e1, tc), e1)
        e3 = overflow_checked(_clock_after_array(e2, tb), msg)
        h1, h2, h3 = e1, e2 - e1, e3 - e2
        vel = (b - a) / (0.5 * h1 + h2 + 0.5 * h3)[:, None]
    overflow_checked(vel, "the waypoints move too far or too little for vmax and amax: "
                     "the velocities or accelerations overflow float64")
    return TrapezoidMoves(a, b, np.stack((e1, e2, e3), axis=1), vel)


def trapezoidal_path(waypoints: ArrayLike, vmax: ArrayLike, amax: ArrayLike, *,
                     wraps: ArrayLike | None = None) -> PiecewisePolynomial:
    """The fastest motion along a path that stops at every waypoint.

    One :func:`trapezoidal` move per segment, back to back: each segment
    takes its own minimum time, its joints synchronized, and the arm is at
    rest at every waypoint (the straight segments the planner checked are
    followed exactly, corners included).

    Parameters
    ----------
    waypoints : (k, n) or (k,), k >= 2
        Repeated consecutive waypoints are dropped.
    vmax, amax : float or (n,), > 0
    wraps : sequence of bool, optional
        Joints that turn freely, unwrapped first as in
        :func:`time_path`.

    Returns
    -------
    PiecewisePolynomial
        Over ``[0, T_total]``, up to three pieces per segment. Each breakpoint
        is rounded up to a float and the coefficients fit the pieces as
        rounded, so rounding never pushes a joint over a limit (late in a
        long path a blend may end an ulp of ``t`` late).

    Examples
    --------
    >>> pp = trapezoidal_path([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]], vmax=1.0, amax=1.0)
    >>> pp.breakpoints.tolist()                   # a triangle, then a trapezoid
    [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    >>> pp.evaluate([2.0, 5.0]).tolist(), pp.evaluate(2.0, 1).tolist()
    ([[1.0, 0.0], [1.0, 2.0]], [0.0, 0.0])
    """
    w = clean_waypoints(waypoints, wraps)
    n = w.shape[1]
    vmax, amax = _limit(vmax, "vmax", n), _limit(amax, "amax", n)
    if w.shape[0] < 2:
        raise ValueError("waypoints must move: all of them are the same configuration "
                         "(a motion of length 0 takes no time)")
    return PiecewisePolynomial.from_local(*_pieces(w, vmax, amax))


# --------------------------------------------------------------------------- peaks


def _peaks(local: np.ndarray, h: np.ndarray, order: int) -> np.ndarray:
    """Max over pieces and local times ``[0, h]`` of ``|d^order q / dt^order|``, per joint.

    The extremes of a polynomial on an interval lie at its ends or at real
    roots of its derivative. The roots come from ``np.roots``; the real part
    of every root, clipped into ``[0, h]``, is a time inside the piece, so a
    spurious candidate (a complex root) can never raise the maximum above the
    true one, and a true critical point is never missed.
    """
    P = np.polynomial.polynomial
    c = P.polyder(local, m=order, axis=1)
    dc = P.polyder(c, axis=1)
    peak = np.zeros(local.shape[2])
    for i in range(c.shape[0]):
        for j in range(c.shape[2]):
            taus = [0.0, h[i]]
            slope = np.trim_zeros(dc[i, :, j], "b")   # drop zero leading powers
            if slope.size > 1:
                taus.extend(np.clip(np.roots(slope[::-1]).real, 0.0, h[i]))
            peak[j] = max(peak[j], np.abs(P.polyval(np.array(taus), c[i, :, j])).max())
    return peak


def peak_rates(pp: PiecewisePolynomial) -> tuple[np.ndarray, np.ndarray]:
    """Exact peak ``|qd|`` and ``|qdd|`` of each joint over ``[pp.t0, pp.tf]``.

    Analytic per piece (ends and critical points, see the module's ``_peaks``),
    not sampled: a dense sample can only under-estimate a peak between its
    times. A jump of the acceleration at a breakpoint (a trapezoid's) counts
    with both of its one-sided values.

    Returns
    -------
    vpeak, apeak : (n,) arrays

    Examples
    --------
    >>> v, a = peak_rates(time_path([0.0, 1.0], 1.0, "quintic"))   # smoothstep
    >>> v.tolist(), a.round(12).tolist(), round(10 / 3**0.5, 12)
    ([1.875], [5.773502691896], 5.773502691896)
    """
    if not isinstance(pp, PiecewisePolynomial):
        raise ValueError(f"pp must be a PiecewisePolynomial, got {type(pp).__name__}")
    h = np.diff(pp.breakpoints)
    with np.errstate(all="ignore"):
        v, a = _peaks(pp.local, h, 1), _peaks(pp.local, h, 2)
    msg = "the trajectory's velocities or accelerations overflow float64"
    return overflow_checked(v, msg), overflow_checked(a, msg)


# --------------------------------------------------------------------------- minimum duration


def minimum_duration(waypoints: ArrayLike, profile: str, vmax: ArrayLike, amax: ArrayLike, *,
                     wraps: ArrayLike | None = None) -> float:
    """The shortest duration of a rest-to-rest timing of ``waypoints`` within the limits.

    Parameters
    ----------
    waypoints : (k, n) or (k,), k >= 2
    profile : "cubic", "quintic", "spline" or "trapezoidal"
        The first three: the timing of
        :func:`time_path` with that profile. ``"trapezoidal"``:
        :func:`trapezoidal_path`, which stops at every waypoint.
    vmax, amax : float or (n,), > 0
    wraps : sequence of bool, optional
        As in :func:`time_path`.

    Returns
    -------
    float
        ``time_path(waypoints, T, profile)`` (or ``trapezoidal_path``) keeps
        every joint within ``vmax`` and ``amax`` for this ``T``, and some joint
        reaches one of its limits. 0.0 when the waypoints do not move.

    Notes
    -----
    ``time_path`` fixes the *shape* of the motion and only stretches it: its
    waypoint times are proportional to the duration, and every velocity of
    its construction (the via-point heuristic, the quintic's accelerations,
    the spline's tridiagonal solve) scales as ``1 / T``. So
    ``q_T(t) = q_1(t / T)``: velocities scale as ``1 / T`` and accelerations
    as ``1 / T**2``. With ``V_i, A_i`` the exact peaks (:func:`peak_rates`) of
    the reference timing at ``T = 1``, the smallest ``T`` is

        ``T = max_i max(V_i / vmax_i, sqrt(A_i / amax_i))``.

    Examples
    --------
    One joint, one unit: cubic ``max(1.5 D/v, sqrt(6 D/a))``, quintic
    ``max(15 D/(8 v), sqrt(10 D/(sqrt(3) a)))``, trapezoid ``D/v + v/a``:

    >>> [round(minimum_duration([0.0, 1.0], p, vmax=1.0, amax=6.0), 12)
    ...  for p in ("cubic", "quintic", "trapezoidal")]
    [1.5, 1.875, 1.166666666667]
    >>> minimum_duration([[0.0, 0.0], [0.0, 0.0]], "cubic", 1.0, 1.0)
    0.0
    """
    if not isinstance(profile, str) or profile not in PROFILES:
        raise ValueError(f"profile must be one of {', '.join(map(repr, PROFILES))}, "
                         f"got {profile!r}")
    w = clean_waypoints(waypoints, wraps)
    n = w.shape[1]
    vmax, amax = _limit(vmax, "vmax", n), _limit(amax, "amax", n)
    if w.shape[0] < 2:
        return 0.0          # nowhere to go
    if profile == "trapezoidal":
        return trapezoidal_path(w, vmax, amax).duration
    # w is already unwrapped and free of repeats: time_path leaves it as it is.
    V, A = peak_rates(time_path(w, 1.0, profile))
    with np.errstate(all="ignore"):
        T = float(np.max(np.maximum(V / vmax, np.sqrt(A / amax))))
    if not np.isfinite(T):
        raise ValueError("the waypoints move too far for vmax and amax: the duration "
                         "overflows float64")
    return T


# --------------------------------------------------------------------------- a path in time


def time_path(waypoints: ArrayLike, duration: float | None = None, profile: str = "cubic", *,
              vmax: ArrayLike | None = None, amax: ArrayLike | None = None,
              wraps: ArrayLike | None = None, t0: float = 0.0) -> PiecewisePolynomial:
    """Turn a joint-space path into ``q(t)``, starting and ending at rest.

    The time of each waypoint is proportional to the joint-space (Euclidean)
    distance travelled so far, so the arm keeps a roughly even speed along a
    grid path; repeated waypoints, and steps of at most ``REPEAT_SHARE`` (1e-12) of
    the path, are dropped (:func:`drop_repeats`). Give the ``duration``, or joint
    limits ``vmax`` and/or ``amax``: without a duration the motion is the
    shortest one of that profile within the limits
    (:func:`minimum_duration`); with both, a duration too
    short for the limits is refused.

    Parameters
    ----------
    waypoints : (k, n)
    duration : float, > 0, optional
        Required unless ``vmax`` or ``amax`` is given.
    profile : "cubic", "quintic", "spline" or "trapezoidal"
        See :func:`rapp.trajectory.via_points`; all of them have zero velocity at both ends.
        ``"trapezoidal"`` (:func:`rapp.trapezoidal_path`: the
        fastest motion that stops at every waypoint) needs both limits.
    vmax, amax : float or (n,), > 0, optional
        Joint velocity (rad/s) and acceleration (rad/s²) limits; one alone
        leaves the other unbounded.
    wraps : sequence of bool, optional
        Joints that turn freely: their angles are unwrapped along the path
        first (``np.unwrap``) so that a step across ``+-pi`` moves the short
        way instead of swinging all the way round.
    t0 : float
        Start time.

    Examples
    --------
    >>> pp = time_path([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], 4.0)
    >>> pp.breakpoints.tolist()
    [0.0, 2.0, 4.0]
    >>> pp.evaluate([0.0, 4.0], 1).tolist()
    [[0.0, 0.0], [0.0, 0.0]]

    Under limits instead of a duration (one joint, one radian: a cubic needs
    ``max(1.5 D / v, sqrt(6 D / a))``):

    >>> round(time_path([0.0, 1.0], vmax=1.0, amax=6.0).duration, 9)
    1.5
    >>> round(time_path([0.0, 1.0], vmax=1.0, amax=1.0, profile="trapezoidal").duration, 9)
    2.0
    """
    if vmax is not None or amax is not None or profile == "trapezoidal":
        return _time_path_within(waypoints, duration, profile, vmax, amax, wraps, t0)
    if duration is None:
        raise ValueError("give a duration, or joint limits vmax and/or amax")
    w = finite_array(waypoints, "waypoints")
    if w.ndim == 1:
        w = w[:, None]
    if w.ndim != 2 or w.shape[0] < 1:
        raise ValueError(f"waypoints must have shape (k, n), got {w.shape}")
    T, t0 = checked_duration(duration), float(finite_array(t0, "t0"))
    if wraps is not None:
        wraps = np.asarray(wraps, dtype=bool)
        if wraps.ndim > 1 or wraps.size not in (1, w.shape[1]):
            raise ValueError(f"wraps must have one bool per joint ({w.shape[1]}), got {wraps.tolist()}")
        w = np.where(wraps, np.unwrap(w, axis=0), w)
    w = drop_repeats(w)
    with np.errstate(over="ignore"):
        end = np.float64(t0) + T
        s = np.concatenate([[0.0], np.cumsum(step_lengths(w))])
        times = t0 + duration_shares(T, s, s[-1]) if w.shape[0] > 1 else np.array([t0, end])
    overflow_checked(times, f"t0 + duration overflows float64, got t0={t0:g}, duration={T:g}")
    if np.any(np.diff(times) <= 0):
        raise ValueError(
            f"duration {T:g} is too short beside t0 = {t0:g}: waypoint times round together "
            "in float64"
        )
    if w.shape[0] == 1:
        # Nowhere to go: rest at the single configuration.
        return PiecewisePolynomial.from_local(times, np.stack(
            [w[0], np.zeros_like(w[0]), np.zeros_like(w[0]), np.zeros_like(w[0])])[None])
    return via_points(times, w, profile=profile)


def _time_path_within(waypoints, duration, profile, vmax, amax, wraps, t0):
    """:func:`time_path` under joint limits: the shortest duration, or the one given if it is
    long enough. A motion ``q_T(t) = q_1(t / T)`` has peak speeds ``V / T`` and accelerations
    ``A / T**2`` (see :func:`minimum_duration`)."""
    w = clean_waypoints(waypoints, wraps)
    n = w.shape[1]
    if profile == "trapezoidal":
        if vmax is None or amax is None:
            raise ValueError("the trapezoidal profile needs both vmax and amax")
        if w.shape[0] < 2:
            raise ValueError("waypoints must move: all of them are the same configuration")
        pp = trapezoidal_path(w, vmax, amax)
        T_min, stretch = pp.duration, pp
    else:
        if w.shape[0] < 2:
            raise ValueError("waypoints must move under limits: all of them are the same "
                             "configuration (give a duration to rest there)")
        V, A = peak_rates(time_path(w, 1.0, profile))
        with np.errstate(all="ignore"):
            tv = V / _limit(vmax, "vmax", n) if vmax is not None else np.zeros(n)
            ta = np.sqrt(A / _limit(amax, "amax", n)) if amax is not None else np.zeros(n)
        # One ulp-scale margin: the peaks of time_path(w, T) are V / T up to rounding.
        T_min, stretch = float(np.max(np.maximum(tv, ta))) * (1.0 + 1e-12), None
        if not np.isfinite(T_min):
            raise ValueError("the waypoints move too far for vmax and amax: the duration "
                             "overflows float64")
    T = T_min
    if duration is not None:
        T = checked_duration(duration)
        if T < T_min:
            raise ValueError(f"duration {T:g} s is too short for vmax and amax: the shortest "
                             f"is {T_min:.6g} s")
    t0 = float(finite_array(t0, "t0"))
    if stretch is None:
        return time_path(w, T, profile, t0=t0)
    k = np.arange(stretch.local.shape[1])
    c = T / stretch.duration
    return PiecewisePolynomial.from_local(t0 + stretch.breakpoints * c,
                                          stretch.local / c ** k[None, :, None])
