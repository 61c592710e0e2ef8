"""The occupancy in numpy: the backend without numba (and on small grids), and the prefix grids.

Link ``i`` depends on joints ``0..i`` only. On the grid of joints ``0..i-1`` (:func:`prefix_grid`:
its base point ``P`` and the previous link's absolute angle) the directions in which the link
touches a disc or a convex polygon form one interval, in closed form (:func:`_circle_hits`,
:func:`_polygon_hits`); shifted by the previous angle it is an interval of joint ``i``'s
angle, painted onto that axis (:func:`_paint`). :func:`hits` ORs the links' grids.
:mod:`rapp.kernels.occupancy_numba` computes the same intervals by compiled loops, from the
geometry of :func:`prefix_step`; :mod:`rapp.kernels.occupancy` chooses between them.

Examples
--------
>>> from rapp import Arm, Circle, JointGrid
>>> arm = Arm([1.0, 1.0])
>>> int(hits(arm, [[Circle((1.75, 0.75), 0.6)]] * 2, JointGrid(arm, 8)).sum())
2
"""

from __future__ import annotations

import numpy as np

from rapp.obstacles import Circle

__all__ = ["hits", "prefix_grid", "prefix_step"]


def hits(arm, per_link, grid, *, prefix=None) -> np.ndarray:
    """Where link ``i`` touches one of the obstacles ``per_link[i]``, for any ``i``: bool ``grid.shape``.

    The obstacles are checked (:func:`rapp.collision.check_obstacle`) and ``grid`` is the arm's
    (:func:`rapp.cspace.check_grid`). ``prefix`` computes each link's prefix geometry
    (default :func:`prefix_grid`), once per link with an obstacle.
    """
    occ = np.zeros(grid.shape, dtype=bool)
    for i in range(arm.n):
        if len(per_link[i]):
            occ |= _link_hits(arm, per_link[i], grid, i, prefix or prefix_grid)
    return occ


def prefix_grid(grid, i, *, trig=False):
    """Base point and absolute angle of link ``i`` on the grid of joints ``0..i-1``.

    Returns ``P`` of shape ``cells[:i] + (2,)`` and ``phi`` of shape ``cells[:i]``
    (the absolute angle of link ``i-1``, 0 for the base); with ``trig=True`` also the
    cosine and sine of ``phi`` (same shape).

    The cosine and sine of each absolute angle come from those of the previous one and
    of the axis by the addition formulas: outer products of short vectors, no
    trigonometry on the grid (which would cost more than the rest of a 3-link
    :func:`occupancy`). They agree with ``cos(phi)``, ``sin(phi)`` to a few units in
    the last place.

    Examples
    --------
    >>> from rapp import Arm, JointGrid
    >>> grid = JointGrid(Arm([1.0, 0.5, 0.5]), 4)
    >>> P, phi = prefix_grid(grid, 2)
    >>> P.shape, phi.shape
    ((4, 4, 2), (4, 4))
    >>> q = grid.angles(np.stack(np.meshgrid(*[range(4)] * 3, indexing="ij"), axis=-1))
    >>> bool(np.allclose(P, grid.arm.joint_positions(q)[:, :, 0, 2], atol=1e-15))
    True
    """
    P, phi, c, s = np.zeros((2,)), np.zeros(()), np.ones(()), np.zeros(())
    axes = grid.axes
    for k in range(i):
        P, phi, c, s = prefix_step(P, phi, c, s, axes[k], np.cos(axes[k]), np.sin(axes[k]),
                                   grid.arm.link_lengths[k])
    return (P, phi, c, s) if trig else (P, phi)


def prefix_step(P, phi, c, s, ax, ca, sa, L):
    """:func:`prefix_grid` (``trig=True``) one joint further: the next joint's angles ``ax``
    (cosines ``ca``, sines ``sa``) and the link ``L`` before it, as a new last axis.

    Examples
    --------
    >>> P, phi, c, s = prefix_step(np.zeros(2), np.zeros(()), np.ones(()), np.zeros(()),
    ...                            np.array([0.0, np.pi / 2]), np.array([1.0, 0.0]),
    ...                            np.array([0.0, 1.0]), 2.0)
    >>> P.tolist(), phi.tolist()
    ([[2.0, 0.0], [0.0, 2.0]], [0.0, 1.5707963267948966])
    """
    phi = phi[..., None] + ax
    c, s = c[..., None] * ca - s[..., None] * sa, s[..., None] * ca + c[..., None] * sa
    return P[..., None, :] + L * np.stack((c, s), axis=-1), phi, c, s


def _circle_hits(P, L, center, r):
    """Absolute directions from ``P`` in which a link of length ``L`` touches a disc.

    ``P`` has shape ``(R, 2)``. Returns ``(start, width)`` of shape ``(R,)``: the link hits the
    disc iff its direction lies in ``[start, start + width]`` (mod ``2 pi``);
    ``width < 0`` means it never does, ``width >= 2 pi`` that it always does.

    Notes
    -----
    With ``v = c - P``, ``d = |v|`` and ``delta`` the angle between the link
    and ``v``, the hit test of :func:`rapp.reference.circle_hits` is monotone in
    ``delta``, so the hitting directions are one interval about ``atan2(v)``
    of half-width ``h``:

    * ``d <= r`` (``P`` in the disc): every direction;
    * ``L < d - r``: none;
    * ``L >= t = sqrt(d^2 - r^2)`` (the link reaches the tangent point):
      ``h = asin(r / d) = atan2(r, t)``;
    * otherwise only the tip can enter, and ``h`` is the angle at ``P`` of
      the triangle with sides ``d`` (to ``c``), ``L`` (to the tip) and ``r``;
      the half-angle formula ``tan(h/2) = sqrt((L+r-d)(d+r-L) / ((d+L+r)(d+L-r)))``
      is accurate even when ``h`` is tiny, where ``acos`` of the cosine law is not.

    Examples
    --------
    >>> [s], [w] = _circle_hits(np.array([[0.0, 0.0]]), 2.0, (1.0, 0.0), 0.5)
    >>> round(float(s + w / 2), 12), round(float(w / 2), 6), round(float(np.arcsin(0.5)), 6)
    (0.0, 0.523599, 0.523599)
    """
    vx = center[0] - P[:, 0]
    vy = center[1] - P[:, 1]
    d2 = vx * vx + vy * vy
    d = np.sqrt(d2)
    start = np.zeros(P.shape[0])
    width = np.full(P.shape[0], -1.0)
    # Only rows whose link can reach the disc need trigonometry (the same threshold as
    # the per-cell test); on a fine grid most rows are far from any one obstacle.
    rows = np.flatnonzero(~(L < d - r))
    vx, vy, d2, d = vx[rows], vy[rows], d2[rows], d[rows]
    t = np.sqrt(np.maximum((d - r) * (d + r), 0.0))
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        tip = 2.0 * np.arctan(np.sqrt(
            np.maximum(L + r - d, 0.0) * np.maximum(d + r - L, 0.0)
            / ((d + L + r) * np.maximum(d + L - r, np.finfo(float).tiny))))
    h = np.where(L >= t, np.arctan2(r, t), tip)
    h = np.where(d2 <= r * r, 2 * np.pi, h)   # P in the disc: every direction
    start[rows] = np.arctan2(vy, vx) - np.minimum(h, np.pi)
    width[rows] = 2.0 * h
    return start, width


def _polygon_hits(P, L, poly):
    """Absolute directions from ``P`` in which a link of length ``L`` touches a convex polygon.

    Returns ``(start, width)`` like :func:`_circle_hits`.

    Notes
    -----
    The link ``{P + s u : 0 <= s <= L}`` meets the closed convex polygon ``K``
    iff ``u`` points at a point of ``K' = K ∩ D``, ``D`` the closed disc of
    radius ``L`` about ``P``. If ``P`` is in ``K`` every direction hits. If
    not, ``K'`` is convex (an intersection of convex sets), compact and
    misses ``P``; a line strictly separates them, so the directions from ``P``
    to ``K'`` form one closed interval of width ``< pi``. Its two ends are
    supporting rays from ``P`` touching ``K'`` at extreme points of ``K'``.
    The extreme points of ``K ∩ D`` are vertices of ``K`` in ``D``, crossings
    of edges of ``K`` with the circle ``∂D``, and points of ``∂D`` inside
    ``K``. A ray from the centre ``P`` through an inner point ``X`` of such an
    arc is not supporting: the arc on either side of ``X`` lies in ``K'`` and
    is seen on either side of the ray. So the ends are attained among the
    vertices within ``L`` and the edge/circle crossings (at most ``3k``
    candidates for ``k`` vertices); ``K'`` is empty iff there are none (with
    ``P`` outside ``K``, a nonempty ``K'`` has boundary points of ``K`` in
    ``D``: a vertex, or an edge entering ``D`` through the circle). Measured
    from any one candidate, the others lie within ``(-pi, pi)``, so their
    least and greatest relative angles are the ends.

    A tolerance of ``1e-12`` of the scene's scale is added to "P in K",
    "vertex within L" and "crossing within the edge": it only ever adds
    directions at which the link passes within that distance of ``K`` (cells
    touching within rounding), and it keeps a vertex at distance exactly
    ``L`` (or ``P`` exactly on an edge) from being lost to rounding.

    Examples
    --------
    >>> from rapp import Polygon
    >>> sq = Polygon.rectangle((1.0, -0.5), 1.0, 1.0)
    >>> [s], [w] = _polygon_hits(np.array([[0.0, 0.0]]), 5.0, sq)   # sees both near corners
    >>> round(float(s), 6), round(float(w), 6), round(float(2 * np.arctan(0.5)), 6)
    (-0.463648, 0.927295, 0.927295)
    >>> float(_polygon_hits(np.array([[0.0, 0.0]]), 0.9, sq)[1][0])  # too short: never
    -1.0
    >>> float(_polygon_hits(np.array([[1.5, 0.0]]), 0.1, sq)[1][0]) >= 2 * np.pi   # inside
    True
    """
    v = poly.array
    e = np.roll(v, -1, axis=0) - v
    ee = np.einsum("ij,ij->i", e, e)
    tol = 1e-12 * max(1.0, L, float(np.abs(v).max()), float(np.abs(P).max(initial=0.0)))
    start = np.zeros(P.shape[0])
    width = np.full(P.shape[0], -1.0)
    # Only rows within L of the polygon's bounding disc can hit it: the rest stay empty.
    c = v.mean(axis=0)
    rad = np.sqrt(((v - c) ** 2).sum(axis=1).max())
    rows = np.flatnonzero(np.hypot(P[:, 0] - c[0], P[:, 1] - c[1]) <= L + rad + 2 * tol)
    P = P[rows]
    wx = v[:, 0] - P[:, 0, None]   # vertex j relative to P, shape (rows, k)
    wy = v[:, 1] - P[:, 1, None]
    # P in K: on the inner side of every (counter-clockwise) edge, within tol.
    inside = np.all(e[:, 1] * wx - e[:, 0] * wy >= -tol * np.sqrt(ee), axis=-1)
    w2 = wx * wx + wy * wy
    vert_ok = w2 <= (L + tol) ** 2
    # Edge j: |w_j + s e_j| = L, i.e. ee s^2 + 2 b s + (w2 - L^2) = 0.
    b = wx * e[:, 0] + wy * e[:, 1]
    disc = b * b - ee * (w2 - L * L)
    root = np.sqrt(np.maximum(disc, 0.0))
    slack = tol / np.sqrt(ee)
    xs, ys, oks = [wx], [wy], [vert_ok]
    for sgn in (-1.0, 1.0):
        s = (-b + sgn * root) / ee
        ok = (disc >= 0) & (s >= -slack) & (s <= 1 + slack)
        s = np.clip(s, 0.0, 1.0)
        xs.append(wx + s * e[:, 0])
        ys.append(wy + s * e[:, 1])
        oks.append(ok)
    cx, cy, ok = np.concatenate(xs, -1), np.concatenate(ys, -1), np.concatenate(oks, -1)
    # Angles relative to one candidate (the first valid one): all lie in (-pi, pi).
    ref = np.argmax(ok, axis=-1)[:, None]
    rx = np.take_along_axis(cx, ref, -1)
    ry = np.take_along_axis(cy, ref, -1)
    rel = np.arctan2(rx * cy - ry * cx, rx * cx + ry * cy)
    lo = np.where(ok, rel, np.inf).min(axis=-1, initial=np.inf)
    hi = np.where(ok, rel, -np.inf).max(axis=-1, initial=-np.inf)
    seen = ok.any(axis=-1)
    start[rows] = np.where(seen, np.arctan2(ry[:, 0], rx[:, 0]) + lo, 0.0)
    width[rows] = np.where(inside, 2 * np.pi, np.where(seen, hi - lo, -1.0))
    return start, width


def _paint(intervals, ax, wraps, step, chunk=2048):
    """Cells of one joint axis whose angle lies in an interval ``[start, start + width]`` mod ``2 pi``.

    Parameters
    ----------
    intervals : list of (start, width)
        Arrays of shape ``(R,)``, one interval per row and entry (``width < 0``:
        empty; ``width >= 2 pi``: the whole circle).
    ax : ndarray, shape (M,)
        The axis' angles, ``ax[k] = ax[0] + k step`` up to rounding.
    wraps : bool
    step : float

    Returns
    -------
    ndarray of bool, shape ``(R, M)``: True where some interval covers the cell.

    Notes
    -----
    Each interval is cut at the multiples of ``2 pi`` into index ranges
    ``ceil(a / step) .. floor(b / step)`` (angles measured from ``ax[0]``),
    added to a difference array along the axis (+1 at the first cell, -1
    after the last) and a cumulative sum counts the intervals covering each
    cell: the work is per interval, plus one pass over the ``R x M`` cells.

    Examples
    --------
    >>> ax = 2 * np.pi * np.arange(8) / 8 - np.pi                 # wrapping, step pi/4
    >>> _paint([(np.array([2.0]), np.array([1.5]))], ax, True, np.pi / 4).astype(int).tolist()
    [[1, 0, 0, 0, 0, 0, 0, 1]]
    >>> ax = np.linspace(-1.0, 1.0, 5)          # limited; the interval wraps past 2 pi onto 0
    >>> _paint([(np.array([0.6]), np.array([6.0]))], ax, False, 0.5).astype(int).tolist()
    [[1, 1, 1, 0, 1]]
    """
    R, M = intervals[0][0].shape[0], ax.size
    lo, two_pi = float(ax[0]), 2 * np.pi
    periods = int((float(ax[-1]) - lo) // two_pi) + 2   # pieces p = -1 .. periods - 2
    if periods > M:
        # A limited joint spanning more turns than it has cells: test every cell directly.
        out = np.zeros((R, M), bool)
        for start, width in intervals:
            out |= (np.mod(ax - start[:, None], two_pi) <= width[:, None]) & (width[:, None] >= 0)
        return out
    # Counts never exceed the number of pieces; int8 keeps the array at one byte per cell.
    dtype = np.int8 if len(intervals) * periods < 127 else np.int32
    diff = np.zeros((R, M + 1), dtype)
    flat = diff.reshape(-1)
    for start, width in intervals:
        rows = np.flatnonzero(width >= 0)
        f = np.mod(start[rows] - lo, two_pi)
        w = width[rows]
        base = rows * (M + 1)
        for p in range(-1, periods - 1):
            a = f + p * two_pi
            first = np.maximum(np.ceil(a / step), 0).astype(np.int64)
            last = np.minimum(np.floor((a + w) / step), M - 1).astype(np.int64)
            use = first <= last
            # One entry per row: the indices are distinct, so plain fancy += is exact.
            flat[base[use] + first[use]] += 1
            flat[base[use] + last[use] + 1] -= 1
    out = np.empty((R, M), bool)
    for r0 in range(0, R, chunk):
        # numpy's int32 cumsum is several times faster than its int8 one; chunks keep
        # the int32 copy small.
        c = np.cumsum(diff[r0:r0 + chunk], axis=1, dtype=np.int32)
        np.greater(c[:, :M], 0, out=out[r0:r0 + chunk])
    return out


def _link_hits(arm, obstacles, grid, i, prefix) -> np.ndarray:
    """Where link ``i`` touches an obstacle, on the grid of joints ``0..i``, shaped to broadcast
    over ``grid.shape`` (trailing axes of length 1)."""
    P, phi_prev = prefix(grid, i)
    P = P.reshape(-1, 2)
    phi_prev = phi_prev.reshape(-1)
    L = arm.link_lengths[i]
    intervals = []
    for ob in obstacles:
        if isinstance(ob, Circle):
            s, w = _circle_hits(P, L, ob.center, ob.radius)
        else:
            s, w = _polygon_hits(P, L, ob)
        intervals.append((s - phi_prev, w))   # absolute direction -> joint i's own angle
    hit = _paint(intervals, grid.axes[i], grid.wraps[i], grid.step[i])
    return hit.reshape(grid.shape[: i + 1] + (1,) * (arm.n - i - 1))
