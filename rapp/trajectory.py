"""Polynomial trajectories: cubic and quintic segments, via points (seed 002, R3).

How a path is put in time (:func:`rapp.time_scaling.time_path`) builds on these and lives in
:mod:`rapp.time_scaling`.

Coefficients are in ascending powers of ABSOLUTE time ``t``, the matrix form
of seed 002 (its eq. 5 writes them descending; we store ``a0, a1, ...``).

Why we do not invert seed 002's matrix directly. Its 4 x 4 matrix has rows
``(t0^3, t0^2, t0, 1)``: when a segment starts late compared with its length
(``t0 / T`` large, ``T = tf - t0``) the matrix is nearly singular (its
condition number grows like ``(t0 / T)^3``) and a numerical inverse loses
digits. The same polynomial written in shifted time ``tau = t - t0`` has a
closed-form, well-conditioned solution; the absolute-time coefficients then
follow *exactly* (as algebra) by expanding ``(t - t0)^k`` with the binomial
theorem. The only rounding left is that of the final sums, and
:mod:`rapp.symbolic` checks the result against sympy's exact solution of the
absolute-time system.

The same ill-conditioning returns when absolute-time coefficients are
*evaluated* late in a trajectory (large terms that cancel), so
:class:`PiecewisePolynomial` keeps each segment in local time as well and
evaluates there; its ``coefficients`` field still holds the absolute-time
form of the contract.

Arrays in, arrays out: ``p0, pf, ...`` may be arrays (one polynomial per
entry), and :class:`PiecewisePolynomial` evaluates a whole vector of times
with one ``np.searchsorted``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from math import comb

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.checks import sorted_unique, positive_integer

__all__ = [
    "cubic",
    "quintic",
    "polyval",
    "PiecewisePolynomial",
    "via_points",
    "heuristic_velocities",
    "spline_velocities",
    "time_polyline",
    "cubic_local",
    "quintic_local",
    "shift_to_absolute",
    "finite_array",
    "overflow_checked",
    "step_lengths",
    "duration_shares",
    "checked_duration",
]


def finite_array(value, name: str) -> np.ndarray:
    """``value`` as a float array, or a ValueError naming ``name`` unless every entry is finite."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers, got {value!r}") from None
    if not np.all(np.isfinite(a)):
        shown = a.tolist() if a.size <= 8 else "an array with non-finite entries"
        raise ValueError(f"{name} must be finite, got {shown}")
    return a


def overflow_checked(result: np.ndarray, message: str) -> np.ndarray:
    """``result``, or a ValueError with ``message`` when a finite input overflowed into it.

    The formulas here run under ``np.errstate(all="ignore")``; an overflow or
    an invalid operation leaves an inf or a nan in the result, so this one
    check turns every such case into an error that says which input is too
    large, instead of a RuntimeWarning and a wrong trajectory.
    """
    if not np.all(np.isfinite(result)):
        raise ValueError(message)
    return result


def shift_to_absolute(b: np.ndarray, t0) -> np.ndarray:
    """Coefficients of ``sum_k b_k (t - t0)^k`` in powers of ``t``.

    ``a_j = sum_{k >= j} C(k, j) (-t0)^(k - j) b_k`` (binomial theorem).
    ``b`` has the degree on axis 0; ``t0`` broadcasts against ``b[0]``.

    Examples
    --------
    >>> shift_to_absolute(np.array([0.0, 1.0, 0.0, 0.0]), 2.0).tolist()   # t - 2
    [-2.0, 1.0, 0.0, 0.0]
    """
    b = finite_array(b, "b")
    t0 = finite_array(t0, "t0")
    with np.errstate(all="ignore"):
        a = _shift(b, -t0)
    return overflow_checked(a, f"t0 up to {np.abs(t0).max():.3g} is too large for these coefficients: the "
                    "absolute-time coefficients overflow float64 (local time does not)")


def _shift(b: np.ndarray, s) -> np.ndarray:
    """Coefficients of ``sum_k b_k (x + s)^k`` in powers of ``x``."""
    deg = b.shape[0] - 1
    a = []
    for j in range(deg + 1):
        a.append(sum(comb(k, j) * s ** (k - j) * b[k] for k in range(j, deg + 1)))
    return np.stack(np.broadcast_arrays(*a), axis=0)


def _durations(t0, tf):
    t0 = finite_array(t0, "t0")
    tf = finite_array(tf, "tf")
    with np.errstate(over="ignore"):
        h = tf - t0
    if np.any(~(h > 0)):
        raise ValueError(f"every segment needs tf > t0, got t0={t0.tolist()}, tf={tf.tolist()}")
    return t0, overflow_checked(h, "tf - t0 overflows float64: t0 and tf are too far apart")


def _too_short(what, h):
    return (f"the {what} coefficients overflow float64: the segment duration (tf - t0, "
            f"shortest {np.min(h):.3g}) is too short for the positions, velocities and "
            "accelerations asked")


def cubic(t0: ArrayLike, tf: ArrayLike, p0: ArrayLike, pf: ArrayLike, v0: ArrayLike = 0.0,
          vf: ArrayLike = 0.0) -> np.ndarray:
    """Cubic through ``(t0, p0, v0)`` and ``(tf, pf, vf)`` (seed 002, eq. 5-6).

    Returns
    -------
    ndarray, shape (4,) or (4, ...)
        ``a0..a3`` with ``p(t) = a0 + a1 t + a2 t^2 + a3 t^3``, t absolute.
        Array arguments broadcast; the coefficient index is axis 0.

    Examples
    --------
    Seed 002, Task 1, segment BC of x (t from 3 s to 8 s, 5 m -> 14 m,
    0.25 m/s -> 0):

    >>> cubic(3.0, 8.0, 5.0, 14.0, 0.25, 0.0).round(3).tolist()
    [16.688, -9.248, 2.186, -0.134]
    """
    t0, h = _durations(t0, tf)
    return shift_to_absolute(cubic_local(h, p0, pf, v0, vf), t0)


def cubic_local(h, p0, pf, v0, vf) -> np.ndarray:
    """Cubic coefficients in local time ``tau = t - t0`` over a segment of length ``h``.

    The closed-form solution of the boundary-value problem (the one home of
    this formula); arguments broadcast and the coefficient index is axis 0.

    Examples
    --------
    >>> cubic_local(3.0, 0.0, 3.0, 0.0, 0.25).round(4).tolist()
    [0.0, 0.0, 0.9167, -0.1944]
    """
    h = _positive_durations(h)
    p0, pf, v0, vf = (finite_array(v, k) for v, k in ((p0, "p0"), (pf, "pf"), (v0, "v0"), (vf, "vf")))
    with np.errstate(all="ignore"):
        d = pf - p0
        b = [
            p0,
            v0,
            (3 * d - (2 * v0 + vf) * h) / h**2,
            (-2 * d + (v0 + vf) * h) / h**3,
        ]
        b = np.stack(np.broadcast_arrays(*b), axis=0)
    return overflow_checked(b, _too_short("cubic", h))


def _positive_durations(h):
    h = finite_array(h, "h")
    if np.any(h <= 0):
        raise ValueError(f"h (the segment duration) must be > 0, got {h.tolist()}")
    return h


def quintic(t0: ArrayLike, tf: ArrayLike, p0: ArrayLike, pf: ArrayLike, v0: ArrayLike = 0.0,
            vf: ArrayLike = 0.0, a0: ArrayLike = 0.0, af: ArrayLike = 0.0) -> np.ndarray:
    """Quintic through position, velocity and acceleration at both ends.

    Returns
    -------
    ndarray, shape (6,) or (6, ...)
        Ascending powers of absolute time.

    Examples
    --------
    >>> quintic(0.0, 1.0, 0.0, 1.0).round(9).tolist()
    [0.0, 0.0, 0.0, 10.0, -15.0, 6.0]
    """
    t0, h = _durations(t0, tf)
    return shift_to_absolute(quintic_local(h, p0, pf, v0, vf, a0, af), t0)


def quintic_local(h, p0, pf, v0, vf, a0, af) -> np.ndarray:
    """Quintic coefficients in local time ``tau = t - t0`` over a segment of length ``h``.

    Examples
    --------
    >>> quintic_local(1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0).tolist()
    [0.0, 0.0, 0.0, 10.0, -15.0, 6.0]
    """
    h = _positive_durations(h)
    p0, pf, v0, vf, a0, af = (finite_array(v, k) for v, k in (
        (p0, "p0"), (pf, "pf"), (v0, "v0"), (vf, "vf"), (a0, "a0"), (af, "af")))
    with np.errstate(all="ignore"):
        d = pf - p0
        b = [
            p0,
            v0,
            a0 / 2,
            (20 * d - (8 * vf + 12 * v0) * h - (3 * a0 - af) * h**2) / (2 * h**3),
            (-30 * d + (14 * vf + 16 * v0) * h + (3 * a0 - 2 * af) * h**2) / (2 * h**4),
            (12 * d - 6 * (vf + v0) * h - (a0 - af) * h**2) / (2 * h**5),
        ]
        b = np.stack(np.broadcast_arrays(*b), axis=0)
    return overflow_checked(b, _too_short("quintic", h))


def _derivative_coeffs(c: np.ndarray, derivative: int, axis: int) -> np.ndarray:
    c = np.moveaxis(c, axis, 0)
    for _ in range(derivative):
        k = np.arange(1, c.shape[0]).reshape((-1,) + (1,) * (c.ndim - 1))
        c = c[1:] * k if c.shape[0] > 1 else np.zeros_like(c)
    return np.moveaxis(c, 0, axis)


def polyval(coeffs, t, derivative: int = 0) -> np.ndarray:
    """Evaluate ascending-power coefficients (axis 0) or a derivative at ``t``.

    ``coeffs`` (deg+1, ...) broadcasts against ``t``; Horner's rule.

    Examples
    --------
    >>> c = cubic(0.0, 3.0, 2.0, 5.0, 0.0, 0.25)
    >>> polyval(c, [0.0, 3.0]).round(12).tolist(), polyval(c, 3.0, 1).round(12).tolist()
    ([2.0, 5.0], 0.25)
    """
    c = _derivative_coeffs(finite_array(coeffs, "coeffs"), derivative, 0)
    t = finite_array(t, "t")
    out = np.zeros(np.broadcast_shapes(c.shape[1:], t.shape))
    with np.errstate(all="ignore"):
        for k in range(c.shape[0] - 1, -1, -1):
            out = out * t + c[k]
    return overflow_checked(out, "the polynomial's value overflows float64 at these t")


@dataclass(frozen=True, eq=False)
class PiecewisePolynomial:
    """A trajectory made of polynomial segments.

    Parameters
    ----------
    breakpoints : (m + 1,) increasing times
    coefficients : (m, deg + 1, d)
        Segment ``i`` holds on ``[breakpoints[i], breakpoints[i+1]]``;
        ascending powers of ABSOLUTE ``t`` (the contract, seed 002's form).
    local : (m, deg + 1, d), optional
        The same segments in local time ``tau = t - breakpoints[i]``. The
        constructors of this module pass it; otherwise it is derived from
        ``coefficients``.

    Notes
    -----
    Evaluation uses the local form. Absolute-time coefficients of a segment
    late in a long trajectory are large and cancel each other (evaluating
    ``sum a_k t^k`` at ``t = 20`` for a degree-5 segment 0.5 s long loses about
    seven digits); local time keeps every term of the size of the motion.

    Outside ``[t0, tf]`` the trajectory holds its end position with zero
    velocity and acceleration (the arm waits).

    Examples
    --------
    >>> pp = via_points([0.0, 3.0, 8.0], [[2.0, 5.0], [5.0, 8.0], [14.0, 7.0]],
    ...                 velocities=[[0, 0], [0.25, 0.25], [0, 0]])
    >>> pp.evaluate([0.0, 3.0, 8.0]).round(12).tolist()
    [[2.0, 5.0], [5.0, 8.0], [14.0, 7.0]]
    >>> q, qd, qdd = pp.sample(np.linspace(0, 8, 5))
    >>> q.shape, qd[-1].tolist()
    ((5, 2), [0.0, 0.0])
    >>> pp.coefficients[1, :, 0].round(3).tolist()   # seed 002, x of segment BC
    [16.688, -9.248, 2.186, -0.134]
    """

    breakpoints: np.ndarray
    coefficients: np.ndarray
    local: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        bp = finite_array(self.breakpoints, "breakpoints")
        c = finite_array(self.coefficients, "coefficients")
        if c.ndim == 2:
            c = c[:, :, None]
        if bp.ndim != 1 or bp.size < 2 or np.any(np.diff(bp) <= 0):
            raise ValueError("breakpoints must be at least two strictly increasing times")
        if c.ndim != 3 or c.shape[0] != bp.size - 1:
            raise ValueError(
                f"coefficients must have shape ({bp.size - 1}, deg+1, d), got {c.shape}"
            )
        if self.local is None:
            with np.errstate(all="ignore"):
                loc = np.moveaxis(_shift(np.moveaxis(c, 1, 0), bp[:-1, None]), 0, 1)
            overflow_checked(loc, "breakpoints and coefficients too large: the local-time coefficients "
                       "overflow float64")
        else:
            loc = finite_array(self.local, "local")
            if loc.size != c.size:
                raise ValueError(f"local must have the shape of coefficients {c.shape}, got {loc.shape}")
            loc = loc.reshape(c.shape)
        for arr in (bp, c, loc):
            arr.setflags(write=False)
        object.__setattr__(self, "breakpoints", bp)
        object.__setattr__(self, "coefficients", c)
        object.__setattr__(self, "local", loc)

    @classmethod
    def from_local(cls, breakpoints, local) -> "PiecewisePolynomial":
        """Build from local-time coefficients (m, deg + 1, d); the absolute form is derived.

        Examples
        --------
        >>> pp = PiecewisePolynomial.from_local([2.0, 3.0], [[[1.0], [1.0]]])   # 1 + (t - 2)
        >>> pp.coefficients.ravel().tolist(), pp.evaluate(2.5).tolist()
        ([-1.0, 1.0], [1.5])
        """
        bp = finite_array(breakpoints, "breakpoints")
        loc = finite_array(local, "local")
        if loc.ndim == 2:
            loc = loc[:, :, None]
        if bp.ndim != 1 or loc.ndim != 3 or loc.shape[0] != bp.size - 1:
            raise ValueError(
                f"local must have shape (len(breakpoints) - 1, deg+1, d), got {loc.shape} "
                f"for {bp.size} breakpoints"
            )
        with np.errstate(all="ignore"):
            absolute = np.moveaxis(_shift(np.moveaxis(loc, 1, 0), -bp[:-1, None]), 0, 1)
        overflow_checked(absolute, f"breakpoints up to {np.abs(bp).max():.3g} are too late for these "
                        "segments: the absolute-time coefficients overflow float64")
        return cls(bp, absolute, loc)

    @classmethod
    def from_checked(cls, breakpoints: np.ndarray, coefficients: np.ndarray,
                     local: np.ndarray) -> "PiecewisePolynomial":
        """Build from arrays a constructor has already made right, without checking them again.

        ``breakpoints`` ``(m + 1,)`` strictly increasing, ``coefficients`` and ``local``
        ``(m, deg + 1, d)``, every entry finite, the two forms of the same segments: what
        :func:`rapp.time_scaling.trapezoidal` computes for one move, where the checks of the
        ordinary constructor would cost more than the move. The arrays are kept, not copied:
        pass read-only ones (views of a read-only array are), as every other constructor makes.

        Examples
        --------
        >>> arrays = [np.array(a) for a in ([2.0, 3.0], [[[-1.0], [1.0]]], [[[1.0], [1.0]]])]
        >>> for a in arrays:
        ...     a.setflags(write=False)
        >>> pp = PiecewisePolynomial.from_checked(*arrays)
        >>> same = PiecewisePolynomial.from_local([2.0, 3.0], [[[1.0], [1.0]]])
        >>> bool((pp.coefficients == same.coefficients).all()), pp.evaluate(2.5).tolist()
        (True, [1.5])
        """
        pp = object.__new__(cls)
        pp.__dict__.update(breakpoints=breakpoints, coefficients=coefficients, local=local)  # frozen
        return pp

    @property
    def t0(self) -> float:
        """Start time, the first breakpoint."""
        return float(self.breakpoints[0])

    @property
    def tf(self) -> float:
        """End time, the last breakpoint."""
        return float(self.breakpoints[-1])

    @property
    def duration(self) -> float:
        """``tf - t0``."""
        return self.tf - self.t0

    @property
    def degree(self) -> int:
        """Polynomial degree of every segment."""
        return self.coefficients.shape[1] - 1

    @property
    def dim(self) -> int:
        """Number of coordinates ``d`` (joints)."""
        return self.coefficients.shape[2]

    def evaluate(self, t, derivative: int = 0) -> np.ndarray:
        """Position (0), velocity (1) or acceleration (2) at times ``t``, shape ``t.shape + (d,)``.

        Outside ``[t0, tf]`` the end position is held and the derivatives are 0.

        Examples
        --------
        >>> pp = via_points([0.0, 2.0], [0.0, 1.0])
        >>> pp.evaluate([1.0, 3.0]).ravel().tolist(), pp.evaluate([1.0, 3.0], 1).ravel().tolist()
        ([0.5, 1.0], [0.75, 0.0])
        """
        if derivative not in (0, 1, 2):
            raise ValueError("derivative must be 0, 1 or 2")
        try:
            t = np.asarray(t, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"t must be times (numbers), got {t!r}") from None
        # +-inf is a fine time (the arm waits at an end); nan is no time at all.
        if np.isnan(t).any():
            raise ValueError("t must be times, got nan")
        tc = np.clip(t, self.t0, self.tf)
        seg = np.clip(np.searchsorted(self.breakpoints, tc, side="right") - 1,
                      0, self.coefficients.shape[0] - 1)
        c = _derivative_coeffs(self.local, derivative, 1)[seg]  # t.shape + (k, d)
        tau = (tc - self.breakpoints[seg])[..., None]
        out = np.zeros(t.shape + (self.dim,))
        with np.errstate(all="ignore"):
            for k in range(c.shape[-2] - 1, -1, -1):
                out = out * tau + c[..., k, :]
        if derivative:
            outside = (t < self.t0) | (t > self.tf)
            out[outside] = 0.0
        return overflow_checked(out, "the trajectory's values overflow float64 at these times")

    def sample(self, t):
        """``(q, qd, qdd)`` at times ``t``, each of shape ``t.shape + (d,)``.

        Examples
        --------
        >>> q, qd, qdd = via_points([0.0, 2.0], [0.0, 1.0]).sample([0.0, 1.0])
        >>> qdd.ravel().tolist()
        [1.5, 0.0]
        """
        return self.evaluate(t, 0), self.evaluate(t, 1), self.evaluate(t, 2)


# --------------------------------------------------------------------------- via points


def _as_points(times, positions):
    times = finite_array(times, "times")
    positions = finite_array(positions, "positions")
    if positions.ndim == 1:
        positions = positions[:, None]
    if times.ndim != 1 or times.size < 2 or positions.ndim != 2 or positions.shape[0] != times.size:
        raise ValueError(
            f"need k >= 2 times and k positions, got times of shape {times.shape} "
            f"and positions of shape {positions.shape}"
        )
    with np.errstate(over="ignore"):
        steps = np.diff(times)
    if np.any(steps <= 0):
        raise ValueError("times must be strictly increasing")
    overflow_checked(steps, "times span more than float64 holds: their differences overflow")
    return times, positions


def _rows(values, k, d, name):
    """``values`` as a finite ``(k, d)`` array, or a ValueError naming ``name``."""
    a = finite_array(values, name)
    if a.size != k * d:
        raise ValueError(f"{name} must have shape ({k}, {d}) like positions, got {a.shape}")
    return a.reshape(k, d)


_STEEP = ("positions change too fast for the times between them: the velocities overflow "
          "float64 (times too close together, or positions too large)")


def heuristic_velocities(times, positions, v_start=0.0, v_end=0.0) -> np.ndarray:
    """The textbook via-point velocities: at an interior point the mean of the
    two adjacent slopes, or zero where the slope changes sign; given values at
    the ends (rest by default).

    Examples
    --------
    >>> heuristic_velocities([0, 1, 2, 3], [0.0, 1.0, 3.0, 2.0]).ravel().tolist()
    [0.0, 1.5, 0.0, 0.0]
    """
    times, p = _as_points(times, positions)
    v_start, v_end = finite_array(v_start, "v_start"), finite_array(v_end, "v_end")
    with np.errstate(all="ignore"):
        slopes = np.diff(p, axis=0) / np.diff(times)[:, None]
        left, right = slopes[:-1], slopes[1:]
        # Halves first: the mean of two huge slopes of one sign must not overflow.
        inner = np.where(np.sign(left) * np.sign(right) > 0, 0.5 * left + 0.5 * right, 0.0)
    v = np.empty_like(p)
    v[0], v[-1], v[1:-1] = v_start, v_end, inner
    return overflow_checked(v, _STEEP)


def spline_velocities(times, positions, v_start=0.0, v_end=0.0) -> np.ndarray:
    """Knot velocities of the C2 cubic spline with clamped end velocities.

    Continuity of acceleration at interior knot ``i`` gives the tridiagonal
    system ``v_{i-1}/h_{i-1} + 2 v_i (1/h_{i-1} + 1/h_i) + v_{i+1}/h_i =
    3 (D_{i-1}/h_{i-1}^2 + D_i/h_i^2)`` with ``D`` the position steps. It is
    solved by the Thomas algorithm: a forward and a backward recurrence over
    the knots (inherently sequential), vectorized over the dimensions.

    Examples
    --------
    >>> spline_velocities([0, 1, 2], [0.0, 1.0, 0.0]).ravel().tolist()
    [0.0, 0.0, 0.0]
    """
    times, p = _as_points(times, positions)
    v_start, v_end = finite_array(v_start, "v_start"), finite_array(v_end, "v_end")
    with np.errstate(all="ignore"):
        v = _spline_velocities(times, p, v_start, v_end)
    return overflow_checked(v, _STEEP)


def _spline_velocities(times, p, v_start, v_end):
    k, d = p.shape
    v = np.empty_like(p)
    v[0], v[-1] = v_start, v_end
    if k == 2:
        return v
    h = np.diff(times)
    step = np.diff(p, axis=0)
    lower = 1.0 / h[:-1]                         # coefficient of v_{i-1}
    diag = 2.0 * (1.0 / h[:-1] + 1.0 / h[1:])
    upper = 1.0 / h[1:]                          # coefficient of v_{i+1}
    rhs = 3.0 * (step[:-1] / h[:-1, None] ** 2 + step[1:] / h[1:, None] ** 2)
    rhs[0] -= lower[0] * v[0]
    rhs[-1] -= upper[-1] * v[-1]
    nin = k - 2
    cp = np.empty(nin)
    dp = np.empty((nin, d))
    cp[0] = upper[0] / diag[0]
    dp[0] = rhs[0] / diag[0]
    for i in range(1, nin):
        den = diag[i] - lower[i] * cp[i - 1]
        cp[i] = upper[i] / den
        dp[i] = (rhs[i] - lower[i] * dp[i - 1]) / den
    inner = np.empty((nin, d))
    inner[-1] = dp[-1]
    for i in range(nin - 2, -1, -1):
        inner[i] = dp[i] - cp[i] * inner[i + 1]
    v[1:-1] = inner
    return v


def _end_values(values, d):
    if values is None:
        return np.zeros(d), np.zeros(d)
    values = finite_array(values, "velocities")
    if values.ndim == 0 or values.shape[0] < 1:
        raise ValueError(f"velocities must have k or 2 rows, got shape {values.shape}")
    if values.ndim == 1:
        values = values[:, None]
    return values[0], values[-1]


def via_points(times: ArrayLike, positions: ArrayLike, velocities: ArrayLike | None = None,
               profile: str = "cubic",
               accelerations: ArrayLike | None = None) -> PiecewisePolynomial:
    """A trajectory through via points (seed 002 Task 1, generalized).

    Parameters
    ----------
    times : (k,) increasing
    positions : (k, d) or (k,)
    velocities : None, "continuous" or array (k, d)
        For ``profile="cubic"`` or ``"quintic"``: the velocity at every via
        point. ``None`` and ``"continuous"`` use the textbook heuristic
        (:func:`heuristic_velocities`) with rest at both ends. An array gives
        them all (seed 002: rest, 0.25 m/s at B, rest). For
        ``profile="spline"`` only the end velocities are used (an array of
        k or 2 rows; ``None`` means rest); the interior ones are solved.
    profile : "cubic", "quintic" or "spline"
        ``"cubic"``: cubic segments, continuous position and velocity.
        ``"quintic"``: quintic segments, continuous acceleration as well
        (each via point gets one acceleration shared by both segments).
        ``"spline"``: the C2 cubic spline, continuous velocity AND
        acceleration with clamped end velocities.
    accelerations : None, "continuous" or array (k, d)
        Quintic only. ``None`` or ``"continuous"``: the mean of the adjacent
        velocity slopes, zero at both ends.

    Examples
    --------
    >>> pp = via_points([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], profile="spline")
    >>> pp.evaluate(1.0, 1).round(12).tolist(), pp.degree
    ([0.0], 3)
    """
    times, p = _as_points(times, positions)
    k, d = p.shape
    if profile == "spline":
        if isinstance(velocities, str):
            if velocities != "continuous":
                raise ValueError(f"unknown velocities {velocities!r}")
            velocities = None
        vs, ve = _end_values(velocities, d)
        v = spline_velocities(times, p, vs, ve)
    elif profile in ("cubic", "quintic"):
        if velocities is None or (isinstance(velocities, str) and velocities == "continuous"):
            v = heuristic_velocities(times, p)
        elif isinstance(velocities, str):
            raise ValueError(f"unknown velocities {velocities!r}")
        else:
            v = _rows(velocities, k, d, "velocities")
    else:
        raise ValueError(f"profile must be 'cubic', 'quintic' or 'spline', got {profile!r}")
    t0, tf = times[:-1, None], times[1:, None]
    if profile == "quintic":
        if accelerations is None or (isinstance(accelerations, str)
                                     and accelerations == "continuous"):
            with np.errstate(all="ignore"):
                slopes = np.diff(v, axis=0) / np.diff(times)[:, None]
                acc = np.zeros_like(v)
                acc[1:-1] = 0.5 * slopes[:-1] + 0.5 * slopes[1:]
            overflow_checked(acc, "velocities change too fast for the times between them: the "
                       "accelerations overflow float64")
        elif isinstance(accelerations, str):
            raise ValueError(f"unknown accelerations {accelerations!r}")
        else:
            acc = _rows(accelerations, k, d, "accelerations")
        c = quintic_local(tf - t0, p[:-1], p[1:], v[:-1], v[1:], acc[:-1], acc[1:])
    else:
        c = cubic_local(tf - t0, p[:-1], p[1:], v[:-1], v[1:])
    return PiecewisePolynomial.from_local(times, np.moveaxis(c, 0, 1))


def duration_shares(T, lengths, total):
    """``T * lengths / total``: each length's share of the duration ``T``."""
    with np.errstate(over="ignore"):
        out = T * lengths / total
    # Only when T * length overflows: the quotient first costs a rounding, not the result.
    return out if np.all(np.isfinite(out)) else T * (lengths / total)


def checked_duration(duration) -> float:
    """``duration`` as a float, or a ValueError naming it unless it is finite and > 0."""
    T = float(finite_array(duration, "duration"))
    if not T > 0:
        raise ValueError(f"duration must be > 0, got {duration!r}")
    return T


def step_lengths(w) -> np.ndarray:
    """Joint-space length of every step between rows of ``w``; a ValueError if the path's overflows."""
    with np.errstate(all="ignore"):
        d = np.diff(w, axis=0)
        step = np.linalg.norm(d, axis=-1)
        if not np.all(np.isfinite(step)):
            # The squares overflowed (steps beyond ~1e154): scale each step by its largest entry.
            m = np.abs(d).max(axis=-1, initial=0.0)
            m = np.where(m > 0, m, 1.0)
            step = m * np.linalg.norm(d / m[:, None], axis=-1)
        overflow_checked(step.sum(), "waypoints are too far apart: the path's length overflows float64")
    return overflow_checked(step, "waypoints are too far apart: a step's length overflows float64")


_SMOOTHSTEP = (lambda s: s**3 * (10 - 15 * s + 6 * s**2),
               lambda s: 30 * s**2 * (1 - s) ** 2,
               lambda s: 60 * s - 180 * s**2 + 120 * s**3)


def time_polyline(waypoints, duration: float, samples: int):
    """Rest-to-rest timing of a polyline: follows its straight segments exactly.

    Segment ``j`` gets a time share proportional to its joint-space length and
    is traversed with the quintic smoothstep ``s = 10 u^3 - 15 u^4 + 6 u^5``,
    so velocity and acceleration are zero at every waypoint and continuous
    everywhere. The sample times are ``samples`` even times, every waypoint
    time, and three times inside each segment (so each segment is sampled).

    Returns
    -------
    t (k,), q (k, n), qd (k, n), qdd (k, n)

    Examples
    --------
    >>> t, q, qd, qdd = time_polyline([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], 2.0, 5)
    >>> t.tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0]
    >>> q[4].tolist(), qd[4].tolist()
    ([1.0, 0.0], [0.0, 0.0])
    """
    w = finite_array(waypoints, "waypoints")
    if w.ndim != 2 or len(w) < 1:
        raise ValueError(f"waypoints must have shape (m, n), got {w.shape}")
    T = checked_duration(duration)
    t = np.linspace(0.0, T, positive_integer(samples, "samples", lo=2))
    n = w.shape[1]
    seg = step_lengths(w)
    total = float(seg.sum())
    if total <= 0.0:
        z = np.zeros((len(t), n))
        return t, np.broadcast_to(w[0], (len(t), n)).copy(), z, z.copy()
    with np.errstate(all="ignore"):
        t, q, qd, qdd = _smoothstep_polyline(w, T, t, seg, total)
    msg = (f"waypoints move too far for duration {T:g}: the velocities or accelerations "
           "overflow float64")
    return t, q, overflow_checked(qd, msg), overflow_checked(qdd, msg)


def _smoothstep_polyline(w, T, t, seg, total):
    dur = duration_shares(T, seg, total)
    bp = np.concatenate(([0.0], np.cumsum(dur)))
    bp[-1] = T
    inner = (bp[:-1, None] + dur[:, None] * np.array([0.25, 0.5, 0.75])).ravel()
    t = sorted_unique(np.concatenate((t, bp, inner)))
    j = np.clip(np.searchsorted(bp, t, side="right") - 1, 0, len(dur) - 1)
    live = dur[j] > 0
    T_j = np.where(live, dur[j], 1.0)
    u = np.clip((t - bp[j]) / T_j, 0.0, 1.0)
    d = w[j + 1] - w[j]
    s, sd, sdd = (f(u)[:, None] for f in _SMOOTHSTEP)
    q = w[j] + np.where(live[:, None], s, 1.0) * d
    qd = np.where(live[:, None], sd * d / T_j[:, None], 0.0)
    qdd = np.where(live[:, None], sdd * d / T_j[:, None] ** 2, 0.0)
    q[-1] = w[-1]
    return t, q, qd, qdd
