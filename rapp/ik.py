"""Inverse kinematics of the planar arm (MIS ``solveIK``; seeds 002, 003, 004).

Three tools, from exact to general:

* :func:`ik_2link` -- the analytic solution of a 2-link arm by the law of
  cosines: every solution (0, 1 or 2 of them), joint limits applied.
* :func:`ik_numeric` -- Newton-Raphson on ``f(q) = target`` for an N-link
  arm over a whole batch of targets at once, with damped least squares (DLS)
  near singular configurations, seeded random restarts and joint limits.
* :func:`ik` -- the contract: every distinct solution for ONE target.

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

from rapp.arm import Arm, wrap_angle
from rapp.collision import collides
from rapp.errors import NoIKSolution, NoPathFound

__all__ = ["ik", "ik_2link", "ik_numeric", "jacobian", "free_ik_solutions"]

TWO_PI = 2.0 * np.pi


def _as_arm(arm_or_lengths) -> Arm:
    return arm_or_lengths if isinstance(arm_or_lengths, Arm) else Arm(arm_or_lengths)


def _target(target) -> np.ndarray:
    target = np.asarray(target, dtype=float)
    if target.shape != (2,) or not np.all(np.isfinite(target)):
        raise ValueError(f"target must be a finite point (x, y), got {target.tolist()}")
    return target


def jacobian(arm: Arm, q) -> np.ndarray:
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


def ik_2link(arm_or_lengths, targets, *, tol: float = 1e-10) -> np.ndarray:
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


def _fk_jac(lengths: np.ndarray, q: np.ndarray):
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


def _dls_step(jx, jy, ex, ey, sigma_floor, lambda_max):
    """Damped least-squares step for every column, closed-form 2 x 2 solve.

    The damping is zero while the smallest singular value of ``J`` stays above
    ``sigma_floor`` (a plain Newton step, quadratic convergence) and grows
    smoothly to ``min(lambda_max, |error|)`` as ``J`` becomes singular (Nakamura-Hanafusa /
    Maciejewski-Klein rule), so the step stays bounded at a stretched or
    folded arm.
    """
    a = (jx * jx).sum(axis=0)
    b = (jx * jy).sum(axis=0)
    c = (jy * jy).sum(axis=0)
    half_tr = 0.5 * (a + c)
    sig2_min = np.maximum(half_tr - np.sqrt((0.5 * (a - c)) ** 2 + b * b), 0.0)
    # Capping lambda by the residual (Levenberg-Marquardt / Yamashita-Fukushima)
    # lets the damping vanish as the error does, so a target whose solution is
    # itself near-singular (a nearly stretched arm) still converges fast.
    lam2 = (1.0 - np.minimum(sig2_min / sigma_floor**2, 1.0)) * np.minimum(
        lambda_max**2, ex * ex + ey * ey)
    a += lam2
    c += lam2
    det = a * c - b * b
    # Only reachable when lambda_max = 0 at an exactly singular J.
    det = np.maximum(det, np.finfo(float).tiny)
    ux = (c * ex - b * ey) / det
    uy = (a * ey - b * ex) / det
    return jx * ux + jy * uy


def _initial_guess(arm: Arm, targets: np.ndarray) -> np.ndarray:
    """A cheap start (n, m): every joint after the first bent by the same angle
    so that the tip distance matches ``|target|``, then turned to face it.

    The distance of the uniformly bent arm is tabulated on a grid of bend
    angles and inverted by interpolation on its decreasing prefix (no loop
    over targets). It is only a start: Newton-Raphson does the solving.
    """
    n = arm.n
    m = targets.shape[1]
    if n == 1:
        return np.arctan2(targets[1], targets[0])[None, :]
    beta = np.linspace(0.0, np.pi, 2049)
    qs = np.zeros((n, beta.size))
    qs[1:] = beta
    px, py = _fk(arm.lengths, qs)
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
    return q


def _project(q: np.ndarray, limited: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Clip limited joints into their interval, wrap free joints to [-pi, pi).

    Wrapping inside the iteration means the configuration whose error is
    measured is exactly the one returned (no re-evaluation after a final wrap).
    """
    wrapped = (q + np.pi) % TWO_PI - np.pi
    if not limited.any():
        return wrapped
    lim = limited[:, None]
    return np.where(lim, np.clip(q, lo[:, None], hi[:, None]), wrapped)


def _newton(arm, targets, q, stop_tol, max_iter, max_step):
    """Iterate on the columns of ``q`` (n, m); a column stops once its error is
    at most ``stop_tol``. Only the unfinished columns are carried along.

    Returns the final ``q`` and each column's error at its final ``q``
    (``inf`` where the iterations ran out before it was evaluated).
    """
    lengths = arm.lengths
    limited, lo, hi = arm.limited, arm.lower, arm.upper
    scale = float(lengths.sum())
    sigma_floor = 1e-3 * scale
    lambda_max = 1e-2 * scale
    any_limited = bool(limited.any())
    lim, lo_c, hi_c = limited[:, None], lo[:, None], hi[:, None]
    q = q.copy()
    err = np.full(q.shape[1], np.inf)
    idx = np.arange(q.shape[1])
    qa, ta = q, targets
    for _ in range(max_iter):
        px, py, jx, jy = _fk_jac(lengths, qa)
        ex = ta[0] - px
        ey = ta[1] - py
        e2 = ex * ex + ey * ey
        done = e2 <= stop_tol * stop_tol
        if done.any():
            q[:, idx[done]] = qa[:, done]
            err[idx[done]] = np.sqrt(e2[done])
            keep = ~done
            if not keep.any():
                return q, err
            qa, ta, idx = qa[:, keep], ta[:, keep], idx[keep]
            jx, jy, ex, ey = jx[:, keep], jy[:, keep], ex[keep], ey[keep]
        dq = _dls_step(jx, jy, ex, ey, sigma_floor, lambda_max)
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
                dq = _dls_step(jx, jy, ex, ey, sigma_floor, lambda_max)
        norm2 = (dq * dq).sum(axis=0)
        big = norm2 > max_step * max_step
        if big.any():
            dq[:, big] *= max_step / np.sqrt(norm2[big])
        qa = _project(qa + dq, limited, lo, hi)
    q[:, idx] = qa
    return q, err


def ik_numeric(
    arm: Arm,
    targets,
    q0=None,
    *,
    tol: float = 1e-10,
    max_iter: int = 60,
    restarts: int = 8,
    seed: int = 0,
    max_step: float = 1.0,
):
    """Numerical IK for a batch of targets: Newton-Raphson with damped least squares.

    Every target is solved at the same time: each iteration is a handful of
    numpy calls over the whole batch (no loop over targets), and only the
    targets not yet converged are carried to the next iteration.

    Parameters
    ----------
    arm : Arm
    targets : array_like, shape (..., 2)
    q0 : array_like, shape (..., n) or (n,), optional
        Starting configurations. By default a uniformly bent arm turned to
        face each target (a good first guess that costs one interpolation).
    tol : float
        Position tolerance (in length units) for success.
    max_iter : int
        Iterations per attempt.
    restarts : int
        Further attempts, each from seeded uniformly random configurations
        within the joint bounds, for the targets that have not converged.
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
        True exactly where ``|f(q) - target| <= tol`` (checked again on the
        returned ``q``) and ``q`` respects the joint limits. A target out of
        reach, or one the attempts did not solve, is False: never a wrong
        ``q`` reported as found.

    Examples
    --------
    >>> arm = Arm([1.0, 0.8, 0.5])
    >>> q, ok = ik_numeric(arm, [[1.2, 0.7], [0.3, -1.1], [5.0, 0.0]])
    >>> ok.tolist()
    [True, True, False]
    >>> bool(np.abs(arm.end_effector(q[:2]) - [[1.2, 0.7], [0.3, -1.1]]).max() < 1e-12)
    True
    """
    targets = np.asarray(targets, dtype=float)
    if targets.ndim == 0 or targets.shape[-1] != 2:
        raise ValueError(f"targets must have shape (..., 2), got {targets.shape}")
    batch = targets.shape[:-1]
    n = arm.n
    t = np.ascontiguousarray(targets.reshape(-1, 2).T)
    m = t.shape[1]
    lo, hi, limited = arm.lower, arm.upper, arm.limited
    if q0 is None:
        q = _initial_guess(arm, t)
    else:
        q0 = np.asarray(q0, dtype=float)
        if q0.shape[-1] != n:
            raise ValueError(f"q0 must have shape (..., {n}), got {q0.shape}")
        q = np.broadcast_to(q0, batch + (n,)).reshape(-1, n).T.copy()
    q = _project(q, limited, lo, hi)
    # Stop a little below tol: one Newton step from there lands at round-off.
    stop_tol = min(tol, 1e-12 * float(arm.lengths.sum()))
    # Targets beyond the outer circle cannot converge; skip their iterations.
    hopeless = np.hypot(t[0], t[1]) > arm.reach[1] * (1 + 1e-12) + tol
    finite = np.all(np.isfinite(t), axis=0)
    todo = np.flatnonzero(~hopeless & finite)
    err_all = np.full(m, np.inf)
    rng = np.random.default_rng(seed)
    for attempt in range(restarts + 1):
        if todo.size == 0:
            break
        if attempt > 0:
            q[:, todo] = rng.uniform(lo[:, None], hi[:, None], size=(n, todo.size))
        q[:, todo], err = _newton(arm, t[:, todo], q[:, todo], stop_tol, max_iter, max_step)
        err_all[todo] = err
        todo = todo[~(err <= tol)]
    # err was measured at exactly these q (see _project); targets never
    # iterated keep err = inf.
    q = q.T.reshape(batch + (n,))
    ok = (err_all <= tol).reshape(batch) & arm.within_limits(q)
    return q, ok


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


def ik(
    arm: Arm,
    target,
    *,
    q0=None,
    starts: int = 32,
    seed: int = 0,
    tol: float = 1e-10,
) -> np.ndarray:
    """Distinct joint solutions for one target (MIS ``solveIK``), shape ``(k, n)``.

    * ``n == 1``: at most one solution, on the circle of radius ``L1``.
    * ``n == 2``: the complete analytic set of :func:`ik_2link` (one row on
      a boundary circle), each within the joint limits: a limited joint takes
      the ``+-2 pi`` equivalent that fits, a free joint is wrapped.
    * ``n >= 3``: the solutions form a continuum (the self-motion manifold:
      the arm can move its joints while the tip stays put), so no finite list
      is "all" of them. This returns the distinct solutions that
      :func:`ik_numeric` reaches from ``q0`` (if given) and from ``starts``
      seeded random configurations -- a deterministic sample of that
      continuum, rows more than 1e-6 rad apart.

    With ``q0`` the rows are sorted by their wrap-aware joint distance from
    ``q0`` (nearest first), so ``ik(...)[0]`` is the solution to move to.

    Raises
    ------
    NoIKSolution
        ``reason="out of reach"`` when the target lies outside the annulus of
        the free arm; ``"joint limits"`` when the free arm reaches it but no
        solution within limits exists (exact for n <= 2) or was found (n >= 3,
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
        if r > r_out * (1 + 1e-12) or r < r_in * (1 - 1e-12):
            raise NoIKSolution(
                f"target ({target[0]:g}, {target[1]:g}) is out of reach: "
                f"r = {r:g} is outside [{r_in:g}, {r_out:g}]",
                reason="out of reach",
            )
        rng = np.random.default_rng(seed)
        starts_q = rng.uniform(arm.lower, arm.upper, size=(starts, arm.n))
        if q0 is not None:
            starts_q = np.concatenate([q0[None, :], starts_q])
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
        sols = _dedupe(arm, q[ok], 1e-6)
    if q0 is not None:
        dist = np.linalg.norm(arm.joint_delta(q0, sols), axis=-1)
        sols = sols[np.argsort(dist, kind="stable")]
    return sols


def free_ik_solutions(arm: Arm, target, obstacles, *, q0=None) -> tuple[np.ndarray, int]:
    """The IK solutions of ``target`` that respect the limits and touch no obstacle.

    Returns
    -------
    free : ndarray, shape (g, n)
        Collision-free solutions, nearest to ``q0`` first when it is given.
    count : int
        How many solutions :func:`ik` found before the obstacles were applied.

    Raises
    ------
    NoIKSolution
        From :func:`ik`.
    NoPathFound
        Every solution found collides with an obstacle.

    Examples
    --------
    >>> from rapp import Circle
    >>> free, count = free_ik_solutions(Arm([1.0, 1.0]), [1.0, 1.0], [Circle((0.0, 1.0), 0.2)])
    >>> count, free.round(4).tolist()
    (2, [[0.0, 1.5708]])
    """
    sols = np.atleast_2d(ik(arm, target, q0=q0))
    sols = sols[arm.within_limits(sols, 1e-12)]
    obstacles = list(obstacles)
    free = sols[~collides(arm, sols, obstacles)] if len(sols) and obstacles else sols
    if len(free) == 0:
        x, y = np.asarray(target, float)
        raise NoPathFound(
            f"every one of the {len(sols)} IK solutions for the goal ({x:g}, {y:g}) "
            "collides with an obstacle")
    return free, len(sols)
