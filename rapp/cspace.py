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
The intervals are computed and painted by compiled loops (:mod:`rapp.kernels.occupancy_numba`,
numba) once numba is loaded or the grid is large, and by numpy otherwise
(:func:`occupancy_numpy`, also the fallback without numba); both give the same cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

if TYPE_CHECKING:
    from rapp.arm import Arm

from rapp.kernels import occupancy as occupancy_backend
from rapp.kernels.occupancy import COMPILE_FROM
from rapp.kernels.occupancy_numpy import hits as numpy_hits, prefix_grid, prefix_step
from rapp.arm import Arm, wrap_angle
from rapp.collision import check_obstacle, motion_bounds, required_distances, scene
from rapp.obstacles import Circle, applies, grown

__all__ = ["JointGrid", "occupancy", "occupancy_numpy", "grid_q", "certified_free", "cell_extent",
           "check_extent", "MAX_EXTENT_RATIO",
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
    if (grid.arm.link_lengths, grid.arm.joint_limits) != (arm.link_lengths, arm.joint_limits):
        # the links' width and self-collision do not change the grid
        raise ValueError("grid was built for a different arm")


def occupancy(arm: Arm, obstacles: Iterable[Circle | Polygon], grid: JointGrid, *,
              margin: float = 0.0) -> np.ndarray:
    """Collision of every grid configuration: a bool array of ``grid.shape`` (True = collides).

    Link ``i`` depends on joints ``0..i`` only. On the grid of joints
    ``0..i-1`` (its base point ``P`` and the previous link's absolute angle)
    the directions in which it touches an obstacle form one interval, in
    closed form (:mod:`rapp.kernels.occupancy_numpy`); shifted
    by the previous angle it is an interval of joint ``i``'s angle, painted
    onto that axis. The work is per prefix cell and obstacle, plus one write of
    the grid.

    The intervals are computed and painted by compiled loops
    (:mod:`rapp.kernels.occupancy_numba`), one prefix cell at a time, skipping the cells
    where an earlier link already collides; without numba (or on a grid of
    fewer than :data:`COMPILE_FROM` cells before numba is loaded) by
    :func:`occupancy_numpy`. The two agree cell for cell (the kernel takes its angles
    from the same numpy ``arctan2``; :mod:`rapp.kernels.occupancy_numba` names the one step
    that could round differently, at a configuration touching an obstacle).

    Parameters
    ----------
    arm : Arm
        Must be the arm of ``grid``. Thick links (``arm.link_radius``) and a
        ``margin`` (>= 0) are painted exactly: link ``j`` against the obstacles grown
        by ``link_radius[j] + margin`` (:func:`rapp.collision.scene`), discs and
        rectangles painted in the same closed form.
    obstacles : iterable of Circle and Polygon
        Those wholly beyond the arm's reach are left out (no link can touch them); one
        within reach must lie within :data:`MAX_EXTENT_RATIO` times the reach of the
        origin, or it is refused (:func:`check_extent`): inside that range the cells are
        those :func:`rapp.collision.collides` gives (tested up to the ratio, and for
        joint angles up to 1e10 rad).
    grid : JointGrid
    margin : float

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
    return occupancy_backend.hits(*_per_link(arm, obstacles, margin), grid)


#: The painted intervals of :func:`occupancy` hold for obstacles whose coordinates lie within
#: this many times the arm's reach of the origin. Beyond it the closed forms lose their digits
#: (a 1 mm arm beside a polygon 10 km across had cells a link's length clear marked
#: colliding): such an obstacle is refused by :func:`check_extent`, naming it. An obstacle
#: wholly out of the arm's reach is left out instead, exactly: no link can touch it.
MAX_EXTENT_RATIO = 1e5


def _extent(ob) -> tuple:
    """``(nearest, farthest)``: bounds on the distance of ``ob``'s points from the origin."""
    if isinstance(ob, Circle):
        d = float(np.hypot(*ob.center))
        return d - ob.radius, d + ob.radius
    v = ob.array
    far = float(np.hypot(v[:, 0], v[:, 1]).max())
    # Outside the polygon the origin is at least its distance from the farthest edge line.
    e = np.roll(v, -1, axis=0) - v
    off = (e[:, 0] * v[:, 1] - e[:, 1] * v[:, 0]) / np.hypot(e[:, 0], e[:, 1])
    return float(max(off.max(), 0.0)), far


def check_extent(arm, obstacles, margin=0.0) -> list:
    """The obstacles :func:`occupancy` paints: those within the arm's reach, each refused when it
    extends beyond :data:`MAX_EXTENT_RATIO` times the reach.

    An obstacle farther from the base than the reach plus the largest distance a link must
    keep (``link_radius + margin``) is dropped: no link can come near it.

    Raises
    ------
    ValueError
        Naming ``obstacles[i]``, the first one within reach that extends too far.

    Examples
    --------
    >>> from rapp import Arm, Circle, Polygon
    >>> arm = Arm([1.0, 1.0])
    >>> len(check_extent(arm, [Circle((1.5, 0), 0.2), Circle((50.0, 0), 1.0)]))
    1
    >>> try:
    ...     check_extent(Arm([1e-3]), [Polygon.rectangle((0.0005, -5e3), 1e4, 1e4)])
    ... except ValueError as e:
    ...     print(str(e)[:72])
    obstacles[0] reaches 1.1e+04 from the base, more than 100000 times the a
    """
    if not isinstance(obstacles, (list, tuple)):
        obstacles = tuple(obstacles)
    reach = float(np.sum(arm.lengths))
    near_enough = reach + float(required_distances(arm, margin).max())
    key = (tuple(map(id, obstacles)), reach, near_enough)
    hit = _EXTENTS.get(key)  # a grid planner asks again with the same obstacles
    if hit is not None:
        return list(hit[1])
    kept = []
    for i, ob in enumerate(obstacles):
        near, far = _extent(check_obstacle(ob))
        if near > near_enough:
            continue
        if far > MAX_EXTENT_RATIO * reach:
            raise ValueError(
                f"obstacles[{i}] reaches {far:.2g} from the base, more than {MAX_EXTENT_RATIO:g} "
                f"times the arm's reach ({reach:.2g}) (rapp.cspace.MAX_EXTENT_RATIO): the "
                "C-space intervals would lose their digits; cut it down to the region the arm "
                "can reach"
            )
        kept.append(ob)
    if len(_EXTENTS) >= 64:
        _EXTENTS.clear()
    _EXTENTS[key] = (tuple(obstacles), tuple(kept))  # the obstacles kept: their ids stay theirs
    return kept


_EXTENTS: dict = {}


def _per_link(arm, obstacles, margin) -> tuple:
    """``(arm0, per_link)``: zero-width links and the checked, grown obstacles each one meets."""
    arm, obstacles = scene(arm, check_extent(arm, obstacles, margin), margin)
    if not any(ob.links is not None for ob in obstacles):
        return arm, [obstacles] * arm.n
    return arm, [[ob for ob in obstacles if applies(ob, j)] for j in range(arm.n)]


def occupancy_numpy(arm, obstacles, grid, *, margin=0.0) -> np.ndarray:
    """:func:`occupancy` by numpy alone: the fallback without numba, and the kernel's oracle.

    For each link, every prefix cell's interval of every obstacle is computed into
    arrays, painted onto the link's axis by a difference array and a cumulative sum
    (:mod:`rapp.kernels.occupancy_numpy`) and ORed, broadcast, into the grid. The arguments are those of
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
    # The prefix geometry is looked up here at call time: one call per link with an obstacle,
    # which chapter 10 counts by watching rapp.cspace.prefix_grid.
    return numpy_hits(*_per_link(arm, obstacles, margin), grid,
                      prefix=lambda g, i: prefix_grid(g, i))


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



def certified_free(arm, obstacles, grid, *, margin=0.0) -> np.ndarray:
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
    ``r``" (:func:`rapp.obstacles.grown`), so this is :func:`occupancy` of grown obstacles, one growth per
    link, painted as intervals on the prefix grids: no distance is computed on the grid
    (by the compiled kernel where :func:`occupancy` uses it). Thick links and a ``margin``
    add to the growth: link ``j``'s obstacles grow by ``link_radius[j] + margin + r``.

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
    n = arm.n
    need = 0.5 * motion_bounds(arm, np.diag(grid.step)).max(axis=0)  # (n,) per link
    obstacles = check_extent(arm, obstacles, margin + float(need.max()))
    need = need + required_distances(arm, margin)  # the growths add (Minkowski sums of discs)
    if not obstacles:
        return np.ones(grid.shape, bool)
    pieces = [[piece for ob in obstacles if applies(ob, j) for piece in grown(ob, float(need[j]))]
              for j in range(n)]
    hit = occupancy_backend.hits(arm, pieces, grid)  # link j against the obstacles grown for it
    return np.logical_not(hit, out=hit)


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
