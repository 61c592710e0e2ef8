"""Case study: an obstacle-avoiding via point for cubic via-point trajectories.

Seed 002 (a cubic-trajectory assignment) steers the tip of a 2-link arm from
B through a via point D to C around a disc. The trajectory is ``start -> via -> goal`` made of two cubic segments in time
(seed 002: B at ``t = 3`` with velocity ``v_start``, D at ``t = 5.5`` at rest,
C at ``t = 8`` at rest). Two answers for the via point D:

* :func:`search_via_point` - the seed's method: a grid of candidate points
  around the obstacle, then a finer grid around the best one. It minimizes the
  *straight-line* length ``|BD| + |DC|`` but requires the *cubic* path (and,
  with an arm, the arm's links) to clear the circle. Here the path clearance is
  exact: the minimum distance of a cubic curve to the centre is found from the
  real roots of the degree-5 derivative of the squared distance
  (:func:`curve_point_distance`), not from samples.
* :func:`tangent_via_point` - the exact answer of the seed's Condition 2A read
  literally (segments BD and DC straight and clear): the intersection of the
  tangent from B and the tangent from C on the shorter side.

Why they differ. Segment DC is rest-to-rest, so the cubic moves along the
straight line DC. Segment BD starts with ``v_start`` not parallel to BD, so
the curve is ``B + (D - B)(3u^2 - 2u^3) + v_start T u (1 - u)^2``: it bulges
towards ``v_start`` (away from the disc for seed 002). The cubic path may
therefore clear the disc although the straight segment BD cuts it, and the
grid search can beat the tangent point on ``|BD| + |DC|`` - which is then no
longer the length of the path the arm travels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rapp.collision import segment_point_distance
from rapp.ik import ik_2link
from rapp.trajectory import cubic_local, polyval, shift_to_absolute, via_points

__all__ = [
    "ViaPoint",
    "cubic_segment",
    "to_absolute_time",
    "curve_point_distance",
    "via_segments",
    "path_clearance",
    "arm_link_distance",
    "first_arm_collision",
    "search_via_point",
    "tangent_via_point",
    "peak_rates",
    "spline_vs_cubic",
    "coefficient_tables",
    "velocity_rows",
    "check_printed",
    "printed_ik",
    "coefficient_names",
    "velocity_names",
]

SEED002_TIMES = (3.0, 5.5, 8.0)


@dataclass(frozen=True)
class ViaPoint:
    """A via point D, the straight-line length ``|BD| + |DC|`` and the path's distance to the centre."""

    point: tuple
    length: float
    clearance: float


def cubic_segment(p0, p1, v0, v1, duration) -> np.ndarray:
    """Cubic from ``(p0, v0)`` to ``(p1, v1)`` in ``duration``: coefficients ``(..., 4, d)``.

    Ascending powers of the local time ``s = t - t0``
    (:func:`rapp.trajectory.cubic_local`, with the coefficient index moved next
    to the coordinates). Broadcasts over leading axes so that many candidate
    via points are handled at once.

    Examples
    --------
    >>> cubic_segment([0.0], [3.0], [0.0], [0.25], 3.0).ravel().round(4).tolist()
    [0.0, 0.0, 0.9167, -0.1944]
    """
    return np.moveaxis(cubic_local(float(duration), p0, p1, v0, v1), 0, -2)


def to_absolute_time(coef, t0) -> np.ndarray:
    """Rewrite local coefficients ``(..., k, d)`` (powers of ``t - t0``) in powers of absolute ``t``.

    Seed 002 prints its tables in absolute time
    (:func:`rapp.trajectory.shift_to_absolute` on the coefficient axis).

    Examples
    --------
    >>> to_absolute_time(np.array([[0.0], [1.0], [0.0], [0.0]]), 2.0).ravel().tolist()
    [-2.0, 1.0, 0.0, 0.0]
    """
    coef = np.moveaxis(np.asarray(coef, dtype=float), -2, 0)
    return np.moveaxis(shift_to_absolute(coef, float(t0)), 0, -2)


def curve_point_distance(coef, duration, point):
    """Exact minimum distance from a cubic curve ``p(s)``, ``s`` in ``[0, T]``, to ``point``.

    ``|p(s) - c|^2`` is a degree-6 polynomial; its minimum on ``[0, T]`` is at
    an end or at a real root of its derivative (degree 5). The roots of every
    curve come from one batched eigenvalue call on the companion matrices.

    Parameters
    ----------
    coef : array_like, shape (..., 4, 2)
    duration : float
    point : array_like, shape (2,)

    Returns
    -------
    dist, s : ndarray, shape (...)
        The distance and the local time where it is attained.

    Examples
    --------
    >>> c = cubic_segment([0.0, 1.0], [2.0, 1.0], [0.0, 0.0], [0.0, 0.0], 1.0)
    >>> d, s = curve_point_distance(c, 1.0, [1.0, 0.0])
    >>> round(float(d), 12), round(float(s), 12)
    (1.0, 0.5)
    """
    P = np.array(coef, dtype=float)
    P[..., 0, :] -= np.asarray(point, dtype=float)
    T = float(duration)
    sq = np.zeros(P.shape[:-2] + (7,))
    for i in range(4):
        for j in range(4):
            sq[..., i + j] += np.einsum("...d,...d->...", P[..., i, :], P[..., j, :])
    der = sq[..., 1:] * np.arange(1, 7)
    # Normalise by the largest coefficient; a vanishing leading term (a curve of
    # lower degree) is handled by perturbing it, its spurious huge root is clipped away.
    lead = der[..., -1]
    scale = np.abs(der).max(axis=-1)
    lead = np.where(np.abs(lead) > 1e-14 * np.where(scale > 0, scale, 1.0), lead, 1e-14 * scale + 1e-300)
    comp = np.zeros(der.shape[:-1] + (5, 5))
    comp[..., 1:, :-1] = np.eye(4)
    comp[..., :, -1] = -der[..., :-1] / lead[..., None]
    roots = np.linalg.eigvals(comp)
    real = np.abs(roots.imag) <= 1e-7 * (1 + np.abs(roots.real))
    s = np.where(real, roots.real, 0.0).clip(0.0, T)
    cand = np.concatenate((s, np.zeros(s.shape[:-1] + (1,)), np.full(s.shape[:-1] + (1,), T)), axis=-1)
    # Distances from the curve points themselves: the expanded degree-6 polynomial
    # cancels catastrophically near a zero distance (sqrt turns 1e-14 into 1e-7).
    powers = cand[..., None] ** np.arange(4)
    pts = np.einsum("...ck,...kd->...cd", powers, P)
    vals = np.linalg.norm(pts, axis=-1)
    i = np.argmin(vals, axis=-1)
    best = np.take_along_axis(vals, i[..., None], -1)[..., 0]
    return best, np.take_along_axis(cand, i[..., None], -1)[..., 0]


def via_segments(start, via, goal, *, v_start=(0.0, 0.0), times=SEED002_TIMES):
    """Local coefficients ``(..., 2, 4, 2)`` of the two segments start -> via -> goal.

    The via point and the goal are reached at rest (seed 002's tables).

    Examples
    --------
    >>> via_segments([5, 8], [10.2, 8.54], [14, 7], v_start=(0.25, 0.25)).shape
    (2, 4, 2)
    """
    via = np.asarray(via, dtype=float)
    zero = np.zeros_like(via)
    t0, t1, t2 = (float(t) for t in times)
    first = cubic_segment(start, via, v_start, zero, t1 - t0)
    second = cubic_segment(via, goal, zero, zero, t2 - t1)
    return np.stack(np.broadcast_arrays(first, second), axis=-3)


def path_clearance(via, start, goal, center, *, v_start=(0.0, 0.0), times=SEED002_TIMES):
    """Exact minimum distance from the centre to the whole path start -> via -> goal, ``(...)``.

    Examples
    --------
    >>> round(float(path_clearance([10.2, 8.54], [5, 8], [14, 7], (10, 7), v_start=(0.25, 0.25))), 4)
    1.5024
    """
    t0, t1, t2 = times
    seg = via_segments(start, via, goal, v_start=v_start, times=times)
    d1, _ = curve_point_distance(seg[..., 0, :, :], t1 - t0, center)
    d2, _ = curve_point_distance(seg[..., 1, :, :], t2 - t1, center)
    return np.minimum(d1, d2)


def _sample_path(via, start, goal, v_start, times, samples):
    t0, t1, t2 = times
    seg = via_segments(start, via, goal, v_start=v_start, times=times)
    u = np.linspace(0.0, 1.0, samples)
    out = []
    for j, T in enumerate((t1 - t0, t2 - t1)):
        s = (u * T)[:, None] ** np.arange(4)  # (samples, 4)
        out.append(np.einsum("sk,...kd->...sd", s, seg[..., j, :, :]))
    t = np.concatenate((t0 + u * (t1 - t0), t1 + u * (t2 - t1)))
    return t, np.concatenate(out, axis=-2)


def _ik(lengths, p, elbow):
    """Joint angles of the tip positions ``p`` (..., 2) on one elbow branch (``"down"``/``"up"``)."""
    q = ik_2link(lengths, p)[..., 0 if elbow == "down" else 1, :]
    return q[..., 0], q[..., 1]


def _link_distances(lengths, p, center, elbow):
    """Distance from the centre to link 1 (base-elbow) and link 2 (elbow-tip), each ``p.shape[:-1]``."""
    q1, _ = _ik(lengths, p, elbow)
    elbow_pt = lengths[0] * np.stack((np.cos(q1), np.sin(q1)), axis=-1)
    return (
        segment_point_distance(np.zeros_like(p), elbow_pt, center),
        segment_point_distance(elbow_pt, p, center),
    )


def arm_link_distance(lengths, via, start, goal, center, *, v_start=(0.0, 0.0),
                      times=SEED002_TIMES, elbow="down", samples=2001):
    """Distance from the centre to the 2-link arm while its tip follows the via path.

    The joints come from analytic IK of the Cartesian path (``elbow`` branch,
    continuous in time away from singularities). Each segment is sampled at
    ``samples`` instants and the link segments are exact (no points along the
    links). Returns ``(dist, bound)``: the sampled minimum and a lower bound
    for continuous time, ``dist - h/2 * vmax`` with ``h`` the sampling step and
    ``vmax`` the largest sampled speed of any point of the arm (the distance
    of a segment to a point changes no faster than its end points move).

    Examples
    --------
    >>> d, lb = arm_link_distance((9, 9), [9.86, 5.32], [5, 8], [14, 7], (10, 7), v_start=(0.25, 0.25))
    >>> bool(lb > 1.5)
    True
    """
    lengths = tuple(float(v) for v in lengths)
    t, p = _sample_path(via, start, goal, v_start, tuple(float(v) for v in times), samples)
    d1, d2 = _link_distances(lengths, p, center, elbow)
    dist = np.minimum(d1, d2).min(axis=-1)
    q1, q2 = _ik(lengths, p, elbow)
    # Joint rates by finite differences inside each segment (both ends included).
    n = samples
    h = np.diff(t.reshape(2, n), axis=-1).max()
    q1s, q2s = (np.unwrap(a.reshape(a.shape[:-1] + (2, n)), axis=-1) for a in (q1, q2))
    w1 = np.abs(np.diff(q1s, axis=-1)) / h
    w12 = np.abs(np.diff(q1s + q2s, axis=-1)) / h
    vmax = (lengths[0] * w1 + lengths[1] * w12).max(axis=(-1, -2))
    return dist, dist - 0.5 * h * vmax


def first_arm_collision(lengths, via, start, goal, obstacle, *, v_start=(0.0, 0.0),
                        times=SEED002_TIMES, elbow="up", samples=2001):
    """First sampled time at which a link of the arm touches the disc, and which link (1 or 2).

    Returns ``None`` when no sample collides. Single via point only.

    Examples
    --------
    >>> from rapp import Circle
    >>> t, link = first_arm_collision((9, 9), [9.86, 5.32], [5, 8], [14, 7], Circle((10, 7), 1.5),
    ...                               v_start=(0.25, 0.25))
    >>> round(t, 3), link
    (5.774, 2)
    """
    lengths = tuple(float(v) for v in lengths)
    t, p = _sample_path(np.asarray(via, float), start, goal, v_start, tuple(float(v) for v in times), samples)
    d1, d2 = _link_distances(lengths, p, obstacle.center, elbow)
    hit = (d1 <= obstacle.radius) | (d2 <= obstacle.radius)
    if not hit.any():
        return None
    k = int(np.argmax(hit))
    return float(t[k]), 1 if d1[k] <= obstacle.radius else 2


def _grid(center, bound, res):
    k = int(np.floor(bound / res + 1e-9))
    g = np.arange(-k, k + 1) * res
    X, Y = np.meshgrid(center[0] + g, center[1] + g, indexing="ij")
    return np.stack((X, Y), axis=-1).reshape(-1, 2)


def search_via_point(start, goal, obstacle, *, v_start=(0.0, 0.0), times=SEED002_TIMES,
                     bound=None, resolutions=(0.1, 0.01), refine_bound=None,
                     arm_lengths=None, arm_samples=201) -> ViaPoint:
    """Seed 002's grid search with refinement for the via point D.

    Candidates are ``c + (i, j) res`` with ``|i res|, |j res| <= bound``
    (default ``1.5 r``) around the obstacle centre, then around the best point
    with ``refine_bound`` (default: the previous resolution, which is the
    seed's 0.1 for its 0.01 pass) for each later resolution. A candidate is kept when
    the whole cubic path clears the disc (exact, :func:`path_clearance`
    ``> r``) and, with ``arm_lengths``, when both links of the elbow-down arm
    clear it at ``arm_samples`` instants per segment (Condition 3); among kept
    candidates the smallest ``|BD| + |DC|`` wins (Condition 2B).

    Examples
    --------
    >>> from rapp import Circle
    >>> d = search_via_point([5, 8], [14, 7], Circle((10, 7), 1.5), v_start=(0.25, 0.25))
    >>> np.round(d.point, 2).tolist()
    [10.2, 8.54]
    """
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    c = np.asarray(obstacle.center, dtype=float)
    r = obstacle.radius
    bound = 1.5 * r if bound is None else float(bound)
    best = c
    for level, res in enumerate(resolutions):
        if level == 0:
            window = bound
        else:
            window = resolutions[level - 1] if refine_bound is None else float(refine_bound)
        D = _grid(best, window, res)
        clear = path_clearance(D, start, goal, c, v_start=v_start, times=times)
        ok = clear > r
        if arm_lengths is not None:
            armd, _ = arm_link_distance(arm_lengths, D, start, goal, c, v_start=v_start,
                                        times=times, elbow="down", samples=arm_samples)
            ok &= armd > r
        length = np.linalg.norm(D - start, axis=-1) + np.linalg.norm(goal - D, axis=-1)
        length = np.where(ok, length, np.inf)
        i = int(np.argmin(length))
        if not np.isfinite(length[i]):
            raise ValueError("no candidate via point clears the obstacle on this grid")
        best = D[i]
    return ViaPoint(tuple(best.tolist()), float(length[i]), float(clear[i]))


def _tangent_points(p, c, r):
    d = p - c
    L = np.linalg.norm(d)
    if L <= r:
        raise ValueError(f"point {p.tolist()} lies inside the obstacle")
    a = np.arccos(r / L)
    base = np.arctan2(d[1], d[0])
    ang = base + np.array([a, -a])
    return c + r * np.stack((np.cos(ang), np.sin(ang)), axis=-1)


def tangent_via_point(start, goal, obstacle) -> ViaPoint:
    """Exact shortest two-segment path start -> D -> goal with straight segments clear of the disc.

    D is where the tangent from the start meets the tangent from the goal,
    on the side of the disc that gives the shorter path; the segments touch
    the circle (distance exactly ``r``). It answers Condition 2A literally;
    :func:`search_via_point` checks the cubic path instead, which bulges away
    from the straight segment BD (see the module notes), so its D differs.

    Examples
    --------
    >>> from rapp import Circle
    >>> d = tangent_via_point([5, 8], [14, 7], Circle((10, 7), 1.5))
    >>> np.round(d.point, 4).tolist(), round(d.length, 5)
    ([10.2181, 8.5299], 9.32454)
    """
    b = np.asarray(start, dtype=float)
    g = np.asarray(goal, dtype=float)
    c = np.asarray(obstacle.center, dtype=float)
    r = obstacle.radius
    if segment_point_distance(b, g, c) > r:
        return ViaPoint(tuple(((b + g) / 2).tolist()), float(np.linalg.norm(g - b)),
                        float(segment_point_distance(b, g, c)))
    tb, tg = _tangent_points(b, c, r), _tangent_points(g, c, r)
    best = None
    for side_b, side_g in ((0, 1), (1, 0)):  # tangents on the same side of the disc
        u, w = tb[side_b] - b, tg[side_g] - g
        M = np.column_stack((u, -w))
        if abs(np.linalg.det(M)) < 1e-12 * np.dot(u, u) * np.dot(w, w):
            # Parallel tangents: usable only when they are one line, i.e. BC itself is tangent.
            if abs(u[0] * (g - b)[1] - u[1] * (g - b)[0]) > 1e-9 * np.dot(u, u):
                continue
            D = tb[side_b]
        else:
            lam = np.linalg.solve(M, g - b)
            if lam[0] <= 0 or lam[1] <= 0:
                continue
            D = b + lam[0] * u
        length = float(np.linalg.norm(D - b) + np.linalg.norm(g - D))
        if best is None or length < best.length:
            clear = min(segment_point_distance(b, D, c), segment_point_distance(D, g, c))
            best = ViaPoint(tuple(D.tolist()), length, float(clear))
    return best


def peak_rates(traj, samples: int = 2001):
    """Peak speed and peak acceleration magnitude of a piecewise polynomial trajectory.

    ``traj`` is a :class:`rapp.trajectory.PiecewisePolynomial`. Each segment
    is sampled on its own closed interval with its own coefficients, so both
    one-sided accelerations at a knot (where piecewise cubics jump) are seen.
    The acceleration of a cubic segment is linear in time, so its peak (at a
    segment end) is exact; the speed peak is exact up to the sampling.

    Returns
    -------
    (vmax, amax) : tuple of float

    Examples
    --------
    >>> from rapp.trajectory import via_points
    >>> pp = via_points([0.0, 2.0], [[0.0, 0.0], [3.0, 4.0]], velocities=[[0, 0], [0, 0]])
    >>> [round(v, 6) for v in peak_rates(pp)]      # rest-to-rest cubic: 1.5 d/T and 6 d/T^2
    [3.75, 7.5]
    """
    h = np.diff(np.asarray(traj.breakpoints, dtype=float))
    tau = np.linspace(0.0, 1.0, samples)[:, None] * h  # (samples, m): local times of each segment
    local = np.moveaxis(np.asarray(traj.local, dtype=float), 0, -2)  # (k, m, d)
    v = polyval(local[:, None], tau[..., None], 1)  # (samples, m, d)
    a = polyval(local[:, None], tau[..., None], 2)
    return float(np.linalg.norm(v, axis=-1).max()), float(np.linalg.norm(a, axis=-1).max())


def spline_vs_cubic(times, positions, velocities, samples: int = 2001):
    """Peak speed and acceleration of seed 002's piecewise cubics and of the C2 spline.

    The piecewise cubics take ``velocities`` at every via point (seed 002:
    rest, 0.25 m/s at B, rest at D and C); the spline
    (:func:`rapp.trajectory.via_points` ``profile="spline"``) keeps only the
    end velocities and solves the interior ones so that acceleration is
    continuous too.

    Returns
    -------
    dict
        ``{"cubic": (vmax, amax), "spline": (vmax, amax)}``.

    Examples
    --------
    >>> out = spline_vs_cubic([0, 1, 2], [[0, 0], [1, 0], [2, 0]], [[0, 0], [0, 0], [0, 0]])
    >>> out["spline"][1] < out["cubic"][1]
    True
    """
    vel = np.asarray(velocities, dtype=float)
    cub = via_points(times, positions, velocities=vel, profile="cubic")
    spl = via_points(times, positions, velocities=vel[[0, -1]], profile="spline")
    return {"cubic": peak_rates(cub, samples), "spline": peak_rates(spl, samples)}


def coefficient_tables(points, times, velocities):
    """The seed's coefficient tables: per axis, one row per segment, ``(c3, c2, c1, c0)``.

    Coefficients of the cubic through consecutive ``points`` at ``times`` with ``velocities``,
    in absolute time, highest power first (the seed's order; :func:`rapp.cubic` gives ascending).

    Examples
    --------
    >>> x, y = coefficient_tables([[0, 0], [1, 2]], [0.0, 1.0], [[0, 0], [0, 0]])
    >>> x.round(6).tolist(), y.round(6).tolist()
    ([[-2.0, 3.0, 0.0, 0.0]], [[-4.0, 6.0, 0.0, 0.0]])
    """
    from rapp.trajectory import cubic

    P, V, t = (np.asarray(a, float) for a in (points, velocities, times))
    return [cubic(t[:-1], t[1:], P[:-1, k], P[1:, k], V[:-1, k], V[1:, k])[::-1].T
            for k in range(P.shape[1])]


def velocity_rows(table):
    """The velocity polynomial of each row of a coefficient table: ``(3 c3, 2 c2, c1)``.

    Examples
    --------
    >>> velocity_rows(np.array([[-2.0, 3.0, 0.0, 0.0]])).tolist()
    [[-6.0, 6.0, 0.0]]
    """
    return np.asarray(table)[:, :3] * [3, 2, 1]


def check_printed(names, computed, printed):
    """Compare the numbers a document prints with the computed ones, to the digits printed.

    A printed value is right when it is the computed value rounded to as many decimals as it
    shows. Returns the table rows ``(name, printed, computed to 4 decimals, verdict)`` and the
    names of the wrong ones.

    Examples
    --------
    >>> rows, wrong = check_printed(["a", "b"], [11 / 12, 11 / 12], ["0.9167", "0.9166"])
    >>> wrong
    ['b']
    """
    rows, wrong = [], []
    for name, value, text in zip(names, np.ravel(computed), printed):
        decimals = len(text.split(".")[1]) if "." in text else 0
        ok = abs(value - float(text)) <= 0.5 * 10.0**-decimals + 1e-12
        rows.append((name, text, f"{value:.4f}", "✓" if ok else "<b>wrong</b>"))
        wrong += [] if ok else [name]
    return rows, wrong


def printed_ik(P, sign_q2, sign_q1=-1.0, lengths=(9.0, 9.0), strict=True) -> np.ndarray:
    """Seed 002's inverse kinematics (its eqs. 34-37) as printed, with arctan(y/x) and arcsin.

    ``q2 = sign_q2 * arccos((x^2 + y^2 - L1^2 - L2^2) / (2 L1 L2))`` and
    ``q1 = arctan(y / x) + sign_q1 * arcsin(L2 sin(q2) / r)``.

    Parameters
    ----------
    P : array_like, shape (..., 2)
        Tip positions.
    sign_q2 : float
        ``+1``: elbow down (eqs. 36-37); ``-1``: elbow up (eqs. 34-35).
    sign_q1 : float
        ``-1``: the sign of eq. 36 and eq. 34 corrected; ``+1``: eq. 34 as printed.
    lengths : pair of float or of arrays
        ``(L1, L2)``; seed 002's Task 3 arm has ``L1 = L2 = 9`` m.
    strict : bool
        The formulas hold only for ``x > 0`` and ``L1 + L2 cos(q2) >= 0``; outside they return
        wrong angles without a warning. ``strict=True`` refuses such points (ValueError);
        :func:`rapp.ik_2link` (atan2) has no such limit.

    Returns
    -------
    ndarray, shape (..., 2)
        ``(q1, q2)`` in rad.

    Examples
    --------
    >>> printed_ik([14.0, 7.0], +1).round(4).tolist()
    [-0.0528, 1.0329]
    >>> printed_ik([-1.0, 0.5], +1, lengths=(1.0, 1.0))
    Traceback (most recent call last):
    ...
    ValueError: outside the domain of eqs. 34-37 (x > 0 and L1 + L2 cos Q2 >= 0): use atan2
    """
    P = np.asarray(P, dtype=float)
    l1, l2 = lengths
    x, y = P[..., 0], P[..., 1]
    q2 = sign_q2 * np.arccos((x**2 + y**2 - l1**2 - l2**2) / (2 * l1 * l2))
    q1 = np.arctan(y / x) + sign_q1 * np.arcsin(l2 * np.sin(q2) / np.hypot(x, y))
    if strict and (np.any(x <= 0) or np.any(l1 + l2 * np.cos(q2) < 0)):
        raise ValueError("outside the domain of eqs. 34-37 (x > 0 and L1 + L2 cos Q2 >= 0): use atan2")
    return np.stack([q1, q2], axis=-1)


def coefficient_names(letter: str, segments) -> list:
    """The seed's names of the coefficients of each segment, highest power first (HTML subscripts).

    Examples
    --------
    >>> coefficient_names("a", ["AB"])
    ['a<sub>AB,3</sub>', 'a<sub>AB,2</sub>', 'a<sub>AB,1</sub>', 'a<sub>AB,0</sub>']
    """
    return [f"{letter}<sub>{s},{k}</sub>" for s in segments for k in (3, 2, 1, 0)]


def velocity_names(axis: str, segments) -> list:
    """Names of the terms of each segment's velocity polynomial (:func:`velocity_rows`'s order).

    Examples
    --------
    >>> velocity_names("y", ["BD"])
    ['dy<sub>BD</sub>/dt: t²', 'dy<sub>BD</sub>/dt: t', 'dy<sub>BD</sub>/dt: t⁰']
    """
    return [f"d{axis}<sub>{s}</sub>/dt: t{p}" for s in segments for p in ("²", "", "⁰")]
