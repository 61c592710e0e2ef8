"""Cartesian paths: the end effector along a straight segment of the workspace.

:func:`line_path` turns a straight segment from the tip's current position to
a goal point into joint waypoints ``(k, n)``. Joint-space planners join
configurations by straight joint-space edges, along which the tip sweeps a
curve; here the curve is the point: the tip stays within ``tolerance`` of the
segment at every waypoint *and everywhere between them*.

How it works
------------
The line ``x(s) = p0 + s (goal - p0)``, ``0 <= s <= 1``, is marched from
``s = 0``. Each new configuration is solved from the previous one
(continuation): for two links the analytic solution of :func:`rapp.ik.ik_2link`
on the elbow branch of ``q_start``, for more links Newton-Raphson with the
damped least-squares step of :mod:`rapp.ik` started from the previous
configuration (limited joints clamped at their limits). A step is accepted
only when

* the joint step ``|dq|`` (2-norm) is at most ``max_step``, so there is no
  jump to another branch or another part of the self-motion manifold;
* the straight joint-space edge between the two waypoints is *certified* to
  keep the tip within ``tolerance`` of the segment (below);

otherwise the step in ``s`` is halved. Each accepted edge is certified
collision-free with :func:`rapp.collision.segment_collision_free`.

The bound between waypoints
---------------------------
Along an edge ``q(t) = qa + t dq``, ``0 <= t <= 1``, the absolute link angles
are ``phi_i(t) = phi_i(0) + t Phi_i`` with ``Phi_i = dq_1 + ... + dq_i``, so
the tip ``x(t) = sum_i L_i (cos phi_i, sin phi_i)`` has::

    x''(t) = -sum_i L_i Phi_i^2 (cos phi_i, sin phi_i),
    |x''(t)| <= K = sum_i L_i Phi_i^2      (<= (sum L) |dq|_1^2).

On a piece ``[t0, t0 + h]`` the curve differs from the chord through its two
end points by at most ``K h^2 / 8`` (apply the scalar interpolation-error
bound ``|g(t)| <= K (t - t0)(t0 + h - t) / 2`` to ``g = u . (x - chord)``, for
the unit vector ``u`` along the difference). The distance to the segment is
convex, so along a chord it is at most its larger value at the chord's ends.
With samples at ``t = 0, 1/4, 1/2, 3/4, 1`` (``h = 1/4``):

    dist(x(t), segment) <= max over the 5 samples of dist + K / 128.

An edge is accepted when both terms are at most ``tolerance / 2``: a proof
for every ``t``, not a sampling resolution.

Redundancy
----------
For three or more links each point of the line has a one-parameter family of
configurations (the self-motion). When the continuation nearest each previous
configuration fails, the march is repeated with, after each waypoint's solve,
a step along the null space of the tip's Jacobian (the tip stays put to first
order; Newton puts it back exactly) up the gradient of a clearance measure:
each link's clearance and each limited joint's distance to its limit, capped
so that only what is near counts. The gains of :data:`REDUNDANCY_GAINS` are
tried in order; then restarts: the arm first moves along its self-motion with
the tip held at the line's start (each way, :data:`RESTART_ANGLES` radians of
joint motion), and the march is tried from there. Every edge is certified as
before. A refusal of a redundant
arm says what was tried: it proves these continuations fail, not that no path
exists. For two links the path from ``q_start`` is unique (the elbow cannot
change without passing a boundary circle, which is refused), so a refusal is a
proof.

Failures raise :class:`rapp.errors.PathNotFollowable` with one line naming
the first thing that goes wrong along the line and its ``s``: the line leaves
the workspace annulus, passes a singularity (the arm stretched or folded
straight: within :data:`SINGULAR_MARGIN` of a boundary circle of the annulus,
or, for three or more links, a configuration the continuation cannot get
past), a joint leaves its limits, or the arm hits an obstacle. A joint is
named by its angle, numbered from 1 as in the book, and by its index in
``arm.joint_limits`` (``θ2 (joint_limits[1])``); an obstacle by its index in
``obstacles``, from 0. Units: lengths in metres (those of the arm), angles in
radians.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.checks import finite_number
from rapp.collision import (check_obstacle, collides, link_clearances, segment_collision_free,
                            segment_point_distance)
from rapp.errors import PathNotFollowable
from rapp.ik import dls_step, fk_and_jacobian, ik_2link, jacobian
from rapp.time_scaling import trapezoidal

__all__ = ["line_path", "edge_deviation_bound", "SINGULAR_MARGIN", "REDUNDANCY_GAINS",
           "RESTART_ANGLES", "tip_along_edges", "line_fraction", "LineRide", "ride_line"]

#: A line that comes within ``SINGULAR_MARGIN * sum(L)`` of a boundary circle of the
#: workspace annulus (without crossing it) passes a singularity: there the arm is
#: stretched (outer circle) or folded straight (inner circle, when it exists), its
#: Jacobian loses rank and the joint speed needed to follow the line blows up. A
#: segment inside a disc touches its outer circle only at an end point, so the
#: stretched arm is met at ``s = 0`` or ``s = 1``; the inner circle can be
#: touched anywhere.
SINGULAR_MARGIN = 1e-6

# Smallest step of the line parameter before the march gives up (a singularity or a limit).
_DS_MIN = 1e-9
# Smallest singular value of the Jacobian of the arm scaled to total length 1 accepted at a
# waypoint (three or more links); below it the configuration counts as singular.
_SIGMA_MIN = 1e-6
# The quarter points of an edge used by the deviation bound.
_T = np.array([0.0, 0.25, 0.5, 0.75, 1.0])


def edge_deviation_bound(arm: Arm, qa, qb, a, b) -> float:
    """Upper bound on the distance from the segment ``ab`` of the tip along the
    joint-space edge ``qa -> qb``: the largest distance at ``t = 0, 1/4, 1/2,
    3/4, 1`` plus ``K / 128``, ``K = sum_i L_i (dq_1 + ... + dq_i)^2`` (see the
    module notes for the proof).

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> edge_deviation_bound(arm, [0.0, 0.0], [0.0, 0.0], [2.0, 0.0], [2.0, 1.0])
    0.0
    >>> # swinging the stretched arm by 0.1 rad: the tip ends 2 (1 - cos 0.1) = 0.00999 off
    >>> round(edge_deviation_bound(arm, [0.0, 0.0], [0.1, 0.0], [2.0, 0.0], [2.0, 1.0]), 5)
    0.01015
    """
    dev, curve = _edge_terms(arm, np.asarray(qa, float), np.asarray(qb, float),
                             np.asarray(a, float), np.asarray(b, float))
    return float(dev + curve)


def _edge_terms(arm: Arm, qa, qb, a, b):
    """(largest sampled distance, curvature term K/128) of the edge ``qa -> qb``."""
    dq = qb - qa
    phi = np.cumsum(dq)
    curve = float(arm.lengths @ (phi * phi)) / 128.0
    pts = arm.end_effector(qa + _T[:, None] * dq)
    return float(segment_point_distance(a, b, pts).max()), curve


def _fmt_point(p) -> str:
    return f"({p[0]:.4g}, {p[1]:.4g})"


def _workspace_check(arm: Arm, p0: np.ndarray, d: np.ndarray) -> None:
    """Raise for the first s at which the line leaves the annulus or touches a boundary circle."""
    lengths = arm.lengths
    r_out = float(lengths.sum())
    r_in_raw = 2.0 * float(lengths.max()) - r_out  # >= 0: the folded arm is a boundary
    margin = SINGULAR_MARGIN * r_out
    a = float(d @ d)
    b = float(p0 @ d)
    c0 = float(p0 @ p0)
    goal = p0 + d
    events = []  # (s, priority, reason, detail)
    r0, r1 = float(np.hypot(*p0)), float(np.hypot(*goal))
    if a > 0 and r1 > r_out:
        disc = max(b * b - a * (c0 - r_out * r_out), 0.0)
        s = min(max((-b + np.sqrt(disc)) / a, 0.0), 1.0)
        events.append((s, 0, "workspace",
                       f"beyond the outer circle r = {r_out:.4g} (the sum of the links)"))
    if r0 >= r_out - margin:
        events.append((0.0, 1, "singularity", "the arm is stretched straight (outer circle "
                       f"r = {r_out:.4g})"))
    elif r1 >= r_out - margin and r1 <= r_out:
        events.append((1.0, 1, "singularity", "the arm is stretched straight (outer circle "
                       f"r = {r_out:.4g})"))
    if r_in_raw >= 0.0:
        s_star = min(max(-b / a, 0.0), 1.0) if a > 0 else 0.0
        r_min = float(np.hypot(*(p0 + s_star * d)))
        if r_min < r_in_raw:
            disc = max(b * b - a * (c0 - r_in_raw * r_in_raw), 0.0)
            s = min(max((-b - np.sqrt(disc)) / a, 0.0), 1.0)
            events.append((s, 0, "workspace",
                           f"inside the inner circle r = {r_in_raw:.4g} that the arm cannot reach"))
        elif r_min <= r_in_raw + margin:
            where = "the base" if r_in_raw == 0.0 else f"the inner circle r = {r_in_raw:.4g}"
            events.append((s_star, 1, "singularity",
                           f"the arm is folded straight (tip on {where})"))
    if not events:
        return
    s, _, reason, detail = min(events)
    p = p0 + s * d
    what = ("the line leaves the workspace" if reason == "workspace"
            else "the line passes a singularity")
    raise PathNotFollowable(f"{what} at s={s:.3f}, (x, y)={_fmt_point(p)}: {detail}",
                            reason=reason, s=s)


def _hit_obstacle(arm: Arm, qa, qb, sa: float, sb: float, obstacles, p0, d):
    """Raise naming the first obstacle the edge ``qa -> qb`` (from s = sa to sb) is not clear of."""
    for i, ob in enumerate(obstacles):
        if not segment_collision_free(arm, qa, qb, [ob]):
            t = np.linspace(0.0, 1.0, 65)
            hit = collides(arm, qa + t[:, None] * (qb - qa), [ob])
            s = sa + (float(t[np.argmax(hit)]) if hit.any() else 0.0) * (sb - sa)
            raise PathNotFollowable(
                f"the arm hits obstacle {i} (obstacles[{i}]) at s={s:.3f}, "
                f"tip (x, y)={_fmt_point(p0 + s * d)}", reason="obstacle", s=s)
    raise AssertionError("an edge not clear of all obstacles is clear of each")  # pragma: no cover


class _Solver:
    """One continuation step: the configuration nearest ``q_prev`` with the tip at a target.

    ``solve`` returns ``(q, None)`` or ``(None, (reason, joint))`` with reason
    ``"singularity"`` or ``"joint limits"``.
    """

    def __init__(self, arm: Arm, q0: np.ndarray, tolerance: float, obstacles=(),
                 gain: float = 0.0, max_step: float = 0.1):
        self.arm = arm
        # Redundancy (3+ links): after each solve, a step along the self-motion (the null space
        # of the tip's Jacobian, which leaves the tip where it is to first order) that climbs
        # the gradient of a clearance measure: links away from obstacles, joints from limits.
        self.obstacles, self.gain = list(obstacles), float(gain)
        self.null_cap = 0.3 * max_step
        self.scale = float(arm.lengths.sum())
        self.lengths = arm.lengths / self.scale
        self.limited, self.lo, self.hi = arm.limited, arm.lower, arm.upper
        # Newton stops at round-off and accepts a waypoint within a thousandth of the
        # tolerance; the edge test then bounds the deviation for real.
        self.accept = max(1e-3 * tolerance, 1e-13 * self.scale)
        # 2 links: the elbow branch of q_start, fixed (sin q2 != 0 there: the workspace
        # check has refused a start on a boundary circle).
        self.branch = (0 if np.sin(q0[1]) > 0 else 1) if arm.n == 2 else None

    def solve(self, q_prev: np.ndarray, target: np.ndarray):
        if self.arm.n == 2:
            sol = ik_2link(self.arm, target)[self.branch]
            if np.isnan(sol).any():  # pragma: no cover - the workspace check comes first
                return None, ("singularity", None)
            # The 2 pi equivalent next to q_prev: continuous in s, limited joints included.
            q = q_prev + wrap_angle(sol - q_prev)
            out = np.flatnonzero(self.limited & ((q < self.lo) | (q > self.hi)))
            return q, (("joint limits", int(out[0])) if out.size else None)
        q, why = self._newton(q_prev, target)
        if why is None and self.gain > 0.0:
            q = self._self_motion(q, target)
        return q, why

    def _room(self, q: np.ndarray) -> float:
        """What the self-motion climbs: each link's clearance and each limited joint's distance
        to its nearer limit, both capped (only what is near matters), summed."""
        reach = 0.25 * self.scale
        room = 0.0
        if self.obstacles:
            room += float(np.minimum(link_clearances(self.arm, q, self.obstacles), reach).sum())
        if self.limited.any():
            gap = np.minimum(q - self.lo, self.hi - q)[self.limited]
            room += self.scale * float(np.minimum(gap, 0.3).sum())
        return room

    def _self_motion(self, q: np.ndarray, target: np.ndarray) -> np.ndarray:
        """``q`` moved along its self-motion toward more room, the tip put back on ``target``."""
        n = q.size
        h = 1e-6
        grad = np.array([(self._room(q + h * e) - self._room(q - h * e)) / (2 * h)
                         for e in np.eye(n)])
        if not grad.any():
            return q
        jac = np.stack(fk_and_jacobian(self.lengths, q[:, None])[2:])[:, :, 0]
        null = np.eye(n) - np.linalg.pinv(jac) @ jac
        dq = self.gain * (null @ grad) / self.scale
        norm = float(np.linalg.norm(dq))
        if norm > self.null_cap:
            dq *= self.null_cap / norm
        moved, why = self._newton(q + dq, target)
        if why is not None or self._room(moved) < self._room(q):
            return q
        return moved

    def _newton(self, q_prev, target):
        lengths, lim, lo, hi = self.lengths, self.limited, self.lo, self.hi
        t = target / self.scale
        q = q_prev.copy()[:, None]
        blocked = np.zeros(lengths.size, dtype=bool)
        for _ in range(20):
            px, py, jx, jy = fk_and_jacobian(lengths, q)
            ex, ey = t[0] - px, t[1] - py
            if float(np.hypot(ex[0], ey[0])) * self.scale <= 1e-3 * self.accept:
                break
            dq = dls_step(jx, jy, ex, ey, 1e-3, 1e-2)
            blocked = lim & (((q + dq)[:, 0] < lo) | ((q + dq)[:, 0] > hi))
            if blocked.any():  # clamp: freeze the joints the step pushes out, re-solve
                jx = np.where(blocked[:, None], 0.0, jx)
                jy = np.where(blocked[:, None], 0.0, jy)
                dq = dls_step(jx, jy, ex, ey, 1e-3, 1e-2)
            norm = float(np.linalg.norm(dq))
            if norm > 0.5:
                dq *= 0.5 / norm
            q = q + dq
            q[:, 0] = np.where(lim, np.clip(q[:, 0], lo, hi), q[:, 0])
        q = q[:, 0]
        err = float(np.linalg.norm(self.arm.end_effector(q) - target))
        if err <= self.accept:
            jac = np.stack(fk_and_jacobian(lengths, q[:, None])[2:])[:, :, 0]
            if np.linalg.svd(jac, compute_uv=False)[-1] < _SIGMA_MIN:
                return None, ("singularity", None)
            return q, None
        on_limit = np.flatnonzero(lim & ((q <= lo) | (q >= hi)))
        if on_limit.size:
            return None, ("joint limits", int(on_limit[0]))
        return None, ("singularity", None)


def line_path(arm: Arm, q_start, goal_xy, obstacles=(), *, tolerance: float = 1e-3,
              max_step: float = 0.1) -> np.ndarray:
    """Joint waypoints ``(k, n)`` that move the tip along the straight segment to ``goal_xy``.

    The segment runs from ``arm.end_effector(q_start)`` to ``goal_xy``. The
    first waypoint is ``q_start`` exactly, the last puts the tip at
    ``goal_xy`` (to round-off), and along every straight joint-space edge
    between consecutive waypoints the tip stays within ``tolerance`` of the
    segment -- proved with a curvature bound, not sampled (module notes).
    Consecutive waypoints differ by at most ``max_step`` (2-norm, radians),
    and a 2-link arm keeps the elbow branch of ``q_start``. Free joints are
    not wrapped: the angles change continuously, so each edge is the short
    motion it looks like. Every edge is certified collision-free.

    Parameters
    ----------
    arm : Arm
    q_start : array_like, shape (n,)
        Within the joint limits.
    goal_xy : array_like, shape (2,)
        Metres, like the link lengths.
    obstacles : iterable of Circle and Polygon
    tolerance : float
        Largest distance (metres) of the tip from the segment, default 1 mm.
    max_step : float
        Largest joint step between consecutive waypoints (radians, 2-norm).

    Returns
    -------
    ndarray, shape (k, n)
        ``k >= 2``, or ``k = 1`` when ``goal_xy`` is the tip's position.

    Raises
    ------
    PathNotFollowable
        One line naming the first failure along the line and its ``s``:
        ``the line leaves the workspace at s=...``, ``the line passes a
        singularity at s=...``, ``θj (joint_limits[j-1]) leaves its limits ... at s=...``, ``the
        arm hits obstacle i at s=...``. ``reason`` and ``s`` are attributes.
    ValueError
        Malformed arguments, or ``q_start`` outside the joint limits.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> q = line_path(arm, [0.3, 1.2], (1.2, -0.4))
    >>> q.shape[1], bool(np.allclose(q[0], [0.3, 1.2]))
    (2, True)
    >>> bool(np.linalg.norm(arm.end_effector(q[-1]) - (1.2, -0.4)) < 1e-9)
    True
    >>> line_path(arm, [0.3, 1.2], (2.5, 0.0))
    Traceback (most recent call last):
    ...
    rapp.errors.PathNotFollowable: the line leaves the workspace at s=0.619, (x, y)=(1.938, 0.4927): beyond the outer circle r = 2 (the sum of the links)
    """
    if not isinstance(arm, Arm):
        raise ValueError(f"arm must be a rapp.Arm, got {type(arm).__name__}")
    q0 = arm.check_q(q_start, "q_start")
    if q0.shape != (arm.n,):
        raise ValueError(f"q_start must be one configuration of shape ({arm.n},), got {q0.shape}")
    try:
        goal = np.asarray(goal_xy, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"goal_xy must be a finite point (x, y), got {goal_xy!r}") from None
    if goal.shape != (2,) or not np.isfinite(goal).all():
        raise ValueError(f"goal_xy must be a finite point (x, y), got {goal_xy!r}")
    tolerance = finite_number(tolerance, "tolerance", above=0.0)
    max_step = finite_number(max_step, "max_step", above=0.0)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    if not arm.within_limits(q0):
        raise ValueError(f"q_start = {q0.tolist()} is outside the joint limits {list(arm.joint_limits)}")
    p0 = arm.end_effector(q0)
    d = goal - p0
    if collides(arm, q0, obstacles):
        _hit_obstacle(arm, q0, q0, 0.0, 0.0, obstacles, p0, d)
    if not d.any():
        return q0[None, :].copy()
    _workspace_check(arm, p0, d)
    if arm.n == 2:
        return _march(arm, q0, p0, d, goal, obstacles, tolerance, max_step)
    # A redundant arm: the continuation nearest the previous configuration first; when it
    # fails, the same march with self-motion away from obstacles and limits, gently, then
    # harder. The first failure is reported, with what was tried.
    first = None
    for gain in REDUNDANCY_GAINS:
        try:
            return _march(arm, q0, p0, d, goal, obstacles, tolerance, max_step, gain)
        except PathNotFollowable as e:
            if first is None:
                first = e
            if e.reason == "workspace":
                raise
    # Restarts: first move along the self-motion with the tip held at the line's start (a
    # motion that keeps the tip on the line, so part of the path), then march from there.
    for sign in (1.0, -1.0) if RESTART_ANGLES else ():
        walk, walked = _self_motion_walk(arm, q0, p0, goal, obstacles, tolerance, max_step, sign,
                                         max(RESTART_ANGLES))
        for angle in RESTART_ANGLES:
            k = int(np.searchsorted(walked, angle))
            if k >= len(walk) or k == 0:
                break
            try:
                rest = _march(arm, walk[k], p0, d, goal, obstacles, tolerance, max_step,
                              REDUNDANCY_GAINS[-1] if len(REDUNDANCY_GAINS) > 1 else 0.0)
            except PathNotFollowable:
                continue
            return np.vstack((walk[: k + 1], rest[1:]))
    tried = ", ".join(f"{g:g}" for g in REDUNDANCY_GAINS[1:])
    restarts = ", ".join(f"{a:g}" for a in RESTART_ANGLES)
    raise PathNotFollowable(
        f"{first} (tried: the continuation nearest each previous configuration; self-motion "
        f"of the {arm.n}-link arm away from obstacles and joint limits with gains {tried}; "
        f"restarts after a self-motion of +-{restarts} rad with the tip held at the start; a "
        "redundant arm may still have a path no continuation from q_start finds)",
        reason=first.reason, s=first.s) from None


#: Gains of the self-motion tried, in order, for an arm of three or more links (0: none).
REDUNDANCY_GAINS = (0.0, 0.5, 2.0, 8.0)
#: Restarts (three or more links): joint-space length (rad) of a self-motion, each way, with
#: the tip held at the line's start, from whose end the march is tried again.
RESTART_ANGLES = (0.5, 1.0, 2.0, 3.0)


def _self_motion_walk(arm, q0, p0, goal, obstacles, tolerance, max_step, sign, length):
    """Waypoints from ``q0`` along the self-motion with the tip at ``p0`` and their cumulative
    joint-space length; every edge certified (tip within tolerance of the line, no collision).
    Stops at ``length``, an obstacle, a limit or a singularity."""
    solver = _Solver(arm, q0, tolerance)
    half = 0.5 * tolerance
    h = 0.5 * max_step
    path, walked = [q0.copy()], [0.0]
    q, v_prev = q0.copy(), None
    for _ in range(int(np.ceil(4 * length / h))):   # each step moves at least h / 4
        if walked[-1] >= length:
            break
        jac = np.stack(fk_and_jacobian(solver.lengths, q[:, None])[2:])[:, :, 0]
        null = np.linalg.svd(jac)[2][2:]          # (n - 2, n): the self-motion directions
        v = null[0] if v_prev is None else null.T @ (null @ v_prev)
        norm = float(np.linalg.norm(v))
        if norm == 0.0:
            break
        v = v / norm
        if v_prev is None:
            v = sign * v
        elif v @ v_prev < 0:
            v = -v
        q_new, why = solver._newton(q + h * v, p0)
        moved = float(np.linalg.norm(q_new - q))
        if why is not None or moved > max_step or moved < 0.25 * h:  # blocked by a limit
            break
        if not arm.within_limits(q_new):
            break
        dev, curve = _edge_terms(arm, q, q_new, p0, goal)
        if dev > half or curve > half:
            break
        if obstacles and not segment_collision_free(arm, q, q_new, obstacles):
            break
        walked.append(walked[-1] + float(np.linalg.norm(q_new - q)))
        path.append(q_new)
        q, v_prev = q_new, v
    return np.array(path), np.array(walked)


def _march(arm, q0, p0, d, goal, obstacles, tolerance, max_step, gain=0.0):
    solver = _Solver(arm, q0, tolerance, obstacles, gain, max_step)
    half = 0.5 * tolerance
    path = [q0.copy()]
    q, s, ds = q0.copy(), 0.0, 0.125
    while s < 1.0:
        ds = min(ds, 1.0 - s)
        while True:
            s_new = 1.0 if s + ds >= 1.0 - 1e-12 else s + ds
            target = goal if s_new == 1.0 else p0 + s_new * d
            q_new, why = solver.solve(q, target)
            if q_new is not None:
                step_ok = float(np.linalg.norm(q_new - q)) <= max_step
                if step_ok:
                    dev, curve = _edge_terms(arm, q, q_new, p0, goal)
                    step_ok = dev <= half and curve <= half
                if step_ok and why is None:
                    break
                if step_ok:  # 2 links: a small, certified step out of the limits
                    j = why[1]
                    bound = arm.lower[j] if q_new[j] < arm.lower[j] else arm.upper[j]
                    frac = (bound - q[j]) / (q_new[j] - q[j])
                    _raise_limit(arm, j, s + frac * (s_new - s), p0, d)
                why = why or ("step", None)
            ds *= 0.5
            if ds < _DS_MIN:
                if why[0] == "joint limits":
                    _raise_limit(arm, why[1], s, p0, d)
                p = p0 + s * d
                raise PathNotFollowable(
                    f"the line passes a singularity at s={s:.3f}, (x, y)={_fmt_point(p)}: "
                    "the arm cannot follow it past there without its joints jumping",
                    reason="singularity", s=s)
        if obstacles and not segment_collision_free(arm, q, q_new, obstacles):
            _hit_obstacle(arm, q, q_new, s, s_new, obstacles, p0, d)
        path.append(q_new)
        q, s = q_new, s_new
        ds *= 2.0
    return np.array(path)


def _raise_limit(arm: Arm, j: int, s: float, p0, d):
    lo, hi = arm.joint_limits[j]
    raise PathNotFollowable(
        f"θ{j + 1} (joint_limits[{j}]) leaves its limits [{lo:.4g}, {hi:.4g}] rad at s={s:.3f}, "
        f"tip (x, y)={_fmt_point(p0 + s * d)}", reason="joint limits", s=s)


# --- following the line in time (chapter 15) ---------------------------------------------------

def tip_along_edges(arm: Arm, qs, per_edge: int = 64) -> np.ndarray:
    """The tip along every straight joint-space edge of the waypoints ``qs`` (m, n), densely.

    Each edge is sampled at ``per_edge`` evenly spaced points (its end excluded), then the last
    waypoint: ``(m - 1) * per_edge + 1`` tip positions, in order.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> tips = tip_along_edges(arm, [[0.0, 0.0], [np.pi / 2, 0.0]], per_edge=2)
    >>> np.round(tips, 6).tolist()
    [[2.0, 0.0], [1.414214, 1.414214], [0.0, 2.0]]
    """
    qs = np.asarray(qs, float)
    tau = np.linspace(0.0, 1.0, per_edge + 1)[:-1, None, None]
    dense = (qs[:-1] + tau * (qs[1:] - qs[:-1])).transpose(1, 0, 2).reshape(-1, qs.shape[1])
    return arm.end_effector(np.vstack([dense, qs[-1:]]))


def line_fraction(points, a, b) -> np.ndarray:
    """Where each point projects onto the line from ``a`` (0) to ``b`` (1), as a fraction.

    >>> line_fraction([[0.5, 3.0], [2.0, 0.0]], [0.0, 0.0], [1.0, 0.0]).tolist()
    [0.5, 2.0]
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    return (np.asarray(points, float) - a) @ (b - a) / np.sum((b - a) ** 2)


@dataclass(frozen=True)
class LineRide:
    """The tip moving along the line ``a`` to ``b`` in time, the joints on ``q_line`` (see :func:`ride_line`).

    ``timing`` moves the distance along the line (m) rest to rest; ``s_way`` is each waypoint's
    fraction of the line.
    """

    arm: Arm
    a: np.ndarray
    b: np.ndarray
    q_line: np.ndarray
    s_way: np.ndarray
    timing: object

    @property
    def length(self) -> float:
        """The line's length (m)."""
        return float(np.linalg.norm(self.b - self.a))

    def state(self, t: float) -> tuple:
        """Configuration, tip velocity (m/s) and joint velocity (rad/s) at time ``t`` (s)."""
        d, dd, _ = (x[0, 0] for x in self.timing.sample([t]))
        q = np.array([np.interp(d / self.length, self.s_way, self.q_line[:, j])
                      for j in range(self.q_line.shape[1])])
        xdot = dd * (self.b - self.a) / self.length
        return q, xdot, np.linalg.solve(jacobian(self.arm, q), xdot)


def ride_line(arm: Arm, a, b, q_line, vmax: float, amax: float) -> LineRide:
    """The tip along the line ``a`` to ``b`` at a trapezoidal speed: at most ``vmax``, ``amax``.

    ``q_line`` are the waypoints :func:`line_path` returned for the line (a 2-link arm: the
    Jacobian is square); between them the joints are interpolated by the tip's fraction of the line.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> q_line = line_path(arm, ik_2link(arm, [1.0, 0.5])[0], [1.5, 0.5])
    >>> ride = ride_line(arm, [1.0, 0.5], [1.5, 0.5], q_line, vmax=0.5, amax=0.5)
    >>> round(ride.timing.duration, 6)                # 0.5 m at 0.5 m/s, plus 1 s of ramps
    2.0
    >>> q, xdot, qdot = ride.state(1.0)
    >>> np.allclose(jacobian(arm, q) @ qdot, xdot), np.round(xdot, 6).tolist()
    (True, [0.5, 0.0])
    """
    a, b, q_line = np.asarray(a, float), np.asarray(b, float), np.asarray(q_line, float)
    length = float(np.linalg.norm(b - a))
    s_way = line_fraction(arm.end_effector(q_line), a, b)
    return LineRide(arm, a, b, q_line, s_way, trapezoidal(0.0, length, vmax=vmax, amax=amax))
