"""Inverse kinematics of the planar arm (MIS ``solveIK``; seeds 002, 003, 004).

The tools, from exact to general:

* :func:`ik_2link` -- the analytic solution of a 2-link arm by the law of
  cosines: every solution (0, 1 or 2 of them), joint limits applied.
* :func:`ik_numeric` -- Newton-Raphson on ``f(q) = target`` for an N-link
  arm over a whole batch of targets at once, with damped least squares (DLS)
  near singular configurations, seeded random restarts and joint limits,
  from the exact start of :func:`closed_form_start` where there is one; on
  large batches compiled per target (:mod:`rapp.kernels.ik_numba`).
* :func:`ik` -- the contract: every distinct solution for ONE target (for
  three or more links a seeded sample of the self-motion manifold, and the
  exact collinear arm on a boundary circle).
* :func:`free_ik_solutions` -- the goal configurations of a Cartesian goal:
  the manifold searched densely for solutions clear of the obstacles.

:func:`jacobian` gives the 2 x n Jacobian ``J = df/dq`` used by the
Newton-Raphson step of the MIS::

    q_{k+1} = q_k + J^T (J J^T + lambda^2 I)^{-1} (target - f(q_k))

which is the plain Newton (minimum-norm) step when ``lambda = 0``. Because
``J J^T`` is only 2 x 2, the step is solved in closed form for every target
of the batch at the same time.

Elbow naming of the 2-link arm. Seen from the base looking at the target,
``q2 > 0`` puts the elbow on the clockwise side of the base-target line:
with the target on the +x axis the elbow is *below* it. We call ``q2 >= 0``
**elbow-down** and ``q2 <= 0`` **elbow-up**, as seed 002 does (its
``Q2,down = +acos(.)``); seed 004 labels ``+acos`` "elbow-up", the opposite
name for the same configuration.
"""

from __future__ import annotations

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.kernels import ik as ik_backend
from rapp.arm import Arm, wrap_angle
from rapp.collision import clearance, collides
from rapp.errors import NoIKSolution, NoPathFound

__all__ = ["ik", "ik_2link", "ik_numeric", "jacobian", "free_ik_solutions", "fk_and_jacobian", "iterate_ik",
           "dls_step", "damped_step", "ik_failure", "closed_form_start"]

TWO_PI = 2.0 * np.pi


def _as_arm(arm_or_lengths) -> Arm:
    return arm_or_lengths if isinstance(arm_or_lengths, Arm) else Arm(arm_or_lengths)


def _target(target) -> np.ndarray:
    target = np.asarray(target, dtype=float)
    if target.shape != (2,) or not np.all(np.isfinite(target)):
        raise ValueError(f"target must be a finite point (x, y), got {target.tolist()}")
    return target


def jacobian(arm: Arm, q: ArrayLike) -> np.ndarray:
    """Jacobian ``d(x, y)/dq`` of the end effector, shape ``(..., 2, n)``.

    With ``phi_i = q_1 + ... + q_i`` the absolute link angles, column ``j`` is
    ``(-sum_{i>=j} L_i sin phi_i, sum_{i>=j} L_i cos phi_i)``: joint ``j``
    swings everything beyond it.

    Examples
    --------
    >>> jacobian(Arm([1.0, 1.0]), [0.0, 0.0]).tolist()
    [[-0.0, -0.0], [2.0, 1.0]]
    >>> jacobian(Arm([1.0, 0.8, 0.5]), np.zeros((4, 3))).shape
    (4, 2, 3)
    """
    phi = arm.absolute_angles(q)
    lengths = arm.lengths
    sx = np.flip(np.cumsum(np.flip(lengths * np.sin(phi), -1), -1), -1)
    cy = np.flip(np.cumsum(np.flip(lengths * np.cos(phi), -1), -1), -1)
    return np.stack((-sx, cy), axis=-2)


# --------------------------------------------------------------------------- 2-link


def _equivalents_within(arm: Arm, q: np.ndarray, tol: float) -> np.ndarray:
    """Every joint-space configuration equal to ``q`` (k, n) modulo 2 pi per
    limited joint that lies inside the limits; free joints wrapped.

    A limited joint is a real interval, so ``q`` and ``q + 2 pi`` are different
    configurations there; both are returned when both fit (limits wider than
    2 pi). Loops run over solutions and joints, never over a batch.
    """
    out = []
    for row in q:
        choices = []
        for j, lim in enumerate(arm.joint_limits):
            if lim is None:
                choices.append(np.array([wrap_angle(row[j])]))
                continue
            lo, hi = lim
            k_lo = int(np.ceil((lo - tol - row[j]) / TWO_PI))
            k_hi = int(np.floor((hi + tol - row[j]) / TWO_PI))
            vals = row[j] + TWO_PI * np.arange(k_lo, k_hi + 1)
            choices.append(np.clip(vals, lo, hi))
        if all(c.size for c in choices):
            grids = np.meshgrid(*choices, indexing="ij")
            out.append(np.stack([g.ravel() for g in grids], axis=-1))
    if not out:
        return np.zeros((0, arm.n))
    return np.concatenate(out, axis=0)


def ik_2link(arm_or_lengths: Arm | ArrayLike, targets: ArrayLike, *,
            tol: float = 1e-10) -> np.ndarray:
    """Both analytic solutions of a 2-link arm for a batch of targets, shape ``(..., 2, 2)``.

    Law of cosines: ``|target|^2 = L1^2 + L2^2 + 2 L1 L2 cos q2``, then
    ``q1 = atan2(y, x) - atan2(L2 sin q2, L1 + L2 cos q2)``. ``sin q2`` is
    computed from the factored form ``(L1+L2-r)(L1+L2+r)(r-|L1-L2|)(r+|L1-L2|)``
    so that it stays accurate next to the workspace boundary, where plain
    ``arccos`` loses half the digits. This is the one home of the 2-link IK;
    :func:`ik` applies joint limits to it, and the case studies call it.

    Parameters
    ----------
    arm_or_lengths : Arm or (L1, L2)
        Joint limits of an Arm are ignored here (see :func:`ik`).
    targets : array_like, shape (..., 2)
    tol : float
        A length. A target whose distance from the base is within ``tol`` of a
        boundary circle of the annulus ``|L1-L2| <= r <= L1+L2`` gets the
        boundary solution (straight arm ``q2 = 0`` or folded ``q2 = -pi``) in
        both rows, which places the tip within ``tol`` of it.

    Returns
    -------
    ndarray, shape (..., 2, 2)
        ``[..., 0, :]`` elbow-down (``q2 >= 0``), ``[..., 1, :]`` elbow-up
        (``q2 <= 0``), see the module notes for the names; angles wrapped to
        ``[-pi, pi)``; ``nan`` where the target is out of reach. With
        ``L1 == L2`` and the target at the base every ``q1`` works; one
        representative is returned.

    Examples
    --------
    >>> ik_2link([1.0, 1.0], [1.0, 1.0]).round(6).tolist()
    [[0.0, 1.570796], [1.570796, -1.570796]]
    >>> ik_2link([1.0, 1.0], [[2.0, 0.0], [3.0, 0.0]]).tolist()
    [[[0.0, 0.0], [0.0, 0.0]], [[nan, nan], [nan, nan]]]
    """
    arm = _as_arm(arm_or_lengths)
    if arm.n != 2:
        raise ValueError(f"ik_2link needs a 2-link arm, got {arm.n} links")
    p = np.asarray(targets, dtype=float)
    if p.ndim == 0 or p.shape[-1] != 2:
        raise ValueError(f"targets must have shape (..., 2), got {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError("targets must be finite points (x, y)")
    x, y = p[..., 0], p[..., 1]
    l1, l2 = arm.link_lengths
    r = np.hypot(x, y)
    r_out, r_in = l1 + l2, abs(l1 - l2)
    reach = (r <= r_out + tol) & (r >= r_in - tol)
    outer, inner = np.abs(r - r_out) <= tol, np.abs(r - r_in) <= tol
    # Factored forms of 1 -+ cos q2 keep sin q2 accurate near both circles.
    one_minus = np.maximum(0.0, (r_out - r) * (r_out + r)) / (2 * l1 * l2)
    one_plus = np.maximum(0.0, (r - r_in) * (r + r_in)) / (2 * l1 * l2)
    c2 = np.clip((r * r - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0)
    c2 = np.where(outer, 1.0, np.where(inner, -1.0, c2))
    edge = outer | inner
    s2 = np.where(edge, 0.0, np.sqrt(one_minus * one_plus))
    # (..., 2): elbow-down, elbow-up; on a circle both are +0.0, so the rows are identical.
    s2 = np.stack((s2, np.where(edge, 0.0, -s2)), axis=-1)
    c2 = c2[..., None]
    q2 = np.arctan2(s2, c2)
    q1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * s2, l1 + l2 * c2)
    q = wrap_angle(np.stack((q1, q2), axis=-1))
    return np.where(reach[..., None, None], q, np.nan)


# --------------------------------------------------------------------------- numeric


def _fk(lengths: np.ndarray, q: np.ndarray):
    """End effector ``(px, py)`` of joint-major configurations ``q`` (n, m)."""
    phi = np.zeros(q.shape[1:])
    px = np.zeros(q.shape[1:])
    py = np.zeros(q.shape[1:])
    for j, length in enumerate(lengths):
        phi = phi + q[j]
        px += length * np.cos(phi)
        py += length * np.sin(phi)
    return px, py


def fk_and_jacobian(lengths: np.ndarray, q: np.ndarray):
    """End effector and Jacobian rows ``jx, jy`` (n, m) of joint-major ``q`` (n, m).

    The cosines and sines of the absolute angles come from those of the
    (wrapped, small) joint angles by the angle-addition formulas: one trig
    call per function on the whole block, and small arguments take libm's
    fast path. Loops run over the few joints, rows are contiguous.
    """
    n = lengths.size
    cq = np.cos(q)
    sq = np.sin(q)
    jx = np.empty(q.shape)
    jy = np.empty(q.shape)
    c, s = cq[0], sq[0]
    jy[0] = lengths[0] * c
    jx[0] = lengths[0] * s
    for j in range(1, n):
        c, s = c * cq[j] - s * sq[j], s * cq[j] + c * sq[j]
        jy[j] = lengths[j] * c
        jx[j] = lengths[j] * s
    # Column j of J sums the links beyond joint j: reverse running sums.
    for j in range(n - 2, -1, -1):
        jy[j] += jy[j + 1]
        jx[j] += jx[j + 1]
    np.negative(jx, out=jx)
    return jy[0].copy(), -jx[0], jx, jy


def dls_step(jx, jy, ex, ey, sigma_floor, lambda_max):
    """Damped least-squares step for every column, through the SVD of the 2 x n ``J``.

    The damping is zero while the smallest singular value of ``J`` stays above
    ``sigma_floor`` (a plain Newton step, quadratic convergence) and grows
    smoothly to ``min(lambda_max, sqrt|error|)`` as ``J`` becomes singular
    (Nakamura-Hanafusa / Maciejewski-Klein rule), so the step stays bounded at
    a stretched or folded arm.

    The 2 x 2 ``J J^T`` is diagonalised in closed form (its eigenvectors
    ``v+-`` are one rotation) and the step is ``sum_k w_k (v_k . e) /
    (|w_k|^2 + lambda^2)`` with ``w_k = J^T v_k``. Taking ``sigma_k^2`` as
    ``|w_k|^2`` of the very vector it divides keeps every term at most
    ``|e| / (2 lambda)`` (or ``|e| / sigma_floor``) however singular ``J`` is;
    the textbook ``(J J^T + lambda^2 I)^{-1}`` divides by ``a c - b^2``, which
    cancels to round-off (even below zero) at a stretched arm and overflowed.
    """
    a = (jx * jx).sum(axis=0)
    b = (jx * jy).sum(axis=0)
    c = (jy * jy).sum(axis=0)
    # Eigenvector of the larger eigenvalue of [[a, b], [b, c]] at angle t.
    t = 0.5 * np.arctan2(2.0 * b, a - c)
    ct, st = np.cos(t), np.sin(t)
    w_big = jx * ct + jy * st
    w_small = jy * ct - jx * st
    sig2_min = (w_small * w_small).sum(axis=0)
    sig2_big = (w_big * w_big).sum(axis=0)
    # Capping lambda^2 by the residual |e| (Levenberg-Marquardt with the
    # exponent of Fan and Yuan) lets the damping vanish as the error does, so
    # a target whose solution is itself singular (a stretched or folded arm)
    # still converges fast. Not by |e|^2: at such a solution the term along
    # the vanishing singular value is up to |e| / (2 lambda), a fixed 1/2 rad
    # driven by round-off, whereas the bend that fixes a radial error e there
    # is of order sqrt(e), which is what lambda^2 = |e| allows.
    lam2 = (1.0 - np.minimum(sig2_min / sigma_floor**2, 1.0)) * np.minimum(
        lambda_max**2, np.sqrt(ex * ex + ey * ey))
    e_big = ex * ct + ey * st
    e_small = ey * ct - ex * st
    den_big = sig2_big + lam2
    den_small = sig2_min + lam2
    # A zero denominator means that term of J is zero and undamped (no error
    # left to cap lambda by): it contributes nothing.
    f_big = np.divide(e_big, den_big, out=np.zeros_like(den_big), where=den_big > 0)
    f_small = np.divide(e_small, den_small, out=np.zeros_like(den_small), where=den_small > 0)
    return w_big * f_big + w_small * f_small


def damped_step(J, e, sigma_floor: float, lambda_max: float) -> np.ndarray:
    """:func:`dls_step` for Jacobians ``J`` of shape ``(..., 2, n)`` and tip errors ``e`` of shape ``(..., 2)``.

    The step :func:`ik_numeric` takes, in the usual batch layout (``dls_step`` takes columns).

    Examples
    --------
    >>> J = jacobian(Arm([0.5, 0.5]), [0.3, 1.2])
    >>> e = np.array([1e-3, -2e-3])
    >>> bool(np.allclose(damped_step(J, e, 1e-3, 1e-2), np.linalg.solve(J, e)))   # regular J: Newton's step
    True
    """
    J, e = np.asarray(J, float), np.asarray(e, float)
    n = J.shape[-1]
    jx, jy = J[..., 0, :].reshape(-1, n).T, J[..., 1, :].reshape(-1, n).T
    step = dls_step(jx, jy, e[..., 0].ravel(), e[..., 1].ravel(), sigma_floor, lambda_max)
    return step.T.reshape(J.shape[:-2] + (n,))


#: The old name, still imported by the exercise test of chapter 6.
_dls_step = dls_step


def _boundary_start(lengths: np.ndarray, targets: np.ndarray, outer: bool,
                    sign: float = 1.0) -> np.ndarray:
    """Configurations (n, m) whose tips sit at ``targets`` (2, m) lying just inside the
    outer circle (``outer``) or just outside the inner one, to second order.

    On a boundary circle the arm is collinear: stretched (every link along
    the target direction) on the outer one, and on the inner one the longest
    link along it with all the others folded back, which gives
    ``2 max(L) - sum(L)``. Bending it by ``s`` times the absolute-angle pattern
    ``D`` (centred on the links that bend, so that the tip does not move
    sideways to first order) moves the tip radially by ``-K s^2 / 2`` with
    ``K = sum(sigma_i L_i D_i^2)`` (``sigma_i = +-1`` the link's orientation),
    so ``s = sqrt(2 (r_circle - r) / K)`` meets the target distance up to
    ``O(s^4)``; turning the first joint then faces the target. Newton-Raphson
    polishes it; from a generic start it creeps towards such targets, where
    ``J`` is nearly singular. ``sign`` picks the mirror-image bend.
    """
    n = lengths.size
    sigma = np.ones(n)
    if not outer:
        sigma = -sigma
        sigma[np.argmax(lengths)] = 1.0
    bends = sigma < 0 if not outer else np.ones(n, dtype=bool)
    k = np.arange(n, dtype=float)
    w = np.where(bends, lengths, 0.0)
    d_pattern = np.where(bends, k - (w @ k) / w.sum(), 0.0)
    curv = float((sigma * lengths * d_pattern**2).sum())
    rho = float((sigma * lengths).sum())
    r = np.hypot(targets[0], targets[1])
    # (rho - r) and curv have the same sign on the reachable side of either circle;
    # with fewer than two links to bend (curv == 0) no bend moves the tip radially.
    ratio = np.divide(2.0 * (rho - r), curv, out=np.zeros_like(r), where=curv != 0.0)
    s = sign * np.sqrt(np.maximum(ratio, 0.0))
    theta = np.arctan2(targets[1], targets[0])
    phi = theta + np.where(sigma < 0, np.pi, 0.0)[:, None] + d_pattern[:, None] * s
    q = np.diff(phi, axis=0, prepend=0.0)
    px, py = _fk(lengths, q)
    q[0] += theta - np.arctan2(py, px)
    return q


def _tail_distances(lengths: np.ndarray, r: np.ndarray):
    """Least and greatest wrist distance from the base reachable both by the first
    two links and by the rest held straight from a target at distance ``r``."""
    l1, l2, lt = float(lengths[0]), float(lengths[1]), float(lengths[2:].sum())
    return np.maximum(abs(l1 - l2), np.abs(r - lt)), np.minimum(l1 + l2, r + lt)


def closed_form_start(lengths: np.ndarray, targets: np.ndarray):
    """An exact start (n, m) for most targets (2, m): two links by the law of
    cosines, the links beyond the second held straight as one rigid link.

    That rigid tail of length ``L_t`` points from the wrist to the target at
    the angle ``alpha`` off the base-target line that puts the wrist at the
    distance ``d`` from the base: the middle of the distances both reachable
    by the first two links (``|L1 - L2| <= d <= L1 + L2``) and by the tail
    (``|r - L_t| <= d <= r + L_t``). The first two links then reach the
    wrist exactly (:func:`ik_2link`, elbow-down), so the tip is on the target
    up to round-off and Newton-Raphson has nothing left to do. Where the two
    ranges do not meet (close to the inner circle when a tail link is the
    longest, or beyond the outer one) there is no such start: ``exists`` is
    False there and those columns are zero.

    Returns
    -------
    q : ndarray, shape (n, m)
    exists : ndarray of bool, shape (m,)

    Examples
    --------
    >>> lengths = np.array([1.0, 0.8, 0.5])
    >>> q, exists = closed_form_start(lengths, np.array([[1.2, 3.0], [0.7, 0.0]]))
    >>> exists.tolist()
    [True, False]
    >>> bool(np.abs(Arm(lengths).end_effector(q[:, 0]) - [1.2, 0.7]).max() < 1e-15)
    True
    """
    n, m = lengths.size, targets.shape[1]
    q = np.zeros((n, m))
    if n == 1:
        q[0] = np.arctan2(targets[1], targets[0])
        return q, np.ones(m, dtype=bool)
    lt = float(lengths[2:].sum())
    r = np.hypot(targets[0], targets[1])
    lo_d, hi_d = _tail_distances(lengths, r)
    exists = lo_d <= hi_d
    d = 0.5 * (lo_d + hi_d)
    den = 2.0 * r * lt
    # The law of cosines in the triangle base-wrist-target; with no tail (or the
    # target at the base) any alpha does, and 0 is taken.
    cos_a = np.divide(r * r + lt * lt - d * d, den, out=np.ones_like(r), where=den > 0.0)
    phi = np.arctan2(targets[1], targets[0]) + np.arccos(np.clip(cos_a, -1.0, 1.0))
    wrist = targets - lt * np.stack((np.cos(phi), np.sin(phi)))
    q12 = ik_2link(lengths[:2], wrist[:, exists].T, tol=1e-12)[:, 0, :].T
    # A wrist a rounding error outside the annulus has no 2-link solution: no start there.
    found = ~np.isnan(q12[0])
    exists[exists] = found
    q[:2, exists] = q12[:, found]
    if n > 2:
        q[2, exists] = phi[exists] - q12[0, found] - q12[1, found]
    return q, exists


def _initial_guess(lengths: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """The default start (n, m): :func:`closed_form_start` where it exists, else
    :func:`_bent_start`."""
    q, exists = closed_form_start(lengths, targets)
    if not exists.all():
        q[:, ~exists] = _bent_start(lengths, targets[:, ~exists])
    return q


def _bent_start(lengths: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """A cheap start (n, m): every joint after the first bent by the same angle
    so that the tip distance matches ``|target|``, then turned to face it.

    The distance of the uniformly bent arm is tabulated on a grid of bend
    angles and inverted by interpolation on its decreasing prefix (no loop
    over targets). Within 1e-3 (of the total length) of a boundary circle the
    grid is too coarse and the analytic near-boundary start of
    :func:`_boundary_start` is used instead. It is only a start:
    Newton-Raphson does the solving.
    """
    n = lengths.size
    m = targets.shape[1]
    if n == 1:
        return np.arctan2(targets[1], targets[0])[None, :]
    beta = np.linspace(0.0, np.pi, 2049)
    qs = np.zeros((n, beta.size))
    qs[1:] = beta
    px, py = _fk(lengths, qs)
    dist = np.hypot(px, py)
    head = np.unwrap(np.arctan2(py, px))
    rising = np.flatnonzero(np.diff(dist) >= 0)
    stop = max(int(rising[0]) if rising.size else beta.size - 1, 1)
    r = np.hypot(targets[0], targets[1])
    b = np.interp(r, dist[: stop + 1][::-1], beta[: stop + 1][::-1])
    h = np.interp(b, beta[: stop + 1], head[: stop + 1])
    q = np.empty((n, m))
    q[0] = np.arctan2(targets[1], targets[0]) - h
    q[1:] = b
    total = float(lengths.sum())
    r_in = max(0.0, 2.0 * float(lengths.max()) - total)
    band = 1e-3 * total
    # Symmetric bands: a target a rounding error beyond a circle still gets the
    # collinear arm (s = 0), the best there is.
    near_out = np.abs(r - total) <= band
    if near_out.any():
        q[:, near_out] = _boundary_start(lengths, targets[:, near_out], outer=True)
    near_in = (np.abs(r - r_in) <= band) & ~near_out if r_in > 0 else np.zeros(m, bool)
    if near_in.any():
        q[:, near_in] = _boundary_start(lengths, targets[:, near_in], outer=False)
    return q


def _project(q: np.ndarray, limited: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Clip limited joints into their interval, wrap free joints to [-pi, pi).

    Wrapping inside the iteration means the configuration whose error is
    measured is exactly the one returned (no re-evaluation after a final wrap).
    """
    wrapped = (q + np.pi) % TWO_PI - np.pi
    # Just below -pi the sum rounds up to 2 pi and the result to +pi.
    wrapped[wrapped >= np.pi] = -np.pi
    if not limited.any():
        return wrapped
    lim = limited[:, None]
    return np.where(lim, np.clip(q, lo[:, None], hi[:, None]), wrapped)


def _newton(lengths, limited, lo, hi, targets, q, stop_tol, max_iter, max_step):
    """Iterate on the columns of ``q`` (n, m); a column stops once its error is
    at most ``stop_tol``. Only the unfinished columns are carried along.

    ``lengths`` and ``targets`` are those of the arm scaled to total length 1
    (see :func:`ik_numeric`), so the damping constants below are pure numbers.
    Returns the final ``q``.
    """
    sigma_floor = ik_backend.SIGMA_FLOOR
    lambda_max = ik_backend.LAMBDA_MAX
    any_limited = bool(limited.any())
    lim, lo_c, hi_c = limited[:, None], lo[:, None], hi[:, None]
    q = q.copy()
    idx = np.arange(q.shape[1])
    qa, ta = q, targets
    for _ in range(max_iter):
        px, py, jx, jy = fk_and_jacobian(lengths, qa)
        ex = ta[0] - px
        ey = ta[1] - py
        done = ex * ex + ey * ey <= stop_tol * stop_tol
        if done.any():
            q[:, idx[done]] = qa[:, done]
            keep = ~done
            if not keep.any():
                return q
            qa, ta, idx = qa[:, keep], ta[:, keep], idx[keep]
            jx, jy, ex, ey = jx[:, keep], jy[:, keep], ex[keep], ey[keep]
        dq = dls_step(jx, jy, ex, ey, sigma_floor, lambda_max)
        if any_limited:
            # Joint clamping: a limited joint the step would push out of its
            # interval is frozen (its Jacobian column zeroed) and the step is
            # recomputed, so the free joints make up for it instead of the
            # clip silently undoing part of the step.
            q_try = qa + dq
            blocked = lim & ((q_try < lo_c) | (q_try > hi_c))
            if blocked.any():
                jx = np.where(blocked, 0.0, jx)
                jy = np.where(blocked, 0.0, jy)
                dq = dls_step(jx, jy, ex, ey, sigma_floor, lambda_max)
        norm2 = (dq * dq).sum(axis=0)
        big = norm2 > max_step * max_step
        if big.any():
            dq[:, big] *= max_step / np.sqrt(norm2[big])
        qa = _project(qa + dq, limited, lo, hi)
    q[:, idx] = qa
    return q


def _tip_error(arm: Arm, q: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """``norm(arm.end_effector(q) - target)`` of rows ``q`` (m, n), ``targets`` (m, 2).

    This, not the error the iteration tracked, decides success: it is the
    very expression a caller checks, evaluated on the very ``q`` returned.
    """
    d = arm.end_effector(q) - targets
    # np.linalg.norm, not np.hypot: the two may differ in the last bit, and a
    # caller's check compares the norm with tol. Beyond the float range the
    # distance is inf, which compares as it should.
    with np.errstate(over="ignore"):
        return np.linalg.norm(d, axis=-1)


def _restart_starts(rng, limited, lo, hi, k: int) -> np.ndarray:
    """Seeded random starts (n, k) within the joint bounds for a restart.

    Each limited joint is put, with probability 1/2, exactly on one of its two
    limits: a solution that needs a joint on its limit is reached from there
    by the clamped steps, while from inside the interval the iterate often
    stalls against a limit on a branch that has no solution within them.
    """
    n = lo.size
    q = rng.uniform(lo[:, None], hi[:, None], size=(n, k))
    if limited.any():
        on_limit = limited[:, None] & (rng.random((n, k)) < 0.5)
        side = np.where(rng.random((n, k)) < 0.5, lo[:, None], hi[:, None])
        q = np.where(on_limit, side, q)
    return q


def _scaled(arm: Arm, rows: np.ndarray, tol: float):
    """The arm and targets (2, m) scaled to total length 1, the targets beyond the
    outer circle (``hopeless``), and the iteration's stopping error.

    Lengths up to MAX_COORDINATE and targets anywhere in the float range then give
    errors and Jacobian entries of order 1, whose squares cannot overflow.
    """
    scale = float(arm.lengths.sum())
    with np.errstate(over="ignore"):
        # Overflow to inf is the right answer in all three: a tolerance beyond
        # any distance, a target beyond any reach.
        tol_s = float(np.float64(tol) / scale)
        r = np.hypot(rows[:, 0], rows[:, 1])
        t = rows.T / scale
    # Beyond the outer circle no q makes the error 0, and the stretched arm
    # facing the target is the nearest the tip gets: skip the iterations and
    # take it (the guess, from the unit-size direction that keeps it finite);
    # the check at the end says whether it is within tol.
    hopeless = (r > scale * (1.0 + 1e-12)) | ~np.isfinite(t).all(axis=0)
    t = np.where(hopeless, rows.T / np.maximum(np.abs(rows).max(axis=1), np.finfo(float).tiny), t)
    # Stop a little below tol: one Newton step from there lands at round-off.
    return arm.lengths / scale, t, hopeless, min(tol_s, 1e-12)


def _numpy_attempts(arm: Arm, rows, q, tol, budget):
    """The attempts of :func:`ik_numeric` in numpy, the whole batch per step; ``q``
    (m, n) the caller's starts or None. Returns ``q`` (m, n) and ``ok`` (m,)."""
    max_iter, restarts, seed, max_step = budget
    lengths, t, hopeless, stop_tol = _scaled(arm, rows, tol)
    lo, hi, limited = arm.lower, arm.upper, arm.limited
    caller_starts = q is not None
    q = _project(q.T if caller_starts else _initial_guess(lengths, t), limited, lo, hi)
    todo = np.flatnonzero(~hopeless)
    err = np.full(t.shape[1], np.inf)
    rng = np.random.default_rng(seed)
    for attempt in range(restarts + 1):
        if todo.size == 0:
            break
        if attempt == 1 and caller_starts:
            # The caller's starts failed: try the default guess once (next to
            # a boundary circle, the only start that reliably converges).
            q[:, todo] = _project(_initial_guess(lengths, t[:, todo]), limited, lo, hi)
        elif attempt > 0:
            q[:, todo] = _restart_starts(rng, limited, lo, hi, todo.size)
        q[:, todo] = _newton(lengths, limited, lo, hi, t[:, todo], q[:, todo], stop_tol,
                             max_iter, max_step)
        err[todo] = _tip_error(arm, q[:, todo].T, rows[todo])
        todo = todo[~(err[todo] <= tol)]
    # The very check a caller makes, on the very q returned, for every target
    # (those never iterated included): ok cannot disagree with it.
    q = q.T
    return q, (_tip_error(arm, q, rows) <= tol) & arm.within_limits(q)


def _compiled_attempts(kernel, arm: Arm, rows, q, tol, budget):
    """The attempts of :func:`ik_numeric`, each target solved start to check by the
    compiled :mod:`rapp.kernels.ik_numba`; ``q`` (m, n) the caller's starts or None.

    The same starts, restarts (the same seeded generator, drawn for the same
    targets as long as the successes agree) and checks as :func:`_numpy_attempts`.
    Returns ``q`` (m, n) and ``ok`` (m,).
    """
    max_iter, restarts, seed, max_step = budget
    lo, hi, limited = arm.lower, arm.upper, arm.limited
    m, n = rows.shape[0], arm.n
    caller_starts = q is not None
    # The kernel builds the default start itself (numpy only where it has none).
    closed = ~np.isfinite(q).all(axis=1) if caller_starts else np.ones(m, dtype=bool)
    q = np.zeros((m, n)) if q is None else q
    hopeless = np.zeros(m, dtype=bool)
    with np.errstate(over="ignore"):
        stop_tol = min(float(np.float64(tol) / float(arm.lengths.sum())), 1e-12)

    def attempt(idx, starts_closed):
        sub_rows = rows if idx is None else rows[idx]
        sub = q if idx is None else np.ascontiguousarray(q[idx])
        far = np.empty(sub.shape[0], dtype=bool)
        status = kernel.solve(arm.lengths, limited, lo, hi, sub_rows, sub, starts_closed, far,
                              stop_tol, tol, max_iter, max_step)
        lost = np.flatnonzero(status == ik_backend.NO_START)
        if lost.size:
            lengths, t, _, _ = _scaled(arm, sub_rows[lost], tol)
            fix = np.ascontiguousarray(_initial_guess(lengths, t).T)
            status[lost] = kernel.solve(arm.lengths, limited, lo, hi, sub_rows[lost], fix,
                                        np.zeros(lost.size, dtype=bool),
                                        np.empty(lost.size, bool), stop_tol, tol, max_iter,
                                        max_step)
            sub[lost] = fix
        unsure = np.flatnonzero(status == ik_backend.UNSURE)
        if unsure.size:
            # Within rounding of tol: the caller's own check decides.
            status[unsure] = ((_tip_error(arm, sub[unsure], sub_rows[unsure]) <= tol)
                              & arm.within_limits(sub[unsure]))
        if idx is not None:
            q[idx] = sub
            hopeless[idx] = far
        else:
            hopeless[:] = far
        return status == ik_backend.OK

    ok = attempt(None, closed)
    todo = np.flatnonzero(~ok & ~hopeless)
    rng = np.random.default_rng(seed)
    for number in range(1, restarts + 1):
        if todo.size == 0:
            break
        q[todo] = 0.0
        if not (number == 1 and caller_starts):
            q[todo] = _restart_starts(rng, limited, lo, hi, todo.size).T
        # After the caller's starts, the default start once (closed form in the kernel).
        ok[todo] = attempt(todo, np.full(todo.size, number == 1 and caller_starts))
        todo = todo[~ok[todo]]
    return q, ok


def ik_numeric(
    arm: Arm,
    targets: ArrayLike,
    q0: ArrayLike | None = None,
    *,
    tol: float = 1e-10,
    max_iter: int = 30,
    restarts: int = 16,
    seed: int = 0,
    max_step: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Numerical IK for a batch of targets: Newton-Raphson with damped least squares.

    Every target is solved at the same time: each iteration is a handful of
    numpy calls over the whole batch (no loop over targets), and only the
    targets not yet converged are carried to the next iteration. With numba,
    a batch of at least ``rapp.kernels.ik.LOAD_FROM`` targets (any batch once
    numba is imported) is instead solved target by target by compiled loops
    that do the same (:mod:`rapp.kernels.ik_numba`): the same starts, steps,
    restarts and checks, equal up to the last bits of ``cos`` and ``sin``, so
    the same targets are solved (on a joint limit a restart may decide
    otherwise, never reporting a wrong ``ok``). The iteration runs on the arm
    scaled to total length 1, so neither a huge nor a tiny arm overflows or
    underflows, and no floating-point warning is raised for any finite input.

    Parameters
    ----------
    arm : Arm
    targets : array_like, shape (..., 2)
        Finite points.
    q0 : array_like, shape (..., n) or (n,), optional
        Starting configurations. By default :func:`closed_form_start`: the
        first two links by the law of cosines and the rest held straight, a
        solution up to round-off wherever it exists (so that Newton-Raphson
        has nothing left to do). Where it does not (next to the inner circle
        when a later link is the longest), a uniformly bent arm turned to
        face the target, and next to a boundary circle the analytic
        near-boundary configuration, where Newton-Raphson from elsewhere
        creeps.
    tol : float
        Position tolerance (in length units) for success.
    max_iter : int
        Iterations per attempt. From a start in the right basin Newton
        converges in far fewer; more restarts find more than longer attempts.
    restarts : int
        Further attempts for the targets that have not converged: with ``q0``
        given, the first from the default guess; the others from seeded random
        configurations within the joint bounds, with some limited joints
        exactly on a limit, where a solution that sits on the limit is found
        most easily.
    seed : int
        Seed of the restart generator; the result is deterministic.
    max_step : float
        Largest joint step (radians, 2-norm) per iteration, so that a far
        start cannot overshoot wildly.

    Returns
    -------
    q : ndarray, shape (..., n)
        Joint angles; free joints wrapped to ``[-pi, pi)``, limited joints
        inside their limits. Where ``ok`` is False this is the last iterate,
        not a solution.
    ok : ndarray of bool, shape (...)
        Exactly ``np.linalg.norm(arm.end_effector(q) - targets, axis=-1) <=
        tol`` and ``arm.within_limits(q)``, evaluated on the returned ``q``:
        for any ``tol`` a caller recomputing that expression gets this
        array. A target out of reach, or one the attempts did not solve
        (``tol`` below the round-off of the forward kinematics included), is
        False: never a wrong ``q`` reported as found. Beyond the outer circle
        ``q`` is the stretched arm facing the target, the nearest the tip
        gets (ok where that is within ``tol``).

    Raises
    ------
    ValueError
        ``targets`` of the wrong shape or not finite; ``q0`` of the wrong shape.

    Examples
    --------
    >>> arm = Arm([1.0, 0.8, 0.5])
    >>> q, ok = ik_numeric(arm, [[1.2, 0.7], [0.3, -1.1], [5.0, 0.0]])
    >>> ok.tolist()
    [True, True, False]
    >>> bool(np.abs(arm.end_effector(q[:2]) - [[1.2, 0.7], [0.3, -1.1]]).max() < 1e-12)
    True

    A solution on a joint limit (the wrist at exactly 0.5 rad):

    >>> wrist = Arm([1.0, 0.8, 0.5], [None, None, (0.5, 2.0)])
    >>> target = wrist.end_effector([0.3, -1.2, 0.5])
    >>> q, ok = ik_numeric(wrist, [target, [2.3, 0.0]], tol=1e-12)
    >>> ok.tolist(), bool(q[0, 2] >= 0.5)
    ([True, False], True)
    """
    targets = np.asarray(targets, dtype=float)
    if targets.ndim == 0 or targets.shape[-1] != 2:
        raise ValueError(f"targets must have shape (..., 2), got {targets.shape}")
    if not np.isfinite(targets).all():
        raise ValueError("targets must be finite points (x, y)")
    batch = targets.shape[:-1]
    n = arm.n
    rows = np.ascontiguousarray(targets.reshape(-1, 2))
    q = None
    if q0 is not None:
        q0 = np.asarray(q0, dtype=float)
        if q0.shape[-1] != n:
            raise ValueError(f"q0 must have shape (..., {n}), got {q0.shape}")
        q = np.broadcast_to(q0, batch + (n,)).reshape(-1, n).copy()
    budget = (max_iter, restarts, seed, max_step)
    kernel = ik_backend.loaded(rows.shape[0])
    if kernel is None:
        if q is not None:
            # A non-finite start is no start: use the default guess there.
            bad = ~np.isfinite(q).all(axis=1)
            if bad.any():
                lengths, t, _, _ = _scaled(arm, rows[bad], tol)
                q[bad] = _initial_guess(lengths, t).T
        q, ok = _numpy_attempts(arm, rows, q, tol, budget)
    else:
        q, ok = _compiled_attempts(kernel, arm, rows, q, tol, budget)
    return q.reshape(batch + (n,)), ok.reshape(batch)


# --------------------------------------------------------------------------- contract


def _dedupe(arm: Arm, q: np.ndarray, eps: float) -> np.ndarray:
    """Keep each row that has no earlier row within ``eps`` (wrap-aware).

    Kept rows are pairwise more than ``eps`` apart; every dropped row lies
    within ``eps`` of an earlier one. One pairwise matrix, no loop over rows.
    """
    if q.shape[0] <= 1:
        return q
    d = np.linalg.norm(arm.joint_delta(q[None, :, :], q[:, None, :]), axis=-1)
    near_earlier = np.tril(d <= eps, k=-1).any(axis=1)
    return q[~near_earlier]


def _ik_2link_within_limits(arm: Arm, target: np.ndarray, tol: float) -> np.ndarray:
    """The distinct solutions of :func:`ik_2link` for one target that fit the joint limits."""
    both = ik_2link(arm, target, tol=tol)
    if np.isnan(both).any():
        r_in, r_out = abs(arm.link_lengths[0] - arm.link_lengths[1]), sum(arm.link_lengths)
        raise NoIKSolution(
            f"target ({target[0]:g}, {target[1]:g}) is out of reach: "
            f"r = {float(np.hypot(*target)):g} is outside [{r_in:g}, {r_out:g}]",
            reason="out of reach")
    rows = both[:1] if np.array_equal(both[0], both[1]) else both  # one on a boundary circle
    inside = _equivalents_within(arm, rows, tol=1e-12)
    if inside.shape[0] == 0:
        raise NoIKSolution(
            f"target ({target[0]:g}, {target[1]:g}) is reachable but no solution lies within "
            "the joint limits", reason="joint limits")
    return inside


def _nlink_solutions(arm: Arm, target: np.ndarray, q0, starts: int, seed: int,
                     tol: float) -> tuple[np.ndarray, bool, int]:
    """Solutions of one target for ``n >= 3`` within the limits, one Newton batch.

    Returns ``(q, complete, tried)``: the solutions found (k, n), each with
    ``|end_effector(q) - target| <= tol`` and within the limits; whether they
    are the complete set (a target on a boundary circle, whose only solution is
    the collinear arm); and how many starts the batch was solved from.
    """
    n = arm.n
    lengths = arm.lengths
    r = float(np.hypot(*target))
    r_in, r_out = arm.reach
    if r > r_out + tol or r < r_in - tol:
        raise NoIKSolution(
            f"target ({target[0]:g}, {target[1]:g}) is out of reach: "
            f"r = {r:g} is outside [{r_in:g}, {r_out:g}]",
            reason="out of reach",
        )
    t = target[:, None]
    # On a boundary circle (within tol, as ik_2link does) the self-motion
    # manifold shrinks to one point, the collinear arm, which Newton-Raphson
    # only creeps towards (J is singular there): take it exactly.
    for outer, circle, name in ((True, r_out, "stretched"), (False, r_in, "folded")):
        if circle > 0 and abs(r - circle) <= tol:
            q = wrap_angle(_boundary_start(lengths, t, outer, sign=0.0)[:, 0])
            sols = _equivalents_within(arm, q[None, :], 1e-12)
            if sols.shape[0] == 0:
                raise NoIKSolution(
                    f"target ({target[0]:g}, {target[1]:g}) is on the "
                    f"{'outer' if outer else 'inner'} boundary circle r = {circle:g}, whose only "
                    f"solution (the {name} arm) breaks the joint limits", reason="joint limits")
            return sols, True, 1
    rng = np.random.default_rng(seed)
    parts = [rng.uniform(arm.lower, arm.upper, size=(starts, n))]
    if q0 is not None:
        parts.insert(0, q0[None, :])
    # Next to a circle the manifold is a small loop around the collinear arm;
    # the analytic bends (both mirror images) start Newton-Raphson on it.
    band = 1e-3 * r_out
    for outer, circle in ((True, r_out), (False, r_in)):
        if circle > 0 and abs(r - circle) <= band:
            parts.append(np.concatenate(
                [_boundary_start(lengths, t, outer, sign).T for sign in (1.0, -1.0)]))
    starts_q = np.concatenate(parts)
    tt = np.broadcast_to(target, (starts_q.shape[0], 2))
    q, ok = ik_numeric(arm, tt, starts_q, tol=tol, restarts=2, seed=seed)
    if not np.any(ok):
        free = Arm(arm.link_lengths)
        if arm.limited.any() and ik_numeric(free, target, tol=tol, seed=seed)[1]:
            raise NoIKSolution(
                "target is reachable by the free arm but no solution within the joint "
                "limits was found", reason="joint limits")
        raise NoIKSolution("numerical IK did not converge for this target",
                           reason="did not converge")
    return q[ok], False, starts_q.shape[0]


def ik(
    arm: Arm,
    target: ArrayLike,
    *,
    q0: ArrayLike | None = None,
    starts: int = 32,
    seed: int = 0,
    tol: float = 1e-10,
) -> np.ndarray:
    """Distinct joint solutions for one target (MIS ``solveIK``), shape ``(k, n)``.

    * ``n == 1``: at most one solution, on the circle of radius ``L1``.
    * ``n == 2``: the complete analytic set of :func:`ik_2link` (one row on
      a boundary circle), each within the joint limits: a limited joint takes
      the ``+-2 pi`` equivalent that fits, a free joint is wrapped.
    * ``n >= 3``, target strictly inside the workspace annulus: the solutions
      form a continuum (the self-motion manifold: the arm can move its joints
      while the tip stays put), so no finite list is "all" of them. This
      returns the distinct solutions that :func:`ik_numeric` reaches, in one
      batch, from ``q0`` (if given) and from ``starts`` seeded random
      configurations -- a deterministic sample of that continuum, rows more
      than 1e-6 rad apart. Within 1e-3 of the total length of a boundary
      circle the analytic near-boundary bends (see below) are added as
      starts, so such targets converge like any other.
      :func:`free_ik_solutions` samples the same manifold far more densely.
    * ``n >= 3``, target within ``tol`` of a boundary circle (as
      :func:`ik_2link` treats it): the manifold is a single configuration,
      returned exactly. On the outer circle ``r = sum(L)`` it is the
      stretched arm ``(atan2(y, x), 0, ..., 0)``; on the inner circle
      ``r = 2 max(L) - sum(L) > 0`` the longest link points at the target
      and every other link is folded back along it (joint angles ``+-pi``
      where the orientation flips). Its ``+-2 pi`` equivalents within the
      limits are returned as for ``n == 2``; none fitting is ``"joint
      limits"``, exactly.

    With ``q0`` the rows are sorted by their wrap-aware joint distance from
    ``q0`` (nearest first), so ``ik(...)[0]`` is the solution to move to.

    Raises
    ------
    NoIKSolution
        ``reason="out of reach"`` when the target lies outside the annulus of
        the free arm (by more than ``tol`` for ``n >= 2``); ``"joint limits"``
        when the free arm reaches it but no solution within limits exists
        (exact for n <= 2 and on a boundary circle) or was found (n >= 3,
        where the free arm's solutions were found but every one breaks a
        limit); ``"did not converge"`` when the free arm's attempts also failed.

    Examples
    --------
    >>> ik(Arm([1.0, 1.0]), [0.0, 2.0]).round(6).tolist()
    [[1.570796, 0.0]]
    >>> arm = Arm([1.0, 0.8, 0.5])
    >>> sols = ik(arm, [1.0, 0.5], q0=[0.0, 0.5, 0.5])
    >>> sols.shape[0] > 2, bool(np.abs(arm.end_effector(sols) - [1.0, 0.5]).max() < 1e-9)
    (True, True)

    On the boundary circles of a 3-link arm, the one collinear solution:

    >>> ik(arm, [0.0, 2.3]).round(6).tolist()
    [[1.570796, 0.0, 0.0]]
    >>> ik(Arm([1.0, 0.3, 0.2]), [0.0, 0.5]).round(6).tolist()
    [[1.570796, -3.141593, 0.0]]
    """
    target = _target(target)
    if q0 is not None:
        q0 = np.asarray(q0, dtype=float)
        if q0.shape != (arm.n,) or not np.all(np.isfinite(q0)):
            raise ValueError(f"q0 must be {arm.n} finite joint angles, got shape {q0.shape}")
    r = float(np.hypot(*target))
    r_in, r_out = arm.reach
    if arm.n == 2:
        sols = _ik_2link_within_limits(arm, target, tol)
    elif arm.n == 1:
        if abs(r - r_out) > 1e-9 * r_out:
            raise NoIKSolution(
                f"target ({target[0]:g}, {target[1]:g}) is out of reach: "
                f"a 1-link arm reaches only r = {r_out:g}",
                reason="out of reach",
            )
        sols = _equivalents_within(arm, np.array([[np.arctan2(target[1], target[0])]]), 1e-12)
        if sols.shape[0] == 0:
            raise NoIKSolution("target is reachable but outside the joint limits",
                               reason="joint limits")
    else:
        sols, _, _ = _nlink_solutions(arm, target, q0, starts, seed, tol)
        sols = _dedupe(arm, sols, 1e-6)
    if q0 is not None:
        dist = np.linalg.norm(arm.joint_delta(q0, sols), axis=-1)
        sols = sols[np.argsort(dist, kind="stable")]
    return sols


def _wrist_parametrized(arm: Arm, target: np.ndarray, phis: np.ndarray, tol: float) -> np.ndarray:
    """Solutions (k, n) of one target for ``n >= 3`` with the absolute angles of
    links 3..n given, ``phis`` (m, n - 2): the self-motion manifold in coordinates.

    Fixing the last ``n - 2`` links leaves the wrist (the tip of link 2) at
    ``target - sum_{i>=3} L_i (cos phi_i, sin phi_i)``, and :func:`ik_2link`
    gives both placements of the first two links for every wrist at once. Every
    solution is of this form, so a grid (n = 3) or a seeded sample of ``phis``
    covers the manifold evenly in these coordinates, which the Newton
    projections of random starts do not (they crowd where the manifold is
    flat to them). A limited joint takes the equivalent ``q + 2 pi k`` nearest
    above its lower limit; rows outside the limits or off the target by more
    than ``tol`` are dropped.
    """
    lengths = arm.lengths
    tail = lengths[2:]
    wrist = target - np.stack(((tail * np.cos(phis)).sum(-1), (tail * np.sin(phis)).sum(-1)), -1)
    q12 = ik_2link(lengths[:2], wrist)                         # (m, 2 branches, 2)
    phi2 = q12.sum(axis=-1)                                    # absolute angle of link 2
    # Joint i >= 3 turns link i - 1 into link i: phi_i - phi_{i-1}, per branch.
    before = np.broadcast_to(phis[:, None, :-1], phi2.shape + (phis.shape[1] - 1,))
    rest = phis[:, None, :] - np.concatenate([phi2[..., None], before], axis=-1)
    q = np.concatenate([q12, rest], axis=-1).reshape(-1, arm.n)
    q = q[~np.isnan(q).any(axis=1)]
    lifted = arm.lower + np.mod(q - arm.lower, TWO_PI)
    q = np.where(arm.limited, lifted, wrap_angle(q))
    q = q[arm.within_limits(q)]
    return q[_tip_error(arm, q, np.broadcast_to(target, (len(q), 2))) <= tol]


def _refine_towards_free(arm: Arm, target: np.ndarray, sols: np.ndarray, obstacles,
                         seed: int, tol: float, *, keep: int = 64, per: int = 16,
                         rounds: int = 4) -> tuple[np.ndarray, int]:
    """More solutions (k, n), sampled where the free part of the manifold most likely is.

    Called when every sampled solution collides: the free part, if any, is
    small. Each round keeps the ``keep`` solutions with the largest clearance
    (the shallowest collisions: for discs, the smallest penetration) and
    projects ``per`` random perturbations of each back onto the manifold
    (one :func:`ik_numeric` batch), with perturbations halving from 0.4 rad;
    it stops at the first round that found a free solution. Returns every
    solution the rounds found and how many starts they used.
    """
    rng = np.random.default_rng(seed + 2)
    found = []
    pool = sols
    tried = 0
    for k in range(rounds):
        best = pool[np.argsort(-clearance(arm, pool, obstacles), kind="stable")[:keep]]
        starts = np.repeat(best, per, axis=0)
        starts = starts + rng.normal(0.0, 0.4 / 2**k, starts.shape)
        tried += len(starts)
        q, ok = ik_numeric(arm, np.broadcast_to(target, (len(starts), 2)), starts, tol=tol,
                           restarts=0, seed=seed)
        new = q[ok]
        found.append(new)
        if len(new) and not collides(arm, new, obstacles).all():
            break
        pool = np.concatenate([best, new])
    return np.concatenate(found), tried


def _spread(arm: Arm, q: np.ndarray, first: int, cap: int, eps: float) -> np.ndarray:
    """Indices of at most ``cap`` rows of ``q`` (m, n), starting with ``first``, each
    next one the row farthest (wrap-aware joint distance) from those already taken.

    Farthest-point sampling: the taken rows cover the set evenly and are
    pairwise more than ``eps`` apart (near-duplicates are never taken). The
    loop runs over the rows taken (at most ``cap``), each step one numpy call
    over all of ``q``.
    """
    taken = [first]
    dist = np.linalg.norm(arm.joint_delta(q[first], q), axis=-1)
    for _ in range(min(cap, q.shape[0]) - 1):
        i = int(np.argmax(dist))
        if dist[i] <= eps:
            break
        taken.append(i)
        dist = np.minimum(dist, np.linalg.norm(arm.joint_delta(q[i], q), axis=-1))
    return np.array(taken)


def free_ik_solutions(arm: Arm, target, obstacles, *, q0=None, samples: int = 1024,
                      max_solutions: int = 64, seed: int = 0,
                      tol: float = 1e-10) -> tuple[np.ndarray, int]:
    """Collision-free IK solutions of ``target`` within the limits: the goal configurations
    of a Cartesian goal.

    * ``n <= 2`` (and ``n >= 3`` on a boundary circle): the complete set of
      :func:`ik`, minus those that touch an obstacle.
    * ``n >= 3``: the self-motion manifold is searched densely, cheaply and
      deterministically. Newton-Raphson (:func:`ik_numeric`, one batch)
      projects ``q0`` and ``samples`` seeded random configurations within the
      limits onto it, and ``samples`` more solutions come evenly spread in
      its wrist coordinates (the absolute angles of links 3..n, a grid for
      ``n = 3``; the first two links by :func:`ik_2link`). If every one of
      them collides, the free part (if any) is small: a few rounds project
      perturbations of the least-colliding solutions (largest clearance)
      onto the manifold before giving up. The solutions within the limits
      that touch no obstacle are kept, and a well-spread subset of at most
      ``max_solutions`` of them is returned: the one nearest ``q0`` (when
      given), then farthest-point sampling, so that every free stretch of
      the manifold the search hit is represented.

    Parameters
    ----------
    arm : Arm
    target : (x, y)
    obstacles : iterable of Circle and Polygon
    q0 : (n,) array_like, optional
        The start configuration: it is one of the samples, the solution
        nearest it is always returned, and the rows are sorted by distance to it.
    samples : int
        Random Newton starts, and wrist-angle samples, of the dense search (``n >= 3``).
    max_solutions : int
        Most rows returned.
    seed, tol
        Seed of the samples; position tolerance of a solution.

    Returns
    -------
    free : ndarray, shape (g, n)
        Collision-free solutions, ``1 <= g <= max_solutions``, pairwise more
        than 1e-6 rad apart, nearest to ``q0`` first when it is given.
    count : int
        How many distinct solutions (within the limits) were found before the
        obstacles were applied: all of them for ``n <= 2`` or on a boundary
        circle, else those of the dense sample (distinct to 1e-6 rad).

    Raises
    ------
    NoIKSolution
        As :func:`ik`.
    NoPathFound
        No solution found is collision-free. For the complete sets this is a
        proof ("every one of the N IK solutions ... collides"); for the
        sampled manifold the message gives the evidence: how many solutions,
        from how many starts.

    Examples
    --------
    >>> from rapp import Circle
    >>> free, count = free_ik_solutions(Arm([1.0, 1.0]), [1.0, 1.0], [Circle((0.0, 1.0), 0.2)])
    >>> count, free.round(4).tolist()
    (2, [[0.0, 1.5708]])

    A 3-link goal about 94 % of whose solutions hit one of two discs. Every
    one of the 33 that :func:`ik` samples collides; the dense search finds
    the free stretch:

    >>> arm, goal = Arm([1.0, 0.8, 0.5]), [1.2, 0.6]
    >>> discs = [Circle((0.8, 0.7), 0.3), Circle((1.2, 0.2), 0.3)]
    >>> bool(collides(arm, ik(arm, goal, q0=[0.0, 0.0, 0.0]), discs).all())
    True
    >>> free, count = free_ik_solutions(arm, goal, discs, q0=[0.0, 0.0, 0.0])
    >>> count > 1000, len(free), bool(collides(arm, free, discs).any())
    (True, 64, False)
    >>> bool(np.abs(arm.end_effector(free) - goal).max() <= 1e-10)
    True
    """
    target = _target(target)
    if q0 is not None:
        q0 = np.asarray(q0, dtype=float)
        if q0.shape != (arm.n,) or not np.all(np.isfinite(q0)):
            raise ValueError(f"q0 must be {arm.n} finite joint angles, got shape {q0.shape}")
    obstacles = list(obstacles)
    angles = 0
    if arm.n <= 2:
        sols, complete, tried = np.atleast_2d(ik(arm, target, q0=q0, tol=tol)), True, 0
    else:
        sols, complete, tried = _nlink_solutions(arm, target, q0, samples, seed, tol)
        if not complete:
            # As many points again, evenly spread in the wrist coordinates of
            # the manifold (a regular grid of the one angle for n = 3, seeded
            # for more links).
            if arm.n == 3:
                phis = np.linspace(-np.pi, np.pi, samples, endpoint=False)[:, None]
            else:
                phis = np.random.default_rng(seed + 1).uniform(-np.pi, np.pi, (samples, arm.n - 2))
            sols = np.concatenate([sols, _wrist_parametrized(arm, target, phis, tol)])
            angles = samples
    sols = sols[arm.within_limits(sols, 1e-12)]
    if not complete and obstacles and len(sols) and collides(arm, sols, obstacles).all():
        more, extra = _refine_towards_free(arm, target, sols, obstacles, seed, tol)
        tried += extra
        sols = np.concatenate([sols, more[arm.within_limits(more, 1e-12)]])
    # Distinct to 1e-6 rad: rows equal after rounding are one solution (a few
    # samples may converge to the same point, e.g. a corner of the limits).
    count = len(sols) if complete else int(np.unique(np.round(arm.wrap(sols), 6), axis=0).shape[0])
    check = bool(obstacles) or arm.self_collision  # a self-colliding solution is no goal either
    free = sols[~collides(arm, sols, obstacles)] if len(sols) and check else sols
    x, y = target
    if len(free) == 0:
        if complete:
            raise NoPathFound(
                f"every one of the {count} IK solutions for the goal ({x:g}, {y:g}) "
                "collides" + ("" if arm.self_collision else " with an obstacle"))
        raise NoPathFound(
            f"no collision-free IK solution found for the goal ({x:g}, {y:g}) among {count} "
            f"solutions of the self-motion manifold sampled from {tried} starts projected by "
            f"Newton-Raphson and {angles} wrist angles")
    if q0 is None:
        pick = _spread(arm, free, 0, max_solutions, 1e-6)
        return free[np.sort(pick)], count
    dist = np.linalg.norm(arm.joint_delta(q0, free), axis=-1)
    pick = _spread(arm, free, int(np.argmin(dist)), max_solutions, 1e-6)
    pick = pick[np.argsort(dist[pick], kind="stable")]
    return free[pick], count


def iterate_ik(arm: Arm, target, q0, lam: float = 0.0, iterations: int = 30):
    """Plain Newton-Raphson (``lam = 0``) or damped least squares with a fixed ``lam``, from each start.

    The textbook iterations of chapter 6 (eqs. ch06-nr and ch06-dls) without the safeguards of
    :func:`ik_numeric` (no step cap, no adaptive damping, no restarts), to show what those are for.
    Newton's step solves with the square Jacobian, so ``lam = 0`` needs a 2-link arm.

    Returns
    -------
    errors, travel : ndarray, shape (iterations, k)
        Before each iteration: each start's tip error (m) and its distance ``|q - q0|`` (rad)
        travelled in joint space.
    q : ndarray, shape (k, n)
        Where the iterations ended.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> errors, travel, q = iterate_ik(arm, [1.0, 1.0], [[0.2, 1.2]], lam=0.05, iterations=20)
    >>> bool(errors[-1, 0] < 1e-12), bool(np.allclose(arm.end_effector(q), [1.0, 1.0]))
    (True, True)
    """
    target, q0 = np.asarray(target, float), np.atleast_2d(np.asarray(q0, float))
    q, errors, travel = q0.copy(), [], []
    for _ in range(iterations):
        e = target - arm.end_effector(q)
        J = jacobian(arm, q)
        if lam == 0.0:
            dq = np.linalg.solve(J, e[..., None])[..., 0]
        else:
            JJt = J @ np.swapaxes(J, -1, -2) + lam**2 * np.eye(2)
            dq = (np.swapaxes(J, -1, -2) @ np.linalg.solve(JJt, e[..., None]))[..., 0]
        errors.append(np.linalg.norm(e, axis=-1))
        travel.append(np.linalg.norm(q - q0, axis=-1))
        q = q + dq
    return np.array(errors), np.array(travel), q


def ik_failure(arm: Arm, target) -> str | None:
    """Why :func:`ik` finds no configuration reaching ``target``: the reason of its
    :class:`~rapp.errors.NoIKSolution` (``"out of reach"``, ``"joint limits"``, ...), or ``None``
    when it finds one.

    Examples
    --------
    >>> arm = Arm([1.0, 0.8])
    >>> ik_failure(arm, [2.0, 0.5]), ik_failure(arm, [1.0, 0.6])
    ('out of reach', None)
    """
    try:
        ik(arm, target)
    except NoIKSolution as err:
        return err.reason
    return None
