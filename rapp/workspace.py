"""Workspace of the 2-link arm and a motion through every IK solution (seed 004).

Seed 004 states the workspace annulus ``|L1 - L2| <= r <= L1 + L2``, the
analytic IK ``cos q2 = (x^2 + y^2 - L1^2 - L2^2) / (2 L1 L2)``,
``q1 = atan2(y, x) - atan2(L2 sin q2, L1 + L2 cos q2)``, and a motion that
visits every solution of a list of targets, skipping unreachable ones.

Naming. rapp (like seed 002 and :func:`rapp.ik.ik_2link`) calls ``q2 > 0``
*elbow-down*: the elbow lies clockwise of the base-to-target line (below it
for a target on the +x axis). Seed 004 calls ``q2 = +arccos`` "elbow-up";
with its own shoulder formula that label is swapped (the check is in
``tests/test_seed004.py``: FK of ``q2 > 0`` puts the elbow below the line).

Everything here is vectorized over targets; no loop runs over targets.
"""

from __future__ import annotations

import numpy as np

from rapp.arm import wrap_angle

__all__ = [
    "workspace_radii",
    "reachable",
    "elbow_solutions",
    "interpolate_joints",
    "motion_through_solutions",
]


def _lengths(lengths):
    lengths = np.asarray(getattr(lengths, "lengths", lengths), dtype=float)
    if lengths.shape != (2,) or not np.all(np.isfinite(lengths)) or np.any(lengths <= 0):
        raise ValueError(f"need two finite positive link lengths, got {lengths.tolist()}")
    return lengths


def workspace_radii(lengths) -> tuple[float, float]:
    """Inner and outer circle of the 2-link workspace: ``(|L1 - L2|, L1 + L2)``.

    Examples
    --------
    >>> workspace_radii([2.0, 1.5])
    (0.5, 3.5)
    """
    l1, l2 = _lengths(lengths)
    return (float(abs(l1 - l2)), float(l1 + l2))


def reachable(lengths, targets, *, tol: float = 1e-12) -> np.ndarray:
    """True where a target ``(..., 2)`` lies in the closed annulus (seed 004's test).

    ``tol`` is relative to ``L1 + L2`` and absorbs rounding on the circles.

    Examples
    --------
    >>> reachable([2.0, 1.5], [[1.0, 0.0], [0.2, 0.0], [4.0, 0.0], [3.5, 0.0]]).tolist()
    [True, False, False, True]
    """
    r_in, r_out = workspace_radii(lengths)
    r = np.linalg.norm(np.asarray(targets, dtype=float), axis=-1)
    eps = tol * r_out
    return (r >= r_in - eps) & (r <= r_out + eps)


def elbow_solutions(lengths, targets) -> np.ndarray:
    """Both analytic solutions of every target, shape ``(..., 2, 2)``.

    Index ``[..., 0, :]`` is elbow-down (``q2 >= 0``), ``[..., 1, :]``
    elbow-up (``q2 <= 0``); on a boundary circle the two coincide (one
    distinct solution); unreachable targets give ``nan``. ``cos q2`` is
    clipped to ``[-1, 1]`` only inside the rounding tolerance of
    :func:`reachable`.

    Examples
    --------
    >>> elbow_solutions([1.0, 1.0], [1.0, 1.0]).round(6).tolist()
    [[0.0, 1.570796], [1.570796, -1.570796]]
    """
    l1, l2 = _lengths(lengths)
    p = np.asarray(targets, dtype=float)
    x, y = p[..., 0], p[..., 1]
    ok = reachable((l1, l2), p)
    c2 = np.clip((x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0)
    q2 = np.stack((np.arccos(c2), -np.arccos(c2)), axis=-1)
    q1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    q = np.stack((wrap_angle(q1), q2), axis=-1)
    return np.where(ok[..., None, None], q, np.nan)


def interpolate_joints(q0, q1, steps: int, *, wrap: bool = True) -> np.ndarray:
    """Rest-to-rest cubic joint-space motion from ``q0`` to ``q1``, shape ``(..., steps, n)``.

    Each joint follows ``q0 + (3 u^2 - 2 u^3) dq``, ``u`` in ``[0, 1]``, with
    ``dq`` the wrapped (shortest) difference, so a free joint never turns the
    long way round (``wrap=False``: the plain difference, for angles the
    caller has already unwrapped). Both end points are included; the last equals ``q1`` up to
    a multiple of ``2 pi``.

    Examples
    --------
    >>> interpolate_joints([0.0, 0.0], [1.0, -1.0], 3).tolist()
    [[0.0, 0.0], [0.5, -0.5], [1.0, -1.0]]
    """
    if steps < 2:
        raise ValueError(f"steps must be >= 2, got {steps}")
    q0 = np.asarray(q0, dtype=float)
    dq = np.asarray(q1, dtype=float) - q0
    if wrap:
        dq = wrap_angle(dq)
    u = np.linspace(0.0, 1.0, steps)
    s = 3 * u**2 - 2 * u**3
    return q0[..., None, :] + s[:, None] * dq[..., None, :]


def motion_through_solutions(lengths, targets, *, steps: int = 30, q_start=None):
    """Joint motion that visits every IK solution of every reachable target, in order.

    For each reachable target its distinct solutions are visited, elbow-down
    first; unreachable targets are skipped and flagged. Consecutive
    configurations are joined by :func:`interpolate_joints` (joint space, as
    seed 004 plans). The motion starts at ``q_start`` (default: the first
    solution).

    Parameters
    ----------
    lengths : (L1, L2) or Arm
    targets : array_like, shape (m, 2)
    steps : int
        Samples per leg between two consecutive configurations, ends included.
    q_start : (2,) array_like, optional

    Returns
    -------
    q : ndarray, shape (k, 2)
        The joint trajectory (legs joined without repeating their shared ends).
    reachable_flags : ndarray of bool, shape (m,)
        False for each skipped target.

    Examples
    --------
    >>> q, ok = motion_through_solutions([1.0, 1.0], [[1.0, 1.0], [5.0, 0.0]], steps=3)
    >>> ok.tolist(), q.shape
    ([True, False], (3, 2))
    """
    targets = np.asarray(targets, dtype=float).reshape(-1, 2)
    flags = reachable(lengths, targets)
    sols = elbow_solutions(lengths, targets[flags]).reshape(-1, 2)
    # On a boundary circle both rows coincide: keep one.
    distinct = np.ones(len(sols), dtype=bool)
    distinct[1::2] = np.any(np.abs(wrap_angle(sols[1::2] - sols[0::2])) > 1e-12, axis=-1)
    way = sols[distinct]
    if q_start is not None:
        way = np.vstack((np.asarray(q_start, dtype=float).reshape(1, 2), way))
    if len(way) == 0:
        return np.empty((0, 2)), flags
    if len(way) == 1:
        return way.copy(), flags
    # Unwrap the waypoints so each leg takes the short way and the motion is continuous.
    way = way[0] + np.concatenate(([[0.0, 0.0]], np.cumsum(wrap_angle(np.diff(way, axis=0)), axis=0)))
    legs = interpolate_joints(way[:-1], way[1:], steps, wrap=False)  # (w-1, steps, 2)
    q = np.vstack((legs[:, :-1, :].reshape(-1, 2), way[-1:]))
    return q, flags
