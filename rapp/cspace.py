"""The discretized joint space (PS3, LC1, LC5) and its occupancy grid.

A joint that turns freely is a circle, so its axis wraps: ``M`` cells at
``theta_i = 2 pi i / M - pi``, ``i = 0 .. M-1``, and cell ``M-1`` neighbours
cell ``0`` (the C-space of a free arm is a torus). A joint with limits
``[lo, hi]`` is a bounded interval of ``M`` angles from ``lo`` to ``hi``
inclusive.

:func:`occupancy` marks every grid configuration that collides. It never loops
over cells: link ``i`` depends only on joints ``0..i``, so its collisions are
computed on the grid of those joints and broadcast over the others; for a disc
the test along the last of those joints is a closed form in the link's angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rapp.arm import Arm, wrap_angle
from rapp.collision import check_obstacle, motion_bounds, segment_clearances
from rapp.obstacles import Circle
from rapp.checks import positive_integer

__all__ = ["JointGrid", "occupancy", "grid_q", "certified_free", "MAX_GRID_CELLS"]

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


def _check_grid(arm, grid):
    """ValueError naming ``grid`` unless it is a JointGrid of ``arm`` (whose size it has checked)."""
    if not isinstance(grid, JointGrid):
        raise ValueError(f"grid must be a rapp.JointGrid, got {type(grid).__name__}")
    if grid.arm != arm:
        raise ValueError("grid was built for a different arm")


def _prefix_grid(grid, i):
    """Base point and absolute angle of link ``i`` on the grid of joints ``0..i-1``.

    Returns ``P`` of shape ``cells[:i] + (2,)`` and ``phi`` of shape ``cells[:i]``
    (the absolute angle of link ``i-1``, 0 for the base).
    """
    P = np.zeros((2,))
    phi = np.zeros(())
    axes = grid.axes
    for k in range(i):
        phi = phi[..., None] + axes[k]
        L = grid.arm.link_lengths[k]
        P = P[..., None, :] + L * np.stack((np.cos(phi), np.sin(phi)), axis=-1)
    return P, phi


def _circle_hits(P, cos_phi, sin_phi, L, center, r):
    """Closed-form hit of a link from ``P`` (prefix grid) at angle ``phi`` with a disc.

    With ``d = |c - P|`` and ``delta`` the angle between the link and ``c - P``:
    inside (``d <= r``) always hits; if the link reaches the tangent point
    (``L >= sqrt(d^2 - r^2)``) it hits iff ``delta <= asin(r / d)``; else it
    hits iff its tip is in the disc, ``cos delta >= (L^2 + d^2 - r^2) / (2 L d)``
    (never when ``L < d - r``). Since ``delta`` is in ``[0, pi]`` these are
    ``d cos delta >= T`` with ``T = sqrt(d^2 - r^2)`` or ``(L^2 + d^2 - r^2) / (2L)``,
    and ``d cos delta = (c - P) . u(phi)``: no trigonometry on the full grid.
    """
    v = np.asarray(center) - P
    d2 = v[..., 0] ** 2 + v[..., 1] ** 2
    t2 = d2 - r * r
    tangent = np.sqrt(np.maximum(t2, 0.0))
    # For a short link far from the disc the tip distance overflows; inf means "never hits".
    with np.errstate(over="ignore"):
        T = np.where(L >= tangent, tangent, (L * L + t2) / (2 * L))
    T = np.where(L < np.sqrt(d2) - r, np.inf, T)
    T = np.where(t2 <= 0, -np.inf, T)
    dot = v[..., 0, None] * cos_phi
    dot += v[..., 1, None] * sin_phi
    return dot >= T[..., None]


def _polygon_hits(P, cos_phi, sin_phi, L, poly):
    """Separating-axis test of every link on the prefix grid against one convex polygon.

    The link runs from ``P`` (shape ``S + (2,)``) to ``P + L u(phi)``
    (``cos_phi``, ``sin_phi`` of shape ``S + (M,)``). Projections of ``P`` are
    computed once on the prefix grid; only the terms in ``phi`` span the full
    grid. Touching counts (separation needs a strict gap).
    """
    v = poly.array
    e = np.roll(v, -1, axis=0) - v
    normals = np.stack((e[:, 1], -e[:, 0]), axis=-1)
    proj = v @ normals.T
    pmin, pmax = proj.min(axis=0), proj.max(axis=0)
    sep = np.zeros(cos_phi.shape, dtype=bool)
    for k in range(len(v)):
        nx, ny = normals[k]
        sa = (P @ normals[k])[..., None]
        sb = sa + L * (cos_phi * nx + sin_phi * ny)
        sep |= (np.maximum(sa, sb) < pmin[k]) | (np.minimum(sa, sb) > pmax[k])
    # The link's own normal m = (-sin, cos): separated when every vertex is strictly on one side.
    above = np.ones(cos_phi.shape, dtype=bool)
    below = np.ones(cos_phi.shape, dtype=bool)
    for vx, vy in v:
        w = (vy - P[..., 1])[..., None] * cos_phi - (vx - P[..., 0])[..., None] * sin_phi
        above &= w > 0
        below &= w < 0
    return ~(sep | above | below)


def occupancy(arm, obstacles, grid) -> np.ndarray:
    """Collision of every grid configuration: a bool array of ``grid.shape`` (True = collides).

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
    _check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    shape = grid.shape
    n = arm.n
    occ = np.zeros(shape, dtype=bool)
    if not obstacles:
        return occ
    circles = [ob for ob in obstacles if isinstance(ob, Circle)]
    polys = [ob for ob in obstacles if not isinstance(ob, Circle)]
    axes = grid.axes
    for i in range(n):
        P, phi_prev = _prefix_grid(grid, i)
        L = arm.link_lengths[i]
        hit = np.zeros(shape[: i + 1], dtype=bool)
        # cos/sin of phi_prev + theta by the addition formulas: outer products, no trig on the grid.
        cp, sp = np.cos(phi_prev)[..., None], np.sin(phi_prev)[..., None]
        ct, st = np.cos(axes[i]), np.sin(axes[i])
        cos_phi = cp * ct - sp * st
        sin_phi = sp * ct + cp * st
        for ob in circles:
            hit |= _circle_hits(P, cos_phi, sin_phi, L, ob.center, ob.radius)
        for ob in polys:
            hit |= _polygon_hits(P, cos_phi, sin_phi, L, ob)
        occ |= hit.reshape(hit.shape + (1,) * (n - i - 1))
    return occ


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



def certified_free(arm, obstacles, grid, *, chunk: int = 200_000) -> np.ndarray:
    """Cells from which every move to an axis neighbour is certified collision-free.

    Along a move of one grid step on axis ``k`` a point of link ``j`` travels
    at most ``B_jk`` (:func:`rapp.collision.motion_bounds`). If at both ends of
    the move link ``j`` has clearance above ``B_jk / 2``, each half of the move
    stays inside the clearance ball of its own end, so the whole move is free.
    A cell is marked True when its clearances exceed half the bound for every
    axis; a search on these cells needs no further check of its moves. It is
    the occupancy inflated by half a step: conservative, so a narrow passage
    may close (the planner then falls back to the plain occupancy).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm, obs = Arm([1.0, 1.0]), [Circle((1.5, 0.0), 0.3)]
    >>> grid = JointGrid(arm, 32)
    >>> safe = certified_free(arm, obs, grid)
    >>> bool(np.all(~safe | ~occupancy(arm, obs, grid))), int(safe.sum()) < int((~occupancy(arm, obs, grid)).sum())
    (True, True)
    """
    _check_grid(arm, grid)
    obstacles = [check_obstacle(ob) for ob in obstacles]
    chunk = positive_integer(chunk, "chunk")
    n = arm.n
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)  # (n,) per link
    axes = grid.axes
    out = np.ones(grid.shape, bool)
    for j in range(n):
        # Link j depends on joints 0..j only: test it on that prefix grid and broadcast.
        prefix = grid.shape[: j + 1]
        size = math.prod(prefix)
        ok = np.empty(size, bool)
        for lo in range(0, size, chunk):  # chunks bound the memory, not a loop over cells
            idx = np.unravel_index(np.arange(lo, min(lo + chunk, size)), prefix)
            q = np.zeros((idx[0].size, n))
            for k in range(j + 1):
                q[:, k] = axes[k][idx[k]]
            pts = arm.joint_positions(q)
            d = segment_clearances(pts[:, j, :], pts[:, j + 1, :], obstacles)
            ok[lo:lo + chunk] = d > need[j]
        out &= ok.reshape(prefix + (1,) * (n - j - 1))
    return out
