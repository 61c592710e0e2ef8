"""A timed motion ``q(t)`` certified free over its whole time span, between samples too.

A motion is a :class:`~rapp.trajectory.PiecewisePolynomial`: on each piece every joint is a
polynomial of time. :func:`certify_motion` proves that every configuration the arm passes
through keeps every link more than ``margin`` from every obstacle (and every limited joint
within its limits, and, for an arm with ``self_collision``, every non-adjacent pair of links
apart: :func:`rapp.collision.self_gaps`, bounded over a sub-interval by
:func:`rapp.collision.pair_bounds`), not only at samples.

The bound. Take a sub-interval ``[m - r, m + r]`` of one piece and write each joint in powers
of ``s = t - m``: ``q_i(m + s) = sum_k d_ik s^k``. Then for ``|s| <= r``

``|q_i(m + s) - q_i(m)| <= D_i = sum_{k >= 1} |d_ik| r^k``.

A point of link ``j`` moves, along the straight joint-space segment from ``q(m)`` to ``q(t)``,
at most ``sum_{i <= j} R_ij |q_i(t) - q_i(m)|`` (:func:`rapp.collision.motion_bounds`: turning
joint ``i`` moves a point of link ``j`` no farther than its distance ``R_ij`` from joint ``i``,
times the angle). Positions depend on the configuration only, so every point of link ``j`` at
time ``t`` lies within ``B_j = sum_i R_ij D_i`` of where it is at ``m``, and the distance to an
obstacle changes by no more than that. The sub-interval is free by ``margin`` when
``clearance_j(q(m)) - B_j > margin`` for every link ``j``; likewise a limited joint stays within
its limits when ``q_i(m) +- D_i`` does. Sub-intervals not certified are bisected (``D`` shrinks
with ``r``); a midpoint that breaks the margin or a limit, or a sub-interval shorter than
``min_interval`` times its piece still uncertified (grazing), leaves its piece uncertified.

The same bisection, continued where the bound is loose, measures the motion's smallest
clearance: the smallest clearance at the times it evaluated (an upper bound on the true
minimum) and a proven lower bound within ``rtol`` of it.

Examples
--------
>>> from rapp import Arm, Circle
>>> from rapp.time_scaling import time_path
>>> arm = Arm([1.0, 1.0])
>>> motion = time_path([[0.0, 0.0], [1.0, 0.5], [1.5, 0.0]], 2.0, "spline")
>>> c = certify_motion(arm, motion, [Circle((-1.0, 1.0), 0.3)], rtol=1e-3)
>>> c.free, round(c.clearance, 3), round(c.lower, 3)
(True, 0.768, 0.768)
>>> certify_motion(arm, motion, [Circle((-1.0, 1.0), 0.3)], margin=0.8).free
False
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np

from rapp.collision import link_clearances, pair_bounds, reach_matrix, self_gaps

__all__ = ["MotionCertificate", "certify_motion", "MAX_MOTION_INTERVALS"]

#: Most sub-intervals :func:`certify_motion` keeps pending at once; a motion needing more is
#: left uncertified where it needs them (conservative), never a run of minutes.
MAX_MOTION_INTERVALS = 1 << 16
#: Most bisection levels (a sub-interval 2**-60 of its piece is below any ``min_interval``).
_MAX_LEVELS = 60


@dataclass(frozen=True)
class MotionCertificate:
    """The outcome of :func:`certify_motion`.

    Attributes
    ----------
    free : bool
        Every configuration of the motion keeps every link more than ``margin`` from every
        obstacle (proved), and every limited joint within its limits (to ``limit_tol``).
    pieces : ndarray of bool (k,)
        Which pieces were certified.
    clearance : float
        The smallest link-obstacle distance at the times evaluated (``inf`` without
        obstacles): the motion comes at least this close.
    lower : float
        A proven lower bound on the motion's clearance over the pieces certified; within
        ``rtol`` of ``clearance`` when the motion is free and ``rtol`` was given.
    within_limits : bool
        No sub-interval was found beyond a joint limit or left unproved against one; a proof
        over the whole motion when ``free`` (a piece left for an obstacle is not examined
        further).
    intervals : int
        How many sub-intervals were evaluated (the work done).
    """

    free: bool
    pieces: np.ndarray
    clearance: float
    lower: float
    within_limits: bool
    intervals: int


def _taylor(local, piece, tau):
    """Coefficients ``d[:, k, :]`` of the pieces ``local[piece]`` in powers of ``t - tau``."""
    c = local[piece]                                   # (I, deg + 1, n)
    deg = c.shape[1] - 1
    tau = tau[:, None]
    out = np.empty_like(c)
    size = np.zeros((c.shape[0], c.shape[2]))          # sum_j |c_j| |tau|^j: the rounding scale
    p = np.ones_like(tau)
    for j in range(deg + 1):
        size += np.abs(c[:, j]) * p
        p = p * np.abs(tau)
    for k in range(deg + 1):
        acc = np.zeros((c.shape[0], c.shape[2]))
        for j in range(deg, k - 1, -1):                # Horner in tau, weights C(j, k)
            acc = acc * tau + comb(j, k) * c[:, j]
        out[:, k] = acc
    return out, size


def _give_up(ok, piece, proven) -> None:
    """Stop refining: a sub-interval already proved clear (only not yet measured tightly) keeps
    its piece certified; any other leaves its piece uncertified."""
    ok[np.unique(piece[np.isnan(proven)])] = False


def certify_motion(arm, motion, obstacles=(), *, margin: float = 0.0, limit_tol: float = 1e-9,
                   min_interval: float = 1e-12, rtol: float | None = None,
                   max_intervals: int = MAX_MOTION_INTERVALS) -> MotionCertificate:
    """Prove a polynomial motion free over its whole time span (see the module's bound).

    Parameters
    ----------
    arm : Arm
    motion : PiecewisePolynomial
        ``q(t)``, one coordinate per joint (unwrapped angles, as a plan's).
    obstacles : iterable of Circle and Polygon
    margin : float
        The clearance required (m): every link stays more than ``margin`` from every obstacle.
    limit_tol : float
        How far (rad) a limited joint may pass its limit (rounding), as the verification's.
    min_interval : float
        Shortest sub-interval examined, relative to its piece's duration, before giving up on
        that piece (the arm grazes an obstacle or a limit).
    rtol : float, optional
        Also bisect until the proven lower bound on the clearance is within ``rtol`` (relative)
        of the smallest clearance found, so that ``clearance`` measures the motion's minimum.
    max_intervals : int
        Most sub-intervals pending at once (:data:`MAX_MOTION_INTERVALS`).

    Returns
    -------
    MotionCertificate

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> from rapp.time_scaling import time_path
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((1.0, 1.0), 0.25)]
    >>> # The chord from (0, 0) to (pi/2, 0) passes through the disc: so does the motion.
    >>> certify_motion(arm, time_path([[0.0, 0.0], [np.pi / 2, 0.0]], 1.0), obs).free
    False
    >>> c = certify_motion(arm, time_path([[0.0, 0.0], [-1.0, 0.0]], 1.0), obs, rtol=1e-3)
    >>> c.free, bool(c.lower >= c.clearance * (1 - 1e-3))
    (True, True)
    """
    local = np.asarray(motion.local, float)
    bp = np.asarray(motion.breakpoints, float)
    n = arm.n
    if local.shape[2] != n:
        raise ValueError(f"motion must have one coordinate per joint ({n}), got {local.shape[2]}")
    margin = float(margin)
    if not np.isfinite(margin) or margin < 0:
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    obstacles = list(obstacles)
    pairs = bool(getattr(arm, "self_collision", False)) and n >= 3
    reach = reach_matrix(arm)
    lo_lim, hi_lim, limited = arm.lower, arm.upper, arm.limited
    touch = 16 * np.finfo(float).eps * float(np.sum(arm.lengths))
    eps = 8 * np.finfo(float).eps * local.shape[1]
    pieces = len(bp) - 1
    h = np.diff(bp)
    ok = np.ones(pieces, bool)
    limits_ok = True
    best = np.inf          # smallest clearance at an evaluated time
    lower = np.inf         # proven lower bound over the certified sub-intervals
    # Pending sub-intervals: piece, start, length (local time).
    piece = np.arange(pieces)
    start = np.zeros(pieces)
    length = h.copy()
    # The clearance already proved over each pending sub-interval (by its parent), or nan.
    proven = np.full(pieces, np.nan)
    evaluated = 0
    for _ in range(_MAX_LEVELS):
        keep = ok[piece]
        piece, start, length, proven = piece[keep], start[keep], length[keep], proven[keep]
        if piece.size == 0:
            break
        if piece.size > max_intervals:
            _give_up(ok, piece, proven)
            lower = min(lower, float(np.nanmin(proven, initial=np.inf)))
            break
        evaluated += piece.size
        r = 0.5 * length
        d, size = _taylor(local, piece, start + r)
        qm = d[:, 0]
        D = eps * size
        rk = np.ones_like(r)[:, None]
        for k in range(1, d.shape[1]):
            rk = rk * r[:, None]
            D += np.abs(d[:, k]) * rk
        # Limits: the midpoint within them, and the whole sub-interval.
        if limited.any():
            bad_mid = (limited & ((qm < lo_lim - limit_tol) | (qm > hi_lim + limit_tol))).any(axis=1)
            lim_done = ~(limited & ((qm - D < lo_lim - limit_tol)
                                    | (qm + D > hi_lim + limit_tol))).any(axis=1)
        else:
            bad_mid = np.zeros(piece.size, bool)
            lim_done = np.ones(piece.size, bool)
        if bad_mid.any():
            limits_ok = False
        if obstacles:
            clear = link_clearances(arm, qm, obstacles)            # (I, n)
            slack = clear - D @ reach                              # proven over the sub-interval
            best = min(best, float(clear.min()))
            hit = (clear <= margin + touch).any(axis=1)
            low = slack.min(axis=1)
            col_done = low > margin + touch
        else:
            hit = np.zeros(piece.size, bool)
            low = np.full(piece.size, np.inf)
            col_done = np.ones(piece.size, bool)
        if pairs:
            # Links that must not cross (arm.self_collision): each non-adjacent pair's gap at
            # the midpoint, less the most it changes over the sub-interval (pair_bounds).
            gaps = self_gaps(arm, qm, margin=margin)               # (I, P)
            hit = hit | (gaps <= touch).any(axis=1)
            col_done = col_done & (gaps - pair_bounds(arm, D) > touch).all(axis=1)
        ok[piece[hit | bad_mid]] = False
        done = col_done & lim_done & ~hit & ~bad_mid
        if rtol is not None and obstacles:
            # Loose bounds near the minimum are refined until they measure it.
            done &= low >= best * (1.0 - rtol) - touch
        if done.any():
            lower = min(lower, float(low[done].min()))
        fail = ~done & (length <= min_interval * h[piece])
        if fail.any():
            grazing = fail & col_done & lim_done & ~hit & ~bad_mid
            # Certified but not yet tight (rtol): keep its proven bound, stop refining it.
            if grazing.any():
                lower = min(lower, float(low[grazing].min()))
            ok[piece[fail & ~grazing]] = False
            if (fail & ~grazing & ~lim_done).any():
                limits_ok = False
        more = ~done & ~fail
        certified = col_done & lim_done & ~hit & ~bad_mid
        proven = np.repeat(np.where(certified, low, np.nan)[more], 2)
        piece = np.repeat(piece[more], 2)
        half = r[more]
        start = np.stack((start[more], start[more] + half), axis=1).ravel()
        length = np.repeat(half, 2)
    else:
        keep = ok[piece]
        _give_up(ok, piece[keep], proven[keep])
        lower = min(lower, float(np.nanmin(proven[keep], initial=np.inf)))
    free = bool(ok.all())
    return MotionCertificate(free, ok, best, lower if free else min(lower, best), limits_ok,
                             evaluated)
