"""Case study: the workspace of a 2-link arm and a motion through every IK solution.

Seed 004 (a 2-DOF arm project) states the workspace annulus
``|L1 - L2| <= r <= L1 + L2``, the analytic IK (:func:`rapp.ik.ik_2link`
here), and a motion that visits every solution of a list of targets,
skipping unreachable ones.

Naming. rapp calls ``q2 > 0`` *elbow-down*: the elbow lies clockwise of the
base-to-target line (below it for a target on the +x axis). Seed 004 calls
``q2 = +arccos`` "elbow-up"; with its own shoulder formula that label is
swapped (the check is in ``tests/cases/test_two_dof_workspace.py``: FK of
``q2 > 0`` puts the elbow below the line).

Everything here is vectorized over targets; no loop runs over targets.

References
----------
Seed 004, the 2-DOF arm project (workspace, analytic IK, motion through solutions).
"""

from __future__ import annotations

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.ik import ik_2link
from rapp.paths import unwrap_path
from rapp.trajectory import cubic_local, polyval

__all__ = [
    "workspace_radii",
    "reachable",
    "interpolate_joints",
    "motion_through_solutions",
]


def _arm(lengths) -> Arm:
    arm = lengths if isinstance(lengths, Arm) else Arm(lengths)
    if arm.n != 2:
        raise ValueError(f"need two link lengths, got {arm.n}")
    return arm


def workspace_radii(lengths) -> tuple[float, float]:
    """Inner and outer circle of the 2-link workspace: ``(|L1 - L2|, L1 + L2)`` (``Arm.reach``).

    Examples
    --------
    >>> workspace_radii([2.0, 1.5])
    (0.5, 3.5)
    """
    return _arm(lengths).reach


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
    # The rest-to-rest cubic on normalized time: s(u) = 3 u^2 - 2 u^3.
    s = polyval(cubic_local(1.0, 0.0, 1.0, 0.0, 0.0), np.linspace(0.0, 1.0, steps))
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
    arm = _arm(lengths)
    targets = np.asarray(targets, dtype=float).reshape(-1, 2)
    flags = reachable(arm, targets)
    sols = ik_2link(arm, targets[flags], tol=1e-12 * arm.reach[1]).reshape(-1, 2)
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
    way = unwrap_path(arm, way)
    legs = interpolate_joints(way[:-1], way[1:], steps, wrap=False)  # (w-1, steps, 2)
    q = np.vstack((legs[:, :-1, :].reshape(-1, 2), way[-1:]))
    return q, flags
