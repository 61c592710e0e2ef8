"""The discretized joint space (PS3, LC1, LC5) and its occupancy grid.

A joint that turns freely is a circle, so its axis wraps: ``M`` cells at
``theta_i = 2 pi i / M - pi``, ``i = 0 .. M-1``, and cell ``M-1`` neighbours
cell ``0`` (the C-space of a free arm is a torus). A joint with limits
``[lo, hi]`` is a bounded interval of ``M`` angles from ``lo`` to ``hi``
inclusive.

:func:`occupancy` marks every grid configuration that collides. It never loops
over cells: link ``i`` depends only on joints ``0..i``, so its collisions are
computed on the grid of those joints and broadcast over the others; and on the
grid of joints ``0..i-1`` the angles of joint ``i`` at which the link touches a
disc or a convex polygon form one interval in closed form, painted onto the
joint's axis, so the work per obstacle is per cell of the shorter prefix grid.
The intervals are computed and painted by compiled loops (:mod:`rapp.cspace_kernel`,
numba) once numba is loaded or the grid is large, and by numpy otherwise
(:func:`occupancy_numpy`, also the fallback without numba); both give the same cells.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm

from rapp.arm import Arm, wrap_angle
from rapp.collision import check_obstacle, motion_bounds
from rapp.obstacles import Circle, Polygon

__all__ = ["JointGrid", "occupancy", "occupancy_numpy", "grid_q", "certified_free", "cell_extent",
           "check_grid", "prefix_grid", "prefix_step", "MAX_GRID_CELLS", "COMPILE_FROM"]

#: Most cells (the product of the cells per joint) a :class:`JointGrid` accepts.
#: At this size :func:`occupancy` and :func:`certified_free` return 50 MB bool
#: arrays and :func:`grid_q` an array of ``8 n`` bytes per cell (0.8 GB for two
#: joints); refusing larger grids up front keeps a typo in ``cells`` (say 30000
#: per joint of a 2-link arm: 7 GB) from exhausting memory. A grid this fine is
#: far beyond what planning needs (the scenarios accept a few million cells).
MAX_GRID_CELLS = 50_000_000


@dataclass(frozen=True)
class JointGrid:
    """A grid over the joint space of ``arm``.

    Parameters
    ----------
    arm : Arm
    cells : int or sequence of int
        Cells per joint (one number for all, or one per joint), each ``>= 2``,
        at most :data:`MAX_GRID_CELLS` in all.

    Raises
    ------
    ValueError
        Naming ``cells`` (or ``arm``) when it is invalid or the grid too large.

    Examples
    --------
    >>> from rapp import Arm
    >>> g = JointGrid(Arm([1.0, 1.0], [None, (-1.0, 1.0)]), (4, 3))
    >>> g.shape, g.wraps
    ((4, 3), (True, False))
    >>> g.axes[0].round(4).tolist(), g.axes[1].tolist()
    ([-3.1416, -1.5708, 0.0, 1.5708], [-1.0, 0.0, 1.0])
    >>> g.angles((2, 0)).tolist()
    [0.0, -1.0]
    >>> g.index([3.1, 0.4]).tolist()      # 3.1 is nearest to -pi across the seam
    [0, 1]
    >>> JointGrid(Arm([1.0, 1.0]), 30000)
    Traceback (most recent call last):
    ...
    ValueError: cells (30000, 30000) make a grid of 900,000,000 cells, more than rapp.cspace.MAX_GRID_CELLS = 50,000,000; use fewer cells per joint
    """

    arm: Arm
    cells: tuple

    def __post_init__(self):
        if not isinstance(self.arm, Arm):
            raise ValueError(f"arm must be a rapp.Arm, got {type(self.arm).__name__}")
        n = self.arm.n
        raw = self.cells
        vals = [raw] * n if np.ndim(raw) == 0 else list(raw)
        if len(vals) != n:
            raise ValueError(f"cells has {len(vals)} entries but the arm has {n} joints")
        out = []
        for i, c in enumerate(vals):
            if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)) or c < 2:
                raise ValueError(f"cells[{i}] must be an integer >= 2, got {c!r}")
            out.append(int(c))
        total = math.prod(out)  # Python integers: no overflow, checked before any allocation
        if total > MAX_GRID_CELLS:
            shown = f"{total:,}" if total < 10**15 else f"{float(total):.3g}"
            raise ValueError(
                f"cells {tuple(out)} make a grid of {shown} cells, more than "
                f"rapp.cspace.MAX_GRID_CELLS = {MAX_GRID_CELLS:,}; use fewer cells per joint"
            )
        object.__setattr__(self, "cells", tuple(out))
        if not np.all(self.step > 0):
            i = int(np.flatnonzero(~(self.step > 0))[0])
            raise ValueError(
                f"cells[{i}] = {out[i]} is too many for joint {i}'s range "
                f"{self.arm.joint_limits[i]}: the angle step would round to 0"
            )

    @property
    def n(self) -> int:
        """Number of axes (joints)."""
        return self.arm.n

    @property
    def shape(self) -> tuple:
        """Cells per axis."""
        return self.cells

    @property
    def wraps(self) -> tuple:
        """True where the joint has no limits: that axis is periodic."""
        return tuple(not bool(x) for x in self.arm.limited)

    @property
    def lower(self) -> np.ndarray:
        """Angle of index 0 on every axis (``-pi`` on a wrapping one): the arm's lower bounds."""
        return self.arm.lower

    @property
    def step(self) -> np.ndarray:
        """Angle between neighbouring cells on every axis, shape ``(n,)``."""
        m = np.array(self.cells, dtype=float)
        span = self.arm.upper - self.arm.lower
        return np.where(self.wraps, 2 * np.pi / m, span / (m - 1))

    @property
    def axes(self) -> list:
        """One 1-D array of angles per axis."""
        return [
            2 * np.pi * np.arange(m) / m - np.pi if w else np.linspace(lo, hi, m)
            for w, lo, hi, m in zip(self.wraps, self.arm.lower, self.arm.upper, self.cells)
        ]

    def angles(self, index) -> np.ndarray:
        """Joint angles of grid indices: ``(..., n)`` integers to ``(..., n)`` radians.

        Indices on a wrapping axis are taken modulo its size; on a bounded axis
        they must lie in ``0 .. M-1``.
        """
        idx = np.asarray(index)
        if idx.ndim == 0 or idx.shape[-1] != self.n or not np.issubdtype(idx.dtype, np.integer):
            raise ValueError(f"index must be integers of shape (..., {self.n}), got {idx.shape}")
        m = np.array(self.cells)
        wr = np.array(self.wraps)
        bad = ~wr & ((idx < 0) | (idx >= m))
        if np.any(bad):
            raise ValueError("index out of range on a bounded (joint-limited) axis")
        idx = np.where(wr, idx % m, idx)
        return np.stack([ax[idx[..., k]] for k, ax in enumerate(self.axes)], axis=-1)

    def fractional_index(self, q) -> np.ndarray:
        """Where configurations ``(..., n)`` fall between grid indices, as real numbers.

        On a wrapping axis the angle is wrapped first, so the value lies in
        ``[0, M)``; on a bounded axis it is ``(q - lo) / step`` and may lie
        outside ``[0, M - 1]`` for a configuration outside the limits.

        Examples
        --------
        >>> from rapp import Arm
        >>> JointGrid(Arm([1.0, 1.0]), 4).fractional_index([0.0, np.pi / 4]).tolist()
        [2.0, 2.5]
        """
        q = self.arm.check_q(q)
        base = np.where(self.wraps, wrap_angle(q) + np.pi, q - self.lower)
        # A configuration far outside a narrow joint range can land beyond float64:
        # +-inf is then the honest position, far off the grid.
        with np.errstate(over="ignore"):
            return base / self.step

    def index(self, q) -> np.ndarray:
        """Nearest grid index of configurations ``(..., n)``; wrap-aware, clipped on bounded axes.

        Examples
        --------
        >>> from rapp import Arm
        >>> JointGrid(Arm([1.0, 1.0], [None, (-1.0, 1.0)]), 5).index([[3.0, 0.4], [0.0, 9.0]]).tolist()
        [[0, 3], [2, 4]]
        """
        m = np.array(self.cells)
        # Clipped before rounding so that a value far off the grid converts to int safely.
        f = np.clip(self.fractional_index(q), -1.0, m.astype(float))
        i = np.rint(f).astype(int)
        return np.where(self.wraps, i % m, np.clip(i, 0, m - 1))


def check_grid(arm, grid):
    """ValueError naming ``grid`` unless it is a JointGrid of ``arm`` (whose size it has checked)."""
    if not isinstance(grid, JointGrid):
        raise ValueError(f"grid must be a rapp.JointGrid, got {type(grid).__name__}")
    if grid.arm != arm:
        raise ValueError("grid was built for a different arm")


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
    >>> from rapp import Arm
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


#: Grids of at least this many cells use the compiled kernel even when numba is not imported
#: yet (:func:`occupancy`); smaller ones use numpy unless numba is already loaded. Importing
#: numba costs a few tenths of a second, more than numpy spends on such a grid; it is the
#: threshold from which :func:`rapp.astar` compiles its search too, so a grid planned on
#: pays the import once.
COMPILE_FROM = 1 << 16


def occupancy(arm: Arm, obstacles: Iterable[Circle | Polygon], grid: JointGrid) -> np.ndarray:
    """Collision of every grid configuration: a bool array of ``grid.shape`` (True = collides).

    Link ``i`` depends on joints ``0..i`` only. On the grid of joints
    ``0..i-1`` (its base point ``P`` and the previous link's absolute angle)
    the directions in which it touches an obstacle form one interval, in
    closed form (:func:`_circle_hits`, :func:`_polygon_hits`); shifted
    by the previous angle it is an interval of joint ``i``'s angle, painted
    onto that axis. The work is per prefix cell and obstacle, plus one write of
    the grid.

    The intervals are computed and painted by compiled loops
    (:mod:`rapp.cspace_kernel`), one prefix cell at a time, skipping the cells
    where an earlier link already collides; without numba (or on a grid of
    fewer than :data:`COMPILE_FROM` cells before numba is loaded) by
    :func:`occupancy_numpy`. The two agree cell for cell (the kernel takes its angles
    from the same numpy ``arctan2``; :mod:`rapp.cspace_kernel` names the one step
    that could round differently, at a configuration touching an obstacle).

    Parameters
    ----------
    arm : Arm
        Must be the arm of ``grid``.
    obstacles : iterable of Circle and Polygon
    grid : JointGrid

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> from rapp.collision import collides
    >>> arm = Arm([1.0, 1.0])
    >>> occ = occupancy(arm, [Circle((1.75, 0.75), 0.6)], JointGrid(arm, 8))
    >>> occ.shape, int(occ.sum())
    ((8, 8), 2)
    >>> bool((occ == collides(arm, grid_q(JointGrid(arm, 8)), [Circle((1.75, 0.75), 0.6)])).all())
    True
    """
    check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    compiled = _compiled_for(grid) if obstacles else None
    if compiled is None:
        return occupancy_numpy(arm, obstacles, grid)
    return _occupancy_compiled(compiled, [obstacles] * arm.n, grid)


def occupancy_numpy(arm, obstacles, grid) -> np.ndarray:
    """:func:`occupancy` by numpy alone: the fallback without numba, and the kernel's oracle.

    For each link, every prefix cell's interval of every obstacle is computed into
    arrays, painted onto the link's axis by a difference array and a cumulative sum
    (:func:`_paint`) and ORed, broadcast, into the grid. The arguments are those of
    :func:`occupancy`.

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 0.8, 0.5])
    >>> grid, obs = JointGrid(arm, 12), [Circle((1.2, 0.5), 0.3)]
    >>> bool((occupancy_numpy(arm, obs, grid) == occupancy(arm, obs, grid)).all())
    True
    """
    check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    occ = np.zeros(grid.shape, dtype=bool)
    if not obstacles:
        return occ
    for i in range(arm.n):
        occ |= _link_hits(arm, obstacles, grid, i)
    return occ


def _compiled_for(grid):
    """The compiled kernels for ``grid`` (see :data:`COMPILE_FROM`), or None: use numpy."""
    if math.prod(grid.shape) >= COMPILE_FROM or "numba" in sys.modules:
        from rapp import cspace_kernel
        return cspace_kernel.kernels()
    return None


def _occupancy_compiled(k, per_link, grid) -> np.ndarray:
    """Occupancy by the compiled kernels ``k``, link ``i`` against the obstacles ``per_link[i]``."""
    from rapp import cspace_kernel
    return cspace_kernel.run(k, cspace_kernel.levels(grid, per_link)).reshape(grid.shape)


def _link_hits(arm, obstacles, grid, i) -> np.ndarray:
    """Where link ``i`` touches an obstacle, on the grid of joints ``0..i``, shaped to broadcast
    over ``grid.shape`` (trailing axes of length 1)."""
    P, phi_prev = prefix_grid(grid, i)
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


def grid_q(grid) -> np.ndarray:
    """Every configuration of the grid, shape ``grid.shape + (n,)``.

    The array takes ``8 n`` bytes per cell; :class:`JointGrid` refuses grids
    of more than :data:`MAX_GRID_CELLS` cells, which bounds it.

    Examples
    --------
    >>> from rapp import Arm
    >>> grid_q(JointGrid(Arm([1.0, 1.0]), 4)).shape
    (4, 4, 2)
    """
    if not isinstance(grid, JointGrid):
        raise ValueError(f"grid must be a rapp.JointGrid, got {type(grid).__name__}")
    return np.stack(np.meshgrid(*grid.axes, indexing="ij"), axis=-1)



def _inflated(ob, r: float) -> list:
    """Convex pieces whose union is the obstacle grown by ``r`` (its Minkowski sum with a disc).

    A disc grows to a disc. A convex polygon grows to itself, plus a rectangle of depth ``r``
    outside each edge, plus a disc of radius ``r`` at each vertex: every point within ``r`` of
    the polygon lies in one of them (nearest point inside, on an edge, or at a vertex).
    """
    if isinstance(ob, Circle):
        return [Circle(ob.center, ob.radius + r)]
    v = ob.array
    e = np.roll(v, -1, axis=0) - v
    # Outward normals of a polygon stored counter-clockwise: the edge turned a quarter clockwise.
    nrm = np.stack((e[:, 1], -e[:, 0]), axis=-1) / np.hypot(e[:, 0], e[:, 1])[:, None]
    pieces = [ob]
    for k in range(len(v)):
        a, b = v[k], v[(k + 1) % len(v)]
        pieces.append(Polygon([a, b, b + r * nrm[k], a + r * nrm[k]]))
        pieces.append(Circle(a, r))
    return pieces


def certified_free(arm, obstacles, grid) -> np.ndarray:
    """Certified cells: a move of one grid step between two of them is collision-free.

    A cell is certified when at its centre every link ``j`` has clearance above
    ``B_j / 2``, half the largest distance a point of link ``j`` travels in one
    grid step along any axis (:func:`rapp.collision.motion_bounds`). Along a
    move between two axis neighbours that are *both* certified, the first half
    of the move stays within the clearance ball of its start and the second
    half within that of its end, so the whole move is free: a search that
    moves only between certified cells needs no further check of its moves.
    Nothing is promised for a move from a certified cell into one that is not
    (it may collide). The set is the free space shrunk by half a step:
    conservative, so a narrow passage may close (the planner then falls back to
    the plain occupancy).

    "Clearance of link ``j`` above ``r``" is "link ``j`` does not touch the obstacles grown by
    ``r``" (:func:`_inflated`), so this is :func:`occupancy` of grown obstacles, one growth per
    link, painted as intervals on the prefix grids: no distance is computed on the grid
    (by the compiled kernel where :func:`occupancy` uses it).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)]
    >>> grid = JointGrid(arm, 32)
    >>> safe = certified_free(arm, obs, grid)
    >>> bool(np.all(~safe | ~occupancy(arm, obs, grid))), int(safe.sum()) < int((~occupancy(arm, obs, grid)).sum())
    (True, True)
    >>> from rapp import reference
    >>> bool((safe == reference.certified_free(arm, obs, grid)).all())
    True
    """
    check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    n = arm.n
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)  # (n,) per link
    if not obstacles:
        return np.ones(grid.shape, bool)
    grown = [[piece for ob in obstacles for piece in _inflated(ob, float(need[j]))]
             for j in range(n)]
    compiled = _compiled_for(grid)
    if compiled is not None:
        # The occupancy of link j against the obstacles grown for it, every link at once.
        hit = _occupancy_compiled(compiled, grown, grid)
        return np.logical_not(hit, out=hit)
    out = np.ones(grid.shape, bool)
    for j in range(n):
        out &= ~_link_hits(arm, grown[j], grid, j)
    return out


def cell_extent(grid) -> list:
    """Cell edges ``[x0, x1, y0, y1]`` of the first two axes, to draw the grid as an image.

    Each sample angle sits at the centre of its cell (pixel), so the image
    reaches half a step beyond the first and last samples.

    Parameters
    ----------
    grid : JointGrid, or any object with ``axes`` (the sample angles of each joint)

    Examples
    --------
    >>> g = JointGrid(Arm([1.0, 1.0], [None, (-1.0, 1.0)]), (4, 3))
    >>> np.round(cell_extent(g), 4).tolist()
    [-3.927, 2.3562, -1.5, 1.5]
    """
    ext = []
    for a in grid.axes[:2]:
        a = np.asarray(a, dtype=float)
        d = (a[-1] - a[0]) / (len(a) - 1) if len(a) > 1 else 2 * np.pi
        ext += [a[0] - d / 2, a[-1] + d / 2]
    return ext


def __getattr__(name):
    # The reference implementations' old private names here (chapter 10 still names one); they
    # are rapp.reference's now. Imported on use: rapp.reference imports this module.
    moved = {"_occupancy_reference": "occupancy", "_certified_free_reference": "certified_free"}
    if name in moved:
        from rapp import reference
        return getattr(reference, moved[name])
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
